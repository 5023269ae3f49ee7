//! Search strategies for trust-guided adaptation: what to try when no case helps.
//!
//! Every strategy implements [`cbr_core::Searcher`] over [`crate::Evaluated`] evidence and
//! [`crate::Outcome`] feedback; [`TrustSearcher`] names that shape. One file per strategy:
//! - [`RandomWalk`]: the paper's `modifyBehavior`;
//! - [`Uniform`]: uniform among untried behaviors, the honest baseline;
//! - [`CauseAware`]: learns which component values bring which signals of failure (stated
//!   reasons, what the robot perceived);
//! - `ModelBased`: a Gaussian-process surrogate of the operator, solved with faer (the
//!   `model-based` cargo feature, on by default);
//! - [`Conditioned`]: what earlier operators trusted, weighed by how consistent each is
//!   with this episode's rejections (the operators who disagree are told apart); as
//!   `hedged` (the `model-based` feature) it falls back to the cause-aware and the
//!   model-based searches taking turns ([`Alternating`]).
//!
//! [`SearchKind`] names the built-in ones in configs.

pub mod alternating;
pub mod cause_aware;
pub mod conditioned;
#[cfg(feature = "model-based")]
pub mod model_based;
pub mod random_walk;
pub mod uniform;
mod untried;
pub mod value_counts;

pub use alternating::Alternating;
pub use cause_aware::CauseAware;
pub use conditioned::Conditioned;
#[cfg(feature = "model-based")]
pub use model_based::ModelBased;
pub use random_walk::RandomWalk;
pub use uniform::Uniform;
pub use untried::{best_untried, cheapest, draw_untried, evaluated_set};
pub use value_counts::ValueCounts;

use crate::{Evaluated, Outcome};
use cbr_core::{Behavior, BehaviorSpace, Proposal, Searcher};
use rand::RngCore;
use serde::{Deserialize, Serialize};
use std::collections::HashSet;

/// A search strategy as the trust adapter drives it.
pub type TrustSearcher = dyn Searcher<Evidence = Evaluated, Feedback = Outcome>;

/// Builds a fresh searcher for a behavior space: how a user's searcher enters an
/// experiment arm or a `serve` session, exactly as the built-in ones do.
pub type SearcherFactory =
    std::sync::Arc<dyn Fn(&std::sync::Arc<BehaviorSpace>) -> Box<TrustSearcher> + Send + Sync>;

/// `E_max`: the first evaluated pair with the largest time (it resisted the longest).
pub fn longest_resisting(evaluated: &[Evaluated]) -> Option<&Evaluated> {
    evaluated
        .iter()
        .fold(None, |best: Option<&Evaluated>, e| match best {
            Some(b) if b.time >= e.time => Some(b),
            _ => Some(e),
        })
}

/// The frame every search among untried behaviors shares: with no evidence yet, a uniform
/// draw; otherwise `choose` picks one of the untried behaviors (it is handed the set of
/// evaluated ones), and when it finds none the space is exhausted and `E_max` is kept.
pub fn propose_untried(
    space: &BehaviorSpace,
    evaluated: &[Evaluated],
    rng: &mut dyn RngCore,
    choose: impl FnOnce(&HashSet<Behavior>, &mut dyn RngCore) -> Option<Behavior>,
) -> Proposal {
    let Some(e_max) = longest_resisting(evaluated) else {
        return Proposal::Next(space.draw(rng));
    };
    match choose(&evaluated_set(evaluated), rng) {
        Some(b) => Proposal::Next(b),
        None => Proposal::Exhausted {
            keep: e_max.behavior,
        },
    }
}

/// The built-in search strategies a config can name.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum SearchKind {
    /// The paper's random walk ([`RandomWalk`]).
    #[default]
    RandomWalk,
    /// Uniform among untried behaviors ([`Uniform`]).
    Uniform,
    /// Cause-aware search ([`CauseAware`]).
    CauseAware,
    /// Model-based search (`ModelBased`; the `model-based` feature).
    #[cfg(feature = "model-based")]
    ModelBased,
    /// Conditioned search ([`Conditioned`]).
    Conditioned,
    /// Conditioned search falling back to the cause-aware and the model-based searches in
    /// turn ([`Conditioned::hedged`]; the `model-based` feature).
    #[cfg(feature = "model-based")]
    Hedged,
}

impl SearchKind {
    /// Every kind built in, the paper's first.
    #[cfg(feature = "model-based")]
    pub const ALL: &[SearchKind] = &[
        SearchKind::RandomWalk,
        SearchKind::Uniform,
        SearchKind::CauseAware,
        SearchKind::ModelBased,
        SearchKind::Conditioned,
        SearchKind::Hedged,
    ];
    /// Every kind built in, the paper's first.
    #[cfg(not(feature = "model-based"))]
    pub const ALL: &[SearchKind] = &[
        SearchKind::RandomWalk,
        SearchKind::Uniform,
        SearchKind::CauseAware,
        SearchKind::Conditioned,
    ];

    /// A fresh searcher of this kind.
    pub fn build(self) -> Box<TrustSearcher> {
        match self {
            SearchKind::RandomWalk => Box::new(RandomWalk::new()),
            SearchKind::Uniform => Box::new(Uniform::new()),
            SearchKind::CauseAware => Box::new(CauseAware::new()),
            #[cfg(feature = "model-based")]
            SearchKind::ModelBased => Box::new(ModelBased::new()),
            SearchKind::Conditioned => Box::new(Conditioned::new()),
            #[cfg(feature = "model-based")]
            SearchKind::Hedged => Box::new(Conditioned::hedged()),
        }
    }

    /// The strategy's name in reports and arm names (`random-walk`, `cause-aware`, ...).
    pub fn name(self) -> &'static str {
        match self {
            SearchKind::RandomWalk => "random-walk",
            SearchKind::Uniform => "uniform",
            SearchKind::CauseAware => "cause-aware",
            #[cfg(feature = "model-based")]
            SearchKind::ModelBased => "model-based",
            SearchKind::Conditioned => "conditioned",
            #[cfg(feature = "model-based")]
            SearchKind::Hedged => "hedged",
        }
    }
}

/// A space of numeric components `c0, c1, ...` with `sizes[k]` values each, for the
/// searchers' unit tests.
#[cfg(test)]
pub(crate) fn grid(sizes: &[u16]) -> BehaviorSpace {
    BehaviorSpace::new(
        sizes
            .iter()
            .enumerate()
            .map(|(k, &n)| {
                cbr_core::NamedComponent::numeric(&format!("c{k}"), "", 0.0, 1.0, n)
                    .expect("a valid grid")
            })
            .collect(),
    )
    .expect("a valid space")
}
