//! `summary.json`: per experiment, each arm's means with their intervals, its tests and
//! effect size against the reference arm, its ratios to the known-operator limit and its
//! explanations' accuracy (and its goal changes, in a suite with some; and by context,
//! against its blind twin, in a suite whose trials ran in contexts); the limit and the
//! population's measures; the provenance; and
//! for a benchmark suite, the benchmark of each scenario ([`crate::population::benchmark`]).

use super::effects::{all_effect_sizes, versus_reference};
use super::entry::{Provenance, ReportEntry};
use super::tables::ratios;
use crate::experiment::arm::Initial;
use crate::experiment::record::{ArmResult, ExplanationCheck};
use crate::experiment::trial_contexts::{ArmInContext, any_contexts, by_context};
use crate::population::benchmark::{
    ArmBenchmark, BestOfEachPopulation, LimitRatio, Metric, ScenarioBenchmark,
};
use crate::reference::limit::Costs;
use crate::report::goal_changes::{ArmGoalChanges, any_goal_changes};
use crate::stats::RatioCi;
use serde_json::{Map, Value, json};

/// The `summary.json` document, with a `benchmark` key for a benchmark suite (`benchmark`
/// given).
pub fn summary(
    entries: &[ReportEntry<'_>],
    benchmark: Option<&[ScenarioBenchmark]>,
    elapsed_s: f64,
    provenance: &Provenance,
) -> Value {
    summary_of(
        entries,
        &all_effect_sizes(entries),
        benchmark,
        elapsed_s,
        provenance,
    )
}

/// The `summary.json` document, with the effect sizes already estimated.
pub(super) fn summary_of(
    entries: &[ReportEntry<'_>],
    effects: &[Vec<Option<RatioCi>>],
    benchmark: Option<&[ScenarioBenchmark]>,
    elapsed_s: f64,
    provenance: &Provenance,
) -> Value {
    // Only in a suite with goal changes, so that other reports stay as they were.
    let goal_changes = entries
        .iter()
        .any(|e| any_goal_changes(e.result.arms.iter()));
    // Only in a suite whose trials ran in contexts, likewise.
    let contexts = entries.iter().any(|e| any_contexts(e.result.arms.iter()));
    let experiments: Vec<Value> = entries
        .iter()
        .zip(effects)
        .map(|(e, effects)| {
            let mut strategies = Map::new();
            let mut by_arm = if contexts {
                by_context(&e.result.arms)
            } else {
                Vec::new()
            }
            .into_iter();
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
                    if let Some(reference) = limit.population_reference {
                        summary["ratio_to_population_reference"] =
                            ratio_json(ratios(arm, &reference.paper));
                    }
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
                if goal_changes {
                    summary["goal_changes"] =
                        goal_change_summary(&ArmGoalChanges::of(arm, e.space, e.limit));
                }
                if let Some((_, rows)) = by_arm.next() {
                    summary["contexts"] = rows.iter().map(context_summary).collect();
                }
                strategies.insert(arm.name.to_string(), summary);
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
                let reference = l.population_reference.map(|r| {
                    json!({
                        "paper_protocol": costs(&r.paper),
                        "free_first_choice": costs(&r.free_first),
                        "standard_error": {
                            "paper_protocol": costs(&r.paper_error),
                            "free_first_choice": costs(&r.free_first_error),
                        },
                        "episodes_per_operator": r.episodes,
                    })
                });
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
                        "pairwise_rate_gap": conflict.rate_gap_share,
                    },
                    "population_reference": reference,
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
    let mut document = json!({ "provenance": provenance, "elapsed_s": elapsed_s, "recommended": crate::RECOMMENDED_ARM, "experiments": experiments });
    if let Some(benchmark) = benchmark {
        document["benchmark"] = benchmark.iter().map(benchmark_summary).collect();
    }
    document
}

/// One scenario's benchmark for `summary.json`: its populations, how its numbers were
/// made, the limit's ECDF (each count where it steps up, with the probability of settling
/// within it), and per arm its ratios to the limit, wins, ties and losses, ECDF and
/// windows.
fn benchmark_summary(benchmark: &ScenarioBenchmark) -> Value {
    let windows: Vec<[u32; 2]> = benchmark
        .windows
        .iter()
        .map(|w| [w.first, w.last])
        .collect();
    let arms: Map<String, Value> = benchmark
        .arms
        .iter()
        .map(|arm| {
            (
                arm.arm.to_string(),
                arm_benchmark_summary(arm, benchmark, &windows),
            )
        })
        .collect();
    json!({
        "scenario": benchmark.scenario,
        "populations": benchmark.populations,
        "bootstrap_resamples": crate::population::benchmark::BOOTSTRAP_RESAMPLES,
        "significance": crate::targets::SIGNIFICANCE,
        "references": benchmark.references,
        "limit_untrustworthy_mean": benchmark.limit_untrustworthy,
        "limit_ecdf": {
            "settled_within": benchmark.limit_law.steps(),
            "never_settled": benchmark.limit_law.unsettled.total(),
            "untrustworthy_mean": benchmark.limit_law.mean(),
        },
        "windows": windows,
        "population_reference_to_limit": ratios_json(&benchmark.population_reference_to_limit),
        "arms": arms,
        "best_of_each_population": best_of_each_population_summary(
            &benchmark.best_of_each_population,
            &windows,
        ),
    })
}

/// Geometric mean ratios per [`Metric::ALL`] for `summary.json`, each with its interval and
/// the populations it is over (`null`: none).
fn ratios_json(ratios: &[Option<LimitRatio>; 3]) -> Value {
    Metric::ALL
        .iter()
        .zip(ratios)
        .map(|(metric, ratio)| {
            let value = ratio.map_or(Value::Null, |LimitRatio { ratio, populations }| {
                json!({
                    "geometric_mean": ratio.ratio,
                    "ci95_low": ratio.low,
                    "ci95_high": ratio.high,
                    "populations": populations,
                })
            });
            (metric.key().to_owned(), value)
        })
        .collect::<Map<String, Value>>()
        .into()
}

/// Ratios per [`Metric::ALL`], keyed by the metric's name (`null`: none, or not finite).
fn per_metric(ratios: [Option<f64>; 3]) -> Value {
    Metric::ALL
        .iter()
        .zip(ratios)
        .map(|(metric, ratio)| {
            (
                metric.key().to_owned(),
                ratio.map_or(Value::Null, finite_or_null),
            )
        })
        .collect::<Map<String, Value>>()
        .into()
}

/// Ratios per window of trials (`windows`, each `[first, last]`) and metric, each window's
/// object with its `trials`.
fn over_trials_json(windows: &[[u32; 2]], ratios: &[[Option<f64>; 3]]) -> Vec<Value> {
    windows
        .iter()
        .zip(ratios)
        .map(|(trials, ratios)| {
            let mut window = per_metric(*ratios);
            window["trials"] = json!(trials);
            window
        })
        .collect()
}

/// The best arm of each population, after the fact, for `summary.json`.
fn best_of_each_population_summary(best: &BestOfEachPopulation, windows: &[[u32; 2]]) -> Value {
    json!({
        "ratio_to_limit": per_metric(best.to_limit),
        "ratio_to_limit_over_trials": over_trials_json(windows, &best.windows),
    })
}

/// One arm of a scenario's benchmark for `summary.json`.
fn arm_benchmark_summary(
    arm: &ArmBenchmark,
    benchmark: &ScenarioBenchmark,
    windows: &[[u32; 2]],
) -> Value {
    let to_limit = ratios_json(&arm.to_limit);
    let versus: Map<String, Value> = benchmark
        .references
        .iter()
        .zip(&arm.versus)
        .filter_map(|(reference, tally)| {
            tally.map(|t| {
                (
                    reference.clone(),
                    json!({ "wins": t.wins, "ties": t.ties, "losses": t.losses }),
                )
            })
        })
        .collect();
    let over_trials = over_trials_json(windows, &arm.windows);
    json!({
        "ratio_to_limit": to_limit,
        "ratio_to_population_reference": ratios_json(&arm.to_population_reference),
        "versus": versus,
        "ecdf": {
            "pairs": arm.ecdf.pairs,
            "settled_within": arm.ecdf.steps(),
        },
        "ratio_to_limit_over_trials": over_trials,
    })
}

/// A number for JSON, `null` when it is not finite.
fn finite_or_null(x: f64) -> Value {
    if x.is_finite() { json!(x) } else { Value::Null }
}

/// An arm's goal changes for `summary.json` (`null` where a figure is not defined).
fn goal_change_summary(g: &ArmGoalChanges) -> Value {
    json!({
        "given_up": g.given_up,
        "given_up_though_trusted": g.wrongly_given_up,
        "untrustworthy_about_behavior": g.untrustworthy_about_behavior,
        "record": g.record,
        "guess_recall": g.record.and_then(|r| r.recall()),
        "guess_precision": g.record.and_then(|r| r.precision()),
    })
}

fn context_summary(c: &ArmInContext) -> Value {
    json!({
        "context": c.context,
        "trials": c.trials,
        "behaviors": c.behaviors,
        "untrustworthy": c.untrustworthy,
        "versus_blind": c.versus_blind.map(|v| json!({
            "behaviors_difference": v.behaviors,
            "behaviors_p": v.behaviors_p,
            "untrustworthy_difference": v.untrustworthy,
            "untrustworthy_p": v.untrustworthy_p,
        })),
    })
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
