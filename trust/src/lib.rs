#![doc = include_str!("../README.md")]
#![deny(missing_docs)]

pub mod adapter;
pub mod cause;
pub mod change;
pub mod competence;
pub mod estimate;
pub mod evaluated;
pub mod explain;
pub mod goal_change;
pub mod mission_mode;
pub mod named;
pub mod overtrust;
pub mod problem;
pub mod retrieval;
pub mod search;
pub mod select;
pub mod start;
#[cfg(feature = "testing")]
pub mod testing;
pub mod watch;
pub mod weights;

pub use adapter::{
    Adaptation, AdapterConfig, AdapterError, ConfigError, Decision, EpisodeReport, EpisodeView,
    Parameters, Retention, TimeUnit, TrustAdapter,
};
pub use cause::{
    Cause, CauseError, DeclaredCause, DefaultWeightError, UndeclaredCause, find_declared,
};
pub use change::{ChangeDetector, ChangeDetectorError, Cusum};
pub use competence::{
    Calibration, Competence, CompetenceAlert, CompetenceJudge, CompetencePart, CompetenceRecord,
    CompetenceStandard, PartEstimate, Predictor, calibrate,
};
pub use estimate::{
    MAX_THRESHOLD, Observations, Outcome, OutcomeError, OutcomeKind, THRESHOLD_TOLERANCE,
    ThresholdError, Thresholds, TrustEstimate, Verdict,
};
pub use evaluated::LambdaError;
pub use evaluated::{Evaluated, RelativeTime, SetSimilarity};
pub use explain::{
    Account, AttributedReason, Attribution, Explanation, Grounds, Hint, Next, Vocabulary,
};
pub use mission_mode::{
    ContextSwitch, EpisodeMachine, MissionAdaptation, MissionAdapter, MissionDecision, SwitchStart,
};
pub use overtrust::{Alert, OwnRecord};
pub use problem::TrustProblem;
pub use retrieval::{InvertedIndex, ParallelScan, RetrieverFactory, RetrieverKind};
pub use search::{SearchKind, SearcherFactory, TrustSearcher};
pub use select::{Selection, Source, select_behavior};
pub use start::{FirstGuess, first_guess};
pub use watch::Watch;
pub use weights::{OutcomeWeights, WeightsError};

use cbr_core::{Behavior, Case, CaseBase, CaseMemory, Retriever};

/// A trust case: an episode's context and evaluated pairs, and the trustworthy behavior
/// found.
pub type TrustCase = Case<TrustProblem, cbr_core::Behavior>;
/// The trust case base.
pub type TrustCaseBase = CaseBase<TrustProblem, Behavior>;
/// The trust case base with its retriever.
pub type TrustMemory = CaseMemory<TrustProblem, Behavior>;
/// A retriever over the trust case base.
pub type TrustRetriever = dyn Retriever<TrustProblem, Behavior>;

/// The random-number crate of `Domain::run` and the searchers, re-exported so a user
/// names the same version.
pub use rand;
