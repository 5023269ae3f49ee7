//! The case base on disk.
//!
//! Loaded once at start (a missing file is an empty case base, created at the first
//! retention; a corrupt or foreign one is refused and left untouched), then rewritten
//! atomically after every retention (`cbr_core::write_atomically`: temporary file, fsync,
//! rename, directory fsync), so the file on disk always loads and holds every case the
//! server has acknowledged.

use cbr_core::{Behavior, BehaviorSpace, CaseBaseError};
use std::path::{Path, PathBuf};
use trust::TrustCaseBase;

/// Where the case base lives.
#[derive(Clone, Debug)]
pub struct CaseStore {
    path: PathBuf,
}

/// Why the case base could not be loaded or saved.
#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    /// Reading, parsing or writing failed.
    #[error(transparent)]
    CaseBase(#[from] CaseBaseError),
    /// A case's behaviors have the wrong number of components or values out of range:
    /// the case base was likely written for another domain.
    #[error(
        "{path}: case #{case} does not fit this domain's behavior space ({reason}); is this the case base of another domain?"
    )]
    Foreign {
        /// The file.
        path: PathBuf,
        /// The case.
        case: u32,
        /// What does not fit.
        reason: String,
    },
    /// A case holds a value no case can have, whatever the domain (a negative time).
    #[error("{path}: case #{case}: {reason}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// The case.
        case: u32,
        /// What is wrong.
        reason: String,
    },
    /// The directory to hold the case base does not exist.
    #[error("{path}: the directory {dir} does not exist")]
    NoDirectory {
        /// The file.
        path: PathBuf,
        /// Its directory.
        dir: PathBuf,
    },
}

impl CaseStore {
    /// Opens the case base at `path` for `space`: loads it if the file exists (checking
    /// every case against `space`), or starts empty. Never writes.
    pub fn open(path: &Path, space: &BehaviorSpace) -> Result<(Self, TrustCaseBase), StoreError> {
        let store = Self {
            path: path.to_owned(),
        };
        if !path.exists() {
            let dir = match path.parent() {
                Some(d) if !d.as_os_str().is_empty() => d,
                _ => Path::new("."),
            };
            if !dir.is_dir() {
                return Err(StoreError::NoDirectory {
                    path: path.to_owned(),
                    dir: dir.to_owned(),
                });
            }
            return Ok((store, TrustCaseBase::new()));
        }
        let cases = TrustCaseBase::load_ron(path)?;
        for (id, case) in cases.iter() {
            let foreign = |reason: String| StoreError::Foreign {
                path: path.to_owned(),
                case: id.0,
                reason,
            };
            check_behavior(space, &case.solution).map_err(|r| foreign(format!("solution: {r}")))?;
            for (k, e) in case.problem.iter().enumerate() {
                check_behavior(space, &e.behavior)
                    .map_err(|r| foreign(format!("evaluated pair {k}: {r}")))?;
                if !(e.time.is_finite() && e.time >= 0.0) {
                    return Err(StoreError::Invalid {
                        path: path.to_owned(),
                        case: id.0,
                        reason: format!(
                            "evaluated pair {k}: time must be a finite number >= 0, got {}",
                            e.time
                        ),
                    });
                }
            }
        }
        Ok((store, cases))
    }

    /// Writes `cases` atomically.
    pub fn save(&self, cases: &TrustCaseBase) -> Result<(), StoreError> {
        Ok(cases.save_ron(&self.path)?)
    }
}

fn check_behavior(space: &BehaviorSpace, behavior: &Behavior) -> Result<(), String> {
    if space.contains(behavior) {
        return Ok(());
    }
    if behavior.len() != space.components().len() {
        return Err(format!(
            "{} value indices for {} components",
            behavior.len(),
            space.components().len()
        ));
    }
    for (k, c) in space.components().iter().enumerate() {
        if usize::from(behavior.get(k)) >= c.len() {
            return Err(format!(
                "value index {} of `{}` is out of range (it has {} values)",
                behavior.get(k),
                c.name,
                c.len()
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use cbr_core::Case;
    use proptest::prelude::*;
    use trust::Evaluated;

    fn space() -> BehaviorSpace {
        (*domains::spaces::movement_space()).clone()
    }

    fn one_case() -> TrustCaseBase {
        let mut cases = TrustCaseBase::new();
        cases.push(Case {
            problem: vec![Evaluated {
                behavior: Behavior::new(&[3, 4]),
                time: 12.0,
            }],
            solution: Behavior::new(&[5, 5]),
        });
        cases
    }

    #[test]
    fn a_missing_file_is_an_empty_base_and_is_not_created() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cases.ron");
        let (store, cases) = CaseStore::open(&path, &space()).unwrap();
        assert!(cases.is_empty());
        assert!(!path.exists());
        store.save(&one_case()).unwrap();
        let (_, loaded) = CaseStore::open(&path, &space()).unwrap();
        assert_eq!(loaded, one_case());
    }

    #[test]
    fn a_corrupt_file_is_refused_and_left_untouched() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cases.ron");
        one_case().save_ron(&path).unwrap();
        let mut bytes = std::fs::read(&path).unwrap();
        bytes.truncate(bytes.len() - 7);
        bytes.extend_from_slice(b"\xff\x00garbage");
        std::fs::write(&path, &bytes).unwrap();
        let err = CaseStore::open(&path, &space()).unwrap_err();
        assert!(
            err.to_string().starts_with(&path.display().to_string()),
            "{err}"
        );
        assert_eq!(std::fs::read(&path).unwrap(), bytes);
    }

    #[test]
    fn a_case_base_of_another_space_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cases.ron");
        let mut cases = one_case();
        cases.push(Case {
            problem: vec![],
            solution: Behavior::new(&[1, 25]),
        });
        cases.save_ron(&path).unwrap();
        let before = std::fs::read(&path).unwrap();
        let err = CaseStore::open(&path, &space()).unwrap_err().to_string();
        assert!(err.contains("case #1"), "{err}");
        assert!(
            err.contains("value index 25 of `padding` is out of range"),
            "{err}"
        );
        let patrol = domains::spaces::patrol_space();
        let err = CaseStore::open(&path, &patrol).unwrap_err().to_string();
        assert!(err.contains("2 value indices for 4 components"), "{err}");
        assert!(
            err.ends_with("is this the case base of another domain?"),
            "{err}"
        );
        assert_eq!(std::fs::read(&path).unwrap(), before);
    }

    #[test]
    fn a_symlinked_case_file_stays_a_link_and_its_target_is_saved() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.ron");
        let link = dir.path().join("cases.ron");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        let (store, cases) = CaseStore::open(&link, &space()).unwrap();
        assert!(cases.is_empty());
        store.save(&one_case()).unwrap();
        assert!(std::fs::symlink_metadata(&link).unwrap().is_symlink());
        assert_eq!(CaseStore::open(&real, &space()).unwrap().1, one_case());
    }

    #[test]
    fn an_unknown_field_in_an_evaluated_pair_is_refused_and_kept() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cases.ron");
        let text =
            "(cases: [(problem: [(behavior: [3, 4], time: 12.0, mood: 1)], solution: [5, 5])])";
        std::fs::write(&path, text).unwrap();
        let err = CaseStore::open(&path, &space()).unwrap_err().to_string();
        assert!(err.contains("`mood`"), "{err}");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), text);
    }

    #[test]
    fn a_bad_time_is_not_blamed_on_another_domain() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cases.ron");
        let mut cases = one_case();
        cases.push(Case {
            problem: vec![Evaluated {
                behavior: Behavior::new(&[1, 1]),
                time: -3.0,
            }],
            solution: Behavior::new(&[2, 2]),
        });
        cases.save_ron(&path).unwrap();
        let err = CaseStore::open(&path, &space()).unwrap_err().to_string();
        assert_eq!(
            err,
            format!(
                "{}: case #1: evaluated pair 0: time must be a finite number >= 0, got -3",
                path.display()
            )
        );
    }

    #[test]
    fn a_missing_directory_is_reported_at_open() {
        let err = CaseStore::open(Path::new("/nonexistent/dir/cases.ron"), &space()).unwrap_err();
        assert!(
            err.to_string().contains("/nonexistent/dir does not exist"),
            "{err}"
        );
    }

    proptest! {
        #[test]
        fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..200)) {
            let dir = tempfile::tempdir().unwrap();
            let path = dir.path().join("cases.ron");
            std::fs::write(&path, &bytes).unwrap();
            let _ = CaseStore::open(&path, &space());
            prop_assert_eq!(std::fs::read(&path).unwrap(), bytes);
        }

        #[test]
        fn arbitrary_case_like_text_never_panics(text in r#"\(cases:\[(\(problem:\[(\(behavior:\[[0-9]{1,5}(,[0-9]{1,5}){0,9}\],time:-?[0-9.e]{1,5}\),?){0,2}\],solution:\[[0-9,]{0,8}\]\),?){0,3}\]\)"#) {
            let _ = TrustCaseBase::from_ron(&text, Path::new("x.ron"));
            let dir = tempfile::tempdir().unwrap();
            let path = dir.path().join("cases.ron");
            std::fs::write(&path, &text).unwrap();
            let _ = CaseStore::open(&path, &space());
        }
    }
}
