//! [`PostgresStore`]: a case base in a PostgreSQL database, shared by a fleet of robots on
//! several machines (`--cases postgres://user@host/db`).
//!
//! The same two tables as the SQLite store: `trustcbr_identity` (one row) and
//! `trustcbr_cases` (`id bigint GENERATED ALWAYS AS IDENTITY`). A sequence hands out ids
//! out of commit order when transactions overlap, and a reader that saw id 7 committed
//! before id 6 would skip 6 for good; so every append (and the creation of the tables)
//! first takes one transaction-scoped advisory lock, [`APPEND_LOCK`]: appends are
//! serialized across the fleet, ids are committed in order, and "every case with an id
//! greater than the last one seen" is exactly what a server has not seen. A commit returns
//! once PostgreSQL has flushed it (`synchronous_commit` on, its default). A lost connection
//! is made again at the next use.

use super::postgres_url::without_password;
use super::{CaseStore, Identity, StoreError, StoreId, StoredCase, row};
use postgres::fallible_iterator::FallibleIterator;
use postgres::{Client, GenericClient, NoTls, Transaction};
use trust::TrustCase;

/// The version of the layout below, recorded in every case base.
const FORMAT: i64 = 1;

/// How long a connection suspected lost may take to answer before it is made again.
const CHECK_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(5);

/// The advisory lock key every append holds until it commits ("trustcbr" in ASCII).
pub const APPEND_LOCK: i64 = 0x7472_7573_7463_6272;

const SCHEMA: &str = "
    CREATE TABLE IF NOT EXISTS trustcbr_identity (
        singleton integer PRIMARY KEY CHECK (singleton = 1),
        format bigint NOT NULL,
        domain text NOT NULL,
        space text NOT NULL
    );
    CREATE TABLE IF NOT EXISTS trustcbr_cases (
        id bigint GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
        problem text NOT NULL,
        solution text NOT NULL
    );";

/// A case base in a PostgreSQL database.
pub struct PostgresStore {
    /// The URL as given (with its password), to reconnect.
    url: String,
    location: String,
    client: Client,
    /// Whether the last use failed, so the connection may be lost.
    suspect: bool,
    identity: Identity,
}

impl PostgresStore {
    /// Connects to `url`. With an `identity`, a database without a case base gets one
    /// recording it; without one, the case base must exist and is only read, in a
    /// read-only transaction (a role with nothing but SELECT rights suffices). Tables of
    /// our names with other columns, and a missing or unreadable identity, are refused
    /// before anything is written. The space recorded is not compared here (see
    /// [`super::open`]).
    pub fn open(url: &str, identity: Option<&Identity>) -> Result<Self, StoreError> {
        let location = without_password(url);
        let db = |e: postgres::Error| database_error(&location, &e);
        let mut client = Client::connect(url, NoTls).map_err(db)?;
        let identity = match identity {
            None => {
                let mut transaction = client
                    .build_transaction()
                    .read_only(true)
                    .start()
                    .map_err(db)?;
                let recorded = recorded(&mut transaction, &location)?
                    .ok_or_else(|| StoreError::Missing(location.clone()))?;
                transaction.commit().map_err(db)?;
                recorded
            }
            Some(identity) => {
                let mut transaction = begin_append(&mut client, &location)?;
                let recorded = match recorded(&mut transaction, &location)? {
                    Some(recorded) => recorded,
                    None => {
                        transaction.batch_execute(SCHEMA).map_err(db)?;
                        transaction
                            .execute(
                                "INSERT INTO trustcbr_identity (singleton, format, domain, space) VALUES (1, $1, $2, $3)",
                                &[&FORMAT, &identity.domain, &row::encode_space(&identity.space)],
                            )
                            .map_err(db)?;
                        identity.clone()
                    }
                };
                transaction.commit().map_err(db)?;
                recorded
            }
        };
        Ok(Self {
            url: url.to_owned(),
            location,
            client,
            suspect: false,
            identity,
        })
    }
}

/// The columns of our two tables (name, type as `format_type` shows it).
const COLUMNS: [(&str, &[(&str, &str)]); 2] = [
    (
        "trustcbr_identity",
        &[
            ("singleton", "integer"),
            ("format", "bigint"),
            ("domain", "text"),
            ("space", "text"),
        ],
    ),
    (
        "trustcbr_cases",
        &[("id", "bigint"), ("problem", "text"), ("solution", "text")],
    ),
];

/// The identity the case base records, read without writing anything: `None` when neither
/// of our tables exists; an error for tables of our names that are not a case base's.
fn recorded(
    client: &mut impl GenericClient,
    location: &str,
) -> Result<Option<Identity>, StoreError> {
    let db = |e: postgres::Error| database_error(location, &e);
    let corrupt = |reason: String| StoreError::Corrupt {
        location: location.to_owned(),
        reason,
    };
    let mut missing = Vec::new();
    for (table, expected) in COLUMNS {
        let columns: Vec<(String, String)> = client
            .query(
                "SELECT attname::text, format_type(atttypid, atttypmod) FROM pg_attribute
                 WHERE attrelid = to_regclass($1) AND attnum > 0 AND NOT attisdropped
                 ORDER BY attnum",
                &[&table],
            )
            .map_err(db)?
            .iter()
            .map(|r| (r.get(0), r.get(1)))
            .collect();
        if columns.is_empty() {
            missing.push(table);
            continue;
        }
        let fits = columns.len() == expected.len()
            && columns
                .iter()
                .zip(expected)
                .all(|((name, kind), (n, k))| name == n && kind == k);
        if !fits {
            let show = |c: Vec<String>| c.join(", ");
            return Err(corrupt(format!(
                "the table {table} has the columns ({}), a case base's has ({})",
                show(columns.iter().map(|(n, k)| format!("{n} {k}")).collect()),
                show(expected.iter().map(|(n, k)| format!("{n} {k}")).collect()),
            )));
        }
    }
    if missing.len() == COLUMNS.len() {
        return Ok(None);
    }
    if let Some(table) = missing.first() {
        return Err(corrupt(format!("the table {table} is missing")));
    }
    let rows = client
        .query("SELECT format, domain, space FROM trustcbr_identity", &[])
        .map_err(db)?;
    let [r] = &rows[..] else {
        return Err(corrupt(format!(
            "the table trustcbr_identity holds {} rows, a case base's holds one",
            rows.len()
        )));
    };
    let unreadable = |e: postgres::Error| corrupt(format!("the row of trustcbr_identity: {e}"));
    let format: i64 = r.try_get(0).map_err(unreadable)?;
    if format != FORMAT {
        return Err(corrupt(format!(
            "format {format}, this program reads format {FORMAT}"
        )));
    }
    Ok(Some(Identity {
        domain: r.try_get(1).map_err(unreadable)?,
        space: row::decode_space(location, r.try_get(2).map_err(unreadable)?)?,
    }))
}

fn database_error(location: &str, e: &postgres::Error) -> StoreError {
    // The database's own message (e.g. "relation ... does not exist") is the useful part.
    let reason = match e.as_db_error() {
        Some(db) => db.message().to_owned(),
        None => e.to_string(),
    };
    StoreError::Database {
        location: location.to_owned(),
        reason,
    }
}

/// A transaction holding [`APPEND_LOCK`] until it ends.
fn begin_append<'c>(client: &'c mut Client, location: &str) -> Result<Transaction<'c>, StoreError> {
    let db = |e: postgres::Error| database_error(location, &e);
    let mut transaction = client.transaction().map_err(db)?;
    transaction
        .execute("SELECT pg_advisory_xact_lock($1)", &[&APPEND_LOCK])
        .map_err(db)?;
    Ok(transaction)
}

/// Inserts one case; returns its id.
fn insert(
    transaction: &mut Transaction<'_>,
    location: &str,
    case: &TrustCase,
) -> Result<StoreId, StoreError> {
    let (problem, solution) = row::encode(case);
    let row = transaction
        .query_one(
            "INSERT INTO trustcbr_cases (problem, solution) VALUES ($1, $2) RETURNING id",
            &[&problem, &solution],
        )
        .map_err(|e| database_error(location, &e))?;
    row.try_get(0).map_err(|e| database_error(location, &e))
}

fn read_rows(
    client: &mut impl GenericClient,
    location: &str,
    after: Option<StoreId>,
    each: &mut dyn FnMut(StoredCase) -> Result<(), StoreError>,
) -> Result<(), StoreError> {
    let db = |e: postgres::Error| database_error(location, &e);
    let after = after.unwrap_or(StoreId::MIN);
    let mut rows = client
        .query_raw(
            "SELECT id, problem, solution FROM trustcbr_cases WHERE id > $1 ORDER BY id",
            [&after],
        )
        .map_err(db)?;
    while let Some(r) = rows.next().map_err(db)? {
        let id: StoreId = r.try_get(0).map_err(db)?;
        let text = |column: usize| {
            r.try_get(column)
                .map_err(|e: postgres::Error| StoreError::Corrupt {
                    location: location.to_owned(),
                    reason: format!("case #{id}: {e}"),
                })
        };
        each(row::decode(location, id, text(1)?, text(2)?)?)?;
    }
    Ok(())
}

impl PostgresStore {
    /// The connection, made again first if it was lost (the database restarted, the
    /// network dropped); the case base's identity is not checked again.
    fn client(&mut self) -> Result<&mut Client, StoreError> {
        let lost = self.client.is_closed()
            || (self.suspect && self.client.is_valid(CHECK_TIMEOUT).is_err());
        if lost {
            self.client = Client::connect(&self.url, NoTls)
                .map_err(|e| database_error(&self.location, &e))?;
        }
        self.suspect = false;
        Ok(&mut self.client)
    }

    /// Runs `operation` on the connection, noting a failure so that the next use checks the
    /// connection first.
    fn with_client<R>(
        &mut self,
        operation: impl FnOnce(&mut Client, &str) -> Result<R, StoreError>,
    ) -> Result<R, StoreError> {
        let location = self.location.clone();
        let result = operation(self.client()?, &location);
        self.suspect = result.is_err();
        result
    }
}

impl CaseStore for PostgresStore {
    fn location(&self) -> String {
        self.location.clone()
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
        self.with_client(|client, location| read_rows(client, location, after, each))
    }

    fn append(
        &mut self,
        case: &TrustCase,
        after: Option<StoreId>,
        missed: &mut dyn FnMut(StoredCase),
    ) -> Result<StoreId, StoreError> {
        self.with_client(|client, location| {
            let mut transaction = begin_append(client, location)?;
            read_rows(&mut transaction, location, after, &mut |c| {
                missed(c);
                Ok(())
            })?;
            let id = insert(&mut transaction, location, case)?;
            transaction
                .commit()
                .map_err(|e| database_error(location, &e))?;
            Ok(id)
        })
    }

    fn append_all(&mut self, cases: &[TrustCase]) -> Result<usize, StoreError> {
        self.with_client(|client, location| {
            let mut transaction = begin_append(client, location)?;
            for case in cases {
                insert(&mut transaction, location, case)?;
            }
            transaction
                .commit()
                .map_err(|e| database_error(location, &e))?;
            Ok(cases.len())
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::store::{Location, open};
    use cbr_core::{Behavior, ContextSpace, ContextVariable};
    use trust::{Evaluated, TrustProblem};

    /// A fresh database on the test server, dropped when the test ends; `None` (with a
    /// message) when no server is named, which CI does not allow.
    struct TestDatabase {
        admin: Client,
        name: String,
        url: String,
    }

    impl TestDatabase {
        fn create(name: &str) -> Option<Self> {
            let Ok(server) = std::env::var("TRUSTCBR_TEST_POSTGRES") else {
                assert!(
                    std::env::var("CI").as_deref() != Ok("true"),
                    "CI must run the PostgreSQL tests: set TRUSTCBR_TEST_POSTGRES"
                );
                eprintln!("skipped: set TRUSTCBR_TEST_POSTGRES=postgres://... to run {name}");
                return None;
            };
            let name = format!("trustcbr_{name}_{}", std::process::id());
            let mut admin = Client::connect(&server, NoTls).unwrap();
            admin
                .batch_execute(&format!("DROP DATABASE IF EXISTS {name}"))
                .unwrap();
            admin
                .batch_execute(&format!("CREATE DATABASE {name}"))
                .unwrap();
            let (base, _) = server.rsplit_once('/').unwrap();
            let url = format!("{base}/{name}");
            Some(Self { admin, name, url })
        }
    }

    impl Drop for TestDatabase {
        fn drop(&mut self) {
            let drop = format!("DROP DATABASE {} WITH (FORCE)", self.name);
            self.admin.batch_execute(&drop).ok();
        }
    }

    fn movement() -> Identity {
        Identity {
            domain: "movement".into(),
            space: (*domains::spaces::movement_space()).clone(),
        }
    }

    /// A case of the default context, but the second, learned with hazardous cargo: a
    /// context read back through the server.
    fn case(solution: u16) -> TrustCase {
        let cargo = ContextSpace::new(vec![ContextVariable::new(
            "cargo",
            &["normal", "hazardous"],
        )])
        .unwrap();
        let value = if solution == 2 { "hazardous" } else { "normal" };
        TrustCase {
            problem: TrustProblem::in_context(
                cargo.context([("cargo", value)]).unwrap(),
                vec![Evaluated {
                    behavior: Behavior::new(&[3, 4]),
                    time: 12.0,
                }],
            ),
            solution: Behavior::new(&[solution, solution]),
        }
    }

    #[test]
    fn appends_catch_up_check_the_space_and_survive_a_lost_connection() {
        let Some(db) = TestDatabase::create("store") else {
            return;
        };
        let location = Location::Postgres(db.url.clone());
        let mut a = open(&location, &movement()).unwrap();
        let mut b = open(&location, &movement()).unwrap();
        let first = a
            .append(&case(1), None, &mut |_| panic!("nothing missed"))
            .unwrap();
        let mut missed = Vec::new();
        let second = b.append(&case(2), None, &mut |c| missed.push(c)).unwrap();
        assert_eq!(missed.len(), 1);
        assert_eq!((missed[0].id, &missed[0].case), (first, &case(1)));
        assert!(second > first);
        // Another space is refused, naming the difference.
        let patrol = Identity {
            domain: "patrol".into(),
            space: (*domains::spaces::patrol_space()).clone(),
        };
        let err = open(&location, &patrol).err().unwrap().to_string();
        assert!(
            err.contains("number of components 2 in the case base, 4 here"),
            "{err}"
        );
        // The server drops `a`'s connection: the next use fails, the one after reconnects.
        let mut admin = Client::connect(&db.url, NoTls).unwrap();
        admin
            .execute(
                "SELECT pg_terminate_backend(pid) FROM pg_stat_activity
                 WHERE datname = current_database() AND pid <> pg_backend_pid()",
                &[],
            )
            .unwrap();
        let others = "SELECT count(*) FROM pg_stat_activity
                      WHERE datname = current_database() AND pid <> pg_backend_pid()";
        while admin.query_one(others, &[]).unwrap().get::<_, i64>(0) > 0 {
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        let mut seen = Vec::new();
        let mut read = |store: &mut Box<dyn CaseStore>| {
            seen.clear();
            store.read_after(Some(first), &mut |c| {
                seen.push(c.id);
                Ok(())
            })
        };
        if read(&mut a).is_err() {
            read(&mut a).unwrap();
        }
        assert_eq!(seen, vec![second]);
    }
}
