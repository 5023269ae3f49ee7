//! What an episode is while under way and how it ends: the decision after each command,
//! the report of an ended episode, a read-only view of the one under way, and why a
//! command is refused.

use crate::Evaluated;
use crate::estimate::{OutcomeError, TrustEstimate};
use crate::explain::Explanation;
use crate::select::Source;
use cbr_core::{Behavior, CaseId, Context};
use serde::{Deserialize, Serialize};

/// How an episode ended.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EpisodeReport {
    /// The behavior the robot settles on.
    pub settled: Behavior,
    /// Whether it was found trustworthy (otherwise every behavior was tried).
    pub found_trustworthy: bool,
    /// Distinct behaviors evaluated, the final one counted.
    pub behaviors_evaluated: u64,
    /// Commands recorded in the episode.
    pub commands: u64,
    /// Commands that failed or were interrupted (what the operator endured).
    pub untrustworthy: u64,
    /// Adaptations that came from the search strategy.
    pub searched: u32,
    /// Adaptations that reused a case.
    pub reused: u32,
    /// Whether the behavior settled on came from the search strategy.
    pub settled_from_search: bool,
    /// The case retained at the end of the episode, if any.
    pub retained: Option<CaseId>,
    /// The evaluated pairs `E_past`, in order.
    pub evaluated: Vec<Evaluated>,
    /// The context the episode ran in (left out of the serialized report when it is the
    /// default one).
    #[serde(default, skip_serializing_if = "Context::is_default")]
    pub context: Context,
    /// The explanation of every switch of the episode, in order, and last the one of its
    /// end.
    pub explanations: Vec<Explanation>,
}

/// What the robot should do after a recorded outcome.
#[derive(Clone, Debug, PartialEq)]
pub enum Decision {
    /// Keep the current behavior and go on.
    Keep,
    /// The current behavior is untrustworthy: use `to` from now on.
    Switch {
        /// The next behavior.
        to: Behavior,
        /// Where it came from.
        source: Source,
        /// Why the behavior was given up and why this one (boxed: a switch is rare next
        /// to the commands kept).
        explanation: Box<Explanation>,
    },
    /// The episode is over.
    Settled(EpisodeReport),
}

/// Why an adapter call was refused. The adapter's state is unchanged.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum AdapterError {
    /// `record` was called with no episode under way.
    #[error("no episode is under way: begin one first")]
    NoEpisode,
    /// `begin_episode` (or [`Adaptation::give_up_kept`], or a context set) was called while
    /// one is under way.
    ///
    /// [`Adaptation::give_up_kept`]: super::Adaptation::give_up_kept
    #[error("an episode is already under way")]
    EpisodeUnderWay,
    /// The outcome's numbers are unusable (shown in the message, so not chained as a
    /// source).
    #[error("invalid outcome: {0}")]
    Outcome(OutcomeError),
    /// The behavior does not belong to the adapter's space.
    #[error("the behavior does not belong to this behavior space")]
    ForeignBehavior,
    /// An offered behavior was taken while no settled behavior is under watch (mission
    /// mode, [`crate::MissionAdapter::accept_offer`]).
    #[error(
        "no settled behavior is under watch: an offer is taken after an overtrust alert, in mission mode"
    )]
    NotWatching,
    /// An episode was begun with two statements of the same name
    /// ([`Adaptation::begin_episode_hearing`]).
    ///
    /// [`Adaptation::begin_episode_hearing`]: super::Adaptation::begin_episode_hearing
    #[error("`{name}` is stated twice: an operator states each name at most once")]
    StatedTwice {
        /// The name.
        name: String,
    },
    /// [`Adaptation::give_up_kept`] was handed an estimate above the untrustworthy
    /// threshold.
    ///
    /// [`Adaptation::give_up_kept`]: super::Adaptation::give_up_kept
    #[error("the kept behavior's estimate {estimate} is above the untrustworthy threshold")]
    NotUntrustworthy {
        /// The estimate handed.
        estimate: f64,
    },
}

impl From<OutcomeError> for AdapterError {
    fn from(reason: OutcomeError) -> Self {
        Self::Outcome(reason)
    }
}

/// A read-only view of the episode under way.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EpisodeView<'a> {
    /// The behavior in use.
    pub current: Behavior,
    /// Its trust estimate so far.
    pub estimate: TrustEstimate,
    /// Those of its commands that failed or were interrupted (`estimate.commands` counts
    /// them all).
    pub current_untrustworthy: u64,
    /// The pairs evaluated so far.
    pub evaluated: &'a [Evaluated],
    /// The context the episode runs in.
    pub context: &'a Context,
    /// Commands recorded in the episode.
    pub commands: u64,
    /// The explanations of the episode's switches so far.
    pub explanations: &'a [Explanation],
}
