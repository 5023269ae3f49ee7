//! Nested search: look for a demanding operator's few trusted behaviors inside what the
//! operators served before trusted, nearest first, never twice for operators left unserved.
//!
//! An operator who minds more (a scan standard, a clearance, a tighter deadline) trusts
//! what a more lenient one trusts *and* meets its extra standards: its trustworthy region
//! lies inside the lenient one's, or next to it. On patrol's development instances every
//! member that trusts at most 35 of the 16,000 behaviors has its region, or part of it,
//! inside or one change from another member's (`dev-4`'s two members of 3 behaviors each
//! lie wholly inside the other two members' regions; docs/search-strategies.md,
//! "`nested`", and `docs/probes/nested_regions.py`). The fallback searches have no lead to
//! such a region and meet it about as often as uniform sampling does, one behavior in
//! thousands; a search outward from the behaviors earlier operators trusted meets most of
//! them within some dozens.
//!
//! **The rule.** Every behavior an episode settled on is remembered. A nested proposal
//! takes the untried behaviors nearest to the remembered ones (fewest component changes,
//! the lattice distance; distance 0 is a remembered behavior itself) and, among them, the
//! one with the highest completion rate for *this* operator by a main-effects model
//! ([`PopulationReliability::mean_for`]): its own commands per component value, shrunk
//! towards the population's. "Untried" also leaves out every behavior rejected in an
//! episode that ended with nothing trusted: the search for an operator no one has served
//! yet goes on from where the last one stopped instead of repeating the nearest layer.
//!
//! **Its share.** Nested proposals alternate with the wrapped search's, nested first,
//! and the wrapped search proposes alone while nothing is remembered or every behavior
//! has been tried. An operator whose region lies far from every earlier one's costs at
//! most about twice what the wrapped search alone would cost (the argument of
//! [`super::Alternating`]).
//!
//! **Its case reuse.** The conditioned search around it vouches for case reuse
//! (`Conditioned::vouching`): `case-based+nested` reuses a case only when its behavior is
//! what the posterior over earlier operators ranks first, so the case met first no longer
//! outranks the behavior the evidence favours.
//!
//! **Its reliability, conditioned on the operator.** The candidates' expected reliability
//! is not the population's pooled record but each profile's commands weighed by how
//! likely the current episode's rejections are under that profile's operator, over the
//! likeliest (`ByOperator::posterior`): on a population whose members' regions are
//! disjoint, what another kind of operator completed or failed no longer ranks what this
//! kind trusts.

use super::registry::{Look, Marker, Strategy, WithCases};
use super::reliable::PopulationReliability;
use super::untried::evaluated_set;
use super::{Alternating, CauseAware, Conditioned, ModelBased};
use crate::{Evaluated, Outcome};
use cbr_core::{Behavior, BehaviorSpace, Context, Proposal, Rationale, Searcher, Statement};
use rand::RngCore;
use std::collections::HashSet;

/// The nested search as the tool offers it, alone and after case reuse.
pub const STRATEGY: Strategy = Strategy {
    name: "nested",
    description: "the reliable search, whose own search when nothing remembered fits looks, on every other turn, nearest to what earlier operators trusted (where demanding operators' small regions lie) for what this operator's record rates best, never twice where an unserved operator rejected",
    look: Look {
        colour: [86, 180, 233],
        marker: Marker::Diamond,
    },
    with_cases: Some(WithCases {
        name: "case-based+nested",
        description: "case reuse first where the nested search's posterior vouches for the case, the nested search otherwise",
        look: Look {
            colour: [0, 158, 115],
            marker: Marker::Hexagon,
        },
    }),
    build: || Box::new(nested()),
};

/// The searcher of [`STRATEGY`]: the reliable search ([`super::reliable`]) whose fallback,
/// the cause-aware and the model-based searches in turn, shares its turns with nested
/// proposals.
pub fn nested() -> Conditioned<Nested<Alternating<CauseAware, ModelBased>>> {
    Conditioned::with_population(
        STRATEGY.name,
        Nested::new(Alternating::new(CauseAware::new(), ModelBased::new())),
    )
    .conditioned_on_operator()
    .vouching()
}

/// Proposes nearest to what earlier operators trusted on every other turn, and `F`'s
/// proposals otherwise (see the module documentation).
#[derive(Clone, Debug, Default)]
pub struct Nested<F> {
    inner: F,
    /// The behaviors episodes settled on, in the order first met.
    remembered: Vec<Behavior>,
    /// The same behaviors, for lookups.
    known: HashSet<Behavior>,
    /// Behaviors rejected in episodes that ended with nothing trusted.
    unserved: HashSet<Behavior>,
    /// Every command observed.
    population: PopulationReliability,
    /// The current episode's commands.
    episode: PopulationReliability,
    /// Whether the next proposal is a nested one.
    nested_next: bool,
    /// The lattice distance of the last nested proposal (`None`: the last was `F`'s).
    last: Option<u32>,
}

impl<F> Nested<F> {
    /// `inner`'s search sharing its turns with nested proposals, nested first.
    pub fn new(inner: F) -> Self {
        Self {
            inner,
            remembered: Vec::new(),
            known: HashSet::new(),
            unserved: HashSet::new(),
            population: PopulationReliability::default(),
            episode: PopulationReliability::default(),
            nested_next: true,
            last: None,
        }
    }

    /// The behaviors not `tried` at the smallest lattice distance from the remembered
    /// ones that has any, with that distance; `None` when nothing is remembered or every
    /// behavior reachable is `tried`.
    fn nearest_untried(
        &self,
        space: &BehaviorSpace,
        tried: impl Fn(&Behavior) -> bool,
    ) -> Option<(u32, Vec<Behavior>)> {
        let mut seen = self.known.clone();
        let mut layer = self.remembered.clone();
        let mut distance = 0;
        while !layer.is_empty() {
            let untried: Vec<Behavior> = layer.iter().filter(|b| !tried(b)).copied().collect();
            if !untried.is_empty() {
                return Some((distance, untried));
            }
            let mut next = Vec::new();
            for b in &layer {
                next.extend(space.neighbours(b).filter(|n| seen.insert(*n)));
            }
            layer = next;
            distance += 1;
        }
        None
    }

    /// The nested proposal for an episode that evaluated `evaluated`, with its distance.
    fn nearest(
        &self,
        space: &BehaviorSpace,
        evaluated: &[Evaluated],
        rng: &mut dyn RngCore,
    ) -> Option<(u32, Behavior)> {
        let evaluated = evaluated_set(evaluated);
        let (distance, layer) = self.nearest_untried(space, |b| {
            evaluated.contains(b) || self.unserved.contains(b)
        })?;
        // The highest rate for this operator; equal rates in a random order.
        layer
            .into_iter()
            .map(|b| {
                (
                    (self.population.mean_for(&self.episode, &b), rng.next_u64()),
                    b,
                )
            })
            .max_by(|(a, _), (b, _)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
            .map(|(_, b)| (distance, b))
    }
}

impl<F> Searcher for Nested<F>
where
    F: Searcher<Evidence = Evaluated, Feedback = Outcome>,
{
    type Evidence = Evaluated;
    type Feedback = Outcome;

    fn name(&self) -> &str {
        "nested"
    }

    fn learns_across_episodes(&self) -> bool {
        true
    }

    fn reads_context(&self) -> bool {
        self.inner.reads_context()
    }

    fn hears_statements(&self) -> bool {
        self.inner.hears_statements()
    }

    fn enter_context(&mut self, context: &Context) {
        self.inner.enter_context(context);
    }

    fn hear(&mut self, stated: &[Statement]) {
        self.inner.hear(stated);
    }

    fn begin_episode(&mut self, space: &BehaviorSpace, initial: &Behavior) {
        self.nested_next = true;
        self.episode = PopulationReliability::default();
        self.inner.begin_episode(space, initial);
    }

    fn propose(
        &mut self,
        space: &BehaviorSpace,
        evaluated: &[Evaluated],
        rng: &mut dyn RngCore,
    ) -> Proposal {
        let nested_turn = self.nested_next;
        self.nested_next = !nested_turn;
        self.last = None;
        if nested_turn && let Some((distance, b)) = self.nearest(space, evaluated, rng) {
            self.last = Some(distance);
            return Proposal::Next(b);
        }
        self.inner.propose(space, evaluated, rng)
    }

    fn rationale(&self, proposed: &Behavior) -> Rationale {
        match self.last {
            Some(0) => Rationale::Explores {
                how: "a behavior an earlier operator trusted, the best rated for this one".into(),
            },
            Some(distance) => Rationale::Explores {
                how: format!(
                    "{distance} change(s) from what earlier operators trusted, the best rated for this operator so near"
                )
                .into(),
            },
            None => self.inner.rationale(proposed),
        }
    }

    fn observe(&mut self, behavior: &Behavior, outcome: &Outcome) {
        let completed = if outcome.is_untrustworthy() { 0.0 } else { 1.0 };
        self.population.add(behavior, 1.0, completed);
        self.episode.add(behavior, 1.0, completed);
        self.inner.observe(behavior, outcome);
    }

    fn end_episode(&mut self, evaluated: &[Evaluated], settled: Option<&Behavior>) {
        match settled {
            // Only a behavior the operator trusted: one kept because every behavior was
            // tried is among the rejected ones.
            Some(b) if !evaluated.iter().any(|e| e.behavior == *b) => {
                if self.known.insert(*b) {
                    self.remembered.push(*b);
                }
            }
            Some(_) => {}
            None => self.unserved.extend(evaluated.iter().map(|e| e.behavior)),
        }
        self.inner.end_episode(evaluated, settled);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::search::{Fixed, grid};
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn evaluated(behaviors: &[[u16; 2]]) -> Vec<Evaluated> {
        behaviors
            .iter()
            .map(|b| Evaluated {
                behavior: Behavior::new(b),
                time: 1.0,
            })
            .collect()
    }

    fn proposal(
        searcher: &mut Nested<Fixed>,
        space: &BehaviorSpace,
        tried: &[Evaluated],
    ) -> [u16; 2] {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        match searcher.propose(space, tried, &mut rng) {
            Proposal::Next(b) => [b.get(0), b.get(1)],
            Proposal::Exhausted { .. } => panic!("a proposal"),
        }
    }

    #[test]
    fn nearest_to_what_was_trusted_the_best_rated_and_never_where_the_unserved_rejected() {
        // A 5 x 5 grid; the inner search always proposes (9, ...) (it only ever reads
        // component 0, so it proposes a one-component behavior: told apart by its length).
        let space = grid(&[5, 5]);
        let mut nested = Nested::new(Fixed {
            at: 9,
            ..Fixed::default()
        });
        // Nothing remembered: the inner search proposes, on every turn.
        nested.begin_episode(&space, &Behavior::new(&[0, 0]));
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        assert_eq!(
            nested.propose(&space, &[], &mut rng),
            Proposal::Next(Behavior::new(&[9]))
        );
        // An episode settles on (2, 2) after (0, 0) was rejected.
        nested.end_episode(&evaluated(&[[0, 0]]), Some(&Behavior::new(&[2, 2])));
        // The next operator rejected (2, 2): the nearest untried are its four neighbours.
        // Its commands on (2, 2) all failed and so did those on (3, 0); on (1, 0) they
        // completed: component 0 at 1 is rated best, so (1, 2) is proposed, then the
        // inner search, then the next nearest.
        nested.begin_episode(&space, &Behavior::new(&[2, 2]));
        for _ in 0..3 {
            nested.observe(&Behavior::new(&[2, 2]), &Outcome::failed(1.0, 1.0));
            nested.observe(&Behavior::new(&[3, 0]), &Outcome::failed(1.0, 1.0));
            nested.observe(&Behavior::new(&[1, 0]), &Outcome::completed(1.0, 1.0));
        }
        let tried = evaluated(&[[2, 2], [3, 0], [1, 0]]);
        assert_eq!(proposal(&mut nested, &space, &tried), [1, 2]);
        assert!(matches!(
            nested.rationale(&Behavior::new(&[1, 2])),
            Rationale::Explores { how } if how.starts_with("1 change(s)")
        ));
        let Proposal::Next(inner) = nested.propose(&space, &tried, &mut rng) else {
            panic!("a proposal");
        };
        assert_eq!(inner, Behavior::new(&[9]));
        // This operator leaves unserved after rejecting (2, 2) and its four neighbours.
        let rejected = evaluated(&[[2, 2], [1, 2], [3, 2], [2, 1], [2, 3]]);
        nested.end_episode(&rejected, None);
        // The next episode starts afresh, yet skips what the unserved one rejected:
        // (2, 2) itself and distance 1 are left out, distance 2 is next.
        nested.begin_episode(&space, &Behavior::new(&[4, 4]));
        let [a, b] = proposal(&mut nested, &space, &evaluated(&[[4, 4]]));
        assert_eq!(a.abs_diff(2) + b.abs_diff(2), 2, "({a}, {b})");
        // A behavior kept because every behavior was tried is not remembered as trusted.
        nested.end_episode(&evaluated(&[[0, 4]]), Some(&Behavior::new(&[0, 4])));
        assert_eq!(nested.remembered, vec![Behavior::new(&[2, 2])]);
    }
}
