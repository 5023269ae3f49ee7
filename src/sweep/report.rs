//! A sweep's report from its runs' summaries alone: `sweep.md` and `sweep.json`, each
//! cell's means over seeds with their 95% intervals, and a plot per parameter.

use super::folder::{REPORT_DIR, check_report_folder, remove_report_files_beside};
use super::plot::plot_parameter;
use super::{Design, RunId, RunSummary, Sweep, SweepError};
use files::{StagedFolder, write_file_in};
use lab::folder::ReportFolderError;
use lab::stats::mean_ci95;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// (cell, experiment, arm) -> the per-seed mean behaviors, the per-seed mean commands, and
/// the trials cut off over all seeds.
pub(super) type Series = BTreeMap<(usize, String, lab::ArmName), (Vec<f64>, Vec<f64>, usize)>;

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

/// Writes the report folder `out/report` ([`REPORT_DIR`]): `sweep.md`, `sweep.json` and
/// one plot per parameter (`sweep-NAME.svg`), from the runs' summaries. The folder is
/// written whole beside its place and swapped in only once every file is written, so a
/// report that fails to write leaves the earlier one as it was; the report files earlier
/// versions wrote into `out` itself are removed once it is in place. Returns the files
/// written, in place.
pub fn write_report(
    sweep: &Sweep,
    summaries: &[(RunId, RunSummary)],
    out: &Path,
) -> Result<Vec<PathBuf>, SweepError> {
    let mut series: Series = BTreeMap::new();
    let mut order: Vec<String> = Vec::new();
    let mut arm_order: Vec<Vec<lab::ArmName>> = vec![Vec::new(); sweep.cells.len()];
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
    let report = out.join(REPORT_DIR);
    if sweep.config.design == Design::OneAtATime {
        for p in &sweep.config.parameters {
            let name = format!("sweep-{}.svg", p.name());
            let svg = plot_parameter(sweep, p, &series, &order, &arm_order, &report.join(&name))?;
            files.push((name, svg));
        }
    }
    // Written only once every file is computed, into a fresh folder beside the report's
    // place, swapped in whole: the earlier report goes only once the new one is in place,
    // with every plot of it.
    check_report_folder(&report)?;
    let staged = StagedFolder::beside(&report).map_err(ReportFolderError::from)?;
    for (name, text) in &files {
        write_file_in(staged.path(), name, text).map_err(|reason| SweepError::Unwritten {
            path: report.clone(),
            reason,
        })?;
    }
    check_report_folder(&report)?;
    staged.commit().map_err(ReportFolderError::from)?;
    remove_report_files_beside(out)?;
    Ok(files.iter().map(|(name, _)| report.join(name)).collect())
}
