#![doc = include_str!("../README.md")]
#![deny(missing_docs)]

pub mod behavior;
pub mod case;
pub mod component;
pub mod context;
pub mod memory;
pub mod neighbourhood;
pub mod retrieve;
pub mod search;
pub mod shown;
pub mod similarity;
pub mod space_diff;
pub mod statement;
#[cfg(any(test, feature = "testing"))]
pub mod testing;
pub mod unique_keys;

pub use behavior::{Behavior, BehaviorSpace, MAX_COMPONENTS, SpaceError};
pub use case::{Case, CaseBase, CaseId};
pub use component::{
    Categorical, Component, ComponentError, ComponentKind, CustomComponent, KindError, KindProblem,
    NamedComponent, NumericGrid, RegistryError, Values, register_component_kind,
    registered_component_kinds,
};
pub use context::{Context, ContextError, ContextSimilarity, ContextSpace, ContextVariable};
pub use memory::CaseMemory;
pub use retrieve::{Exclusion, LinearRetriever, Retrieved, Retriever, better};
pub use search::{Proposal, Rationale, Searcher};
pub use shown::{Shown, shown};
pub use similarity::SimilarityMeasure;
pub use space_diff::SpaceDifference;
pub use statement::Statement;

/// The random-number crate of `BehaviorSpace::draw` and the `Searcher` trait, re-exported so
/// a user names the same version.
pub use rand;
