//! Reading input files: the one way every file of the workspace is read, and
//! [`FileError`], a file that could not be read or written.

use std::fs::FileType;
use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};

/// A file that could not be read or written.
#[derive(Debug, thiserror::Error)]
#[error("{}: {reason}", path.display())]
pub struct FileError {
    /// The file.
    pub path: PathBuf,
    /// What went wrong (shown in the message, so not chained as a source).
    pub reason: std::io::Error,
}

/// The whole text of the file at `path`.
pub fn read_text(path: &Path) -> Result<String, FileError> {
    std::fs::read_to_string(path).map_err(|reason| FileError {
        path: path.to_owned(),
        reason,
    })
}

/// What a file that is not a regular file is, e.g. `a FIFO (named pipe)`; `None` for a
/// regular file (or a symbolic link, whose target decides).
pub(crate) fn special_file_kind(file_type: &FileType) -> Option<&'static str> {
    if file_type.is_file() || file_type.is_symlink() {
        None
    } else if file_type.is_dir() {
        Some("a directory")
    } else if file_type.is_fifo() {
        Some("a FIFO (named pipe)")
    } else if file_type.is_char_device() {
        Some("a character device")
    } else if file_type.is_block_device() {
        Some("a block device")
    } else if file_type.is_socket() {
        Some("a socket")
    } else {
        Some("not a regular file")
    }
}
