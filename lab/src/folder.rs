//! Report folders: what makes a folder hold a report, and the rule for writing one.
//!
//! An experiment or mission report is checked before any work starts
//! ([`prepare_output_dir`]), written whole into a fresh folder beside its target
//! ([`begin_report`]) and swapped in only once every file is written ([`finish_report`]):
//! the earlier report is removed only after the new one is in place, and a failed write
//! leaves it exactly as it was. The rule: the folder may be missing, empty, or hold an
//! earlier report (it has a `summary.json`) and nothing else; a folder holding anything
//! else, a symbolic link (as the folder or in it) is refused. Sweeps, whose folder holds
//! their runs too, check it by [`FolderRule`] and keep their report in a folder of its own
//! in it, swapped in whole the same way.

use files::FileError;
use files::output::{FolderError, ensure_writable_dir, is_temporary_name};
use files::{StagedFolder, StagingError};
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
    "provenance.json",
];

/// The extensions of a report's plots: removed with an earlier report.
pub const REPORT_PLOT_EXTENSIONS: &[&str] = &["svg", "html"];

/// The folder of a report holding the copies of the operator files its config names.
pub const REPORT_OPERATORS: &str = "operators";

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
    /// A symbolic link where the tool would write: the folder itself, or an entry of it.
    #[error(
        "{}: is a symbolic link; nothing is written through one, nor is what it points to removed: remove the link, or give another folder",
        path.display()
    )]
    Symlink {
        /// The link.
        path: PathBuf,
    },
    /// A file of an earlier report could not be removed.
    #[error(transparent)]
    Remove(#[from] FileError),
    /// The new report could not be put in place.
    #[error(transparent)]
    Staging(StagingError),
}

impl From<StagingError> for ReportFolderError {
    fn from(error: StagingError) -> Self {
        match error {
            StagingError::Symlink { path } => Self::Symlink { path },
            other => Self::Staging(other),
        }
    }
}

impl FolderRule {
    /// Checks, before any work starts, that `dir` can take this kind of report: as
    /// [`ensure_writable_dir`], and refuses a folder that holds anything but an earlier one
    /// (marked by [`FolderRule::marker`]) or what an unmarked folder may hold, and a folder
    /// that is, or holds, a symbolic link. Writes nothing but the folder.
    pub fn prepare(&self, dir: &Path) -> Result<(), ReportFolderError> {
        ensure_writable_dir(dir)?;
        if let Some(link) = first_symlink(dir)? {
            return Err(ReportFolderError::Symlink { path: link });
        }
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

/// The first entry of the folder `dir` that is a symbolic link, if any.
fn first_symlink(dir: &Path) -> Result<Option<PathBuf>, FolderError> {
    let listing = fs::read_dir(dir).map_err(|reason| FolderError::Unwritable {
        path: dir.to_owned(),
        action: "list this folder",
        reason,
    })?;
    Ok(listing
        .flatten()
        .find(|e| e.file_type().is_ok_and(|t| t.is_symlink()))
        .map(|e| e.path()))
}

/// Checks, before any work starts, that a report can be written at `dir`: it is not a
/// symbolic link, and is missing, an empty folder, or a folder holding an earlier report
/// (marked by its [`REPORT_MARKER`]) and nothing else: its files ([`REPORT_FILES`], the
/// plots), its [`REPORT_OPERATORS`] folder and temporary files of an interrupted write;
/// no entry a symbolic link. A fresh folder is made beside it and removed, to find out
/// that the new report can be written there (its parent folders are created). Changes
/// nothing else.
pub fn prepare_output_dir(dir: &Path) -> Result<(), ReportFolderError> {
    check_earlier_report(dir)?;
    drop(StagedFolder::beside(dir)?);
    Ok(())
}

/// The check of [`prepare_output_dir`], without the probe: asked again just before the
/// new report replaces the folder.
fn check_earlier_report(dir: &Path) -> Result<(), ReportFolderError> {
    let meta = match fs::symlink_metadata(dir) {
        Ok(meta) if meta.file_type().is_symlink() => {
            return Err(ReportFolderError::Symlink {
                path: dir.to_owned(),
            });
        }
        Ok(meta) => meta,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(()),
        Err(reason) => {
            return Err(FolderError::Unwritable {
                path: dir.to_owned(),
                action: "look at this folder",
                reason,
            }
            .into());
        }
    };
    if !meta.is_dir() {
        // Refused as a folder that cannot take files is, naming what it is.
        ensure_writable_dir(dir)?;
    }
    if let Some(link) = first_symlink(dir)? {
        return Err(ReportFolderError::Symlink { path: link });
    }
    let is_operators = |name: &str| {
        name == REPORT_OPERATORS && fs::symlink_metadata(dir.join(name)).is_ok_and(|m| m.is_dir())
    };
    let marked = dir.join(REPORT_MARKER).is_file();
    let entry = foreign_entry(dir, None, |name| {
        marked && (is_report_file(name) || is_operators(name))
    })?;
    match entry {
        Some(entry) => Err(ReportFolderError::Foreign {
            path: dir.to_owned(),
            entry,
            holds: REPORT.holds,
            marker: REPORT.marker,
        }),
        None => Ok(()),
    }
}

/// Starts writing a report at `dir`: checks it ([`prepare_output_dir`]) and makes the
/// fresh folder beside it that the report's files are written into
/// ([`StagedFolder::path`]). Dropped, the folder is removed and `dir` stays as it was;
/// [`finish_report`] swaps it in.
pub fn begin_report(dir: &Path) -> Result<StagedFolder, ReportFolderError> {
    check_earlier_report(dir)?;
    Ok(StagedFolder::beside(dir)?)
}

/// Puts a report written whole into `staged` in place of its target: the target checked
/// again as [`prepare_output_dir`] does (it may have changed while the report ran), the
/// earlier report moved aside, the new one renamed in, then the earlier one removed.
/// Returns the report's folder.
pub fn finish_report(staged: StagedFolder) -> Result<PathBuf, ReportFolderError> {
    check_earlier_report(staged.target())?;
    Ok(staged.commit()?)
}

/// `paths` of files written into `staged`'s folder, as they are named once it is in
/// place.
pub fn in_place(staged: &StagedFolder, paths: Vec<PathBuf>) -> Vec<PathBuf> {
    paths
        .into_iter()
        .map(|p| match p.strip_prefix(staged.path()) {
            Ok(rest) => staged.target().join(rest),
            Err(_) => p,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::os::unix::fs::symlink;

    fn names_in(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn a_missing_report_folder_is_accepted_and_an_empty_one_too() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("a/b/report");
        prepare_output_dir(&out).unwrap();
        let parent = dir.path().join("a/b");
        assert!(names_in(&parent).is_empty(), "the probe folder is removed");
        fs::create_dir(&out).unwrap();
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
        let err = prepare_output_dir(Path::new("/proc/self/report")).unwrap_err();
        assert!(
            err.to_string()
                .starts_with("/proc/self: cannot create a folder in this folder: "),
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
    fn an_earlier_report_holding_other_files_or_links_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("report");
        fs::create_dir(&out).unwrap();
        fs::write(out.join("summary.json"), b"{}").unwrap();
        fs::write(out.join("notes.txt"), b"mine").unwrap();
        let err = begin_report(&out).unwrap_err();
        assert!(matches!(&err, ReportFolderError::Foreign { entry, .. } if entry == "notes.txt"));
        fs::remove_file(out.join("notes.txt")).unwrap();
        let outside = dir.path().join("outside.md");
        fs::write(&outside, b"precious").unwrap();
        symlink(&outside, out.join("table.md")).unwrap();
        let err = begin_report(&out).unwrap_err();
        assert!(
            matches!(&err, ReportFolderError::Symlink { path } if path.ends_with("table.md")),
            "{err}"
        );
        let link = dir.path().join("link");
        symlink(&out, &link).unwrap();
        let err = prepare_output_dir(&link).unwrap_err();
        assert!(
            err.to_string()
                .starts_with(&format!("{}: is a symbolic link;", link.display())),
            "{err}"
        );
        assert_eq!(fs::read(&outside).unwrap(), b"precious");
        assert_eq!(names_in(dir.path()), ["link", "outside.md", "report"]);
    }

    #[test]
    fn an_earlier_report_is_replaced_whole_and_kept_when_the_new_one_fails() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("report");
        fs::create_dir_all(out.join(REPORT_OPERATORS)).unwrap();
        for name in [
            "summary.json",
            "table.md",
            "curves-a.svg",
            "operators/x.ron",
        ] {
            fs::write(out.join(name), b"old").unwrap();
        }
        // A failed write: the staged folder dropped.
        let staged = begin_report(&out).unwrap();
        fs::write(staged.path().join("summary.json"), b"half").unwrap();
        drop(staged);
        assert_eq!(
            names_in(&out),
            ["curves-a.svg", "operators", "summary.json", "table.md"]
        );
        assert_eq!(fs::read(out.join("summary.json")).unwrap(), b"old");
        assert_eq!(names_in(dir.path()), ["report"]);
        let staged = begin_report(&out).unwrap();
        let written = files::write_file_in(staged.path(), "summary.json", "new").unwrap();
        let written = in_place(&staged, vec![written]);
        assert_eq!(written, [out.join("summary.json")]);
        finish_report(staged).unwrap();
        assert_eq!(names_in(&out), ["summary.json"]);
        assert_eq!(fs::read(out.join("summary.json")).unwrap(), b"new");
        assert_eq!(names_in(dir.path()), ["report"]);
    }

    #[test]
    fn temporary_files_of_an_interrupted_write_do_not_make_a_folder_foreign() {
        let dir = tempfile::tempdir().unwrap();
        fs::write(dir.path().join(".summary.json.tmp-99999999-abc"), b"x").unwrap();
        prepare_output_dir(dir.path()).unwrap();
    }

    #[test]
    fn a_sweep_like_folder_holding_a_link_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        symlink("/etc/hostname", dir.path().join("sweep.md")).unwrap();
        let err = REPORT.prepare(dir.path()).unwrap_err();
        assert!(matches!(err, ReportFolderError::Symlink { .. }), "{err}");
    }
}
