//! Sweeps: a suite run over several seeds and over values of named parameters, aggregated
//! across seeds.
//!
//! A [`SweepConfig`] (RON) names a base suite, the seeds, and the parameters to vary
//! ([`Parameter`]: lambda, thresholds, the retention reading, the unit of `t`, the arms,
//! and any reading the catalog's domain declares, such as the UGV patrol weight reading). Its *cells* are the base and, one parameter at a time, each
//! of its other values (or, with `design: grid`, every combination). Every (cell, seed)
//! pair is one *run* of the suite, summarised into a small JSON file
//! (`runs/CELL/seed-SEED.json`); the report aggregates the runs of each cell across seeds
//! (mean of the per-seed means, with a 95% confidence interval over seeds).
//!
//! Runs are independent, so a sweep can be split: `--shard I/N` runs every N-th run and
//! writes only its run files, and [`merge`] rebuilds the report from shard folders. The
//! report is a function of the run files alone (no timings, fixed order), so a merged
//! report is byte-for-byte the report of a single run.

use crate::catalog::{Catalog, resolve_readings};
use crate::suite::{EMBEDDED_ORIGIN, SuiteConfig, SuiteError, SuiteResults, run_suite};
use cbr_core::{FileError, RonError, parse_ron, read_text, write_file_in};
use lab::plot::{ArmStyle, arm_style, drawing_order, log_ticks, text_width, tick_label};
use lab::report::{category_label, file_stems};
use lab::stats::mean_ci95;
use plotters::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::num::NonZeroU32;
use std::path::{Path, PathBuf};
use trust::{Retention, Thresholds, TimeUnit};

/// The most runs (cells times seeds) a sweep may ask for.
pub const MAX_RUNS: usize = 10_000;

/// A sweep, as written in RON.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepConfig {
    /// The suite every cell starts from: `embedded` (the catalog's embedded suite) or a
    /// RON file, relative to the sweep file.
    pub suite: SuiteSource,
    /// Trials per experiment and arm (overrides the suite's).
    #[serde(default)]
    pub trials: Option<NonZeroU32>,
    /// The arms (overrides the suite's).
    #[serde(default)]
    pub arms: Option<Vec<String>>,
    /// The master seeds; every cell runs once per seed.
    pub seeds: Vec<u64>,
    /// The parameters to vary.
    pub parameters: Vec<Parameter>,
    /// How cells are formed from the parameters.
    #[serde(default)]
    pub design: Design,
}

/// Where a sweep's base suite comes from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum SuiteSource {
    /// The catalog's embedded suite (what `reproduce` runs; for the UGV catalog, the
    /// paper's seven experiments).
    Embedded,
    /// A suite config file, relative to the sweep file.
    File(PathBuf),
}

/// How a sweep's cells are formed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum Design {
    /// The base suite, then each parameter's other values one at a time, the rest as in
    /// the base.
    #[default]
    OneAtATime,
    /// Every combination of the parameters' values.
    Grid,
}

/// A parameter and the values it takes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum Parameter {
    /// Algorithm 2's threshold.
    Lambda(Vec<f64>),
    /// The trust thresholds.
    Thresholds(Vec<Thresholds>),
    /// The retention reading.
    Retention(Vec<Retention>),
    /// The unit of `t`.
    TimeUnit(Vec<TimeUnit>),
    /// A reading the catalog's domain declares, by name, and its values, e.g.
    /// `reading("patrol_weights", ["as_written", "three_and_one"])`.
    Reading(String, Vec<String>),
    /// The arms compared.
    Arms(Vec<Vec<String>>),
}

impl Parameter {
    /// The parameter's name in reports.
    pub fn name(&self) -> &str {
        match self {
            Parameter::Lambda(_) => "lambda",
            Parameter::Thresholds(_) => "thresholds",
            Parameter::Retention(_) => "retention",
            Parameter::TimeUnit(_) => "time_unit",
            Parameter::Reading(name, _) => name,
            Parameter::Arms(_) => "arms",
        }
    }

    fn len(&self) -> usize {
        match self {
            Parameter::Lambda(v) => v.len(),
            Parameter::Thresholds(v) => v.len(),
            Parameter::Retention(v) => v.len(),
            Parameter::TimeUnit(v) => v.len(),
            Parameter::Reading(_, v) => v.len(),
            Parameter::Arms(v) => v.len(),
        }
    }

    /// Sets value `i` in `suite`; returns its label, e.g. `lambda=0.9`.
    fn apply(&self, i: usize, suite: &mut SuiteConfig) -> String {
        let value = match self {
            Parameter::Lambda(v) => {
                suite.adapter.lambda = v[i];
                v[i].to_string()
            }
            Parameter::Thresholds(v) => {
                suite.adapter.thresholds = v[i];
                format!("{}/{}", v[i].trustworthy, v[i].untrustworthy)
            }
            Parameter::Retention(v) => {
                suite.adapter.retention = v[i];
                ron_name(&v[i])
            }
            Parameter::TimeUnit(v) => {
                suite.adapter.time_unit = v[i];
                ron_name(&v[i])
            }
            Parameter::Reading(name, v) => {
                suite.readings.insert(name.clone(), v[i].clone());
                v[i].clone()
            }
            Parameter::Arms(v) => {
                suite.arms = v[i].clone();
                v[i].join("+")
            }
        };
        format!("{}={value}", self.name())
    }
}

/// A unit variant's RON spelling.
fn ron_name(value: &impl Serialize) -> String {
    ron::to_string(value).expect("plain data serializes")
}

/// Why a sweep cannot be run or merged.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SweepError {
    /// A file could not be read or written.
    #[error(transparent)]
    Io(#[from] FileError),
    /// A RON file does not parse.
    #[error(transparent)]
    Parse(#[from] RonError),
    /// A value is out of range.
    #[error("{path}: {field}: {message}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// The field.
        field: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// A cell's suite is invalid or could not run.
    #[error("cell {cell}: {reason}")]
    Suite {
        /// The cell's label.
        cell: String,
        /// Why.
        reason: SuiteError,
    },
    /// A run file is missing or unreadable when merging.
    #[error("{path}: {message}")]
    Run {
        /// The run file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A plot could not be drawn.
    #[error("plot {path}: {message}")]
    Plot {
        /// The plot file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

/// One cell: a label and its suite.
#[derive(Clone, Debug)]
pub struct Cell {
    /// e.g. `base` or `lambda=0.9`.
    pub label: String,
    /// The suite this cell runs.
    pub suite: SuiteConfig,
}

/// One run: a cell and a seed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RunId {
    /// The cell's index.
    pub cell: usize,
    /// The seed's index.
    pub seed: usize,
}

/// A checked sweep: its cells and runs.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// The config as read.
    pub config: SweepConfig,
    /// Where the base suite's operator files are found from.
    pub origin: PathBuf,
    /// The cells, in report order.
    pub cells: Vec<Cell>,
    /// Each cell's folder name under `runs/` ([`file_stems`] of the labels).
    folders: Vec<String>,
}

impl Sweep {
    /// Reads and checks a sweep file against `catalog`.
    pub fn load<C: Catalog>(catalog: &C, path: &Path) -> Result<Self, SweepError> {
        let text = read_text(path)?;
        let config: SweepConfig = parse_ron(&text, path)?;
        Self::new(catalog, config, path)
    }

    /// Checks `config` (read from `path`) against `catalog` and forms its cells.
    pub fn new<C: Catalog>(
        catalog: &C,
        config: SweepConfig,
        path: &Path,
    ) -> Result<Self, SweepError> {
        let invalid = |field: &str, message: String| SweepError::Invalid {
            path: path.to_owned(),
            field: field.to_owned(),
            message,
        };
        if config.seeds.is_empty() {
            return Err(invalid("seeds", "at least one seed is needed".into()));
        }
        for (i, p) in config.parameters.iter().enumerate() {
            if p.len() == 0 {
                return Err(invalid(
                    &format!("parameters[{i}]"),
                    format!("{} lists no value", p.name()),
                ));
            }
        }
        let (base, origin) = match &config.suite {
            SuiteSource::Embedded => (
                SuiteConfig::embedded(catalog),
                PathBuf::from(EMBEDDED_ORIGIN),
            ),
            SuiteSource::File(file) => {
                let file = path.parent().unwrap_or(Path::new(".")).join(file);
                (SuiteConfig::load(catalog, &file), file)
            }
        };
        let mut base = base.map_err(|reason| SweepError::Suite {
            cell: "base".into(),
            reason,
        })?;
        // Every reading spelled out, so a cell setting a reading to its default is the
        // base cell.
        base.readings = resolve_readings(catalog, &base.readings)
            .map_err(|e| invalid("suite", e.to_string()))?;
        if let Some(trials) = config.trials {
            base.trials = trials;
        }
        if let Some(arms) = &config.arms {
            base.arms.clone_from(arms);
        }
        let cells = match config.design {
            Design::OneAtATime => one_at_a_time(&base, &config.parameters),
            Design::Grid => grid(&base, &config.parameters),
        };
        let runs = cells.len() * config.seeds.len();
        if runs > MAX_RUNS {
            return Err(invalid(
                "parameters",
                format!("{runs} runs (cells x seeds); at most {MAX_RUNS}"),
            ));
        }
        for cell in &cells {
            cell.suite
                .validate(catalog, &origin)
                .map_err(|reason| SweepError::Suite {
                    cell: cell.label.clone(),
                    reason,
                })?;
        }
        let folders = file_stems(cells.iter().map(|c| &c.label));
        Ok(Self {
            config,
            origin,
            cells,
            folders,
        })
    }

    /// Every run, cells in order and seeds in order within a cell.
    pub fn runs(&self) -> Vec<RunId> {
        (0..self.cells.len())
            .flat_map(|cell| (0..self.config.seeds.len()).map(move |seed| RunId { cell, seed }))
            .collect()
    }

    /// The runs of shard `index` (from 1) of `count`: every `count`-th run.
    pub fn shard(&self, index: usize, count: usize) -> Vec<RunId> {
        self.runs()
            .into_iter()
            .enumerate()
            .filter(|(i, _)| i % count == index - 1)
            .map(|(_, r)| r)
            .collect()
    }

    /// Trials per run, for progress: experiments x arms x trials, summed over `runs`.
    pub fn trials_in(&self, runs: &[RunId]) -> u64 {
        runs.iter()
            .map(|r| {
                let s = &self.cells[r.cell].suite;
                (s.experiments.len() * s.arms.len()) as u64 * u64::from(s.trials.get())
            })
            .sum()
    }

    /// The run file of `run`, relative to a sweep folder.
    pub fn run_file(&self, run: RunId) -> PathBuf {
        Path::new("runs")
            .join(&self.folders[run.cell])
            .join(format!("seed-{}.json", self.config.seeds[run.seed]))
    }

    /// Runs `run` on the current rayon pool and returns its summary;
    /// `progress()` is called after every trial.
    pub fn run<C: Catalog>(
        &self,
        catalog: &C,
        run: RunId,
        progress: &(dyn Fn() + Sync),
    ) -> Result<RunSummary, SweepError> {
        let cell = &self.cells[run.cell];
        let mut suite = cell.suite.clone();
        suite.seed = self.config.seeds[run.seed];
        let results =
            run_suite(catalog, &suite, &self.origin, None, &|_| progress()).map_err(|reason| {
                SweepError::Suite {
                    cell: cell.label.clone(),
                    reason,
                }
            })?;
        Ok(RunSummary::of(&suite, &results))
    }
}

fn one_at_a_time(base: &SuiteConfig, parameters: &[Parameter]) -> Vec<Cell> {
    let mut cells = vec![Cell {
        label: "base".into(),
        suite: base.clone(),
    }];
    for p in parameters {
        for i in 0..p.len() {
            let mut suite = base.clone();
            let label = p.apply(i, &mut suite);
            // A value equal to the base's is the base cell itself.
            if suite != *base {
                cells.push(Cell { label, suite });
            }
        }
    }
    cells
}

fn grid(base: &SuiteConfig, parameters: &[Parameter]) -> Vec<Cell> {
    let mut cells = vec![Cell {
        label: String::new(),
        suite: base.clone(),
    }];
    for p in parameters {
        cells = cells
            .into_iter()
            .flat_map(|cell| {
                (0..p.len()).map(move |i| {
                    let mut suite = cell.suite.clone();
                    let label = p.apply(i, &mut suite);
                    Cell {
                        label: if cell.label.is_empty() {
                            label
                        } else {
                            format!("{},{label}", cell.label)
                        },
                        suite,
                    }
                })
            })
            .collect();
    }
    if parameters.is_empty() {
        cells[0].label = "base".into();
    }
    cells
}

/// What one run contributes to the report: per experiment and arm, the run's means.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSummary {
    /// The master seed.
    pub seed: u64,
    /// Trials per experiment and arm.
    pub trials: u32,
    /// Experiment name -> arm name -> means.
    pub experiments: BTreeMap<String, BTreeMap<String, ArmMeans>>,
    /// Experiments in suite order.
    pub order: Vec<String>,
    /// Arms in suite order.
    pub arms: Vec<String>,
}

/// One arm's means in one run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ArmMeans {
    /// Behaviors evaluated per trial.
    pub behaviors: f64,
    /// Commands per trial.
    pub commands: f64,
    /// Untrustworthy commands per trial.
    pub untrustworthy: f64,
    /// Share of trials that found a trustworthy behavior.
    pub found_share: f64,
    /// Trials cut off by `max_commands`.
    pub truncated: usize,
}

impl RunSummary {
    fn of(suite: &SuiteConfig, results: &SuiteResults) -> Self {
        let order: Vec<String> = suite.experiments.iter().map(|e| e.name()).collect();
        let experiments = order
            .iter()
            .zip(&results.results)
            .map(|(name, result)| {
                let arms = result
                    .arms
                    .iter()
                    .map(|a| {
                        (
                            a.name.clone(),
                            ArmMeans {
                                behaviors: a.behaviors.mean,
                                commands: a.commands.mean,
                                untrustworthy: a.untrustworthy.mean,
                                found_share: a.found_share.mean,
                                truncated: a.truncated(),
                            },
                        )
                    })
                    .collect();
                (name.clone(), arms)
            })
            .collect();
        Self {
            seed: suite.seed,
            trials: suite.trials.get(),
            experiments,
            order,
            arms: suite.arms.clone(),
        }
    }

    /// The run file's text.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("plain data serializes") + "\n"
    }
}

/// Writes `summary` as the run file of `run` in `dir`.
pub fn write_run(
    dir: &Path,
    sweep: &Sweep,
    run: RunId,
    summary: &RunSummary,
) -> Result<PathBuf, SweepError> {
    Ok(write_file_in(dir, sweep.run_file(run), &summary.to_json())?)
}

/// Writes the sweep config's text into `dir` as `sweep.ron` (every shard folder carries
/// it, so a merge can check that its folders belong to one sweep).
pub fn write_config(dir: &Path, text: &str) -> Result<PathBuf, SweepError> {
    Ok(write_file_in(dir, "sweep.ron", text)?)
}

/// Reads the run files of every run of `sweep` (whose config file says `text`) from
/// `dirs` (the first folder holding a run's file wins) and writes the report into `out`.
/// Every run must be present, and every folder must carry the same `sweep.ron`.
pub fn merge(
    sweep: &Sweep,
    text: &str,
    dirs: &[PathBuf],
    out: &Path,
) -> Result<Vec<PathBuf>, SweepError> {
    for dir in dirs {
        let path = dir.join("sweep.ron");
        if read_text(&path)? != text {
            return Err(SweepError::Run {
                path,
                message: "this folder belongs to another sweep (its sweep.ron differs)".into(),
            });
        }
    }
    let mut summaries = Vec::new();
    for run in sweep.runs() {
        let file = sweep.run_file(run);
        let Some(path) = dirs.iter().map(|d| d.join(&file)).find(|p| p.is_file()) else {
            return Err(SweepError::Run {
                path: file,
                message: format!(
                    "no shard folder holds this run (looked in {}); run the missing shard first",
                    dirs.iter()
                        .map(|d| d.display().to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            });
        };
        let text = read_text(&path)?;
        let summary: RunSummary = serde_json::from_str(&text).map_err(|e| SweepError::Run {
            path: path.clone(),
            message: e.to_string(),
        })?;
        summaries.push((run, summary));
    }
    write_report(sweep, &summaries, out)
}

/// (cell, experiment, arm) -> the per-seed mean behaviors, the per-seed mean commands, and
/// the trials cut off over all seeds.
type Series = BTreeMap<(usize, String, String), (Vec<f64>, Vec<f64>, usize)>;

/// One cell's aggregate for one experiment and arm: mean of the per-seed means and the
/// half-width of its 95% confidence interval over seeds.
fn aggregate(values: &[f64]) -> (f64, f64) {
    mean_ci95(values).map_or((0.0, 0.0), |m| (m.mean, m.ci95))
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
        "# Sweep: {} cells x {seeds} seeds\n\nBehaviors evaluated per trial: the mean over seeds of each run's mean, ± the half-width of its 95% confidence interval over seeds; commands per trial likewise. Seeds: {:?}.\n",
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
                        "| {} | {arm} | {b:.2} ± {bci:.2} | {m:.1} ± {mci:.1} | {truncated} |",
                        cell.label
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
    let mut written = Vec::new();
    let mut write = |name: &str, text: &str| -> Result<(), SweepError> {
        written.push(write_file_in(out, name, text)?);
        Ok(())
    };
    write("sweep.md", &md)?;
    let json = serde_json::json!({
        "seeds": sweep.config.seeds,
        "cells": sweep.cells.iter().map(|c| &c.label).collect::<Vec<_>>(),
        "results": json_cells,
    });
    write(
        "sweep.json",
        &(serde_json::to_string_pretty(&json).expect("plain data serializes") + "\n"),
    )?;
    if sweep.config.design == Design::OneAtATime {
        for p in &sweep.config.parameters {
            let name = format!("sweep-{}.svg", p.name());
            let svg = plot_parameter(sweep, p, &series, &order, &arm_order, &out.join(&name))?;
            write(&name, &svg)?;
        }
    }
    Ok(written)
}

/// One panel per experiment: behaviors evaluated (log scale) against the parameter's
/// values, one line per arm (its colour and marker as in every report) with its
/// confidence interval over seeds, the paper's two arms on top; the legend right of the
/// panels.
fn plot_parameter(
    sweep: &Sweep,
    parameter: &Parameter,
    series: &Series,
    order: &[String],
    arm_order: &[Vec<String>],
    path: &Path,
) -> Result<String, SweepError> {
    // The cells on this parameter's axis: the base, and those varying it, in value order.
    let prefix = format!("{}=", parameter.name());
    let mut axis: Vec<(String, usize)> = Vec::new();
    for i in 0..parameter.len() {
        let mut suite = sweep.cells[0].suite.clone();
        let label = parameter.apply(i, &mut suite);
        let cell = sweep
            .cells
            .iter()
            .position(|c| c.suite == suite && (c.label == label || c.label == "base"))
            .unwrap_or(0);
        axis.push((label.trim_start_matches(&prefix).to_owned(), cell));
    }
    let arms: Vec<String> = arm_order.first().cloned().unwrap_or_default();
    let styles: Vec<ArmStyle> = arms
        .iter()
        .enumerate()
        .map(|(k, arm)| arm_style(arm, k))
        .collect();
    let columns = order.len().clamp(1, 4);
    let rows = order.len().div_ceil(columns).max(1);
    let (panel_width, legend_width) = (340u32, 230u32);
    let size = (
        panel_width * columns as u32 + legend_width,
        300 * rows as u32 + 60,
    );
    let svg = lab::plot::svg_with(path, size, |area, overlay| {
        let (title, body) = area.split_vertically(40);
        title.titled(
            &format!(
                "Sweep over {}: behaviors evaluated (mean over {} seeds, 95% CI)",
                parameter.name(),
                sweep.config.seeds.len()
            ),
            ("sans-serif", 18),
        )?;
        let (panels_area, legend_area) = body.split_horizontally(panel_width * columns as u32);
        let panels = panels_area.split_evenly((rows, columns));
        let labels: Vec<String> = axis.iter().map(|(l, _)| l.clone()).collect();
        for (panel, experiment) in panels.iter().zip(order) {
            let mut top: f64 = 1.0;
            for (_, cell) in &axis {
                for arm in &arms {
                    if let Some((v, _, _)) = series.get(&(*cell, experiment.clone(), arm.clone())) {
                        let (m, ci) = aggregate(v);
                        top = top.max(m + ci);
                    }
                }
            }
            let n = axis.len();
            let mut chart = ChartBuilder::on(panel)
                .caption(experiment, ("sans-serif", 14))
                .margin(8)
                .margin_right(16)
                .x_label_area_size(44)
                .y_label_area_size(50)
                .build_cartesian_2d(
                    -0.5..n as f64 - 0.5,
                    (0.9f64..top * 1.3)
                        .log_scale()
                        .with_key_points(log_ticks(0.9, top * 1.3, 190)),
                )?;
            // Every `step`-th value is labelled so that labels never overlap.
            let (plot_width, _) = chart.plotting_area().dim_in_pixel();
            let widest = labels.iter().map(|l| text_width(l, 12)).max().unwrap_or(0);
            let step = ((f64::from(widest) + 6.0) * n as f64 / f64::from(plot_width.max(1)))
                .ceil()
                .max(1.0) as usize;
            let sparse: Vec<String> = labels
                .iter()
                .enumerate()
                .map(|(i, l)| {
                    if i % step == 0 {
                        l.clone()
                    } else {
                        String::new()
                    }
                })
                .collect();
            let label = category_label(&sparse);
            chart
                .configure_mesh()
                .disable_x_mesh()
                .light_line_style(TRANSPARENT)
                .x_labels(n)
                .x_label_formatter(&label)
                .y_label_formatter(&tick_label)
                .label_style(("sans-serif", 12))
                .x_desc(parameter.name())
                .y_desc("behaviors evaluated (log scale)")
                .draw()?;
            for k in drawing_order(&arms) {
                let (arm, style) = (&arms[k], styles[k]);
                let points: Vec<(f64, f64, f64)> = axis
                    .iter()
                    .enumerate()
                    .filter_map(|(x, (_, cell))| {
                        series
                            .get(&(*cell, experiment.clone(), arm.clone()))
                            .map(|(v, _, _)| {
                                let (m, ci) = aggregate(v);
                                (x as f64, m, ci)
                            })
                    })
                    .collect();
                chart.draw_series(LineSeries::new(
                    points.iter().map(|&(x, m, _)| (x, m)),
                    style.color.stroke_width(2),
                ))?;
                chart.draw_series(points.iter().map(|&(x, m, ci)| {
                    PathElement::new(
                        vec![(x, (m - ci).max(0.9)), (x, m + ci)],
                        style.color.stroke_width(1),
                    )
                }))?;
                overlay.markers(
                    style.shape,
                    Some((style.color, 1.0)),
                    Some((WHITE, 1.0)),
                    points.iter().map(|&(x, m, _)| {
                        let (px, py) = chart.backend_coord(&(x, m));
                        ((f64::from(px), f64::from(py)), 4.0)
                    }),
                );
            }
        }
        // The legend, right of the panels: each arm's line and marker.
        let (left, base) = legend_area.get_base_pixel();
        for (k, (arm, style)) in arms.iter().zip(&styles).enumerate() {
            let y = 30 + 20 * k as i32;
            legend_area.draw(&PathElement::new(
                vec![(8, y), (32, y)],
                style.color.stroke_width(2),
            ))?;
            overlay.markers(
                style.shape,
                Some((style.color, 1.0)),
                Some((WHITE, 1.0)),
                [((f64::from(left + 20), f64::from(base + y)), 4.0)],
            );
            legend_area.draw(&Text::new(
                arm.as_str(),
                (40, y - 7),
                ("sans-serif", 12).into_font(),
            ))?;
        }
        Ok(())
    });
    svg.map_err(|e| SweepError::Plot {
        path: e.path,
        message: e.message,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::UgvCatalog;

    fn sweep(text: &str) -> Sweep {
        Sweep::new(
            &UgvCatalog,
            parse_ron(text, Path::new("s.ron")).unwrap(),
            Path::new("s.ron"),
        )
        .unwrap()
    }

    #[test]
    fn cells_one_at_a_time_and_as_a_grid() {
        let s = sweep(
            "(suite: embedded, seeds: [1, 2], parameters: [lambda([0.9, 0.95]), retention([any_search, final_from_search])])",
        );
        // 0.95 and any_search are the paper's: the base cell.
        let labels: Vec<&str> = s.cells.iter().map(|c| c.label.as_str()).collect();
        assert_eq!(
            labels,
            ["base", "lambda=0.9", "retention=final_from_search"]
        );
        assert_eq!(s.runs().len(), 6);
        assert_eq!(s.cells[1].suite.adapter.lambda, 0.9);
        let g = sweep(
            "(suite: embedded, seeds: [1], design: grid, parameters: [lambda([0.9, 0.95]), time_unit([task_seconds, commands])])",
        );
        assert_eq!(g.cells.len(), 4);
        assert_eq!(g.cells[3].label, "lambda=0.95,time_unit=commands");
        assert_eq!(g.cells[3].suite.adapter.time_unit, TimeUnit::Commands);
    }

    #[test]
    fn shards_partition_the_runs() {
        let s = sweep("(suite: embedded, seeds: [1, 2, 3], parameters: [lambda([0.9, 0.8])])");
        let mut all: Vec<RunId> = (1..=4).flat_map(|i| s.shard(i, 4)).collect();
        all.sort_by_key(|r| (r.cell, r.seed));
        assert_eq!(all, s.runs());
        assert_eq!(s.shard(1, 4)[0], RunId { cell: 0, seed: 0 });
    }

    #[test]
    fn bad_sweeps_are_named() {
        let err = Sweep::new(
            &UgvCatalog,
            parse_ron(
                "(suite: embedded, seeds: [], parameters: [])",
                Path::new("s.ron"),
            )
            .unwrap(),
            Path::new("s.ron"),
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("seeds"), "{err}");
        let err = Sweep::new(
            &UgvCatalog,
            parse_ron(
                "(suite: embedded, seeds: [1], parameters: [lambda([1.5])])",
                Path::new("s.ron"),
            )
            .unwrap(),
            Path::new("s.ron"),
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("lambda=1.5"), "{err}");
    }
}
