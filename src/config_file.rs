//! What goes wrong with a config file, whatever it configures (a suite, a mission suite, a
//! sweep), in one place: a file cannot be read or written, its RON does not parse, or a
//! value is out of range. [`SuiteError`](crate::SuiteError) and
//! [`SweepError`](crate::SweepError) each wrap a [`ConfigFileError`] and print it as it
//! is; what is their own (an operator file, a plan, a cell, a merge) they add beside it.

use files::{FileError, RonError};
use std::path::{Path, PathBuf};

/// Why a config file, or a file its run reads or writes, cannot be used.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ConfigFileError {
    /// A file could not be read or written.
    #[error(transparent)]
    Io(#[from] FileError),
    /// A RON file does not parse.
    #[error(transparent)]
    Parse(#[from] RonError),
    /// A value is out of range.
    #[error("{path}: {field}: {message}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// The field, e.g. `experiments[2].operator`.
        field: String,
        /// What is wrong and what is allowed.
        message: String,
    },
}

impl ConfigFileError {
    /// An [`Invalid`](Self::Invalid) value of `field` in the file `path`.
    pub fn invalid(path: &Path, field: String, message: String) -> Self {
        Self::Invalid {
            path: path.to_owned(),
            field,
            message,
        }
    }
}

/// A content hash of `bytes` (64-bit FNV-1a, as 16 hex digits): what a sweep's run files
/// and a report's `summary.json` record of the config (and case bases) they ran, so that a
/// merge or `explain` notices one edited since. It tells versions apart, it does not
/// defend against forgery.
pub fn content_hash(bytes: &[u8]) -> String {
    let hash = bytes.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    });
    format!("{hash:016x}")
}

/// `From<FileError>` and `From<RonError>` for an error enum with a
/// `File(ConfigFileError)` variant, so that `?` takes a read or a parse as it comes.
macro_rules! from_config_file_errors {
    ($error:ty) => {
        impl From<files::FileError> for $error {
            fn from(error: files::FileError) -> Self {
                Self::File(error.into())
            }
        }

        impl From<files::RonError> for $error {
            fn from(error: files::RonError) -> Self {
                Self::File(error.into())
            }
        }
    };
}
pub(crate) use from_config_file_errors;
