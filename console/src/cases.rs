//! A participant's case base: the cases their condition's earlier participants retained,
//! as they were when the participant pressed Start (none when each starts empty), as a
//! [`CaseStore`] under `serve`'s own session. What the participant's robot retains goes
//! into the study's database.
//!
//! Pinning the case base at Start makes a participant's session a function of what is
//! stored about them: a console that restarts, or another console serving the same study,
//! replays it to the same decisions whatever other participants retained meanwhile (a
//! robot of a fleet that takes the fleet's cases with it when it sets out).

use crate::db::{Db, DbError, Participant};
use service::store::{CaseStore, Identity, StoreError, StoreId, StoredCase};
use std::sync::Arc;
use trust::TrustCase;

/// The case base of one participant's robot.
pub struct ParticipantCases {
    identity: Identity,
    pinned: Vec<StoredCase>,
    db: Arc<dyn Db>,
    condition: usize,
    participant: u64,
}

impl ParticipantCases {
    /// The cases `participant` starts from (the study's sharing decided their snapshot).
    pub fn open(
        db: Arc<dyn Db>,
        identity: Identity,
        participant: &Participant,
    ) -> Result<Self, DbError> {
        let pinned = if participant.snapshot > 0 {
            db.cases(participant.condition, participant.snapshot)?
        } else {
            Vec::new()
        };
        Ok(Self {
            identity,
            pinned,
            db,
            condition: participant.condition,
            participant: participant.number,
        })
    }
}

fn store_error(location: String, error: &DbError) -> StoreError {
    StoreError::Corrupt {
        location,
        reason: error.to_string(),
    }
}

impl CaseStore for ParticipantCases {
    fn location(&self) -> String {
        self.db.location()
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
        for stored in &self.pinned {
            if after.is_none_or(|after| stored.id > after) {
                each(stored.clone())?;
            }
        }
        Ok(())
    }

    /// Stores the retained case in the study's database. Cases other participants stored
    /// meanwhile are not passed on: this robot's case base stays as it was at Start (its
    /// episode is over when it retains).
    fn append(
        &mut self,
        case: &TrustCase,
        _after: Option<StoreId>,
        _missed: &mut dyn FnMut(StoredCase),
    ) -> Result<StoreId, StoreError> {
        self.db
            .retain(self.condition, self.participant, case)
            .map_err(|e| store_error(self.db.location(), &e))
    }

    fn append_all(&mut self, cases: &[TrustCase]) -> Result<usize, StoreError> {
        for case in cases {
            self.append(case, None, &mut |_| {})?;
        }
        Ok(cases.len())
    }
}
