//! [`SqliteStore`]: a case base in an SQLite database file (the default store).
//!
//! Two tables: `trustcbr_identity` (one row: format, domain, behavior space as JSON) and
//! `trustcbr_cases` (`id INTEGER PRIMARY KEY AUTOINCREMENT`, evaluated pairs and solution
//! as JSON). The database runs in WAL mode with `synchronous=FULL`, so a committed append
//! survives a crash or a power cut; SQLite has one writer at a time, so ids are assigned in
//! commit order and never reused. Several processes may open one file: each append takes
//! the write lock first (`BEGIN IMMEDIATE`) and waits for it up to [`BUSY_TIMEOUT`].

use super::sqlite_file::{HEADER, header};
use super::{CaseStore, Identity, StoreError, StoreId, StoredCase, check_file, row};
use rusqlite::types::Value;
use rusqlite::{Connection, OpenFlags, TransactionBehavior, params};
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
    /// exist and is opened read-only: nothing is written to the file or beside it that a
    /// reader would not write (no switch to WAL, no table). A path that is not a regular
    /// file is refused before anything opens it, and a database that is not a case base of
    /// this program (other tables, tables of our names with other columns, a missing or
    /// unreadable identity) is refused before anything is written to it. The space
    /// recorded is not compared here (see [`super::open`]).
    pub fn open(path: &Path, identity: Option<&Identity>) -> Result<Self, StoreError> {
        let mut exists = check_file(path)?;
        let location = path.display().to_string();
        match identity {
            None if !exists => return Err(StoreError::Missing(location)),
            Some(identity) if !exists => {
                // A new case base appears whole or not at all: a process killed while it
                // is made leaves no file a reader would take for an empty store.
                files::output::create_whole(path, |temp| create(temp, identity))
                    .map_err(|e| e.into_store_error(&location))?;
                exists = true;
            }
            _ => {}
        }
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
                Err(Failure::Sqlite(e)) if identity.is_some() && cannot_write(&e) => {
                    return Err(unwritable(path, &location, e));
                }
                Err(failure) => return Err(failure.into_store_error(&location)),
            }
        }
    }

    /// One attempt at [`Self::open`] once the file is known to be fit to open.
    fn connect(path: &Path, location: &str, identity: Option<&Identity>) -> Result<Self, Failure> {
        let Some(identity) = identity else {
            let (connection, recorded) = open_read_only(path, location)?;
            return Ok(Self {
                path: path.to_owned(),
                connection,
                identity: recorded.ok_or_else(|| StoreError::Missing(location.to_owned()))?,
            });
        };
        let flags = OpenFlags::SQLITE_OPEN_READ_WRITE
            | OpenFlags::SQLITE_OPEN_CREATE
            | OpenFlags::SQLITE_OPEN_NO_MUTEX;
        let mut connection = Connection::open_with_flags(path, flags)?;
        connection.busy_timeout(BUSY_TIMEOUT)?;
        // Checked before the first write, so a database that is not ours stays as it is.
        recorded(&connection, location)?;
        connection.pragma_update(None, "journal_mode", "WAL")?;
        connection.pragma_update(None, "synchronous", "FULL")?;
        let transaction = connection.transaction_with_behavior(TransactionBehavior::Immediate)?;
        // Another process may have created the case base since the check above.
        let identity = match recorded(&transaction, location)? {
            Some(recorded) => recorded,
            None => {
                transaction.execute_batch(SCHEMA)?;
                transaction.execute(
                    "INSERT INTO trustcbr_identity (singleton, format, domain, space) VALUES (1, ?1, ?2, ?3)",
                    params![FORMAT, identity.domain, row::encode_space(&identity.space)],
                )?;
                identity.clone()
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

/// Makes a new case base recording `identity` in the (empty) file at `path`: WAL mode,
/// the schema and the identity, committed, and the connection closed (which folds the
/// write-ahead log back into the file), so the file alone holds all of it.
fn create(path: &Path, identity: &Identity) -> Result<(), Failure> {
    let flags = OpenFlags::SQLITE_OPEN_READ_WRITE | OpenFlags::SQLITE_OPEN_NO_MUTEX;
    let mut connection = Connection::open_with_flags(path, flags)?;
    connection.pragma_update(None, "journal_mode", "WAL")?;
    connection.pragma_update(None, "synchronous", "FULL")?;
    let transaction = connection.transaction_with_behavior(TransactionBehavior::Immediate)?;
    transaction.execute_batch(SCHEMA)?;
    transaction.execute(
        "INSERT INTO trustcbr_identity (singleton, format, domain, space) VALUES (1, ?1, ?2, ?3)",
        params![FORMAT, identity.domain, row::encode_space(&identity.space)],
    )?;
    transaction.commit()?;
    connection.close().map_err(|(_, e)| Failure::Sqlite(e))
}

/// Opens `path` read-only and reads its identity. A reader of a database in WAL mode needs
/// its `-wal` and `-shm` files, and SQLite creates them beside the database when they are
/// missing (holding nothing: the database file itself is never written). Where they cannot
/// be created (a read-only folder or file system) and no `-wal` exists, so that no process
/// has the database open for writing, it is opened as immutable: nothing can change it.
fn open_read_only(path: &Path, location: &str) -> Result<(Connection, Option<Identity>), Failure> {
    let flags = OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_NO_MUTEX;
    let connection = Connection::open_with_flags(path, flags)?;
    connection.busy_timeout(BUSY_TIMEOUT)?;
    match recorded(&connection, location) {
        Err(Failure::Sqlite(e))
            if e.sqlite_error_code() == Some(rusqlite::ErrorCode::CannotOpen)
                && !sibling(path, "-wal").exists() =>
        {
            let mut uri = String::from("file:");
            for byte in path.as_os_str().as_encoded_bytes() {
                if byte.is_ascii_alphanumeric() || b"/-._~".contains(byte) {
                    uri.push(char::from(*byte));
                } else {
                    uri.push_str(&format!("%{byte:02X}"));
                }
            }
            uri.push_str("?immutable=1");
            let connection = Connection::open_with_flags(&uri, flags | OpenFlags::SQLITE_OPEN_URI)?;
            let recorded = recorded(&connection, location)?;
            Ok((connection, recorded))
        }
        read => Ok((connection, read?)),
    }
}

/// `path` with `suffix` appended to its file name (`-wal`, `-shm`).
fn sibling(path: &Path, suffix: &str) -> PathBuf {
    let mut name = path.as_os_str().to_owned();
    name.push(suffix);
    PathBuf::from(name)
}

/// The columns of our two tables, as `PRAGMA table_info` gives them (name, declared type).
const COLUMNS: [(&str, &[(&str, &str)]); 2] = [
    (
        "trustcbr_identity",
        &[
            ("singleton", "INTEGER"),
            ("format", "INTEGER"),
            ("domain", "TEXT"),
            ("space", "TEXT"),
        ],
    ),
    (
        "trustcbr_cases",
        &[("id", "INTEGER"), ("problem", "TEXT"), ("solution", "TEXT")],
    ),
];

/// The identity a case base records, read without writing anything: `None` for a database
/// with no table at all (a new file); an error for anything but a case base of ours.
fn recorded(connection: &Connection, location: &str) -> Result<Option<Identity>, Failure> {
    let corrupt = |reason: String| {
        Failure::Store(StoreError::Corrupt {
            location: location.to_owned(),
            reason,
        })
    };
    let tables: Vec<String> = connection
        .prepare("SELECT name FROM sqlite_master WHERE type = 'table' AND name NOT LIKE 'sqlite\\_%' ESCAPE '\\' ORDER BY name")?
        .query_map([], |r| r.get(0))?
        .collect::<Result<_, _>>()?;
    if tables.is_empty() {
        return Ok(None);
    }
    let ours = COLUMNS.map(|(table, _)| table);
    let others: Vec<&str> = tables
        .iter()
        .map(String::as_str)
        .filter(|t| !ours.contains(t))
        .collect();
    if !others.is_empty() {
        return Err(corrupt(format!(
            "an SQLite database with other tables ({}); give a new file name",
            others.join(", ")
        )));
    }
    for (table, expected) in COLUMNS {
        if !tables.iter().any(|t| t == table) {
            return Err(corrupt(format!("the table {table} is missing")));
        }
        let columns: Vec<(String, String)> = connection
            .prepare(&format!("PRAGMA table_info({table})"))?
            .query_map([], |r| Ok((r.get(1)?, r.get(2)?)))?
            .collect::<Result<_, _>>()?;
        let fits = columns.len() == expected.len()
            && columns
                .iter()
                .zip(expected)
                .all(|((name, kind), (n, k))| name == n && kind.eq_ignore_ascii_case(k));
        if !fits {
            let show = |c: &mut dyn Iterator<Item = (&str, &str)>| {
                c.map(|(n, k)| format!("{n} {k}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            return Err(corrupt(format!(
                "the table {table} has the columns ({}), a case base's has ({})",
                show(&mut columns.iter().map(|(n, k)| (n.as_str(), k.as_str()))),
                show(&mut expected.iter().copied()),
            )));
        }
    }
    let rows: Vec<(Value, Value, Value)> = connection
        .prepare("SELECT format, domain, space FROM trustcbr_identity")?
        .query_map([], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)))?
        .collect::<Result<_, _>>()?;
    let [(format, domain, space)] = <[_; 1]>::try_from(rows).map_err(|rows: Vec<_>| {
        corrupt(format!(
            "the table trustcbr_identity holds {} rows, a case base's holds one",
            rows.len()
        ))
    })?;
    let (Value::Integer(format), Value::Text(domain), Value::Text(space)) = (format, domain, space)
    else {
        return Err(corrupt(
            "the row of trustcbr_identity does not hold an integer format, a text domain and a text space".to_owned(),
        ));
    };
    if format != FORMAT {
        return Err(corrupt(format!(
            "format {format}, this program reads format {FORMAT}"
        )));
    }
    Ok(Some(Identity {
        domain,
        space: row::decode_space(location, &space)?,
    }))
}

/// Why one attempt to open failed: SQLite's own error (perhaps worth another attempt), or
/// a case base that is not fit to serve.
enum Failure {
    Sqlite(rusqlite::Error),
    Store(StoreError),
    Io(std::io::Error),
}

impl From<rusqlite::Error> for Failure {
    fn from(e: rusqlite::Error) -> Self {
        Self::Sqlite(e)
    }
}

impl From<std::io::Error> for Failure {
    fn from(e: std::io::Error) -> Self {
        Self::Io(e)
    }
}

impl Failure {
    /// The store's error for this failure at `location`.
    fn into_store_error(self, location: &str) -> StoreError {
        match self {
            Self::Sqlite(e) => database_error(location, e),
            Self::Store(e) => e,
            Self::Io(e) => StoreError::Database {
                location: location.to_owned(),
                reason: format!("cannot create the case base beside it: {e}"),
            },
        }
    }
}

impl From<StoreError> for Failure {
    fn from(e: StoreError) -> Self {
        Self::Store(e)
    }
}

/// Whether SQLite refused because another connection holds a lock.
/// Whether SQLite could not open or write a database (it does not say why).
fn cannot_write(e: &rusqlite::Error) -> bool {
    matches!(
        e.sqlite_error_code(),
        Some(rusqlite::ErrorCode::CannotOpen | rusqlite::ErrorCode::ReadOnly)
    )
}

/// The error of a case base at `path` that SQLite could not open to write (`e`), with the
/// reason it does not give: what the system says when the file, or its folder (where the
/// write-ahead log goes), is opened for writing (a read-only file system, no permission).
fn unwritable(path: &Path, location: &str, e: rusqlite::Error) -> StoreError {
    let folder = files::output::folder_of(path);
    let refused = std::fs::OpenOptions::new()
        .append(true)
        .open(path)
        .err()
        .map(|why| format!("the file cannot be opened for writing ({why})"))
        .or_else(|| {
            files::output::ensure_writable_dir(folder).err().map(|why| {
                format!("its folder takes no new file, as the write-ahead log needs ({why})")
            })
        });
    match refused {
        Some(reason) => StoreError::Database {
            location: location.to_owned(),
            reason: format!(
                "{e}: {reason}; a served case base is written: give a writable place (`cases export` and `cases info` read it as it is)"
            ),
        },
        None => database_error(location, e),
    }
}

fn is_busy(e: &rusqlite::Error) -> bool {
    matches!(
        e.sqlite_error_code(),
        Some(rusqlite::ErrorCode::DatabaseBusy | rusqlite::ErrorCode::DatabaseLocked)
    )
}

/// Whether the file is empty or begins with SQLite's header: SQLite would take any file
/// shorter than a page for an empty database and write over it.
fn starts_like_a_database(path: &Path) -> bool {
    matches!(header(path), Some(start) if start.is_empty() || start == HEADER)
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
        let text = |column: usize, name: &str| match r.get_ref(column) {
            Ok(rusqlite::types::ValueRef::Text(bytes)) => std::str::from_utf8(bytes)
                .map_err(|_| corrupt_case(location, id, name, "not UTF-8 text")),
            Ok(_) => Err(corrupt_case(location, id, name, "not text")),
            Err(e) => Err(db(e)),
        };
        each(row::decode(
            location,
            id,
            text(1, "problem")?,
            text(2, "solution")?,
        )?)?;
    }
    Ok(())
}

fn corrupt_case(location: &str, id: StoreId, column: &str, what: &str) -> StoreError {
    StoreError::Corrupt {
        location: location.to_owned(),
        reason: format!("case #{id}: its {column} is {what}"),
    }
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
