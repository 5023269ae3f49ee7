//! How much each outcome weighs in the estimate, as an operator model states it: a
//! completion, a failure or interruption by cause, and a default for causes it does not
//! name. Every domain's operators need this much, so it lives here once.

use crate::{Cause, DeclaredCause, UndeclaredCause, find_declared};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The weights of an operator's outcomes.
///
/// The weight of a failure or interruption with a cause is the `by_cause` entry for it;
/// without one, the default weight the domain declares for the cause (filled in by
/// [`OutcomeWeights::check`]); without that, `default`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutcomeWeights {
    /// Weight of a completion.
    #[serde(default = "one")]
    pub completed: f64,
    /// Weight of a failure or interruption whose cause is not listed in `by_cause`.
    #[serde(default = "one")]
    pub default: f64,
    /// Weights of failures and interruptions by cause (causes the domain declares; quoted
    /// in RON: `by_cause: {"dropped-item": 1.0}`), each cause once.
    #[serde(default, deserialize_with = "each_cause_once")]
    pub by_cause: BTreeMap<Cause, f64>,
}

/// Reads `by_cause`, refusing a cause given twice (a map would keep the last silently).
fn each_cause_once<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<BTreeMap<Cause, f64>, D::Error> {
    cbr_core::unique_keys::map_with_unique_keys(d, |cause| {
        format!("`weights.by_cause` gives the cause `{cause}` twice; give each cause once")
    })
}

fn one() -> f64 {
    1.0
}

impl Default for OutcomeWeights {
    fn default() -> Self {
        Self {
            completed: 1.0,
            default: 1.0,
            by_cause: BTreeMap::new(),
        }
    }
}

/// Weights that cannot be used.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum WeightsError {
    /// A weight is negative or not a finite number.
    #[error("`{field}` must be a finite number >= 0, got {}", cbr_core::Shown(*.value))]
    Range {
        /// The field, e.g. `weights.by_cause.too-slow`.
        field: String,
        /// The value given.
        value: f64,
    },
    /// `by_cause` names a cause the domain does not declare.
    #[error("`weights.by_cause`: {0}")]
    Undeclared(Box<UndeclaredCause>),
}

impl OutcomeWeights {
    /// Every weight times `factor`.
    pub fn scaled(&self, factor: f64) -> Self {
        Self {
            completed: self.completed * factor,
            default: self.default * factor,
            by_cause: self
                .by_cause
                .iter()
                .map(|(&cause, &w)| (cause, w * factor))
                .collect(),
        }
    }

    /// The weight of a failure or interruption with `cause`.
    pub fn of(&self, cause: Cause) -> f64 {
        self.by_cause.get(&cause).copied().unwrap_or(self.default)
    }

    /// Checks the weights against the domain's `declared` causes (every weight finite and
    /// `>= 0`, fields named as `weights.FIELD`; `by_cause` naming only declared causes) and
    /// fills in the declared default weight of every cause `by_cause` leaves out.
    pub fn check(&mut self, declared: &[DeclaredCause]) -> Result<(), WeightsError> {
        let fields = [
            ("weights.completed".to_owned(), self.completed),
            ("weights.default".to_owned(), self.default),
        ]
        .into_iter()
        .chain(
            self.by_cause
                .iter()
                .map(|(c, &w)| (format!("weights.by_cause.{c}"), w)),
        );
        for (field, value) in fields {
            if !(value.is_finite() && value >= 0.0) {
                return Err(WeightsError::Range { field, value });
            }
        }
        for &cause in self.by_cause.keys() {
            find_declared(declared, cause).map_err(|e| WeightsError::Undeclared(Box::new(e)))?;
        }
        for cause in declared {
            if let Some(weight) = cause.default_weight {
                self.by_cause.entry(cause.name).or_insert(weight);
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SLOW: Cause = Cause::from_static("too-slow");
    const DROPPED: Cause = Cause::from_static("dropped-item");

    fn declared() -> [DeclaredCause; 2] {
        [
            DeclaredCause {
                name: SLOW,
                default_weight: None,
            },
            DeclaredCause {
                name: DROPPED,
                default_weight: Some(0.25),
            },
        ]
    }

    #[test]
    fn the_operator_s_entry_then_the_declared_default_then_its_default() {
        let mut w: OutcomeWeights =
            ron::from_str(r#"(default: 0.5, by_cause: {"too-slow": 2.0})"#).unwrap();
        w.check(&declared()).unwrap();
        assert_eq!(w.completed, 1.0);
        assert_eq!(w.of(SLOW), 2.0);
        assert_eq!(w.of(DROPPED), 0.25);
        assert_eq!(w.of(Cause::from_static("other")), 0.5);
        assert_eq!(w.scaled(3.0).of(SLOW), 6.0);
    }

    #[test]
    fn bad_weights_and_undeclared_causes_are_named() {
        let mut w: OutcomeWeights = ron::from_str(r#"(by_cause: {"too-slow": -1.0})"#).unwrap();
        assert_eq!(
            w.check(&declared()).unwrap_err().to_string(),
            "`weights.by_cause.too-slow` must be a finite number >= 0, got -1"
        );
        let mut w: OutcomeWeights = ron::from_str(r#"(by_cause: {"glare": 1.0})"#).unwrap();
        let err = w.check(&declared()).unwrap_err().to_string();
        assert!(
            err.starts_with("`weights.by_cause`: ") && err.contains("glare"),
            "{err}"
        );
    }
}
