//! Merging the folders of a sweep's shards: every run found once (or with the same
//! bytes), each checked to be the run of its place, then the report written.

use super::runs::suite_hash;
use super::{RunId, RunSummary, Sweep, SweepError, write_report};
use files::read_text;
use lab::ArmName;
use std::path::{Path, PathBuf};

/// Reads the run files of every run of `sweep` (whose config file says `text`) from
/// `dirs` and writes the report into `out`'s report folder (`out/report`, swapped in
/// whole). Every folder must carry the same `sweep.ron`;
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

impl Sweep {
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
                ArmName::join(&summary.arms, ", "),
                suite.trials,
                experiments.join(", "),
                ArmName::join(&suite.arms, ", ")
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
