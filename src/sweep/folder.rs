//! The folder a sweep writes into: checked before any work, cleared of an earlier sweep
//! of another config, and marked with the sweep's `sweep.ron`. Its report is a folder of
//! its own in it, [`REPORT_DIR`], written whole beside its place and swapped in
//! ([`write_report`](super::write_report)): the runs stay where they are, and a report that
//! fails to write leaves the earlier one as it was.

use super::SweepError;
use files::output::ensure_writable_dir;
use files::{FileError, read_text, write_file_in};
use lab::folder::{FolderRule, ReportFolderError, foreign_entry};
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// The folder of a sweep's report in the sweep's folder (or a merge's `--out`):
/// `sweep.md`, `sweep.json` and the plots.
pub const REPORT_DIR: &str = "report";

/// A sweep's folder: marked by its `sweep.ron`, holding `runs/` and [`REPORT_DIR`]. An
/// unmarked one (a merge's) may hold the report folder; the report files it owns are
/// those earlier versions wrote into the folder itself, removed once a new report is in
/// place.
pub const SWEEP_FOLDER: FolderRule = FolderRule {
    holds: "sweep",
    marker: "sweep.ron",
    owns: is_report_file,
    unmarked_may_hold: |name| name == REPORT_DIR || is_report_file(name),
};

/// The files of a sweep's report: `sweep.md`, `sweep.json` and the plots.
fn is_report_file(name: &str) -> bool {
    name == "sweep.md"
        || name == "sweep.json"
        || (name.starts_with("sweep-") && name.ends_with(".svg"))
}

/// Checks, before any work starts, that `dir` can take a sweep's files: it is created if
/// missing, must be writable, and may hold nothing but an earlier sweep (marked by its
/// `sweep.ron`) or a report (what [`merge`](super::merge) writes), or be empty; its report
/// folder, if any, must be one (`check_report_folder`).
pub fn prepare_dir(dir: &Path) -> Result<(), SweepError> {
    SWEEP_FOLDER.prepare(dir)?;
    check_report_folder(&dir.join(REPORT_DIR))
}

/// Checks the report folder `report` of a sweep's folder, if there is one, before any work
/// and again just before a new report replaces it whole: it is a folder, not a symbolic
/// link, and holds a sweep report's files alone, none a link (anything else would go with
/// it).
pub(super) fn check_report_folder(report: &Path) -> Result<(), SweepError> {
    match fs::symlink_metadata(report) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(()),
        // Refuses a link or what is not a folder, naming it.
        _ => ensure_writable_dir(report).map_err(ReportFolderError::from)?,
    }
    let unlisted = |reason| {
        ReportFolderError::from(files::FolderError::Unwritable {
            path: report.to_owned(),
            action: "list this folder",
            reason,
        })
    };
    for entry in fs::read_dir(report).map_err(unlisted)? {
        let entry = entry.map_err(unlisted)?;
        if entry.file_type().is_ok_and(|t| t.is_symlink()) {
            return Err(ReportFolderError::Symlink { path: entry.path() }.into());
        }
    }
    match foreign_entry(report, None, is_report_file).map_err(ReportFolderError::from)? {
        Some(entry) => Err(ReportFolderError::Foreign {
            path: report.to_owned(),
            entry,
            holds: "sweep report",
            marker: "sweep.json",
        }
        .into()),
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
                    let path = run.path();
                    removed(&path, fs::remove_file(&path))?;
                }
            }
            std::fs::remove_dir(cell.path()).ok();
        }
        std::fs::remove_dir(&runs).ok();
    }
    let report = dir.join(REPORT_DIR);
    check_report_folder(&report)?;
    if report.is_dir() {
        // Checked: a folder of report files, no link (remove_dir_all follows none anyway).
        removed(&report, fs::remove_dir_all(&report))?;
    }
    remove_report_files_beside(dir)
}

/// Removes from `dir` the report files earlier versions wrote into a sweep's folder
/// itself, beside its runs: a report now lives in [`REPORT_DIR`].
pub(super) fn remove_report_files_beside(dir: &Path) -> Result<(), SweepError> {
    SWEEP_FOLDER.remove_files(dir)?;
    Ok(())
}

/// The outcome of removing `path`, as a sweep's error naming it.
fn removed(path: &Path, outcome: io::Result<()>) -> Result<(), SweepError> {
    outcome.map_err(|reason| {
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
