//! Trust-guided behavior adaptation (Floyd, Drinkwater & Aha, ICCBR 2014), generic over
//! any domain.
//!
//! - [`cause`]: causes of failure as names a domain declares.
//! - [`estimate`]: outcomes (what the robot is told and perceives), the inverse trust
//!   estimate, thresholds and verdicts.
//! - [`explain`]: explanations of every decision (why a behavior was given up, why the
//!   next one, why the episode ended), from what the robot was told and perceived.
//! - [`evaluated`]: evaluated pairs and Algorithm 2 (set similarity).
//! - [`select`]: Algorithm 1 (`selectBehavior`) over any retriever and searcher.
//! - [`search`]: search strategies: the paper's random walk, uniform sampling, cause-aware
//!   and model-based search.
//! - [`retrieval`]: the retrievers a config can name.
//! - [`start`]: a learned first behavior, the case memory's best guess for an operator
//!   the robot does not yet know.
//! - [`adapter`]: [`TrustAdapter`], the online state machine a robot embeds (the paper's
//!   episodes), made of an [`Adaptation`] (one robot's episode and search) and the case
//!   memory it owns.
//! - [`mission`]: mission mode, the episode machine wrapped to keep listening after an
//!   episode settles ([`MissionAdaptation`], [`MissionAdapter`]).
//! - [`watch`]: the settled behavior kept under watch on a mission.
//! - [`overtrust`]: the robot's own record of a settled behavior, and the alert it raises
//!   when its operator trusts it more than that record says it should.
//! - [`named`]: behaviors as JSON objects in real units.
//! - `testing` (feature `testing`): conformance kits for users' own parts.
//!
//! This crate knows nothing of any particular robot or simulator, and nothing in it can
//! read the truth of a simulated command: the simulation contract (`Domain`, `Judgement`,
//! `FeedbackChannel`) is the `lab` crate's, which depends on this one and not the other
//! way round. What a domain tells the adapter is its [`Vocabulary`] (causes, observations,
//! hints), the names a robot also knows:
//!
//! ```compile_fail
//! // The truth of a run is not a type of this crate.
//! use trust::Judgement;
//! ```
//!
//! It is lean: what a
//! robot embeds, with no plotting, statistics or thread pool (the parallel scan's thread
//! pool is the opt-in `parallel` feature). Experiments, statistics, landscapes, reports
//! and plots are the `lab` crate's.

#![deny(missing_docs)]

pub mod adapter;
pub mod cause;
pub mod estimate;
pub mod evaluated;
pub mod explain;
pub mod mission;
pub mod named;
pub mod overtrust;
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
pub use estimate::{
    Observations, Outcome, OutcomeError, OutcomeKind, THRESHOLD_TOLERANCE, ThresholdError,
    Thresholds, TrustEstimate, Verdict,
};
pub use evaluated::LambdaError;
pub use evaluated::{Evaluated, RelativeTime, SetSimilarity};
pub use explain::{
    Account, AttributedReason, Attribution, Explanation, Grounds, Hint, Next, Vocabulary,
};
pub use mission::{MissionAdaptation, MissionAdapter, MissionDecision};
pub use overtrust::{Alert, OwnRecord};
pub use retrieval::{InvertedIndex, ParallelScan, RetrieverFactory, RetrieverKind};
pub use search::{SearchKind, SearcherFactory, TrustSearcher};
pub use select::{Selection, Source, select_behavior};
pub use start::{FirstGuess, first_guess};
pub use watch::Watch;
pub use weights::{OutcomeWeights, WeightsError};

use cbr_core::{Behavior, Case, CaseBase, CaseMemory, Retriever};

/// A trust case: the evaluated pairs of an episode and the trustworthy behavior found.
pub type TrustCase = Case<Vec<Evaluated>, cbr_core::Behavior>;
/// The trust case base.
pub type TrustCaseBase = CaseBase<Vec<Evaluated>, Behavior>;
/// The trust case base with its retriever.
pub type TrustMemory = CaseMemory<Vec<Evaluated>, Behavior>;
/// A retriever over the trust case base.
pub type TrustRetriever = dyn Retriever<Vec<Evaluated>, Behavior>;

/// The random-number crate of `Domain::run` and the searchers, re-exported so a user
/// names the same version.
pub use rand;
