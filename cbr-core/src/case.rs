//! Cases and the append-only case base.
//!
//! A [`Case`] pairs a problem with its solution. A [`CaseBase`] only grows: a case, once
//! appended, keeps its [`CaseId`] (its position) for good, so indices built over the base
//! stay valid. It serializes with serde; where it is stored is the caller's business
//! (the service's case stores).

use serde::{Deserialize, Serialize};
use std::fmt;

/// The stable identity of a case: its position in the case base.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct CaseId(pub u32);

impl CaseId {
    /// The position of the case in the case base.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

impl fmt::Display for CaseId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "#{}", self.0)
    }
}

/// A problem and the solution that worked for it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Case<P, S> {
    /// What was faced.
    pub problem: P,
    /// What solved it.
    pub solution: S,
}

/// An append-only, ordered collection of cases.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseBase<P, S> {
    cases: Vec<Case<P, S>>,
}

impl<P, S> Default for CaseBase<P, S> {
    fn default() -> Self {
        Self { cases: Vec::new() }
    }
}

impl<P, S> CaseBase<P, S> {
    /// An empty case base.
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends a case and returns its id.
    pub fn push(&mut self, case: Case<P, S>) -> CaseId {
        let id = CaseId(u32::try_from(self.cases.len()).expect("fewer than 2^32 cases"));
        self.cases.push(case);
        id
    }

    /// The case with id `id`, if any.
    pub fn get(&self, id: CaseId) -> Option<&Case<P, S>> {
        self.cases.get(id.index())
    }

    /// Number of cases.
    pub fn len(&self) -> usize {
        self.cases.len()
    }

    /// Whether there are no cases.
    pub fn is_empty(&self) -> bool {
        self.cases.is_empty()
    }

    /// Every case with its id, in case-base order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = (CaseId, &Case<P, S>)> + '_ {
        self.cases
            .iter()
            .enumerate()
            .map(|(i, c)| (CaseId(i as u32), c))
    }

    /// The cases, in case-base order.
    pub fn cases(&self) -> &[Case<P, S>] {
        &self.cases
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type Base = CaseBase<Vec<u32>, String>;

    fn sample() -> Base {
        let mut base = Base::new();
        base.push(Case {
            problem: vec![1, 2],
            solution: "a".into(),
        });
        base.push(Case {
            problem: vec![],
            solution: "b".into(),
        });
        base
    }

    #[test]
    fn ids_are_positions_and_stable() {
        let mut base = sample();
        let id = base.push(Case {
            problem: vec![3],
            solution: "c".into(),
        });
        assert_eq!(id, CaseId(2));
        assert_eq!(base.get(CaseId(0)).unwrap().solution, "a");
        assert_eq!(base.get(id).unwrap().problem, vec![3]);
        assert_eq!(base.len(), 3);
    }
}
