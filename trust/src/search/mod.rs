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
//!   model-based searches taking turns ([`Alternating`]); as `bandit` (the same feature)
//!   the two share the proposals under a lead learned across episodes ([`Bandit`]); as
//!   `reliable` (the same feature) it ranks what it may propose by how often the whole
//!   population lets each behavior complete ([`reliable::PopulationReliability`]); as
//!   `nested` (the same feature) that one's fallback shares its turns with a search
//!   nearest to what earlier operators trusted ([`Nested`]).
//!
//! Each file declares its strategy (`STRATEGY`), registered in one place
//! ([`registry::strategies`]); [`SearchKind`] names a registered one in configs.

pub mod alternating;
#[cfg(feature = "model-based")]
pub mod bandit;
pub mod cause_aware;
pub mod conditioned;
#[cfg(feature = "model-based")]
pub mod model_based;
#[cfg(feature = "model-based")]
pub mod nested;
mod pair;
pub mod random_walk;
pub mod registry;
#[cfg(feature = "model-based")]
pub mod reliable;
pub mod uniform;
mod untried;
pub mod value_counts;

pub use alternating::Alternating;
#[cfg(feature = "model-based")]
pub use bandit::Bandit;
pub use cause_aware::CauseAware;
pub use conditioned::Conditioned;
#[cfg(feature = "model-based")]
pub use model_based::ModelBased;
#[cfg(feature = "model-based")]
pub use nested::Nested;
pub use random_walk::RandomWalk;
pub use registry::{Look, Marker, Rgb, Strategy, WithCases, strategies, strategy};
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

/// A built-in search strategy as a config names it (`search: cause_aware`): one of
/// [`registry::strategies`], written with `_` for `-`. The paper's random walk by default.
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct SearchKind(&'static Strategy);

impl SearchKind {
    /// The built-in strategy named `name` (as in arm names: `cause-aware`).
    pub fn named(name: &str) -> Option<Self> {
        registry::strategy(name).map(Self)
    }

    /// Every built-in strategy, the paper's first.
    pub fn all() -> impl Iterator<Item = SearchKind> {
        registry::strategies().iter().map(Self)
    }

    /// A fresh searcher of this strategy.
    pub fn build(self) -> Box<TrustSearcher> {
        (self.0.build)()
    }

    /// The strategy's name in reports and arm names (`random-walk`, `cause-aware`, ...).
    pub fn name(self) -> &'static str {
        self.0.name
    }

    /// The strategy as registered.
    pub fn strategy(self) -> &'static Strategy {
        self.0
    }
}

impl Default for SearchKind {
    fn default() -> Self {
        Self(&registry::strategies()[0])
    }
}

impl std::fmt::Debug for SearchKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.0.config_name())
    }
}

impl Serialize for SearchKind {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let index = registry::strategies()
            .iter()
            .position(|s| s == self.0)
            .unwrap_or(0);
        serializer.serialize_unit_variant(
            "SearchKind",
            u32::try_from(index).unwrap_or(u32::MAX),
            self.0.config_name(),
        )
    }
}

impl<'de> Deserialize<'de> for SearchKind {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        /// A unit variant of the registry's names (RON writes it bare, JSON as a string).
        struct Named;
        impl<'de> serde::de::Visitor<'de> for Named {
            type Value = SearchKind;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a search strategy's name")
            }
            fn visit_str<E: serde::de::Error>(self, name: &str) -> Result<SearchKind, E> {
                registry::strategies()
                    .iter()
                    .find(|s| s.config_name() == name)
                    .map(SearchKind)
                    .ok_or_else(|| E::unknown_variant(name, registry::config_names()))
            }
            fn visit_enum<A: serde::de::EnumAccess<'de>>(
                self,
                data: A,
            ) -> Result<SearchKind, A::Error> {
                use serde::de::VariantAccess;
                let (VariantName(name), variant) = data.variant()?;
                variant.unit_variant()?;
                self.visit_str(&name)
            }
        }
        /// A variant's name, read as an identifier (RON writes it bare).
        struct VariantName(String);
        impl<'de> Deserialize<'de> for VariantName {
            fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                struct Identifier;
                impl serde::de::Visitor<'_> for Identifier {
                    type Value = VariantName;
                    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                        f.write_str("a search strategy's name")
                    }
                    fn visit_str<E: serde::de::Error>(self, name: &str) -> Result<VariantName, E> {
                        Ok(VariantName(name.to_owned()))
                    }
                }
                d.deserialize_identifier(Identifier)
            }
        }
        deserializer.deserialize_enum("SearchKind", registry::config_names(), Named)
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

/// Always proposes one fixed behavior, and counts what it is told: a searcher whose
/// proposals a combining searcher's unit test can tell apart.
#[cfg(test)]
#[derive(Default)]
pub(crate) struct Fixed {
    pub(crate) at: u16,
    pub(crate) observed: usize,
    pub(crate) ended: usize,
}

#[cfg(test)]
impl Searcher for Fixed {
    type Evidence = Evaluated;
    type Feedback = Outcome;
    fn name(&self) -> &str {
        "fixed"
    }
    fn propose(&mut self, _: &BehaviorSpace, _: &[Evaluated], _: &mut dyn RngCore) -> Proposal {
        Proposal::Next(Behavior::new(&[self.at]))
    }
    fn rationale(&self, _: &Behavior) -> cbr_core::Rationale {
        cbr_core::Rationale::Explores {
            how: format!("always {}", self.at).into(),
        }
    }
    fn observe(&mut self, _: &Behavior, _: &Outcome) {
        self.observed += 1;
    }
    fn end_episode(&mut self, _: &[Evaluated], _: Option<&Behavior>) {
        self.ended += 1;
    }
}
