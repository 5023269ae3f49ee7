//! Retrieval: finding the most similar stored case for a query.
//!
//! A [`Retriever`] owns its similarity measure and any index it builds. It is told of every
//! case appended to the case base ([`Retriever::retain`]), so an index can grow
//! incrementally, and it answers queries with an exclusion predicate. [`LinearRetriever`]
//! scans every case and is the reference: every other retriever must return exactly its
//! answer, ties included.

use crate::case::{Case, CaseBase, CaseId};
use crate::similarity::SimilarityMeasure;

/// The answer to a retrieval query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Retrieved {
    /// The best case.
    pub id: CaseId,
    /// Its similarity to the query.
    pub similarity: f64,
}

/// Tells which cases a query must not return.
pub type Exclusion<'a, P, S> = &'a dyn Fn(&Case<P, S>) -> bool;

/// A strategy for finding the best case for a query.
///
/// Contract: among the cases not excluded, return the one of greatest similarity to the
/// query *strictly above zero*; on equal similarity the case with the smallest id wins;
/// `None` when no case qualifies.
pub trait Retriever<P, S>: Send + Sync {
    /// A short name for configs and reports (e.g. `linear`).
    fn name(&self) -> &str;

    /// Called once for every case appended to the base, in id order.
    fn retain(&mut self, id: CaseId, case: &Case<P, S>);

    /// The best case for `query` in `base`, skipping cases for which `exclude` is true.
    fn retrieve(
        &self,
        base: &CaseBase<P, S>,
        query: &P,
        exclude: Exclusion<'_, P, S>,
    ) -> Option<Retrieved>;
}

/// Keeps the better of two candidates under the retrieval contract (greater similarity,
/// then smaller id).
pub fn better(current: Option<Retrieved>, candidate: Retrieved) -> Option<Retrieved> {
    match current {
        Some(c)
            if c.similarity > candidate.similarity
                || (c.similarity == candidate.similarity && c.id < candidate.id) =>
        {
            Some(c)
        }
        _ if candidate.similarity > 0.0 => Some(candidate),
        other => other,
    }
}

/// The reference retriever: compares the query with every case, in order.
#[derive(Clone, Debug)]
pub struct LinearRetriever<M> {
    measure: M,
}

impl<M> LinearRetriever<M> {
    /// A linear scan under `measure`.
    pub fn new(measure: M) -> Self {
        Self { measure }
    }

    /// The measure it ranks cases by.
    pub fn measure(&self) -> &M {
        &self.measure
    }
}

impl<P, S, M> Retriever<P, S> for LinearRetriever<M>
where
    M: SimilarityMeasure<P> + Send + Sync,
{
    fn name(&self) -> &str {
        "linear"
    }

    fn retain(&mut self, _id: CaseId, _case: &Case<P, S>) {}

    fn retrieve(
        &self,
        base: &CaseBase<P, S>,
        query: &P,
        exclude: Exclusion<'_, P, S>,
    ) -> Option<Retrieved> {
        let mut best = None;
        for (id, case) in base.iter() {
            if exclude(case) {
                continue;
            }
            let similarity = self.measure.similarity(query, &case.problem);
            // Strictly greater: the earliest case keeps ties.
            if similarity > best.map_or(0.0, |b: Retrieved| b.similarity) {
                best = Some(Retrieved { id, similarity });
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn base(problems: &[f64]) -> CaseBase<f64, usize> {
        let mut base = CaseBase::new();
        for (i, &p) in problems.iter().enumerate() {
            base.push(Case {
                problem: p,
                solution: i,
            });
        }
        base
    }

    fn closeness(a: &f64, b: &f64) -> f64 {
        (1.0 - (a - b).abs()).max(0.0)
    }

    #[test]
    fn linear_scan_finds_the_most_similar_earliest_case() {
        let base = base(&[0.1, 0.5, 0.9, 0.5]);
        let r = LinearRetriever::new(closeness);
        let best = r.retrieve(&base, &0.55, &|_| false).unwrap();
        // |0.55 - 0.5| = 0.05 for cases 1 and 3: the tie goes to case 1.
        assert_eq!(best.id, CaseId(1));
        assert!((best.similarity - 0.95).abs() < 1e-12);
        let best = r.retrieve(&base, &0.55, &|c| c.solution == 1).unwrap();
        assert_eq!(best.id, CaseId(3));
    }

    #[test]
    fn zero_similarity_is_never_returned() {
        let base = base(&[5.0]);
        let r = LinearRetriever::new(closeness);
        assert_eq!(r.retrieve(&base, &0.0, &|_| false), None);
    }

    #[test]
    fn better_prefers_similarity_then_id() {
        let a = Retrieved {
            id: CaseId(4),
            similarity: 0.5,
        };
        let b = Retrieved {
            id: CaseId(2),
            similarity: 0.5,
        };
        assert_eq!(better(Some(a), b), Some(b));
        assert_eq!(better(Some(b), a), Some(b));
        let zero = Retrieved {
            id: CaseId(0),
            similarity: 0.0,
        };
        assert_eq!(better(None, zero), None);
    }
}
