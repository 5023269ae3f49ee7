//! A folder written whole beside its target, then swapped in.
//!
//! [`StagedFolder::beside`] creates a fresh, empty folder next to the target (same parent,
//! so renames between them are atomic), named `.NAME.tmp-PID-RANDOM` like the temporary
//! files of [`write_no_follow`](crate::write_no_follow) (so
//! [`is_temporary_name`](crate::output::is_temporary_name) recognizes it). The writer
//! fills it; [`StagedFolder::commit`] moves the earlier folder aside, renames the new one
//! into its place and only then removes the earlier one. Dropped without a commit (a
//! write failed), the new folder is removed and the target is left exactly as it was.
//! Nothing is written through a symbolic link: the target may not be one, and every file
//! goes into the folder this module created.

use crate::input::special_file_kind;
use crate::output::{FolderError, folder_of, remove_stale_temporaries, temporary_prefix};
use std::collections::hash_map::RandomState;
use std::ffi::OsString;
use std::fs;
use std::hash::{BuildHasher, Hasher};
use std::io;
use std::os::unix::fs::DirBuilderExt;
use std::path::{Path, PathBuf};

/// A fresh folder beside `target`, to be swapped in whole ([`StagedFolder::commit`]) or
/// removed (dropped).
#[derive(Debug)]
pub struct StagedFolder {
    target: PathBuf,
    staging: Option<PathBuf>,
}

/// Why a staged folder could not be created or swapped in.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StagingError {
    /// The target is a symbolic link.
    #[error(
        "{}: is a symbolic link; a report folder is never written through one: give the folder itself, or another path",
        path.display()
    )]
    Symlink {
        /// The target.
        path: PathBuf,
    },
    /// The target, or the folder it is in, cannot take the new folder.
    #[error(transparent)]
    Folder(#[from] FolderError),
}

impl StagedFolder {
    /// Creates a fresh empty folder beside `target` (creating `target`'s parent folders
    /// first); removes folders left there for the same target by writers that no longer
    /// run. Refuses a `target` that is a symbolic link or exists and is not a folder.
    pub fn beside(target: &Path) -> Result<Self, StagingError> {
        check_target(target)?;
        let (parent, name) = parent_and_name(target)?;
        let unwritable = |action| {
            let parent = parent.clone();
            move |reason| FolderError::Unwritable {
                path: parent,
                action,
                reason,
            }
        };
        fs::create_dir_all(&parent).map_err(unwritable("create this folder"))?;
        let prefix = temporary_prefix(&name);
        remove_stale_temporaries(&parent, &prefix);
        let staging = fresh_path(&parent, &prefix);
        // The usual mode of new folders (0777 less the umask); fails if anything is there.
        fs::DirBuilder::new()
            .mode(0o777)
            .create(&staging)
            .map_err(unwritable("create a folder in this folder"))?;
        Ok(Self {
            target: target.to_owned(),
            staging: Some(staging),
        })
    }

    /// The new folder, to write the files into.
    pub fn path(&self) -> &Path {
        self.staging
            .as_deref()
            .expect("a staged folder is there until committed")
    }

    /// The folder it will replace.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Swaps the new folder in: an earlier folder at the target is renamed aside, the new
    /// one renamed into its place, then the earlier one removed. Should the second rename
    /// fail, the earlier folder is renamed back. Refuses a target that has become a
    /// symbolic link or something other than a folder.
    pub fn commit(mut self) -> Result<PathBuf, StagingError> {
        check_target(&self.target)?;
        let (parent, name) = parent_and_name(&self.target)?;
        let staging = self.staging.take().expect("committed once");
        let failed = |action, reason| FolderError::Unwritable {
            path: self.target.clone(),
            action,
            reason,
        };
        let aside = if fs::symlink_metadata(&self.target).is_ok() {
            let aside = fresh_path(&parent, &temporary_prefix(&name));
            if let Err(e) = fs::rename(&self.target, &aside) {
                fs::remove_dir_all(&staging).ok();
                return Err(failed("move the earlier report aside", e).into());
            }
            Some(aside)
        } else {
            None
        };
        if let Err(e) = fs::rename(&staging, &self.target) {
            if let Some(aside) = &aside {
                fs::rename(aside, &self.target).ok();
            }
            fs::remove_dir_all(&staging).ok();
            return Err(failed("put the new report in place", e).into());
        }
        if let Some(aside) = aside {
            // The new folder is in place: what is left of the earlier one is a temporary
            // folder, removed later as a dead writer's should this fail.
            fs::remove_dir_all(aside).ok();
        }
        if let Ok(dir) = fs::File::open(&parent) {
            dir.sync_all().ok();
        }
        Ok(self.target.clone())
    }
}

impl Drop for StagedFolder {
    fn drop(&mut self) {
        if let Some(staging) = self.staging.take() {
            fs::remove_dir_all(staging).ok();
        }
    }
}

/// Refuses a target that is a symbolic link or exists and is not a folder.
fn check_target(target: &Path) -> Result<(), StagingError> {
    match fs::symlink_metadata(target) {
        Ok(meta) if meta.file_type().is_symlink() => Err(StagingError::Symlink {
            path: target.to_owned(),
        }),
        Ok(meta) if !meta.is_dir() => Err(FolderError::NotAFolder {
            path: target.to_owned(),
            kind: special_file_kind(&meta.file_type()).unwrap_or("a regular file"),
        }
        .into()),
        _ => Ok(()),
    }
}

/// The folder `target` is in (`.` for a bare name) and its own name.
fn parent_and_name(target: &Path) -> Result<(PathBuf, OsString), FolderError> {
    let name = target.file_name().ok_or_else(|| FolderError::Unwritable {
        path: target.to_owned(),
        action: "name a folder beside it",
        reason: io::Error::new(
            io::ErrorKind::InvalidInput,
            "the path ends in `..` or `/`: give the folder's own name",
        ),
    })?;
    Ok((folder_of(target).to_owned(), name.to_owned()))
}

/// `PREFIX PID-RANDOM` in `parent`, a name nothing there has.
fn fresh_path(parent: &Path, prefix: &OsString) -> PathBuf {
    loop {
        let mut hasher = RandomState::new().build_hasher();
        hasher.write_u64(u64::from(std::process::id()));
        let mut name = prefix.clone();
        name.push(format!("{}-{:016x}", std::process::id(), hasher.finish()));
        let path = parent.join(name);
        if fs::symlink_metadata(&path).is_err() {
            return path;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::tests::names_in;
    use std::os::unix::fs::symlink;

    #[test]
    fn a_new_folder_replaces_the_earlier_one_whole() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("report");
        fs::create_dir(&target).unwrap();
        fs::write(target.join("old.svg"), b"old").unwrap();
        let staged = StagedFolder::beside(&target).unwrap();
        assert!(crate::output::is_temporary_name(
            &staged.path().file_name().unwrap().to_string_lossy()
        ));
        fs::write(staged.path().join("new.svg"), b"new").unwrap();
        staged.commit().unwrap();
        assert_eq!(names_in(&target), ["new.svg"]);
        assert_eq!(names_in(dir.path()), ["report"]);
    }

    #[test]
    fn a_dropped_folder_leaves_the_earlier_one_as_it_was() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("report");
        fs::create_dir(&target).unwrap();
        fs::write(target.join("old.svg"), b"old").unwrap();
        let staged = StagedFolder::beside(&target).unwrap();
        fs::write(staged.path().join("half.svg"), b"half").unwrap();
        drop(staged);
        assert_eq!(names_in(&target), ["old.svg"]);
        assert_eq!(names_in(dir.path()), ["report"]);
    }

    #[test]
    fn a_symlinked_target_and_a_file_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let elsewhere = dir.path().join("elsewhere");
        fs::create_dir(&elsewhere).unwrap();
        let link = dir.path().join("report");
        symlink(&elsewhere, &link).unwrap();
        let err = StagedFolder::beside(&link).unwrap_err();
        assert!(matches!(err, StagingError::Symlink { .. }), "{err}");
        let file = dir.path().join("file");
        fs::write(&file, b"x").unwrap();
        let err = StagedFolder::beside(&file).unwrap_err();
        assert!(err.to_string().contains("is a regular file"), "{err}");
        assert_eq!(names_in(dir.path()), ["elsewhere", "file", "report"]);
    }
}
