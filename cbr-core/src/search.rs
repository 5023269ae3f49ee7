//! Search strategies: proposing the next behavior to try when no case helps.
//!
//! A [`Searcher`] implements one step (which behavior next); the caller owns the loop. It
//! sees the evidence gathered in the current episode, may watch every piece of feedback and
//! the end of every episode (so learning strategies fit the same trait), and draws all its
//! randomness from the seeded generator it is handed.

use crate::behavior::{Behavior, BehaviorSpace};
use crate::context::Context;
use crate::statement::Statement;
use rand::RngCore;
use serde::{Deserialize, Serialize};
use std::borrow::Cow;

/// What a searcher proposes: its answer to one step. This is not a record of where a
/// behavior came from (a caller that also reuses cases keeps that itself, naming the
/// search as one origin among others): a proposal may instead say that nothing is left,
/// which is no behavior's origin but the end of the search.
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

/// Why a strategy proposed a behavior, for explanations shown to operators and
/// researchers ([`Searcher::rationale`]). Texts are short plain phrases, one line each;
/// `"a fixed text".into()` or `format!(...).into()` makes one.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Rationale {
    /// The strategy explores: it expects nothing in particular of the proposal.
    Explores {
        /// How it picked the proposal (e.g. "one random step from the behavior that
        /// resisted longest").
        how: Cow<'static, str>,
    },
    /// The strategy expects the proposal to do better than what was given up.
    Expects {
        /// What it expects to change (e.g. "fewer collisions").
        what: Cow<'static, str>,
        /// Its confidence in that, a probability, when it has one.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        confidence: Option<f64>,
    },
}

impl Rationale {
    /// The rationale of a strategy that gives none (the default of
    /// [`Searcher::rationale`]).
    pub fn unstated() -> Self {
        Self::Explores {
            how: "the search strategy gives no reason".into(),
        }
    }

    /// The same rationale with every control character of its text (an escape sequence, a
    /// line break) replaced by U+FFFD: what an explanation keeps of a strategy's text, so
    /// a report, a page or a terminal shows it as one plain line.
    pub fn plain(self) -> Self {
        fn plain(text: Cow<'static, str>) -> Cow<'static, str> {
            if text.chars().any(char::is_control) {
                text.chars()
                    .map(|c| if c.is_control() { '\u{FFFD}' } else { c })
                    .collect::<String>()
                    .into()
            } else {
                text
            }
        }
        match self {
            Self::Explores { how } => Self::Explores { how: plain(how) },
            Self::Expects { what, confidence } => Self::Expects {
                what: plain(what),
                confidence,
            },
        }
    }

    /// The phrase an explanation shows: what is expected (with its confidence) or how the
    /// strategy explored.
    pub fn phrase(&self) -> String {
        match self {
            Self::Explores { how } => format!("exploring: {how}"),
            Self::Expects {
                what,
                confidence: Some(p),
            } => format!("expecting {what} (confidence {:.0}%)", p * 100.0),
            Self::Expects {
                what,
                confidence: None,
            } => format!("expecting {what}"),
        }
    }
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

    /// Whether what the robot is told of its context ([`Searcher::enter_context`]) can
    /// change what the strategy proposes. `true` by default (a strategy that does not say
    /// may read it); one that ignores the context says `false`, and an arm of it that
    /// reuses no case and is blind to the context is then refused as its own twin.
    fn reads_context(&self) -> bool {
        true
    }

    /// Whether what users state up front ([`Searcher::hear`]) can change what the strategy
    /// proposes. `true` by default; one that ignores statements says `false`, and an arm
    /// of it ignoring statements is then refused as its own twin.
    fn hears_statements(&self) -> bool {
        true
    }

    /// Called when the robot is told its context, between episodes: the episodes that
    /// follow are in `context` until it is told another. A strategy that weighs what it
    /// learned by the context it was learned in reads it here; the default ignores it.
    fn enter_context(&mut self, _context: &Context) {}

    /// Called right after [`Searcher::begin_episode`] with what this episode's user stated
    /// up front ([`crate::statement`]): possibly nothing, possibly incomplete or wrong. A
    /// strategy that takes statements as a prior reads them here; the default ignores
    /// them.
    fn hear(&mut self, _stated: &[Statement]) {}

    /// Called when an episode begins with `initial` in use.
    fn begin_episode(&mut self, _space: &BehaviorSpace, _initial: &Behavior) {}

    /// The next behavior to try, given the evidence of this episode so far (in order).
    fn propose(
        &mut self,
        space: &BehaviorSpace,
        evaluated: &[Self::Evidence],
        rng: &mut dyn RngCore,
    ) -> Proposal;

    /// Why the strategy proposed `proposed`, asked right after [`Searcher::propose`]
    /// returned `Proposal::Next(proposed)` (a strategy may remember what it computed
    /// there). It must not change what the strategy proposes later. The default says the
    /// strategy gives no reason; a strategy that has one should say it.
    fn rationale(&self, _proposed: &Behavior) -> Rationale {
        Rationale::unstated()
    }

    /// Whether, given this episode's evidence so far, the strategy expects `behavior` to be
    /// found untrustworthy: case reuse then passes over every case proposing it, to the
    /// next most similar case or to [`Searcher::propose`]. Asked before a case is reused,
    /// once per distinct behavior; it must not change what the strategy proposes later.
    /// The default doubts nothing (the paper's case reuse).
    fn doubts(
        &mut self,
        _space: &BehaviorSpace,
        _evaluated: &[Self::Evidence],
        _behavior: &Behavior,
    ) -> bool {
        false
    }

    /// Called for every piece of feedback about the behavior in use.
    fn observe(&mut self, _behavior: &Behavior, _feedback: &Self::Feedback) {}

    /// Called when an episode ends, with its evidence and the behavior it settled on
    /// (`None` if the episode was abandoned).
    fn end_episode(&mut self, _evaluated: &[Self::Evidence], _settled: Option<&Behavior>) {}
}
