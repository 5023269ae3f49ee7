#![doc = include_str!("../README.md")]
#![deny(missing_docs)]

// The crate's folders, each a `//!` of its own. Their imports run one way, in this order:
// contract, reference, experiment, population, report, mission; a module imports only from
// the root's shared modules, its own folder and the folders before its own
// (.ci/check-lab-layers.py checks it).
pub mod contract;
pub mod experiment;
pub mod mission;
pub mod population;
pub mod reference;
pub mod report;

// Shared by every folder, importing none of them (`testing`, the conformance kit, runs
// over the contract).
pub mod folder;
pub mod interrupt;
pub mod seeds;
pub mod stats;
pub mod targets;
#[cfg(feature = "testing")]
pub mod testing;

pub use contract::capability::{
    AttentionNotModelled, GoalChangesNotModelled, SelfJudgingNotModelled, check_attention,
    check_goal_changes, check_self_judging,
};
pub use contract::domain::{Attentive, Domain, GoalChanging, SelfJudging, vocabulary};
pub use contract::feedback::{FeedbackChannel, FeedbackError};
pub use contract::judgement::Judgement;
pub use contract::operator::{GiveUpFactor, SimulatedOperator, StandardFields};
pub use contract::operator_file::{OperatorFileError, UnperceivedWeight};
pub use experiment::arm::{
    Arm, BuiltinArm, COMPETENT_PASSES, RECOMMENDED_ARM, UnknownArm, builtin_arm, builtin_arm_names,
    builtin_arms,
};
pub use experiment::arm_name::{
    ArmName, ArmNameError, CONTEXT_BLIND, IGNORES_STATEMENTS, Initial, LEARNED_START, NameOptions,
    PREFERS_COMPETENT,
};
pub use experiment::goal_change::{GoalChangeRecord, GoalChanges, GoalChangesError, GoalChangesOn};
pub use experiment::plan::{ExperimentPlan, OperatorChoice, PlanError};
pub use experiment::record::{
    ArmResult, ExperimentResult, ExplanationCheck, ExplanationSample, GivenUpRecord, PairedTests,
    SAMPLE_EXPLANATIONS, Step, TracedCommand, TrialRecord,
};
pub use experiment::runner::{run_experiments, trace_trial};
pub use experiment::simulate::{SimulatedCommand, Simulation, SimulationError};
pub use experiment::trial_contexts::TrialContexts;
pub use interrupt::Interrupted;
pub use population::instance::{Instance, InstanceError, Split};
pub use reference::known_operator::KnownLimitError;
pub use reference::landscape::LandscapeError;
pub use reference::limit::LimitError;
pub use report::ReportError;
pub use report::heatmap::LandscapeSvgError;
pub use report::plot::PlotError;
pub use trust::{RetrieverFactory, SearcherFactory};
