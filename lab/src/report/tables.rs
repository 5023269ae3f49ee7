//! The report's tables, in Markdown (printed, in `table.md`, and as HTML on the page):
//! the paper's Table 1, every arm, the effect sizes, the explanations against the truth
//! (with sample explanations), every arm against the known-operator limit (the paper's
//! protocol, and free to choose the first behavior) and how much each population
//! disagrees; goal changes, when an experiment has them; each arm by context, against its
//! blind twin, when trials ran in contexts; and the one line per experiment printed after a
//! run. A benchmark suite's tables are [`super::benchmark_tables`]'.

use super::benchmark_tables::{benchmark_section, ratio_cell};
use super::effects::versus_reference;
use super::entry::ReportEntry;
use crate::experiment::arm::Initial;
use crate::experiment::record::ArmResult;
use crate::experiment::trial_contexts::{any_contexts, by_context};
use crate::population::benchmark::ScenarioBenchmark;
use crate::reference::known_operator::{ExperimentLimit, RATE_GAP};
use crate::reference::limit::Costs;
use crate::reference::population_reference::PopulationReference;
use crate::report::goal_changes::{ArmGoalChanges, any_goal_changes};
use crate::stats::{MeanCi, RatioCi};
use std::fmt::Write as _;

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
pub(super) fn found_note(entries: &[ReportEntry<'_>]) -> &'static str {
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

/// Every arm's effect size against its experiment's reference arm, from
/// [`all_effect_sizes`](super::all_effect_sizes).
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

/// Goal changes, per arm of every experiment (empty when no experiment has any): goal
/// changes per trial and the share said, behaviors given up and those of them the
/// trial's operator trusts (given up wrongly; `—` without a limit), untrustworthy
/// commands about the behavior, and the robot's guess of unsaid goal changes against the
/// truth (recall: unsaid goal changes guessed; precision: guesses that were goal changes).
pub fn goal_changes_table(entries: &[ReportEntry<'_>]) -> String {
    if !entries
        .iter()
        .any(|e| any_goal_changes(e.result.arms.iter()))
    {
        return String::new();
    }
    let mut out = String::from(
        "| Experiment | Arm | Goal changes per trial (said) | Behaviors given up | Given up though trusted | Untrustworthy about the behavior | Guess: recall | Guess: precision |
",
    );
    out.push_str(
        "|---|---|---:|---:|---:|---:|---:|---:|
",
    );
    let share = |x: Option<f64>| x.map_or("—".to_owned(), |x| format!("{:.0}%", 100.0 * x));
    for e in entries {
        for arm in &e.result.arms {
            let g = ArmGoalChanges::of(arm, e.space, e.limit);
            let trials = arm.trials.len().max(1) as f64;
            let happened = g.record.map_or("none".to_owned(), |r| {
                format!(
                    "{:.2} ({})",
                    f64::from(r.happened) / trials,
                    share((r.happened > 0).then(|| f64::from(r.said) / f64::from(r.happened)))
                )
            });
            let _ = writeln!(
                out,
                "| {} | {} | {happened} | {} | {} | {} | {} | {} |",
                e.result.name,
                arm.name,
                mean_cell(&g.given_up, 0),
                g.wrongly_given_up
                    .map_or("—".to_owned(), |m| mean_cell(&m, 0)),
                mean_cell(&g.untrustworthy_about_behavior, 0),
                share(g.record.and_then(|r| r.recall())),
                share(g.record.and_then(|r| r.precision())),
            );
        }
    }
    out
}

/// Each arm by the contexts its trials ran in (empty when every trial of every experiment
/// ran in the default context): behaviors evaluated and untrustworthy commands per trial,
/// and for an arm whose twin blind to the context (`NAME+context-blind`) ran the same
/// trials, the mean paired difference, told minus blind, with its Wilcoxon p.
pub fn contexts_table(entries: &[ReportEntry<'_>]) -> String {
    if !entries.iter().any(|e| any_contexts(e.result.arms.iter())) {
        return String::new();
    }
    let mut out = String::from(
        "| Experiment | Arm | Context | Trials | Behaviors evaluated | Untrustworthy commands | Told − blind: behaviors (p) | Told − blind: untrustworthy (p) |\n|---|---|---|---:|---:|---:|---:|---:|\n",
    );
    for e in entries {
        for (arm, contexts) in by_context(&e.result.arms) {
            for c in contexts {
                let (behaviors, untrustworthy) =
                    c.versus_blind
                        .map_or(("—".to_owned(), "—".to_owned()), |v| {
                            (
                                format!("{:+.2} ({})", v.behaviors, format_p(v.behaviors_p)),
                                format!(
                                    "{:+.2} ({})",
                                    v.untrustworthy,
                                    format_p(v.untrustworthy_p)
                                ),
                            )
                        });
                let context = match &c.context {
                    None => "all".to_owned(),
                    Some(c) if c.is_default() => "default".to_owned(),
                    Some(c) => c.to_string(),
                };
                let _ = writeln!(
                    out,
                    "| {} | {arm} | {context} | {} | {} | {} | {behaviors} | {untrustworthy} |",
                    e.result.name,
                    c.trials,
                    mean_cell(&c.behaviors, 0),
                    mean_cell(&c.untrustworthy, 0),
                );
            }
        }
    }
    out
}

/// The title of [`contexts_table`]'s section.
pub(super) const CONTEXTS_TITLE: &str = "By context: each arm in each context of its trials, and against its twin blind to the context on the same trials";

/// [`contexts_table`] under its title, or nothing when every trial ran in the default
/// context.
fn contexts_section(entries: &[ReportEntry<'_>]) -> String {
    let table = contexts_table(entries);
    if table.is_empty() {
        table
    } else {
        format!("\n## {CONTEXTS_TITLE}\n\n{table}")
    }
}

/// The title of [`goal_changes_table`]'s section.
pub(super) const GOAL_CHANGES_TITLE: &str = "Goal changes: interruptions not about the behavior, behaviors given up though the operator trusts them, and the robot's guess of unsaid ones";

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
            (arm.name.to_string(), samples)
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
pub(super) fn ratios(arm: &ArmResult, limit: &Costs) -> [f64; 3] {
    [
        arm.behaviors.mean / limit.behaviors,
        arm.commands.mean / limit.commands,
        arm.untrustworthy.mean / limit.untrustworthy,
    ]
}

/// Every arm against the known-operator limit of its experiment: the limit (an agent that
/// knows the operator's outcome distribution of every behavior, starting from the
/// paper's random behavior; and free to choose its first), the population reference where
/// the experiment has one (its costs, and its multiples of the limit's: what telling
/// operators apart costs), then each arm's behaviors, commands and untrustworthy commands
/// as multiples of the limit's and of the population reference's (what learning costs).
/// Experiments without a
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
        let reference = limit.population_reference;
        if let Some(r) = reference {
            reference_rows(&mut out, &e.result.name, &r, &paper);
        }
        for arm in &e.result.arms {
            let mut multiples = |of: &str, costs: &Costs| {
                let [b, c, u] = ratios(arm, costs);
                let _ = writeln!(
                    out,
                    "| {} | {} (× {of}) | {} | {} | {} |",
                    e.result.name,
                    arm.name,
                    ratio_cell(b),
                    ratio_cell(c),
                    ratio_cell(u)
                );
            };
            multiples("limit", &paper);
            if let Some(r) = reference {
                multiples("population reference", &r.paper);
            }
        }
    }
    out
}

/// The limit table's rows of an experiment's population reference: its costs with their
/// standard errors under both protocols, and its multiples of the limit's (`paper`).
fn reference_rows(out: &mut String, experiment: &str, r: &PopulationReference, paper: &Costs) {
    for (protocol, costs, error) in [
        (
            "population reference (knows each operator, not which it faces; mean ± standard error of its simulation), random first behavior",
            r.paper,
            r.paper_error,
        ),
        (
            "the same, free to choose its first",
            r.free_first,
            r.free_first_error,
        ),
    ] {
        let _ = writeln!(
            out,
            "| {experiment} | {protocol} | {:.2} ± {:.2} | {:.1} ± {:.1} | {:.1} ± {:.1} |",
            costs.behaviors,
            error.behaviors,
            costs.commands,
            error.commands,
            costs.untrustworthy,
            error.untrustworthy
        );
    }
    let cell = |of: fn(&Costs) -> f64| ratio_cell(of(&r.paper) / of(paper));
    let _ = writeln!(
        out,
        "| {experiment} | population reference (× limit) | {} | {} | {} |",
        cell(|c| c.behaviors),
        cell(|c| c.commands),
        cell(|c| c.untrustworthy)
    );
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

/// The title of [`population_table`]'s section.
pub(super) const POPULATION_TITLE: &str = "How much each experiment's operators disagree (their trustworthy regions and completion rates)";

/// How much each experiment's operators disagree, measured on the landscapes behind the
/// limit: the behaviors each trusts, those all trust, the pairwise Jaccard index of their
/// trustworthy regions, the pairwise share of behaviors whose completion rates lie more
/// than [`RATE_GAP`] apart, whether one behavior pleases everyone. Empty when no
/// experiment has a limit.
pub fn population_table(entries: &[ReportEntry<'_>]) -> String {
    let mut out = String::new();
    for e in entries {
        let Some(limit) = e.limit else {
            continue;
        };
        if out.is_empty() {
            let _ = writeln!(
                out,
                "| Experiment | Operators | Trusted by each | Trusted by all | Jaccard (pairs) | Rates >{RATE_GAP} apart (pairs) | One behavior pleases all |"
            );
            out.push_str("|---|---:|---|---:|---|---|---|\n");
        }
        let c = &limit.conflict;
        let each: Vec<String> = c.trusted_by_each.iter().map(usize::to_string).collect();
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} ({:.1}%) | {} | {} | {} |",
            e.result.name,
            limit.operators,
            each.join(", "),
            c.trusted_by_all,
            100.0 * c.shared_share(),
            pairs_range(&c.jaccard),
            pairs_range(&c.rate_gap_share),
            if c.trusted_by_all > 0 { "yes" } else { "no" }
        );
    }
    out
}

/// A figure over every pair of operators as its range, `0.12 to 0.40`: one figure when
/// the pairs agree to two decimals, `—` when there is no pair.
fn pairs_range(pairs: &[f64]) -> String {
    match (
        pairs.iter().copied().reduce(f64::min),
        pairs.iter().copied().reduce(f64::max),
    ) {
        (Some(lo), Some(hi)) if hi - lo < 0.005 => format!("{lo:.2}"),
        (Some(lo), Some(hi)) => format!("{lo:.2} to {hi:.2}"),
        _ => "—".to_owned(),
    }
}

fn format_p(p: f64) -> String {
    if p < 1e-4 {
        format!("{p:.1e}")
    } else {
        format!("{p:.4}")
    }
}

/// [`goal_changes_table`] under its title, or nothing when no experiment has goal
/// changes.
fn goal_changes_section(entries: &[ReportEntry<'_>]) -> String {
    let table = goal_changes_table(entries);
    if table.is_empty() {
        table
    } else {
        format!("\n## {GOAL_CHANGES_TITLE}\n\n{table}")
    }
}

/// The title of [`free_first_table`]'s section.
pub(super) const FREE_FIRST_TITLE: &str = "Arms that may start from the case memory's guess, against the known-operator limit free to choose its first behavior";

/// `table.md`: the tables in order, each under its title; the benchmark's last, when the
/// suite is one.
pub(super) fn table_md(
    entries: &[ReportEntry<'_>],
    effects: &[Vec<Option<RatioCi>>],
    benchmark: Option<&[ScenarioBenchmark]>,
) -> String {
    let limits = limit_table(entries);
    let free_first = free_first_table(entries);
    let limits = if limits.is_empty() {
        String::new()
    } else {
        format!(
            "\n## Against the known-operator limit (the paper's protocol: a random first behavior)\n\n{limits}{}\n## {POPULATION_TITLE}\n\n{}",
            if free_first.is_empty() {
                String::new()
            } else {
                format!("\n## {FREE_FIRST_TITLE}\n\n{free_first}")
            },
            population_table(entries)
        )
    };
    format!(
        "## Behaviors evaluated per trial (mean ± 95% CI): the paper's two arms\n\n{}\n## Every arm: what it costs the operator (p-values against the reference arm, {})\n\n{}{}\n## Effect sizes against the reference arm\n\n{}{limits}\n## Explanations against the truth: is the first reason given for a behavior given up the operator's most frequent true reason?\n\n{}",
        table(entries),
        entries.first().map_or("", |e| e.reference),
        arms_table(entries),
        found_note(entries),
        effects_table(entries, effects),
        explanations_table(entries)
    ) + &goal_changes_section(entries)
        + &contexts_section(entries)
        + &benchmark.map_or(String::new(), benchmark_section)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn p_values_are_readable() {
        assert_eq!(format_p(0.01234), "0.0123");
        assert_eq!(format_p(3.0e-9), "3.0e-9");
    }

    #[test]
    fn a_figure_over_pairs_reads_as_its_range() {
        assert_eq!(pairs_range(&[0.4, 0.123, 0.2]), "0.12 to 0.40");
        assert_eq!(pairs_range(&[2.0 / 3.0, 0.668]), "0.67");
        assert_eq!(pairs_range(&[]), "—");
    }
}
