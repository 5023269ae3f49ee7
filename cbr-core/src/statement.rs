//! What a user states up front: preferences in the domain's vocabulary, which a search
//! strategy may take as a prior ([`crate::Searcher::hear`]).
//!
//! A domain declares the names a statement may use (for a robot, "hurry" or "avoid
//! bumps"); a [`Statement`] says of one of them whether the user minds it. A set of
//! statements may be incomplete (a name left unsaid is unknown, not denied) and may be
//! wrong: people misjudge what they will react to, so a strategy should treat statements
//! as evidence that what it observes can overrule, never as truth.

use serde::{Deserialize, Serialize};
use std::fmt;

/// One stated preference: whether the user minds what `name` names.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Statement {
    /// A name the domain declares.
    pub name: String,
    /// `true`: the user says it minds this; `false`: it says it does not.
    pub minds: bool,
}

impl Statement {
    /// The statement that the user minds (`minds`) or does not mind `name`.
    pub fn new(name: &str, minds: bool) -> Self {
        Self {
            name: name.to_owned(),
            minds,
        }
    }

    /// The same statement said the other way round (what a wrong statement says).
    #[must_use]
    pub fn negated(&self) -> Self {
        Self {
            name: self.name.clone(),
            minds: !self.minds,
        }
    }
}

impl fmt::Display for Statement {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.minds {
            write!(f, "{}", self.name)
        } else {
            write!(f, "not {}", self.name)
        }
    }
}

/// The first name `stated` says more than once, if any: a set of statements says each name
/// at most once.
pub fn repeated_name(stated: &[Statement]) -> Option<&str> {
    stated
        .iter()
        .enumerate()
        .find(|(i, s)| stated[..*i].iter().any(|earlier| earlier.name == s.name))
        .map(|(_, s)| s.name.as_str())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_statement_shows_and_negates() {
        let hurry = Statement::new("hurry", true);
        assert_eq!(hurry.to_string(), "hurry");
        assert_eq!(hurry.negated().to_string(), "not hurry");
        assert_eq!(hurry.negated().negated(), hurry);
    }

    #[test]
    fn a_name_said_twice_is_found() {
        let stated = [
            Statement::new("hurry", true),
            Statement::new("avoid-bumps", false),
            Statement::new("hurry", false),
        ];
        assert_eq!(repeated_name(&stated), Some("hurry"));
        assert_eq!(repeated_name(&stated[..2]), None);
    }

    #[test]
    fn statements_read_from_json() {
        let read: Vec<Statement> =
            serde_json::from_str(r#"[{"name": "hurry", "minds": false}]"#).unwrap();
        assert_eq!(read, [Statement::new("hurry", false)]);
        assert!(serde_json::from_str::<Statement>(r#"{"name": "hurry"}"#).is_err());
    }
}
