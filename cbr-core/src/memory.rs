//! Case memory: a case base and the retriever indexing it, kept in step.
//!
//! Appending through [`CaseMemory::retain`] is the only way to add a case, so the retriever
//! is told of every case exactly once, in order, and can never fall out of date.

use crate::case::{Case, CaseBase, CaseId};
use crate::retrieve::{Exclusion, Retrieved, Retriever};

/// A case base together with the retriever that answers queries over it.
pub struct CaseMemory<P, S> {
    base: CaseBase<P, S>,
    retriever: Box<dyn Retriever<P, S>>,
}

impl<P, S> CaseMemory<P, S> {
    /// Wraps `base`, telling `retriever` of every case it already holds.
    pub fn new(base: CaseBase<P, S>, mut retriever: Box<dyn Retriever<P, S>>) -> Self {
        for (id, case) in base.iter() {
            retriever.retain(id, case);
        }
        Self { base, retriever }
    }

    /// Appends a case and indexes it.
    pub fn retain(&mut self, case: Case<P, S>) -> CaseId {
        let id = self.base.push(case);
        let stored = self.base.get(id).expect("just appended");
        self.retriever.retain(id, stored);
        id
    }

    /// The best case for `query` under the retriever's contract.
    pub fn retrieve(&self, query: &P, exclude: Exclusion<'_, P, S>) -> Option<Retrieved> {
        self.retriever.retrieve(&self.base, query, exclude)
    }

    /// The case base.
    pub fn base(&self) -> &CaseBase<P, S> {
        &self.base
    }

    /// The retriever's name.
    pub fn retriever_name(&self) -> &str {
        self.retriever.name()
    }
}
