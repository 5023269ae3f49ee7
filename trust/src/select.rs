//! `selectBehavior` (docs/model.md#algorithm-1-choosing-the-next-behavior), and [`Source`],
//! where a behavior the adapter switches to came from.
//!
//! Reuse the final behavior of the most similar case whose final behavior has not been
//! evaluated in this episode; fall back to the search strategy when no case has a
//! similarity above zero. The case memory's retriever does the ranking, so any index that
//! honours the retrieval contract gives the same selection as the linear scan.

use crate::search::TrustSearcher;
use crate::{TrustCase, TrustMemory, TrustProblem};
use cbr_core::{Behavior, BehaviorSpace, CaseId, Proposal};
use rand::RngCore;
use serde::{Deserialize, Serialize};

/// Where a behavior the adapter switches to came from: the one notion of a behavior's
/// origin, in Algorithm 1's answer ([`Selection`]), a switch ([`crate::Decision::Switch`]),
/// its explanation ([`crate::Next::Switch`]) and an experiment's records.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "source")]
pub enum Source {
    /// A case's final behavior, reused (Algorithm 1).
    Case {
        /// The case reused.
        case: CaseId,
        /// Its Algorithm 2 similarity to the episode.
        similarity: f64,
    },
    /// Proposed by the search strategy.
    Search,
}

/// Algorithm 1's answer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Selection {
    /// Use `behavior` next.
    Next {
        /// The behavior.
        behavior: Behavior,
        /// Where it came from.
        source: Source,
    },
    /// No case fits and the search strategy has nothing left to try: settle on `keep`
    /// ([`Proposal::Exhausted`]).
    Exhausted {
        /// The behavior to settle on.
        keep: Behavior,
    },
}

/// Algorithm 1. With `memory` set to `None` this is the search strategy alone.
pub fn select_behavior(
    problem: &TrustProblem,
    memory: Option<&TrustMemory>,
    searcher: &mut TrustSearcher,
    space: &BehaviorSpace,
    rng: &mut dyn RngCore,
) -> Selection {
    let e_past = &problem.evaluated;
    let already_evaluated = |case: &TrustCase| e_past.iter().any(|e| e.behavior == case.solution);
    if let Some(best) = memory.and_then(|m| m.retrieve(problem, &already_evaluated)) {
        let behavior = memory
            .and_then(|m| m.base().get(best.id))
            .expect("retrievers return ids of stored cases")
            .solution;
        return Selection::Next {
            behavior,
            source: Source::Case {
                case: best.id,
                similarity: best.similarity,
            },
        };
    }
    match searcher.propose(space, e_past, rng) {
        Proposal::Next(behavior) => Selection::Next {
            behavior,
            source: Source::Search,
        },
        Proposal::Exhausted { keep } => Selection::Exhausted { keep },
    }
}
