//! Replacing only the files a writer wrote itself.
//!
//! A writer that puts a file of a fixed name in a folder the user names (`competence.md`,
//! `landscape.svg`, a population's `MEMBER.ron`) may find a file of that name there. It
//! replaces it only when it is absent or one it wrote earlier, as its content shows
//! ([`OwnFile::is_own`]); a symbolic link, a folder, a device or any other file is
//! refused, naming it, and stays as it was. The new file is written atomically and never
//! through a link ([`write_no_follow`]).

use crate::input::{FileError, special_file_kind};
use crate::output::write_no_follow;
use std::fs::{self, OpenOptions};
use std::io::{self, Read};
use std::os::unix::fs::OpenOptionsExt;
use std::path::{Path, PathBuf};

/// The most of an existing file read to recognize it: larger files are no writer's own.
pub const MAX_RECOGNIZED_BYTES: u64 = 256 << 20;

/// What a writer may replace: the files it wrote itself, as their content shows.
pub struct OwnFile<'a> {
    /// What such a file is, as messages name it: `a competence report written by
    /// trustcbr competence`.
    pub what: &'a str,
    /// What the user can do instead, as messages say it: `give --out another folder, or
    /// move the file`.
    pub remedy: &'a str,
    /// Whether the bytes of an existing regular file are such a file.
    pub is_own: &'a dyn Fn(&[u8]) -> bool,
}

/// Why a file is not replaced.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReplaceError {
    /// The path is a symbolic link: nothing is written through one.
    #[error(
        "{}: is a symbolic link; nothing is written through one, and the file it points to stays as it was: {remedy}",
        path.display()
    )]
    Symlink {
        /// The link.
        path: PathBuf,
        /// What the user can do ([`OwnFile::remedy`]).
        remedy: String,
    },
    /// The path is a folder, a FIFO, a device or a socket.
    #[error("{}: exists and is {kind}, not {what}: {remedy}", path.display())]
    NotAFile {
        /// The path.
        path: PathBuf,
        /// What it is.
        kind: &'static str,
        /// What the writer would replace ([`OwnFile::what`]).
        what: String,
        /// What the user can do ([`OwnFile::remedy`]).
        remedy: String,
    },
    /// The path is a regular file the writer did not write.
    #[error(
        "{}: exists and is not {what}, so it is not replaced: {remedy}",
        path.display()
    )]
    Foreign {
        /// The file.
        path: PathBuf,
        /// What the writer would replace ([`OwnFile::what`]).
        what: String,
        /// What the user can do ([`OwnFile::remedy`]).
        remedy: String,
    },
    /// The file could not be read or written.
    #[error(transparent)]
    File(#[from] FileError),
}

impl OwnFile<'_> {
    /// Checks that `path` may be written: absent, or a regular file (no symbolic link)
    /// that [`OwnFile::is_own`] recognizes. Reads without following a link.
    pub fn check(&self, path: &Path) -> Result<(), ReplaceError> {
        let meta = match fs::symlink_metadata(path) {
            Ok(meta) => meta,
            Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(()),
            Err(reason) => return Err(self.file_error(path, reason)),
        };
        if meta.file_type().is_symlink() {
            return Err(ReplaceError::Symlink {
                path: path.to_owned(),
                remedy: self.remedy.to_owned(),
            });
        }
        if let Some(kind) = special_file_kind(&meta.file_type()) {
            return Err(ReplaceError::NotAFile {
                path: path.to_owned(),
                kind,
                what: self.what.to_owned(),
                remedy: self.remedy.to_owned(),
            });
        }
        let bytes = read_no_follow(path).map_err(|reason| self.file_error(path, reason))?;
        match bytes {
            Some(bytes) if (self.is_own)(&bytes) => Ok(()),
            _ => Err(ReplaceError::Foreign {
                path: path.to_owned(),
                what: self.what.to_owned(),
                remedy: self.remedy.to_owned(),
            }),
        }
    }

    /// Writes `bytes` as `path` when [`OwnFile::check`] allows it: atomically, never
    /// through a symbolic link.
    pub fn write(&self, path: &Path, bytes: &[u8]) -> Result<(), ReplaceError> {
        self.check(path)?;
        write_no_follow(path, bytes).map_err(|reason| self.file_error(path, reason))
    }

    fn file_error(&self, path: &Path, reason: io::Error) -> ReplaceError {
        ReplaceError::File(FileError {
            path: path.to_owned(),
            reason,
        })
    }
}

/// The bytes of the regular file `path`, opened without following a link or blocking;
/// `None` when it holds more than [`MAX_RECOGNIZED_BYTES`] or is no regular file.
fn read_no_follow(path: &Path) -> io::Result<Option<Vec<u8>>> {
    let file = OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK)
        .open(path)?;
    if !file.metadata()?.is_file() {
        return Ok(None);
    }
    let mut bytes = Vec::new();
    file.take(MAX_RECOGNIZED_BYTES + 1)
        .read_to_end(&mut bytes)?;
    Ok((bytes.len() as u64 <= MAX_RECOGNIZED_BYTES).then_some(bytes))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::os::unix::fs::symlink;

    const REPORT: OwnFile<'static> = OwnFile {
        what: "a report written by this test",
        remedy: "move it",
        is_own: &|bytes| bytes.starts_with(b"# report"),
    };

    #[test]
    fn an_absent_file_and_an_own_file_are_written() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("r.md");
        REPORT.write(&path, b"# report 1").unwrap();
        REPORT.write(&path, b"# report 2").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"# report 2");
    }

    #[test]
    fn links_foreign_files_and_folders_are_refused_unchanged() {
        let dir = tempfile::tempdir().unwrap();
        let outside = dir.path().join("outside.md");
        // Even a link to a file the writer would recognize is refused.
        fs::write(&outside, b"# report of someone else's").unwrap();
        let link = dir.path().join("r.md");
        symlink(&outside, &link).unwrap();
        let err = REPORT.write(&link, b"# report").unwrap_err();
        assert!(matches!(err, ReplaceError::Symlink { .. }), "{err}");
        assert!(err.to_string().ends_with(": move it"), "{err}");
        assert_eq!(fs::read(&outside).unwrap(), b"# report of someone else's");
        assert!(fs::symlink_metadata(&link).unwrap().is_symlink());

        let notes = dir.path().join("notes.md");
        fs::write(&notes, b"my notes").unwrap();
        let err = REPORT.write(&notes, b"# report").unwrap_err();
        assert_eq!(
            err.to_string(),
            format!(
                "{}: exists and is not a report written by this test, so it is not replaced: move it",
                notes.display()
            )
        );
        assert_eq!(fs::read(&notes).unwrap(), b"my notes");

        let folder = dir.path().join("folder.md");
        fs::create_dir(&folder).unwrap();
        let err = REPORT.write(&folder, b"# report").unwrap_err();
        assert!(err.to_string().contains("is a directory"), "{err}");
    }
}
