//! Case stores: where a case base lives, behind one [`CaseStore`] trait.
//!
//! - [`sqlite`]: an SQLite database file, the default (embedded, nothing to install).
//! - [`postgres`]: a PostgreSQL database, for a fleet of robots on several machines.
//! - [`ron_file`]: a RON file, the human-readable exchange format; served read-only.
//!
//! Every store records the domain name and the [`BehaviorSpace`] its cases were learned in
//! (their [`Identity`]) and refuses to open with another space, naming the first
//! difference, or for another domain of the same space (a domain file is named by its
//! file name, so it may move). Cases have store ids that only grow and are never reused; a store hands back
//! the cases stored after a given id, so several processes on one store can each catch up
//! with what the others retained. An append is one durable transaction that first hands
//! back the cases stored since the caller last looked, so every process sees the cases in
//! one and the same order.
//!
//! Which store a location names: `postgres://` or `postgresql://` URLs are PostgreSQL,
//! paths ending in `.ron` are RON files, any other path is an SQLite database.
//!
//! The SQLite and PostgreSQL stores are the crate's `sqlite` and `postgres` features (both
//! on by default; the RON store is always there). A build without one reads locations the
//! same way, and opening a location of the store it left out fails with
//! [`StoreError::NotBuilt`], naming the feature.

#[cfg(feature = "postgres")]
pub mod postgres;
pub mod postgres_url;
pub mod ron_file;
#[cfg(feature = "sqlite")]
pub mod sqlite;
mod sqlite_file;

use cbr_core::{Behavior, BehaviorSpace, ContextSpace};
use std::path::{Path, PathBuf};
use trust::TrustCase;

/// The id a store gives a case: unique in the store, growing with every append.
pub type StoreId = i64;

/// A case as a store holds it.
#[derive(Clone, Debug, PartialEq)]
pub struct StoredCase {
    /// Its id in the store.
    pub id: StoreId,
    /// The case.
    pub case: TrustCase,
}

/// What a case base was learned in: the domain's name and its behavior space.
#[derive(Clone, Debug, PartialEq)]
pub struct Identity {
    /// The domain's name (`movement`, `patrol`, a domain file), for people.
    pub domain: String,
    /// The behavior space the cases' value indices refer to.
    pub space: BehaviorSpace,
}

/// Where a case base lives, parsed from `--cases`.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Location {
    /// An SQLite database file.
    Sqlite(PathBuf),
    /// A PostgreSQL connection URL.
    Postgres(String),
    /// A RON case file.
    Ron(PathBuf),
}

impl Location {
    /// Reads a `--cases` argument.
    pub fn parse(text: &str) -> Self {
        if text.starts_with("postgres://") || text.starts_with("postgresql://") {
            Self::Postgres(text.to_owned())
        } else if Path::new(text).extension().is_some_and(|e| e == "ron") {
            Self::Ron(PathBuf::from(text))
        } else {
            Self::Sqlite(PathBuf::from(text))
        }
    }

    /// The location for messages (a URL's password is not shown).
    pub fn shown(&self) -> String {
        match self {
            Self::Sqlite(path) | Self::Ron(path) => path.display().to_string(),
            Self::Postgres(url) => postgres_url::without_password(url),
        }
    }
}

/// Why a case base could not be opened, read or appended to.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StoreError {
    /// The path exists but is not a regular file (a FIFO, a device, a directory).
    #[error("{path}: not a regular file ({kind}); a case base must be a regular file or absent")]
    NotAFile {
        /// The path.
        path: PathBuf,
        /// What it is.
        kind: &'static str,
    },
    /// The directory to hold a new case base does not exist.
    #[error("{path}: the directory {dir} does not exist")]
    NoDirectory {
        /// The file.
        path: PathBuf,
        /// Its directory.
        dir: PathBuf,
    },
    /// The case base does not exist (and is not created by this operation).
    #[error("{0}: no case base there")]
    Missing(String),
    /// The case base was learned in another behavior space.
    #[error(
        "{location}: the case base was learned in another behavior space (domain `{domain}`): {what} {stored} in the case base, {here} here"
    )]
    OtherSpace {
        /// The store.
        location: String,
        /// The domain recorded in the case base.
        domain: String,
        /// What differs first.
        what: String,
        /// Its value in the case base.
        stored: String,
        /// Its value in the space being served.
        here: String,
    },
    /// The case base was learned in another domain of the same behavior space.
    #[error(
        "{location}: the case base was learned in domain `{recorded}`, not `{here}` (domains are compared by name, a domain file by its file name); serve or import it with the domain it was learned in"
    )]
    OtherDomain {
        /// The store.
        location: String,
        /// The domain recorded in the case base.
        recorded: String,
        /// The domain being served or imported into.
        here: String,
    },
    /// A stored case does not fit the behavior space.
    #[error(
        "{location}: case #{id} does not fit this domain's behavior space ({reason}); is this the case base of another domain?"
    )]
    Foreign {
        /// The store.
        location: String,
        /// The case's store id.
        id: StoreId,
        /// What does not fit.
        reason: String,
    },
    /// A stored case was learned in a context the domain does not declare.
    #[error(
        "{location}: case #{id} was learned in a context this domain does not declare ({reason}); is this the case base of another domain, or were the domain's context variables changed?"
    )]
    ForeignContext {
        /// The store.
        location: String,
        /// The case's store id.
        id: StoreId,
        /// What is not declared.
        reason: String,
    },
    /// A stored case holds a value no case can have, whatever the domain (a negative
    /// time): not a sign of another domain, so no such hint.
    #[error("{location}: case #{id}: {reason}")]
    Invalid {
        /// The store.
        location: String,
        /// The case's store id.
        id: StoreId,
        /// What is wrong.
        reason: String,
    },
    /// The store holds something that is not a case base of this program.
    #[error("{location}: not a trustcbr case base: {reason}")]
    Corrupt {
        /// The store.
        location: String,
        /// What is wrong.
        reason: String,
    },
    /// RON case files are read-only.
    #[error(
        "{0}: RON case files are read-only; import the cases into an SQLite file or a postgres:// URL instead"
    )]
    ReadOnly(PathBuf),
    /// `cases import` was given a RON file as its target.
    #[error(
        "{target}: RON case files are read-only; import the cases into an SQLite file or a postgres:// URL instead, e.g. `{instead}`"
    )]
    ImportIntoRon {
        /// The RON file given as the target.
        target: PathBuf,
        /// An SQLite file beside it.
        instead: PathBuf,
    },
    /// `cases export` was asked to write over the case base it exports.
    #[error(
        "{out}: this is the case base being exported ({source_base}); give the export another file name"
    )]
    ExportOverSource {
        /// The output path.
        out: PathBuf,
        /// The case base, as given.
        source_base: String,
    },
    /// `cases export` was asked to write over a file that is not an earlier export.
    #[error(
        "{out}: exists and is not an earlier export ({reason}); `cases export` writes over nothing else: give a new file name"
    )]
    ExportOverOther {
        /// The output path.
        out: PathBuf,
        /// What the file is.
        reason: String,
    },
    /// `cases export` writes RON files, whose names end in `.ron`.
    #[error(
        "{0}: an export is a RON case file and its name must end in `.ron` (a case base named otherwise is read as SQLite)"
    )]
    ExportName(PathBuf),
    /// The database refused or failed.
    #[error("{location}: {reason}")]
    Database {
        /// The store.
        location: String,
        /// The database's message.
        reason: String,
    },
    /// The location names a store this build left out (its cargo feature was off).
    #[error(
        "{location}: this tool was built without the `{feature}` feature, so it opens no {store} case base (a `.ron` case file needs no feature)"
    )]
    NotBuilt {
        /// The store.
        location: String,
        /// The kind of store, for people (`SQLite`, `PostgreSQL`).
        store: &'static str,
        /// The cargo feature of `service` (and of the `trustcbr` tool) that builds it.
        feature: &'static str,
    },
    /// A RON file could not be read, parsed or written.
    #[error(transparent)]
    Ron(#[from] ron_file::CaseBaseError),
}

/// A case base: cases with growing ids, learned in one [`Identity`].
pub trait CaseStore: Send {
    /// Where the store is, for messages.
    fn location(&self) -> String;

    /// The domain and space the case base was learned in.
    fn identity(&self) -> &Identity;

    /// Whether [`Self::append`] can succeed (RON files are read-only).
    fn writable(&self) -> bool;

    /// Passes every case with an id greater than `after` (all when `None`) to `each`, in id
    /// order, one at a time.
    fn read_after(
        &mut self,
        after: Option<StoreId>,
        each: &mut dyn FnMut(StoredCase) -> Result<(), StoreError>,
    ) -> Result<(), StoreError>;

    /// In one transaction, durable before it returns: passes every case stored with an id
    /// greater than `after` to `missed`, in id order, then appends `case` and returns its id,
    /// which is greater than every id passed.
    fn append(
        &mut self,
        case: &TrustCase,
        after: Option<StoreId>,
        missed: &mut dyn FnMut(StoredCase),
    ) -> Result<StoreId, StoreError>;

    /// Appends many cases in one transaction (an import), returning how many.
    fn append_all(&mut self, cases: &[TrustCase]) -> Result<usize, StoreError>;
}

/// Opens the case base at `location` for `identity`, creating it (SQLite, PostgreSQL) when
/// absent; refuses one learned in another space. Never rewrites anything that exists.
pub fn open(location: &Location, identity: &Identity) -> Result<Box<dyn CaseStore>, StoreError> {
    let store: Box<dyn CaseStore> = match location {
        Location::Sqlite(path) => open_sqlite(path, Some(identity))?,
        Location::Postgres(url) => open_postgres(url, Some(identity))?,
        Location::Ron(path) => Box::new(ron_file::RonStore::open(path, Some(identity))?),
    };
    check_space(store.as_ref(), &identity.space)?;
    check_domain(store.as_ref(), &identity.domain)?;
    Ok(store)
}

/// Opens the existing case base at `location` as it is, whatever its space (for `cases
/// info` and `cases export`).
pub fn open_existing(location: &Location) -> Result<Box<dyn CaseStore>, StoreError> {
    Ok(match location {
        Location::Sqlite(path) => open_sqlite(path, None)?,
        Location::Postgres(url) => open_postgres(url, None)?,
        Location::Ron(path) => Box::new(ron_file::RonStore::open(path, None)?),
    })
}

#[cfg(feature = "sqlite")]
fn open_sqlite(path: &Path, identity: Option<&Identity>) -> Result<Box<dyn CaseStore>, StoreError> {
    Ok(Box::new(sqlite::SqliteStore::open(path, identity)?))
}

#[cfg(not(feature = "sqlite"))]
fn open_sqlite(
    path: &Path,
    _identity: Option<&Identity>,
) -> Result<Box<dyn CaseStore>, StoreError> {
    Err(StoreError::NotBuilt {
        location: path.display().to_string(),
        store: "SQLite",
        feature: "sqlite",
    })
}

#[cfg(feature = "postgres")]
fn open_postgres(url: &str, identity: Option<&Identity>) -> Result<Box<dyn CaseStore>, StoreError> {
    Ok(Box::new(postgres::PostgresStore::open(url, identity)?))
}

#[cfg(not(feature = "postgres"))]
fn open_postgres(
    url: &str,
    _identity: Option<&Identity>,
) -> Result<Box<dyn CaseStore>, StoreError> {
    Err(StoreError::NotBuilt {
        location: postgres_url::without_password(url),
        store: "PostgreSQL",
        feature: "postgres",
    })
}

fn check_space(store: &dyn CaseStore, space: &BehaviorSpace) -> Result<(), StoreError> {
    let stored = store.identity();
    match stored.space.first_difference(space) {
        None => Ok(()),
        Some(d) => Err(StoreError::OtherSpace {
            location: store.location(),
            domain: stored.domain.clone(),
            what: d.what,
            stored: d.this,
            here: d.other,
        }),
    }
}

/// Refuses a case base recording another domain than `domain`. Built-in domains are
/// compared by name; a domain file (named by the path it was given) by its file name, so
/// the file may move or be given by another path. A case file recording no domain (one
/// written by hand) is not compared.
fn check_domain(store: &dyn CaseStore, domain: &str) -> Result<(), StoreError> {
    let recorded = &store.identity().domain;
    let key = |name: &str| {
        Path::new(name)
            .file_name()
            .map_or_else(|| name.to_owned(), |f| f.to_string_lossy().into_owned())
    };
    if recorded.is_empty() || key(recorded) == key(domain) {
        return Ok(());
    }
    Err(StoreError::OtherDomain {
        location: store.location(),
        recorded: recorded.clone(),
        here: domain.to_owned(),
    })
}

/// Refuses a path that exists but is not a regular file (after following symlinks), so a
/// FIFO or a device is never opened, and a symlink to nothing, so no file is created where
/// it points; a missing path must have an existing directory. Returns whether the file
/// exists.
pub fn check_file(path: &Path) -> Result<bool, StoreError> {
    match std::fs::metadata(path) {
        Ok(meta) if meta.is_file() => Ok(true),
        Ok(meta) => {
            use std::os::unix::fs::FileTypeExt;
            let t = meta.file_type();
            let kind = if t.is_dir() {
                "a directory"
            } else if t.is_fifo() {
                "a FIFO"
            } else if t.is_char_device() || t.is_block_device() {
                "a device"
            } else if t.is_socket() {
                "a socket"
            } else {
                "not a regular file"
            };
            Err(StoreError::NotAFile {
                path: path.to_owned(),
                kind,
            })
        }
        Err(e) if std::fs::symlink_metadata(path).is_ok() => Err(StoreError::NotAFile {
            path: path.to_owned(),
            kind: if e.kind() == std::io::ErrorKind::NotFound {
                "a symlink to nothing"
            } else {
                "a symlink that cannot be followed: a loop of symlinks, or through a folder that cannot be entered"
            },
        }),
        Err(_) => {
            let dir = files::output::folder_of(path);
            if dir.is_dir() {
                Ok(false)
            } else {
                Err(StoreError::NoDirectory {
                    path: path.to_owned(),
                    dir: dir.to_owned(),
                })
            }
        }
    }
}

/// Checks a case read from a store against `space` and `contexts`: every behavior belongs
/// to the space, every time is a finite number >= 0, and its context is one the domain
/// declares, written as a context is (only the values away from their defaults).
pub fn check_case(
    location: &str,
    stored: &StoredCase,
    space: &BehaviorSpace,
    contexts: &ContextSpace,
) -> Result<(), StoreError> {
    let foreign = |reason: String| StoreError::Foreign {
        location: location.to_owned(),
        id: stored.id,
        reason,
    };
    let case = &stored.case;
    check_behavior(space, &case.solution).map_err(|r| foreign(format!("solution: {r}")))?;
    for (k, e) in case.problem.evaluated.iter().enumerate() {
        check_behavior(space, &e.behavior)
            .map_err(|r| foreign(format!("evaluated pair {k}: {r}")))?;
        if !(e.time.is_finite() && e.time >= 0.0) {
            return Err(StoreError::Invalid {
                location: location.to_owned(),
                id: stored.id,
                reason: format!(
                    "evaluated pair {k}: time must be a finite number >= 0, got {}",
                    cbr_core::Shown(e.time)
                ),
            });
        }
    }
    let context = &case.problem.context;
    match contexts.context(context.iter()) {
        Ok(declared) if declared == *context => Ok(()),
        Ok(declared) => {
            let at_default: Vec<String> = context
                .iter()
                .filter(|(variable, _)| declared.get(variable).is_none())
                .map(|(variable, value)| format!("`{variable}` at its default `{value}`"))
                .collect();
            Err(StoreError::Invalid {
                location: location.to_owned(),
                id: stored.id,
                reason: format!(
                    "context: {} written out; a context leaves its defaults out",
                    at_default.join(", ")
                ),
            })
        }
        Err(e) => Err(StoreError::ForeignContext {
            location: location.to_owned(),
            id: stored.id,
            reason: e.to_string(),
        }),
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

/// A case as a database row holds it: the evaluated pairs and the solution, as JSON. An
/// import compares cases by their rows in every build; reading rows back is the
/// databases' alone (the `sqlite` and `postgres` features). Other stores of cases (a trust
/// study's, in the `console` crate) write and read their rows with the same functions.
pub mod row {
    #[cfg(any(feature = "sqlite", feature = "postgres"))]
    use super::{StoreError, StoreId, StoredCase};
    use trust::TrustCase;

    /// The two JSON texts of a case's row.
    pub fn encode(case: &TrustCase) -> (String, String) {
        (
            serde_json::to_string(&case.problem).expect("cases serialize"),
            serde_json::to_string(&case.solution).expect("behaviors serialize"),
        )
    }

    /// A case from its row.
    #[cfg(any(feature = "sqlite", feature = "postgres"))]
    pub fn decode(
        location: &str,
        id: StoreId,
        problem: &str,
        solution: &str,
    ) -> Result<StoredCase, StoreError> {
        let corrupt = |e: serde_json::Error| StoreError::Corrupt {
            location: location.to_owned(),
            reason: format!("case #{id}: {e}"),
        };
        Ok(StoredCase {
            id,
            case: TrustCase {
                problem: serde_json::from_str(problem).map_err(corrupt)?,
                solution: serde_json::from_str(solution).map_err(corrupt)?,
            },
        })
    }

    /// The identity as the JSON text stored beside the cases.
    #[cfg(any(feature = "sqlite", feature = "postgres"))]
    pub fn encode_space(space: &cbr_core::BehaviorSpace) -> String {
        serde_json::to_string(space).expect("spaces serialize")
    }

    /// The stored space, checked as it is read.
    #[cfg(any(feature = "sqlite", feature = "postgres"))]
    pub fn decode_space(location: &str, text: &str) -> Result<cbr_core::BehaviorSpace, StoreError> {
        serde_json::from_str(text).map_err(|e| StoreError::Corrupt {
            location: location.to_owned(),
            reason: format!("the recorded behavior space: {e}"),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cbr_core::{ContextSpace, ContextVariable};
    use proptest::prelude::*;
    use trust::Evaluated;

    fn movement() -> Identity {
        Identity {
            domain: "movement".into(),
            space: (*domains::spaces::movement_space()).clone(),
        }
    }

    fn case(solution: [u16; 2]) -> TrustCase {
        TrustCase {
            problem: vec![Evaluated {
                behavior: Behavior::new(&[3, 4]),
                time: 12.0,
            }]
            .into(),
            solution: Behavior::new(&solution),
        }
    }

    /// `case(solution)`, learned with hazardous cargo.
    fn hazardous_case(solution: [u16; 2]) -> TrustCase {
        let cargo = ContextSpace::new(vec![ContextVariable::new(
            "cargo",
            &["normal", "hazardous"],
        )])
        .unwrap();
        let mut case = case(solution);
        case.problem.context = cargo.context([("cargo", "hazardous")]).unwrap();
        case
    }

    /// A case learned in another context reads back with it from an SQLite file and from
    /// the RON file exported from it, beside a case of the default context, which is stored
    /// as it was before contexts (the problem column holds the bare pairs).
    #[test]
    fn a_case_keeps_its_context_in_every_file_store() {
        let dir = tempfile::tempdir().unwrap();
        let written = vec![case([5, 5]), hazardous_case([6, 6])];
        let sqlite = Location::Sqlite(dir.path().join("cases.db"));
        let mut store = open(&sqlite, &movement()).unwrap();
        let mut last = None;
        for c in &written {
            last = Some(
                store
                    .append(c, last, &mut |_| panic!("nothing missed"))
                    .unwrap(),
            );
        }
        let ron = dir.path().join("cases.ron");
        assert_eq!(super::ron_file::export(store.as_mut(), &ron).unwrap(), 2);
        drop(store);
        for location in [sqlite, Location::Ron(ron)] {
            let mut again = open_existing(&location).unwrap();
            let read: Vec<TrustCase> = all(again.as_mut(), None)
                .into_iter()
                .map(|c| c.case)
                .collect();
            assert_eq!(read, written, "{location:?}");
        }
        let (problem, _) = row::encode(&case([5, 5]));
        assert_eq!(problem, r#"[{"behavior":[3,4],"time":12.0}]"#);
        let (problem, _) = row::encode(&hazardous_case([5, 5]));
        assert!(problem.starts_with(r#"{"context":{"cargo":"hazardous"},"evaluated":"#));
    }

    fn refused(opened: Result<Box<dyn CaseStore>, StoreError>) -> StoreError {
        match opened {
            Ok(_) => panic!("the case base should have been refused"),
            Err(e) => e,
        }
    }

    fn all(store: &mut dyn CaseStore, after: Option<StoreId>) -> Vec<StoredCase> {
        let mut cases = Vec::new();
        store
            .read_after(after, &mut |c| {
                cases.push(c);
                Ok(())
            })
            .unwrap();
        cases
    }

    #[test]
    fn locations_name_their_store() {
        assert_eq!(
            Location::parse("cases.db"),
            Location::Sqlite("cases.db".into())
        );
        assert_eq!(Location::parse("old.ron"), Location::Ron("old.ron".into()));
        assert_eq!(
            Location::parse("postgres://robot:pw@fleet/cases").shown(),
            "postgres://robot:***@fleet/cases"
        );
    }

    /// A build without the PostgreSQL store still reads the URL as PostgreSQL's, and
    /// refuses it naming the feature, its password hidden. Run it with `cargo test -p
    /// service --no-default-features --features sqlite --lib` (a build of its own, so not
    /// in `.ci/run`).
    #[cfg(not(feature = "postgres"))]
    #[test]
    fn a_postgres_url_is_refused_naming_the_feature_when_it_is_left_out() {
        let location = Location::parse("postgres://robot:s3cret@fleet/cases");
        for opened in [open(&location, &movement()), open_existing(&location)] {
            assert_eq!(
                refused(opened).to_string(),
                "postgres://robot:***@fleet/cases: this tool was built without the `postgres` feature, so it opens no PostgreSQL case base (a `.ron` case file needs no feature)"
            );
        }
    }

    #[test]
    fn an_sqlite_base_is_created_appended_and_read_back_by_id() {
        let dir = tempfile::tempdir().unwrap();
        let location = Location::Sqlite(dir.path().join("cases.db"));
        let mut a = open(&location, &movement()).unwrap();
        let mut b = open(&location, &movement()).unwrap();
        assert!(all(a.as_mut(), None).is_empty());
        let first = a
            .append(&case([5, 5]), None, &mut |_| panic!("nothing missed"))
            .unwrap();
        // `b` has seen nothing: its append hands back `a`'s case first.
        let mut missed = Vec::new();
        let second = b
            .append(&case([6, 6]), None, &mut |c| missed.push(c))
            .unwrap();
        assert_eq!(
            missed,
            vec![StoredCase {
                id: first,
                case: case([5, 5])
            }]
        );
        assert!(second > first);
        let seen = all(a.as_mut(), Some(first));
        assert_eq!(seen.len(), 1);
        assert_eq!(seen[0].id, second);
        assert_eq!(seen[0].case, case([6, 6]));
        assert_eq!(all(a.as_mut(), None).len(), 2);
    }

    #[test]
    fn a_base_of_another_space_is_refused_naming_the_first_difference() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cases.db");
        let location = Location::Sqlite(path.clone());
        open(&location, &movement()).unwrap();
        let before = std::fs::read(&path).unwrap();
        let mut edited = movement().space.components().to_vec();
        if let cbr_core::Values::Numeric(grid) = &mut edited[1].values {
            grid.step = 0.05;
        }
        let edited = Identity {
            domain: "movement".into(),
            space: BehaviorSpace::new(edited).unwrap(),
        };
        let err = refused(open(&location, &edited)).to_string();
        assert!(
            err.contains("component 1 (padding): step 0.1 in the case base, 0.05 here"),
            "{err}"
        );
        let patrol = Identity {
            domain: "patrol".into(),
            space: (*domains::spaces::patrol_space()).clone(),
        };
        let err = refused(open(&location, &patrol)).to_string();
        assert!(
            err.contains("(domain `movement`): number of components 2 in the case base, 4 here"),
            "{err}"
        );
        assert_eq!(std::fs::read(&path).unwrap(), before);
    }

    #[test]
    fn a_base_of_another_domain_of_the_same_space_is_refused_naming_both() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cases.db");
        let location = Location::Sqlite(path.clone());
        let file_domain = |name: &str| Identity {
            domain: name.into(),
            ..movement()
        };
        open(&location, &file_domain("/srv/domains/warehouse.ron")).unwrap();
        let before = std::fs::read(&path).unwrap();
        // The same domain file, moved or given by another path.
        open(&location, &file_domain("warehouse.ron")).unwrap();
        open(&location, &file_domain("./d/warehouse.ron")).unwrap();
        for other in ["movement", "/srv/domains/depot.ron"] {
            let err = refused(open(&location, &file_domain(other))).to_string();
            assert_eq!(
                err,
                format!(
                    "{}: the case base was learned in domain `/srv/domains/warehouse.ron`, not `{other}` (domains are compared by name, a domain file by its file name); serve or import it with the domain it was learned in",
                    path.display()
                )
            );
        }
        assert_eq!(std::fs::read(&path).unwrap(), before);
    }

    #[test]
    fn fifos_devices_and_missing_directories_are_refused_before_opening() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("cases.db");
        assert!(
            std::process::Command::new("mkfifo")
                .arg(&fifo)
                .status()
                .unwrap()
                .success()
        );
        let err = refused(open(&Location::Sqlite(fifo), &movement()));
        assert!(
            err.to_string().contains("not a regular file (a FIFO)"),
            "{err}"
        );
        let zero = dir.path().join("zero.ron");
        std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
        let err = refused(open(&Location::Ron(zero), &movement()));
        assert!(
            err.to_string().contains("not a regular file (a device)"),
            "{err}"
        );
        let dangling = dir.path().join("planted.db");
        let target = dir.path().join("elsewhere.db");
        std::os::unix::fs::symlink(&target, &dangling).unwrap();
        let err = refused(open(&Location::Sqlite(dangling), &movement()));
        assert!(
            err.to_string()
                .contains("not a regular file (a symlink to nothing)"),
            "{err}"
        );
        assert!(!target.exists());
        let err = refused(open(
            &Location::parse("/nonexistent/dir/cases.db"),
            &movement(),
        ));
        assert!(
            err.to_string()
                .contains("the directory /nonexistent/dir does not exist"),
            "{err}"
        );
    }

    #[test]
    fn a_database_of_another_program_is_refused_untouched() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("inventory.db");
        rusqlite::Connection::open(&path)
            .unwrap()
            .execute_batch("CREATE TABLE parts (name TEXT)")
            .unwrap();
        let before = std::fs::read(&path).unwrap();
        let err = refused(open(&Location::Sqlite(path.clone()), &movement()));
        assert!(err.to_string().contains("other tables (parts)"), "{err}");
        assert_eq!(std::fs::read(&path).unwrap(), before);
    }

    #[test]
    fn a_ron_file_is_read_only_and_its_cases_are_checked_by_the_reader() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cases.ron");
        let text = "(cases: [(problem: [(behavior: [3, 4], time: 12.0)], solution: [1, 25])])";
        std::fs::write(&path, text).unwrap();
        let mut store = open(&Location::Ron(path.clone()), &movement()).unwrap();
        assert!(!store.writable());
        let cases = all(store.as_mut(), None);
        let err = check_case(
            &store.location(),
            &cases[0],
            &movement().space,
            &ContextSpace::NONE,
        )
        .unwrap_err();
        assert!(
            err.to_string()
                .contains("case #0 does not fit this domain's behavior space (solution: value index 25 of `padding` is out of range"),
            "{err}"
        );
        let err = store.append(&case([1, 1]), None, &mut |_| {}).unwrap_err();
        assert!(
            err.to_string().contains("RON case files are read-only"),
            "{err}"
        );
        assert_eq!(std::fs::read_to_string(&path).unwrap(), text);
    }

    #[test]
    fn a_case_is_read_only_in_a_context_the_domain_declares_and_as_contexts_are_written() {
        let contexts = ContextSpace::new(vec![cbr_core::ContextVariable::new(
            "cargo",
            &["normal", "hazardous"],
        )])
        .unwrap();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cases.ron");
        let read = |context: &str| {
            let text = format!(
                "(cases: [(problem: (context: {context}, evaluated: [(behavior: [3, 4], time: 12.0)]), solution: [1, 2])])"
            );
            std::fs::write(&path, &text).unwrap();
            let mut store = open(&Location::Ron(path.clone()), &movement()).unwrap();
            let cases = all(store.as_mut(), None);
            let checked = check_case(&store.location(), &cases[0], &movement().space, &contexts);
            assert_eq!(std::fs::read_to_string(&path).unwrap(), text);
            checked.map_err(|e| e.to_string())
        };
        assert_eq!(read(r#"{"cargo": "hazardous"}"#), Ok(()));
        let err = read(r#"{"cargo": "toxic"}"#).unwrap_err();
        assert!(
            err.contains("case #0 was learned in a context this domain does not declare (context variable `cargo` may be normal, hazardous, not `toxic`)"),
            "{err}"
        );
        let err = read(r#"{"situation": "emergency"}"#).unwrap_err();
        assert!(
            err.contains("was learned in a context this domain does not declare"),
            "{err}"
        );
        let err = read(r#"{"cargo": "normal"}"#).unwrap_err();
        assert!(
            err.ends_with("case #0: context: `cargo` at its default `normal` written out; a context leaves its defaults out"),
            "{err}"
        );
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        #[test]
        fn arbitrary_bytes_never_panic_and_are_left_untouched(bytes in prop::collection::vec(any::<u8>(), 1..200)) {
            let dir = tempfile::tempdir().unwrap();
            for name in ["cases.db", "cases.ron"] {
                let path = dir.path().join(name);
                std::fs::write(&path, &bytes).unwrap();
                let _ = open(&Location::parse(path.to_str().unwrap()), &movement());
                prop_assert_eq!(std::fs::read(&path).unwrap(), bytes.clone());
            }
        }

        #[test]
        fn arbitrary_case_like_text_never_panics(text in r#"\(cases:\[(\(problem:\[(\(behavior:\[[0-9]{1,5}(,[0-9]{1,5}){0,9}\],time:-?[0-9.e]{1,5}\),?){0,2}\],solution:\[[0-9,]{0,8}\]\),?){0,3}\]\)"#) {
            let dir = tempfile::tempdir().unwrap();
            let path = dir.path().join("cases.ron");
            std::fs::write(&path, &text).unwrap();
            if let Ok(mut store) = open(&Location::Ron(path), &movement()) {
                let location = store.location();
                let space = movement().space;
                let _ = store.read_after(None, &mut |c| {
                    check_case(&location, &c, &space, &ContextSpace::NONE)
                });
            }
        }
    }
}
