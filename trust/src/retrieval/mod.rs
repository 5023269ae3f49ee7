//! The retrievers available for the trust case base and how a config names them.
//!
//! - [`LinearRetriever`] (`linear`): the reference scan of cbr-core.
//! - [`InvertedIndex`] (`inverted_index`): postings by behavior, probed only within
//!   `lambda`'s neighbourhoods, then exact verification in order of an upper bound.
//! - [`ParallelScan`] (`parallel_scan`): the reference scan spread over threads.
//!
//! Every kind returns the linear scan's answer (same case, bit-identical similarity, ties
//! to the smallest id), so the choice changes speed and memory, never results;
//! `trust/tests/integration/retrievers.rs` checks this for every kind in [`RetrieverKind::ALL`].

mod inverted;
mod parallel;

pub use inverted::InvertedIndex;
pub use parallel::ParallelScan;

use crate::TrustRetriever;
use crate::evaluated::{LambdaError, SetSimilarity};
use cbr_core::{BehaviorSpace, LinearRetriever};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Builds a retriever ranking cases by the measure it is given (Algorithm 2 over the
/// behavior space at the adapter's `lambda`, weighing contexts as the domain declares):
/// how a user's retriever enters an experiment arm or a `serve` session, exactly as the
/// built-in ones do ([`RetrieverKind::build_measure`]).
pub type RetrieverFactory = Arc<dyn Fn(SetSimilarity) -> Box<TrustRetriever> + Send + Sync>;

/// Which retriever answers Algorithm 1's queries. Every kind returns the same answers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum RetrieverKind {
    /// Compare the episode with every case ([`LinearRetriever`]); the reference.
    #[default]
    Linear,
    /// Probe an inverted index of the cases' behaviors ([`InvertedIndex`]); fast while
    /// `lambda` is near 1.
    InvertedIndex,
    /// Compare the episode with every case on all cores ([`ParallelScan`]); for any `lambda`.
    ParallelScan,
}

impl RetrieverKind {
    /// Every kind, the reference first.
    pub const ALL: [RetrieverKind; 3] = [
        RetrieverKind::Linear,
        RetrieverKind::InvertedIndex,
        RetrieverKind::ParallelScan,
    ];

    /// Builds the retriever over `space` with Algorithm 2's threshold `lambda`.
    pub fn build(
        self,
        space: Arc<BehaviorSpace>,
        lambda: f64,
    ) -> Result<Box<TrustRetriever>, LambdaError> {
        Ok(self.build_measure(SetSimilarity::new(space, lambda)?))
    }

    /// The retriever ranking cases by `measure`: how a domain that declares how similar
    /// its contexts are ([`SetSimilarity::with_context_similarity`]) gets any kind.
    pub fn build_measure(self, measure: SetSimilarity) -> Box<TrustRetriever> {
        match self {
            RetrieverKind::Linear => Box::new(LinearRetriever::new(measure)),
            RetrieverKind::InvertedIndex => Box::new(InvertedIndex::new(measure)),
            RetrieverKind::ParallelScan => Box::new(ParallelScan::new(measure)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cbr_core::NamedComponent;

    #[test]
    fn config_names_are_the_retrievers_names() {
        let space = Arc::new(
            BehaviorSpace::new(vec![NamedComponent::numeric("x", "", 0.0, 1.0, 3).unwrap()])
                .unwrap(),
        );
        for kind in RetrieverKind::ALL {
            let retriever = kind.build(space.clone(), 0.95).unwrap();
            let name = format!("\"{}\"", retriever.name());
            assert_eq!(serde_json::to_string(&kind).unwrap(), name);
            let back: RetrieverKind = serde_json::from_str(&name).unwrap();
            assert_eq!(back, kind);
        }
    }
}
