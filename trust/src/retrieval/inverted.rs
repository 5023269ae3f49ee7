//! An inverted index from behaviors to the cases that evaluated them.
//!
//! Algorithm 2 only counts a query pair `e` when some pair of the case has a behavior more
//! similar to `e.behavior` than `lambda`; with `lambda` near 1 those behaviors form a small
//! neighbourhood of `e.behavior` ([`BehaviorSpace::for_each_more_similar`]). The index keeps,
//! for every behavior that occurs in a case, the list of `(case, time)` postings, appended
//! as cases are retained (so each list is in id order and nothing is ever rebuilt).
//!
//! A query probes only the neighbourhoods of its behaviors. For every case it reaches, the
//! probe yields, per query pair in query order, whether the pair counts (exactly: the pair
//! counts iff a posting of the case lies in the neighbourhood) and the best time similarity
//! among the case's pairs there. Summing those best values in query order and dividing by
//! the number of counted pairs gives an *upper bound* on Algorithm 2 that is never below the
//! exact value, not even after rounding (IEEE addition and division are monotone, and the
//! exact value sums, in the same order, a time similarity no larger for each counted pair).
//! Cases are then verified in decreasing order of bound with the exact
//! [`SetSimilarity::compare_problems`], the very function the linear scan calls, and the
//! search stops as soon as no remaining bound can beat (or tie with a smaller id) the best
//! exact value. The contexts of query and case weigh the exact value by a factor in
//! `[0, 1]` (IEEE multiplication by it never increases a value), so the bound of a case's
//! pairs bounds its similarity in any context.
//!
//! Invariant: every case with similarity above zero is reached by the probe (a case no
//! posting of which lies in any neighbourhood counts no pair, so its similarity is 0), and
//! the answer is the linear scan's: same case, bit-identical similarity, ties to the
//! smallest id. Queries and cases must belong to the index's behavior space.

use crate::evaluated::{Evaluated, RelativeTime, SetSimilarity};
use crate::problem::TrustProblem;
use cbr_core::{
    Behavior, Case, CaseBase, CaseId, Exclusion, Retrieved, Retriever, SimilarityMeasure, better,
};
use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap};
use std::mem::size_of;

/// One evaluated pair of a stored case, filed under its behavior.
#[derive(Clone, Copy, Debug)]
struct Posting {
    case: u32,
    time: f64,
}

/// The inverted index over the trust case base.
#[derive(Clone, Debug)]
pub struct InvertedIndex<T = RelativeTime> {
    measure: SetSimilarity<T>,
    /// Postings by behavior rank, each list in case-id order.
    postings: HashMap<u64, Vec<Posting>>,
    /// Number of cases retained so far.
    cases: usize,
}

impl<T> InvertedIndex<T> {
    /// An empty index ranking cases by `measure`.
    pub fn new(measure: SetSimilarity<T>) -> Self {
        Self {
            measure,
            postings: HashMap::new(),
            cases: 0,
        }
    }

    /// About how many bytes the index holds on the heap beyond the case base itself: the
    /// posting lists by capacity and the hash table by capacity (entry plus control byte).
    /// A query also allocates, for its duration, 4 bytes per case and 32 per case reached.
    pub fn heap_bytes(&self) -> usize {
        let table = self.postings.capacity() * (size_of::<(u64, Vec<Posting>)>() + 1);
        let lists: usize = self
            .postings
            .values()
            .map(|list| list.capacity() * size_of::<Posting>())
            .sum();
        table + lists
    }
}

/// What the probe learned about one case.
#[derive(Clone, Copy, Debug)]
struct Bound {
    case: u32,
    /// Sum, in query order, of the best time similarity of every counted query pair.
    total: f64,
    /// Number of counted query pairs.
    matched: u32,
    /// 1 + the query pair that last touched this case.
    stamp: u32,
    /// Best time similarity for the query pair being probed.
    best: f64,
}

/// A case awaiting exact verification, ordered by bound, then smaller id first.
#[derive(Clone, Copy, Debug)]
struct Candidate {
    bound: f64,
    case: u32,
}

impl PartialEq for Candidate {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Candidate {}

impl PartialOrd for Candidate {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Candidate {
    fn cmp(&self, other: &Self) -> Ordering {
        self.bound
            .total_cmp(&other.bound)
            .then_with(|| other.case.cmp(&self.case))
    }
}

impl<T: SimilarityMeasure<f64>> InvertedIndex<T> {
    /// The upper bound of every case the query's neighbourhoods reach.
    fn bounds(&self, query: &[Evaluated]) -> Vec<Bound> {
        let space = self.measure.space();
        let lambda = self.measure.lambda();
        // slot[case] = 1 + the case's position in `bounds`, 0 while unreached.
        let mut slot = vec![0u32; self.cases];
        let mut bounds: Vec<Bound> = Vec::new();
        let mut touched: Vec<usize> = Vec::new();
        for (q, e) in query.iter().enumerate() {
            let stamp = q as u32 + 1;
            space.for_each_more_similar(&e.behavior, lambda, &mut |b: Behavior| {
                let Some(list) = self.postings.get(&space.rank(&b)) else {
                    return;
                };
                for posting in list {
                    let t = self.measure.time_similarity(e.time, posting.time);
                    let s = &mut slot[posting.case as usize];
                    if *s == 0 {
                        bounds.push(Bound {
                            case: posting.case,
                            total: 0.0,
                            matched: 0,
                            stamp: 0,
                            best: 0.0,
                        });
                        *s = bounds.len() as u32;
                    }
                    let at = *s as usize - 1;
                    let bound = &mut bounds[at];
                    if bound.stamp != stamp {
                        bound.stamp = stamp;
                        bound.best = t;
                        touched.push(at);
                    } else if t > bound.best {
                        bound.best = t;
                    }
                }
            });
            for at in touched.drain(..) {
                let bound = &mut bounds[at];
                bound.total += bound.best;
                bound.matched += 1;
            }
        }
        bounds
    }
}

impl<T> Retriever<TrustProblem, Behavior> for InvertedIndex<T>
where
    T: SimilarityMeasure<f64> + Send + Sync,
{
    fn name(&self) -> &str {
        "inverted_index"
    }

    fn retain(&mut self, id: CaseId, case: &Case<TrustProblem, Behavior>) {
        debug_assert_eq!(id.index(), self.cases, "cases are retained in id order");
        let space = self.measure.space();
        for e in &case.problem.evaluated {
            self.postings
                .entry(space.rank(&e.behavior))
                .or_default()
                .push(Posting {
                    case: id.0,
                    time: e.time,
                });
        }
        self.cases += 1;
    }

    fn retrieve(
        &self,
        base: &CaseBase<TrustProblem, Behavior>,
        query: &TrustProblem,
        exclude: Exclusion<'_, TrustProblem, Behavior>,
    ) -> Option<Retrieved> {
        debug_assert_eq!(base.len(), self.cases, "the index has seen every case");
        let mut queue: BinaryHeap<Candidate> = self
            .bounds(&query.evaluated)
            .into_iter()
            .map(|b| Candidate {
                bound: b.total / f64::from(b.matched),
                case: b.case,
            })
            .collect();
        let mut best: Option<Retrieved> = None;
        while let Some(next) = queue.pop() {
            let can_win = match best {
                None => next.bound > 0.0,
                Some(b) => {
                    next.bound > b.similarity || (next.bound == b.similarity && next.case < b.id.0)
                }
            };
            if !can_win {
                // Every remaining bound is at most this one: none can win either.
                break;
            }
            let id = CaseId(next.case);
            let case = base.get(id).expect("indexed cases are stored");
            if exclude(case) {
                continue;
            }
            let similarity = self.measure.compare_problems(query, &case.problem);
            best = better(best, Retrieved { id, similarity });
        }
        best
    }
}
