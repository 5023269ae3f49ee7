//! [`RonStore`]: a case base in a RON file, the human-readable exchange format.
//!
//! ```ron
//! (
//!     domain: "movement",
//!     space: (components: [...], weights: [1.0, 1.0]),
//!     cases: [(problem: [(behavior: [3, 4], time: 12.0)], solution: [5, 5])],
//! )
//! ```
//!
//! `domain` and `space` are optional, so case files written before case bases recorded
//! their space still open (their cases are then only checked to fit the space served). A
//! RON case base is read once and never written: serving one reuses its cases and retains
//! none; `trustcbr cases import` converts it into a database, `trustcbr cases export`
//! writes one. A case's id in a RON file is its position, from 0.

use super::{CaseStore, Identity, StoreError, StoreId, StoredCase, check_file};
use cbr_core::BehaviorSpace;
use files::{FileError, MAX_CASE_BASE_BYTES, RonError, parse_ron, read_text_at_most};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use trust::TrustCase;

/// Why a RON case file could not be read or written.
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

/// The layout of a RON case file, as read.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CaseFile {
    #[serde(default)]
    domain: Option<String>,
    #[serde(default)]
    space: Option<BehaviorSpace>,
    cases: Vec<TrustCase>,
}

/// The same layout as written: always with its domain and space.
#[derive(Serialize)]
struct CaseFileRef<'a> {
    domain: Option<&'a str>,
    space: Option<&'a BehaviorSpace>,
    cases: &'a [TrustCase],
}

/// A RON case file, read once at open.
pub struct RonStore {
    path: PathBuf,
    identity: Identity,
    cases: Vec<TrustCase>,
}

impl RonStore {
    /// Reads the case file at `path`. Its identity is the one it records or, for a file
    /// recording none, `identity`; with neither it is refused.
    pub fn open(path: &Path, identity: Option<&Identity>) -> Result<Self, StoreError> {
        if !check_file(path)? {
            return Err(StoreError::Missing(path.display().to_string()));
        }
        let text = read_text_at_most(path, MAX_CASE_BASE_BYTES).map_err(CaseBaseError::from)?;
        let file: CaseFile = parse_ron(&text, path).map_err(CaseBaseError::from)?;
        let identity = match (file.space, identity) {
            (Some(space), _) => Identity {
                domain: file.domain.unwrap_or_default(),
                space,
            },
            (None, Some(identity)) => identity.clone(),
            (None, None) => {
                return Err(StoreError::Corrupt {
                    location: path.display().to_string(),
                    reason: "the file records no behavior space, so it cannot be read on its own; `trustcbr cases import` it into a database with `--domain` naming the domain its cases were learned in".to_owned(),
                });
            }
        };
        Ok(Self {
            path: path.to_owned(),
            identity,
            cases: file.cases,
        })
    }
}

impl CaseStore for RonStore {
    fn location(&self) -> String {
        self.path.display().to_string()
    }

    fn identity(&self) -> &Identity {
        &self.identity
    }

    fn writable(&self) -> bool {
        false
    }

    fn read_after(
        &mut self,
        after: Option<StoreId>,
        each: &mut dyn FnMut(StoredCase) -> Result<(), StoreError>,
    ) -> Result<(), StoreError> {
        let first = after.map_or(0, |a| usize::try_from(a + 1).unwrap_or(0));
        for (position, case) in self.cases.iter().enumerate().skip(first) {
            each(StoredCase {
                id: position as StoreId,
                case: case.clone(),
            })?;
        }
        Ok(())
    }

    fn append(
        &mut self,
        _case: &TrustCase,
        _after: Option<StoreId>,
        _missed: &mut dyn FnMut(StoredCase),
    ) -> Result<StoreId, StoreError> {
        Err(StoreError::ReadOnly(self.path.clone()))
    }

    fn append_all(&mut self, _cases: &[TrustCase]) -> Result<usize, StoreError> {
        Err(StoreError::ReadOnly(self.path.clone()))
    }
}

/// Checks that the existing file at `path` is one an export may write over: an earlier
/// export, that is a RON case file recording its behavior space; otherwise says what it is.
pub fn check_earlier_export(path: &Path) -> Result<(), String> {
    if std::fs::symlink_metadata(path).is_ok_and(|meta| meta.file_type().is_symlink()) {
        return Err(
            "a symbolic link: nothing is written through one, nor is what it points to changed"
                .to_owned(),
        );
    }
    if super::sqlite_file::is_database(path) {
        return Err("an SQLite database".to_owned());
    }
    let text = read_text_at_most(path, MAX_CASE_BASE_BYTES).map_err(|e| e.reason.to_string())?;
    let file: CaseFile = parse_ron(&text, path).map_err(|_| "not a RON case file".to_owned())?;
    match file.space {
        Some(_) => Ok(()),
        None => Err(
            "a RON case file recording no behavior space, so not written by `cases export`"
                .to_owned(),
        ),
    }
}

/// Writes every case of `store`, with its identity, to the RON file `out` (atomically,
/// never through a symbolic link).
/// Returns how many cases were written.
pub fn export(store: &mut dyn CaseStore, out: &Path) -> Result<usize, StoreError> {
    let mut cases = Vec::new();
    store.read_after(None, &mut |stored| {
        cases.push(stored.case);
        Ok(())
    })?;
    save(out, store.identity(), &cases)?;
    Ok(cases.len())
}

/// Writes `cases`, learned in `identity`, to the RON file `out` (atomically, never
/// through a symbolic link: an `out` that is one is refused), in the
/// layout [`RonStore`] reads: a file that names its domain and space, so that `cases info`,
/// `cases import` and `serve` need nothing else to read it.
pub fn save(out: &Path, identity: &Identity, cases: &[TrustCase]) -> Result<(), CaseBaseError> {
    let file = CaseFileRef {
        domain: Some(&identity.domain),
        space: Some(&identity.space),
        cases,
    };
    let text =
        ron::ser::to_string_pretty(&file, ron::ser::PrettyConfig::default()).map_err(|e| {
            CaseBaseError::Serialize {
                path: out.to_owned(),
                message: e.to_string(),
            }
        })?;
    files::write_no_follow(out, text.as_bytes()).map_err(|reason| {
        CaseBaseError::Io(FileError {
            path: out.to_owned(),
            reason,
        })
    })
}
