//! The retrievers available for the trust case base and how a config names them.

use crate::TrustRetriever;
use crate::evaluated::{LambdaError, SetSimilarity};
use cbr_core::{BehaviorSpace, LinearRetriever};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Which retriever answers Algorithm 1's queries. Every kind returns the same answers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RetrieverKind {
    /// Compare the episode with every case ([`LinearRetriever`]); the reference.
    #[default]
    Linear,
}

impl RetrieverKind {
    /// Builds the retriever over `space` with Algorithm 2's threshold `lambda`.
    pub fn build(
        self,
        space: Arc<BehaviorSpace>,
        lambda: f64,
    ) -> Result<Box<TrustRetriever>, LambdaError> {
        let measure = SetSimilarity::new(space, lambda)?;
        Ok(match self {
            RetrieverKind::Linear => Box::new(LinearRetriever::new(measure)),
        })
    }
}
