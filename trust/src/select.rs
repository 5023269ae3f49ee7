//! `selectBehavior` (docs/model.md#algorithm-1-choosing-the-next-behavior).
//!
//! Reuse the final behavior of the most similar case whose final behavior has not been
//! evaluated in this episode; fall back to the search strategy when no case has a
//! similarity above zero. The case memory's retriever does the ranking, so any index that
//! honours the retrieval contract gives the same selection as the linear scan.

use crate::search::TrustSearcher;
use crate::{Evaluated, TrustCase, TrustMemory};
use cbr_core::{Behavior, BehaviorSpace, CaseId, Proposal};
use rand::RngCore;

/// Where the next behavior comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Selection {
    /// A case's final behavior.
    Reuse {
        /// The case reused.
        case: CaseId,
        /// Its Algorithm 2 similarity to the episode.
        similarity: f64,
        /// Its final behavior.
        behavior: Behavior,
    },
    /// The search strategy's proposal.
    Search(Proposal),
}

/// Algorithm 1. With `memory` set to `None` this is the search strategy alone.
pub fn select_behavior(
    e_past: &Vec<Evaluated>,
    memory: Option<&TrustMemory>,
    searcher: &mut TrustSearcher,
    space: &BehaviorSpace,
    rng: &mut dyn RngCore,
) -> Selection {
    let already_evaluated = |case: &TrustCase| e_past.iter().any(|e| e.behavior == case.solution);
    if let Some(best) = memory.and_then(|m| m.retrieve(e_past, &already_evaluated)) {
        let behavior = memory
            .and_then(|m| m.base().get(best.id))
            .expect("retrievers return ids of stored cases")
            .solution;
        return Selection::Reuse {
            case: best.id,
            similarity: best.similarity,
            behavior,
        };
    }
    Selection::Search(searcher.propose(space, e_past, rng))
}
