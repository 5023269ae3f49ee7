//! A parallel linear scan: every case compared, the comparisons spread over rayon's threads.
//!
//! Why this one besides the inverted index: the index pays off only while `lambda`'s
//! neighbourhoods are small. With a low `lambda`, heavily weighted-down components, or
//! categorical components whose other labels are all "similar enough", a neighbourhood can
//! cover much of the space and the probe costs more than a scan. The parallel scan makes no
//! assumption about the measure, `lambda` or the behavior space, keeps no index (nothing to
//! build, no memory per case), and turns the cores of a long-running robot or an experiment
//! machine into speed. It is also the honest yardstick for the index: how much of its gain
//! could cores alone buy?
//!
//! Invariant: it computes the same similarity as [`LinearRetriever`](cbr_core::LinearRetriever)
//! for every case (the same measure on the same inputs) and reduces with [`better`], which
//! picks the maximum of a total order (greater similarity, then smaller id, above zero
//! only); the maximum does not depend on how the threads split the work, so the answer is
//! the linear scan's. The exclusion predicate need not be thread-safe: it is evaluated on
//! the calling thread, in one cheap pass, before the comparisons fan out.
//!
//! The thread pool is the `parallel` feature of this crate (rayon), which the experiment
//! lab, the service and the tool turn on. Without it (a robot embedding the adapter alone)
//! the same scan runs on the calling thread: the same answers, without the extra cores.

use cbr_core::{
    Case, CaseBase, CaseId, Exclusion, Retrieved, Retriever, SimilarityMeasure, better,
};
#[cfg(feature = "parallel")]
use rayon::prelude::*;

/// Compares the query with every case on rayon's thread pool (on the calling thread without
/// the `parallel` feature).
#[derive(Clone, Debug)]
pub struct ParallelScan<M> {
    measure: M,
}

impl<M> ParallelScan<M> {
    /// A parallel scan under `measure`.
    pub fn new(measure: M) -> Self {
        Self { measure }
    }
}

fn merge(a: Option<Retrieved>, b: Option<Retrieved>) -> Option<Retrieved> {
    match b {
        Some(candidate) => better(a, candidate),
        None => a,
    }
}

impl<P, S, M> Retriever<P, S> for ParallelScan<M>
where
    P: Sync,
    S: Sync,
    M: SimilarityMeasure<P> + Send + Sync,
{
    fn name(&self) -> &str {
        "parallel_scan"
    }

    fn retain(&mut self, _id: CaseId, _case: &Case<P, S>) {}

    fn retrieve(
        &self,
        base: &CaseBase<P, S>,
        query: &P,
        exclude: Exclusion<'_, P, S>,
    ) -> Option<Retrieved> {
        let excluded: Vec<bool> = base.iter().map(|(_, case)| exclude(case)).collect();
        let compare = |(i, (case, skip)): (usize, (&Case<P, S>, &bool))| {
            (!*skip).then(|| Retrieved {
                id: CaseId(i as u32),
                similarity: self.measure.similarity(query, &case.problem),
            })
        };
        #[cfg(feature = "parallel")]
        let best = base
            .cases()
            .par_iter()
            .zip(excluded.par_iter())
            .enumerate()
            .map(compare)
            .reduce(|| None, merge);
        #[cfg(not(feature = "parallel"))]
        let best = base
            .cases()
            .iter()
            .zip(&excluded)
            .enumerate()
            .map(compare)
            .fold(None, merge);
        best
    }
}
