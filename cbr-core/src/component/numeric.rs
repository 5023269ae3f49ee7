//! [`NumericGrid`], the built-in kind of evenly spaced numbers `min, min + step, ...`.
//!
//! Similarity falls linearly with the distance between two values over the grid's span;
//! one change is one grid step. The range rules of its fields live here, shared by
//! validation and deserialization so both say the same thing.

use super::{Component, ComponentError};
use serde::{Deserialize, Deserializer};
use std::fmt;

/// `count` values `min, min + step, ..., min + (count - 1) * step`.
#[derive(Clone, Debug, PartialEq)]
pub struct NumericGrid {
    /// The smallest value (finite).
    pub min: f64,
    /// The distance between neighbouring values (finite, > 0).
    pub step: f64,
    /// How many values (>= 1).
    pub count: u16,
}

impl NumericGrid {
    /// The number at `index`: `min + index * step`.
    pub fn value(&self, index: u16) -> f64 {
        self.min + f64::from(index) * self.step
    }

    /// The index of the grid value nearest to `value` within 1e-6 of a step, or `None` if
    /// `value` is not on the grid (`NaN` and infinities never are).
    pub fn index_of(&self, value: f64) -> Option<u16> {
        if !value.is_finite() {
            return None;
        }
        let position = (value - self.min) / self.step;
        let index = position.round();
        if (position - index).abs() > 1e-6 || index < 0.0 || index >= f64::from(self.count) {
            return None;
        }
        Some(index as u16)
    }

    /// The index of the grid value nearest to `value`, clamped to the grid (a real value
    /// rounded onto the grid; `NaN` gives the first value).
    ///
    /// ```
    /// let grid = cbr_core::NumericGrid { min: 0.5, step: 0.5, count: 4 };
    /// assert_eq!((grid.nearest_index(1.2), grid.nearest_index(9.0), grid.nearest_index(-3.0)), (1, 3, 0));
    /// ```
    pub fn nearest_index(&self, value: f64) -> u16 {
        let position = ((value - self.min) / self.step).round();
        if position.is_nan() || position <= 0.0 {
            0
        } else {
            position.min(f64::from(self.count - 1)) as u16
        }
    }

    /// Number of changes between the values at `a` and `b`: grid steps.
    pub fn changes(&self, a: u16, b: u16) -> u32 {
        u32::from(a.abs_diff(b))
    }

    /// The largest number of changes between two values: `count - 1`.
    pub fn max_changes(&self) -> u32 {
        u32::from(self.count.saturating_sub(1))
    }

    /// Checks the definition, naming the component `name` in errors.
    pub(super) fn check(&self, name: &str) -> Result<(), ComponentError> {
        if self.count == 0 {
            return Err(ComponentError::Empty(name.to_owned()));
        }
        for (rule, value) in [(&MIN_RULE, self.min), (&STEP_RULE, self.step)] {
            if !(rule.holds)(value) {
                return Err(ComponentError::OutOfRange {
                    name: name.to_owned(),
                    field: rule.field,
                    allowed: rule.allowed,
                    value,
                });
            }
        }
        if !self.value(self.count - 1).is_finite() {
            return Err(ComponentError::Overflow {
                name: name.to_owned(),
                min: self.min,
                step: self.step,
                count: self.count,
            });
        }
        Ok(())
    }
}

impl Component for NumericGrid {
    fn value_count(&self) -> usize {
        usize::from(self.count)
    }

    /// `1 - |a - b| / (max - min)` (1 for a single-valued grid).
    #[inline]
    fn similarity(&self, a: u16, b: u16) -> f64 {
        if self.count <= 1 {
            1.0
        } else {
            // On a grid, |a - b| / (max - min) is the index distance over count - 1.
            1.0 - f64::from(a.abs_diff(b)) / f64::from(self.count - 1)
        }
    }

    fn adjacent(&self, a: u16, b: u16) -> bool {
        a.abs_diff(b) == 1
    }

    fn parse(&self, text: &str) -> Option<u16> {
        self.index_of(text.trim().parse().ok()?)
    }

    fn write_value(&self, index: u16, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(out, "{}", without_binary_noise(self.value(index)))
    }

    fn axis_value(&self, index: u16) -> Option<f64> {
        Some(self.value(index))
    }

    fn describe_values(&self) -> String {
        format!(
            "{} to {} in steps of {}",
            without_binary_noise(self.value(0)),
            without_binary_noise(self.value(self.count - 1)),
            self.step
        )
    }
}

/// `value` rounded to 9 decimals, which removes binary noise such as `0.30000000000000004`:
/// how a grid shows and writes its values (a user's numeric kind may do the same).
///
/// ```
/// assert_eq!(cbr_core::component::without_binary_noise(0.1 + 0.2), 0.3);
/// ```
pub fn without_binary_noise(value: f64) -> f64 {
    let scaled = value * 1e9;
    // Beyond about 1e299 the scaled value overflows; such values have no binary noise
    // below 1e-9 to remove.
    if scaled.is_finite() {
        scaled.round() / 1e9
    } else {
        value
    }
}

/// A range rule for one number of a grid, shared by [`NumericGrid::check`] and
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
            "field `{}` must be {}, got {}",
            rule.field,
            rule.allowed,
            crate::Shown(value)
        )))
    }
}

/// Reads `min`, refusing a value outside its rule where it stands.
pub(super) fn deserialize_min<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    deserialize_ruled(d, &MIN_RULE)
}

/// Reads `step`, refusing a value outside its rule where it stands.
pub(super) fn deserialize_step<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    deserialize_ruled(d, &STEP_RULE)
}

/// Reads `count`, refusing 0 where it stands.
pub(super) fn deserialize_count<'de, D: Deserializer<'de>>(d: D) -> Result<u16, D::Error> {
    let count = u16::deserialize(d)?;
    if count == 0 {
        return Err(serde::de::Error::custom(
            "field `count` must be at least 1: a component needs a value",
        ));
    }
    Ok(count)
}
