//! The trust laboratory: the experiment machinery of the paper's experiments (trials,
//! arms, statistics), landscapes, reports and plots, generic over any
//! [`Domain`].
//!
//! This crate is what a researcher runs and a robot does not embed: the adapter, the
//! estimate and the search strategies are the lean `trust` crate's; everything that needs
//! a thread pool, statistics or plotting is here.
//!
//! A *trial* is one adaptation episode driven through the same
//! [`TrustAdapter`](trust::TrustAdapter) a robot embeds; a *mission* ([`mission`]) is a
//! long run of commands through its mission wrapper ([`trust::MissionAdapter`]), driven
//! alike (the first behavior and each command come from one place, the private `drive`
//! module). An *experiment* runs a number of trials with one operator (or one drawn at
//! random per trial) once per [`Arm`] (a search strategy, with or without case reuse,
//! starting each episode at random or from the memory's guess), pairing trial `i` of every
//! arm. Arms, statistics and report files live in submodules.

#![deny(missing_docs)]

pub mod arm;
pub mod domain;
mod drive;
pub mod feedback;
pub mod folder;
pub mod heatmap;
pub mod interrupt;
pub mod known_operator;
pub mod landscape;
pub mod limit;
pub mod mission;
pub mod mission_figure;
pub mod mission_report;
pub mod plot;
pub mod report;
pub mod runner;
pub mod seeds;
pub mod stats;
#[cfg(feature = "testing")]
pub mod testing;
pub mod timeline;

pub use arm::{Arm, BUILTIN_ARMS, Initial, LEARNED_START, UnknownArm};
pub use domain::{Domain, Judgement, vocabulary};
pub use feedback::{FeedbackChannel, FeedbackError};
pub use heatmap::LandscapeSvgError;
pub use interrupt::Interrupted;
pub use known_operator::KnownLimitError;
pub use landscape::LandscapeError;
pub use limit::LimitError;
pub use plot::PlotError;
pub use report::ReportError;
pub use runner::{
    ArmResult, ExperimentPlan, ExperimentResult, ExplanationCheck, ExplanationSample,
    GivenUpRecord, OperatorChoice, PairedTests, PlanError, SAMPLE_EXPLANATIONS, Step,
    TracedCommand, TrialRecord, TrialSettings, run_experiments, trace_trial,
};
pub use trust::{RetrieverFactory, SearcherFactory};
