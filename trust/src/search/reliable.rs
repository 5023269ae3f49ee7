//! Reliability learned across the population: how often operators like the ones served so
//! far let each behavior complete its commands, and a search that proposes, among what the
//! current operator is expected to accept, what the population finds reliable.
//!
//! The conditioned search ([`Conditioned`]) remembers which behavior each earlier operator
//! trusted and ranks them by the share of commands that behavior completed *for the
//! operators who trusted it*. An episode ends on the first behavior its operator trusts,
//! so what it remembers is what the search met first: a behavior one member trusted after
//! completing half its commands is proposed to the next member as readily as one that
//! every member lets complete. This searcher keeps, beside the profiles, every command of
//! every episode (trusted and rejected behaviors alike) in one model of the population:
//!
//! - **Pooled and shrunk.** A behavior `b`'s completion rate `theta_b` has the prior
//!   `Beta(s m_b, s (1 - m_b))`, `s =` [`BEHAVIOR_PRIOR`] commands, centred on a
//!   main-effects model over component values, `m_b = r + sum_k (r_k(b_k) - r)` (clamped
//!   to `[0.01, 0.99]`): `r` the population's completion rate (Laplace's rule), `r_k(v)`
//!   the rate of commands run with component `k` at `v`, shrunk towards `r` with
//!   [`VALUE_PRIOR`] commands' weight. Its posterior adds the commands `b` itself ran, for
//!   every operator: `Beta(s m_b + C_b, s (1 - m_b) + N_b - C_b)`. Behaviors never run
//!   borrow strength from every command run with their component values; their
//!   uncertainty is the prior's.
//! - **Conditioned on the operator** (`nested`'s searcher, [`ByOperator`]). The commands
//!   `C_b` and `N_b` are each earlier operator's weighed by how likely the current
//!   episode's rejections are under that operator's profile, over the likeliest: the
//!   commands of operators unlike this one fade from its reliability as they fade from its
//!   acceptance. `reliable` itself keeps the pooled record.
//! - **Where it looks.** Candidates are the trusted behaviors of the profiles most
//!   consistent with the episode so far (as the conditioned search), their untried
//!   neighbours (one component one step away: "among what a pleased member trusts"), and
//!   the behaviors the population ran with the highest posterior means ("what pleases more
//!   members").
//! - **How it chooses: Thompson sampling.** Each candidate's score is `P(accept) *
//!   theta~_b`, `P(accept)` the conditioned search's probability that the current operator
//!   accepts it (kept above even odds, as there) and `theta~_b` one draw from its posterior.
//!   The derivation (docs/search-strategies.md, "`reliable`") in short: the cost of trying
//!   a behavior until its operator trusts it, in untrustworthy commands per trusted
//!   behavior found, falls as its completion rate rises, so the behavior to try is the one
//!   most likely to have the highest rate; drawing from the posterior and taking the best
//!   draw proposes each candidate with exactly that probability (Thompson, 1933), so a
//!   proven behavior is kept while an untried one is unlikely to beat it, and an untried
//!   neighbour is tried in proportion to its chance of being better: the expected saving
//!   for later operators against the rejections now. Thompson sampling's expected regret
//!   on Bernoulli arms is logarithmic in the rounds (Agrawal and Goyal, *Analysis of
//!   Thompson Sampling for the Multi-armed Bandit Problem*, COLT 2012).
//!
//! When no candidate beats even odds, the search is `hedged`'s: the cause-aware and the
//! model-based searches in turn.

use super::registry::{Look, Marker, Strategy, WithCases};
use super::{Alternating, CauseAware, Conditioned, ModelBased};
use cbr_core::Behavior;
use rand::RngCore;
use rand_distr::{Beta, Distribution};
use std::collections::HashMap;

/// Weight of a behavior's prior (the component-value model) in its posterior, in commands.
/// Set a priori: two commands, so that a behavior's prior at even odds is Laplace's
/// `Beta(1, 1)`, and its own first commands outweigh what its component values suggest.
pub const BEHAVIOR_PRIOR: f64 = 2.0;

/// Weight of the population's rate in each component value's rate, in commands (as the
/// cause-aware and model-based searches' per-value means).
pub const VALUE_PRIOR: f64 = 20.0;

/// Behaviors with the highest posterior means among those the population ran that join
/// each proposal's candidates.
pub const RELIABLE_CANDIDATES: usize = 16;

/// Profiles (the most consistent with the episode) whose trusted behavior's untried
/// neighbours join each proposal's candidates.
pub const NEIGHBOURHOODS: usize = 4;

/// The reliable search as the tool offers it, alone and after case reuse.
pub const STRATEGY: Strategy = Strategy {
    name: "reliable",
    description: "the conditioned search choosing, among what the current operator is expected to accept, what the whole population lets complete (a pooled model of completion over behaviors and component values, Thompson sampling); the cause-aware and model-based searches in turn when nothing fits",
    look: Look {
        colour: [230, 159, 0],
        marker: Marker::Diamond,
    },
    with_cases: Some(WithCases {
        name: "case-based+reliable",
        description: "case reuse first, the reliable search when no case fits",
        look: Look {
            colour: [0, 0, 0],
            marker: Marker::Star,
        },
    }),
    build: || Box::new(reliable()),
};

/// The searcher of [`STRATEGY`]: a conditioned searcher with the population's reliability,
/// falling back to the cause-aware and the model-based searches in turn.
pub fn reliable() -> Conditioned<Alternating<CauseAware, ModelBased>> {
    Conditioned::with_population(
        STRATEGY.name,
        Alternating::new(CauseAware::new(), ModelBased::new()),
    )
}

/// One draw from `Beta(alpha, beta)` (its mean when the parameters admit no draw).
pub(super) fn draw_beta(alpha: f64, beta: f64, rng: &mut dyn RngCore) -> f64 {
    Beta::new(alpha, beta).map_or(alpha / (alpha + beta), |d| d.sample(rng))
}

/// Commands and completions.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Record {
    commands: f64,
    completed: f64,
}

impl Record {
    fn add(&mut self, commands: f64, completed: f64) {
        self.commands += commands;
        self.completed += completed;
    }

    /// The rate of these commands, shrunk towards `toward` with [`VALUE_PRIOR`] commands'
    /// weight.
    fn shrunk_to(self, toward: f64) -> f64 {
        (self.completed + VALUE_PRIOR * toward) / (self.commands + VALUE_PRIOR)
    }
}

/// How often the population let each behavior, and each component value, complete (see
/// the module documentation).
#[derive(Clone, Debug, Default)]
pub struct PopulationReliability {
    overall: Record,
    by_behavior: HashMap<Behavior, Record>,
    /// `by_value[k][v]`: commands run with component `k` at value `v`.
    by_value: Vec<Vec<Record>>,
}

impl PopulationReliability {
    /// Adds `commands` run on `behavior`, `completed` of them completed.
    pub fn add(&mut self, behavior: &Behavior, commands: f64, completed: f64) {
        self.overall.add(commands, completed);
        self.by_behavior
            .entry(*behavior)
            .or_default()
            .add(commands, completed);
        if self.by_value.len() < behavior.len() {
            self.by_value.resize(behavior.len(), Vec::new());
        }
        for (k, &v) in behavior.indices().iter().enumerate() {
            let values = &mut self.by_value[k];
            let v = usize::from(v);
            if values.len() <= v {
                values.resize(v + 1, Record::default());
            }
            values[v].add(commands, completed);
        }
    }

    /// The prior mean completion rate at `behavior`: the main-effects model over its
    /// component values, clamped to `[0.01, 0.99]`.
    pub fn prior_mean(&self, behavior: &Behavior) -> f64 {
        let overall = self.overall_rate();
        let effects: f64 = behavior
            .indices()
            .iter()
            .enumerate()
            .map(|(k, &v)| self.value_rate(k, v, overall) - overall)
            .sum();
        (overall + effects).clamp(0.01, 0.99)
    }

    /// The main-effects mean completion rate at `behavior` for the operator whose own
    /// commands are `own` (one episode's): the overall rate and each component value's
    /// rate are `own`'s, shrunk towards this population's with [`VALUE_PRIOR`] commands'
    /// weight, clamped to `[0.01, 0.99]`. For an operator with no commands yet it is
    /// [`Self::prior_mean`].
    pub fn mean_for(&self, own: &PopulationReliability, behavior: &Behavior) -> f64 {
        let population = self.overall_rate();
        let overall = own.overall.shrunk_to(population);
        let effects: f64 = behavior
            .indices()
            .iter()
            .enumerate()
            .map(|(k, &v)| own.value_rate(k, v, self.value_rate(k, v, population)) - overall)
            .sum();
        (overall + effects).clamp(0.01, 0.99)
    }

    /// The population's completion rate (Laplace's rule).
    fn overall_rate(&self) -> f64 {
        (self.overall.completed + 1.0) / (self.overall.commands + 2.0)
    }

    /// The rate of the commands run with component `k` at value `v`, shrunk towards
    /// `toward` with [`VALUE_PRIOR`] commands' weight.
    fn value_rate(&self, k: usize, v: u16, toward: f64) -> f64 {
        self.by_value
            .get(k)
            .and_then(|values| values.get(usize::from(v)))
            .copied()
            .unwrap_or_default()
            .shrunk_to(toward)
    }

    /// The posterior `Beta(alpha, beta)` of `behavior`'s completion rate.
    pub fn posterior(&self, behavior: &Behavior) -> (f64, f64) {
        let own = self.by_behavior.get(behavior).copied().unwrap_or_default();
        self.posterior_with(behavior, own)
    }

    /// The posterior `Beta(alpha, beta)` of `behavior`'s completion rate after the commands
    /// of `ran`: the prior at it ([`Self::prior_mean`], [`BEHAVIOR_PRIOR`] commands'
    /// weight), updated with them.
    fn posterior_with(&self, behavior: &Behavior, ran: Record) -> (f64, f64) {
        let m = self.prior_mean(behavior);
        (
            BEHAVIOR_PRIOR * m + ran.completed,
            BEHAVIOR_PRIOR * (1.0 - m) + ran.commands - ran.completed,
        )
    }

    /// One draw of `behavior`'s completion rate from its posterior.
    pub fn draw(&self, behavior: &Behavior, rng: &mut dyn RngCore) -> f64 {
        let (alpha, beta) = self.posterior(behavior);
        draw_beta(alpha, beta, rng)
    }

    /// Up to `count` behaviors the population ran, not in `excluded`, with the highest
    /// posterior means (ties by behavior, so the order never depends on hashing).
    pub fn most_reliable(
        &self,
        count: usize,
        excluded: impl Fn(&Behavior) -> bool,
    ) -> Vec<Behavior> {
        let mut ran: Vec<(f64, Behavior)> = self
            .by_behavior
            .keys()
            .filter(|b| !excluded(b))
            .map(|b| {
                let (alpha, beta) = self.posterior(b);
                (alpha / (alpha + beta), *b)
            })
            .collect();
        ran.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        ran.into_iter().take(count).map(|(_, b)| b).collect()
    }
}

/// What each remembered operator's episodes ran, for a reliability conditioned on the
/// operator instead of pooled over the population ([`ByOperator::posterior`], `nested`).
///
/// The population's posterior counts every command alike. On a population whose members'
/// trustworthy regions are disjoint, a behavior one member trusts but often fails is
/// completed by another member who passes through it, and the pooled record ranks it above
/// what the first member completes; the conditioned record weighs each command by how
/// likely its operator is to be of the current operator's kind.
#[derive(Clone, Debug, Default)]
pub struct ByOperator {
    /// Per profile of the conditioned searcher, in its order: commands per behavior.
    profiles: Vec<HashMap<Behavior, Record>>,
    /// Commands of the episodes that trusted nothing (operators no profile stands for).
    unserved: HashMap<Behavior, Record>,
}

impl ByOperator {
    /// Adds an episode's commands, `(behavior, commands, completed)`, to the record of
    /// profile `profile` (the conditioned searcher's index; one past the last adds a
    /// profile), or to the unserved operators' record.
    pub fn add(&mut self, profile: Option<usize>, episode: &[(Behavior, f64, f64)]) {
        let record = match profile {
            Some(index) => {
                if self.profiles.len() <= index {
                    self.profiles.resize_with(index + 1, HashMap::new);
                }
                &mut self.profiles[index]
            }
            None => &mut self.unserved,
        };
        for (b, commands, completed) in episode {
            record.entry(*b).or_default().add(*commands, *completed);
        }
    }

    /// The posterior `Beta(alpha, beta)` of `behavior`'s completion rate for the current
    /// operator: the population's prior at it ([`PopulationReliability::prior_mean`],
    /// [`BEHAVIOR_PRIOR`] commands), updated with each profile's commands on it weighed by
    /// `weights[p]` (the likelihood of the current episode's evidence under the profile's
    /// operator, over the largest likelihood, so in `[0, 1]`: commands of the operators the
    /// evidence favours most count in full, those of unlikely ones fade), and the unserved
    /// operators' commands weighed by `unserved` likewise. With every weight 1 it is the
    /// population's posterior ([`PopulationReliability::posterior`]).
    pub fn posterior(
        &self,
        population: &PopulationReliability,
        behavior: &Behavior,
        weights: &[f64],
        unserved: f64,
    ) -> (f64, f64) {
        let mut weighed = Record::default();
        let records = self
            .profiles
            .iter()
            .zip(weights)
            .chain(std::iter::once((&self.unserved, &unserved)));
        for (record, &weight) in records {
            if let Some(ran) = record.get(behavior) {
                weighed.add(weight * ran.commands, weight * ran.completed);
            }
        }
        population.posterior_with(behavior, weighed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cbr_core::Searcher;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn the_pooled_model_by_hand() {
        // Two components of three values. Behavior (0, 0) ran 10 commands, 9 completed;
        // (2, 1) ran 10, 1 completed.
        let mut model = PopulationReliability::default();
        let (good, bad) = (Behavior::new(&[0, 0]), Behavior::new(&[2, 1]));
        model.add(&good, 10.0, 9.0);
        model.add(&bad, 10.0, 1.0);
        // Overall: (10 + 1) / (20 + 2) = 1/2.
        // Component 0 at 0: (9 + 20 * 0.5) / (10 + 20) = 19/30; component 1 at 0 likewise.
        // Prior mean at (0, 0): 1/2 + 2 * (19/30 - 1/2) = 23/30.
        assert!((model.prior_mean(&good) - 23.0 / 30.0).abs() < 1e-12);
        // Its posterior: Beta(2 * 23/30 + 9, 2 * 7/30 + 1).
        let (alpha, beta) = model.posterior(&good);
        assert!((alpha - (46.0 / 30.0 + 9.0)).abs() < 1e-12);
        assert!((beta - (14.0 / 30.0 + 1.0)).abs() < 1e-12);
        // A behavior never run borrows its values' rates: (0, 1) has component 0 at 0
        // (19/30) and component 1 at 1 ((1 + 10) / 30 = 11/30): 1/2 + 4/30 - 4/30 = 1/2.
        let unseen = Behavior::new(&[0, 1]);
        assert!((model.prior_mean(&unseen) - 0.5).abs() < 1e-12);
        let (alpha, beta) = model.posterior(&unseen);
        assert!((alpha - 1.0).abs() < 1e-12 && (beta - 1.0).abs() < 1e-12);
        // A value nobody ran keeps the population's rate.
        assert!((model.prior_mean(&Behavior::new(&[1, 2])) - 0.5).abs() < 1e-12);
        // For an operator whose one command so far, on (2, 1), failed: overall
        // (0 + 20 * 1/2) / 21 = 10/21; component 0 at 0 keeps the population's 19/30 and
        // component 1 at 0 likewise (it ran neither): 10/21 + 2 * (19/30 - 10/21).
        let mut own = PopulationReliability::default();
        own.add(&bad, 1.0, 0.0);
        let expected = 10.0 / 21.0 + 2.0 * (19.0 / 30.0 - 10.0 / 21.0);
        assert!((model.mean_for(&own, &good) - expected).abs() < 1e-12);
        // At (2, 1) its own failure counts: each value (0 + 20 * r) / 21, r the
        // population's rate for it ((1 + 10) / 30 = 11/30 for both).
        let at_bad = 10.0 / 21.0 + 2.0 * (20.0 * 11.0 / 30.0 / 21.0 - 10.0 / 21.0);
        assert!((model.mean_for(&own, &bad) - at_bad).abs() < 1e-12);
        // With no commands of its own, the operator is the population.
        let nobody = PopulationReliability::default();
        assert!((model.mean_for(&nobody, &good) - model.prior_mean(&good)).abs() < 1e-12);
        // The most reliable first, the excluded left out.
        assert_eq!(model.most_reliable(5, |_| false), vec![good, bad]);
        assert_eq!(model.most_reliable(5, |b| *b == good), vec![bad]);
    }

    /// Runs one finished episode on `searcher`: `rejected` first, then `trusted` for
    /// `commands` commands of which `completed` completed.
    fn episode<S: Searcher<Evidence = crate::Evaluated, Feedback = crate::Outcome>>(
        searcher: &mut S,
        space: &cbr_core::BehaviorSpace,
        rejected: Behavior,
        trusted: Behavior,
        (commands, completed): (usize, usize),
    ) {
        run(
            searcher,
            space,
            &[(rejected, 1, 0), (trusted, commands, completed)],
        );
    }

    /// Runs one finished episode on `searcher` that ran each `(behavior, commands,
    /// completed)` in turn and settled on the last, every one before it rejected.
    fn run<S: Searcher<Evidence = crate::Evaluated, Feedback = crate::Outcome>>(
        searcher: &mut S,
        space: &cbr_core::BehaviorSpace,
        ran: &[(Behavior, usize, usize)],
    ) {
        searcher.begin_episode(space, &ran[0].0);
        for &(behavior, commands, completed) in ran {
            for k in 0..commands {
                let outcome = if k < completed {
                    crate::Outcome::completed(1.0, 1.0)
                } else {
                    crate::Outcome::failed(1.0, 1.0)
                };
                searcher.observe(&behavior, &outcome);
            }
        }
        let (settled, rejected) = ran.split_last().expect("an episode runs a behavior");
        let evaluated: Vec<crate::Evaluated> = rejected
            .iter()
            .map(|&(behavior, _, _)| crate::Evaluated {
                behavior,
                time: 1.0,
            })
            .collect();
        searcher.end_episode(&evaluated, Some(&settled.0));
    }

    #[test]
    fn the_record_conditioned_on_the_operator_by_hand() {
        // The population of `the_pooled_model_by_hand`: (0, 0) ran 10 commands, 9
        // completed, (2, 1) ran 10, 1 completed; its prior mean at (0, 0) is 23/30 and at
        // (2, 1) 1/2 - 2 * (1/2 - 11/30) = 7/30. The commands on (0, 0) were one
        // profile's 4 (3 completed) and another's 6 (all completed); those on (2, 1) an
        // episode's that trusted nothing.
        let mut population = PopulationReliability::default();
        let (good, bad) = (Behavior::new(&[0, 0]), Behavior::new(&[2, 1]));
        let mut by_operator = ByOperator::default();
        for (profile, behavior, commands, completed) in [
            (Some(0), good, 4.0, 3.0),
            (Some(1), good, 6.0, 6.0),
            (None, bad, 10.0, 1.0),
        ] {
            population.add(&behavior, commands, completed);
            by_operator.add(profile, &[(behavior, commands, completed)]);
        }
        // With every operator as likely, the record is the population's.
        for b in [good, bad] {
            let (alpha, beta) = by_operator.posterior(&population, &b, &[1.0, 1.0], 1.0);
            let (pooled_alpha, pooled_beta) = population.posterior(&b);
            assert!((alpha - pooled_alpha).abs() < 1e-12 && (beta - pooled_beta).abs() < 1e-12);
        }
        // The second profile half as likely as the first: Beta(2 * 23/30 + 3 + 6/2,
        // 2 * 7/30 + 1 + 0).
        let (alpha, beta) = by_operator.posterior(&population, &good, &[1.0, 0.5], 1.0);
        assert!((alpha - (46.0 / 30.0 + 6.0)).abs() < 1e-12);
        assert!((beta - (14.0 / 30.0 + 1.0)).abs() < 1e-12);
        // The unserved operators unlikely: (2, 1) keeps its prior, Beta(2 * 7/30, 2 * 23/30).
        let (alpha, beta) = by_operator.posterior(&population, &bad, &[1.0, 1.0], 0.0);
        assert!((alpha - 14.0 / 30.0).abs() < 1e-12 && (beta - 46.0 / 30.0).abs() < 1e-12);
    }

    proptest::proptest! {
        /// Weighing commands can only take evidence away: the conditioned posterior's
        /// commands lie between the prior's alone and the population's, equal to the
        /// population's with every weight 1, and its mean stays a rate.
        #[test]
        fn the_conditioned_record_lies_between_the_prior_and_the_population(
            episodes in proptest::collection::vec(
                (proptest::option::of(0usize..4), 0u16..5, 0u8..12, 0u8..12),
                1..20,
            ),
            weights in proptest::collection::vec(0.0f64..=1.0, 4),
            unserved in 0.0f64..=1.0,
            at in 0u16..5,
        ) {
            let mut population = PopulationReliability::default();
            let mut by_operator = ByOperator::default();
            for (profile, v, commands, completed) in episodes {
                let b = Behavior::new(&[v, 0]);
                let (n, c) = (f64::from(commands), f64::from(completed.min(commands)));
                population.add(&b, n, c);
                by_operator.add(profile, &[(b, n, c)]);
            }
            let b = Behavior::new(&[at, 0]);
            let (alpha, beta) = by_operator.posterior(&population, &b, &weights, unserved);
            let (pooled_alpha, pooled_beta) = population.posterior(&b);
            proptest::prop_assert!(alpha + beta >= BEHAVIOR_PRIOR - 1e-9);
            proptest::prop_assert!(alpha + beta <= pooled_alpha + pooled_beta + 1e-9);
            proptest::prop_assert!(alpha > 0.0 && beta > 0.0);
            let (alpha, beta) = by_operator.posterior(&population, &b, &[1.0; 4], 1.0);
            proptest::prop_assert!((alpha - pooled_alpha).abs() < 1e-9);
            proptest::prop_assert!((beta - pooled_beta).abs() < 1e-9);
        }
    }

    #[test]
    fn what_operators_of_another_kind_failed_does_not_count_against_this_kind() {
        // A line of 21 behaviors. Strict operators trusted 4 (7 of 10 commands completed)
        // once and 8 (all 10) three times, each after rejecting 18; lenient ones trusted
        // 18 four times, three of them after 8 failed 9 of 10 commands. Over the
        // population 8 completed 33 of 60 commands and 4 7 of 10, so the pooled record
        // ranks 8 below 4 (and below 8's untried neighbours, whose prior is the
        // population's rate: a search that has never run them). The current operator rejected 18, as strict operators do: the
        // likelihood of that is 1/6 under the lenient profile (the kernel more than five
        // steps away, about 0: 1 / (2 + 4)), 2/3 and 4/5 under the strict ones, so the
        // lenient operators' commands on 8 count (1/6) / (4/5) = 0.21 each, and 8,
        // completed by every operator of the current one's kind, ranks first.
        let space = crate::search::grid(&[21]);
        let b = |v: u16| Behavior::new(&[v]);
        let mut pooled = reliable().vouching();
        let mut conditioned = Conditioned::with_population(
            "conditioned on the operator",
            Alternating::new(CauseAware::new(), ModelBased::new()),
        )
        .conditioned_on_operator()
        .vouching();
        let mut episodes = vec![[(b(18), 1, 0), (b(4), 10, 7)]];
        episodes.extend([[(b(18), 1, 0), (b(8), 10, 10)]; 3]);
        episodes.extend([[(b(8), 10, 1), (b(18), 10, 10)]; 3]);
        episodes.push([(b(12), 1, 0), (b(18), 10, 10)]);
        for ran in &episodes {
            run(&mut pooled, &space, ran);
            run(&mut conditioned, &space, ran);
        }
        let current = [crate::Evaluated {
            behavior: b(18),
            time: 1.0,
        }];
        assert!(pooled.doubts(&space, &current, &b(8)));
        assert!(!conditioned.doubts(&space, &current, &b(8)));
        assert!(conditioned.doubts(&space, &current, &b(4)));
    }

    #[test]
    fn among_what_a_pleased_member_trusts_it_looks_for_what_pleases_more() {
        // A 21 x 21 grid. One operator trusted (5, 0) after completing half of 30
        // commands; another, far away, trusted (15, 1) completing all 30. The current
        // operator rejected (16, 1), next to the second one's: it is expected to accept
        // what the first trusted and, a little less surely, its neighbours. The
        // conditioned search proposes (5, 0), the coin toss; the reliable one mostly
        // proposes (5, 1), one change away, whose component value `1` the population
        // lets complete.
        let space = crate::search::grid(&[21, 21]);
        let mut conditioned = Conditioned::new();
        let mut pooled = reliable();
        let first = (Behavior::new(&[0, 20]), Behavior::new(&[5, 0]), (30, 15));
        let second = (Behavior::new(&[20, 20]), Behavior::new(&[15, 1]), (30, 30));
        for (rejected, trusted, record) in [first, second] {
            episode(&mut conditioned, &space, rejected, trusted, record);
            episode(&mut pooled, &space, rejected, trusted, record);
        }
        let current = [crate::Evaluated {
            behavior: Behavior::new(&[16, 1]),
            time: 1.0,
        }];
        let (coin_toss, neighbour) = (Behavior::new(&[5, 0]), Behavior::new(&[5, 1]));
        let mut chosen = HashMap::new();
        for seed in 0..200 {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            assert_eq!(
                conditioned.propose(&space, &current, &mut rng),
                cbr_core::Proposal::Next(coin_toss)
            );
            if let cbr_core::Proposal::Next(b) = pooled.propose(&space, &current, &mut rng) {
                *chosen.entry(b).or_insert(0) += 1;
            }
        }
        let count = |b: &Behavior| chosen.get(b).copied().unwrap_or(0);
        assert!(
            count(&neighbour) > 100 && count(&neighbour) > 2 * count(&coin_toss),
            "{chosen:?}"
        );
        // What is proposed is never the far operator's behavior, which this one is not.
        assert_eq!(count(&Behavior::new(&[15, 1])), 0, "{chosen:?}");
    }

    #[test]
    fn draws_follow_the_posterior() {
        let mut model = PopulationReliability::default();
        let b = Behavior::new(&[0]);
        model.add(&b, 40.0, 30.0);
        let (alpha, beta) = model.posterior(&b);
        let mean = alpha / (alpha + beta);
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let n = 20_000;
        let draws: Vec<f64> = (0..n).map(|_| model.draw(&b, &mut rng)).collect();
        let sample_mean = draws.iter().sum::<f64>() / f64::from(n);
        // The Beta's variance is mean (1 - mean) / (alpha + beta + 1); the sample mean's
        // standard error is its root over n: four of them bound the difference.
        let se = (mean * (1.0 - mean) / (alpha + beta + 1.0) / f64::from(n)).sqrt();
        assert!(
            (sample_mean - mean).abs() < 4.0 * se,
            "{sample_mean} vs {mean}"
        );
        assert!(draws.iter().all(|d| (0.0..=1.0).contains(d)));
    }
}
