//! The experiment machinery of SPEC section 7, generic over any [`Domain`](crate::Domain).
//!
//! A *trial* is one adaptation episode driven through the same [`TrustAdapter`](crate::TrustAdapter)
//! a robot embeds. An *experiment* runs a number of trials with one operator (or one drawn
//! at random per trial), once per strategy (random walk alone, case-based), pairing trial `i`
//! of one with trial `i` of the other. Statistics and report files live in submodules.

pub mod report;
pub mod runner;
pub mod seeds;
pub mod stats;

pub use runner::{
    ExperimentPlan, ExperimentResult, OperatorChoice, Strategy, StrategyResult, TrialRecord,
    run_experiments,
};
