//! Conformance kits for a user's own parts (behind the `testing` feature).
//!
//! - [`check_searcher`]: the properties every search strategy must have (never an
//!   evaluated behavior while untried ones remain, `Exhausted` only when the space is,
//!   deterministic for a seed, correct across episodes); [`searcher_conformance`] checks
//!   them on given spaces (a domain's own) and returns the [`SearcherRule`] broken with
//!   its case instead of panicking;
//! - [`check_retriever`]: every retriever returns the linear scan's answer bit for bit
//!   (same case, same similarity, ties to the smallest id), told of cases incrementally,
//!   under exclusions, and inside an adapter.
//!
//! Every built-in searcher and retriever passes them (`trust/tests/integration/searchers.rs`,
//! `trust/tests/integration/retrievers.rs`), and a user's parts are checked the same way, from a test
//! of the user's crate with `trust = { ..., features = ["testing"] }`:
//!
//! ```
//! use std::sync::Arc;
//! use trust::{SetSimilarity, TrustRetriever};
//!
//! trust::testing::check_searcher(|| Box::new(trust::search::Uniform::new()));
//!
//! // A user's retriever, ranking cases by the measure it is given (here the reference
//! // scan itself, standing in for the user's own index).
//! trust::testing::check_retriever(|measure: SetSimilarity| {
//!     Box::new(cbr_core::LinearRetriever::new(measure)) as Box<TrustRetriever>
//! });
//! ```

mod retriever;
mod searcher;

pub use retriever::check_retriever;
pub use searcher::{
    SearcherFailure, SearcherRule, check_searcher, check_searcher_on, searcher_conformance,
};
