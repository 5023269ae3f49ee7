//! [`SqliteStore`]: a case base in an SQLite database file (the default store).
//!
//! Two tables: `trustcbr_identity` (one row: format, domain, behavior space as JSON) and
//! `trustcbr_cases` (`id INTEGER PRIMARY KEY AUTOINCREMENT`, evaluated pairs and solution
//! as JSON). The database runs in WAL mode with `synchronous=FULL`, so a committed append
//! survives a crash or a power cut; SQLite has one writer at a time, so ids are assigned in
//! commit order and never reused. Several processes may open one file: each append takes
//! the write lock first (`BEGIN IMMEDIATE`) and waits for it up to [`BUSY_TIMEOUT`].

use super::{CaseStore, Identity, StoreError, StoreId, StoredCase, check_file, row};
use rusqlite::{Connection, OpenFlags, OptionalExtension, TransactionBehavior, params};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use trust::TrustCase;

/// The version of the layout below, recorded in every case base.
const FORMAT: i64 = 1;

/// How long an append waits for another process's write to finish.
pub const BUSY_TIMEOUT: Duration = Duration::from_secs(30);

const SCHEMA: &str = "
    CREATE TABLE IF NOT EXISTS trustcbr_identity (
        singleton INTEGER PRIMARY KEY CHECK (singleton = 1),
        format INTEGER NOT NULL,
        domain TEXT NOT NULL,
        space TEXT NOT NULL
    );
    CREATE TABLE IF NOT EXISTS trustcbr_cases (
        id INTEGER PRIMARY KEY AUTOINCREMENT,
        problem TEXT NOT NULL,
        solution TEXT NOT NULL
    );";

/// A case base in an SQLite file.
pub struct SqliteStore {
    path: PathBuf,
    connection: Connection,
    identity: Identity,
}

impl SqliteStore {
    /// Opens the database at `path`. With an `identity`, a missing file (or an empty
    /// database) becomes a new case base recording it; without one, the case base must
    /// exist. A path that is not a regular file is refused before anything opens it, and a
    /// database holding other tables is refused untouched. The space recorded is not
    /// compared here (see [`super::open`]).
    pub fn open(path: &Path, identity: Option<&Identity>) -> Result<Self, StoreError> {
        let exists = check_file(path)?;
        if !exists && identity.is_none() {
            return Err(StoreError::Missing(path.display().to_string()));
        }
        let location = path.display().to_string();
        if exists && !starts_like_a_database(path) {
            return Err(StoreError::Corrupt {
                location,
                reason: "not an SQLite database (nor empty); RON case files must end in `.ron`"
                    .to_owned(),
            });
        }
        // Several servers starting together on a new file race to switch it to WAL, and
        // SQLite may refuse that switch without waiting; every step below may be repeated,
        // so a busy database is tried again until `BUSY_TIMEOUT`.
        let deadline = Instant::now() + BUSY_TIMEOUT;
        loop {
            match Self::connect(path, &location, identity) {
                Ok(store) => return Ok(store),
                Err(Failure::Sqlite(e)) if is_busy(&e) && Instant::now() < deadline => {
                    std::thread::sleep(Duration::from_millis(10));
                }
                Err(Failure::Sqlite(e)) => return Err(database_error(&location, e)),
                Err(Failure::Store(e)) => return Err(e),
            }
        }
    }

    /// One attempt at [`Self::open`] once the file is known to be fit to open.
    fn connect(path: &Path, location: &str, identity: Option<&Identity>) -> Result<Self, Failure> {
        let mut flags = OpenFlags::SQLITE_OPEN_READ_WRITE | OpenFlags::SQLITE_OPEN_NO_MUTEX;
        if identity.is_some() {
            flags |= OpenFlags::SQLITE_OPEN_CREATE;
        }
        let mut connection = Connection::open_with_flags(path, flags)?;
        connection.busy_timeout(BUSY_TIMEOUT)?;
        let tables: Vec<String> = connection
            .prepare("SELECT name FROM sqlite_master WHERE type = 'table'")?
            .query_map([], |r| r.get(0))?
            .collect::<Result<_, _>>()?;
        let ours = tables.iter().any(|t| t == "trustcbr_identity");
        if !ours && tables.iter().any(|t| !t.starts_with("sqlite_")) {
            return Err(Failure::Store(StoreError::Corrupt {
                location: location.to_owned(),
                reason: format!(
                    "an SQLite database with other tables ({}); give a new file name",
                    tables.join(", ")
                ),
            }));
        }
        connection.pragma_update(None, "journal_mode", "WAL")?;
        connection.pragma_update(None, "synchronous", "FULL")?;
        let transaction = connection.transaction_with_behavior(TransactionBehavior::Immediate)?;
        transaction.execute_batch(SCHEMA)?;
        let recorded: Option<(i64, String, String)> = transaction
            .query_row(
                "SELECT format, domain, space FROM trustcbr_identity",
                [],
                |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)),
            )
            .optional()?;
        let identity = match (recorded, identity) {
            (Some((format, domain, space)), _) => {
                if format != FORMAT {
                    return Err(Failure::Store(StoreError::Corrupt {
                        location: location.to_owned(),
                        reason: format!("format {format}, this program reads format {FORMAT}"),
                    }));
                }
                Identity {
                    domain,
                    space: row::decode_space(location, &space)?,
                }
            }
            (None, Some(identity)) => {
                transaction.execute(
                    "INSERT INTO trustcbr_identity (singleton, format, domain, space) VALUES (1, ?1, ?2, ?3)",
                    params![FORMAT, identity.domain, row::encode_space(&identity.space)],
                )?;
                identity.clone()
            }
            (None, None) => {
                return Err(Failure::Store(StoreError::Missing(location.to_owned())));
            }
        };
        transaction.commit()?;
        Ok(Self {
            path: path.to_owned(),
            connection,
            identity,
        })
    }
}

/// Why one attempt to open failed: SQLite's own error (perhaps worth another attempt), or
/// a case base that is not fit to serve.
enum Failure {
    Sqlite(rusqlite::Error),
    Store(StoreError),
}

impl From<rusqlite::Error> for Failure {
    fn from(e: rusqlite::Error) -> Self {
        Self::Sqlite(e)
    }
}

impl From<StoreError> for Failure {
    fn from(e: StoreError) -> Self {
        Self::Store(e)
    }
}

/// Whether SQLite refused because another connection holds a lock.
fn is_busy(e: &rusqlite::Error) -> bool {
    matches!(
        e.sqlite_error_code(),
        Some(rusqlite::ErrorCode::DatabaseBusy | rusqlite::ErrorCode::DatabaseLocked)
    )
}

/// Whether the file is empty or begins with SQLite's header: SQLite would take any file
/// shorter than a page for an empty database and write over it.
fn starts_like_a_database(path: &Path) -> bool {
    use std::io::Read;
    const HEADER: &[u8; 16] = b"SQLite format 3\0";
    let mut start = Vec::with_capacity(HEADER.len());
    let read =
        std::fs::File::open(path).and_then(|f| f.take(HEADER.len() as u64).read_to_end(&mut start));
    read.is_ok() && (start.is_empty() || start == HEADER)
}

fn database_error(location: &str, e: rusqlite::Error) -> StoreError {
    StoreError::Database {
        location: location.to_owned(),
        reason: e.to_string(),
    }
}

/// A transaction that holds the write lock from its start, so what it reads is what it
/// appends after.
fn begin_write<'c>(
    connection: &'c mut Connection,
    location: &str,
) -> Result<rusqlite::Transaction<'c>, StoreError> {
    connection
        .transaction_with_behavior(TransactionBehavior::Immediate)
        .map_err(|e| database_error(location, e))
}

/// Inserts one case; returns its id.
fn insert(
    connection: &Connection,
    location: &str,
    case: &TrustCase,
) -> Result<StoreId, StoreError> {
    let (problem, solution) = row::encode(case);
    connection
        .prepare_cached("INSERT INTO trustcbr_cases (problem, solution) VALUES (?1, ?2)")
        .and_then(|mut s| s.execute(params![problem, solution]))
        .map_err(|e| database_error(location, e))?;
    Ok(connection.last_insert_rowid())
}

fn read_rows(
    connection: &Connection,
    location: &str,
    after: Option<StoreId>,
    each: &mut dyn FnMut(StoredCase) -> Result<(), StoreError>,
) -> Result<(), StoreError> {
    let db = |e| database_error(location, e);
    let mut statement = connection
        .prepare_cached(
            "SELECT id, problem, solution FROM trustcbr_cases WHERE id > ?1 ORDER BY id",
        )
        .map_err(db)?;
    let mut rows = statement
        .query([after.unwrap_or(StoreId::MIN)])
        .map_err(db)?;
    while let Some(r) = rows.next().map_err(db)? {
        let id: StoreId = r.get(0).map_err(db)?;
        let problem = r
            .get_ref(1)
            .map_err(db)?
            .as_str()
            .map_err(|e| db(e.into()))?;
        let solution = r
            .get_ref(2)
            .map_err(db)?
            .as_str()
            .map_err(|e| db(e.into()))?;
        each(row::decode(location, id, problem, solution)?)?;
    }
    Ok(())
}

impl CaseStore for SqliteStore {
    fn location(&self) -> String {
        self.path.display().to_string()
    }

    fn identity(&self) -> &Identity {
        &self.identity
    }

    fn writable(&self) -> bool {
        true
    }

    fn read_after(
        &mut self,
        after: Option<StoreId>,
        each: &mut dyn FnMut(StoredCase) -> Result<(), StoreError>,
    ) -> Result<(), StoreError> {
        read_rows(&self.connection, &self.location(), after, each)
    }

    fn append(
        &mut self,
        case: &TrustCase,
        after: Option<StoreId>,
        missed: &mut dyn FnMut(StoredCase),
    ) -> Result<StoreId, StoreError> {
        let location = self.location();
        let transaction = begin_write(&mut self.connection, &location)?;
        read_rows(&transaction, &location, after, &mut |c| {
            missed(c);
            Ok(())
        })?;
        let id = insert(&transaction, &location, case)?;
        transaction
            .commit()
            .map_err(|e| database_error(&location, e))?;
        Ok(id)
    }

    fn append_all(&mut self, cases: &[TrustCase]) -> Result<usize, StoreError> {
        let location = self.location();
        let transaction = begin_write(&mut self.connection, &location)?;
        for case in cases {
            insert(&transaction, &location, case)?;
        }
        transaction
            .commit()
            .map_err(|e| database_error(&location, e))?;
        Ok(cases.len())
    }
}
