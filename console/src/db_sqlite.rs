//! A study in one SQLite file (the default): write-ahead logging, every transaction synced
//! to disk before it returns, and a busy timeout so several consoles may share the file.

use crate::db::{
    Db, DbError, Event, NewEvent, Participant, Recording, SCHEMA, decode_body, decode_case,
    needs_recording, seed_from_i64, seed_to_i64, study_identity,
};
use crate::study::{CaseSharing, Study};
use rusqlite::{Connection, OpenFlags, OptionalExtension, TransactionBehavior, params};
use service::store::{StoreId, StoredCase};
use std::path::Path;
use std::sync::Mutex;
use std::time::Duration;
use trust::TrustCase;

/// How long a write waits for another console's transaction on the same file.
const BUSY: Duration = Duration::from_secs(10);

/// A study's SQLite file.
pub struct SqliteDb {
    location: String,
    connection: Mutex<Connection>,
}

impl SqliteDb {
    /// Opens the file at `path`. With `study` (the study, its text and the file it was
    /// read from), a file that does not exist is made and the study recorded; one that
    /// holds another study is refused. Without, the file must exist and hold a study.
    pub fn open(path: &Path, study: Recording<'_>) -> Result<Self, DbError> {
        let location = path.display().to_string();
        let sqlite = |source| DbError::Sqlite {
            location: location.clone(),
            source,
        };
        let flags = match study {
            Some(_) => OpenFlags::SQLITE_OPEN_READ_WRITE | OpenFlags::SQLITE_OPEN_CREATE,
            None => OpenFlags::SQLITE_OPEN_READ_WRITE,
        };
        let connection = Connection::open_with_flags(path, flags).map_err(sqlite)?;
        connection.busy_timeout(BUSY).map_err(sqlite)?;
        connection
            .pragma_update(None, "journal_mode", "wal")
            .map_err(sqlite)?;
        connection
            .pragma_update(None, "synchronous", "full")
            .map_err(sqlite)?;
        let db = Self {
            location,
            connection: Mutex::new(connection),
        };
        match study {
            Some((study, text, origin)) => db.record_study(study, text, origin)?,
            None => {
                db.study_text()?;
            }
        }
        Ok(db)
    }

    fn sqlite(&self, source: rusqlite::Error) -> DbError {
        DbError::Sqlite {
            location: self.location.clone(),
            source,
        }
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Connection> {
        self.connection
            .lock()
            .expect("no request panics while holding the database")
    }

    /// Makes the tables and records the study, or checks that the recorded one is it.
    fn record_study(&self, study: &Study, text: &str, origin: &str) -> Result<(), DbError> {
        let mut connection = self.lock();
        let tx = connection
            .transaction_with_behavior(TransactionBehavior::Immediate)
            .map_err(|e| self.sqlite(e))?;
        for statement in SCHEMA {
            tx.execute(statement, []).map_err(|e| self.sqlite(e))?;
        }
        let identity = study_identity(study);
        let recorded: Option<String> = tx
            .query_row("SELECT identity FROM console_study", [], |row| row.get(0))
            .optional()
            .map_err(|e| self.sqlite(e))?;
        if needs_recording(recorded, &identity, &self.location, origin)? {
            tx.execute(
                "INSERT INTO console_study (one, identity, text) VALUES (1, ?1, ?2)",
                params![identity, text],
            )
            .map_err(|e| self.sqlite(e))?;
        }
        tx.commit().map_err(|e| self.sqlite(e))
    }
}

fn participant_of(row: &rusqlite::Row<'_>) -> rusqlite::Result<Participant> {
    Ok(Participant {
        number: row.get::<_, i64>(0)? as u64,
        token: row.get(1)?,
        condition: row.get::<_, i64>(2)? as usize,
        seed: seed_from_i64(row.get(3)?),
        snapshot: row.get(4)?,
    })
}

const PARTICIPANT_COLUMNS: &str = "number, token, condition, seed, snapshot";

impl Db for SqliteDb {
    fn location(&self) -> String {
        self.location.clone()
    }

    fn study_text(&self) -> Result<String, DbError> {
        let connection = self.lock();
        let text: Option<String> = connection
            .query_row("SELECT text FROM console_study", [], |row| row.get(0))
            .optional()
            .or_else(|e| match e {
                // A file made by something else has no `study` table.
                rusqlite::Error::SqliteFailure(_, Some(ref m)) if m.contains("no such table") => {
                    Ok(None)
                }
                e => Err(e),
            })
            .map_err(|e| self.sqlite(e))?;
        text.ok_or_else(|| DbError::NoStudy {
            location: self.location.clone(),
        })
    }

    fn enroll(&self, study: &Study, token: &str, now_ms: i64) -> Result<Participant, DbError> {
        let mut connection = self.lock();
        let tx = connection
            .transaction_with_behavior(TransactionBehavior::Immediate)
            .map_err(|e| self.sqlite(e))?;
        let number: i64 = tx
            .query_row("SELECT COUNT(*) FROM console_participants", [], |row| {
                row.get(0)
            })
            .map_err(|e| self.sqlite(e))?;
        let number = number as u64;
        let condition = study.condition_of(number);
        let snapshot: StoreId = match study.cases {
            CaseSharing::Shared => tx
                .query_row(
                    "SELECT COALESCE(MAX(id), 0) FROM console_cases WHERE condition = ?1",
                    params![condition as i64],
                    |row| row.get(0),
                )
                .map_err(|e| self.sqlite(e))?,
            CaseSharing::EachEmpty => 0,
        };
        let participant = Participant::enrolled(study, number, token, snapshot);
        tx.execute(
            "INSERT INTO console_participants (number, token, condition, seed, snapshot) VALUES (?1, ?2, ?3, ?4, ?5)",
            params![
                number as i64,
                token,
                condition as i64,
                seed_to_i64(participant.seed),
                snapshot
            ],
        )
        .map_err(|e| self.sqlite(e))?;
        let body = crate::participant::enrolled_body(study, &participant);
        tx.execute(
            "INSERT INTO console_events (participant, seq, at_ms, kind, body) VALUES (?1, 0, ?2, 'enrolled', ?3)",
            params![number as i64, now_ms, body.to_string()],
        )
        .map_err(|e| self.sqlite(e))?;
        tx.commit().map_err(|e| self.sqlite(e))?;
        Ok(participant)
    }

    fn participant(&self, token: &str) -> Result<Option<Participant>, DbError> {
        let connection = self.lock();
        connection
            .query_row(
                &format!("SELECT {PARTICIPANT_COLUMNS} FROM console_participants WHERE token = ?1"),
                params![token],
                participant_of,
            )
            .optional()
            .map_err(|e| self.sqlite(e))
    }

    fn participants(&self) -> Result<Vec<Participant>, DbError> {
        let connection = self.lock();
        let mut statement = connection
            .prepare(&format!(
                "SELECT {PARTICIPANT_COLUMNS} FROM console_participants ORDER BY number"
            ))
            .map_err(|e| self.sqlite(e))?;
        statement
            .query_map([], participant_of)
            .and_then(Iterator::collect)
            .map_err(|e| self.sqlite(e))
    }

    fn events(&self, participant: u64) -> Result<Vec<Event>, DbError> {
        let rows: Vec<(i64, i64, String, String)> = {
            let connection = self.lock();
            let mut statement = connection
                .prepare(
                    "SELECT seq, at_ms, kind, body FROM console_events WHERE participant = ?1 ORDER BY seq",
                )
                .map_err(|e| self.sqlite(e))?;
            statement
                .query_map(params![participant as i64], |row| {
                    Ok((row.get(0)?, row.get(1)?, row.get(2)?, row.get(3)?))
                })
                .and_then(Iterator::collect)
                .map_err(|e| self.sqlite(e))?
        };
        rows.into_iter()
            .map(|(seq, at_ms, kind, body)| {
                let seq = seq as u64;
                Ok(Event {
                    seq,
                    at_ms,
                    kind,
                    body: decode_body(&self.location, participant, seq, &body)?,
                })
            })
            .collect()
    }

    fn append(
        &self,
        participant: u64,
        seq: u64,
        events: &[NewEvent],
        now_ms: i64,
    ) -> Result<bool, DbError> {
        let mut connection = self.lock();
        let tx = connection
            .transaction_with_behavior(TransactionBehavior::Immediate)
            .map_err(|e| self.sqlite(e))?;
        for (k, event) in events.iter().enumerate() {
            let inserted = tx.execute(
                "INSERT INTO console_events (participant, seq, at_ms, kind, body) VALUES (?1, ?2, ?3, ?4, ?5) ON CONFLICT DO NOTHING",
                params![
                    participant as i64,
                    (seq + k as u64) as i64,
                    now_ms,
                    event.kind,
                    event.body.to_string()
                ],
            )
            .map_err(|e| self.sqlite(e))?;
            if inserted == 0 {
                // Dropping the transaction rolls back what it stored.
                return Ok(false);
            }
        }
        tx.commit().map_err(|e| self.sqlite(e))?;
        Ok(true)
    }

    fn cases(&self, condition: usize, up_to: StoreId) -> Result<Vec<StoredCase>, DbError> {
        let rows: Vec<(i64, String, String)> = {
            let connection = self.lock();
            let mut statement = connection
                .prepare(
                    "SELECT id, problem, solution FROM console_cases WHERE condition = ?1 AND id <= ?2 ORDER BY id",
                )
                .map_err(|e| self.sqlite(e))?;
            statement
                .query_map(params![condition as i64, up_to], |row| {
                    Ok((row.get(0)?, row.get(1)?, row.get(2)?))
                })
                .and_then(Iterator::collect)
                .map_err(|e| self.sqlite(e))?
        };
        rows.iter()
            .map(|(id, problem, solution)| decode_case(&self.location, *id, problem, solution))
            .collect()
    }

    fn retain(
        &self,
        condition: usize,
        participant: u64,
        case: &TrustCase,
    ) -> Result<StoreId, DbError> {
        let mut connection = self.lock();
        let tx = connection
            .transaction_with_behavior(TransactionBehavior::Immediate)
            .map_err(|e| self.sqlite(e))?;
        let existing: Option<StoreId> = tx
            .query_row(
                "SELECT id FROM console_cases WHERE participant = ?1",
                params![participant as i64],
                |row| row.get(0),
            )
            .optional()
            .map_err(|e| self.sqlite(e))?;
        if let Some(id) = existing {
            return Ok(id);
        }
        let (problem, solution) = service::store::row::encode(case);
        let id: StoreId = tx
            .query_row(
                "SELECT COALESCE(MAX(id), 0) + 1 FROM console_cases",
                [],
                |row| row.get(0),
            )
            .map_err(|e| self.sqlite(e))?;
        tx.execute(
            "INSERT INTO console_cases (id, condition, participant, problem, solution) VALUES (?1, ?2, ?3, ?4, ?5)",
            params![id, condition as i64, participant as i64, problem, solution],
        )
        .map_err(|e| self.sqlite(e))?;
        tx.commit().map_err(|e| self.sqlite(e))?;
        Ok(id)
    }
}
