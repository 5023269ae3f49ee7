//! Cases and the append-only case base, with atomic RON persistence.
//!
//! A [`Case`] pairs a problem with its solution. A [`CaseBase`] only grows: a case, once
//! appended, keeps its [`CaseId`] (its position) for good, so indices built over the base
//! stay valid. Saving goes through [`write_atomically`], so a crash leaves either the old
//! or the new file, never a torn one.

use crate::input::{FileError, MAX_CASE_BASE_BYTES, read_text_at_most};
use crate::output::write_atomically;
use crate::ron_text::{RonError, parse_ron};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::path::{Path, PathBuf};

/// The stable identity of a case: its position in the case base.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct CaseId(pub u32);

impl CaseId {
    /// The position of the case in the case base.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

impl fmt::Display for CaseId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "#{}", self.0)
    }
}

/// A problem and the solution that worked for it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Case<P, S> {
    /// What was faced.
    pub problem: P,
    /// What solved it.
    pub solution: S,
}

/// An append-only, ordered collection of cases.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseBase<P, S> {
    cases: Vec<Case<P, S>>,
}

impl<P, S> Default for CaseBase<P, S> {
    fn default() -> Self {
        Self { cases: Vec::new() }
    }
}

/// Why a case base could not be loaded or saved.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CaseBaseError {
    /// The file could not be read or written.
    #[error(transparent)]
    Io(#[from] FileError),
    /// The file is not a valid case base.
    #[error(transparent)]
    Parse(#[from] RonError),
    /// The case base could not be serialized.
    #[error("{path}: cannot serialize the case base: {message}")]
    Serialize {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

impl<P, S> CaseBase<P, S> {
    /// An empty case base.
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends a case and returns its id.
    pub fn push(&mut self, case: Case<P, S>) -> CaseId {
        let id = CaseId(u32::try_from(self.cases.len()).expect("fewer than 2^32 cases"));
        self.cases.push(case);
        id
    }

    /// The case with id `id`, if any.
    pub fn get(&self, id: CaseId) -> Option<&Case<P, S>> {
        self.cases.get(id.index())
    }

    /// Number of cases.
    pub fn len(&self) -> usize {
        self.cases.len()
    }

    /// Whether there are no cases.
    pub fn is_empty(&self) -> bool {
        self.cases.is_empty()
    }

    /// Every case with its id, in case-base order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = (CaseId, &Case<P, S>)> + '_ {
        self.cases
            .iter()
            .enumerate()
            .map(|(i, c)| (CaseId(i as u32), c))
    }

    /// The cases, in case-base order.
    pub fn cases(&self) -> &[Case<P, S>] {
        &self.cases
    }
}

impl<P: Serialize, S: Serialize> CaseBase<P, S> {
    /// Writes the case base to `path` as RON, atomically: the previous file stays intact
    /// until the new one is complete and synced.
    pub fn save_ron(&self, path: &Path) -> Result<(), CaseBaseError> {
        let text =
            ron::ser::to_string_pretty(self, ron::ser::PrettyConfig::default()).map_err(|e| {
                CaseBaseError::Serialize {
                    path: path.to_owned(),
                    message: e.to_string(),
                }
            })?;
        write_atomically(path, text.as_bytes()).map_err(|reason| {
            CaseBaseError::Io(FileError {
                path: path.to_owned(),
                reason,
            })
        })
    }
}

impl<P: DeserializeOwned, S: DeserializeOwned> CaseBase<P, S> {
    /// Reads a case base written by [`Self::save_ron`] (at most [`MAX_CASE_BASE_BYTES`]).
    /// The file is only read.
    pub fn load_ron(path: &Path) -> Result<Self, CaseBaseError> {
        let text = read_text_at_most(path, MAX_CASE_BASE_BYTES)?;
        Self::from_ron(&text, path)
    }

    /// Parses a case base from RON text; `origin` names the source in errors.
    pub fn from_ron(text: &str, origin: &Path) -> Result<Self, CaseBaseError> {
        Ok(parse_ron(text, origin)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type Base = CaseBase<Vec<u32>, String>;

    fn sample() -> Base {
        let mut base = Base::new();
        base.push(Case {
            problem: vec![1, 2],
            solution: "a".into(),
        });
        base.push(Case {
            problem: vec![],
            solution: "b".into(),
        });
        base
    }

    #[test]
    fn ids_are_positions_and_stable() {
        let mut base = sample();
        let id = base.push(Case {
            problem: vec![3],
            solution: "c".into(),
        });
        assert_eq!(id, CaseId(2));
        assert_eq!(base.get(CaseId(0)).unwrap().solution, "a");
        assert_eq!(base.get(id).unwrap().problem, vec![3]);
        assert_eq!(base.len(), 3);
    }

    #[test]
    fn save_and_load_round_trip() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cases.ron");
        let base = sample();
        base.save_ron(&path).unwrap();
        assert_eq!(Base::load_ron(&path).unwrap(), base);
        // No temporary files are left behind.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn truncated_file_gives_position_and_is_left_untouched() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cases.ron");
        sample().save_ron(&path).unwrap();
        let full = std::fs::read_to_string(&path).unwrap();
        let truncated = &full[..full.len() / 2];
        std::fs::write(&path, truncated).unwrap();
        let err = Base::load_ron(&path).unwrap_err();
        match &err {
            CaseBaseError::Parse(RonError {
                path: p,
                line,
                column,
                ..
            }) => {
                assert_eq!(p, &path);
                assert!(*line >= 1 && *column >= 1);
            }
            other => panic!("expected a parse error, got {other}"),
        }
        assert!(err.to_string().starts_with(&path.display().to_string()));
        assert_eq!(std::fs::read_to_string(&path).unwrap(), truncated);
    }

    #[test]
    fn malformed_file_names_line_and_column() {
        let text = "(\n  cases: [\n    (problem: [1], solution: \"a\"),\n    (problem: [x], solution: \"b\"),\n  ],\n)";
        let err = Base::from_ron(text, Path::new("cb.ron")).unwrap_err();
        let CaseBaseError::Parse(RonError { line, column, .. }) = err else {
            panic!("expected a parse error");
        };
        // `x` is the 16th character of line 4: `    (problem: [x]`.
        assert_eq!((line, column), (4, 16));
    }

    #[test]
    fn an_unknown_field_in_a_case_is_refused_where_it_is() {
        let text = "(cases: [(problem: [1], solution: \"a\", note: \"x\")])";
        let err = Base::from_ron(text, Path::new("cb.ron")).unwrap_err();
        let CaseBaseError::Parse(RonError { message, .. }) = err else {
            panic!("expected a parse error");
        };
        assert!(message.contains("`note`"), "{message}");
    }

    #[test]
    fn missing_file_is_an_io_error_naming_it() {
        let err = Base::load_ron(Path::new("/nonexistent/cases.ron")).unwrap_err();
        assert!(matches!(err, CaseBaseError::Io(_)));
        assert!(err.to_string().contains("/nonexistent/cases.ron"));
    }
}
