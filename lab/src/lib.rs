#![doc = include_str!("../README.md")]
#![deny(missing_docs)]

pub mod arm;
pub mod attention;
pub mod benchmark;
pub mod competence;
pub mod context;
pub mod domain;
mod drive;
pub mod feedback;
pub mod folder;
pub mod goal_change;
pub mod heatmap;
pub mod instance;
pub mod interrupt;
pub mod known_operator;
pub mod landscape;
pub mod limit;
pub mod limit_law;
pub mod mission;
pub mod mission_calibration;
pub mod mission_contexts;
pub mod mission_figure;
pub mod mission_noticing;
pub mod mission_oracle;
pub mod mission_report;
pub mod operator;
pub mod operator_file;
pub mod patience;
pub mod plot;
pub mod population;
pub mod report;
pub mod runner;
pub mod seeds;
pub mod simulate;
pub mod stating;
pub mod stats;
#[cfg(feature = "testing")]
pub mod testing;
pub mod timeline;

pub use arm::{
    Arm, BUILTIN_ARMS, COMPETENT_PASSES, CONTEXT_BLIND, IGNORES_STATEMENTS, Initial, LEARNED_START,
    NameOptions, PREFERS_COMPETENT, UnknownArm, prefers_competent,
};
pub use context::TrialContexts;
pub use domain::{
    AttentionNotModelled, Domain, GoalChangesNotModelled, Judgement, check_attention,
    check_goal_changes, vocabulary,
};
pub use feedback::{FeedbackChannel, FeedbackError};
pub use goal_change::{GoalChangeRecord, GoalChanges, GoalChangesError};
pub use heatmap::LandscapeSvgError;
pub use instance::{Instance, InstanceError, Split};
pub use interrupt::Interrupted;
pub use known_operator::KnownLimitError;
pub use landscape::LandscapeError;
pub use limit::LimitError;
pub use operator::{GiveUpFactor, SimulatedOperator, StandardFields};
pub use operator_file::{OperatorFileError, UnperceivedWeight};
pub use plot::PlotError;
pub use report::ReportError;
pub use runner::{
    ArmResult, ExperimentPlan, ExperimentResult, ExplanationCheck, ExplanationSample,
    GivenUpRecord, OperatorChoice, PairedTests, PlanError, SAMPLE_EXPLANATIONS, Step,
    TracedCommand, TrialRecord, run_experiments, trace_trial,
};
pub use simulate::{SimulatedCommand, Simulation, SimulationError};
pub use trust::{RetrieverFactory, SearcherFactory};
