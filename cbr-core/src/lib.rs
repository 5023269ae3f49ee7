//! Generic case-based reasoning vocabulary.
//!
//! This crate names the concepts every CBR application here shares and nothing more:
//! [`Component`]s (numeric grids, categorical labels or a user's own [`ComponentKind`]) and
//! the [`BehaviorSpace`] they span, [`SimilarityMeasure`]s, [`Case`]s in
//! an append-only [`CaseBase`], similarity neighbourhoods of a behavior, the first difference between two spaces, [`Retriever`]s
//! (with [`LinearRetriever`] as the reference) kept in step with the base by
//! [`CaseMemory`], and [`Searcher`]s. It knows nothing of trust, robots or experiments;
//! those live in the `trust` and `domains` crates.

#![deny(missing_docs)]

pub mod behavior;
pub mod case;
pub mod component;
pub mod memory;
pub mod neighbourhood;
pub mod retrieve;
pub mod search;
pub mod similarity;
pub mod space_diff;
#[cfg(any(test, feature = "testing"))]
pub mod testing;

pub use behavior::{Behavior, BehaviorSpace, MAX_COMPONENTS, SpaceError};
pub use case::{Case, CaseBase, CaseId};
pub use component::{
    Categorical, Component, ComponentError, ComponentKind, CustomComponent, KindError, KindProblem,
    NamedComponent, NumericGrid, RegistryError, Values, register_component_kind,
    registered_component_kinds,
};
pub use memory::CaseMemory;
pub use retrieve::{Exclusion, LinearRetriever, Retrieved, Retriever, better};
pub use search::{Proposal, Rationale, Searcher};
pub use similarity::SimilarityMeasure;
pub use space_diff::SpaceDifference;

/// The random-number crate of `BehaviorSpace::draw` and the `Searcher` trait, re-exported so
/// a user names the same version.
pub use rand;
