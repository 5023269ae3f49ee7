//! [`Categorical`], the built-in kind of named values in a fixed order.
//!
//! Similarity is 1 for equal labels and 0 otherwise, unless a table gives it; any other
//! label is one change away.

use super::{Component, ComponentError, MAX_VALUES};
use serde::{Deserialize, Deserializer};
use std::fmt;

/// Named values in a fixed order, with an optional table of value similarities.
#[derive(Clone, Debug, PartialEq)]
pub struct Categorical {
    /// The value names (at least one, no duplicates).
    pub labels: Vec<String>,
    /// Optional square table of value similarities in `[0, 1]`, rows and columns in label
    /// order, 1 on the diagonal; `None` means 1 for equal labels and 0 otherwise.
    pub similarity: Option<Vec<Vec<f64>>>,
}

impl Categorical {
    /// Labels with equal-or-not similarity.
    pub fn new<S: Into<String>>(labels: impl IntoIterator<Item = S>) -> Self {
        Self {
            labels: labels.into_iter().map(Into::into).collect(),
            similarity: None,
        }
    }

    /// The same labels with `table` as their similarities (rows and columns in label
    /// order; checked when the component is made, e.g. by [`super::NamedComponent::new`]).
    pub fn with_similarity(self, table: Vec<Vec<f64>>) -> Self {
        Self {
            similarity: Some(table),
            ..self
        }
    }

    /// Number of changes between the values at `a` and `b`: 0 or 1.
    pub fn changes(&self, a: u16, b: u16) -> u32 {
        u32::from(a != b)
    }

    /// The largest number of changes between two values: 1, or 0 for a single label.
    pub fn max_changes(&self) -> u32 {
        u32::from(self.labels.len() > 1)
    }

    /// Checks the definition, naming the component `name` in errors.
    pub(super) fn check(&self, name: &str) -> Result<(), ComponentError> {
        let labels = &self.labels;
        if labels.is_empty() {
            return Err(ComponentError::Empty(name.to_owned()));
        }
        if labels.len() > MAX_VALUES {
            return Err(ComponentError::TooManyValues {
                name: name.to_owned(),
                count: labels.len(),
            });
        }
        for (i, label) in labels.iter().enumerate() {
            if labels[..i].contains(label) {
                return Err(ComponentError::DuplicateLabel {
                    name: name.to_owned(),
                    label: label.clone(),
                });
            }
        }
        if let Some(table) = &self.similarity {
            let n = labels.len();
            let square = table.len() == n && table.iter().all(|row| row.len() == n);
            let in_range = square
                && table
                    .iter()
                    .enumerate()
                    .all(|(i, row)| row.iter().all(|s| (0.0..=1.0).contains(s)) && row[i] == 1.0);
            if !in_range {
                return Err(ComponentError::BadTable(name.to_owned()));
            }
        }
        Ok(())
    }
}

impl Component for Categorical {
    fn value_count(&self) -> usize {
        self.labels.len()
    }

    /// The table's entry, or 1 if equal and 0 otherwise.
    #[inline]
    fn similarity(&self, a: u16, b: u16) -> f64 {
        match &self.similarity {
            Some(table) => table[usize::from(a)][usize::from(b)],
            None => f64::from(u8::from(a == b)),
        }
    }

    fn adjacent(&self, a: u16, b: u16) -> bool {
        a != b
    }

    fn parse(&self, text: &str) -> Option<u16> {
        let text = text.trim();
        self.labels.iter().position(|l| l == text).map(|i| i as u16)
    }

    fn write_value(&self, index: u16, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        out.write_str(&self.labels[usize::from(index)])
    }

    fn describe_values(&self) -> String {
        format!("one of {}", self.labels.join(", "))
    }
}

/// Reads `labels`, refusing an empty list where it stands.
pub(super) fn deserialize_labels<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<String>, D::Error> {
    let labels = Vec::<String>::deserialize(d)?;
    if labels.is_empty() {
        return Err(serde::de::Error::custom(
            "field `labels` must name at least one value: a component needs a value",
        ));
    }
    Ok(labels)
}
