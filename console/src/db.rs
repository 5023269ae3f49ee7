//! Where a study lives: its participants, every event in the order it happened, and the
//! cases their robots retained. Everything a console knows is here, so a console that is
//! killed loses nothing it acknowledged, and several consoles may serve one study.
//!
//! [`Db`] is what the console needs of a database; `SqliteDb` (the default, one file) and
//! `PostgresDb` (the `postgres` feature, a URL) answer it.

use crate::study::Study;
use serde_json::Value;
use service::store::{StoreId, StoredCase};
use trust::TrustCase;

/// A participant as the study holds them.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Participant {
    /// Their number, from 0, in the order they pressed Start.
    pub number: u64,
    /// The unguessable token their page holds.
    pub token: String,
    /// Their condition (an index into the study's conditions).
    pub condition: usize,
    /// The seed of their adapter and runs.
    pub seed: u64,
    /// The last case id of their condition when they started (their robot's case base is
    /// the condition's cases up to it, in a study whose participants share cases).
    pub snapshot: StoreId,
}

impl Participant {
    /// The participant numbered `number` (from 0) who starts with `token` and the cases
    /// up to `snapshot`: their condition by the study's assignment, their seed by its seed.
    pub fn enrolled(study: &Study, number: u64, token: &str, snapshot: StoreId) -> Self {
        Self {
            number,
            token: token.to_owned(),
            condition: study.condition_of(number),
            seed: study.participant_seed(number),
            snapshot,
        }
    }

    /// Their pseudonym in exports: `P001`, `P002`, ...
    pub fn pseudonym(&self) -> String {
        format!("P{:03}", self.number + 1)
    }
}

/// One stored event of a participant.
#[derive(Clone, Debug, PartialEq)]
pub struct Event {
    /// Its place in the participant's events, from 0.
    pub seq: u64,
    /// When it was stored (ms since the Unix epoch).
    pub at_ms: i64,
    /// What happened (docs/studies.md, "What is stored").
    pub kind: String,
    /// Its fields.
    pub body: Value,
}

/// An event to store.
#[derive(Clone, Debug, PartialEq)]
pub struct NewEvent {
    /// What happened.
    pub kind: &'static str,
    /// Its fields.
    pub body: Value,
}

/// Why the study's database could not be used.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DbError {
    /// SQLite refused.
    #[error("{location}: {source}")]
    Sqlite {
        /// The file.
        location: String,
        /// What SQLite said.
        #[source]
        source: rusqlite::Error,
    },
    /// PostgreSQL refused.
    #[cfg(feature = "postgres")]
    #[error("{location}: {source}")]
    Postgres {
        /// The URL, without its password.
        location: String,
        /// What PostgreSQL said.
        #[source]
        source: postgres::Error,
    },
    /// The database holds another study.
    #[error(
        "{location} holds another study than {study}: a study's database serves that study alone (start a new database, or give the study file it was made with)"
    )]
    OtherStudy {
        /// The database.
        location: String,
        /// The study file given.
        study: String,
    },
    /// The database does not hold a study.
    #[error(
        "{location} holds no study: make one with `trustcbr console --study STUDY.ron --db {location}`"
    )]
    NoStudy {
        /// The database.
        location: String,
    },
    /// A PostgreSQL URL given to a build without PostgreSQL.
    #[error(
        "{location}: this build has no PostgreSQL support (the `console` crate's `postgres` feature, on in the `trustcbr` tool's default build)"
    )]
    NoPostgres {
        /// The URL, without its password.
        location: String,
    },
    /// What is stored cannot be read back.
    #[error("{location}: {reason}")]
    Corrupt {
        /// The database.
        location: String,
        /// What is wrong.
        reason: String,
    },
}

/// What the console needs of a database. Every write is durable before it returns.
pub trait Db: Send + Sync {
    /// Where the database is, for messages.
    fn location(&self) -> String;

    /// The study text the database was made with.
    fn study_text(&self) -> Result<String, DbError>;

    /// Enrolls the next participant with `token` in one transaction: their number, their
    /// condition by the study's assignment, their seed, their case snapshot, and their
    /// `enrolled` event (seq 0).
    fn enroll(&self, study: &Study, token: &str, now_ms: i64) -> Result<Participant, DbError>;

    /// The participant holding `token`.
    fn participant(&self, token: &str) -> Result<Option<Participant>, DbError>;

    /// Every participant, by number.
    fn participants(&self) -> Result<Vec<Participant>, DbError>;

    /// The participant's events, in order.
    fn events(&self, participant: u64) -> Result<Vec<Event>, DbError>;

    /// Stores `events` as the participant's events `seq`, `seq + 1`, ... in one
    /// transaction. Returns false, storing nothing, when another request stored an event
    /// at `seq` first.
    fn append(
        &self,
        participant: u64,
        seq: u64,
        events: &[NewEvent],
        now_ms: i64,
    ) -> Result<bool, DbError>;

    /// The cases of `condition` with ids up to `up_to`, in id order.
    fn cases(&self, condition: usize, up_to: StoreId) -> Result<Vec<StoredCase>, DbError>;

    /// Stores the case `participant`'s robot retained (once: a participant's robot
    /// retains one case at most, and storing it again returns the id it has).
    fn retain(
        &self,
        condition: usize,
        participant: u64,
        case: &TrustCase,
    ) -> Result<StoreId, DbError>;
}

/// The study as the database records it, to tell one study from another: its parsed
/// form, so comments and layout may change.
pub fn study_identity(study: &Study) -> String {
    serde_json::to_string(study).expect("a study serializes")
}

/// Whether the study `identity` (read from `origin`) must be recorded in the database at
/// `location`, which holds `recorded`: yes when it holds none, no when it holds this
/// one, and an error when it holds another.
pub(crate) fn needs_recording(
    recorded: Option<String>,
    identity: &str,
    location: &str,
    origin: &str,
) -> Result<bool, DbError> {
    match recorded {
        None => Ok(true),
        Some(recorded) if recorded == identity => Ok(false),
        Some(_) => Err(DbError::OtherStudy {
            location: location.to_owned(),
            study: origin.to_owned(),
        }),
    }
}

/// A case from its row, as the case stores decode theirs.
pub(crate) fn decode_case(
    location: &str,
    id: StoreId,
    problem: &str,
    solution: &str,
) -> Result<StoredCase, DbError> {
    service::store::row::decode(location, id, problem, solution).map_err(|e| DbError::Corrupt {
        location: location.to_owned(),
        reason: e.to_string(),
    })
}

/// An event's body from its stored text.
pub(crate) fn decode_body(
    location: &str,
    participant: u64,
    seq: u64,
    text: &str,
) -> Result<Value, DbError> {
    serde_json::from_str(text).map_err(|e| DbError::Corrupt {
        location: location.to_owned(),
        reason: format!("participant {participant}'s event {seq}: {e}"),
    })
}

/// The statements that make a study's tables (SQLite and PostgreSQL alike).
pub(crate) const SCHEMA: [&str; 4] = [
    "CREATE TABLE IF NOT EXISTS console_study (one INTEGER PRIMARY KEY CHECK (one = 1), identity TEXT NOT NULL, text TEXT NOT NULL)",
    "CREATE TABLE IF NOT EXISTS console_participants (number BIGINT PRIMARY KEY, token TEXT NOT NULL UNIQUE, condition BIGINT NOT NULL, seed BIGINT NOT NULL, snapshot BIGINT NOT NULL)",
    "CREATE TABLE IF NOT EXISTS console_events (participant BIGINT NOT NULL, seq BIGINT NOT NULL, at_ms BIGINT NOT NULL, kind TEXT NOT NULL, body TEXT NOT NULL, PRIMARY KEY (participant, seq))",
    "CREATE TABLE IF NOT EXISTS console_cases (id BIGINT PRIMARY KEY, condition BIGINT NOT NULL, participant BIGINT NOT NULL UNIQUE, problem TEXT NOT NULL, solution TEXT NOT NULL)",
];

/// A seed as a database's signed 64-bit integer holds it, and back.
pub(crate) fn seed_to_i64(seed: u64) -> i64 {
    i64::from_ne_bytes(seed.to_ne_bytes())
}

/// The seed a database's signed 64-bit integer holds.
pub(crate) fn seed_from_i64(stored: i64) -> u64 {
    u64::from_ne_bytes(stored.to_ne_bytes())
}

/// Opens the study's database at `location` (an SQLite file, or a `postgres://` URL with
/// the `postgres` feature), making its tables and recording `study` when it is new, and
/// refusing one that holds another study.
pub fn open(
    location: &str,
    study: &Study,
    text: &str,
    origin: &str,
) -> Result<Box<dyn Db>, DbError> {
    open_at(location, Some((study, text, origin)))
}

/// Opens an existing study's database at `location` as it is (for exports and reports).
pub fn open_existing(location: &str) -> Result<Box<dyn Db>, DbError> {
    open_at(location, None)
}

/// The study a database is opened for: the study, its text and the file it was read from.
pub(crate) type Recording<'a> = Option<(&'a Study, &'a str, &'a str)>;

fn open_at(location: &str, study: Recording<'_>) -> Result<Box<dyn Db>, DbError> {
    if let service::Location::Postgres(url) = service::Location::parse(location) {
        #[cfg(feature = "postgres")]
        return Ok(Box::new(crate::db_postgres::PostgresDb::open(&url, study)?));
        #[cfg(not(feature = "postgres"))]
        return Err(DbError::NoPostgres {
            location: service::Location::Postgres(url).shown(),
        });
    }
    Ok(Box::new(crate::db_sqlite::SqliteDb::open(
        std::path::Path::new(location),
        study,
    )?))
}
