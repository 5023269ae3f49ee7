//! Uniform sampling of untried behaviors: the honest baseline of every informed search.
//!
//! Each proposal is drawn uniformly among the behaviors the episode has not evaluated,
//! without looking at where the evaluated ones lie. On this project's simulator it needs
//! an order of magnitude fewer behaviors than the paper's random walk in patrol, so every
//! claim about a strategy is made against it as well.

use super::propose_untried;
use super::registry::{Look, Marker, Strategy};
use super::untried::draw_untried;
use crate::{Evaluated, Outcome};
use cbr_core::{Behavior, BehaviorSpace, Proposal, Rationale, Searcher};
use rand::RngCore;

/// Uniform among the unevaluated behaviors; when every behavior has been evaluated it
/// stops and keeps `E_max`, as the random walk does.
#[derive(Clone, Debug, Default)]
pub struct Uniform;

/// The uniform search as the tool offers it: alone, the baseline.
pub const STRATEGY: Strategy = Strategy {
    name: "uniform",
    description: "an untried behavior uniformly at random: the baseline a learning strategy must beat",
    look: Look {
        colour: [0, 0, 0],
        marker: Marker::Diamond,
    },
    with_cases: None,
    build: || Box::new(Uniform::new()),
};

impl Uniform {
    /// The uniform sampler.
    pub fn new() -> Self {
        Self
    }
}

impl Searcher for Uniform {
    type Evidence = Evaluated;
    type Feedback = Outcome;

    fn name(&self) -> &str {
        STRATEGY.name
    }

    // It proposes from the episode's evidence alone: told a context or statements, it
    // proposes the same.
    fn reads_context(&self) -> bool {
        false
    }

    fn hears_statements(&self) -> bool {
        false
    }

    fn propose(
        &mut self,
        space: &BehaviorSpace,
        evaluated: &[Evaluated],
        rng: &mut dyn RngCore,
    ) -> Proposal {
        propose_untried(space, evaluated, rng, |tried, rng| {
            draw_untried(space, tried, 1, rng).first().copied()
        })
    }

    fn rationale(&self, _proposed: &Behavior) -> Rationale {
        Rationale::Explores {
            how: "an untried behavior drawn uniformly".into(),
        }
    }
}
