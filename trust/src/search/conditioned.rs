//! Conditioned search: reuse what earlier operators trusted, but only the operators the
//! current episode's evidence says this one may be.
//!
//! What a strategy carries from earlier episodes must not assume the next operator is like
//! the last ones: where operators disagree, what pleased one displeases another. This
//! searcher remembers every earlier episode as an operator *profile*: the behaviors that
//! operator found untrustworthy and the one it trusted in the end (episodes that ended on
//! the same behavior are one profile, their rejections pooled). When the current operator
//! rejects a behavior, each profile is weighed by how likely its operator would have
//! rejected it too, and the search proposes the remembered trusted behavior the weighed
//! profiles most expect the current operator to accept. This is the paper's idea (the
//! path of the search tells operators apart, Algorithm 2), with soft matching instead of
//! a threshold, so a rejection teaches something even when no case matches closely.
//!
//! **The model.** Around a behavior `b`, a profile's operator rejects with a probability
//! estimated from the profile's own behaviors by kernel smoothing with a Beta(1, 1) prior:
//! `P(reject b) = (1 + R(b)) / (2 + R(b) + A(b))`, `R(b)` the summed kernel to the
//! profile's rejected behaviors, `A(b)` the kernel to its trusted one (times the episodes
//! that trusted it). The kernel is `exp(-(1 - sim(a, b)) / KERNEL_SCALE)` over the space's
//! behavior similarity: `KERNEL_SCALE` is the paper's `1 - lambda` (0.05), so behaviors
//! "similar enough" for Algorithm 2 weigh `1/e` or more, and behaviors twice as far weigh
//! `1/e^2`.
//!
//! A profile's weight is its episodes times its likelihood, the product over the episode's
//! rejected behaviors of its `P(reject)`. Beside the profiles stands an *unknown operator*,
//! unlike any met before (the open world: one episode's weight, `P(reject) = 1/2`
//! everywhere). Under each hypothesis the current episode's rejections are that operator's
//! too, so they join its data when a candidate is judged; a candidate's score is the
//! weighed mean of the hypotheses' `P(accept)` at it. Among the remembered trusted behaviors not yet tried whose score beats the prior's even
//! odds (the evidence favours acceptance), the one proposed has the best score times its
//! *reliability*, the share of commands it completed while trusted (Laplace's rule): of two
//! behaviors the same operators trusted, the one trusted after fewer failures costs the
//! next operator fewer untrustworthy commands. Otherwise, and before any episode has
//! ended, the proposal is the *fallback* search's, which this searcher feeds every
//! outcome: the cause-aware search ([`CauseAware`]) for `conditioned`, and for `hedged`
//! the cause-aware and the model-based searches taking turns
//! ([`super::Alternating`]: which of the two fits an operator met for the first time
//! cannot be known in advance, and each fails on operators the other finds).
//!
//! **Vouching for case reuse** (`nested`'s searcher). Algorithm 1 reuses the most similar
//! case, and a case's final behavior is one of the remembered behaviors this searcher
//! weighs, judged there by one resemblance only. A searcher that vouches
//! (`Conditioned::vouching`) doubts a case's behavior unless its posterior ranks it
//! first: among what it may propose, its acceptance beats even odds and no candidate's
//! acceptance times expected reliability is higher. Case reuse then passes over it to the
//! next case, or to this searcher. It doubts only what a remembered operator trusted, so
//! cases written by another robot of a fleet, or before a restart, are reused as the paper
//! reuses them.

use super::CauseAware;
use super::propose_untried;
use super::registry::{Look, Marker, Strategy, WithCases};
#[cfg(feature = "model-based")]
use super::reliable::{
    ByOperator, NEIGHBOURHOODS, PopulationReliability, RELIABLE_CANDIDATES, draw_beta,
};
#[cfg(feature = "model-based")]
use super::{Alternating, ModelBased};
use crate::{Evaluated, Outcome};
use cbr_core::{Behavior, BehaviorSpace, Context, Proposal, Rationale, Searcher, Statement};
use rand::RngCore;
use std::collections::HashSet;

/// The kernel's scale in behavior similarity: the paper's `1 - lambda`.
pub const KERNEL_SCALE: f64 = 0.05;

/// Candidates judged per proposal: the trusted behaviors of the most probable profiles
/// (judging one weighs every profile, so this bounds a proposal's cost as profiles grow).
pub const CANDIDATES: usize = 16;

/// One earlier operator, as its episodes left it.
#[derive(Clone, Debug)]
struct Profile {
    /// The behavior it trusted in the end.
    trusted: Behavior,
    /// Episodes that ended on it.
    episodes: f64,
    /// The behaviors those episodes found untrustworthy.
    rejected: Vec<Behavior>,
    /// Commands those episodes gave the trusted behavior, and how many it completed.
    commands: f64,
    /// Completions among them.
    completed: f64,
}

impl Profile {
    /// `P(reject b)` under this profile's operator, its data joined by the current
    /// episode's rejections, whose summed kernel to `b` is `near` ([`near_rejections`],
    /// the same for every profile, so a caller judging many profiles sums it once; see
    /// the module documentation).
    fn p_reject(&self, space: &BehaviorSpace, b: &Behavior, near: f64) -> f64 {
        let rejected = self
            .rejected
            .iter()
            .map(|r| kernel(space, b, r))
            .sum::<f64>()
            + near;
        let accepted = self.episodes * kernel(space, b, &self.trusted);
        (1.0 + rejected) / (2.0 + rejected + accepted)
    }
}

/// The summed kernel from `b` to the behaviors `current` rejected.
fn near_rejections(space: &BehaviorSpace, b: &Behavior, current: &[Evaluated]) -> f64 {
    current.iter().map(|e| kernel(space, b, &e.behavior)).sum()
}

impl Profile {
    /// How reliably its trusted behavior completed commands (Laplace's rule): a behavior
    /// trusted after few failures costs the next operator of its kind few untrustworthy
    /// commands.
    fn reliability(&self) -> f64 {
        (self.completed + 1.0) / (self.commands + 2.0)
    }
}

/// The unknown operator's weight after an episode rejected `evaluated`: one episode's,
/// times `P(reject) = 1/2` per rejection.
fn unknown_weight(evaluated: &[Evaluated]) -> f64 {
    0.5f64.powi(i32::try_from(evaluated.len()).unwrap_or(i32::MAX))
}

/// The similarity kernel between two behaviors.
fn kernel(space: &BehaviorSpace, a: &Behavior, b: &Behavior) -> f64 {
    (-(1.0 - space.similarity(a, b)) / KERNEL_SCALE).exp()
}

/// Each profile's likelihood of an episode's rejections, the product over them of its
/// `P(reject)`, kept between proposals: an episode's evidence grows by one rejection per
/// proposal, so each proposal multiplies in only the rejections since the last one (the
/// products' factors and their order are those of a product taken afresh, so the weights
/// are the same to the last bit).
#[derive(Clone, Debug, Default)]
struct Likelihoods {
    /// The rejected behaviors the products cover, in order.
    covered: Vec<Behavior>,
    /// Per profile, the product of its `P(reject)` over `covered`.
    products: Vec<f64>,
}

impl Likelihoods {
    /// Brings the products up to `evaluated`, starting afresh unless the behaviors covered
    /// so far begin `evaluated` and the profiles are the ones covered.
    fn cover(&mut self, space: &BehaviorSpace, profiles: &[Profile], evaluated: &[Evaluated]) {
        let extends = self.products.len() == profiles.len()
            && self.covered.len() <= evaluated.len()
            && self
                .covered
                .iter()
                .zip(evaluated)
                .all(|(c, e)| *c == e.behavior);
        if !extends {
            self.forget();
            self.products.resize(profiles.len(), 1.0);
        }
        for e in &evaluated[self.covered.len()..] {
            for (product, profile) in self.products.iter_mut().zip(profiles) {
                *product *= profile.p_reject(space, &e.behavior, 0.0);
            }
            self.covered.push(e.behavior);
        }
    }

    /// Forgets every product (the profiles changed, or a new episode began).
    fn forget(&mut self) {
        self.covered.clear();
        self.products.clear();
    }
}

/// A candidate's reliability: its profile's own record, or the population's posterior.
#[derive(Clone, Copy, Debug)]
enum Reliability {
    /// Its profile's own record ([`Profile::reliability`]).
    Own(f64),
    /// The population's posterior `Beta(alpha, beta)` of its completion rate (`reliable`).
    #[cfg(feature = "model-based")]
    Pooled(f64, f64),
}

impl Reliability {
    /// The reliability expected: the record, or the posterior's mean.
    fn mean(self) -> f64 {
        match self {
            Self::Own(reliability) => reliability,
            #[cfg(feature = "model-based")]
            Self::Pooled(alpha, beta) => alpha / (alpha + beta),
        }
    }

    /// The reliability to weigh the candidate by: the record, or one draw from the
    /// posterior.
    #[cfg_attr(not(feature = "model-based"), allow(unused_variables))]
    fn value(self, rng: &mut dyn RngCore) -> f64 {
        match self {
            Self::Own(reliability) => reliability,
            #[cfg(feature = "model-based")]
            Self::Pooled(alpha, beta) => draw_beta(alpha, beta, rng),
        }
    }
}

/// The conditioned searcher, searching with `F` when no remembered behavior is expected
/// to be accepted.
#[derive(Clone, Debug)]
pub struct Conditioned<F = CauseAware> {
    /// The strategy's name: `conditioned`, or `hedged` with the alternating fallback.
    name: &'static str,
    profiles: Vec<Profile>,
    /// The current episode's commands per behavior: (behavior, commands, completions).
    episode: Vec<(Behavior, f64, f64)>,
    fallback: F,
    /// The last remembered behavior proposed and its probability of acceptance (for its
    /// rationale); `None` when the last proposal was the fallback's.
    last: Option<(Behavior, f64)>,
    /// The profiles' likelihoods of the current episode's rejections so far.
    likelihoods: Likelihoods,
    /// The population's reliability, for `reliable` (`None`: each profile's own record).
    #[cfg(feature = "model-based")]
    population: Option<PopulationReliability>,
    /// What each profile's episodes ran, when the population's reliability is conditioned
    /// on the operator (`nested`; `None`: pooled over the population).
    #[cfg(feature = "model-based")]
    by_operator: Option<ByOperator>,
    /// Whether case reuse must be vouched for (`Conditioned::vouching`), and the
    /// scores of the evidence it was last asked about (`None`: the paper's case reuse).
    vouching: Option<Vouching>,
}

/// The scores case reuse is vetted against ([`Conditioned::doubts`]), kept while the
/// evidence stays the same: one selection may pass over several cases.
#[derive(Clone, Debug, Default)]
struct Vouching {
    /// The rejections the scores are for (`None`: none computed since the profiles or
    /// the episode changed).
    covered: Option<usize>,
    /// What the evidence favours, each with its score ([`Conditioned::favoured`]).
    scores: Vec<(Behavior, f64)>,
}

impl Default for Conditioned {
    fn default() -> Self {
        Self::new()
    }
}

/// The conditioned search as the tool offers it, alone and after case reuse.
pub const STRATEGY: Strategy = Strategy {
    name: "conditioned",
    description: "remembers earlier operators' rejected and trusted behaviors, weighed by how much each resembles the current operator",
    look: Look {
        colour: [204, 121, 167],
        marker: Marker::Pentagon,
    },
    with_cases: Some(WithCases {
        name: "case-based+conditioned",
        description: "case reuse first, the conditioned search when no case fits",
        look: Look {
            colour: [0, 0, 0],
            marker: Marker::Plus,
        },
    }),
    build: || Box::new(Conditioned::new()),
};

/// The hedged search (the conditioned one falling back to the cause-aware and the
/// model-based searches in turn) as the tool offers it, alone and after case reuse.
#[cfg(feature = "model-based")]
pub const HEDGED: Strategy = Strategy {
    name: "hedged",
    description: "the conditioned search, whose own search when nothing remembered fits lets the cause-aware and model-based searches propose in turn",
    look: Look {
        colour: [230, 159, 0],
        marker: Marker::Circle,
    },
    with_cases: Some(WithCases {
        name: "case-based+hedged",
        description: "case reuse first, the hedged search when no case fits",
        look: Look {
            colour: [0, 158, 115],
            marker: Marker::Square,
        },
    }),
    build: || Box::new(Conditioned::hedged()),
};

impl Conditioned {
    /// A conditioned searcher that remembers no episode yet, falling back to the
    /// cause-aware search (`conditioned`).
    pub fn new() -> Self {
        Self::with_fallback(STRATEGY.name, CauseAware::new())
    }
}

/// The fallback of `hedged`: the cause-aware and the model-based searches in turn.
#[cfg(feature = "model-based")]
pub type HedgedFallback = Alternating<CauseAware, ModelBased>;

#[cfg(feature = "model-based")]
impl Conditioned<HedgedFallback> {
    /// A conditioned searcher that remembers no episode yet, falling back to the
    /// cause-aware and the model-based searches in turn (`hedged`).
    pub fn hedged() -> Self {
        Self::with_fallback(
            HEDGED.name,
            Alternating::new(CauseAware::new(), ModelBased::new()),
        )
    }
}

impl<F: Searcher<Evidence = Evaluated, Feedback = Outcome>> Conditioned<F> {
    /// A conditioned searcher named `name`, searching with `fallback` when no remembered
    /// behavior is expected to be accepted.
    pub(super) fn with_fallback(name: &'static str, fallback: F) -> Self {
        Self {
            name,
            profiles: Vec::new(),
            episode: Vec::new(),
            fallback,
            last: None,
            likelihoods: Likelihoods::default(),
            #[cfg(feature = "model-based")]
            population: None,
            #[cfg(feature = "model-based")]
            by_operator: None,
            vouching: None,
        }
    }

    /// This searcher, vouching for case reuse: Algorithm 1 reuses a case only when its
    /// solution is what this searcher's posterior ranks first among what it may propose
    /// ([`Conditioned::doubts`]; `case-based+nested`).
    #[cfg(any(test, feature = "model-based"))]
    pub(super) fn vouching(self) -> Self {
        Self {
            vouching: Some(Vouching::default()),
            ..self
        }
    }

    /// This searcher, its reliability conditioned on the operator: each command the
    /// population ran weighed by how likely its operator is to be of the current one's kind
    /// ([`ByOperator::posterior`]; `nested`).
    #[cfg(feature = "model-based")]
    pub(super) fn conditioned_on_operator(self) -> Self {
        Self {
            by_operator: Some(ByOperator::default()),
            ..self
        }
    }

    /// Forgets the scores case reuse was vetted against (the evidence starts afresh or the
    /// profiles changed).
    fn forget_vouching(&mut self) {
        if let Some(vouching) = &mut self.vouching {
            *vouching = Vouching::default();
        }
    }

    /// A conditioned searcher named `name` that ranks what it may propose by the
    /// population's reliability ([`PopulationReliability`], `reliable`), searching with
    /// `fallback` when nothing is expected to be accepted.
    #[cfg(feature = "model-based")]
    pub(super) fn with_population(name: &'static str, fallback: F) -> Self {
        Self {
            population: Some(PopulationReliability::default()),
            ..Self::with_fallback(name, fallback)
        }
    }

    /// The untried behavior the profiles consistent with `evaluated` most expect to be
    /// accepted, weighed by its reliability, if it beats even odds, with its probability of
    /// acceptance; `likelihoods` are the profiles' likelihoods of `evaluated`
    /// ([`Likelihoods`]).
    fn best_remembered(
        &self,
        space: &BehaviorSpace,
        evaluated: &[Evaluated],
        likelihoods: &[f64],
        tried: &HashSet<Behavior>,
        rng: &mut dyn RngCore,
    ) -> Option<(f64, Behavior)> {
        self.above_even_odds(space, evaluated, likelihoods, tried)
            .into_iter()
            .map(|(accept, b, reliability)| (accept, accept * reliability.value(rng), b))
            .fold(
                None,
                |best: Option<(f64, f64, Behavior)>, (accept, score, b)| match best {
                    Some((_, s, _)) if s >= score => best,
                    _ => Some((accept, score, b)),
                },
            )
            .map(|(accept, _, b)| (accept, b))
    }

    /// What may be proposed ([`Conditioned::candidates`], from the most probable profiles,
    /// at most [`CANDIDATES`], whose trusted behavior is not `tried`) that the evidence
    /// favours: each with its probability of acceptance, above even odds, and where its
    /// reliability comes from, in the candidates' order.
    fn above_even_odds(
        &self,
        space: &BehaviorSpace,
        evaluated: &[Evaluated],
        likelihoods: &[f64],
        tried: &HashSet<Behavior>,
    ) -> Vec<(f64, Behavior, Reliability)> {
        let weights = self.weights(likelihoods);
        let mut likely: Vec<(f64, &Profile)> = self
            .profiles
            .iter()
            .zip(&weights)
            .filter(|(p, _)| !tried.contains(&p.trusted))
            .map(|(p, &w)| (w, p))
            .collect();
        likely.sort_by(|a, b| b.0.total_cmp(&a.0));
        likely.truncate(CANDIDATES);
        self.candidates(
            space,
            &likely,
            tried,
            (likelihoods, unknown_weight(evaluated)),
        )
        .into_iter()
        .map(|(b, reliability)| {
            (
                self.acceptance(space, evaluated, &weights, &b),
                b,
                reliability,
            )
        })
        .filter(|&(accept, _, _)| accept > 0.5)
        .collect()
    }

    /// What may be proposed after an episode rejected `evaluated` and the evidence favours,
    /// each with its acceptance times its expected reliability: the scores
    /// [`Conditioned::doubts`] compares.
    fn favoured(&mut self, space: &BehaviorSpace, evaluated: &[Evaluated]) -> Vec<(Behavior, f64)> {
        self.likelihoods.cover(space, &self.profiles, evaluated);
        let tried = super::evaluated_set(evaluated);
        self.above_even_odds(space, evaluated, &self.likelihoods.products, &tried)
            .into_iter()
            .map(|(accept, b, reliability)| (b, accept * reliability.mean()))
            .collect()
    }

    /// Each profile's weight: its episodes times its `likelihood` of the episode's
    /// rejections.
    fn weights(&self, likelihoods: &[f64]) -> Vec<f64> {
        self.profiles
            .iter()
            .zip(likelihoods)
            .map(|(p, likelihood)| likelihood * p.episodes)
            .collect()
    }

    /// The probability that the operator of an episode that rejected `evaluated` accepts
    /// `b`: the hypotheses' `P(accept b)` weighed by the profiles' `weights` and the unknown
    /// operator's (see the module documentation).
    fn acceptance(
        &self,
        space: &BehaviorSpace,
        evaluated: &[Evaluated],
        weights: &[f64],
        b: &Behavior,
    ) -> f64 {
        let unknown = unknown_weight(evaluated);
        let total: f64 = weights.iter().sum::<f64>() + unknown;
        let near = near_rejections(space, b, evaluated);
        let unknown_accept = 1.0 - (1.0 + near) / (2.0 + near);
        (self
            .profiles
            .iter()
            .zip(weights)
            .map(|(p, w)| w * (1.0 - p.p_reject(space, b, near)))
            .sum::<f64>()
            + unknown * unknown_accept)
            / total
    }

    /// What may be proposed, each with where its reliability comes from: the `likely`
    /// profiles' trusted behaviors, each with its profile's own record; with the
    /// population's reliability instead, also their untried neighbours and the behaviors
    /// the population found most reliable. `hypotheses` are the profiles' likelihoods of the
    /// episode's rejections and the unknown operator's, by which a reliability conditioned
    /// on the operator weighs the commands behind it.
    #[cfg_attr(not(feature = "model-based"), allow(unused_variables))]
    fn candidates(
        &self,
        space: &BehaviorSpace,
        likely: &[(f64, &Profile)],
        tried: &HashSet<Behavior>,
        hypotheses: (&[f64], f64),
    ) -> Vec<(Behavior, Reliability)> {
        #[cfg(feature = "model-based")]
        if let Some(population) = &self.population {
            // Conditioned on the operator: each hypothesis's likelihood over the likeliest.
            let conditioned = self.by_operator.as_ref().map(|by_operator| {
                let (likelihoods, unknown) = hypotheses;
                let top = likelihoods.iter().copied().fold(unknown, f64::max);
                let relative: Vec<f64> = likelihoods.iter().map(|l| l / top).collect();
                (by_operator, relative, unknown / top)
            });
            let pooled = |b: Behavior| {
                let (alpha, beta) = match &conditioned {
                    Some((by_operator, relative, unserved)) => {
                        by_operator.posterior(population, &b, relative, *unserved)
                    }
                    None => population.posterior(&b),
                };
                (b, Reliability::Pooled(alpha, beta))
            };
            let mut candidates: Vec<(Behavior, Reliability)> =
                likely.iter().map(|(_, p)| pooled(p.trusted)).collect();
            let mut seen: HashSet<Behavior> = candidates.iter().map(|c| c.0).collect();
            for (_, profile) in likely.iter().take(NEIGHBOURHOODS) {
                for n in space.neighbours(&profile.trusted) {
                    if !tried.contains(&n) && seen.insert(n) {
                        candidates.push(pooled(n));
                    }
                }
            }
            let reliable = population.most_reliable(RELIABLE_CANDIDATES, |b| {
                tried.contains(b) || seen.contains(b)
            });
            candidates.extend(reliable.into_iter().map(pooled));
            return candidates;
        }
        likely
            .iter()
            .map(|(_, p)| (p.trusted, Reliability::Own(p.reliability())))
            .collect()
    }

    /// What a proposal of a remembered behavior expects, in its rationale.
    fn expected(&self) -> &'static str {
        #[cfg(feature = "model-based")]
        if self.population.is_some() {
            return "acceptance: earlier operators like this one trusted it or a behavior one \
                    change away, and operators complete commands with it";
        }
        "acceptance: earlier operators like this one trusted it"
    }
}

impl<F: Searcher<Evidence = Evaluated, Feedback = Outcome>> Searcher for Conditioned<F> {
    type Evidence = Evaluated;
    type Feedback = Outcome;

    fn name(&self) -> &str {
        self.name
    }

    fn learns_across_episodes(&self) -> bool {
        true
    }

    fn enter_context(&mut self, context: &Context) {
        self.fallback.enter_context(context);
    }

    fn hear(&mut self, stated: &[Statement]) {
        self.fallback.hear(stated);
    }

    fn begin_episode(&mut self, space: &BehaviorSpace, initial: &Behavior) {
        self.episode.clear();
        self.likelihoods.forget();
        self.forget_vouching();
        self.fallback.begin_episode(space, initial);
    }

    fn observe(&mut self, behavior: &Behavior, outcome: &Outcome) {
        self.fallback.observe(behavior, outcome);
        let completed = if outcome.is_untrustworthy() { 0.0 } else { 1.0 };
        match self.episode.iter_mut().find(|(b, _, _)| b == behavior) {
            Some((_, commands, completions)) => {
                *commands += 1.0;
                *completions += completed;
            }
            None => self.episode.push((*behavior, 1.0, completed)),
        }
    }

    fn propose(
        &mut self,
        space: &BehaviorSpace,
        evaluated: &[Evaluated],
        rng: &mut dyn RngCore,
    ) -> Proposal {
        self.last = None;
        if evaluated.is_empty() {
            return self.fallback.propose(space, evaluated, rng);
        }
        self.likelihoods.cover(space, &self.profiles, evaluated);
        let likelihoods = &self.likelihoods.products;
        let mut accept = 0.0;
        let remembered = propose_untried(space, evaluated, rng, |tried, rng| {
            self.best_remembered(space, evaluated, likelihoods, tried, rng)
                .map(|(p, b)| {
                    accept = p;
                    b
                })
        });
        match remembered {
            Proposal::Next(b) => {
                self.last = Some((b, accept));
                Proposal::Next(b)
            }
            Proposal::Exhausted { .. } => self.fallback.propose(space, evaluated, rng),
        }
    }

    /// With `Conditioned::vouching` set, doubts a remembered operator's trusted behavior
    /// `b` unless the posterior ranks it first: among what this searcher may propose, its
    /// acceptance above even odds, and no other candidate's acceptance times expected
    /// reliability above its own. A behavior no remembered operator trusted (a case another
    /// robot of a fleet wrote, or one from before a restart) is left to case reuse.
    fn doubts(&mut self, space: &BehaviorSpace, evaluated: &[Evaluated], b: &Behavior) -> bool {
        let covered = match &self.vouching {
            None => return false,
            Some(vouching) => vouching.covered,
        };
        if evaluated.is_empty() || !self.profiles.iter().any(|p| p.trusted == *b) {
            return false;
        }
        if covered != Some(evaluated.len()) {
            let scores = self.favoured(space, evaluated);
            self.vouching = Some(Vouching {
                covered: Some(evaluated.len()),
                scores,
            });
        }
        let Some(Vouching { scores, .. }) = &self.vouching else {
            return false;
        };
        let best = scores.iter().map(|s| s.1).fold(f64::NEG_INFINITY, f64::max);
        scores
            .iter()
            .find(|(c, _)| c == b)
            .is_none_or(|(_, score)| *score < best)
    }

    fn rationale(&self, proposed: &Behavior) -> Rationale {
        match self.last {
            Some((b, accept)) if b == *proposed => Rationale::Expects {
                what: self.expected().into(),
                confidence: Some(accept),
            },
            _ => self.fallback.rationale(proposed),
        }
    }

    fn end_episode(&mut self, evaluated: &[Evaluated], settled: Option<&Behavior>) {
        self.fallback.end_episode(evaluated, settled);
        self.likelihoods.forget();
        self.forget_vouching();
        #[cfg(feature = "model-based")]
        if let Some(population) = &mut self.population {
            for (b, commands, completed) in &self.episode {
                population.add(b, *commands, *completed);
            }
        }
        // Only a behavior the operator trusted is a profile: one kept because every
        // behavior was tried is among the rejected ones.
        // Its profile's index: an earlier one that trusted it, or one past the last.
        let trusted = settled
            .filter(|s| !evaluated.iter().any(|e| e.behavior == **s))
            .map(|&t| {
                let index = self.profiles.iter().position(|p| p.trusted == t);
                (t, index.unwrap_or(self.profiles.len()))
            });
        #[cfg(feature = "model-based")]
        if let Some(by_operator) = &mut self.by_operator {
            by_operator.add(trusted.map(|(_, index)| index), &self.episode);
        }
        let Some((trusted, index)) = trusted else {
            return;
        };
        let rejected = evaluated.iter().map(|e| e.behavior);
        let (commands, completed) = self
            .episode
            .iter()
            .find(|(b, _, _)| *b == trusted)
            .map_or((0.0, 0.0), |&(_, n, c)| (n, c));
        self.episode.clear();
        match self.profiles.get_mut(index) {
            Some(profile) => {
                profile.episodes += 1.0;
                profile.rejected.extend(rejected);
                profile.commands += commands;
                profile.completed += completed;
            }
            None => self.profiles.push(Profile {
                trusted,
                episodes: 1.0,
                rejected: rejected.collect(),
                commands,
                completed,
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn pair(behavior: Behavior) -> Evaluated {
        Evaluated {
            behavior,
            time: 1.0,
        }
    }

    #[test]
    fn the_kernel_by_hand() {
        // One component of 21 values on [0, 1]: behaviors 1 apart are 0.05 less similar.
        let space = crate::search::grid(&[21]);
        let (a, b) = (Behavior::new(&[0]), Behavior::new(&[1]));
        assert!((kernel(&space, &a, &a) - 1.0).abs() < 1e-12);
        assert!((kernel(&space, &a, &b) - (-1.0f64).exp()).abs() < 1e-12);
        // A profile that trusted `a` once and rejected nothing: P(reject a) = 1 / 3.
        let profile = Profile {
            trusted: a,
            episodes: 1.0,
            rejected: Vec::new(),
            commands: 8.0,
            completed: 6.0,
        };
        // Six of eight commands completed: (6 + 1) / (8 + 2).
        assert!((profile.reliability() - 0.7).abs() < 1e-12);
        assert!((profile.p_reject(&space, &a, 0.0) - 1.0 / 3.0).abs() < 1e-12);
        // Far away the prior's even odds come back.
        let far = Behavior::new(&[20]);
        assert!((profile.p_reject(&space, &far, 0.0) - 0.5).abs() < 1e-6);
        // The current episode rejected `b`: with it, (1 + 1/e) / (2 + 1/e + 1) at `a`.
        let e = (-1.0f64).exp();
        let near = near_rejections(&space, &a, &[pair(b)]);
        assert!((near - e).abs() < 1e-12);
        assert!((profile.p_reject(&space, &a, near) - (1.0 + e) / (3.0 + e)).abs() < 1e-12);
    }

    #[test]
    fn a_rejection_tells_the_operators_apart() {
        // Two kinds of operator on a 21-value line: "low" trusts 2 and rejects the high
        // end, "high" trusts 18 and rejects the low end, ten episodes each.
        let space = crate::search::grid(&[21]);
        let mut searcher = Conditioned::new();
        for _ in 0..10 {
            searcher.end_episode(&[pair(Behavior::new(&[17]))], Some(&Behavior::new(&[2])));
            searcher.end_episode(&[pair(Behavior::new(&[3]))], Some(&Behavior::new(&[18])));
        }
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        // This operator rejected a high behavior: it is a "low" one.
        searcher.begin_episode(&space, &Behavior::new(&[16]));
        let proposal = searcher.propose(&space, &[pair(Behavior::new(&[16]))], &mut rng);
        assert_eq!(proposal, Proposal::Next(Behavior::new(&[2])));
        // This one rejected a low behavior: a "high" one.
        let proposal = searcher.propose(&space, &[pair(Behavior::new(&[4]))], &mut rng);
        assert_eq!(proposal, Proposal::Next(Behavior::new(&[18])));
    }

    #[test]
    fn of_two_behaviors_the_same_operators_trusted_the_reliable_one_goes_first() {
        // Two profiles, alike but for how their trusted behaviors fared: 12 trusted after
        // 15 completions of 15 commands, 13 after 15 of 25.
        let space = crate::search::grid(&[21]);
        let mut searcher = Conditioned::new();
        let mut episode = |trusted: u16, completed: usize, failed: usize| {
            let b = Behavior::new(&[trusted]);
            searcher.begin_episode(&space, &b);
            for _ in 0..completed {
                searcher.observe(&b, &Outcome::completed(1.0 / 3.0, 1.0));
            }
            for _ in 0..failed {
                searcher.observe(&b, &Outcome::failed(1.0 / 3.0, 1.0));
            }
            searcher.end_episode(&[pair(Behavior::new(&[2]))], Some(&b));
        };
        episode(12, 15, 0);
        episode(13, 15, 10);
        let reliability: Vec<f64> = searcher.profiles.iter().map(Profile::reliability).collect();
        assert!((reliability[0] - 16.0 / 17.0).abs() < 1e-12);
        assert!((reliability[1] - 16.0 / 27.0).abs() < 1e-12);
        let evaluated = [pair(Behavior::new(&[3]))];
        let tried = crate::search::evaluated_set(&evaluated);
        searcher
            .likelihoods
            .cover(&space, &searcher.profiles, &evaluated);
        assert_eq!(
            searcher
                .best_remembered(
                    &space,
                    &evaluated,
                    &searcher.likelihoods.products,
                    &tried,
                    &mut ChaCha8Rng::seed_from_u64(1)
                )
                .map(|(_, b)| b),
            Some(Behavior::new(&[12]))
        );
    }

    #[test]
    fn likelihoods_kept_between_proposals_are_those_taken_afresh() {
        // Two profiles on a 21-value line; an episode rejects 5, 6, 7 one at a time.
        let space = crate::search::grid(&[21]);
        let mut searcher = Conditioned::new();
        searcher.end_episode(&[pair(Behavior::new(&[17]))], Some(&Behavior::new(&[2])));
        searcher.end_episode(&[pair(Behavior::new(&[3]))], Some(&Behavior::new(&[18])));
        let afresh = |evaluated: &[Evaluated]| -> Vec<f64> {
            let profiles = &searcher.profiles;
            profiles
                .iter()
                .map(|p| {
                    evaluated
                        .iter()
                        .map(|e| p.p_reject(&space, &e.behavior, 0.0))
                        .product()
                })
                .collect()
        };
        let evaluated = [5, 6, 7].map(|v| pair(Behavior::new(&[v])));
        let mut kept = Likelihoods::default();
        for n in 1..=evaluated.len() {
            kept.cover(&space, &searcher.profiles, &evaluated[..n]);
            assert_eq!(kept.products, afresh(&evaluated[..n]));
            assert_eq!(kept.covered.len(), n);
        }
        // Evidence that does not extend what is covered starts afresh.
        let other = [pair(Behavior::new(&[5])), pair(Behavior::new(&[9]))];
        kept.cover(&space, &searcher.profiles, &other);
        assert_eq!(kept.products, afresh(&other));
        // By hand, profile "trusted 2, rejected 17" at 5: kernel(5, 2) = e^-3 (the line's
        // similarity falls by 1/20 a step), kernel(5, 17) = e^-12.
        let (k2, k17) = ((-3.0f64).exp(), (-12.0f64).exp());
        let by_hand = (1.0 + k17) / (2.0 + k17 + k2);
        assert!((afresh(&evaluated[..1])[0] - by_hand).abs() < 1e-12);
    }

    proptest::proptest! {
        #[test]
        fn proposals_with_kept_likelihoods_are_those_taken_afresh_and_those_asked_to_vouch(
            earlier in proptest::collection::vec(
                (proptest::collection::vec((0u16..7, 0u16..7), 0..6), (0u16..7, 0u16..7)),
                0..8,
            ),
            current in proptest::collection::vec((0u16..7, 0u16..7), 1..10),
            seed in proptest::prelude::any::<u64>(),
        ) {
            // Earlier episodes (rejections, then a settled behavior) make the profiles;
            // then one episode's evidence grows a behavior at a time. One searcher keeps
            // its likelihoods between proposals, its twin forgets them before each: the
            // products are equal to the bit and so are the proposals. A third twin vouches
            // for case reuse and is asked, before each proposal, about every behavior an
            // earlier episode settled on: asking changes none of its proposals.
            let space = crate::search::grid(&[7, 7]);
            let pairs = |bs: &[(u16, u16)]| -> Vec<Evaluated> {
                bs.iter().map(|&(a, b)| pair(Behavior::new(&[a, b]))).collect()
            };
            let mut kept = Conditioned::new();
            for (rejected, (a, b)) in &earlier {
                kept.end_episode(&pairs(rejected), Some(&Behavior::new(&[*a, *b])));
            }
            let mut afresh = kept.clone();
            let mut asked = kept.clone().vouching();
            let start = Behavior::new(&[current[0].0, current[0].1]);
            for searcher in [&mut kept, &mut afresh, &mut asked] {
                searcher.begin_episode(&space, &start);
            }
            let evidence = pairs(&current);
            for n in 1..=evidence.len() {
                afresh.likelihoods.forget();
                for (_, (a, b)) in &earlier {
                    asked.doubts(&space, &evidence[..n], &Behavior::new(&[*a, *b]));
                }
                let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_add(n as u64));
                let (mut twin_rng, mut asked_rng) = (rng.clone(), rng.clone());
                let proposal = kept.propose(&space, &evidence[..n], &mut rng);
                let twin = afresh.propose(&space, &evidence[..n], &mut twin_rng);
                proptest::prop_assert_eq!(proposal, twin);
                proptest::prop_assert_eq!(&kept.likelihoods.products, &afresh.likelihoods.products);
                proptest::prop_assert_eq!(proposal, asked.propose(&space, &evidence[..n], &mut asked_rng));
            }
        }
    }

    #[test]
    fn a_vouching_searcher_doubts_what_its_posterior_does_not_rank_first() {
        // Operator A trusted 10 after rejecting 0; operator B trusted 20 at once. This one
        // rejected 0 too. By hand (the kernel e^-10 ten steps away, about 0): A's weight
        // P_A(reject 0) = 2/3, B's 1/2, the unknown operator's 1/2; then
        // P(accept 10) = (2/3 * 2/3 + 1/2 * 1/2 + 1/2 * 1/2) / (5/3) = 0.5667 and
        // P(accept 20) = (2/3 * 1/2 + 1/2 * 2/3 + 1/2 * 1/2) / (5/3) = 0.5500. Both beat
        // even odds and neither has a record (reliability 1/2 each), so 10 ranks first: a
        // case proposing 20 is doubted, one proposing 10 is not.
        let space = crate::search::grid(&[21]);
        let b = |v: u16| Behavior::new(&[v]);
        let mut plain = Conditioned::new();
        let evaluated = [pair(b(0))];
        assert!(
            !plain.clone().vouching().doubts(&space, &evaluated, &b(20)),
            "no profile yet"
        );
        plain.end_episode(&[pair(b(0))], Some(&b(10)));
        plain.end_episode(&[], Some(&b(20)));
        let mut vouching = plain.clone().vouching();
        vouching
            .likelihoods
            .cover(&space, &vouching.profiles, &evaluated);
        let weights = vouching.weights(&vouching.likelihoods.products);
        let accept = |v| vouching.acceptance(&space, &evaluated, &weights, &b(v));
        assert!((accept(10) - 0.5667).abs() < 1e-4, "{}", accept(10));
        assert!((accept(20) - 0.5500).abs() < 1e-4, "{}", accept(20));
        assert!(!vouching.doubts(&space, &evaluated, &b(10)));
        assert!(vouching.doubts(&space, &evaluated, &b(20)));
        // A behavior no remembered operator trusted is left to case reuse (a case another
        // robot of a fleet wrote).
        assert!(!vouching.doubts(&space, &evaluated, &b(3)));
        // Without vouching nothing is doubted: the paper's case reuse.
        assert!(!plain.doubts(&space, &evaluated, &b(20)));
    }

    #[test]
    fn without_evidence_for_acceptance_it_searches() {
        // The only remembered operator trusted 10; this one rejected 10's four nearest
        // neighbours, so 10 is not proposed: the fallback searches instead.
        let space = crate::search::grid(&[21]);
        let mut searcher = Conditioned::new();
        searcher.end_episode(&[pair(Behavior::new(&[0]))], Some(&Behavior::new(&[10])));
        let evaluated = [8, 9, 11, 12].map(|v| pair(Behavior::new(&[v])));
        searcher
            .likelihoods
            .cover(&space, &searcher.profiles, &evaluated);
        assert_eq!(
            searcher.best_remembered(
                &space,
                &evaluated,
                &searcher.likelihoods.products,
                &crate::search::evaluated_set(&evaluated),
                &mut ChaCha8Rng::seed_from_u64(1)
            ),
            None
        );
        // An exhausted episode's kept behavior is no profile.
        let mut forgetful = Conditioned::new();
        forgetful.end_episode(&[pair(Behavior::new(&[3]))], Some(&Behavior::new(&[3])));
        assert!(forgetful.profiles.is_empty());
    }
}
