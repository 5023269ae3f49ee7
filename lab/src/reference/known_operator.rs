//! The known-operator limit of an experiment: how few behaviors, commands and
//! untrustworthy commands an agent needs that knows each behavior's outcome distribution
//! for the operator at hand ([`crate::reference::limit`] has the maths), estimated from the
//! operator's landscape over every behavior.
//!
//! **Estimation.** Every behavior is run [`LimitSettings::runs`] times under the operator
//! (more in a small space: [`LimitSettings::budget`] runs spread over it)
//! (a landscape with every component fixed, [`landscape::estimate`]), which gives each
//! behavior's step law (its outcomes' contributions to the estimate and their shares).
//! The limit is decided by the few behaviors an optimal agent tries first, and those are
//! the ones a short estimate flatters most (the best of thousands of noisy shares is
//! biased upwards). So the [`LimitSettings::candidates`] behaviors that lead each metric's
//! optimal order are run again, [`LimitSettings::candidate_runs`] times on streams of their
//! own, and their fresh estimates replace the first ones. Each behavior's walk is then
//! solved exactly ([`limit::solve_walk`]; behaviors with identical counts share one
//! solve) and the limit follows ([`Limit::from_outcomes`]), with the law of its agent's
//! untrustworthy commands under the paper's protocol ([`crate::reference::limit_law`]; behaviors with
//! identical counts share one walk's law too).
//!
//! **Populations.** An experiment whose operator is drawn per trial gets the mean of its
//! operators' limits ([`Limit::mean_of`]): a lower bound for an agent that is not told
//! which operator it faces. How much its operators disagree ([`Conflict`]) is measured on
//! the same landscapes: the share of behaviors every operator trusts, the pairwise Jaccard
//! index of their trustworthy regions, the pairwise share of behaviors whose completion
//! rates lie more than [`RATE_GAP`] apart, and whether any single behavior pleases
//! everyone.

use crate::Domain;
use crate::reference::landscape::{self, LandscapeError, Tally};
use crate::reference::limit::{self, DEFAULT_MAX_STATES, Limit, LimitError, Step, WalkOutcome};
use crate::reference::limit_law::{self, UntrustworthyLaw, WalkLaw};
use crate::reference::population_reference::{
    Member, PopulationReference, ReferenceError, ReferencePlan, population_reference,
};
use crate::seeds::{Purpose, stream_seed};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::collections::hash_map::Entry;
use trust::Thresholds;

/// How the limit is estimated. The defaults keep the paper's seven experiments within
/// their time budget (see `docs/search-strategies.md`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LimitSettings {
    /// Runs per behavior of the first estimate, at least (0: no limit is computed).
    pub runs: u32,
    /// Runs of the first estimate in all, spread over the space when that gives a behavior
    /// more than `runs` (a small space is estimated closely for the same cost).
    pub budget: u64,
    /// Behaviors at the head of each metric's optimal order that are estimated again.
    pub candidates: usize,
    /// Runs per candidate of the second estimate.
    pub candidate_runs: u32,
    /// Episodes per member the population reference of a population of several operators
    /// is simulated over ([`crate::reference::population_reference`]; 0: none is).
    pub reference_episodes: usize,
}

impl Default for LimitSettings {
    fn default() -> Self {
        Self {
            runs: 20,
            budget: 160_000,
            candidates: 32,
            candidate_runs: 400,
            reference_episodes: 1000,
        }
    }
}

/// Why the limit could not be estimated.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum KnownLimitError {
    /// The landscape could not be estimated.
    #[error(transparent)]
    Landscape(#[from] LandscapeError),
    /// A walk or the limit could not be solved.
    #[error("the known-operator limit: {0}")]
    Limit(#[from] LimitError),
    /// The population reference could not be simulated.
    #[error("the population reference: {0}")]
    Reference(#[from] ReferenceError),
}

/// What the estimate tells of one operator: its limit and its trustworthy region.
#[derive(Clone, Debug, PartialEq)]
pub struct KnownOperator {
    /// The operator's limit under both protocols.
    pub limit: Limit,
    /// The law of the untrustworthy commands of the limit's agent under the paper's
    /// protocol ([`limit_law::paper_protocol_law`]): its mean is `limit.paper.untrustworthy`.
    pub law: UntrustworthyLaw,
    /// Per behavior (in rank order), whether it is in the operator's trustworthy region:
    /// its estimated mean contribution per command is positive, so the expected estimate
    /// climbs ([`Tally::trusted_on_average`]).
    pub trusted: Vec<bool>,
    /// Per behavior (in rank order), its walk solved from the estimate: the acceptance
    /// probability and expected costs the limit's optimal orders are made of.
    pub walks: Vec<WalkOutcome>,
    /// Per behavior (in rank order), the estimated probability that a command is
    /// untrustworthy (anything but a completion).
    pub untrustworthy_rate: Vec<f64>,
    /// The distinct step laws of the estimate (behaviors whose runs were counted alike
    /// share one): what the population reference simulates and weighs evidence with
    /// ([`crate::reference::population_reference`]).
    pub laws: Vec<Vec<Step>>,
    /// Per behavior (in rank order), which of [`KnownOperator::laws`] is its step law.
    pub law_of: Vec<usize>,
}

impl KnownOperator {
    /// The operator as a member of a population met `weight` times as often as a member
    /// of weight 1: what the population reference knows of it.
    pub fn as_member(&self, weight: f64) -> Member<'_> {
        Member {
            weight,
            walks: &self.walks,
            laws: &self.laws,
            law_of: &self.law_of,
        }
    }

    /// Per behavior (in rank order), the estimated probability that a command completes:
    /// one minus [`KnownOperator::untrustworthy_rate`].
    pub fn completion_rate(&self) -> Vec<f64> {
        self.untrustworthy_rate.iter().map(|u| 1.0 - u).collect()
    }
}

/// How far apart two operators' completion rates on a behavior must be for
/// [`Conflict::rate_gap_share`] to count it. One half, because rates (in [0, 1]) more than
/// one half apart put the behavior on opposite sides of one half: one operator mostly lets
/// it complete and the other mostly stops it, whatever the rates. A behavior counts as
/// trusted even at 60% completion, so the trustworthy regions alone do not tell how far
/// apart two operators are: both may trust a behavior at rates 0.6 and 1.0, and one may
/// trust it at 0.6 while the other, at 0.55, does not.
pub const RATE_GAP: f64 = 0.5;

/// How much two completion rates may differ beyond [`RATE_GAP`] and still count as exactly
/// `RATE_GAP` apart: rates are shares of runs, and the gap between two of them that is
/// exactly one half (0.7 and 0.2) may come out of floating point a rounding error off.
const RATE_GAP_ROUNDING: f64 = 1e-9;

/// Whether completion rates `a` and `b` lie more than [`RATE_GAP`] apart.
fn rates_apart(a: f64, b: f64) -> bool {
    (a - b).abs() > RATE_GAP + RATE_GAP_ROUNDING
}

/// How much a population's operators disagree, measured on their trustworthy regions and
/// completion rates.
#[derive(Clone, Debug, PartialEq)]
pub struct Conflict {
    /// Behaviors in the space.
    pub behaviors: usize,
    /// Behaviors in each operator's trustworthy region.
    pub trusted_by_each: Vec<usize>,
    /// Behaviors in every operator's region (0: no single behavior pleases everyone).
    pub trusted_by_all: usize,
    /// The Jaccard index (shared / either) of every pair of operators' regions, pairs
    /// `(0, 1), (0, 2), ..., (1, 2), ...`.
    pub jaccard: Vec<f64>,
    /// For every pair of operators (in the order of [`Conflict::jaccard`]), the share of
    /// the space's behaviors whose completion rates for the two lie more than
    /// [`RATE_GAP`] apart: behaviors one operator mostly lets complete and the other
    /// mostly stops. Unlike the Jaccard index it tells how far apart the rates are, not
    /// only on which side of the trust threshold each falls.
    pub rate_gap_share: Vec<f64>,
}

impl Conflict {
    /// The conflict of operators, each given by its trustworthy region and its completion
    /// rate per behavior (both in rank order, all over one space).
    pub fn of(operators: &[(&[bool], &[f64])]) -> Self {
        let behaviors = operators.first().map_or(0, |(r, _)| r.len());
        let count = |f: &dyn Fn(usize) -> bool| (0..behaviors).filter(|&b| f(b)).count();
        let mut jaccard = Vec::new();
        let mut rate_gap_share = Vec::new();
        for (i, (a, a_rates)) in operators.iter().enumerate() {
            for (b, b_rates) in &operators[i + 1..] {
                let both = count(&|k| a[k] && b[k]);
                let either = count(&|k| a[k] || b[k]);
                jaccard.push(if either == 0 {
                    1.0
                } else {
                    both as f64 / either as f64
                });
                let apart = count(&|k| rates_apart(a_rates[k], b_rates[k]));
                rate_gap_share.push(apart as f64 / behaviors.max(1) as f64);
            }
        }
        Self {
            behaviors,
            trusted_by_each: operators.iter().map(|(r, _)| count(&|k| r[k])).collect(),
            trusted_by_all: count(&|k| operators.iter().all(|(r, _)| r[k])),
            jaccard,
            rate_gap_share,
        }
    }

    /// The share of the space every operator trusts.
    pub fn shared_share(&self) -> f64 {
        self.trusted_by_all as f64 / self.behaviors.max(1) as f64
    }
}

/// An experiment's limit: the mean over its operators (one: exact up to landscape noise;
/// several: a lower bound), and how much its operators disagree.
#[derive(Clone, Debug, PartialEq)]
pub struct ExperimentLimit {
    /// The limit under both protocols.
    pub limit: Limit,
    /// The law of the untrustworthy commands of the limit's agent under the paper's
    /// protocol: the mixture of its operators' laws, each weighing as much (as each
    /// operator's limit does in the mean).
    pub law: UntrustworthyLaw,
    /// How many operators it is the mean of.
    pub operators: usize,
    /// How much the operators disagree (for one operator: its region alone).
    pub conflict: Conflict,
    /// Each operator's name and trustworthy region ([`KnownOperator::trusted`]), in the
    /// order given: what a report judges a given-up behavior against.
    pub regions: Vec<(String, Vec<bool>)>,
    /// The population reference: the agent that knows every operator but not which it
    /// faces ([`crate::reference::population_reference`]); `None` for one operator (it is
    /// the limit's agent then) or when none was asked for.
    pub population_reference: Option<PopulationReference>,
}

impl ExperimentLimit {
    /// The limit of an experiment whose trials draw from these operators (equally often),
    /// each with its name; with several, and a `reference` plan of some episodes, its
    /// population reference too.
    pub fn of(
        operators: &[(&str, &KnownOperator)],
        reference: Option<ReferencePlan>,
    ) -> Result<Self, KnownLimitError> {
        let limits: Vec<Limit> = operators.iter().map(|(_, o)| o.limit).collect();
        let rates: Vec<Vec<f64>> = operators.iter().map(|(_, o)| o.completion_rate()).collect();
        let members: Vec<(&[bool], &[f64])> = operators
            .iter()
            .zip(&rates)
            .map(|((_, o), rates)| (o.trusted.as_slice(), rates.as_slice()))
            .collect();
        let population_reference = match reference {
            Some(plan) if operators.len() > 1 && plan.episodes > 0 => {
                let members: Vec<Member<'_>> =
                    operators.iter().map(|(_, o)| o.as_member(1.0)).collect();
                Some(population_reference(&members, plan)?)
            }
            _ => None,
        };
        Ok(Self {
            population_reference,
            limit: Limit::mean_of(&limits)?,
            law: UntrustworthyLaw::mixture(operators.iter().map(|(_, o)| (1.0, &o.law))),
            operators: operators.len(),
            conflict: Conflict::of(&members),
            regions: operators
                .iter()
                .map(|(name, o)| ((*name).to_owned(), o.trusted.clone()))
                .collect(),
        })
    }

    /// Whether operator `operator` trusts the behavior of rank `rank` (`None`: an
    /// operator or rank the limit does not know).
    pub fn trusts(&self, operator: &str, rank: u64) -> Option<bool> {
        let (_, region) = self.regions.iter().find(|(name, _)| name == operator)?;
        region.get(usize::try_from(rank).ok()?).copied()
    }

    /// Whether it is a lower bound only (the mean over a population's operators).
    pub fn is_lower_bound(&self) -> bool {
        self.operators > 1
    }
}

/// The step law of a tally.
fn steps(tally: &Tally) -> Vec<Step> {
    let runs = f64::from(tally.runs.max(1));
    tally
        .steps
        .iter()
        .map(|s| Step {
            prob: f64::from(s.runs) / runs,
            delta: s.contribution,
            untrustworthy: s.untrustworthy,
        })
        .collect()
}

/// The distinct step laws of `tallies` (tallies with the same step counts have one), and
/// which of them each tally has.
fn distinct_steps(tallies: &[Tally]) -> (Vec<Vec<Step>>, Vec<usize>) {
    let key = |t: &Tally| -> Vec<(u64, bool, u32, u32)> {
        t.steps
            .iter()
            .map(|s| (s.contribution.to_bits(), s.untrustworthy, s.runs, t.runs))
            .collect()
    };
    let mut known: HashMap<Vec<(u64, bool, u32, u32)>, usize> = HashMap::new();
    let mut distinct = Vec::new();
    let which = tallies
        .iter()
        .map(|t| match known.entry(key(t)) {
            Entry::Occupied(seen) => *seen.get(),
            Entry::Vacant(new) => {
                distinct.push(steps(t));
                *new.insert(distinct.len() - 1)
            }
        })
        .collect();
    (distinct, which)
}

/// Solves the walk of every tally; tallies with the same step counts share one solve.
fn solve_all(
    tallies: &[Tally],
    thresholds: Thresholds,
) -> Result<Vec<WalkOutcome>, KnownLimitError> {
    let (distinct, which) = distinct_steps(tallies);
    let solved = distinct
        .iter()
        .map(|steps| limit::solve_walk(steps, thresholds, DEFAULT_MAX_STATES))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(which.iter().map(|&i| solved[i]).collect())
}

/// The law of the paper-protocol agent's untrustworthy commands over behaviors with these
/// walks, whose step laws are `distinct[which[rank]]`: behaviors that share a step law
/// share one walk's law.
fn paper_law(
    distinct: &[Vec<Step>],
    which: &[usize],
    walks: &[WalkOutcome],
    thresholds: Thresholds,
) -> Result<UntrustworthyLaw, KnownLimitError> {
    let laws = distinct
        .par_iter()
        .map(|steps| limit_law::walk_law(steps, thresholds, DEFAULT_MAX_STATES))
        .collect::<Result<Vec<WalkLaw>, _>>()?;
    let walks: Vec<(WalkOutcome, &WalkLaw)> = walks
        .iter()
        .zip(which)
        .map(|(&walk, &i)| (walk, &laws[i]))
        .collect();
    Ok(limit_law::paper_protocol_law(&walks)?)
}

/// The behaviors (ranks) that lead the optimal order of any metric, `count` per metric.
fn candidates(walks: &[WalkOutcome], count: usize) -> Vec<usize> {
    let accept: Vec<f64> = walks.iter().map(|w| w.accept).collect();
    let metrics: [Vec<f64>; 3] = [
        vec![1.0; walks.len()],
        walks.iter().map(|w| w.commands).collect(),
        walks.iter().map(|w| w.untrustworthy).collect(),
    ];
    let mut chosen: Vec<usize> = metrics
        .iter()
        .flat_map(|cost| limit::optimal_order(&accept, cost).into_iter().take(count))
        .collect();
    chosen.sort_unstable();
    chosen.dedup();
    chosen
}

/// The limit and trustworthy region of `operator` over every behavior of `domain` under
/// `thresholds`. The first
/// estimate draws from `seed` (cell `k` on stream `k`, as every landscape); the candidates'
/// second estimate from a seed derived from it.
pub fn known_operator<D: Domain>(
    domain: &D,
    operator: &D::Operator,
    thresholds: Thresholds,
    settings: LimitSettings,
    seed: u64,
) -> Result<KnownOperator, KnownLimitError> {
    let space = domain.space();
    let every: Vec<usize> = (0..space.components().len()).collect();
    let spread = u32::try_from(settings.budget / space.size().max(1)).unwrap_or(u32::MAX);
    let runs = settings.runs.max(spread);
    let first = landscape::estimate(domain, &[operator], &every, runs, seed, &|| {})?;
    let mut tallies = first.cells;
    let mut walks = solve_all(&tallies, thresholds)?;
    if settings.candidates > 0 && settings.candidate_runs > 0 {
        let again = stream_seed(seed, 0, 0, Purpose::Landscape);
        let ranks = candidates(&walks, settings.candidates);
        let fresh: Vec<Tally> = ranks
            .par_iter()
            .map(|&rank| {
                crate::interrupt::check()?;
                let behavior = space.unrank(rank as u64);
                let mut rng = ChaCha8Rng::seed_from_u64(again);
                rng.set_stream(rank as u64);
                let mut tally = Tally::default();
                for _ in 0..settings.candidate_runs {
                    tally.record(&domain.run(&behavior, operator, &mut rng));
                }
                Ok(tally)
            })
            .collect::<Result<_, crate::Interrupted>>()
            .map_err(LandscapeError::from)?;
        let fresh_walks = solve_all(&fresh, thresholds)?;
        for ((&rank, tally), walk) in ranks.iter().zip(fresh).zip(fresh_walks) {
            tallies[rank] = tally;
            walks[rank] = walk;
        }
    }
    let (laws, law_of) = distinct_steps(&tallies);
    Ok(KnownOperator {
        limit: Limit::from_outcomes(&walks)?,
        law: paper_law(&laws, &law_of, &walks, thresholds)?,
        trusted: tallies.iter().map(Tally::trusted_on_average).collect(),
        untrustworthy_rate: tallies.iter().map(|t| 1.0 - t.p_complete()).collect(),
        walks,
        laws,
        law_of,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rate_gap_share_counts_behaviors_whose_completion_rates_lie_more_than_half_apart() {
        // Gaps 0.7, 0.7 and 0.05: two of three behaviors lie more than 0.5 apart.
        let (a, b) = ([1.0, 0.2, 0.6], [0.3, 0.9, 0.55]);
        let (a_trusts, b_trusts) = ([true, false, true], [false, true, true]);
        let conflict = Conflict::of(&[(&a_trusts[..], &a[..]), (&b_trusts[..], &b[..])]);
        assert_eq!(conflict.rate_gap_share, vec![2.0 / 3.0]);
        // The same pair's Jaccard: one shared behavior of three trusted by either.
        assert_eq!(conflict.jaccard, vec![1.0 / 3.0]);
    }

    #[test]
    fn the_rate_gap_share_follows_the_pair_order_of_the_jaccard() {
        let trusts = [true, true];
        let rates: [&[f64]; 3] = [&[1.0, 1.0], &[0.0, 1.0], &[0.0, 0.0]];
        let members: Vec<(&[bool], &[f64])> = rates.iter().map(|r| (&trusts[..], *r)).collect();
        let conflict = Conflict::of(&members);
        // Pairs (0, 1), (0, 2), (1, 2).
        assert_eq!(conflict.rate_gap_share, vec![0.5, 1.0, 0.5]);
        assert_eq!(conflict.jaccard, vec![1.0; 3]);
    }

    #[test]
    fn rates_exactly_half_apart_are_not_counted_even_after_rounding() {
        // 0.7 - 0.2 is 0.49999999999999994 in floating point, 0.8 - 0.3 is 0.5.
        assert!(!rates_apart(0.7, 0.2));
        assert!(!rates_apart(0.3, 0.8));
        // Completion rates of 400 runs, as one minus the untrustworthy rates: 0.8825 and
        // 0.3825, whose difference comes out 0.5000000000000001.
        let (high, low) = (1.0 - 47.0 / 400.0, 1.0 - 247.0 / 400.0);
        assert!(high - low > RATE_GAP);
        assert!(!rates_apart(high, low));
        assert!(rates_apart(0.76, 0.25));
    }

    #[test]
    fn one_operator_has_no_pairs() {
        let conflict = Conflict::of(&[(&[true, false][..], &[0.9, 0.1][..])]);
        assert!(conflict.jaccard.is_empty());
        assert!(conflict.rate_gap_share.is_empty());
        assert_eq!(conflict.trusted_by_all, 1);
    }
}
