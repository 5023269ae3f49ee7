//! One run of a sweep (a cell's suite with one seed): running it, its summary (each
//! experiment and arm's means) and its run file, `runs/CELL/seed-SEED.json`.

use super::{RunId, Sweep, SweepError};
use crate::catalog::Catalog;
use crate::config_file::content_hash;
use crate::suite::{SuiteConfig, SuiteResults, run_suite};
use files::write_file_in;
use lab::ArmName;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

impl Sweep {
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
}

/// A content hash of the suite a run runs (FNV-1a over its RON text), recorded in the run
/// file so that a merge takes no run of another suite.
pub(super) fn suite_hash(suite: &SuiteConfig) -> String {
    content_hash(
        ron::to_string(suite)
            .expect("plain data serializes")
            .as_bytes(),
    )
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
    pub experiments: BTreeMap<String, BTreeMap<ArmName, ArmMeans>>,
    /// Experiments in suite order.
    pub order: Vec<String>,
    /// Arms in suite order.
    pub arms: Vec<ArmName>,
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
