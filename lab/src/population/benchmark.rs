//! The benchmark report: every arm aggregated over many populations (instances) of one
//! scenario, against each population's known-operator limit, as COCO/BBOB aggregates an
//! optimizer over many problem instances.
//!
//! **What is measured.** A suite with `benchmark: true` runs every arm on many
//! populations of operators of a scenario; each population is an experiment with its own
//! known-operator limit ([`crate::reference::known_operator`], the paper's protocol: a random first
//! behavior). Per arm, scenario and metric (behaviors evaluated, commands, untrustworthy
//! commands per trial: [`Metric`]), the arm's mean over a population's trials divided by
//! that population's limit is its *ratio to the limit* there; the benchmark reports:
//!
//! - the **geometric mean of the ratios over populations**, with a **percentile
//!   bootstrap 95% interval over populations** ([`BOOTSTRAP_RESAMPLES`] resamples of the
//!   populations with replacement, each from its own seeded stream,
//!   [`Purpose::Benchmark`], so a report is the same every time). The geometric mean,
//!   because ratios multiply: an arm twice the limit on one population and half of it on
//!   another is even with it (an arithmetic mean would say 1.25), and one hard population
//!   with a ratio of 50 does not outweigh every other. The bootstrap is over populations
//!   and not trials, because the populations are the sample the benchmark generalizes
//!   from: with ten populations of 500 trials each, the uncertainty that matters is which
//!   ten populations were drawn. A ratio that is not finite and above 0 (a limit of 0, an
//!   arm mean of 0) has no logarithm and is left out, and the populations counted are
//!   reported beside the mean ([`LimitRatio::populations`]);
//! - **wins, ties and losses** against the reference arms [`REFERENCE_ARMS`] (those that
//!   ran), one verdict per population: the Wilcoxon signed-rank test
//!   ([`crate::stats::signed_rank_test`]) of the untrustworthy commands of the arm and the
//!   reference, trial by trial (trial `i` of every arm draws the same operator, initial
//!   behavior and outcome streams, [`crate::experiment::runner`], so trials pair by index); a *win*
//!   when the arm endures significantly fewer (`p <` [`SIGNIFICANCE`]), a *loss* when
//!   significantly more, else a *tie*;
//! - the **empirical distribution of the untrustworthy commands to settle** ([`Ecdf`]):
//!   the share of every (population, trial) pair of the arm that ended on a trustworthy
//!   behavior within `N` untrustworthy commands, as `N` grows (pairs that never settled
//!   stay out of reach), and the same distribution of the known-operator limit's agent
//!   ([`ScenarioBenchmark::limit_law`]): on each population, the exact law of the
//!   untrustworthy commands after which that agent, under the paper's protocol, settles
//!   ([`crate::reference::limit_law`]), pooled over populations as the arms' pairs are, each
//!   population weighing as many pairs as it has trials;
//! - the **ratio to the limit over episodes** ([`TRIAL_WINDOWS`]): the geometric mean over
//!   populations of the arm's mean over the trials of a window divided by the limit, for
//!   trials 1–50, 51–200 and 201 to the end (a window with no trial is left out): how an
//!   arm that learns across episodes closes on the limit.
//! - **the split of the excess**, where populations have a population reference
//!   ([`crate::reference::population_reference`]): the geometric mean over populations of
//!   the reference's ratio to the limit (what telling members apart costs,
//!   [`ScenarioBenchmark::population_reference_to_limit`]) and of each arm's ratio to the
//!   reference (what learning costs, [`ArmBenchmark::to_population_reference`]), with
//!   their bootstrap intervals over the populations that have one.
//! - **the best arm of each population, after the fact** ([`BestOfEachPopulation`]): on
//!   each population the lowest ratio to the limit any arm reached, and the geometric mean
//!   of those minima over populations, per metric and window. It is what algorithm
//!   selection benchmarks call the virtual best solver: no arm, since no rule fixed before
//!   the trials picks a different arm on each population, and the least of many noisy
//!   means flatters itself; it says how far an arm is from everything the suite ran.
//!
//! Everything here is computed from results; the report draws and writes it
//! ([`crate::report`]).

use crate::experiment::arm_name::ArmName;
use crate::experiment::record::{ArmResult, ExperimentResult, TrialRecord};
use crate::reference::limit::Costs;
use crate::reference::limit_law::UntrustworthyLaw;
use crate::seeds::{Purpose, stream};
use crate::stats::{RatioCi, percentile, signed_rank_test};
use crate::targets::SIGNIFICANCE;
use rand::Rng;

/// Resamples of the bootstrap over populations.
pub const BOOTSTRAP_RESAMPLES: usize = 2000;

/// The arms every arm is counted wins, ties and losses against, when they ran: the honest
/// baseline and the paper's case-based arm.
pub const REFERENCE_ARMS: [&str; 2] = ["uniform", "case-based"];

/// The windows of trials (1-based, both ends included; `None`: to the last trial) the
/// ratio to the limit is followed over.
pub const TRIAL_WINDOWS: [(u32, Option<u32>); 3] = [(1, Some(50)), (51, Some(200)), (201, None)];

/// What a trial costs the operator, as the limit tables compare it with the limit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Metric {
    /// Behaviors evaluated (the paper's metric).
    Behaviors,
    /// Commands until the trial ended.
    Commands,
    /// Commands that failed or were interrupted.
    Untrustworthy,
}

impl Metric {
    /// The three, in the tables' order.
    pub const ALL: [Metric; 3] = [Metric::Behaviors, Metric::Commands, Metric::Untrustworthy];

    /// Its value in one trial (what [`ArmResult`]'s means are the means of).
    pub fn of_trial(self, trial: &TrialRecord) -> f64 {
        let report = &trial.report;
        (match self {
            Metric::Behaviors => report.behaviors_evaluated,
            Metric::Commands => report.commands,
            Metric::Untrustworthy => report.untrustworthy,
        }) as f64
    }

    /// The limit's value.
    pub fn of_limit(self, limit: &Costs) -> f64 {
        match self {
            Metric::Behaviors => limit.behaviors,
            Metric::Commands => limit.commands,
            Metric::Untrustworthy => limit.untrustworthy,
        }
    }

    /// Its name in `summary.json`.
    pub fn key(self) -> &'static str {
        match self {
            Metric::Behaviors => "behaviors",
            Metric::Commands => "commands",
            Metric::Untrustworthy => "untrustworthy",
        }
    }
}

/// One population of a benchmark: an experiment's results and its known-operator limit
/// under the paper's protocol.
#[derive(Clone, Copy, Debug)]
pub struct BenchmarkPopulation<'a> {
    /// The scenario it is a population of.
    pub scenario: &'a str,
    /// Its results.
    pub result: &'a ExperimentResult,
    /// Its limit (the paper's protocol: a random first behavior).
    pub limit: Costs,
    /// The law of its limit agent's untrustworthy commands (the paper's protocol), whose
    /// mean is `limit.untrustworthy`.
    pub limit_law: &'a UntrustworthyLaw,
    /// Its population reference (the paper's protocol), when it has one
    /// ([`crate::reference::population_reference`]).
    pub population_reference: Option<Costs>,
}

/// An arm's geometric mean ratio to the limit, with the populations it is over.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LimitRatio {
    /// The geometric mean over populations and its percentile bootstrap 95% interval.
    pub ratio: RatioCi,
    /// The populations whose ratio was finite and above 0 (the others have no logarithm).
    pub populations: usize,
}

/// How a paired comparison of an arm with a reference ended on one population.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Comparison {
    /// Significantly fewer untrustworthy commands than the reference.
    Win,
    /// No significant difference.
    Tie,
    /// Significantly more.
    Loss,
}

/// Wins, ties and losses over populations.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WinsTiesLosses {
    /// Populations won.
    pub wins: usize,
    /// Populations tied.
    pub ties: usize,
    /// Populations lost.
    pub losses: usize,
}

impl FromIterator<Comparison> for WinsTiesLosses {
    fn from_iter<I: IntoIterator<Item = Comparison>>(verdicts: I) -> Self {
        let mut tally = Self::default();
        for verdict in verdicts {
            match verdict {
                Comparison::Win => tally.wins += 1,
                Comparison::Tie => tally.ties += 1,
                Comparison::Loss => tally.losses += 1,
            }
        }
        tally
    }
}

/// The empirical distribution of the untrustworthy commands to settle on a trustworthy
/// behavior, over (population, trial) pairs.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Ecdf {
    /// Every pair counted.
    pub pairs: usize,
    /// The untrustworthy commands of each pair that settled, ascending.
    pub settled: Vec<u64>,
}

impl Ecdf {
    /// The distribution of pairs `(found trustworthy, untrustworthy commands)`.
    pub fn of(pairs: impl IntoIterator<Item = (bool, u64)>) -> Self {
        let mut ecdf = Self::default();
        for (found, untrustworthy) in pairs {
            ecdf.pairs += 1;
            if found {
                ecdf.settled.push(untrustworthy);
            }
        }
        ecdf.settled.sort_unstable();
        ecdf
    }

    /// The share of pairs that settled within `n` untrustworthy commands (0 with no pair).
    pub fn share_within(&self, n: u64) -> f64 {
        let within = self.settled.partition_point(|&u| u <= n);
        within as f64 / self.pairs.max(1) as f64
    }

    /// Where the curve steps up: each count at which some pair settled, with the share
    /// settled within it.
    pub fn steps(&self) -> Vec<(u64, f64)> {
        let mut counts = self.settled.clone();
        counts.dedup();
        counts
            .into_iter()
            .map(|n| (n, self.share_within(n)))
            .collect()
    }
}

/// A window of trials, 1-based, both ends included.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TrialRange {
    /// The first trial.
    pub first: u32,
    /// The last trial.
    pub last: u32,
}

impl TrialRange {
    /// The windows of [`TRIAL_WINDOWS`] that hold some of `trials` trials, cut at the last.
    pub fn windows(trials: u32) -> Vec<Self> {
        TRIAL_WINDOWS
            .iter()
            .filter(|&&(first, _)| first <= trials)
            .map(|&(first, last)| Self {
                first,
                last: last.map_or(trials, |last| last.min(trials)),
            })
            .collect()
    }

    /// Whether the trial numbered `trial` (from 0, as [`TrialRecord::trial`]) is in it.
    pub fn holds(self, trial: u32) -> bool {
        (self.first..=self.last).contains(&(trial + 1))
    }
}

/// One arm of a scenario's benchmark.
#[derive(Clone, Debug, PartialEq)]
pub struct ArmBenchmark {
    /// The arm's name.
    pub arm: ArmName,
    /// Per [`Metric::ALL`], the geometric mean ratio to the limit (`None`: no population
    /// has a usable ratio).
    pub to_limit: [Option<LimitRatio>; 3],
    /// Per [`Metric::ALL`], the geometric mean ratio to the population reference over the
    /// populations that have one: what learning costs the arm.
    pub to_population_reference: [Option<LimitRatio>; 3],
    /// Per reference arm of the scenario ([`ScenarioBenchmark::references`]), the wins,
    /// ties and losses against it (`None` for the reference itself).
    pub versus: Vec<Option<WinsTiesLosses>>,
    /// Its untrustworthy commands to settle, over every (population, trial) pair.
    pub ecdf: Ecdf,
    /// Per window of [`ScenarioBenchmark::windows`], per [`Metric::ALL`], the geometric
    /// mean ratio to the limit over the window's trials.
    pub windows: Vec<[Option<f64>; 3]>,
}

/// The best arm of each population, picked after the fact: per population the lowest
/// ratio to the limit of any arm, and the geometric mean of those minima over the
/// populations where some arm's ratio was usable. Not an arm (see the module's doc).
#[derive(Clone, Debug, PartialEq)]
pub struct BestOfEachPopulation {
    /// Per [`Metric::ALL`], over every trial.
    pub to_limit: [Option<f64>; 3],
    /// Per window of [`ScenarioBenchmark::windows`], per [`Metric::ALL`].
    pub windows: Vec<[Option<f64>; 3]>,
}

/// The benchmark of one scenario: every arm over its populations.
#[derive(Clone, Debug, PartialEq)]
pub struct ScenarioBenchmark {
    /// The scenario.
    pub scenario: String,
    /// Its populations (experiments), by name.
    pub populations: Vec<String>,
    /// The reference arms of [`REFERENCE_ARMS`] that ran.
    pub references: Vec<String>,
    /// The windows of trials the ratio to the limit is followed over.
    pub windows: Vec<TrialRange>,
    /// Per [`Metric::ALL`], the geometric mean ratio of the population reference to the
    /// limit over the populations that have one: what telling members apart costs.
    pub population_reference_to_limit: [Option<LimitRatio>; 3],
    /// The mean over populations of the limit's expected untrustworthy commands (paper
    /// protocol).
    pub limit_untrustworthy: f64,
    /// The law of the limit agent's untrustworthy commands (paper protocol), pooled over
    /// populations as the arms' [`Ecdf`]s are: each population weighs its trials. The ECDF
    /// figure draws its settled part as the limit's curve.
    pub limit_law: UntrustworthyLaw,
    /// Every arm, in the experiments' order.
    pub arms: Vec<ArmBenchmark>,
    /// The best arm of each population, after the fact.
    pub best_of_each_population: BestOfEachPopulation,
}

/// The ratios that have a logarithm: finite and above 0.
fn usable(ratios: impl IntoIterator<Item = f64>) -> Vec<f64> {
    ratios
        .into_iter()
        .filter(|r| r.is_finite() && *r > 0.0)
        .collect()
}

/// The geometric mean of `ratios` (each finite and above 0); `None` for none.
pub fn geometric_mean(ratios: &[f64]) -> Option<f64> {
    (!ratios.is_empty())
        .then(|| (ratios.iter().map(|r| r.ln()).sum::<f64>() / ratios.len() as f64).exp())
}

/// The geometric mean of `ratios` (each finite and above 0) with the 95% interval of the
/// percentile bootstrap: `resamples` times, `n` ratios drawn with replacement from `rng`,
/// their geometric mean; the 2.5th and 97.5th percentiles of those. `None` for none.
pub fn bootstrap_geometric_mean<R: Rng + ?Sized>(
    ratios: &[f64],
    resamples: usize,
    rng: &mut R,
) -> Option<RatioCi> {
    let logs: Vec<f64> = ratios.iter().map(|r| r.ln()).collect();
    let n = logs.len();
    let ratio = geometric_mean(ratios)?;
    let mut means: Vec<f64> = (0..resamples.max(1))
        .map(|_| {
            let sum: f64 = (0..n).map(|_| logs[rng.random_range(0..n)]).sum();
            (sum / n as f64).exp()
        })
        .collect();
    means.sort_by(f64::total_cmp);
    Some(RatioCi {
        ratio,
        low: percentile(&means, 0.025)?,
        high: percentile(&means, 0.975)?,
    })
}

/// The verdict of an arm against a reference on one population from their untrustworthy
/// commands per trial, paired by trial: a win when the arm's are significantly fewer by
/// the Wilcoxon signed-rank test, a loss when significantly more. `None` if the slices
/// differ in length or are empty.
pub fn paired_comparison(arm: &[f64], reference: &[f64]) -> Option<Comparison> {
    let test = signed_rank_test(arm, reference)?;
    Some(if test.p >= SIGNIFICANCE {
        Comparison::Tie
    } else if test.z < 0.0 {
        Comparison::Win
    } else {
        Comparison::Loss
    })
}

/// The mean of `values`; `None` for none.
fn mean(values: &[f64]) -> Option<f64> {
    (!values.is_empty()).then(|| values.iter().sum::<f64>() / values.len() as f64)
}

/// An arm's `metric` per trial, in trial order, of the trials `window` holds.
fn per_trial(arm: &ArmResult, metric: Metric, window: TrialRange) -> Vec<f64> {
    arm.trials
        .iter()
        .filter(|t| window.holds(t.trial))
        .map(|t| metric.of_trial(t))
        .collect()
}

/// The arm's mean `metric` over the trials `window` holds as a ratio to `costs` (the
/// limit's or the population reference's).
fn ratio_to(arm: &ArmResult, costs: &Costs, metric: Metric, window: TrialRange) -> Option<f64> {
    mean(&per_trial(arm, metric, window)).map(|m| m / metric.of_limit(costs))
}

/// Per population, the lowest usable ratio to the limit of any of its arms over the
/// trials `window` holds (populations where no arm's ratio is usable are left out).
fn lowest_ratios(
    populations: &[&BenchmarkPopulation<'_>],
    metric: Metric,
    window: TrialRange,
) -> Vec<f64> {
    populations
        .iter()
        .filter_map(|p| {
            usable(
                p.result
                    .arms
                    .iter()
                    .filter_map(|arm| ratio_to(arm, &p.limit, metric, window)),
            )
            .into_iter()
            .reduce(f64::min)
        })
        .collect()
}

/// The geometric mean of usable `ratios` with its bootstrap interval, from the stream of
/// (`seed`, `experiment`, `trial`) for the benchmark.
fn bootstrapped(ratios: &[f64], seed: u64, experiment: u64, trial: u64) -> Option<LimitRatio> {
    let ratios = usable(ratios.iter().copied());
    let mut rng = stream(seed, experiment, trial, Purpose::Benchmark);
    bootstrap_geometric_mean(&ratios, BOOTSTRAP_RESAMPLES, &mut rng).map(|ratio| LimitRatio {
        ratio,
        populations: ratios.len(),
    })
}

/// Where the bootstraps of ratios to the population reference draw from: the scenario's
/// index plus this as the stream's "experiment" (the ratios to the limit use the index
/// alone, so their intervals are what they were before the reference was reported).
const REFERENCE_STREAMS: u64 = 1 << 32;

/// The benchmark of every scenario of `populations` (in the order each first appears),
/// its bootstraps drawn from streams of `seed`.
pub fn benchmarks(populations: &[BenchmarkPopulation<'_>], seed: u64) -> Vec<ScenarioBenchmark> {
    let mut scenarios: Vec<&str> = Vec::new();
    for p in populations {
        if !scenarios.contains(&p.scenario) {
            scenarios.push(p.scenario);
        }
    }
    scenarios
        .iter()
        .enumerate()
        .map(|(k, scenario)| {
            let of_scenario: Vec<&BenchmarkPopulation<'_>> = populations
                .iter()
                .filter(|p| p.scenario == *scenario)
                .collect();
            scenario_benchmark(scenario, &of_scenario, seed, k as u64)
        })
        .collect()
}

/// The benchmark of one scenario, the `index`-th of the report.
fn scenario_benchmark(
    scenario: &str,
    populations: &[&BenchmarkPopulation<'_>],
    seed: u64,
    index: u64,
) -> ScenarioBenchmark {
    let arm_names: Vec<&ArmName> = populations
        .first()
        .map(|p| p.result.arms.iter().map(|a| &a.name).collect())
        .unwrap_or_default();
    let references: Vec<&str> = REFERENCE_ARMS
        .into_iter()
        .filter(|r| arm_names.iter().any(|name| name == r))
        .collect();
    let trials = populations
        .iter()
        .map(|p| p.result.trials())
        .max()
        .unwrap_or(0);
    let every_trial = TrialRange {
        first: 1,
        last: u32::try_from(trials).unwrap_or(u32::MAX),
    };
    let windows = TrialRange::windows(every_trial.last);
    let arms = arm_names
        .iter()
        .enumerate()
        .map(|(a, name)| {
            // The populations with this arm, each with the arm's results there.
            let runs: Vec<(&BenchmarkPopulation<'_>, &ArmResult)> = populations
                .iter()
                .filter_map(|p| p.result.arm(name.as_str()).map(|arm| (*p, arm)))
                .collect();
            let geometric_ratio = |metric: Metric, window: TrialRange| {
                usable(
                    runs.iter()
                        .filter_map(|(p, arm)| ratio_to(arm, &p.limit, metric, window)),
                )
            };
            let trial = |metric: Metric| (a * Metric::ALL.len()) as u64 + metric as u64;
            let to_limit = Metric::ALL.map(|metric| {
                bootstrapped(
                    &geometric_ratio(metric, every_trial),
                    seed,
                    index,
                    trial(metric),
                )
            });
            let to_population_reference = Metric::ALL.map(|metric| {
                let ratios: Vec<f64> = runs
                    .iter()
                    .filter_map(|(p, arm)| {
                        ratio_to(arm, p.population_reference.as_ref()?, metric, every_trial)
                    })
                    .collect();
                bootstrapped(&ratios, seed, index + REFERENCE_STREAMS, trial(metric))
            });
            let versus = references
                .iter()
                .map(|reference| {
                    (*reference != name.as_str()).then(|| {
                        runs.iter()
                            .filter_map(|(p, arm)| {
                                let base = p.result.arm(reference)?;
                                paired_comparison(
                                    &per_trial(arm, Metric::Untrustworthy, every_trial),
                                    &per_trial(base, Metric::Untrustworthy, every_trial),
                                )
                            })
                            .collect()
                    })
                })
                .collect();
            let ecdf = Ecdf::of(runs.iter().flat_map(|(_, arm)| {
                arm.trials
                    .iter()
                    .map(|t| (t.report.found_trustworthy, t.report.untrustworthy))
            }));
            let windows = windows
                .iter()
                .map(|&window| {
                    Metric::ALL.map(|metric| geometric_mean(&geometric_ratio(metric, window)))
                })
                .collect();
            ArmBenchmark {
                arm: (*name).clone(),
                to_limit,
                to_population_reference,
                versus,
                ecdf,
                windows,
            }
        })
        .collect();
    let best_of = |window: TrialRange| {
        Metric::ALL.map(|metric| geometric_mean(&lowest_ratios(populations, metric, window)))
    };
    let best_of_each_population = BestOfEachPopulation {
        to_limit: best_of(every_trial),
        windows: windows.iter().map(|&window| best_of(window)).collect(),
    };
    let population_reference_to_limit = Metric::ALL.map(|metric| {
        let ratios: Vec<f64> = populations
            .iter()
            .filter_map(|p| {
                let reference = p.population_reference.as_ref()?;
                Some(metric.of_limit(reference) / metric.of_limit(&p.limit))
            })
            .collect();
        // After every arm's streams, in the reference's range.
        let trial = (arm_names.len() * Metric::ALL.len()) as u64 + metric as u64;
        bootstrapped(&ratios, seed, index + REFERENCE_STREAMS, trial)
    });
    ScenarioBenchmark {
        scenario: scenario.to_owned(),
        populations: populations.iter().map(|p| p.result.name.clone()).collect(),
        references: references.iter().map(|r| (*r).to_owned()).collect(),
        windows,
        population_reference_to_limit,
        limit_untrustworthy: mean(
            &populations
                .iter()
                .map(|p| p.limit.untrustworthy)
                .collect::<Vec<_>>(),
        )
        .unwrap_or(0.0),
        limit_law: UntrustworthyLaw::mixture(
            populations
                .iter()
                .map(|p| (p.result.trials() as f64, p.limit_law)),
        ),
        arms,
        best_of_each_population,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn the_geometric_mean_by_hand() {
        // Ratios 2 and 1/2 are even with the limit: exp((ln 2 - ln 2) / 2) = 1 (the
        // arithmetic mean would say 1.25). Ratios 1, 2, 4: (1 * 2 * 4)^(1/3) = 2.
        assert!((geometric_mean(&[2.0, 0.5]).unwrap() - 1.0).abs() < 1e-12);
        assert!((geometric_mean(&[1.0, 2.0, 4.0]).unwrap() - 2.0).abs() < 1e-12);
        assert_eq!(geometric_mean(&[]), None);
        // A ratio without a logarithm is left out.
        assert_eq!(
            usable([2.0, 0.0, f64::INFINITY, f64::NAN, 0.5]),
            vec![2.0, 0.5]
        );
    }

    #[test]
    fn the_bootstrap_is_deterministic_and_brackets_the_geometric_mean() {
        let ratios = [1.0, 2.0, 4.0, 1.5, 3.0, 0.8];
        let draw = |seed: u64| {
            bootstrap_geometric_mean(
                &ratios,
                BOOTSTRAP_RESAMPLES,
                &mut ChaCha8Rng::seed_from_u64(seed),
            )
            .unwrap()
        };
        let ci = draw(7);
        assert_eq!(ci, draw(7));
        assert!((ci.ratio - geometric_mean(&ratios).unwrap()).abs() < 1e-12);
        assert!(ci.low < ci.ratio && ci.ratio < ci.high, "{ci:?}");
        // Within the smallest and largest ratio: a resample's geometric mean cannot leave it.
        assert!(ci.low >= 0.8 && ci.high <= 4.0, "{ci:?}");
        // Every population at the same ratio: every resample too.
        let same = bootstrap_geometric_mean(&[1.5; 4], 100, &mut ChaCha8Rng::seed_from_u64(1));
        assert_eq!(
            same.map(|c| (c.ratio, c.low, c.high)),
            Some((1.5, 1.5, 1.5))
        );
        assert_eq!(
            bootstrap_geometric_mean(&[], 100, &mut ChaCha8Rng::seed_from_u64(1)),
            None
        );
    }

    #[test]
    fn wins_ties_and_losses_by_hand() {
        // Differences arm - reference -1, -2, -3, -4, -5, 0 (dropped): W+ = 0, n = 5,
        // z = (0 - 7.5) / sqrt(13.75) = -2.0226, p = 0.0431 < 0.05: fewer, a win.
        let arm = [2.0, 2.0, 2.0, 2.0, 2.0, 9.0];
        let reference = [3.0, 4.0, 5.0, 6.0, 7.0, 9.0];
        assert_eq!(paired_comparison(&arm, &reference), Some(Comparison::Win));
        // The other way round: significantly more, a loss.
        assert_eq!(paired_comparison(&reference, &arm), Some(Comparison::Loss));
        // Differences -1, 1, 2, 2: p = 0.19, a tie; and equal counts are a tie.
        let tie = paired_comparison(&[0.0, 1.0, 2.0, 2.0], &[1.0, 0.0, 0.0, 0.0]);
        assert_eq!(tie, Some(Comparison::Tie));
        assert_eq!(paired_comparison(&arm, &arm), Some(Comparison::Tie));
        assert_eq!(paired_comparison(&arm, &reference[1..]), None);
        // Four populations: won, lost, tied twice.
        let tally: WinsTiesLosses = [
            Comparison::Win,
            Comparison::Loss,
            Comparison::Tie,
            Comparison::Tie,
        ]
        .into_iter()
        .collect();
        assert_eq!(
            tally,
            WinsTiesLosses {
                wins: 1,
                ties: 2,
                losses: 1
            }
        );
    }

    #[test]
    fn the_ecdf_by_hand() {
        // Five pairs: settled after 0, 3, 3 and 7 untrustworthy commands; one never did.
        let ecdf = Ecdf::of([(true, 3), (false, 12), (true, 0), (true, 7), (true, 3)]);
        assert_eq!(ecdf.pairs, 5);
        assert_eq!(ecdf.share_within(0), 0.2);
        assert_eq!(ecdf.share_within(2), 0.2);
        assert_eq!(ecdf.share_within(3), 0.6);
        // The pair that never settled stays out of reach, however many commands.
        assert_eq!(ecdf.share_within(1000), 0.8);
        assert_eq!(ecdf.steps(), vec![(0, 0.2), (3, 0.6), (7, 0.8)]);
        assert_eq!(Ecdf::of([]).share_within(5), 0.0);
    }

    /// An arm whose trials ended with these (found trustworthy, untrustworthy commands);
    /// each trial evaluated 2 behaviors in 10 commands.
    fn arm(name: &str, trials: &[(bool, u64)]) -> ArmResult {
        ArmResult::of_trials(name, trials)
    }

    #[test]
    fn a_scenario_by_hand() {
        let settled = |counts: &[u64]| counts.iter().map(|&u| (true, u)).collect::<Vec<_>>();
        // Population p: `uniform` endures 2 untrustworthy commands a trial, `other` 1, 2,
        // 3, 4, 5, 6 fewer (a win by the Wilcoxon test); population q: `other` endures
        // more than `uniform` in every trial (a loss).
        let p = ExperimentResult {
            name: "s/p".to_owned(),
            arms: vec![
                arm("uniform", &settled(&[8, 8, 8, 8, 8, 8])),
                arm("other", &settled(&[7, 6, 5, 4, 3, 2])),
            ],
        };
        let q = ExperimentResult {
            name: "s/q".to_owned(),
            arms: vec![
                arm("uniform", &settled(&[1, 1, 1, 1, 1, 1])),
                arm(
                    "other",
                    &[
                        (true, 2),
                        (true, 3),
                        (true, 4),
                        (true, 5),
                        (true, 6),
                        (false, 7),
                    ],
                ),
            ],
        };
        // The limits: 1 behavior, 5 commands, 2 and 4 untrustworthy commands.
        let limit = |untrustworthy| Costs {
            behaviors: 1.0,
            commands: 5.0,
            untrustworthy,
        };
        // Their laws: p's agent settles after 2 untrustworthy commands; q's after 0 or 4,
        // even odds.
        let settled_at = |counts: &[(u64, f64)]| {
            let mut law = UntrustworthyLaw::default();
            for &(u, mass) in counts {
                law.settled.mass.resize(u as usize + 1, 0.0);
                law.settled.mass[u as usize] = mass;
            }
            law
        };
        let (p_law, q_law) = (settled_at(&[(2, 1.0)]), settled_at(&[(0, 0.5), (4, 0.5)]));
        let populations = [
            BenchmarkPopulation {
                scenario: "s",
                result: &p,
                limit: limit(2.0),
                limit_law: &p_law,
                // p's population reference: 1.5 behaviors, 7.5 commands, 3 untrustworthy.
                population_reference: Some(Costs {
                    behaviors: 1.5,
                    commands: 7.5,
                    untrustworthy: 3.0,
                }),
            },
            BenchmarkPopulation {
                scenario: "s",
                result: &q,
                limit: limit(4.0),
                limit_law: &q_law,
                population_reference: None,
            },
        ];
        let [s] = benchmarks(&populations, 1).try_into().unwrap();
        assert_eq!(s.populations, ["s/p", "s/q"]);
        assert_eq!(s.references, ["uniform"]);
        assert_eq!(s.limit_untrustworthy, 3.0);
        // Six trials each: the populations weigh alike.
        assert_eq!(s.limit_law.steps(), [(0, 0.25), (2, 0.75), (4, 1.0)]);
        assert_eq!(s.windows, vec![TrialRange { first: 1, last: 6 }]);
        let (uniform, other) = (&s.arms[0], &s.arms[1]);
        // `other`: untrustworthy means 4.5 and 4.5, over limits 2 and 4: ratios 2.25 and
        // 1.125, geometric mean sqrt(2.53125) = 1.59099; behaviors 2 / 1 and commands
        // 10 / 5 on both: 2.
        let [behaviors, commands, untrustworthy] = other.to_limit.map(Option::unwrap);
        assert!((untrustworthy.ratio.ratio - 2.53125f64.sqrt()).abs() < 1e-12);
        assert_eq!(untrustworthy.populations, 2);
        assert!(untrustworthy.ratio.low >= 1.125 && untrustworthy.ratio.high <= 2.25);
        assert!((behaviors.ratio.ratio - 2.0).abs() < 1e-12);
        assert!((commands.ratio.ratio - 2.0).abs() < 1e-12);
        assert_eq!(
            other.windows,
            vec![other.to_limit.map(|r| Some(r.unwrap().ratio.ratio))]
        );
        // Over the population reference, on p alone (q has none): untrustworthy 4.5 / 3,
        // behaviors 2 / 1.5, commands 10 / 7.5; the reference over p's limit: 1.5 each.
        let over = other.to_population_reference.map(Option::unwrap);
        let expected = [4.0 / 3.0, 4.0 / 3.0, 1.5];
        for (ratio, expected) in over.iter().zip(expected) {
            assert!((ratio.ratio.ratio - expected).abs() < 1e-12);
            assert_eq!(ratio.populations, 1);
        }
        for ratio in s.population_reference_to_limit.map(Option::unwrap) {
            assert!((ratio.ratio.ratio - 1.5).abs() < 1e-12);
        }
        // Against `uniform`: one win (p), one loss (q); `uniform` against itself: none.
        assert_eq!(
            other.versus,
            vec![Some(WinsTiesLosses {
                wins: 1,
                ties: 0,
                losses: 1
            })]
        );
        assert_eq!(uniform.versus, vec![None]);
        // The best arm of each population, after the fact: on p `other` (4.5 / 2 = 2.25
        // against `uniform`'s 8 / 2 = 4), on q `uniform` (1 / 4 = 0.25 against 4.5 / 4):
        // sqrt(2.25 * 0.25) = 0.75, below both arms (`uniform` sqrt(4 * 0.25) = 1); both
        // arms evaluate 2 behaviors in 10 commands everywhere: 2 and 2.
        let best = &s.best_of_each_population;
        let [behaviors, commands, untrustworthy] = best.to_limit.map(Option::unwrap);
        assert!((untrustworthy - 0.75).abs() < 1e-12);
        assert!((behaviors - 2.0).abs() < 1e-12 && (commands - 2.0).abs() < 1e-12);
        assert_eq!(best.windows, vec![best.to_limit]);
        // Twelve pairs of `other`, eleven settled; the one that did not stays out.
        assert_eq!(other.ecdf.pairs, 12);
        assert_eq!(other.ecdf.share_within(4), 6.0 / 12.0);
        assert_eq!(other.ecdf.share_within(100), 11.0 / 12.0);
        // The bootstrap is the same every time.
        assert_eq!(benchmarks(&populations, 1), vec![s]);
    }

    #[test]
    fn the_limits_curve_weighs_each_population_by_its_trials() {
        // p: 2 trials, its agent settles at 0; q: 6 trials, at 3 or never, even odds. Pooled
        // as 8 pairs: 2 at 0, 3 at 3, 3 never.
        let result = |name: &str, trials: usize| ExperimentResult {
            name: name.to_owned(),
            arms: vec![arm("uniform", &vec![(true, 1); trials])],
        };
        let (p, q) = (result("s/p", 2), result("s/q", 6));
        let at_zero = UntrustworthyLaw {
            settled: crate::reference::limit_law::CountLaw {
                mass: vec![1.0],
                ..Default::default()
            },
            unsettled: Default::default(),
        };
        let half_at_three = UntrustworthyLaw {
            settled: crate::reference::limit_law::CountLaw {
                mass: vec![0.0, 0.0, 0.0, 0.5],
                ..Default::default()
            },
            unsettled: crate::reference::limit_law::CountLaw {
                mass: vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.5],
                ..Default::default()
            },
        };
        let limit = Costs {
            behaviors: 1.0,
            commands: 5.0,
            untrustworthy: 1.0,
        };
        let populations = [
            BenchmarkPopulation {
                scenario: "s",
                result: &p,
                limit,
                limit_law: &at_zero,
                population_reference: None,
            },
            BenchmarkPopulation {
                scenario: "s",
                result: &q,
                limit,
                limit_law: &half_at_three,
                population_reference: None,
            },
        ];
        let [s] = benchmarks(&populations, 1).try_into().unwrap();
        assert_eq!(s.limit_law.steps(), [(0, 0.25), (3, 0.625)]);
        assert_eq!(s.limit_law.unsettled.total(), 0.375);
    }

    #[test]
    fn windows_by_hand() {
        let range = |first, last| TrialRange { first, last };
        assert_eq!(
            TrialRange::windows(500),
            vec![range(1, 50), range(51, 200), range(201, 500)]
        );
        // Too few trials for the later windows: cut, then left out.
        assert_eq!(TrialRange::windows(120), vec![range(1, 50), range(51, 120)]);
        assert_eq!(TrialRange::windows(30), vec![range(1, 30)]);
        assert_eq!(TrialRange::windows(0), vec![]);
        // Trial numbers count from 0: trial 49 is the 50th, the last of the first window.
        assert!(range(1, 50).holds(49) && !range(1, 50).holds(50));
        assert!(range(51, 200).holds(50));
    }
}
