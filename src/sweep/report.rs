//! A sweep's report from its runs' summaries alone: `sweep.md` and `sweep.json`, each
//! cell's means over seeds with their 95% intervals, and a plot per parameter.

use super::folder::remove_earlier_report;
use super::plot::plot_parameter;
use super::{Design, RunId, RunSummary, Sweep, SweepError};
use files::write_file_in;
use lab::stats::mean_ci95;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// (cell, experiment, arm) -> the per-seed mean behaviors, the per-seed mean commands, and
/// the trials cut off over all seeds.
pub(super) type Series = BTreeMap<(usize, String, String), (Vec<f64>, Vec<f64>, usize)>;

/// One cell's aggregate for one experiment and arm: mean of the per-seed means and the
/// half-width of its 95% confidence interval over seeds (none from a single seed).
pub(super) fn aggregate(values: &[f64]) -> (f64, Option<f64>) {
    match mean_ci95(values) {
        Some(m) if values.len() > 1 => (m.mean, Some(m.ci95)),
        Some(m) => (m.mean, None),
        None => (0.0, None),
    }
}

/// `mean ± half-width` to `decimals` places, or the mean alone without an interval.
fn with_interval(mean: f64, ci: Option<f64>, decimals: usize) -> String {
    match ci {
        Some(ci) => format!("{mean:.decimals$} ± {ci:.decimals$}"),
        None => format!("{mean:.decimals$}"),
    }
}

/// Writes `sweep.md`, `sweep.json` and one plot per parameter (`sweep-NAME.svg`) into
/// `out`, from the runs' summaries. Returns the files written.
pub fn write_report(
    sweep: &Sweep,
    summaries: &[(RunId, RunSummary)],
    out: &Path,
) -> Result<Vec<PathBuf>, SweepError> {
    let mut series: Series = BTreeMap::new();
    let mut order: Vec<String> = Vec::new();
    let mut arm_order: Vec<Vec<String>> = vec![Vec::new(); sweep.cells.len()];
    for (run, summary) in summaries {
        for name in &summary.order {
            if !order.contains(name) {
                order.push(name.clone());
            }
        }
        arm_order[run.cell].clone_from(&summary.arms);
        for (experiment, arms) in &summary.experiments {
            for (arm, means) in arms {
                let entry = series
                    .entry((run.cell, experiment.clone(), arm.clone()))
                    .or_default();
                entry.0.push(means.behaviors);
                entry.1.push(means.commands);
                entry.2 += means.truncated;
            }
        }
    }
    let seeds = sweep.config.seeds.len();
    let mut md = format!(
        "# Sweep: {} cells x {seeds} seeds\n\nBehaviors evaluated per trial: the mean over seeds of each run's mean, ± the half-width of its 95% confidence interval over seeds (none from one seed); commands per trial likewise. Seeds: {:?}.\n",
        sweep.cells.len(),
        sweep.config.seeds
    );
    let mut json_cells = Vec::new();
    for experiment in &order {
        let _ = write!(
            md,
            "\n## {experiment}\n\n| cell | arm | behaviors evaluated | commands | cut off |\n|---|---|---:|---:|---:|\n"
        );
        for (c, cell) in sweep.cells.iter().enumerate() {
            for arm in &arm_order[c] {
                if let Some((behaviors, commands, truncated)) =
                    series.get(&(c, experiment.clone(), arm.clone()))
                {
                    let (b, bci) = aggregate(behaviors);
                    let (m, mci) = aggregate(commands);
                    let _ = writeln!(
                        md,
                        "| {} | {arm} | {} | {} | {truncated} |",
                        cell.label,
                        with_interval(b, bci, 2),
                        with_interval(m, mci, 1),
                    );
                    json_cells.push(serde_json::json!({
                        "cell": cell.label,
                        "experiment": experiment,
                        "arm": arm,
                        "behaviors_mean": b,
                        "behaviors_ci95": bci,
                        "commands_mean": m,
                        "commands_ci95": mci,
                        "truncated": truncated,
                        "seeds": behaviors.len(),
                    }));
                }
            }
        }
    }
    let json = serde_json::json!({
        "seeds": sweep.config.seeds,
        "cells": sweep.cells.iter().map(|c| &c.label).collect::<Vec<_>>(),
        "results": json_cells,
    });
    let mut files = vec![
        ("sweep.md".to_owned(), md),
        (
            "sweep.json".to_owned(),
            serde_json::to_string_pretty(&json).expect("plain data serializes") + "\n",
        ),
    ];
    if sweep.config.design == Design::OneAtATime {
        for p in &sweep.config.parameters {
            let name = format!("sweep-{}.svg", p.name());
            let svg = plot_parameter(sweep, p, &series, &order, &arm_order, &out.join(&name))?;
            files.push((name, svg));
        }
    }
    // Written only once every file is computed, so a failure leaves no partial report;
    // an earlier report's files go first, so no stale plot stays beside the new ones.
    remove_earlier_report(out)?;
    files
        .iter()
        .map(|(name, text)| Ok(write_file_in(out, name, text)?))
        .collect()
}
