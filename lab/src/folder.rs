//! Report folders: what makes a folder hold a report, and the rule for writing one.
//!
//! A report folder is checked before any work starts ([`prepare_output_dir`]) and an
//! earlier report in it is removed before the new one is written
//! ([`remove_previous_report`]), so a report never mixes with another's files. The rule:
//! the folder may be missing (it is created), empty, or hold an earlier report (it has a
//! `summary.json`); a folder holding anything else is refused. Every kind of report
//! (experiments, missions, sweeps) follows it.

use files::FileError;
use files::output::{FolderError, ensure_writable_dir, is_temporary_name};
use std::ffi::OsStr;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// The file that marks a folder as holding a report.
pub const REPORT_MARKER: &str = "summary.json";

/// The files of a report, besides its plots: removed with an earlier report.
pub const REPORT_FILES: &[&str] = &[
    "summary.json",
    "table.md",
    "trials.jsonl",
    "config.ron",
    "missions.md",
    "missions.jsonl",
];

/// The extensions of a report's plots: removed with an earlier report.
pub const REPORT_PLOT_EXTENSIONS: &[&str] = &["svg", "html"];

/// What makes a folder hold one kind of report, and which of its files are that report's:
/// the one rule every kind of report folder follows (experiments and missions
/// ([`REPORT`]), sweeps).
#[derive(Clone, Copy, Debug)]
pub struct FolderRule {
    /// What the folder holds, as messages name it: `report`, `sweep`.
    pub holds: &'static str,
    /// The file that marks a folder as holding one.
    pub marker: &'static str,
    /// Whether a file, by name, is part of one (removed with an earlier one).
    pub owns: fn(&str) -> bool,
    /// Whether an unmarked folder may hold a file of this name and still be written in
    /// (besides the temporary files an interrupted write leaves).
    pub unmarked_may_hold: fn(&str) -> bool,
}

/// Experiment and mission reports: marked by their `summary.json`; an unmarked folder must
/// be empty.
pub const REPORT: FolderRule = FolderRule {
    holds: "report",
    marker: REPORT_MARKER,
    owns: is_report_file,
    unmarked_may_hold: |_| false,
};

/// Whether `name` is one of [`REPORT_FILES`] or a plot ([`REPORT_PLOT_EXTENSIONS`]).
fn is_report_file(name: &str) -> bool {
    let is_plot = Path::new(name)
        .extension()
        .and_then(OsStr::to_str)
        .is_some_and(|ext| REPORT_PLOT_EXTENSIONS.contains(&ext));
    REPORT_FILES.contains(&name) || is_plot
}

/// Why a report folder cannot be used.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReportFolderError {
    /// The folder cannot take files.
    #[error(transparent)]
    Folder(#[from] FolderError),
    /// The folder holds files that are not part of a report.
    #[error(
        "{}: the folder holds `{entry}`, which is not part of a trustcbr {holds}; give an empty or new folder, or one holding an earlier {holds} (with its {marker})",
        path.display()
    )]
    Foreign {
        /// The folder.
        path: PathBuf,
        /// One entry that is not part of a report.
        entry: String,
        /// What the folder was to hold ([`FolderRule::holds`]).
        holds: &'static str,
        /// Its marker file ([`FolderRule::marker`]).
        marker: &'static str,
    },
    /// A file of an earlier report could not be removed.
    #[error(transparent)]
    Remove(#[from] FileError),
}

impl FolderRule {
    /// Checks, before any work starts, that `dir` can take this kind of report: as
    /// [`ensure_writable_dir`], and refuses a folder that holds anything but an earlier one
    /// (marked by [`FolderRule::marker`]) or what an unmarked folder may hold. Writes
    /// nothing but the folder.
    pub fn prepare(&self, dir: &Path) -> Result<(), ReportFolderError> {
        ensure_writable_dir(dir)?;
        match foreign_entry(dir, Some(self.marker), self.unmarked_may_hold)? {
            Some(entry) => Err(ReportFolderError::Foreign {
                path: dir.to_owned(),
                entry,
                holds: self.holds,
                marker: self.marker,
            }),
            None => Ok(()),
        }
    }

    /// Removes the files this kind of report owns ([`FolderRule::owns`]) from `dir`;
    /// other files and folders stay. Returns the files removed, in order.
    pub fn remove_files(&self, dir: &Path) -> Result<Vec<PathBuf>, ReportFolderError> {
        let listing = fs::read_dir(dir).map_err(|reason| FolderError::Unwritable {
            path: dir.to_owned(),
            action: "list this folder",
            reason,
        })?;
        let mut removed = Vec::new();
        for entry in listing.flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            let is_file = entry.file_type().is_ok_and(|t| t.is_file());
            if is_file && (self.owns)(&name) {
                let path = entry.path();
                fs::remove_file(&path).map_err(|reason| FileError {
                    path: path.clone(),
                    reason,
                })?;
                removed.push(path);
            }
        }
        removed.sort();
        Ok(removed)
    }
}

/// The first entry of the folder `dir` that may not be there: none when the folder holds
/// `marker` (it holds what it is meant to); otherwise the first that is neither a
/// temporary file of an interrupted write nor one `may_hold` accepts.
pub fn foreign_entry(
    dir: &Path,
    marker: Option<&str>,
    may_hold: impl Fn(&str) -> bool,
) -> Result<Option<String>, FolderError> {
    let unwritable = |reason| FolderError::Unwritable {
        path: dir.to_owned(),
        action: "list this folder",
        reason,
    };
    let entries: Vec<String> = fs::read_dir(dir)
        .map_err(unwritable)?
        .map(|entry| entry.map(|e| e.file_name().to_string_lossy().into_owned()))
        .collect::<io::Result<_>>()
        .map_err(unwritable)?;
    if marker.is_some_and(|m| entries.iter().any(|name| name == m)) {
        return Ok(None);
    }
    Ok(entries
        .into_iter()
        .find(|name| !is_temporary_name(name) && !may_hold(name)))
}

/// Checks, before any work starts, that a report can be written in `dir`
/// ([`FolderRule::prepare`] of [`REPORT`]).
pub fn prepare_output_dir(dir: &Path) -> Result<(), ReportFolderError> {
    REPORT.prepare(dir)
}

/// Removes the files of an earlier report from `dir`, only if it holds one (marked by its
/// [`REPORT_MARKER`]): [`REPORT_FILES`] and the plots ([`REPORT_PLOT_EXTENSIONS`]). Other
/// files stay. Returns the files removed.
pub fn remove_previous_report(dir: &Path) -> Result<Vec<PathBuf>, ReportFolderError> {
    if !dir.join(REPORT_MARKER).is_file() {
        return Ok(Vec::new());
    }
    REPORT.remove_files(dir)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names_in(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn a_missing_report_folder_is_created_and_an_empty_one_accepted() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("a/b/report");
        prepare_output_dir(&out).unwrap();
        assert!(out.is_dir());
        assert!(names_in(&out).is_empty(), "the probe file is removed");
        prepare_output_dir(&out).unwrap();
    }

    #[test]
    fn a_file_an_unwritable_folder_and_foreign_files_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("report");
        fs::write(&file, b"x").unwrap();
        let err = prepare_output_dir(&file).unwrap_err();
        assert_eq!(
            err.to_string(),
            format!(
                "{}: exists and is a regular file, not a folder for the report",
                file.display()
            )
        );
        let err = prepare_output_dir(Path::new("/dev/null")).unwrap_err();
        assert!(err.to_string().contains("is a character device"), "{err}");
        // Not writable even by root.
        let err = prepare_output_dir(Path::new("/proc/self")).unwrap_err();
        assert!(
            err.to_string()
                .starts_with("/proc/self: cannot create a file in this folder: "),
            "{err}"
        );
        let notes = dir.path().join("notes");
        fs::create_dir(&notes).unwrap();
        fs::write(notes.join("todo.txt"), b"keep").unwrap();
        let err = prepare_output_dir(&notes).unwrap_err();
        assert!(matches!(&err, ReportFolderError::Foreign { entry, .. } if entry == "todo.txt"));
        assert_eq!(names_in(&notes), ["todo.txt"]);
    }

    #[test]
    fn an_earlier_report_is_accepted_and_removed_file_by_file() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path();
        for name in [
            "summary.json",
            "table.md",
            "trials.jsonl",
            "config.ron",
            "curves-movement-balanced.svg",
            "index.html",
            "notes.txt",
            ".table.md.tmp-99999999-abc",
        ] {
            fs::write(out.join(name), b"old").unwrap();
        }
        fs::create_dir(out.join("plots.svg")).unwrap();
        prepare_output_dir(out).unwrap();
        let removed = remove_previous_report(out).unwrap();
        assert_eq!(removed.len(), 6);
        assert_eq!(
            names_in(out),
            [".table.md.tmp-99999999-abc", "notes.txt", "plots.svg"]
        );
        // Without its summary the folder no longer holds a report: nothing more goes.
        assert!(remove_previous_report(out).unwrap().is_empty());
        assert!(matches!(
            prepare_output_dir(out),
            Err(ReportFolderError::Foreign { .. })
        ));
    }

    #[test]
    fn temporary_files_of_an_interrupted_write_do_not_make_a_folder_foreign() {
        let dir = tempfile::tempdir().unwrap();
        fs::write(dir.path().join(".summary.json.tmp-99999999-abc"), b"x").unwrap();
        prepare_output_dir(dir.path()).unwrap();
    }
}
