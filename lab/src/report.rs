//! The report of a set of experiments: the printed tables (the paper's two arms, then
//! every arm with what it costs the operator), `table.md`, `summary.json` (with the
//! report's provenance), `trials.jsonl`, the config used, and SVG plots (learning curves,
//! and where the final behaviors land in the behavior space, over the operator's
//! landscape). Every file is written atomically.

use crate::Domain;
use crate::arm::Initial;
use crate::heatmap::{self, KEY_WIDTH};
use crate::known_operator::ExperimentLimit;
use crate::landscape::{self, Grid, Landscape};
use crate::limit::Costs;
use crate::plot::{
    Area, ArmStyle, DrawResult, Overlay, PlotError, Shape, arm_style, drawing_order, log_ticks,
    svg, svg_with, tick_label, wrap,
};
use crate::runner::{
    ArmResult, ExperimentResult, ExplanationCheck, GivenUpRecord, PairedTests, TrialRecord,
};
use crate::seeds::{Purpose, stream, stream_seed};
use crate::stats::{
    MeanCi, RatioCi, mean_ci95, paired_bootstrap_ratio, paired_t_test, wilcoxon_signed_rank,
};
use crate::timeline::{Timeline, timeline_figure};
use cbr_core::BehaviorSpace;
use files::{FileError, write_file_in};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use rayon::prelude::*;
use serde::Serialize;
use serde_json::{Map, Value, json};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use trust::Cause;
use trust::named::named_behavior;

/// One experiment's results with what the report needs to describe them.
pub struct ReportEntry<'a> {
    /// The results.
    pub result: &'a ExperimentResult,
    /// The scenario (domain) name, e.g. `movement`.
    pub scenario: &'a str,
    /// The configured operator: a name, `random`, or the name of a population.
    pub operator: &'a str,
    /// The behavior space, to show behaviors in real units.
    pub space: &'a BehaviorSpace,
    /// The operator's landscapes the final behaviors are drawn over, one per pair of
    /// [`component_pairs`] ([`finals_landscapes`]); empty to draw them on white.
    pub landscapes: &'a [Landscape],
    /// The known-operator limit of the experiment ([`crate::known_operator`]), when
    /// computed.
    pub limit: Option<&'a ExperimentLimit>,
    /// A sample trial traced command by command ([`crate::timeline`]), when traced.
    pub timeline: Option<&'a Timeline>,
    /// The arm every other arm is tested against (p-values) and measured against (effect
    /// sizes); when it is not among the arms, no arm is.
    pub reference: &'a str,
    /// The master seed of the experiments, from which the effect sizes' bootstrap
    /// streams derive ([`Purpose::Bootstrap`]).
    pub seed: u64,
}

/// Resamples of the paired bootstrap of an effect size.
const BOOTSTRAP_RESAMPLES: usize = 2000;

/// Each arm's effect size in experiment number `experiment` (its place in the report):
/// its mean behaviors evaluated as a ratio to the reference arm's, with the paired
/// bootstrap's 95% interval (arm `a` resampled from stream `(seed, experiment, a,
/// Bootstrap)`); `None` for the reference itself, and for every arm when the reference
/// is not among them or evaluated nothing.
pub fn effect_sizes(e: &ReportEntry<'_>, experiment: usize) -> Vec<Option<RatioCi>> {
    against_reference(e, |a, counts, base| {
        let mut rng = stream(e.seed, experiment as u64, a as u64, Purpose::Bootstrap);
        paired_bootstrap_ratio(counts, base, BOOTSTRAP_RESAMPLES, &mut rng)
    })
    .into_iter()
    .map(Option::flatten)
    .collect()
}

/// `compare(a, counts, reference_counts)` for each arm `a` of `e` but its reference arm
/// ([`ReportEntry::reference`]), over the behaviors evaluated per trial; `None` for the
/// reference itself, and for every arm when the reference is not among them.
fn against_reference<T>(
    e: &ReportEntry<'_>,
    compare: impl Fn(usize, &[f64], &[f64]) -> T,
) -> Vec<Option<T>> {
    let Some(reference) = e.result.arm(e.reference) else {
        return e.result.arms.iter().map(|_| None).collect();
    };
    let base = reference.counts();
    e.result
        .arms
        .iter()
        .enumerate()
        .map(|(a, arm)| (arm.name != reference.name).then(|| compare(a, &arm.counts(), &base)))
        .collect()
}

/// The effect sizes of every entry ([`effect_sizes`]), in the entries' order: the
/// bootstrap runs once per report, and the entries' in parallel (each has its streams).
pub fn all_effect_sizes(entries: &[ReportEntry<'_>]) -> Vec<Vec<Option<RatioCi>>> {
    entries
        .par_iter()
        .enumerate()
        .map(|(k, e)| effect_sizes(e, k))
        .collect()
}

/// Every arm's effect size against its experiment's reference arm, from
/// [`all_effect_sizes`].
pub fn effects_table(entries: &[ReportEntry<'_>], effects: &[Vec<Option<RatioCi>>]) -> String {
    let mut out = String::from(
        "| Experiment | Arm | Behaviors evaluated ÷ reference's | 95% CI (paired bootstrap) |\n",
    );
    out.push_str("|---|---|---:|---:|\n");
    for (e, effects) in entries.iter().zip(effects) {
        for (arm, effect) in e.result.arms.iter().zip(effects.iter().copied()) {
            let (ratio, ci) = match effect {
                Some(r) => (
                    format!("{:.2}", r.ratio),
                    format!("{:.2} to {:.2}", r.low, r.high),
                ),
                None if arm.name == e.reference => ("1 (reference)".to_owned(), "—".to_owned()),
                None => ("—".to_owned(), "—".to_owned()),
            };
            let _ = writeln!(out, "| {} | {} | {ratio} | {ci} |", e.result.name, arm.name);
        }
    }
    out
}

/// Each arm of `e` against its reference arm ([`ReportEntry::reference`]): paired tests
/// of the behaviors evaluated per trial; `None` for the reference itself, and for every
/// arm when the reference is not among them.
pub fn versus_reference(e: &ReportEntry<'_>) -> Vec<Option<PairedTests>> {
    against_reference(e, |_, counts, base| PairedTests {
        t_test_p: paired_t_test(base, counts).unwrap_or(1.0),
        wilcoxon_p: wilcoxon_signed_rank(base, counts).unwrap_or(1.0),
    })
}

pub use crate::plot::category_label;

/// Runs per cell of the landscapes behind the final behaviors, by default: the standard
/// error of a completion share is at most 0.035.
pub const FINALS_LANDSCAPE_RUNS: u32 = 200;

/// The pairs of components the final behaviors are drawn over, across then up: the first
/// two, the next two, ..., the last two when their number is odd (none for a space of one
/// component).
pub fn component_pairs(space: &BehaviorSpace) -> Vec<(usize, usize)> {
    let n = space.components().len();
    (0..n / 2)
        .map(|k| (2 * k, 2 * k + 1))
        .chain((n % 2 == 1 && n > 1).then(|| (n - 2, n - 1)))
        .collect()
}

/// The landscapes of experiment number `experiment` (its place in the report) for its
/// [`ReportEntry::landscapes`]: one per pair of [`component_pairs`], the other components
/// drawn at random, `runs` per cell (at least 1), each run judged by one of
/// `operators` (those the experiment's trials draw from; one per run when there are
/// several, so the landscape is their mean). Pair `p` draws from the seed
/// `stream_seed(seed, experiment, p, Landscape)`. `progress()` is called after each cell.
pub fn finals_landscapes<D: Domain>(
    domain: &D,
    operators: &[&D::Operator],
    experiment: u64,
    seed: u64,
    runs: u32,
    progress: &(dyn Fn() + Sync),
) -> Result<Vec<Landscape>, landscape::LandscapeError> {
    component_pairs(domain.space())
        .into_iter()
        .enumerate()
        .map(|(p, (x, y))| {
            let seed = stream_seed(seed, experiment, p as u64, Purpose::Landscape);
            landscape::estimate(domain, operators, &[x, y], runs, seed, progress)
        })
        .collect()
}

/// Why the report could not be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReportError {
    /// A file or folder could not be written.
    #[error(transparent)]
    Io(#[from] FileError),
    /// A plot could not be drawn.
    #[error(transparent)]
    Plot(#[from] PlotError),
}

/// Trials averaged by the moving average of the learning-curve plots.
const MOVING_AVERAGE_WINDOW: usize = 25;

/// Where the report came from: the tool, its version and commit, and the command line.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Provenance {
    /// The program that wrote the report.
    pub tool: String,
    /// Its version.
    pub version: String,
    /// The source commit it was built from, when known.
    pub git_commit: Option<String>,
    /// The command line, program first.
    pub command_line: Vec<String>,
}

/// `mean ± ci95`, with the trials cut off by `max_commands` counted beside it.
fn mean_cell(mean: &MeanCi, truncated: usize) -> String {
    let cell = format!("{:.2} ± {:.2}", mean.mean, mean.ci95);
    match truncated {
        0 => cell,
        n => format!("{cell} ({n} cut off)"),
    }
}

/// The paper's Table 1: behaviors evaluated per trial (mean ± 95% CI) by the first two arms
/// of every experiment (random walk and case-based in the default suite), the cases the
/// second acquired and the paired t-test between them, as printed and at the top of
/// `table.md`. Its rows fit 100 columns.
pub fn table(entries: &[ReportEntry<'_>]) -> String {
    let Some(first) = entries.first() else {
        return String::new();
    };
    let names: Vec<&str> = first
        .result
        .arms
        .iter()
        .take(2)
        .map(|a| a.name.as_str())
        .collect();
    let mut out = String::from("| Scenario | Operator | Trials |");
    for name in &names {
        let _ = write!(out, " {name} |");
    }
    if names.len() > 1 {
        out.push_str(" Cases acquired | Paired t-test p |");
    }
    out.push('\n');
    out.push_str("|---|---|---:|");
    out.push_str(&"---:|".repeat(names.len() + if names.len() > 1 { 2 } else { 0 }));
    out.push('\n');
    for e in entries {
        let _ = write!(
            out,
            "| {} | {} | {} |",
            e.scenario,
            e.operator,
            e.result.trials()
        );
        for arm in e.result.arms.iter().take(2) {
            let _ = write!(out, " {} |", mean_cell(&arm.behaviors, arm.truncated()));
        }
        if let Some(second) = e.result.arms.get(1) {
            let p = second.versus_first.map_or(1.0, |t| t.t_test_p);
            let _ = write!(out, " {} | {} |", second.cases_acquired, format_p(p));
        }
        out.push('\n');
    }
    out
}

/// One line per experiment, fit for a terminal: the arm that needed the fewest behaviors,
/// against the first arm.
pub fn best_arms(entries: &[ReportEntry<'_>]) -> String {
    let mut out = String::new();
    for e in entries {
        let (Some(first), Some(best)) = (
            e.result.arms.first(),
            e.result
                .arms
                .iter()
                .min_by(|a, b| a.behaviors.mean.total_cmp(&b.behaviors.mean)),
        ) else {
            continue;
        };
        let _ = writeln!(
            out,
            "{}: fewest behaviors {} ({:.2} ± {:.2}; {}: {:.2})",
            e.result.name,
            best.name,
            best.behaviors.mean,
            best.behaviors.ci95,
            first.name,
            first.behaviors.mean
        );
    }
    out
}

/// Whether every trial of every arm ended on a behavior found trustworthy, as in the
/// paper's experiments, where some behavior always pleases the operator: a column of 100%
/// in every row says nothing, so the tables leave it out and say so once.
fn every_trial_found(entries: &[ReportEntry<'_>]) -> bool {
    entries
        .iter()
        .flat_map(|e| &e.result.arms)
        .all(|arm| arm.found_share.mean >= 1.0)
}

/// The sentence that stands for the share found trustworthy when [`every_trial_found`].
fn found_note(entries: &[ReportEntry<'_>]) -> &'static str {
    if every_trial_found(entries) {
        "Every trial of every arm ended on a behavior found trustworthy (100%), so the table leaves out that column.\n"
    } else {
        ""
    }
}

/// Every arm of every experiment: what it costs the operator, and the paired tests of
/// its behaviors evaluated against the experiment's reference arm (marked). The share of
/// trials found trustworthy is a column only when some arm falls short of 100%.
pub fn arms_table(entries: &[ReportEntry<'_>]) -> String {
    let with_found = !every_trial_found(entries);
    let (found_head, found_align) = if with_found {
        (" Found trustworthy |", "---:|")
    } else {
        ("", "")
    };
    let mut out = format!(
        "| Experiment | Arm | Behaviors evaluated | Commands | Untrustworthy commands |{found_head} Cases acquired | Cut off | t-test p vs reference | Wilcoxon p vs reference |\n|---|---|---:|---:|---:|{found_align}---:|---:|---:|---:|\n"
    );
    for e in entries {
        for (arm, tests) in e.result.arms.iter().zip(versus_reference(e)) {
            let (t, w) = tests.map_or(("—".to_owned(), "—".to_owned()), |p| {
                (format_p(p.t_test_p), format_p(p.wilcoxon_p))
            });
            let mut started = match arm.starting_cases {
                0 => String::new(),
                n => format!(" (from {n} saved)"),
            };
            if arm.name == e.reference {
                started.push_str(" (reference)");
            }
            let found = if with_found {
                format!(
                    " {:.1}% ± {:.1} |",
                    100.0 * arm.found_share.mean,
                    100.0 * arm.found_share.ci95
                )
            } else {
                String::new()
            };
            let _ = writeln!(
                out,
                "| {} | {}{started} | {} | {} | {} |{found} {} | {} | {t} | {w} |",
                e.result.name,
                arm.name,
                mean_cell(&arm.behaviors, 0),
                mean_cell(&arm.commands, 0),
                mean_cell(&arm.untrustworthy, 0),
                arm.cases_acquired,
                arm.truncated(),
            );
        }
    }
    out
}

/// `93.1% (of 420)`, or `—` when nothing was counted.
fn share_cell(right: u32, of: u32) -> String {
    if of == 0 {
        "—".to_owned()
    } else {
        format!("{:.1}% (of {of})", 100.0 * f64::from(right) / f64::from(of))
    }
}

/// Every arm of every experiment: how often the first reason its explanations give for a
/// given-up behavior is the operator's most frequent true reason on it, overall, for the
/// reasons the robot perceives itself, and for the rest.
pub fn explanations_table(entries: &[ReportEntry<'_>]) -> String {
    let mut out = String::from(
        "| Experiment | Arm | Behaviors given up | First reason right | Perceivable reasons | Other reasons |\n",
    );
    out.push_str("|---|---|---:|---:|---:|---:|\n");
    for e in entries {
        for arm in &e.result.arms {
            let x = &arm.explained;
            let _ = writeln!(
                out,
                "| {} | {} | {} | {} | {} | {} |",
                e.result.name,
                arm.name,
                x.given_up,
                share_cell(x.right, x.given_up),
                share_cell(x.perceivable_right, x.perceivable),
                share_cell(x.right - x.perceivable_right, x.given_up - x.perceivable),
            );
        }
    }
    out
}

/// The explanations each arm kept whole ([`ArmResult::samples`]) as sentences, with the
/// operator's most frequent true reason.
pub fn sample_explanations(e: &ReportEntry<'_>) -> Vec<(String, Vec<String>)> {
    e.result
        .arms
        .iter()
        .map(|arm| {
            let samples = arm
                .samples
                .iter()
                .map(|x| {
                    format!(
                        "trial {}: {} (the operator's most frequent true reason: {})",
                        x.trial,
                        x.explanation.sentence(e.space),
                        x.truth.map_or("none".to_owned(), |c| c.to_string())
                    )
                })
                .collect();
            (arm.name.clone(), samples)
        })
        .collect()
}

/// What the limit's row calls it: a lower bound for a population.
fn limit_label(limit: &ExperimentLimit) -> String {
    if limit.is_lower_bound() {
        format!(
            "known-operator limit (lower bound: mean of {} operators)",
            limit.operators
        )
    } else {
        "known-operator limit".to_owned()
    }
}

/// Each arm's cost as a multiple of the limit's (the paper's protocol: a random first
/// behavior).
fn ratios(arm: &ArmResult, limit: &Costs) -> [f64; 3] {
    [
        arm.behaviors.mean / limit.behaviors,
        arm.commands.mean / limit.commands,
        arm.untrustworthy.mean / limit.untrustworthy,
    ]
}

/// A ratio to the limit, `—` when the limit is 0 (nothing to divide by).
fn ratio_cell(ratio: f64) -> String {
    if ratio.is_finite() {
        format!("{ratio:.2}")
    } else {
        "—".to_owned()
    }
}

/// Every arm against the known-operator limit of its experiment: the limit (an agent that
/// knows the operator's outcome distribution of every behavior, starting from the
/// paper's random behavior; and free to choose its first), then each arm's behaviors,
/// commands and untrustworthy commands as multiples of the limit's. Experiments without a
/// limit are left out; empty when none has one.
pub fn limit_table(entries: &[ReportEntry<'_>]) -> String {
    let mut out = String::new();
    for e in entries {
        let Some(limit) = e.limit else {
            continue;
        };
        if out.is_empty() {
            out.push_str(
                "| Experiment | Arm or limit | Behaviors | Commands | Untrustworthy commands |\n",
            );
            out.push_str("|---|---|---:|---:|---:|\n");
        }
        let (paper, free) = (limit.limit.paper, limit.limit.free_first);
        let _ = writeln!(
            out,
            "| {} | {}, random first behavior | {:.2} | {:.1} | {:.1} |",
            e.result.name,
            limit_label(limit),
            paper.behaviors,
            paper.commands,
            paper.untrustworthy
        );
        let _ = writeln!(
            out,
            "| {} | the same, free to choose its first | {:.2} | {:.1} | {:.1} |",
            e.result.name, free.behaviors, free.commands, free.untrustworthy
        );
        for arm in &e.result.arms {
            let [b, c, u] = ratios(arm, &paper);
            let _ = writeln!(
                out,
                "| {} | {} (× limit) | {} | {} | {} |",
                e.result.name,
                arm.name,
                ratio_cell(b),
                ratio_cell(c),
                ratio_cell(u)
            );
        }
    }
    out
}

/// Whether an experiment has an arm that starts each episode from the case memory's guess.
fn has_learned_start(e: &ReportEntry<'_>) -> bool {
    e.result.arms.iter().any(|a| a.initial == Initial::Learned)
}

/// Every arm of each experiment that has one starting from the case memory's guess
/// ([`Initial::Learned`]), against the known-operator limit free to choose its first
/// behavior (the paper's limit assumes a random first behavior, which such an arm does not
/// take): the limit, then each arm's behaviors, commands and untrustworthy commands (mean
/// ± 95% CI) with their multiples of the limit's where it is not 0. Empty when no such
/// experiment has a limit.
pub fn free_first_table(entries: &[ReportEntry<'_>]) -> String {
    let mut out = String::new();
    for e in entries.iter().filter(|e| has_learned_start(e)) {
        let Some(limit) = e.limit else {
            continue;
        };
        if out.is_empty() {
            out.push_str(
                "| Experiment | Arm or limit | Behaviors | Commands | Untrustworthy commands |\n",
            );
            out.push_str("|---|---|---:|---:|---:|\n");
        }
        let free = limit.limit.free_first;
        let _ = writeln!(
            out,
            "| {} | {}, free to choose its first behavior | {:.2} | {:.1} | {:.1} |",
            e.result.name,
            limit_label(limit),
            free.behaviors,
            free.commands,
            free.untrustworthy
        );
        for arm in &e.result.arms {
            let [b, c, u] = ratios(arm, &free);
            let cell = |mean: &MeanCi, ratio: f64| {
                let cell = mean_cell(mean, 0);
                if ratio.is_finite() {
                    format!("{cell} ({ratio:.2} ×)")
                } else {
                    cell
                }
            };
            let _ = writeln!(
                out,
                "| {} | {} | {} | {} | {} |",
                e.result.name,
                arm.name,
                cell(&arm.behaviors, b),
                cell(&arm.commands, c),
                cell(&arm.untrustworthy, u)
            );
        }
    }
    out
}

/// How much each experiment's operators disagree, measured on their trustworthy regions
/// (the landscapes behind the limit): the behaviors each trusts, those all trust, the
/// pairwise Jaccard index, whether one behavior pleases everyone. Empty when no experiment
/// has a limit.
pub fn population_table(entries: &[ReportEntry<'_>]) -> String {
    let mut out = String::new();
    for e in entries {
        let Some(limit) = e.limit else {
            continue;
        };
        if out.is_empty() {
            out.push_str("| Experiment | Operators | Trusted by each | Trusted by all | Jaccard (pairs) | One behavior pleases all |\n");
            out.push_str("|---|---:|---|---:|---|---|\n");
        }
        let c = &limit.conflict;
        let each: Vec<String> = c.trusted_by_each.iter().map(usize::to_string).collect();
        let jaccard = match (
            c.jaccard.iter().copied().reduce(f64::min),
            c.jaccard.iter().copied().reduce(f64::max),
        ) {
            (Some(lo), Some(hi)) if hi - lo < 0.005 => format!("{lo:.2}"),
            (Some(lo), Some(hi)) => format!("{lo:.2} to {hi:.2}"),
            _ => "—".to_owned(),
        };
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} ({:.1}%) | {jaccard} | {} |",
            e.result.name,
            limit.operators,
            each.join(", "),
            c.trusted_by_all,
            100.0 * c.shared_share(),
            if c.trusted_by_all > 0 { "yes" } else { "no" }
        );
    }
    out
}

fn format_p(p: f64) -> String {
    if p < 1e-4 {
        format!("{p:.1e}")
    } else {
        format!("{p:.4}")
    }
}

/// The `summary.json` document.
pub fn summary(entries: &[ReportEntry<'_>], elapsed_s: f64, provenance: &Provenance) -> Value {
    summary_of(entries, &all_effect_sizes(entries), elapsed_s, provenance)
}

/// The `summary.json` document, with the effect sizes already estimated.
fn summary_of(
    entries: &[ReportEntry<'_>],
    effects: &[Vec<Option<RatioCi>>],
    elapsed_s: f64,
    provenance: &Provenance,
) -> Value {
    let experiments: Vec<Value> = entries
        .iter()
        .zip(effects)
        .map(|(e, effects)| {
            let mut strategies = Map::new();
            for ((arm, tests), effect) in e
                .result
                .arms
                .iter()
                .zip(versus_reference(e))
                .zip(effects.iter().copied())
            {
                let mut summary = arm_summary(arm);
                summary["behaviors_ratio_to_reference"] = effect.map_or(Value::Null, |r| {
                    json!({ "ratio": r.ratio, "ci95_low": r.low, "ci95_high": r.high })
                });
                summary["t_test_p_vs_reference"] = json!(tests.map(|t| t.t_test_p));
                summary["wilcoxon_p_vs_reference"] = json!(tests.map(|t| t.wilcoxon_p));
                let ratio_json = |[b, c, u]: [f64; 3]| {
                    json!({
                        "behaviors": finite_or_null(b),
                        "commands": finite_or_null(c),
                        "untrustworthy": finite_or_null(u),
                    })
                };
                if let Some(limit) = e.limit {
                    summary["ratio_to_limit"] = ratio_json(ratios(arm, &limit.limit.paper));
                }
                // Only where an arm starts from the memory's guess, so that other reports
                // stay as they were.
                if arm.initial == Initial::Learned {
                    summary["initial"] = json!(arm.initial);
                    if let Some(limit) = e.limit {
                        summary["ratio_to_free_first_limit"] =
                            ratio_json(ratios(arm, &limit.limit.free_first));
                    }
                }
                strategies.insert(arm.name.clone(), summary);
            }
            let limit = e.limit.map(|l| {
                let costs = |c: &Costs| {
                    json!({
                        "behaviors": c.behaviors,
                        "commands": c.commands,
                        "untrustworthy": c.untrustworthy,
                    })
                };
                let conflict = &l.conflict;
                json!({
                    "paper_protocol": costs(&l.limit.paper),
                    "free_first_choice": costs(&l.limit.free_first),
                    "operators": l.operators,
                    "lower_bound": l.is_lower_bound(),
                    "population": {
                        "behaviors": conflict.behaviors,
                        "trusted_by_each": conflict.trusted_by_each,
                        "trusted_by_all": conflict.trusted_by_all,
                        "trusted_by_all_share": conflict.shared_share(),
                        "one_behavior_pleases_all": conflict.trusted_by_all > 0,
                        "pairwise_jaccard": conflict.jaccard,
                    },
                })
            });
            json!({
                "name": e.result.name,
                "scenario": e.scenario,
                "operator": e.operator,
                "trials": e.result.trials(),
                "arms": e.result.arms.iter().map(|a| a.name.as_str()).collect::<Vec<_>>(),
                "reference": e.reference,
                "p_value": e.result.arms.get(1).and_then(|a| a.versus_first).map_or(1.0, |t| t.t_test_p),
                "strategies": strategies,
                "limit": limit,
            })
        })
        .collect();
    json!({ "provenance": provenance, "elapsed_s": elapsed_s, "experiments": experiments })
}

/// A number for JSON, `null` when it is not finite.
fn finite_or_null(x: f64) -> Value {
    if x.is_finite() { json!(x) } else { Value::Null }
}

fn arm_summary(arm: &ArmResult) -> Value {
    json!({
        "mean": arm.behaviors.mean,
        "ci95": arm.behaviors.ci95,
        "commands_mean": arm.commands.mean,
        "commands_ci95": arm.commands.ci95,
        "untrustworthy_mean": arm.untrustworthy.mean,
        "untrustworthy_ci95": arm.untrustworthy.ci95,
        "found_share": arm.found_share.mean,
        "found_share_ci95": arm.found_share.ci95,
        "cases_acquired": arm.cases_acquired,
        "reuses_cases": arm.reuses_cases,
        "started_from_cases": arm.starting_cases,
        "truncated": arm.truncated(),
        "t_test_p_vs_first": arm.versus_first.map(|t| t.t_test_p),
        "wilcoxon_p_vs_first": arm.versus_first.map(|t| t.wilcoxon_p),
        "explanations": explanation_summary(&arm.explained),
    })
}

/// How an arm's explanations compare with the truth, for `summary.json`: behaviors given
/// up and the share whose first attributed reason was right, overall, for perceivable
/// reasons and for the rest (`null` where none was counted).
fn explanation_summary(x: &ExplanationCheck) -> Value {
    let [all, perceivable, rest] = x.shares();
    json!({
        "given_up": x.given_up,
        "first_reason_right": all,
        "perceivable": { "given_up": x.perceivable, "first_reason_right": perceivable },
        "other": { "given_up": x.given_up - x.perceivable, "first_reason_right": rest },
    })
}

#[derive(Serialize)]
struct TrialLine<'a> {
    experiment: &'a str,
    scenario: &'a str,
    operator: &'a str,
    arm: &'a str,
    trial: u32,
    behaviors_evaluated: u64,
    commands: u64,
    untrustworthy: u64,
    found_trustworthy: bool,
    #[serde(rename = "final")]
    final_behavior: Map<String, Value>,
    initial: Map<String, Value>,
    /// Whether the initial behavior was the case memory's guess (left out when not).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    learned_start: bool,
    searched: u32,
    reused: u32,
    retained: bool,
    truncated: bool,
    /// The operator's true reasons for the untrustworthy commands (evaluation only).
    true_causes: &'a BTreeMap<Cause, u32>,
    /// Every behavior given up: the reason its explanation settled on, the most frequent
    /// true reason (evaluation only), and whether it was right.
    given_up: Vec<GivenUpLine>,
}

/// A given-up behavior in `trials.jsonl` (how the next behavior was chosen is counted by
/// the line's `searched` and `reused`; a trial is told whole by `trustcbr explain`).
#[derive(Serialize)]
struct GivenUpLine {
    reason: Option<Cause>,
    truth: Option<Cause>,
    right: bool,
}

impl From<&GivenUpRecord> for GivenUpLine {
    fn from(record: &GivenUpRecord) -> Self {
        Self {
            reason: record.reason,
            truth: record.truth,
            right: record.right,
        }
    }
}

/// `trials.jsonl`: one JSON object per trial, experiments in order, arms in order.
pub fn trials_jsonl(entries: &[ReportEntry<'_>]) -> String {
    let mut out = String::new();
    for e in entries {
        for arm in &e.result.arms {
            for t in &arm.trials {
                let line = trial_line(e, t);
                out.push_str(&serde_json::to_string(&line).expect("plain data serializes"));
                out.push('\n');
            }
        }
    }
    out
}

fn trial_line<'a>(e: &'a ReportEntry<'_>, t: &'a TrialRecord) -> TrialLine<'a> {
    TrialLine {
        experiment: &e.result.name,
        scenario: e.scenario,
        operator: &t.operator,
        arm: &t.arm,
        trial: t.trial,
        behaviors_evaluated: t.report.behaviors_evaluated,
        commands: t.report.commands,
        untrustworthy: t.report.untrustworthy,
        found_trustworthy: t.report.found_trustworthy,
        final_behavior: named_behavior(e.space, &t.report.settled),
        initial: named_behavior(e.space, &t.initial),
        learned_start: t.learned_start,
        searched: t.report.searched,
        reused: t.report.reused,
        retained: t.report.retained.is_some(),
        truncated: t.truncated,
        true_causes: &t.true_causes,
        given_up: t.given_up.iter().map(GivenUpLine::from).collect(),
    }
}

/// A file-name stem per name (experiment names): every character outside
/// `[A-Za-z0-9_-]` replaced by `-`, and `-2`, `-3`, ... added where two would collide.
pub fn file_stems(names: impl IntoIterator<Item = impl AsRef<str>>) -> Vec<String> {
    let mut stems: Vec<String> = Vec::new();
    for name in names {
        let base: String = name
            .as_ref()
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                    c
                } else {
                    '-'
                }
            })
            .collect();
        let mut stem = base.clone();
        let mut k = 2;
        while stems.contains(&stem) {
            stem = format!("{base}-{k}");
            k += 1;
        }
        stems.push(stem);
    }
    stems
}

/// The title of [`free_first_table`]'s section.
const FREE_FIRST_TITLE: &str = "Arms that may start from the case memory's guess, against the known-operator limit free to choose its first behavior";

/// Writes the whole report into `dir` (created if needed): `table.md`, `summary.json`,
/// `trials.jsonl`, `config.ron` (the text given) and the plots. Returns the files written.
pub fn write_report(
    dir: &Path,
    entries: &[ReportEntry<'_>],
    config_ron: &str,
    elapsed_s: f64,
    provenance: &Provenance,
) -> Result<Vec<PathBuf>, ReportError> {
    let mut written = Vec::new();
    let mut write = |name: &str, text: &str| -> Result<(), ReportError> {
        written.push(write_file_in(dir, name, text)?);
        Ok(())
    };
    let effects = all_effect_sizes(entries);
    let limits = limit_table(entries);
    let free_first = free_first_table(entries);
    let limits = if limits.is_empty() {
        String::new()
    } else {
        format!(
            "\n## Against the known-operator limit (the paper's protocol: a random first behavior)\n\n{limits}{}\n## How much each experiment's operators disagree (their trustworthy regions)\n\n{}",
            if free_first.is_empty() {
                String::new()
            } else {
                format!("\n## {FREE_FIRST_TITLE}\n\n{free_first}")
            },
            population_table(entries)
        )
    };
    write(
        "table.md",
        &format!(
            "## Behaviors evaluated per trial (mean ± 95% CI): the paper's two arms\n\n{}\n## Every arm: what it costs the operator (p-values against the reference arm, {})\n\n{}{}\n## Effect sizes against the reference arm\n\n{}{limits}\n## Explanations against the truth: is the first reason given for a behavior given up the operator's most frequent true reason?\n\n{}",
            table(entries),
            entries.first().map_or("", |e| e.reference),
            arms_table(entries),
            found_note(entries),
            effects_table(entries, &effects),
            explanations_table(entries)
        ),
    )?;
    let summary =
        serde_json::to_string_pretty(&summary_of(entries, &effects, elapsed_s, provenance))
            .expect("plain data serializes");
    write("summary.json", &(summary + "\n"))?;
    write("trials.jsonl", &trials_jsonl(entries))?;
    write("config.ron", config_ron)?;
    // Every figure is written as its own SVG file and the same text goes into the page.
    let mut figures: Vec<Figure> = Vec::new();
    for metric in SUMMARY_METRICS {
        let name = format!("{}.svg", metric.stem);
        let summary_svg = svg_with(&dir.join(&name), (1200, 560), |area, overlay| {
            every_arm_figure(area, overlay, entries, &summary_figure(entries, metric))
        })?;
        write(&name, &summary_svg)?;
        figures.push(Figure::new(
            "Every experiment and arm",
            summary_svg,
            format!(
                "{}: the mean per trial of each arm (its marker, offset within its \
                 experiment; key at the right) with its 95% confidence interval (the vertical \
                 line), one column per experiment, on a log axis (lower is better). The black \
                 bar is the known-operator limit: an agent that knows the operator's outcome \
                 distribution of every behavior, starting from a random behavior as the arms do.",
                metric.what
            ),
        ));
    }
    let reference = entries.first().map_or("", |e| e.reference);
    let effects_figure = EveryArm {
        title: format!("Behaviors evaluated per trial as a ratio to {reference}'s (95% CI)"),
        axis: "ratio to the reference arm (log scale)",
        values: effects
            .iter()
            .map(|effects| {
                effects
                    .iter()
                    .map(|r| {
                        r.map(|r| Interval {
                            mid: r.ratio,
                            low: r.low,
                            high: r.high,
                        })
                    })
                    .collect()
            })
            .collect(),
        bars: vec![Some(1.0); entries.len()],
        bar_key: format!("{reference} (the reference) = 1"),
    };
    let name = "effect-sizes.svg";
    let drawn = svg_with(&dir.join(name), (1200, 560), |area, overlay| {
        every_arm_figure(area, overlay, entries, &effects_figure)
    })?;
    write(name, &drawn)?;
    figures.push(Figure::new(
        "Every experiment and arm",
        drawn,
        format!(
            "Effect sizes: each arm's mean behaviors evaluated per trial divided by the \
             reference arm's ({}; the black bar at 1), with the 95% interval of a paired \
             bootstrap ({BOOTSTRAP_RESAMPLES} resamples of the trials, the same trials for both \
             arms), on a log axis. Below 1 the arm needs fewer behaviors than the reference; \
             an interval that crosses 1 is no evidence of a difference.",
            escape(reference)
        ),
    ));
    let over_trials = [
        (
            "untrustworthy-over-trials.svg",
            Panels {
                title: "Untrustworthy commands summed over the trials so far".to_owned(),
                x_axis: "trial",
                y_axis: "untrustworthy commands so far",
                log_x: false,
                series: per_trial_lines(entries, |_| true, cumulative_untrustworthy),
            },
            "What the operator has endured: the commands that failed or that it interrupted, \
             summed from the first trial on, one panel per experiment and one line per arm \
             (its marker at the end). A steeper line costs the operator more per trial; a line \
             that bends flatter has learned.",
        ),
        (
            "case-base-over-trials.svg",
            Panels {
                title: "Cases in the base of each arm that reuses cases, after each trial"
                    .to_owned(),
                x_axis: "trial",
                y_axis: "cases",
                log_x: false,
                series: per_trial_lines(entries, |a| a.reuses_cases, case_base_sizes),
            },
            "The case base of each arm that reuses cases (Algorithm 1), trial by trial: the \
             cases it started from, plus one for each trial whose behavior is retained. It \
             levels off once the base covers the situations the operators bring.",
        ),
        (
            "reuse-over-trials.svg",
            Panels {
                title: format!(
                    "Share of adaptations taken from a case (moving average of {MOVING_AVERAGE_WINDOW} trials)"
                ),
                x_axis: "trial",
                y_axis: "share from a case",
                log_x: false,
                series: per_trial_lines(entries, |a| a.reuses_cases, reuse_rates),
            },
            "How often an arm that reuses cases took its next behavior from a stored case \
             rather than from its search, per trial and averaged over the last 25 trials: it \
             rises as the base fills, and stays low where the stored cases seldom fit.",
        ),
        (
            "distributions.svg",
            Panels {
                title: "Behaviors evaluated per trial: each arm's distribution".to_owned(),
                x_axis: "behaviors evaluated (log scale)",
                y_axis: "share of trials",
                log_x: true,
                series: entries
                    .iter()
                    .map(|e| {
                        e.result
                            .arms
                            .iter()
                            .map(|a| Some(ecdf(a.counts())))
                            .collect()
                    })
                    .collect(),
            },
            "Each arm's distribution of behaviors evaluated per trial (the empirical \
             cumulative distribution): across, a number of behaviors (log scale); up, the share \
             of trials that needed at most that many. Further up and left is better; a long \
             tail to the right, which a mean and its CI hide, shows here.",
        ),
    ];
    // A figure with no line at all (no arm reuses cases) is left out.
    for (name, panels, caption) in over_trials {
        if panels.series.iter().flatten().all(Option::is_none) {
            continue;
        }
        let drawn = svg_with(&dir.join(name), panels.size(), |area, overlay| {
            small_multiples(area, overlay, entries, &panels)
        })?;
        write(name, &drawn)?;
        figures.push(Figure::new(
            "Every experiment and arm",
            drawn,
            caption.to_owned(),
        ));
    }
    for (e, stem) in entries
        .iter()
        .zip(file_stems(entries.iter().map(|e| &e.result.name)))
    {
        let name = format!("curves-{stem}.svg");
        let curves = |dots: bool| {
            svg_with(&dir.join(&name), (1250, 520), |area, overlay| {
                learning_curves(area, overlay, e, dots)
            })
        };
        write(&name, &curves(true)?)?;
        figures.push(Figure::new(
            &e.result.name,
            curves(false)?,
            format!(
                "Behaviors evaluated in each trial, trials in order: the moving average over \
                 {MOVING_AVERAGE_WINDOW} trials (the line, with the arm's marker at eight places) \
                 and its 95% band, on a log axis (lower is better). An arm that learns across \
                 trials (a growing case base, a searcher's memory) falls as trials go on; one \
                 that does not stays level. Each trial's count is a dot in \
                 <code>{name}</code> and a line of <code>trials.jsonl</code>."
            ),
        ));
        if let Some(timeline) = e.timeline {
            let name = format!("timeline-{stem}.svg");
            let switches = timeline
                .commands
                .iter()
                .filter(|c| c.explanation.is_some())
                .count() as u32;
            let drawn = svg(&dir.join(&name), (1250, 480 + 22 * switches), |area| {
                timeline_figure(area, timeline)
            })?;
            write(&name, &drawn)?;
            figures.push(Figure::new(
                &e.result.name,
                drawn,
                timeline_caption(timeline, e.space),
            ));
        }
        // One figure per pair of components: the first two, then the next two, ...
        let components = e.space.components();
        for (k, (x, y)) in component_pairs(e.space).into_iter().enumerate() {
            let name = if k == 0 {
                format!("finals-{stem}.svg")
            } else {
                format!(
                    "finals-{stem}-{}-{}.svg",
                    components[x].name, components[y].name
                )
            };
            // The id of the heatmap every arm's panel shares, unique in the page.
            let id = format!("cells-{}", name.trim_end_matches(".svg"));
            let grid = e
                .landscapes
                .iter()
                .find(|l| l.fixed == [x, y])
                .map(|l| l.grid(e.space, x, y))
                .transpose()
                .map_err(|reason| PlotError {
                    path: dir.join(&name),
                    message: reason.to_string(),
                })?;
            let layout = FinalsLayout::new(e.result.arms.len(), &finals_subtitle(e, grid.as_ref()));
            let finals = svg_with(&dir.join(&name), layout.size(), |area, overlay| {
                final_behaviors(area, overlay, e, (x, y), grid.as_ref(), &layout, &id)
            })?;
            write(&name, &finals)?;
            figures.push(Figure::new(
                &e.result.name,
                finals,
                finals_caption(e, (x, y), grid.as_ref()),
            ));
        }
    }
    write(
        "report.html",
        &html_page(entries, &effects, config_ron, provenance, &figures),
    )?;
    Ok(written)
}

/// A figure of the page: its section, its SVG text and its caption (HTML).
struct Figure {
    section: String,
    svg: String,
    caption: String,
}

impl Figure {
    fn new(section: &str, svg: String, caption: String) -> Self {
        Self {
            section: section.to_owned(),
            svg,
            caption,
        }
    }
}

/// The caption of a timeline: how to read it, and every explanation of the trial in full.
fn timeline_caption(timeline: &Timeline, space: &BehaviorSpace) -> String {
    let mut caption = format!(
        "The trust estimate of the behavior in use after every command of trial {} of the {} arm \
         (operator {}): completions (dots) raise it, failures and interruptions (crosses) lower \
         it; a behavior is given up when its estimate reaches the untrustworthy threshold and \
         kept when it reaches the trustworthy one. The numbered lines are the adapter's decisions, \
         explained as it explained them (only from what it was told and perceived):<ol>",
        timeline.record.trial,
        escape(&timeline.arm),
        escape(&timeline.record.operator)
    );
    for c in &timeline.commands {
        if let Some(x) = &c.explanation {
            let _ = write!(caption, "<li>{}</li>", escape(&x.sentence(space)));
        }
    }
    caption.push_str("</ol>");
    caption
}

/// Escapes text for HTML.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A Markdown table as made by [`table`] and [`arms_table`], as an HTML table in a
/// container that scrolls sideways when the table is wider than the screen.
fn html_table(markdown: &str) -> String {
    let cells = |line: &str| -> Vec<String> {
        line.trim()
            .trim_matches('|')
            .split('|')
            .map(|c| escape(c.trim()))
            .collect()
    };
    let mut lines = markdown.lines().filter(|l| l.starts_with('|'));
    let mut html = String::from("<div class=\"scroll\">\n<table>\n<thead><tr>");
    if let Some(header) = lines.next() {
        for c in cells(header) {
            let _ = write!(html, "<th>{c}</th>");
        }
    }
    html.push_str("</tr></thead>\n<tbody>\n");
    for line in lines.skip(1) {
        html.push_str("<tr>");
        for c in cells(line) {
            let _ = write!(html, "<td>{c}</td>");
        }
        html.push_str("</tr>\n");
    }
    html.push_str("</tbody>\n</table>\n</div>\n");
    html
}

/// What the tables' columns mean, one line each.
const METRICS: [(&str, &str); 9] = [
    (
        "Behaviors evaluated",
        "behaviors the robot tried in a trial before settling on one the operator trusts (the paper's metric; lower is better)",
    ),
    (
        "Commands",
        "commands the operator gave in a trial until it ended",
    ),
    (
        "Untrustworthy commands",
        "commands that failed or that the operator interrupted: what the operator endured",
    ),
    (
        "Found trustworthy",
        "share of trials that ended on a behavior whose trust estimate reached the trustworthy threshold",
    ),
    (
        "Cases acquired",
        "cases retained over the experiment (an arm that reuses cases reads them in later trials)",
    ),
    (
        "Cut off",
        "trials stopped by the suite's <code>max_commands</code> before they ended",
    ),
    (
        "Mean ± CI",
        "the mean over trials and the half-width of its 95% confidence interval",
    ),
    (
        "t-test p, Wilcoxon p",
        "two-sided p-values of the paired t-test and the Wilcoxon signed-rank test of behaviors evaluated, trial by trial, against the reference arm",
    ),
    (
        "Known-operator limit",
        "the cost of an agent that knows every behavior's outcome distribution under the operator and tries them in the best order: no arm can do better on average",
    ),
];

/// The glossary: each arm of the report in one line, then the metrics.
fn glossary(entries: &[ReportEntry<'_>]) -> String {
    let mut html = String::from("<h3>Arms</h3>\n<dl>\n");
    let mut seen: Vec<&str> = Vec::new();
    for arm in entries.iter().flat_map(|e| &e.result.arms) {
        if seen.contains(&arm.name.as_str()) {
            continue;
        }
        seen.push(&arm.name);
        let what = crate::arm::describe(&arm.name).unwrap_or_else(|| {
            let what = if arm.reuses_cases {
                "an arm of the catalog's own that reuses cases"
            } else {
                "an arm of the catalog's own"
            };
            match arm.initial {
                Initial::Random => what.to_owned(),
                Initial::Learned => {
                    format!("{what}, starting each episode from the case memory's guess")
                }
            }
        });
        let _ = writeln!(
            html,
            "<dt><code>{}</code></dt><dd>{}</dd>",
            escape(&arm.name),
            escape(&what)
        );
    }
    html.push_str("</dl>\n<h3>Metrics</h3>\n<dl>\n");
    for (name, what) in METRICS {
        let _ = writeln!(html, "<dt>{name}</dt><dd>{what}</dd>");
    }
    html.push_str("</dl>\n");
    html
}

/// The page's style: readable at 800 px, tables scroll sideways in their container,
/// numbers never wrap.
const STYLE: &str = "body { font-family: sans-serif; margin: 2em auto; padding: 0 1em; max-width: 1300px; color: #222; }
table { border-collapse: collapse; margin: 1em 0; font-size: 0.9em; }
.scroll { overflow-x: auto; }
th, td { border: 1px solid #bbb; padding: 0.25em 0.6em; }
th { background: #eee; }
td { text-align: right; white-space: nowrap; }
td:first-child, td:nth-child(2) { text-align: left; white-space: normal; }
figure { margin: 1em 0 2em; }
figure svg { max-width: 100%; height: auto; }
figcaption { max-width: 60em; color: #333; }
dt { font-weight: bold; margin-top: 0.4em; }
code { overflow-wrap: anywhere; }
pre { background: #f6f6f6; padding: 1em; overflow-x: auto; }
";

/// `report.html`: one self-contained page (inline SVG and CSS, nothing fetched): a
/// contents list, the glossary, the tables, the figures (the same SVG text as the files,
/// but the learning curves without their per-trial dots) each with a caption, the config
/// and the provenance.
fn html_page(
    entries: &[ReportEntry<'_>],
    effects: &[Vec<Option<RatioCi>>],
    config_ron: &str,
    provenance: &Provenance,
    figures: &[Figure],
) -> String {
    // The sections, in order: (id, title, HTML).
    let mut sections: Vec<(String, String, String)> = Vec::new();
    let mut section = |id: &str, title: &str, html: String| {
        sections.push((id.to_owned(), title.to_owned(), html));
    };
    section("glossary", "Arms and metrics", glossary(entries));
    section(
        "paper",
        "Behaviors evaluated per trial (mean ± 95% CI): the paper's two arms",
        html_table(&table(entries)),
    );
    let reference = entries.first().map_or("", |e| e.reference);
    section(
        "arms",
        "Every arm: what it costs the operator",
        format!(
            "<p>p-values test each arm's behaviors evaluated against the reference arm, \
             <code>{}</code> (the suite's <code>reference</code>), trial by trial.</p>\n{}{}",
            escape(reference),
            html_table(&arms_table(entries)),
            match found_note(entries) {
                "" => String::new(),
                note => format!("<p>{}</p>\n", note.trim_end()),
            }
        ),
    );
    section(
        "effects",
        "Effect sizes against the reference arm",
        html_table(&effects_table(entries, effects)),
    );
    let limits = limit_table(entries);
    if !limits.is_empty() {
        section(
            "limit",
            "Against the known-operator limit (the paper's protocol: a random first behavior)",
            html_table(&limits),
        );
        let free_first = free_first_table(entries);
        if !free_first.is_empty() {
            section("free-first", FREE_FIRST_TITLE, html_table(&free_first));
        }
        section(
            "population",
            "How much each experiment's operators disagree (their trustworthy regions)",
            html_table(&population_table(entries)),
        );
    }
    let mut explanations = format!(
        "<p>Every behavior an arm gave up was explained from what the robot was told and perceived; the share whose first reason is the operator's most frequent true reason on that behavior (the simulator knows it; the robot does not). Perceivable reasons are those the robot perceives itself (a collision, being stuck, a detonation).</p>\n{}",
        html_table(&explanations_table(entries))
    );
    for e in entries {
        let _ = writeln!(
            explanations,
            "<details><summary>Sample explanations: {}</summary><ul>",
            escape(&e.result.name)
        );
        for (arm, samples) in sample_explanations(e) {
            for sample in samples {
                let _ = writeln!(
                    explanations,
                    "<li><b>{}</b>, {}</li>",
                    escape(&arm),
                    escape(&sample)
                );
            }
        }
        explanations.push_str("</ul></details>\n");
    }
    section(
        "explanations",
        "Explanations against the truth",
        explanations,
    );
    let mut titles: Vec<&str> = Vec::new();
    for figure in figures {
        if !titles.contains(&figure.section.as_str()) {
            titles.push(&figure.section);
        }
    }
    for (title, stem) in titles.iter().zip(file_stems(&titles)) {
        let mut html = String::new();
        for figure in figures.iter().filter(|f| f.section == *title) {
            let _ = write!(
                html,
                "<figure>\n{}\n<figcaption>{}</figcaption>\n</figure>\n",
                figure.svg, figure.caption
            );
        }
        section(&format!("figures-{stem}"), title, html);
    }
    section(
        "config",
        "Config",
        format!("<pre>{}</pre>\n", escape(config_ron)),
    );

    let mut page = format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>trustcbr report</title>\n<style>\n{STYLE}</style>\n</head>\n<body>\n<h1>Trust-guided behavior adaptation: experiment report</h1>\n"
    );
    let _ = writeln!(
        page,
        "<p>{} {}{}. Command line: <code>{}</code>.</p>",
        escape(&provenance.tool),
        escape(&provenance.version),
        provenance
            .git_commit
            .as_ref()
            .map_or(String::new(), |c| format!(
                ", commit <code>{}</code>",
                escape(c)
            )),
        escape(&provenance.command_line.join(" "))
    );
    page.push_str("<nav>\n<h2>Contents</h2>\n<ul>\n");
    for (id, title, _) in &sections {
        let _ = writeln!(page, "<li><a href=\"#{id}\">{}</a></li>", escape(title));
    }
    page.push_str("</ul>\n</nav>\n");
    for (id, title, html) in &sections {
        let _ = write!(page, "<h2 id=\"{id}\">{}</h2>\n{html}", escape(title));
    }
    page.push_str("</body>\n</html>\n");
    page
}

fn moving_average(values: &[f64], window: usize) -> Vec<f64> {
    let mut out = Vec::with_capacity(values.len());
    let mut sum = 0.0;
    for (i, v) in values.iter().enumerate() {
        sum += v;
        if i >= window {
            sum -= values[i - window];
        }
        out.push(sum / (i + 1).min(window) as f64);
    }
    out
}

/// Width of the legend strip right of a chart, in pixels.
const LEGEND_WIDTH: u32 = 250;

/// What a legend entry draws before its label.
enum Key {
    /// A line (a series drawn as a line).
    Line(RGBColor),
    /// The arm's marker (a series drawn as markers).
    Marker(ArmStyle),
    /// A line with the arm's marker on it.
    LineMarker(ArmStyle),
}

/// Draws a legend of `entries` (label, key) in `area`, top to bottom; markers go into
/// `overlay`.
fn legend(area: &Area<'_>, overlay: &mut Overlay, entries: &[(String, Key)]) -> DrawResult {
    let (left, top) = area.get_base_pixel();
    for (k, (label, key)) in entries.iter().enumerate() {
        let y = 60 + 22 * k as i32;
        let (line, marker) = match key {
            Key::Line(color) => (Some(*color), None),
            Key::Marker(style) => (None, Some(style)),
            Key::LineMarker(style) => (Some(style.color), Some(style)),
        };
        if let Some(color) = line {
            area.draw(&PathElement::new(
                vec![(8, y), (32, y)],
                color.stroke_width(3),
            ))?;
        }
        if let Some(style) = marker {
            let at = (f64::from(left + 20), f64::from(top + y));
            overlay.markers(
                style.shape,
                Some((style.color, 1.0)),
                Some((WHITE, 1.0)),
                [(at, 5.0)],
            );
        }
        area.draw(&Text::new(
            label.clone(),
            (40, y - 7),
            ("sans-serif", 13).into_font(),
        ))?;
    }
    Ok(())
}

/// Points a curve of `n` trials is drawn through: at most `points` (and the last),
/// evenly spaced, the first and the last always (a moving average of
/// [`MOVING_AVERAGE_WINDOW`] changes little from one trial to the next).
fn thinned(n: usize, points: usize) -> impl Iterator<Item = usize> {
    let step = n.div_ceil(points).max(1);
    (0..n)
        .step_by(step)
        .chain((n > 0 && !(n - 1).is_multiple_of(step)).then(|| n - 1))
}

/// At most this many points per learning curve (and one more: the last).
const CURVE_POINTS: usize = 200;

/// At most this many points per curve of a panel of [`small_multiples`].
const PANEL_POINTS: usize = 100;

/// The points of a line, in data units.
type Line = Vec<(f64, f64)>;

/// A figure of one panel per experiment (four a row), one line per arm, the legend at the
/// right.
struct Panels {
    title: String,
    x_axis: &'static str,
    y_axis: &'static str,
    /// Whether the x axis is logarithmic (the x values must then be positive).
    log_x: bool,
    /// Per experiment, per arm: the line's points (`None`: the arm is not drawn).
    series: Vec<Vec<Option<Line>>>,
}

impl Panels {
    /// Size of one panel (px).
    const PANEL: (u32, u32) = (300, 260);

    fn size(&self) -> (u32, u32) {
        let n = self.series.len().max(1);
        let columns = n.min(4) as u32;
        (
            Self::PANEL.0 * columns + LEGEND_WIDTH,
            50 + Self::PANEL.1 * n.div_ceil(4) as u32,
        )
    }
}

/// Per experiment, per arm, a line over its trials in order from `value(arm)` (one value
/// per trial), thinned to [`PANEL_POINTS`]; arms for which `drawn` is false are left out.
fn per_trial_lines(
    entries: &[ReportEntry<'_>],
    drawn: impl Fn(&ArmResult) -> bool,
    value: impl Fn(&ArmResult) -> Vec<f64>,
) -> Vec<Vec<Option<Line>>> {
    entries
        .iter()
        .map(|e| {
            e.result
                .arms
                .iter()
                .map(|arm| {
                    drawn(arm).then(|| {
                        let values = value(arm);
                        thinned(values.len(), PANEL_POINTS)
                            .map(|i| ((i + 1) as f64, values[i]))
                            .collect()
                    })
                })
                .collect()
        })
        .collect()
}

/// Untrustworthy commands summed over the trials so far, trial by trial.
fn cumulative_untrustworthy(arm: &ArmResult) -> Vec<f64> {
    arm.trials
        .iter()
        .scan(0.0, |sum, t| {
            *sum += t.report.untrustworthy as f64;
            Some(*sum)
        })
        .collect()
}

/// Cases in the arm's base after each trial: those it started from and those retained.
fn case_base_sizes(arm: &ArmResult) -> Vec<f64> {
    arm.trials
        .iter()
        .scan(arm.starting_cases as f64, |size, t| {
            *size += f64::from(u8::from(t.report.retained.is_some()));
            Some(*size)
        })
        .collect()
}

/// The share of each trial's adaptations that reused a case (0 for a trial without
/// adaptation), as a moving average of [`MOVING_AVERAGE_WINDOW`] trials.
fn reuse_rates(arm: &ArmResult) -> Vec<f64> {
    let shares: Vec<f64> = arm
        .trials
        .iter()
        .map(|t| {
            let adaptations = t.report.reused + t.report.searched;
            if adaptations == 0 {
                0.0
            } else {
                f64::from(t.report.reused) / f64::from(adaptations)
            }
        })
        .collect();
    moving_average(&shares, MOVING_AVERAGE_WINDOW)
}

/// The empirical distribution of `counts` as the steps of its cumulative share:
/// `(count, share of trials with at most that count)`, each step's foot then its top.
fn ecdf(mut counts: Vec<f64>) -> Vec<(f64, f64)> {
    counts.sort_by(f64::total_cmp);
    let n = counts.len() as f64;
    let mut steps = Vec::new();
    let mut below = 0.0;
    for (k, &c) in counts.iter().enumerate() {
        if counts.get(k + 1) != Some(&c) {
            let share = (k + 1) as f64 / n;
            steps.push((c, below));
            steps.push((c, share));
            below = share;
        }
    }
    steps
}

/// Draws `figure`: a panel per experiment, each arm's line in its colour (the paper's two
/// last) with its marker at the line's end, a shared legend at the right.
fn small_multiples(
    area: &Area<'_>,
    overlay: &mut Overlay,
    entries: &[ReportEntry<'_>],
    figure: &Panels,
) -> DrawResult {
    let (width, _) = area.dim_in_pixel();
    let (top, body) = area.split_vertically(50);
    top.draw(&Text::new(
        figure.title.as_str(),
        (10, 12),
        ("sans-serif", 20).into_font(),
    ))?;
    let (panels_area, side) = body.split_horizontally(width.saturating_sub(LEGEND_WIDTH));
    let columns = entries.len().clamp(1, 4);
    let panels = panels_area.split_evenly((entries.len().div_ceil(4).max(1), columns));
    let names: Vec<&str> = entries
        .first()
        .map(|e| e.result.arms.iter().map(|a| a.name.as_str()).collect())
        .unwrap_or_default();
    let scale = |v: f64| if figure.log_x { v.max(1e-9).log10() } else { v };
    for ((panel, e), series) in panels.iter().zip(entries).zip(&figure.series) {
        let points = || series.iter().flatten().flatten();
        let (mut x0, mut x1) = points().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.0), b.max(p.0))
        });
        // Plotters never ends placing ticks on an empty or infinite range.
        if !x0.is_finite() {
            (x0, x1) = (1.0, 2.0);
        } else if x1 <= x0 {
            x1 = x0 + 1.0;
        }
        if figure.log_x {
            (x0, x1) = (x0 * 0.9, x1 * 1.1);
        }
        let y1 = match points().map(|p| p.1).fold(0.0f64, f64::max) {
            most if most > 0.0 => most * 1.05,
            _ => 1.0,
        };
        let mut chart = ChartBuilder::on(panel)
            .caption(&e.result.name, ("sans-serif", 14))
            .margin(8)
            .margin_right(14)
            .x_label_area_size(36)
            .y_label_area_size(48)
            .build_cartesian_2d(scale(x0)..scale(x1), 0.0..y1)?;
        let mut mesh = chart.configure_mesh();
        mesh.light_line_style(TRANSPARENT)
            .x_label_formatter(&tick_label)
            .y_label_formatter(&tick_label)
            .label_style(("sans-serif", 11))
            .axis_desc_style(("sans-serif", 12))
            .x_desc(figure.x_axis)
            .y_desc(figure.y_axis)
            .y_labels(5);
        // A log axis is drawn in log10 units: its ticks and labels are placed by hand.
        mesh.x_labels(if figure.log_x { 0 } else { 5 });
        mesh.draw()?;
        if figure.log_x {
            let at: Vec<(f64, (f64, f64))> = log_ticks(x0, x1, 220)
                .into_iter()
                .map(|t| {
                    let (px, py) = chart.backend_coord(&(scale(t), 0.0));
                    (t, (f64::from(px), f64::from(py)))
                })
                .collect();
            overlay.segments(
                BLACK,
                1.0,
                at.iter().map(|&(_, (x, y))| ((x, y), (x, y + 5.0))),
            );
            overlay.texts(
                11,
                at.iter()
                    .map(|&(t, (x, y))| ((x, y + 12.0), BLACK, tick_label(&t))),
            );
        }
        for a in drawing_order(&names) {
            let Some(Some(line)) = series.get(a) else {
                continue;
            };
            let style = arm_style(names[a], a);
            chart.draw_series(LineSeries::new(
                line.iter().map(|&(x, y)| (scale(x), y)),
                style.color.stroke_width(2),
            ))?;
            if let Some(&(x, y)) = line.last() {
                let (px, py) = chart.backend_coord(&(scale(x), y));
                overlay.markers(
                    style.shape,
                    Some((style.color, 1.0)),
                    Some((WHITE, 1.0)),
                    [((f64::from(px), f64::from(py)), 4.0)],
                );
            }
        }
    }
    let drawn: Vec<(String, Key)> = names
        .iter()
        .enumerate()
        .filter(|&(a, _)| {
            figure
                .series
                .iter()
                .any(|s| matches!(s.get(a), Some(Some(_))))
        })
        .map(|(a, name)| ((*name).to_owned(), Key::LineMarker(arm_style(name, a))))
        .collect();
    legend(&side, overlay, &drawn)
}

/// The 95% confidence band of the moving average: mean ± t * sd / sqrt(n) over the same
/// window, per trial.
fn moving_band(values: &[f64], window: usize) -> Vec<(f64, f64)> {
    (0..values.len())
        .map(|i| {
            let from = (i + 1).saturating_sub(window);
            let m = mean_ci95(&values[from..=i]).expect("a non-empty window");
            (m.mean - m.ci95, m.mean + m.ci95)
        })
        .collect()
}

/// The learning curves of an experiment: each arm's moving average of behaviors
/// evaluated with its 95% band, and each trial's count as a faint dot when `dots` (the
/// SVG file has them, the page does not: they are most of its weight).
fn learning_curves(
    area: &Area<'_>,
    overlay: &mut Overlay,
    e: &ReportEntry<'_>,
    dots: bool,
) -> DrawResult {
    let trials = e.result.trials().max(1) as u32;
    let top = e
        .result
        .arms
        .iter()
        .flat_map(|s| s.trials.iter().map(|t| t.report.behaviors_evaluated))
        .max()
        .unwrap_or(1)
        .max(2) as f64;
    let (width, _) = area.dim_in_pixel();
    let (plot, side) = area.split_horizontally(width.saturating_sub(LEGEND_WIDTH));
    let mut chart = ChartBuilder::on(&plot)
        .caption(
            format!("{}: behaviors evaluated per trial", e.result.name),
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(
            0u32..trials,
            (0.8f64..top * 1.2)
                .log_scale()
                .with_key_points(log_ticks(0.8, top * 1.2, 400)),
        )?;
    chart
        .configure_mesh()
        .light_line_style(TRANSPARENT)
        .x_desc("trial (in order; the case base grows)")
        .y_desc("behaviors evaluated (log scale)")
        .y_label_formatter(&tick_label)
        .draw()?;
    let names: Vec<&str> = e.result.arms.iter().map(|a| a.name.as_str()).collect();
    let styles: Vec<ArmStyle> = names
        .iter()
        .enumerate()
        .map(|(i, name)| arm_style(name, i))
        .collect();
    for index in drawing_order(&names) {
        let (s, style) = (&e.result.arms[index], styles[index]);
        let color = style.color;
        let counts = s.counts();
        if dots {
            chart.draw_series(
                counts
                    .iter()
                    .enumerate()
                    .map(|(i, &c)| Circle::new((i as u32, c), 2, color.mix(0.25).filled())),
            )?;
        }
        let band = moving_band(&counts, MOVING_AVERAGE_WINDOW);
        let kept: Vec<usize> = thinned(band.len(), CURVE_POINTS).collect();
        let outline: Vec<(u32, f64)> = kept
            .iter()
            .map(|&i| (i as u32, band[i].1.max(0.8)))
            .chain(kept.iter().rev().map(|&i| (i as u32, band[i].0.max(0.8))))
            .collect();
        chart.draw_series(std::iter::once(Polygon::new(
            outline,
            color.mix(0.18).filled(),
        )))?;
        let average = moving_average(&counts, MOVING_AVERAGE_WINDOW);
        chart.draw_series(LineSeries::new(
            thinned(average.len(), CURVE_POINTS).map(|i| (i as u32, average[i])),
            color.stroke_width(3),
        ))?;
        // The arm's marker on its line at eight places, staggered by arm so that markers
        // of lines that run together do not hide each other.
        let stagger = trials as usize / (8 * names.len().max(1));
        overlay.markers(
            style.shape,
            Some((color, 1.0)),
            Some((WHITE, 1.0)),
            (0..8)
                .map(|k| k * trials as usize / 8 + index * stagger)
                .filter_map(|i| average.get(i).map(|&m| (i, m)))
                .map(|(i, m)| {
                    let (x, y) = chart.backend_coord(&(i as u32, m));
                    ((f64::from(x), f64::from(y)), 4.5)
                }),
        );
    }
    side.draw(&Text::new(
        format!("moving average of {MOVING_AVERAGE_WINDOW}, 95% CI band"),
        (8, 30),
        ("sans-serif", 12).into_font(),
    ))?;
    let entries: Vec<(String, Key)> = names
        .iter()
        .zip(&styles)
        .map(|(name, &style)| ((*name).to_owned(), Key::LineMarker(style)))
        .collect();
    legend(&side, overlay, &entries)
}

/// Every experiment and arm at once: mean behaviors evaluated with its 95% confidence
/// interval, log scale.
/// The experiments' names as a figure's categories, and the scenario they share: without
/// the scenario when every experiment has the same one (a ladder's rungs), so more of them
/// fit side by side (the title names it instead).
fn category_names<'a>(entries: &[ReportEntry<'a>]) -> (Option<&'a str>, Vec<String>) {
    let shared = entries
        .first()
        .map(|first| first.scenario)
        .filter(|scenario| entries.iter().all(|e| e.scenario == *scenario));
    let names = entries
        .iter()
        .map(|e| match shared {
            Some(scenario) => e
                .result
                .name
                .strip_prefix(&format!("{scenario}/"))
                .unwrap_or(&e.result.name)
                .to_owned(),
            None => e.result.name.clone(),
        })
        .collect();
    (shared, names)
}

/// What a summary figure shows of each arm, and of the limit.
#[derive(Clone, Copy)]
struct SummaryMetric {
    /// The file name's stem.
    stem: &'static str,
    /// The figure's title.
    title: &'static str,
    /// What it measures, for its caption.
    what: &'static str,
    /// The y axis's title.
    axis: &'static str,
    /// The arm's mean and CI.
    arm: fn(&ArmResult) -> MeanCi,
    /// The limit's value.
    limit: fn(&Costs) -> f64,
}

/// The three summary figures: behaviors (the paper's metric), commands, untrustworthy
/// commands.
const SUMMARY_METRICS: [SummaryMetric; 3] = [
    SummaryMetric {
        stem: "summary",
        title: "Behaviors evaluated per trial: every experiment and arm (mean, 95% CI)",
        what: "Behaviors evaluated per trial (the paper's metric)",
        axis: "behaviors evaluated (log scale)",
        arm: |a| a.behaviors,
        limit: |c| c.behaviors,
    },
    SummaryMetric {
        stem: "summary-commands",
        title: "Commands per trial: every experiment and arm (mean, 95% CI)",
        what: "Commands per trial (how long the operator waited for a trustworthy behavior)",
        axis: "commands (log scale)",
        arm: |a| a.commands,
        limit: |c| c.commands,
    },
    SummaryMetric {
        stem: "summary-untrustworthy",
        title: "Untrustworthy commands per trial: every experiment and arm (mean, 95% CI)",
        what: "Untrustworthy commands per trial (commands that failed or that the operator interrupted)",
        axis: "untrustworthy commands (log scale)",
        arm: |a| a.untrustworthy,
        limit: |c| c.untrustworthy,
    },
];

/// A value with its 95% interval, as a figure of every experiment and arm draws it.
#[derive(Clone, Copy, Debug)]
struct Interval {
    mid: f64,
    low: f64,
    high: f64,
}

impl From<MeanCi> for Interval {
    fn from(m: MeanCi) -> Self {
        Self {
            mid: m.mean,
            low: m.mean - m.ci95,
            high: m.mean + m.ci95,
        }
    }
}

/// What a figure of every experiment (across) and arm (offset within it) shows.
struct EveryArm<'a> {
    title: String,
    axis: &'a str,
    /// Per experiment, per arm: the value and its interval (`None`: not drawn).
    values: Vec<Vec<Option<Interval>>>,
    /// Per experiment, a black bar across its arms (`None`: none), and its key.
    bars: Vec<Option<f64>>,
    bar_key: String,
}

/// The summary figure of `metric`: each arm's mean and CI, the limit as bars.
fn summary_figure(entries: &[ReportEntry<'_>], metric: SummaryMetric) -> EveryArm<'static> {
    EveryArm {
        title: metric.title.to_owned(),
        axis: metric.axis,
        values: entries
            .iter()
            .map(|e| {
                e.result
                    .arms
                    .iter()
                    .map(|a| Some((metric.arm)(a).into()))
                    .collect()
            })
            .collect(),
        bars: entries
            .iter()
            .map(|e| e.limit.map(|l| (metric.limit)(&l.limit.paper)))
            .collect(),
        bar_key: "known-operator limit".to_owned(),
    }
}

/// Draws `figure`: one column per experiment, each arm's value as its marker with its
/// interval as a vertical line, on a log axis, the bars in black, the legend at the right.
fn every_arm_figure(
    area: &Area<'_>,
    overlay: &mut Overlay,
    entries: &[ReportEntry<'_>],
    figure: &EveryArm<'_>,
) -> DrawResult {
    let (width, _) = area.dim_in_pixel();
    let (plot, side) = area.split_horizontally(width.saturating_sub(LEGEND_WIDTH));
    let arms = entries.first().map_or(0, |e| e.result.arms.len()).max(1);
    let drawn = || figure.values.iter().flatten().flatten();
    let top = drawn()
        .map(|v| v.high)
        .chain(figure.bars.iter().flatten().copied())
        .fold(2.0f64, f64::max);
    // The lower ends where they are positive (a mean minus its CI may not be).
    let bottom = drawn()
        .map(|v| if v.low > 0.0 { v.low } else { v.mid })
        .chain(figure.bars.iter().flatten().copied())
        .fold(0.8f64, f64::min)
        .max(0.1);
    let (scenario, names) = category_names(entries);
    let title = match scenario {
        Some(scenario) => format!("{scenario}: {}", figure.title),
        None => figure.title.clone(),
    };
    let mut chart = ChartBuilder::on(&plot)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(60)
        .y_label_area_size(60)
        .build_cartesian_2d(
            -0.5..names.len() as f64 - 0.5,
            (bottom * 0.8..top * 1.3)
                .log_scale()
                .with_key_points(log_ticks(bottom * 0.8, top * 1.3, 420)),
        )?;
    let label = category_label(&names);
    chart
        .configure_mesh()
        .light_line_style(TRANSPARENT)
        .disable_x_mesh()
        .x_labels(names.len().max(1))
        .x_label_formatter(&label)
        .x_label_style(("sans-serif", 11))
        .y_desc(figure.axis)
        .y_label_formatter(&tick_label)
        .draw()?;
    let mut legend_entries = Vec::new();
    let arm_names: Vec<&str> = entries
        .first()
        .map(|e| e.result.arms.iter().map(|a| a.name.as_str()).collect())
        .unwrap_or_default();
    for (a, name) in arm_names.iter().enumerate() {
        legend_entries.push(((*name).to_owned(), Key::Marker(arm_style(name, a))));
    }
    for a in drawing_order(&arm_names) {
        let style = arm_style(arm_names[a], a);
        let color = style.color;
        let offset = (a as f64 + 0.5) / arms as f64 * 0.7 - 0.35;
        let points: Vec<(f64, Interval)> = figure
            .values
            .iter()
            .enumerate()
            .filter_map(|(x, values)| {
                values
                    .get(a)
                    .copied()
                    .flatten()
                    .map(|v| (x as f64 + offset, v))
            })
            .collect();
        chart.draw_series(points.iter().map(|&(x, v)| {
            PathElement::new(
                vec![(x, v.low.max(bottom * 0.8)), (x, v.high)],
                color.stroke_width(2),
            )
        }))?;
        overlay.markers(
            style.shape,
            Some((color, 1.0)),
            Some((WHITE, 1.0)),
            points.iter().map(|&(x, v)| {
                let (x, y) = chart.backend_coord(&(x, v.mid));
                ((f64::from(x), f64::from(y)), 4.5)
            }),
        );
    }
    let bars: Vec<(f64, f64)> = figure
        .bars
        .iter()
        .enumerate()
        .filter_map(|(x, bar)| bar.map(|y| (x as f64, y)))
        .collect();
    if !bars.is_empty() {
        chart.draw_series(bars.iter().map(|&(x, y)| {
            PathElement::new(vec![(x - 0.42, y), (x + 0.42, y)], BLACK.stroke_width(2))
        }))?;
        legend_entries.push((figure.bar_key.clone(), Key::Line(BLACK)));
    }
    legend(&side, overlay, &legend_entries)
}

/// The layout of a final-behaviors figure: a title band with the subtitle's lines, then
/// up to four arms' panels a row and the keys.
struct FinalsLayout {
    subtitle: Vec<String>,
    rows: usize,
    columns: usize,
}

impl FinalsLayout {
    /// Size of one arm's panel (px).
    const PANEL: (u32, u32) = (330, 320);
    /// Font size of the subtitle.
    const SUBTITLE_FONT: u32 = 15;

    fn new(arms: usize, subtitle: &str) -> Self {
        let columns = arms.clamp(1, 4);
        let width = Self::PANEL.0 * columns as u32 + KEY_WIDTH - 20;
        Self {
            subtitle: wrap(subtitle, Self::SUBTITLE_FONT, width),
            rows: arms.div_ceil(columns).max(1),
            columns,
        }
    }

    /// Height of the title band (px).
    fn header(&self) -> u32 {
        40 + 18 * self.subtitle.len() as u32 + 8
    }

    fn size(&self) -> (u32, u32) {
        (
            Self::PANEL.0 * self.columns as u32 + KEY_WIDTH,
            self.header() + Self::PANEL.1 * self.rows as u32,
        )
    }
}

/// How to read a final-behaviors figure over components `x` and `y`, and why it is empty
/// of trustworthy cells when it is.
fn finals_caption(e: &ReportEntry<'_>, (x, y): (usize, usize), grid: Option<&Grid>) -> String {
    let components = e.space.components();
    let mut caption = format!(
        "Where each arm's trials ended: one panel per arm, each cell a setting of {} \
         (across) and {} (up){}. ",
        escape(&components[x].name),
        escape(&components[y].name),
        if components.len() > 2 {
            ", the other components pooled"
        } else {
            ""
        }
    );
    match grid {
        Some(grid) => {
            caption.push_str(
                "The colour is the chance that the operator lets a command with that setting \
                 complete (dark: rarely, yellow: almost always); the outlined cells are the \
                 trustworthy region, where the trust estimate is expected to climb. ",
            );
            if !grid.tallies.iter().any(|t| t.trusted_on_average()) {
                caption.push_str(
                    "No cell of this pair is trustworthy on average over the other \
                     components: whether a setting of these two is trusted depends on the \
                     others, so the panels show where trials ended, not a region to find. ",
                );
            }
        }
        None => caption.push_str("No landscape of the operator was estimated. "),
    }
    caption.push_str(
        "A marker's area is in proportion to the trials that ended in its cell (the key at \
         the right gives sizes); a good arm ends its trials inside the outline.",
    );
    caption
}

/// What the colour and the circles of a final-behaviors figure show.
fn finals_subtitle(e: &ReportEntry<'_>, grid: Option<&Grid>) -> String {
    let background = match (grid, e.landscapes.first()) {
        (Some(grid), Some(landscape)) => {
            let runs = grid.tallies.first().map_or(0, |t| t.runs);
            let others = if e.space.components().len() > 2 {
                ", the other components drawn at random"
            } else {
                ""
            };
            let judged = if landscape.operators > 1 {
                format!(
                    "the mean over its {} operators (one drawn per run, as each trial draws one)",
                    landscape.operators
                )
            } else {
                format!("operator {}", e.operator)
            };
            let region = if grid.tallies.iter().any(|t| t.trusted_on_average()) {
                ""
            } else {
                " No cell is in the trustworthy region: on average over the other components none is trusted."
            };
            format!("Colour: P(complete) under {judged}; {runs} runs per cell{others}.{region}")
        }
        _ => "No landscape of the operator was estimated.".to_owned(),
    };
    format!("{background} Circles: trials whose final behavior lies in the cell.")
}

/// Up to three counts for the key of marker sizes: 1, a round number near a quarter of
/// `most`, and `most` (each once).
fn count_key(most: u32) -> Vec<u32> {
    let quarter = f64::from(most) / 4.0;
    let round = if quarter < 1.0 {
        1
    } else {
        let magnitude = 10f64.powf(quarter.log10().floor());
        let nice = [1.0, 2.0, 5.0, 10.0]
            .into_iter()
            .map(|m| m * magnitude)
            .filter(|&v| v <= quarter)
            .fold(magnitude, f64::max);
        nice as u32
    };
    let mut key = vec![1, round, most];
    key.dedup();
    key
}

/// The smallest marker's radius (px), so that one trial shows.
const SMALLEST_MARKER: f64 = 1.0;

/// The radius (px) of the marker of `count` trials when the most in one cell is `most`
/// and the largest marker has radius `largest`: area in proportion to the count, at
/// least [`SMALLEST_MARKER`].
fn marker_radius(count: u32, most: u32, largest: f64) -> f64 {
    (largest * (f64::from(count) / f64::from(most.max(1))).sqrt()).max(SMALLEST_MARKER)
}

/// Where each arm's final behaviors land over components `x` and `y`: one panel per arm,
/// circles sized by the trials ending in each cell (one size scale for the figure), over
/// the operator's landscape `grid` (one colour scale) with its trustworthy region
/// outlined; the colour bar and both keys right of the panels.
fn final_behaviors(
    area: &Area<'_>,
    overlay: &mut Overlay,
    e: &ReportEntry<'_>,
    (x, y): (usize, usize),
    grid: Option<&Grid>,
    layout: &FinalsLayout,
    id: &str,
) -> DrawResult {
    let components = e.space.components();
    let (nx, ny) = (components[x].len(), components[y].len());
    let all_counts: Vec<Vec<u32>> = e
        .result
        .arms
        .iter()
        .map(|s| {
            let mut counts = vec![0u32; nx * ny];
            for t in &s.trials {
                let b = t.report.settled;
                counts[usize::from(b.get(x)) * ny + usize::from(b.get(y))] += 1;
            }
            counts
        })
        .collect();
    let most = all_counts
        .iter()
        .flatten()
        .copied()
        .max()
        .unwrap_or(0)
        .max(1);
    let title = format!(
        "{}: final behaviors of every arm by {} and {} ({} trials each)",
        e.result.name,
        components[x].name,
        components[y].name,
        e.result.trials()
    );
    area.draw(&Text::new(title, (10, 8), ("sans-serif", 21).into_font()))?;
    let subtitle = ("sans-serif", FinalsLayout::SUBTITLE_FONT)
        .into_font()
        .color(&RGBColor(60, 60, 60));
    for (k, line) in layout.subtitle.iter().enumerate() {
        area.draw(&Text::new(
            line.as_str(),
            (10, 38 + 18 * k as i32),
            subtitle.clone(),
        ))?;
    }
    let (_, body) = area.split_vertically(layout.header());
    let (panels_area, key_area) =
        body.split_horizontally(FinalsLayout::PANEL.0 * layout.columns as u32);
    let panels = panels_area.split_evenly((layout.rows, layout.columns));
    let mut largest = 0.0;
    let arms = e.result.arms.len();
    for (k, (panel, (arm, counts))) in panels
        .iter()
        .zip(e.result.arms.iter().zip(&all_counts))
        .enumerate()
    {
        // Ticks on the outer axes only: the bottom panel of each column, the first column.
        let style = heatmap::PanelStyle {
            caption: &arm.name,
            write_values: false,
            id,
            ticks: (k + layout.columns >= arms, k % layout.columns == 0),
        };
        let chart = heatmap::panel(panel, overlay, e.space, (x, y), grid, style)?;
        let (width, height) = chart.plotting_area().dim_in_pixel();
        let cell = (f64::from(width) / nx as f64).min(f64::from(height) / ny as f64);
        largest = 0.48 * cell;
        // A light disc in a dark ring, readable on every colour of the scale.
        overlay.markers(
            Shape::Circle,
            Some((WHITE, 0.85)),
            Some((BLACK, 1.0)),
            (0..nx)
                .flat_map(|i| (0..ny).map(move |j| (i, j)))
                .filter(|&(i, j)| counts[i * ny + j] > 0)
                .map(|(i, j)| {
                    let (px, py) = chart.backend_coord(&(i as f64, j as f64));
                    (
                        (f64::from(px), f64::from(py)),
                        marker_radius(counts[i * ny + j], most, largest),
                    )
                }),
        );
    }
    let mut top = 10;
    if grid.is_some() {
        heatmap::color_key(&key_area, top)?;
        top += heatmap::color_key_height() + 20;
    }
    key_area.draw(&Text::new(
        "trials ending there",
        (10, top),
        ("sans-serif", 14).into_font(),
    ))?;
    key_area.draw(&Text::new(
        "(marker area in proportion)",
        (10, top + 17),
        ("sans-serif", 12).into_font(),
    ))?;
    top += 40;
    let (left, base) = key_area.get_base_pixel();
    for count in count_key(most) {
        let r = marker_radius(count, most, largest);
        let cy = top + r.ceil() as i32;
        overlay.markers(
            Shape::Circle,
            Some((WHITE, 1.0)),
            Some((BLACK, 1.0)),
            [((f64::from(left + 19), f64::from(base + cy)), r)],
        );
        let label = if count == 1 {
            "1 trial".to_owned()
        } else {
            format!("{count} trials")
        };
        key_area.draw(&Text::new(
            label,
            (36, cy),
            TextStyle::from(("sans-serif", 13).into_font()).pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
        top = cy + r.ceil() as i32 + 8;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moving_average_by_hand() {
        // Window 2 over 1, 3, 5, 7: 1, (1+3)/2, (3+5)/2, (5+7)/2.
        assert_eq!(
            moving_average(&[1.0, 3.0, 5.0, 7.0], 2),
            vec![1.0, 2.0, 4.0, 6.0]
        );
    }

    #[test]
    fn curves_are_thinned_to_about_200_points() {
        assert_eq!(thinned(3, 200).collect::<Vec<_>>(), [0, 1, 2]);
        assert_eq!(thinned(10, 4).collect::<Vec<_>>(), [0, 3, 6, 9]);
        let points: Vec<usize> = thinned(500, 200).collect();
        assert_eq!(
            (points.len(), points[1], points.last()),
            (168, 3, Some(&499))
        );
        assert_eq!(thinned(0, 200).count(), 0);
    }

    #[test]
    fn distributions_step_by_hand() {
        // Counts 1, 1, 3, 2: half of the trials at 1, three quarters at 2, all at 3.
        assert_eq!(
            ecdf(vec![1.0, 1.0, 3.0, 2.0]),
            [
                (1.0, 0.0),
                (1.0, 0.5),
                (2.0, 0.5),
                (2.0, 0.75),
                (3.0, 0.75),
                (3.0, 1.0)
            ]
        );
        assert_eq!(ecdf(Vec::new()), []);
    }

    #[test]
    fn count_keys_are_round_integers() {
        assert_eq!(count_key(1), [1]);
        assert_eq!(count_key(3), [1, 3]);
        assert_eq!(count_key(37), [1, 5, 37]);
        assert_eq!(count_key(120), [1, 20, 120]);
        assert_eq!(count_key(500), [1, 100, 500]);
        // Area in proportion to the count, never below 1 px; 1 and 20 trials differ.
        assert_eq!(marker_radius(100, 100, 7.0), 7.0);
        assert_eq!(marker_radius(25, 100, 8.0), 4.0);
        assert_eq!(marker_radius(1, 500, 7.0), 1.0);
        assert!(marker_radius(20, 300, 6.0) > marker_radius(1, 300, 6.0) + 0.5);
    }

    #[test]
    fn components_pair_up() {
        let space = |n: usize| {
            let c = |i: usize| {
                cbr_core::NamedComponent::numeric(&format!("c{i}"), "m", 0.0, 1.0, 2).unwrap()
            };
            BehaviorSpace::new((0..n).map(c).collect()).unwrap()
        };
        assert_eq!(component_pairs(&space(1)), []);
        assert_eq!(component_pairs(&space(2)), [(0, 1)]);
        assert_eq!(component_pairs(&space(3)), [(0, 1), (1, 2)]);
        assert_eq!(component_pairs(&space(4)), [(0, 1), (2, 3)]);
    }

    #[test]
    fn p_values_are_readable() {
        assert_eq!(format_p(0.01234), "0.0123");
        assert_eq!(format_p(3.0e-9), "3.0e-9");
    }
}
