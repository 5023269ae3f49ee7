//! Search strategies: proposing the next behavior to try when no case helps.
//!
//! A [`Searcher`] implements one step (which behavior next); the caller owns the loop. It
//! sees the evidence gathered in the current episode, may watch every piece of feedback and
//! the end of every episode (so learning strategies fit the same trait), and draws all its
//! randomness from the seeded generator it is handed.

use crate::behavior::{Behavior, BehaviorSpace};
use rand::RngCore;

/// What a searcher proposes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Proposal {
    /// Try this behavior next.
    Next(Behavior),
    /// Nothing is left to try: stop adapting and keep this behavior.
    Exhausted {
        /// The behavior to settle on.
        keep: Behavior,
    },
}

/// A search strategy over a behavior space.
pub trait Searcher: Send {
    /// What the strategy knows about one evaluated behavior.
    type Evidence;
    /// What the strategy is told after every observation (e.g. a command outcome).
    type Feedback;

    /// A short name for configs and reports (e.g. `random-walk`).
    fn name(&self) -> &str;

    /// Whether the strategy carries anything learned in one episode into the next. The
    /// default is `false`; a strategy that keeps knowledge across episodes must say `true`,
    /// so that whoever drives it (an experiment runner) keeps its episodes in order.
    fn learns_across_episodes(&self) -> bool {
        false
    }

    /// Called when an episode begins with `initial` in use.
    fn begin_episode(&mut self, _space: &BehaviorSpace, _initial: &Behavior) {}

    /// The next behavior to try, given the evidence of this episode so far (in order).
    fn propose(
        &mut self,
        space: &BehaviorSpace,
        evaluated: &[Self::Evidence],
        rng: &mut dyn RngCore,
    ) -> Proposal;

    /// Called for every piece of feedback about the behavior in use.
    fn observe(&mut self, _behavior: &Behavior, _feedback: &Self::Feedback) {}

    /// Called when an episode ends, with its evidence and the behavior it settled on
    /// (`None` if the episode was abandoned).
    fn end_episode(&mut self, _evaluated: &[Self::Evidence], _settled: Option<&Behavior>) {}
}
