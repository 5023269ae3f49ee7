//! [`SharedCases`]: the one case memory every session of a server selects from and retains
//! into, kept in step with the case store.
//!
//! Before any session reads the memory it catches up: the cases other processes appended to
//! the store since this one last looked are checked against the space and fed through
//! `CaseMemory::retain`, so the retriever stays in step and every process holds the cases
//! in store-id order. A retention appends to the store first (one durable transaction that
//! also hands back any case appended meanwhile) and only then to the memory, so a case the
//! memory holds is always in the store. Positions in the memory (`CaseId`) are local; the
//! ids shown to controllers are store ids.

use crate::domain::DomainDefinition;
use crate::store::{self, CaseStore, Identity, Location, StoreError, StoreId, StoredCase};
use cbr_core::{BehaviorSpace, ContextSpace};
use std::sync::{Arc, Mutex, MutexGuard};
use trust::{ConfigError, TrustCase, TrustCaseBase, TrustMemory};

/// The case memory of one server, shared by its sessions.
pub struct SharedCases {
    space: Arc<BehaviorSpace>,
    contexts: Arc<ContextSpace>,
    location: String,
    writable: bool,
    inner: Mutex<Inner>,
}

struct Inner {
    memory: TrustMemory,
    /// The store id of the case at each position of the memory.
    ids: Vec<StoreId>,
    store: Box<dyn CaseStore>,
}

/// Why the shared case memory could not be set up.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OpenError {
    /// The case store could not be opened or read.
    #[error(transparent)]
    Store(#[from] StoreError),
    /// The domain's adapter configuration is unusable.
    #[error("adapter configuration: {0}")]
    Config(#[from] ConfigError),
}

impl SharedCases {
    /// Opens the case base at `location` for `domain` (creating a database that does not
    /// exist yet) and loads every case into a memory with the domain's retriever
    /// ([`DomainDefinition::memory`]: a user's, or the kind its config names).
    pub fn open(domain: &DomainDefinition, location: &Location) -> Result<Self, OpenError> {
        let identity = Identity {
            domain: domain.name.clone(),
            space: (*domain.space).clone(),
        };
        let store = store::open(location, &identity)?;
        let memory = domain.memory(TrustCaseBase::new())?;
        Ok(Self::load(
            store,
            memory,
            domain.space.clone(),
            domain.contexts.clone(),
        )?)
    }

    /// Wraps `store`, loading every case it holds into `memory` (empty); each is checked
    /// against `space` and `contexts` ([`store::check_case`]).
    pub fn load(
        store: Box<dyn CaseStore>,
        memory: TrustMemory,
        space: Arc<BehaviorSpace>,
        contexts: Arc<ContextSpace>,
    ) -> Result<Self, StoreError> {
        let location = store.location();
        let writable = store.writable();
        let mut inner = Inner {
            memory,
            ids: Vec::new(),
            store,
        };
        inner.catch_up(&space, &contexts, &location)?;
        Ok(Self {
            space,
            contexts,
            location,
            writable,
            inner: Mutex::new(inner),
        })
    }

    /// Where the cases are stored.
    pub fn location(&self) -> &str {
        &self.location
    }

    /// Whether retained cases are stored (a RON case file is served read-only).
    pub fn writable(&self) -> bool {
        self.writable
    }

    fn lock(&self) -> MutexGuard<'_, Inner> {
        self.inner
            .lock()
            .expect("no session panics while holding the case memory")
    }

    /// Catches up with the store, then runs `f` on the memory and the store id of each of
    /// its positions, holding the memory for the duration of `f` only.
    pub fn current<R>(
        &self,
        f: impl FnOnce(&TrustMemory, &[StoreId]) -> R,
    ) -> Result<R, StoreError> {
        let mut inner = self.lock();
        inner.catch_up(&self.space, &self.contexts, &self.location)?;
        Ok(f(&inner.memory, &inner.ids))
    }

    /// Stores `case` (durably, in one transaction) and then adds it to the memory, after
    /// any case another process stored meanwhile. Returns its store id and the number of
    /// cases now held.
    pub fn retain(&self, case: TrustCase) -> Result<(StoreId, usize), StoreError> {
        let mut inner = self.lock();
        let after = inner.ids.last().copied();
        let mut missed = Vec::new();
        let id = inner
            .store
            .append(&case, after, &mut |stored| missed.push(stored))?;
        let Inner { memory, ids, .. } = &mut *inner;
        for stored in missed.into_iter().chain([StoredCase { id, case }]) {
            add(
                memory,
                ids,
                stored,
                (&self.space, &self.contexts),
                &self.location,
            )?;
        }
        Ok((id, ids.len()))
    }

    /// Up to `count` cases from position `from` on, with their store ids, copied so they
    /// can be written out without holding the memory.
    pub fn copy_range(&self, from: usize, count: usize) -> Vec<(StoreId, TrustCase)> {
        let inner = self.lock();
        let end = inner.ids.len().min(from.saturating_add(count));
        (from.min(end)..end)
            .map(|position| {
                let case = &inner.memory.base().cases()[position];
                (inner.ids[position], case.clone())
            })
            .collect()
    }
}

impl Inner {
    fn catch_up(
        &mut self,
        space: &BehaviorSpace,
        contexts: &ContextSpace,
        location: &str,
    ) -> Result<(), StoreError> {
        let after = self.ids.last().copied();
        let (memory, ids) = (&mut self.memory, &mut self.ids);
        self.store.read_after(after, &mut |stored| {
            add(memory, ids, stored, (space, contexts), location)
        })
    }
}

/// Checks a stored case against the domain's behavior space and contexts
/// ([`store::check_case`]) and appends it to the memory.
fn add(
    memory: &mut TrustMemory,
    ids: &mut Vec<StoreId>,
    stored: StoredCase,
    (space, contexts): (&BehaviorSpace, &ContextSpace),
    location: &str,
) -> Result<(), StoreError> {
    store::check_case(location, &stored, space, contexts)?;
    memory.retain(stored.case);
    ids.push(stored.id);
    Ok(())
}
