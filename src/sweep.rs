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
use files::output::{FolderError, ensure_writable_dir};
use files::{FileError, RonError, parse_ron, read_text, write_file_in};
use lab::plot::{ArmStyle, arm_style, drawing_order, log_ticks, sparse_labels, tick_label};
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

/// The most trials a sweep may run in all, over its runs (each run's experiments x arms x
/// trials; a run itself is held to [`crate::suite::MAX_SUITE_TRIALS`]): runs go one after
/// the other, so this bounds time, not memory; at the 1,600 trials a second of
/// `reproduce` on the two cores of the machine of `docs/results.md`, about 2 hours.
pub const MAX_SWEEP_TRIALS: u64 = 10_000_000;

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

    /// Value `i` as labels show it, e.g. `0.9`.
    fn value(&self, i: usize) -> String {
        match self {
            Parameter::Lambda(v) => v[i].to_string(),
            Parameter::Thresholds(v) => format!("{}/{}", v[i].trustworthy, v[i].untrustworthy),
            Parameter::Retention(v) => ron_name(&v[i]),
            Parameter::TimeUnit(v) => ron_name(&v[i]),
            Parameter::Reading(_, v) => v[i].clone(),
            Parameter::Arms(v) => v[i].join("+"),
        }
    }

    /// The first value listed twice (after an equal one), if any.
    fn repeated(&self) -> Option<usize> {
        fn first<T: PartialEq>(values: &[T]) -> Option<usize> {
            (1..values.len()).find(|&j| values[..j].contains(&values[j]))
        }
        match self {
            Parameter::Lambda(v) => first(v),
            Parameter::Thresholds(v) => first(v),
            Parameter::Retention(v) => first(v),
            Parameter::TimeUnit(v) => first(v),
            Parameter::Reading(_, v) => first(v),
            Parameter::Arms(v) => first(v),
        }
    }

    /// Whether value `i` is the one `base` has already.
    fn is_in(&self, i: usize, base: &SuiteConfig) -> bool {
        match self {
            Parameter::Lambda(v) => v[i] == base.adapter.lambda,
            Parameter::Thresholds(v) => v[i] == base.adapter.thresholds,
            Parameter::Retention(v) => v[i] == base.adapter.retention,
            Parameter::TimeUnit(v) => v[i] == base.adapter.time_unit,
            Parameter::Reading(name, v) => base.readings.get(name) == Some(&v[i]),
            Parameter::Arms(v) => v[i] == base.arms,
        }
    }

    /// Sets value `i` in `suite`; returns its label, e.g. `lambda=0.9`.
    fn apply(&self, i: usize, suite: &mut SuiteConfig) -> String {
        match self {
            Parameter::Lambda(v) => suite.adapter.lambda = v[i],
            Parameter::Thresholds(v) => suite.adapter.thresholds = v[i],
            Parameter::Retention(v) => suite.adapter.retention = v[i],
            Parameter::TimeUnit(v) => suite.adapter.time_unit = v[i],
            Parameter::Reading(name, v) => {
                suite.readings.insert(name.clone(), v[i].clone());
            }
            Parameter::Arms(v) => suite.arms.clone_from(&v[i]),
        }
        format!("{}={}", self.name(), self.value(i))
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
    /// A run file is unreadable, or does not belong in its place, when merging.
    #[error("{path}: {message}")]
    Run {
        /// The run file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// Runs no folder holds, when merging.
    #[error(
        "{} of {total} runs are in none of the folders ({}): {}; run the shards that hold them first",
        runs.len(),
        folders.iter().map(|d| d.display().to_string()).collect::<Vec<_>>().join(", "),
        runs.iter().map(|r| r.display().to_string()).collect::<Vec<_>>().join(", ")
    )]
    Missing {
        /// The missing run files, relative to a folder.
        runs: Vec<PathBuf>,
        /// How many runs the sweep has.
        total: usize,
        /// The folders looked in.
        folders: Vec<PathBuf>,
    },
    /// A folder for a sweep's files cannot be used.
    #[error(transparent)]
    Output(#[from] FolderError),
    /// A folder for a sweep's files holds other files.
    #[error(
        "{}: the folder holds `{entry}`, which is not part of a trustcbr sweep; give an empty or new folder, or one holding an earlier sweep (with its sweep.ron)",
        path.display()
    )]
    Foreign {
        /// The folder.
        path: PathBuf,
        /// The first entry that is not a sweep's.
        entry: String,
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
        if let Some(j) =
            (1..config.seeds.len()).find(|&j| config.seeds[..j].contains(&config.seeds[j]))
        {
            return Err(invalid(
                "seeds",
                format!(
                    "seed {} is listed twice; each seed runs every cell once",
                    config.seeds[j]
                ),
            ));
        }
        for (i, p) in config.parameters.iter().enumerate() {
            if p.len() == 0 {
                return Err(invalid(
                    &format!("parameters[{i}]"),
                    format!("{} lists no value", p.name()),
                ));
            }
            if let Some(j) = p.repeated() {
                return Err(invalid(
                    &format!("parameters[{i}]"),
                    format!("{} lists {} twice", p.name(), p.value(j)),
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
        // Counted before any cell is built: a grid of a few long lists has more cells than
        // memory holds.
        let cells = match config.design {
            Design::OneAtATime => config.parameters.iter().fold(1usize, |n, p| {
                n.saturating_add((0..p.len()).filter(|&i| !p.is_in(i, &base)).count())
            }),
            Design::Grid => config
                .parameters
                .iter()
                .fold(1usize, |n, p| n.saturating_mul(p.len())),
        };
        let runs = cells.saturating_mul(config.seeds.len());
        if runs > MAX_RUNS {
            let design = match config.design {
                Design::OneAtATime => "the base and each value it does not have",
                Design::Grid => "every combination of the values",
            };
            return Err(invalid(
                "parameters",
                format!(
                    "{runs} runs ({cells} cells, {design}, x {} seeds); at most {MAX_RUNS}",
                    config.seeds.len()
                ),
            ));
        }
        let cells = match config.design {
            Design::OneAtATime => one_at_a_time(&base, &config.parameters),
            Design::Grid => grid(&base, &config.parameters),
        };
        let trials = cells.iter().fold(0u64, |sum, cell| {
            let suite = &cell.suite;
            sum.saturating_add(
                suite.experiments.len() as u64
                    * suite.arms.len() as u64
                    * u64::from(suite.trials.get())
                    * config.seeds.len() as u64,
            )
        });
        if trials > MAX_SWEEP_TRIALS {
            return Err(invalid(
                "parameters",
                format!(
                    "{trials} trials in all (per cell: experiments x arms x trials, x {} seeds); at most {MAX_SWEEP_TRIALS}",
                    config.seeds.len()
                ),
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
        Ok(RunSummary::of(&cell.label, &suite, &results))
    }

    /// Checks that `summary`, read from a run file, is the summary of `run`: its cell,
    /// seed, suite (by content hash: the sweep and its suite file as they are now), trials,
    /// experiments and arms, and values a run can have. Says what does not fit.
    fn check_run(&self, run: RunId, summary: &RunSummary) -> Result<(), String> {
        let cell = &self.cells[run.cell];
        let seed = self.config.seeds[run.seed];
        if summary.cell != cell.label || summary.seed != seed {
            return Err(format!(
                "this is the run of cell `{}`, seed {}, not of cell `{}`, seed {} whose place it holds",
                summary.cell, summary.seed, cell.label, seed
            ));
        }
        let mut suite = cell.suite.clone();
        suite.seed = seed;
        if summary.suite != suite_hash(&suite) {
            return Err(
                "this run was made from another suite than the sweep's (the sweep, its suite file or the folder's runs are of another version); run it again".into(),
            );
        }
        let experiments: Vec<String> = suite.experiments.iter().map(|e| e.name()).collect();
        if summary.trials != suite.trials.get()
            || summary.order != experiments
            || summary.arms != suite.arms
        {
            return Err(format!(
                "holds {} trials of experiments [{}] and arms [{}]; this cell runs {} trials of [{}] and [{}]",
                summary.trials,
                summary.order.join(", "),
                summary.arms.join(", "),
                suite.trials,
                experiments.join(", "),
                suite.arms.join(", ")
            ));
        }
        let shape_fits = summary.experiments.len() == experiments.len()
            && experiments.iter().all(|e| {
                summary.experiments.get(e).is_some_and(|arms| {
                    arms.len() == suite.arms.len()
                        && suite.arms.iter().all(|a| arms.contains_key(a))
                })
            });
        if !shape_fits {
            return Err("its results do not cover every experiment and arm exactly once".into());
        }
        // No trial evaluates more behaviors or gives more commands than `max_commands`.
        let most = suite.max_commands as f64;
        for (experiment, arms) in &summary.experiments {
            for (arm, means) in arms {
                let counts = [
                    ("behaviors", means.behaviors, most),
                    ("commands", means.commands, most),
                    ("untrustworthy", means.untrustworthy, most),
                    ("found_share", means.found_share, 1.0),
                ];
                for (field, value, top) in counts {
                    if !(0.0..=top).contains(&value) {
                        return Err(format!(
                            "experiment `{experiment}`, arm `{arm}`: {field} must be a number from 0 to {top}, got {value:?}"
                        ));
                    }
                }
                if means.truncated > summary.trials as usize {
                    return Err(format!(
                        "experiment `{experiment}`, arm `{arm}`: truncated must be 0 to {}, got {}",
                        summary.trials, means.truncated
                    ));
                }
            }
        }
        Ok(())
    }
}

/// A content hash of the suite a run runs (FNV-1a over its RON text), recorded in the run
/// file so that a merge takes no run of another suite.
fn suite_hash(suite: &SuiteConfig) -> String {
    let text = ron::to_string(suite).expect("plain data serializes");
    let hash = text.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    });
    format!("{hash:016x}")
}

fn one_at_a_time(base: &SuiteConfig, parameters: &[Parameter]) -> Vec<Cell> {
    let mut cells = vec![Cell {
        label: "base".into(),
        suite: base.clone(),
    }];
    for p in parameters {
        // A value equal to the base's is the base cell itself.
        for i in (0..p.len()).filter(|&i| !p.is_in(i, base)) {
            let mut suite = base.clone();
            let label = p.apply(i, &mut suite);
            cells.push(Cell { label, suite });
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
    /// The cell's label.
    pub cell: String,
    /// The master seed.
    pub seed: u64,
    /// The content hash of the suite run (the cell's, with this seed).
    pub suite: String,
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
    fn of(cell: &str, suite: &SuiteConfig, results: &SuiteResults) -> Self {
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
            cell: cell.to_owned(),
            seed: suite.seed,
            suite: suite_hash(suite),
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

/// The files of a sweep's report in its folder: `sweep.md`, `sweep.json` and the plots.
fn is_report_file(name: &str) -> bool {
    name == "sweep.md"
        || name == "sweep.json"
        || (name.starts_with("sweep-") && name.ends_with(".svg"))
}

/// Checks, before any work starts, that `dir` can take a sweep's files: it is created if
/// missing, must be writable, and may hold nothing but an earlier sweep (marked by its
/// `sweep.ron`) or a report (the files [`merge`] writes), or be empty.
pub fn prepare_dir(dir: &Path) -> Result<(), SweepError> {
    ensure_writable_dir(dir)?;
    let listed = |reason| FileError {
        path: dir.to_owned(),
        reason,
    };
    let entries: Vec<String> = std::fs::read_dir(dir)
        .map_err(listed)?
        .map(|e| e.map(|e| e.file_name().to_string_lossy().into_owned()))
        .collect::<std::io::Result<_>>()
        .map_err(listed)?;
    if entries.iter().any(|name| name == "sweep.ron") {
        return Ok(());
    }
    // Temporary files an interrupted atomic write may leave (`.NAME.tmp-...`).
    let ours =
        |name: &str| is_report_file(name) || (name.starts_with('.') && name.contains(".tmp-"));
    match entries.into_iter().find(|name| !ours(name)) {
        Some(entry) => Err(SweepError::Foreign {
            path: dir.to_owned(),
            entry,
        }),
        None => Ok(()),
    }
}

/// Removes from `dir` the run files (`runs/CELL/seed-SEED.json`, and the folders they
/// leave empty) and report of an earlier sweep of another config than `text`, so that a
/// folder reused for another sweep holds nothing of the old one. Runs of the same sweep
/// stay (shards may share a folder); so do files that are not a sweep's.
pub fn remove_earlier_sweep(dir: &Path, text: &str) -> Result<(), SweepError> {
    let Ok(earlier) = read_text(&dir.join("sweep.ron")) else {
        return Ok(());
    };
    if earlier == text {
        return Ok(());
    }
    let runs = dir.join("runs");
    if let Ok(cells) = std::fs::read_dir(&runs) {
        for cell in cells
            .flatten()
            .filter(|c| c.file_type().is_ok_and(|t| t.is_dir()))
        {
            for run in std::fs::read_dir(cell.path())
                .into_iter()
                .flatten()
                .flatten()
            {
                let name = run.file_name().to_string_lossy().into_owned();
                if name.starts_with("seed-") && name.ends_with(".json") {
                    remove(&run.path())?;
                }
            }
            std::fs::remove_dir(cell.path()).ok();
        }
        std::fs::remove_dir(&runs).ok();
    }
    remove_earlier_report(dir)
}

/// Removes an earlier sweep report's files from `dir`.
fn remove_earlier_report(dir: &Path) -> Result<(), SweepError> {
    for entry in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        if is_report_file(&name) && entry.file_type().is_ok_and(|t| t.is_file()) {
            remove(&entry.path())?;
        }
    }
    Ok(())
}

fn remove(path: &Path) -> Result<(), SweepError> {
    std::fs::remove_file(path).map_err(|reason| {
        SweepError::Io(FileError {
            path: path.to_owned(),
            reason,
        })
    })
}

/// Writes the sweep config's text into `dir` as `sweep.ron` (every shard folder carries
/// it, so a merge can check that its folders belong to one sweep).
pub fn write_config(dir: &Path, text: &str) -> Result<PathBuf, SweepError> {
    Ok(write_file_in(dir, "sweep.ron", text)?)
}

/// Reads the run files of every run of `sweep` (whose config file says `text`) from
/// `dirs` and writes the report into `out`. Every folder must carry the same `sweep.ron`;
/// every run must be in some folder (all missing runs are named), and where several hold
/// it, with the same bytes; every run file must be the run of its place (its cell, seed,
/// suite content hash, trials, experiments and arms, and values a run can have). Nothing
/// is written unless all of it holds.
pub fn merge(
    sweep: &Sweep,
    text: &str,
    dirs: &[PathBuf],
    out: &Path,
) -> Result<Vec<PathBuf>, SweepError> {
    for dir in dirs {
        let path = dir.join("sweep.ron");
        // A shard that failed before writing anything leaves an empty folder, or none: it
        // holds no run, and its runs are named below as missing.
        let empty = std::fs::read_dir(dir).map_or(true, |mut entries| entries.next().is_none());
        if empty {
            continue;
        }
        if read_text(&path)? != text {
            return Err(SweepError::Run {
                path,
                message: "this folder belongs to another sweep (its sweep.ron differs)".into(),
            });
        }
    }
    let mut summaries = Vec::new();
    let mut missing = Vec::new();
    for run in sweep.runs() {
        let file = sweep.run_file(run);
        let mut found: Option<(PathBuf, String)> = None;
        for path in dirs.iter().map(|d| d.join(&file)).filter(|p| p.is_file()) {
            let text = read_text(&path)?;
            match &found {
                None => found = Some((path, text)),
                Some((first, first_text)) if *first_text != text => {
                    return Err(SweepError::Run {
                        message: format!(
                            "differs from {}: two versions of one run; remove the wrong one",
                            first.display()
                        ),
                        path,
                    });
                }
                Some(_) => {}
            }
        }
        let Some((path, text)) = found else {
            missing.push(file);
            continue;
        };
        let summary: RunSummary = serde_json::from_str(&text).map_err(|e| SweepError::Run {
            path: path.clone(),
            message: e.to_string(),
        })?;
        sweep
            .check_run(run, &summary)
            .map_err(|message| SweepError::Run { path, message })?;
        summaries.push((run, summary));
    }
    if !missing.is_empty() {
        return Err(SweepError::Missing {
            runs: missing,
            total: sweep.runs().len(),
            folders: dirs.to_vec(),
        });
    }
    write_report(sweep, &summaries, out)
}

/// (cell, experiment, arm) -> the per-seed mean behaviors, the per-seed mean commands, and
/// the trials cut off over all seeds.
type Series = BTreeMap<(usize, String, String), (Vec<f64>, Vec<f64>, usize)>;

/// One cell's aggregate for one experiment and arm: mean of the per-seed means and the
/// half-width of its 95% confidence interval over seeds (none from a single seed).
fn aggregate(values: &[f64]) -> (f64, Option<f64>) {
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
                        top = top.max(m + ci.unwrap_or(0.0));
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
            let cell_width = f64::from(plot_width.max(1)) / n as f64;
            let sparse = sparse_labels(&labels, 12, 6.0, cell_width);
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
                let points: Vec<(f64, f64, Option<f64>)> = axis
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
                chart.draw_series(points.iter().filter_map(|&(x, m, ci)| {
                    ci.map(|ci| {
                        PathElement::new(
                            vec![(x, (m - ci).max(0.9)), (x, m + ci)],
                            style.color.stroke_width(1),
                        )
                    })
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
