//! The folder a sweep writes into: checked before any work, cleared of an earlier sweep
//! of another config, and marked with the sweep's `sweep.ron`.

use super::SweepError;
use files::{FileError, read_text, write_file_in};
use lab::folder::FolderRule;
use std::path::{Path, PathBuf};

/// A sweep's folder: marked by its `sweep.ron`; its report is `sweep.md`, `sweep.json`
/// and the plots, which an unmarked folder may hold too (what [`merge`](super::merge)
/// writes).
pub const SWEEP_FOLDER: FolderRule = FolderRule {
    holds: "sweep",
    marker: "sweep.ron",
    owns: is_report_file,
    unmarked_may_hold: is_report_file,
};

/// The files of a sweep's report in its folder: `sweep.md`, `sweep.json` and the plots.
fn is_report_file(name: &str) -> bool {
    name == "sweep.md"
        || name == "sweep.json"
        || (name.starts_with("sweep-") && name.ends_with(".svg"))
}

/// Checks, before any work starts, that `dir` can take a sweep's files: it is created if
/// missing, must be writable, and may hold nothing but an earlier sweep (marked by its
/// `sweep.ron`) or a report (the files [`merge`](super::merge) writes), or be empty.
pub fn prepare_dir(dir: &Path) -> Result<(), SweepError> {
    Ok(SWEEP_FOLDER.prepare(dir)?)
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
pub(super) fn remove_earlier_report(dir: &Path) -> Result<(), SweepError> {
    SWEEP_FOLDER.remove_files(dir)?;
    Ok(())
}

fn remove(path: &Path) -> Result<(), SweepError> {
    std::fs::remove_file(path).map_err(|reason| {
        SweepError::from(FileError {
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
