//! The experiment machinery of SPEC section 7, generic over any [`Domain`](crate::Domain).
//!
//! A *trial* is one adaptation episode driven through the same [`TrustAdapter`](crate::TrustAdapter)
//! a robot embeds. An *experiment* runs a number of trials with one operator (or one drawn
//! at random per trial) once per [`Arm`] (a search strategy, with or without case reuse),
//! pairing trial `i` of every arm. Arms, statistics and report files live in submodules.

pub mod arm;
pub mod heatmap;
pub mod landscape;
pub mod plot;
pub mod report;
pub mod runner;
pub mod seeds;
pub mod stats;

pub use arm::{Arm, BUILTIN_ARMS, RetrieverFactory, SearcherFactory, UnknownArm};
pub use runner::{
    ArmResult, ExperimentPlan, ExperimentResult, OperatorChoice, PairedTests, PlanError,
    TrialRecord, TrialSettings, run_experiments,
};
