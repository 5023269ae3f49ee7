//! `selectBehavior` (docs/model.md#algorithm-1-choosing-the-next-behavior), and [`Source`],
//! where a behavior the adapter switches to came from.
//!
//! Reuse the final behavior of the most similar case whose final behavior has not been
//! evaluated in this episode; fall back to the search strategy when no case has a
//! similarity above zero. The case memory's retriever does the ranking, so any index that
//! honours the retrieval contract gives the same selection as the linear scan.
//!
//! A search strategy may doubt a case's final behavior ([`cbr_core::Searcher::doubts`]):
//! the selection then passes over every case proposing it and goes on to the next most
//! similar. The paper's strategies doubt nothing, so theirs is the paper's selection.

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

/// Algorithm 1. With `memory` set to `None` this is the search strategy alone. The
/// searcher is asked once about each distinct final behavior retrieved, most similar case
/// first, until it doubts one not.
pub fn select_behavior(
    problem: &TrustProblem,
    memory: Option<&TrustMemory>,
    searcher: &mut TrustSearcher,
    space: &BehaviorSpace,
    rng: &mut dyn RngCore,
) -> Selection {
    let e_past = &problem.evaluated;
    let already_evaluated = |case: &TrustCase| e_past.iter().any(|e| e.behavior == case.solution);
    let mut doubted: Vec<Behavior> = Vec::new();
    while let Some(best) = memory.and_then(|m| {
        m.retrieve(problem, &|case: &TrustCase| {
            already_evaluated(case) || doubted.contains(&case.solution)
        })
    }) {
        let behavior = memory
            .and_then(|m| m.base().get(best.id))
            .expect("retrievers return ids of stored cases")
            .solution;
        if searcher.doubts(space, e_past, &behavior) {
            doubted.push(behavior);
            continue;
        }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::search::grid;
    use crate::{Evaluated, Outcome, RetrieverKind, TrustCaseBase};
    use cbr_core::{Case, Searcher};
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    /// Proposes (2, 2) and doubts the behaviors it is given, noting every one it is asked
    /// about.
    struct Doubting {
        doubted: Vec<Behavior>,
        asked: Vec<Behavior>,
    }

    impl Searcher for Doubting {
        type Evidence = Evaluated;
        type Feedback = Outcome;
        fn name(&self) -> &str {
            "doubting"
        }
        fn propose(&mut self, _: &BehaviorSpace, _: &[Evaluated], _: &mut dyn RngCore) -> Proposal {
            Proposal::Next(Behavior::new(&[2, 2]))
        }
        fn doubts(&mut self, _: &BehaviorSpace, _: &[Evaluated], behavior: &Behavior) -> bool {
            self.asked.push(*behavior);
            self.doubted.contains(behavior)
        }
    }

    #[test]
    fn case_reuse_passes_over_every_case_whose_solution_the_searcher_doubts() {
        let space = grid(&[5, 5]);
        let rejected = |b: [u16; 2]| Evaluated {
            behavior: Behavior::new(&b),
            time: 10.0,
        };
        // Three cases equally similar to the episode (the same rejection): by the retrieval
        // contract the smallest id wins, so (4, 4) first, then (3, 3).
        let mut base = TrustCaseBase::new();
        for solution in [[4, 4], [4, 4], [3, 3]] {
            base.push(Case {
                problem: TrustProblem::new(vec![rejected([0, 0])]),
                solution: Behavior::new(&solution),
            });
        }
        let retriever = RetrieverKind::Linear
            .build(std::sync::Arc::new(space.clone()), 0.95)
            .unwrap();
        let memory = TrustMemory::new(base, retriever);
        let episode = TrustProblem::new(vec![rejected([0, 0])]);
        let select = |doubted: &[[u16; 2]]| {
            let mut searcher = Doubting {
                doubted: doubted.iter().map(|b| Behavior::new(b)).collect(),
                asked: Vec::new(),
            };
            let mut rng = ChaCha8Rng::seed_from_u64(1);
            let selection =
                select_behavior(&episode, Some(&memory), &mut searcher, &space, &mut rng);
            let Selection::Next { behavior, source } = selection else {
                panic!("a behavior");
            };
            let asked: Vec<[u16; 2]> = searcher
                .asked
                .iter()
                .map(|b| [b.get(0), b.get(1)])
                .collect();
            ([behavior.get(0), behavior.get(1)], source, asked)
        };
        let case = |id: u32| Source::Case {
            case: CaseId(id),
            similarity: 1.0,
        };
        // Doubting nothing is the paper's Algorithm 1.
        assert_eq!(select(&[]), ([4, 4], case(0), vec![[4, 4]]));
        // Doubting (4, 4) passes over both cases proposing it, asking once.
        assert_eq!(select(&[[4, 4]]), ([3, 3], case(2), vec![[4, 4], [3, 3]]));
        // Doubting every solution leaves the searcher to propose.
        assert_eq!(
            select(&[[4, 4], [3, 3]]),
            ([2, 2], Source::Search, vec![[4, 4], [3, 3]])
        );
    }
}
