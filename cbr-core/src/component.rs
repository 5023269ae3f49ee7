//! One modifiable component of a behavior: a finite, ordered set of admissible values.
//!
//! A component is either a numeric grid (`min, min + step, ..., max`) or a categorical list.
//! It knows how similar two of its values are and what "one change" means for it
//! (adjacency). It knows nothing of behaviors, cases or trust.

use serde::{Deserialize, Deserializer, Serialize};
use std::fmt;

/// Largest number of values one component may have (values are stored as `u16` indices).
pub const MAX_VALUES: usize = u16::MAX as usize;

/// The admissible values of a component.
///
/// Deserialization checks each field where it is read (so a parser reports the position of
/// the offending value) and rejects unknown fields.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Values {
    /// `count` values `min, min + step, ..., min + (count - 1) * step`.
    Numeric {
        /// The smallest value.
        #[serde(deserialize_with = "deserialize_min")]
        min: f64,
        /// The distance between neighbouring values (> 0).
        #[serde(deserialize_with = "deserialize_step")]
        step: f64,
        /// How many values (>= 1).
        #[serde(deserialize_with = "deserialize_count")]
        count: u16,
    },
    /// Named values in a fixed order. Similarity is 1 for equal labels and 0 otherwise,
    /// unless a square `similarity` table (rows and columns in label order) is given.
    Categorical {
        /// The value names.
        #[serde(deserialize_with = "deserialize_labels")]
        labels: Vec<String>,
        /// Optional user table of value similarities in `[0, 1]`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        similarity: Option<Vec<Vec<f64>>>,
    },
}

/// A named component with its admissible values and an optional unit for display.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Component {
    /// Name used in configs, reports and behavior strings (e.g. `speed`).
    pub name: String,
    /// Unit shown after numeric values (e.g. `m/s`); empty for none.
    #[serde(default)]
    pub unit: String,
    /// The admissible values.
    pub values: Values,
}

/// Why a component definition is not usable.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ComponentError {
    /// The component has no values.
    #[error("component `{0}` has no values")]
    Empty(String),
    /// More values than a behavior can index.
    #[error("component `{name}` has {count} values; at most {MAX_VALUES} are allowed")]
    TooManyValues {
        /// Component name.
        name: String,
        /// Number of values given.
        count: usize,
    },
    /// A numeric grid with a step that is not a positive finite number, or a non-finite min.
    #[error("component `{name}`: {field} must be {allowed}, got {value}")]
    OutOfRange {
        /// Component name.
        name: String,
        /// Offending field.
        field: &'static str,
        /// What is allowed.
        allowed: &'static str,
        /// The value given.
        value: f64,
    },
    /// A categorical similarity table of the wrong shape or with entries outside `[0, 1]`.
    #[error(
        "component `{0}`: the similarity table must be square, one row per label, entries in [0, 1], 1 on the diagonal"
    )]
    BadTable(String),
    /// A numeric grid whose largest value, `min + (count - 1) * step`, is not a finite
    /// number.
    #[error(
        "component `{name}`: the grid overflows: `min` {min:e} + (`count` {count} - 1) x `step` {step:e} is not a finite number"
    )]
    Overflow {
        /// Component name.
        name: String,
        /// The smallest value.
        min: f64,
        /// The distance between values.
        step: f64,
        /// How many values.
        count: u16,
    },
    /// Two categorical labels are the same.
    #[error("component `{name}`: label `{label}` appears twice")]
    DuplicateLabel {
        /// Component name.
        name: String,
        /// The repeated label.
        label: String,
    },
}

/// A range rule for one number of a numeric grid, shared by [`Component::validate`] and
/// deserialization so both say the same thing.
struct Rule {
    field: &'static str,
    allowed: &'static str,
    holds: fn(f64) -> bool,
}

const MIN_RULE: Rule = Rule {
    field: "min",
    allowed: "a finite number",
    holds: f64::is_finite,
};

const STEP_RULE: Rule = Rule {
    field: "step",
    allowed: "a finite number > 0",
    holds: |step| step.is_finite() && step > 0.0,
};

fn deserialize_ruled<'de, D: Deserializer<'de>>(d: D, rule: &Rule) -> Result<f64, D::Error> {
    let value = f64::deserialize(d)?;
    if (rule.holds)(value) {
        Ok(value)
    } else {
        Err(serde::de::Error::custom(format_args!(
            "field `{}` must be {}, got {value}",
            rule.field, rule.allowed
        )))
    }
}

fn deserialize_min<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    deserialize_ruled(d, &MIN_RULE)
}

fn deserialize_step<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    deserialize_ruled(d, &STEP_RULE)
}

fn deserialize_count<'de, D: Deserializer<'de>>(d: D) -> Result<u16, D::Error> {
    let count = u16::deserialize(d)?;
    if count == 0 {
        return Err(serde::de::Error::custom(
            "field `count` must be at least 1: a component needs a value",
        ));
    }
    Ok(count)
}

fn deserialize_labels<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<String>, D::Error> {
    let labels = Vec::<String>::deserialize(d)?;
    if labels.is_empty() {
        return Err(serde::de::Error::custom(
            "field `labels` must name at least one value: a component needs a value",
        ));
    }
    Ok(labels)
}

impl Component {
    /// A numeric grid component of `count` values starting at `min`, `step` apart.
    pub fn numeric(
        name: &str,
        unit: &str,
        min: f64,
        step: f64,
        count: u16,
    ) -> Result<Self, ComponentError> {
        let component = Self {
            name: name.to_owned(),
            unit: unit.to_owned(),
            values: Values::Numeric { min, step, count },
        };
        component.validate()?;
        Ok(component)
    }

    /// A categorical component with the given labels (equal-or-not similarity).
    pub fn categorical(name: &str, labels: &[&str]) -> Result<Self, ComponentError> {
        let component = Self {
            name: name.to_owned(),
            unit: String::new(),
            values: Values::Categorical {
                labels: labels.iter().map(|l| (*l).to_owned()).collect(),
                similarity: None,
            },
        };
        component.validate()?;
        Ok(component)
    }

    /// Checks the definition; every constructor and every deserialized space calls this.
    pub fn validate(&self) -> Result<(), ComponentError> {
        let name = || self.name.clone();
        match &self.values {
            Values::Numeric { min, step, count } => {
                if *count == 0 {
                    return Err(ComponentError::Empty(name()));
                }
                for (rule, value) in [(&MIN_RULE, *min), (&STEP_RULE, *step)] {
                    if !(rule.holds)(value) {
                        return Err(ComponentError::OutOfRange {
                            name: name(),
                            field: rule.field,
                            allowed: rule.allowed,
                            value,
                        });
                    }
                }
                if !(min + f64::from(count - 1) * step).is_finite() {
                    return Err(ComponentError::Overflow {
                        name: name(),
                        min: *min,
                        step: *step,
                        count: *count,
                    });
                }
            }
            Values::Categorical { labels, similarity } => {
                if labels.is_empty() {
                    return Err(ComponentError::Empty(name()));
                }
                if labels.len() > MAX_VALUES {
                    return Err(ComponentError::TooManyValues {
                        name: name(),
                        count: labels.len(),
                    });
                }
                for (i, label) in labels.iter().enumerate() {
                    if labels[..i].contains(label) {
                        return Err(ComponentError::DuplicateLabel {
                            name: name(),
                            label: label.clone(),
                        });
                    }
                }
                if let Some(table) = similarity {
                    let n = labels.len();
                    let square = table.len() == n && table.iter().all(|row| row.len() == n);
                    let in_range = square
                        && table.iter().enumerate().all(|(i, row)| {
                            row.iter().all(|s| (0.0..=1.0).contains(s)) && row[i] == 1.0
                        });
                    if !in_range {
                        return Err(ComponentError::BadTable(name()));
                    }
                }
            }
        }
        Ok(())
    }

    /// Number of admissible values.
    pub fn len(&self) -> usize {
        match &self.values {
            Values::Numeric { count, .. } => usize::from(*count),
            Values::Categorical { labels, .. } => labels.len(),
        }
    }

    /// Whether the component has no values (never true for a validated component).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether the values are numeric.
    pub fn is_numeric(&self) -> bool {
        matches!(self.values, Values::Numeric { .. })
    }

    /// The numeric value at `index` (categorical components give the index itself).
    pub fn numeric_value(&self, index: u16) -> f64 {
        match &self.values {
            Values::Numeric { min, step, .. } => min + f64::from(index) * step,
            Values::Categorical { .. } => f64::from(index),
        }
    }

    /// The numeric value at `index` rounded to 9 decimals, which removes binary noise such as
    /// `0.30000000000000004` (categorical components give the index itself).
    pub fn real_value(&self, index: u16) -> f64 {
        let value = self.numeric_value(index);
        let scaled = value * 1e9;
        // Beyond about 1e299 the scaled value overflows; such values have no binary noise
        // below 1e-9 to remove.
        if scaled.is_finite() {
            scaled.round() / 1e9
        } else {
            value
        }
    }

    /// The index of the admissible value nearest to `value` within 1e-6 of a step,
    /// or `None` if `value` is not on the grid (`NaN` and infinities never are).
    pub fn index_of_numeric(&self, value: f64) -> Option<u16> {
        match &self.values {
            Values::Numeric { .. } if !value.is_finite() => None,
            Values::Numeric { min, step, count } => {
                let position = (value - min) / step;
                let index = position.round();
                if (position - index).abs() > 1e-6 || index < 0.0 || index >= f64::from(*count) {
                    return None;
                }
                Some(index as u16)
            }
            Values::Categorical { .. } => None,
        }
    }

    /// The index of a value given as text: a number for numeric grids, a label otherwise.
    pub fn index_of_text(&self, text: &str) -> Option<u16> {
        match &self.values {
            Values::Numeric { .. } => self.index_of_numeric(text.trim().parse().ok()?),
            Values::Categorical { labels, .. } => labels
                .iter()
                .position(|l| l == text.trim())
                .map(|i| i as u16),
        }
    }

    /// The value at `index` for display, e.g. `3.5` or `astar`.
    pub fn display_value(&self, index: u16) -> ValueDisplay<'_> {
        ValueDisplay {
            component: self,
            index,
        }
    }

    /// Similarity of the values at `a` and `b`, in `[0, 1]`.
    ///
    /// Numeric: `1 - |a - b| / (max - min)` (1 for a single-valued grid); categorical: the
    /// user table, or 1 if equal and 0 otherwise.
    pub fn similarity(&self, a: u16, b: u16) -> f64 {
        match &self.values {
            Values::Numeric { count, .. } => {
                if *count <= 1 {
                    1.0
                } else {
                    // On a grid, |a - b| / (max - min) is the index distance over count - 1.
                    1.0 - f64::from(a.abs_diff(b)) / f64::from(count - 1)
                }
            }
            Values::Categorical { similarity, .. } => match similarity {
                Some(table) => table[usize::from(a)][usize::from(b)],
                None => f64::from(u8::from(a == b)),
            },
        }
    }

    /// Number of changes between the values at `a` and `b`: a change moves to an adjacent
    /// value (numeric: one grid step; categorical: any other label).
    pub fn changes(&self, a: u16, b: u16) -> u32 {
        match &self.values {
            Values::Numeric { .. } => u32::from(a.abs_diff(b)),
            Values::Categorical { .. } => u32::from(a != b),
        }
    }

    /// The values one change away from `index`, in ascending order.
    pub fn adjacent(&self, index: u16) -> impl Iterator<Item = u16> + '_ {
        let len = self.len() as u16;
        let numeric = self.is_numeric();
        (0..len).filter(move |&j| {
            if numeric {
                j.abs_diff(index) == 1
            } else {
                j != index
            }
        })
    }

    /// The largest number of changes between any two values of this component.
    pub fn max_changes(&self) -> u32 {
        match &self.values {
            Values::Numeric { count, .. } => u32::from(count.saturating_sub(1)),
            Values::Categorical { labels, .. } => u32::from(labels.len() > 1),
        }
    }
}

/// Displays one value of a component (see [`Component::display_value`]).
pub struct ValueDisplay<'a> {
    component: &'a Component,
    index: u16,
}

impl fmt::Display for ValueDisplay<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.component.values {
            Values::Numeric { .. } => write!(f, "{}", self.component.real_value(self.index)),
            Values::Categorical { labels, .. } => f.write_str(&labels[usize::from(self.index)]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn speed() -> Component {
        // SPEC section 8: speed {0.5, 1.0, ..., 10.0} m/s, 20 values.
        Component::numeric("speed", "m/s", 0.5, 0.5, 20).unwrap()
    }

    #[test]
    fn numeric_similarity_is_one_minus_normalised_distance() {
        let c = speed();
        // values 1.0 (index 1) and 3.5 (index 6): 1 - |1.0 - 3.5| / (10.0 - 0.5) = 1 - 2.5/9.5
        let expected = 1.0 - 2.5 / 9.5;
        assert!((c.similarity(1, 6) - expected).abs() < 1e-12);
        assert_eq!(c.similarity(4, 4), 1.0);
        assert_eq!(c.similarity(0, 19), 0.0);
    }

    #[test]
    fn categorical_similarity_and_adjacency() {
        let c = Component::categorical("planner", &["astar", "rrt", "lattice"]).unwrap();
        assert_eq!(c.similarity(0, 0), 1.0);
        assert_eq!(c.similarity(0, 2), 0.0);
        assert_eq!(c.adjacent(1).collect::<Vec<_>>(), vec![0, 2]);
        assert_eq!(c.changes(0, 2), 1);
    }

    #[test]
    fn numeric_adjacency_and_changes() {
        let c = speed();
        assert_eq!(c.adjacent(0).collect::<Vec<_>>(), vec![1]);
        assert_eq!(c.adjacent(5).collect::<Vec<_>>(), vec![4, 6]);
        assert_eq!(c.changes(2, 7), 5);
    }

    #[test]
    fn values_parse_and_display() {
        let c = speed();
        assert_eq!(c.index_of_text("3.5"), Some(6));
        assert_eq!(c.index_of_text("3.4"), None);
        assert_eq!(c.index_of_text("10.5"), None);
        // `NaN` once fell through every range test and became the first grid value.
        for not_a_value in ["NaN", "nan", "inf", "-inf", "infinity"] {
            assert_eq!(c.index_of_text(not_a_value), None, "{not_a_value}");
        }
        assert_eq!(c.display_value(6).to_string(), "3.5");
        let padding = Component::numeric("padding", "m", 0.1, 0.1, 20).unwrap();
        assert_eq!(padding.display_value(2).to_string(), "0.3");
    }

    #[test]
    fn deserialization_checks_each_field_where_it_is_read() {
        let read = |text: &str| ron::from_str::<Component>(text).unwrap_err();
        let text = "(name: \"speed\", values: Numeric(min: 0.5, step: -0.5, count: 20))";
        let e = read(text);
        assert_eq!(
            e.code.to_string(),
            "field `step` must be a finite number > 0, got -0.5"
        );
        // The position is just past the offending value.
        let past_value = text.find("step: -0.5").unwrap() + "step: -0.5".len() + 1;
        assert_eq!((e.position.line, e.position.col), (1, past_value));
        let e = read("(name: \"x\", values: Numeric(min: inf, step: 1.0, count: 2))");
        assert!(
            e.code
                .to_string()
                .starts_with("field `min` must be a finite number")
        );
        let e = read("(name: \"x\", values: Numeric(min: 0.0, step: 1.0, count: 0))");
        assert!(
            e.code
                .to_string()
                .starts_with("field `count` must be at least 1")
        );
        let e = read("(name: \"x\", values: Categorical(labels: []))");
        assert!(
            e.code
                .to_string()
                .starts_with("field `labels` must name at least one")
        );
        let e = read("(name: \"x\", colour: 1, values: Categorical(labels: [\"a\"]))");
        assert!(e.code.to_string().contains("colour"));
        let e = read("(name: \"x\", values: Numeric(min: 0.0, step: 1.0, count: 2, max: 3.0))");
        assert!(e.code.to_string().contains("max"));
        let ok: Component =
            ron::from_str("(name: \"x\", values: Numeric(min: 0.0, step: 1.0, count: 2))").unwrap();
        assert_eq!(ok.len(), 2);
    }

    #[test]
    fn a_grid_that_overflows_is_refused_naming_its_fields() {
        let err = Component::numeric("speed", "m/s", 1e308, 1e308, 3).unwrap_err();
        assert!(matches!(err, ComponentError::Overflow { count: 3, .. }));
        assert_eq!(
            err.to_string(),
            "component `speed`: the grid overflows: `min` 1e308 + (`count` 3 - 1) x `step` 1e308 is not a finite number"
        );
        // The largest finite grids stay usable and display their values.
        let huge = Component::numeric("x", "", 1e300, 1e300, 2).unwrap();
        assert_eq!(huge.real_value(1), 2e300);
    }

    #[test]
    fn invalid_definitions_are_rejected() {
        assert!(matches!(
            Component::numeric("speed", "m/s", 0.5, -0.5, 20),
            Err(ComponentError::OutOfRange { field: "step", .. })
        ));
        assert!(matches!(
            Component::numeric("speed", "m/s", 0.5, 0.5, 0),
            Err(ComponentError::Empty(_))
        ));
        assert!(matches!(
            Component::categorical("x", &[]),
            Err(ComponentError::Empty(_))
        ));
        assert!(matches!(
            Component::categorical("x", &["a", "a"]),
            Err(ComponentError::DuplicateLabel { .. })
        ));
    }
}
