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

/// A config given as JSON (the Python package hands its dicts over so), read as `T`. An
/// error names the field at fault by its path in the dict (`experiments[0].trials`; the
/// config itself as `config`), not the line and column of JSON text its caller never
/// wrote.
pub fn from_json<T: serde::de::DeserializeOwned>(
    text: &str,
    origin: &Path,
) -> Result<T, ConfigFileError> {
    let mut json = serde_json::Deserializer::from_str(text);
    serde_path_to_error::deserialize(&mut json).map_err(|e| {
        let field = match e.path().to_string() {
            root if root == "." => "config".to_owned(),
            path => path,
        };
        let inner = e.into_inner();
        let message = inner.to_string();
        // serde_json ends its message with where in the text the error is.
        let message = match message.rfind(" at line ") {
            Some(at) if inner.line() > 0 => message[..at].to_owned(),
            _ => message,
        };
        ConfigFileError::invalid(origin, field, message)
    })
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

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Outer {
        items: Vec<Inner>,
    }

    #[derive(Debug, serde::Deserialize)]
    #[allow(dead_code)]
    struct Inner {
        weight: f64,
    }

    #[test]
    fn a_json_config_s_error_names_the_field_by_its_path_not_a_place_in_the_text() {
        let read = |text: &str| {
            from_json::<Outer>(text, Path::new("<dict>"))
                .unwrap_err()
                .to_string()
        };
        assert_eq!(
            read(r#"{"items": [{"weight": 1.0}, {"weight": "x"}]}"#),
            r#"<dict>: items[1].weight: invalid type: string "x", expected f64"#
        );
        assert_eq!(
            read("true"),
            "<dict>: config: invalid type: boolean `true`, expected struct Outer"
        );
        assert!(read(r#"{"items": [], "colour": 1}"#).contains("unknown field `colour`"));
        assert!(from_json::<Outer>(r#"{"items": [{"weight": 2}]}"#, Path::new("x")).is_ok());
    }
}
