//! Reading input files: the one way every file of the workspace is read, and
//! [`FileError`], a file that could not be read or written.
//!
//! A read is bounded: a file that is not a regular file (a FIFO, a device, a directory, a
//! socket) or that holds more than a cap is refused at once, before anything is read, so
//! neither `/dev/zero` nor a FIFO nobody writes to can exhaust memory or hang the reader.
//! Configs, operators and domain files may hold [`MAX_CONFIG_BYTES`], case bases
//! [`MAX_CASE_BASE_BYTES`]. A UTF-8 byte-order mark at the start is skipped.

use std::fs::{FileType, Metadata, OpenOptions};
use std::io::{self, Read};
use std::os::unix::fs::{FileTypeExt, OpenOptionsExt};
use std::path::{Path, PathBuf};

/// The most bytes read from a config, operator file or domain file: 1 MiB.
pub const MAX_CONFIG_BYTES: u64 = 1 << 20;

/// The most bytes read from a case-base file: 256 MiB.
pub const MAX_CASE_BASE_BYTES: u64 = 256 << 20;

/// The UTF-8 encoding of U+FEFF, which some editors put at the start of a text file.
pub const BYTE_ORDER_MARK: &str = "\u{feff}";

/// A file that could not be read or written.
#[derive(Debug, thiserror::Error)]
#[error("{}: {reason}", path.display())]
pub struct FileError {
    /// The file.
    pub path: PathBuf,
    /// What went wrong (shown in the message, so not chained as a source).
    pub reason: std::io::Error,
}

/// The whole text of the config, operator or domain file at `path` (at most
/// [`MAX_CONFIG_BYTES`]), without a leading byte-order mark.
pub fn read_text(path: &Path) -> Result<String, FileError> {
    read_text_at_most(path, MAX_CONFIG_BYTES)
}

/// The whole text of the regular file at `path`, refused if it holds more than `cap`
/// bytes, without a leading byte-order mark.
pub fn read_text_at_most(path: &Path, cap: u64) -> Result<String, FileError> {
    read_bounded(path, cap).map_err(|reason| FileError {
        path: path.to_owned(),
        reason,
    })
}

fn read_bounded(path: &Path, cap: u64) -> io::Result<String> {
    // Checked before opening: opening a FIFO for reading waits for a writer.
    check_readable(&std::fs::metadata(path)?, cap)?;
    // Should the file be swapped for a FIFO meanwhile, the open does not wait, and the
    // check of the opened file refuses it.
    let file = OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK)
        .open(path)?;
    check_readable(&file.metadata()?, cap)?;
    let mut bytes = Vec::new();
    file.take(cap + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > cap {
        return Err(too_large(cap));
    }
    let text = String::from_utf8(bytes)
        .map_err(|_| io::Error::new(io::ErrorKind::InvalidData, "the file is not UTF-8 text"))?;
    Ok(match text.strip_prefix(BYTE_ORDER_MARK) {
        Some(rest) => rest.to_owned(),
        None => text,
    })
}

/// Refuses anything but a regular file of at most `cap` bytes.
fn check_readable(meta: &Metadata, cap: u64) -> io::Result<()> {
    if let Some(kind) = special_file_kind(&meta.file_type()) {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("is {kind}, not a regular file; only regular files are read"),
        ));
    }
    if meta.len() > cap {
        return Err(too_large(cap));
    }
    Ok(())
}

fn too_large(cap: u64) -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidInput,
        format!(
            "holds more than {} MiB ({cap} bytes), the most read from a file of this kind",
            cap >> 20
        ),
    )
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

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use std::sync::mpsc;
    use std::time::Duration;

    /// Makes a FIFO (named pipe) at `path` with `mkfifo`.
    pub(crate) fn make_fifo(path: &Path) {
        let made = std::process::Command::new("mkfifo")
            .arg(path)
            .status()
            .unwrap();
        assert!(made.success());
    }

    /// `read_text_at_most(path, cap)`'s error, failing the test if the read takes more
    /// than five seconds (a FIFO once blocked it forever).
    fn refusal(path: &Path, cap: u64) -> String {
        let (send, receive) = mpsc::channel();
        let owned = path.to_owned();
        std::thread::spawn(move || send.send(read_text_at_most(&owned, cap)).ok());
        let result = receive
            .recv_timeout(Duration::from_secs(5))
            .expect("the read returned at once");
        let err = result.unwrap_err();
        assert_eq!(err.path, path);
        err.to_string()
    }

    #[test]
    fn fifos_devices_and_directories_are_refused_at_once() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("config.ron");
        make_fifo(&fifo);
        assert_eq!(
            refusal(&fifo, MAX_CONFIG_BYTES),
            format!(
                "{}: is a FIFO (named pipe), not a regular file; only regular files are read",
                fifo.display()
            )
        );
        let zero = refusal(Path::new("/dev/zero"), MAX_CASE_BASE_BYTES);
        assert!(
            zero.starts_with("/dev/zero: is a character device"),
            "{zero}"
        );
        let directory = refusal(dir.path(), MAX_CONFIG_BYTES);
        assert!(directory.contains(": is a directory"), "{directory}");
    }

    #[test]
    fn files_above_the_cap_are_refused_without_being_read() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("big.ron");
        // A sparse file: its size is known without reading it.
        let file = std::fs::File::create(&path).unwrap();
        file.set_len(MAX_CONFIG_BYTES + 1).unwrap();
        assert_eq!(
            refusal(&path, MAX_CONFIG_BYTES),
            format!(
                "{}: holds more than 1 MiB (1048576 bytes), the most read from a file of this kind",
                path.display()
            )
        );
        file.set_len(MAX_CONFIG_BYTES).unwrap();
        assert_eq!(read_text(&path).unwrap().len() as u64, MAX_CONFIG_BYTES);
    }

    #[test]
    fn a_byte_order_mark_is_skipped_and_other_bytes_must_be_utf8() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.ron");
        std::fs::write(&path, "\u{feff}(a: 1)").unwrap();
        assert_eq!(read_text(&path).unwrap(), "(a: 1)");
        std::fs::write(&path, b"(a: \xff)").unwrap();
        assert!(
            read_text(&path)
                .unwrap_err()
                .to_string()
                .ends_with("the file is not UTF-8 text")
        );
    }
}
