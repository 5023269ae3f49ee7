//! Two searchers that share an episode's proposals and are both told everything: what
//! [`super::Alternating`] and [`super::Bandit`] have in common, whatever decides whose turn
//! it is. Every outcome, every episode's start and end, the context and the statements
//! reach both, so each learns from the behaviors the other proposed; the rationale of a
//! proposal is its proposer's.

use crate::{Evaluated, Outcome};
use cbr_core::{Behavior, BehaviorSpace, Context, Proposal, Rationale, Searcher, Statement};
use rand::RngCore;

/// Two searchers, and which of them proposed last.
#[derive(Clone, Debug, Default)]
pub(super) struct Pair<A, B> {
    pub(super) first: A,
    pub(super) second: B,
    /// Whether the last proposal was the second searcher's (for its rationale).
    second_last: bool,
}

impl<A, B> Pair<A, B> {
    /// `first` and `second`, neither having proposed.
    pub(super) fn new(first: A, second: B) -> Self {
        Self {
            first,
            second,
            second_last: false,
        }
    }
}

impl<A, B> Pair<A, B>
where
    A: Searcher<Evidence = Evaluated, Feedback = Outcome>,
    B: Searcher<Evidence = Evaluated, Feedback = Outcome>,
{
    /// A proposal of the second searcher when `second`, else of the first.
    pub(super) fn propose(
        &mut self,
        second: bool,
        space: &BehaviorSpace,
        evaluated: &[Evaluated],
        rng: &mut dyn RngCore,
    ) -> Proposal {
        self.second_last = second;
        if second {
            self.second.propose(space, evaluated, rng)
        } else {
            self.first.propose(space, evaluated, rng)
        }
    }

    /// Why the last proposal's searcher proposed `proposed`.
    pub(super) fn rationale(&self, proposed: &Behavior) -> Rationale {
        if self.second_last {
            self.second.rationale(proposed)
        } else {
            self.first.rationale(proposed)
        }
    }

    /// Whether either learns across episodes.
    pub(super) fn learns_across_episodes(&self) -> bool {
        self.first.learns_across_episodes() || self.second.learns_across_episodes()
    }

    /// Whether either reads the context.
    pub(super) fn reads_context(&self) -> bool {
        self.first.reads_context() || self.second.reads_context()
    }

    /// Whether either hears statements.
    pub(super) fn hears_statements(&self) -> bool {
        self.first.hears_statements() || self.second.hears_statements()
    }

    /// Tells both the context.
    pub(super) fn enter_context(&mut self, context: &Context) {
        self.first.enter_context(context);
        self.second.enter_context(context);
    }

    /// Tells both what was stated.
    pub(super) fn hear(&mut self, stated: &[Statement]) {
        self.first.hear(stated);
        self.second.hear(stated);
    }

    /// Tells both an episode began.
    pub(super) fn begin_episode(&mut self, space: &BehaviorSpace, initial: &Behavior) {
        self.first.begin_episode(space, initial);
        self.second.begin_episode(space, initial);
    }

    /// Tells both an outcome.
    pub(super) fn observe(&mut self, behavior: &Behavior, outcome: &Outcome) {
        self.first.observe(behavior, outcome);
        self.second.observe(behavior, outcome);
    }

    /// Tells both the episode ended.
    pub(super) fn end_episode(&mut self, evaluated: &[Evaluated], settled: Option<&Behavior>) {
        self.first.end_episode(evaluated, settled);
        self.second.end_episode(evaluated, settled);
    }
}
