//! A study in a PostgreSQL database (`--db postgres://...`): several consoles, one study.
//! The same tables as SQLite's; enrolment and retention take a table lock, so participant
//! numbers and case ids are handed out in commit order; every commit returns once
//! PostgreSQL has flushed it (`synchronous_commit` on, its default).

use crate::db::{
    Db, DbError, Event, NewEvent, Participant, Recording, SCHEMA, decode_body, decode_case,
    needs_recording, seed_from_i64, seed_to_i64, study_identity,
};
use crate::study::{CaseSharing, Study};
use postgres::{Client, NoTls};
use service::store::{StoreId, StoredCase};
use std::sync::Mutex;
use trust::TrustCase;

/// The advisory lock key a console holds while it makes the tables ("console!" in ASCII).
const SCHEMA_LOCK: i64 = 0x636f_6e73_6f6c_6521;

/// A study's PostgreSQL database.
pub struct PostgresDb {
    location: String,
    client: Mutex<Client>,
}

impl PostgresDb {
    fn connect(url: &str) -> Result<Self, DbError> {
        let location = service::Location::parse(url).shown();
        let client = Client::connect(url, NoTls).map_err(|source| DbError::Postgres {
            location: location.clone(),
            source,
        })?;
        Ok(Self {
            location,
            client: Mutex::new(client),
        })
    }

    /// Connects to `url`. With `study` (its text, the file it was read from), makes the
    /// study's tables when absent and records it, or refuses a database that holds
    /// another; without, the database must hold a study.
    pub fn open(url: &str, study: Recording<'_>) -> Result<Self, DbError> {
        let db = Self::connect(url)?;
        let Some((study, text, origin)) = study else {
            db.study_text()?;
            return Ok(db);
        };
        {
            let mut client = db.lock();
            let mut tx = client.transaction().map_err(|e| db.pg(e))?;
            // Two consoles starting at once make the tables one after the other.
            tx.execute("SELECT pg_advisory_xact_lock($1)", &[&SCHEMA_LOCK])
                .map_err(|e| db.pg(e))?;
            for statement in SCHEMA {
                tx.batch_execute(statement).map_err(|e| db.pg(e))?;
            }
            tx.batch_execute("LOCK TABLE console_study IN EXCLUSIVE MODE")
                .map_err(|e| db.pg(e))?;
            let identity = study_identity(study);
            let recorded = tx
                .query_opt("SELECT identity FROM console_study", &[])
                .map_err(|e| db.pg(e))?
                .map(|row| row.get::<_, String>(0));
            if needs_recording(recorded, &identity, &db.location, origin)? {
                tx.execute(
                    "INSERT INTO console_study (one, identity, text) VALUES (1, $1, $2)",
                    &[&identity, &text],
                )
                .map_err(|e| db.pg(e))?;
            }
            tx.commit().map_err(|e| db.pg(e))?;
        }
        Ok(db)
    }

    fn pg(&self, source: postgres::Error) -> DbError {
        DbError::Postgres {
            location: self.location.clone(),
            source,
        }
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Client> {
        self.client
            .lock()
            .expect("no request panics while holding the database")
    }
}

fn participant_of(row: &postgres::Row) -> Participant {
    Participant {
        number: row.get::<_, i64>(0) as u64,
        token: row.get(1),
        condition: row.get::<_, i64>(2) as usize,
        seed: seed_from_i64(row.get(3)),
        snapshot: row.get(4),
    }
}

impl Db for PostgresDb {
    fn location(&self) -> String {
        self.location.clone()
    }

    fn study_text(&self) -> Result<String, DbError> {
        let mut client = self.lock();
        let exists: bool = client
            .query_one("SELECT to_regclass('console_study') IS NOT NULL", &[])
            .map_err(|e| self.pg(e))?
            .get(0);
        let text = if exists {
            client
                .query_opt("SELECT text FROM console_study", &[])
                .map_err(|e| self.pg(e))?
                .map(|row| row.get::<_, String>(0))
        } else {
            None
        };
        text.ok_or_else(|| DbError::NoStudy {
            location: self.location.clone(),
        })
    }

    fn enroll(&self, study: &Study, token: &str, now_ms: i64) -> Result<Participant, DbError> {
        let mut client = self.lock();
        let mut tx = client.transaction().map_err(|e| self.pg(e))?;
        tx.batch_execute("LOCK TABLE console_participants IN EXCLUSIVE MODE")
            .map_err(|e| self.pg(e))?;
        let number: i64 = tx
            .query_one("SELECT COUNT(*) FROM console_participants", &[])
            .map_err(|e| self.pg(e))?
            .get(0);
        let number = number as u64;
        let condition = study.condition_of(number);
        let snapshot: StoreId = match study.cases {
            CaseSharing::Shared => tx
                .query_one(
                    "SELECT COALESCE(MAX(id), 0) FROM console_cases WHERE condition = $1",
                    &[&(condition as i64)],
                )
                .map_err(|e| self.pg(e))?
                .get(0),
            CaseSharing::EachEmpty => 0,
        };
        let participant = Participant::enrolled(study, number, token, snapshot);
        tx.execute(
            "INSERT INTO console_participants (number, token, condition, seed, snapshot) VALUES ($1, $2, $3, $4, $5)",
            &[
                &(number as i64),
                &token,
                &(condition as i64),
                &seed_to_i64(participant.seed),
                &snapshot,
            ],
        )
        .map_err(|e| self.pg(e))?;
        let body = crate::participant::enrolled_body(study, &participant).to_string();
        tx.execute(
            "INSERT INTO console_events (participant, seq, at_ms, kind, body) VALUES ($1, 0, $2, 'enrolled', $3)",
            &[&(number as i64), &now_ms, &body],
        )
        .map_err(|e| self.pg(e))?;
        tx.commit().map_err(|e| self.pg(e))?;
        Ok(participant)
    }

    fn participant(&self, token: &str) -> Result<Option<Participant>, DbError> {
        let mut client = self.lock();
        Ok(client
            .query_opt(
                "SELECT number, token, condition, seed, snapshot FROM console_participants WHERE token = $1",
                &[&token],
            )
            .map_err(|e| self.pg(e))?
            .as_ref()
            .map(participant_of))
    }

    fn participants(&self) -> Result<Vec<Participant>, DbError> {
        let mut client = self.lock();
        Ok(client
            .query(
                "SELECT number, token, condition, seed, snapshot FROM console_participants ORDER BY number",
                &[],
            )
            .map_err(|e| self.pg(e))?
            .iter()
            .map(participant_of)
            .collect())
    }

    fn events(&self, participant: u64) -> Result<Vec<Event>, DbError> {
        let rows = self
            .lock()
            .query(
                "SELECT seq, at_ms, kind, body FROM console_events WHERE participant = $1 ORDER BY seq",
                &[&(participant as i64)],
            )
            .map_err(|e| self.pg(e))?;
        rows.iter()
            .map(|row| {
                let seq = row.get::<_, i64>(0) as u64;
                Ok(Event {
                    seq,
                    at_ms: row.get(1),
                    kind: row.get(2),
                    body: decode_body(&self.location, participant, seq, row.get(3))?,
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
        let mut client = self.lock();
        let mut tx = client.transaction().map_err(|e| self.pg(e))?;
        for (k, event) in events.iter().enumerate() {
            let inserted = tx
                .execute(
                    "INSERT INTO console_events (participant, seq, at_ms, kind, body) VALUES ($1, $2, $3, $4, $5) ON CONFLICT DO NOTHING",
                    &[
                        &(participant as i64),
                        &((seq + k as u64) as i64),
                        &now_ms,
                        &event.kind,
                        &event.body.to_string(),
                    ],
                )
                .map_err(|e| self.pg(e))?;
            if inserted == 0 {
                return Ok(false);
            }
        }
        tx.commit().map_err(|e| self.pg(e))?;
        Ok(true)
    }

    fn cases(&self, condition: usize, up_to: StoreId) -> Result<Vec<StoredCase>, DbError> {
        let rows = self
            .lock()
            .query(
                "SELECT id, problem, solution FROM console_cases WHERE condition = $1 AND id <= $2 ORDER BY id",
                &[&(condition as i64), &up_to],
            )
            .map_err(|e| self.pg(e))?;
        rows.iter()
            .map(|row| decode_case(&self.location, row.get(0), row.get(1), row.get(2)))
            .collect()
    }

    fn retain(
        &self,
        condition: usize,
        participant: u64,
        case: &TrustCase,
    ) -> Result<StoreId, DbError> {
        let mut client = self.lock();
        let mut tx = client.transaction().map_err(|e| self.pg(e))?;
        tx.batch_execute("LOCK TABLE console_cases IN EXCLUSIVE MODE")
            .map_err(|e| self.pg(e))?;
        if let Some(row) = tx
            .query_opt(
                "SELECT id FROM console_cases WHERE participant = $1",
                &[&(participant as i64)],
            )
            .map_err(|e| self.pg(e))?
        {
            return Ok(row.get(0));
        }
        let (problem, solution) = service::store::row::encode(case);
        let id: StoreId = tx
            .query_one("SELECT COALESCE(MAX(id), 0) + 1 FROM console_cases", &[])
            .map_err(|e| self.pg(e))?
            .get(0);
        tx.execute(
            "INSERT INTO console_cases (id, condition, participant, problem, solution) VALUES ($1, $2, $3, $4, $5)",
            &[&id, &(condition as i64), &(participant as i64), &problem, &solution],
        )
        .map_err(|e| self.pg(e))?;
        tx.commit().map_err(|e| self.pg(e))?;
        Ok(id)
    }
}
