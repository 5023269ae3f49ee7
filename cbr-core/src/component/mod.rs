//! Components: the modifiable parts of a behavior, each a finite, ordered set of values.
//!
//! The [`Component`] trait is what a kind of component says of its values: how many there
//! are, how similar two of them are, which pairs are one change apart (adjacency), which
//! value a user's text names and how a value reads in real units. The number of changes
//! between two values and its largest value follow from adjacency.
//!
//! Two kinds are built in, [`NumericGrid`] and [`Categorical`]; a user's own kind
//! implements [`Component`] and [`ComponentKind`] and enters a space as a
//! [`CustomComponent`] (checked once, stored by name and definition, read back through
//! [`register_component_kind`]). A [`NamedComponent`] is one component of a space: a name,
//! a unit and its [`Values`]. Similarity and changes, on the hot path of retrieval and
//! search, dispatch on [`Values`] so the built-in kinds are called directly. Nothing here
//! knows of behaviors, cases or trust.

mod categorical;
mod custom;
mod format;
mod numeric;
mod registry;

pub use categorical::Categorical;
pub use custom::{ComponentKind, CustomComponent, KindError, KindProblem, MAX_CUSTOM_VALUES};
pub use numeric::{NumericGrid, without_binary_noise};
pub use registry::{RegistryError, register_component_kind, registered_component_kinds};

use serde::{Deserialize, Serialize};
use std::fmt;

/// Largest number of values one component may have (values are stored as `u16` indices).
pub const MAX_VALUES: usize = u16::MAX as usize;

/// A kind of component: a finite, ordered set of values, indexed `0..value_count()`.
///
/// Methods may assume every index given is below [`Component::value_count`]. A user's kind
/// is checked when it enters a space ([`CustomComponent::new`] states the rules), so every
/// method of a space may rely on them.
pub trait Component: fmt::Debug + Send + Sync {
    /// Number of values (at least 1).
    fn value_count(&self) -> usize;

    /// Similarity of the values at `a` and `b`: in `[0, 1]`, symmetric, 1 when `a == b`.
    fn similarity(&self, a: u16, b: u16) -> f64;

    /// Whether `a` and `b` are one change apart: symmetric, false when `a == b`, and
    /// connecting every value to every other through a path of changes.
    fn adjacent(&self, a: u16, b: u16) -> bool;

    /// The index of the value a user's text names (surrounding spaces ignored), or `None`.
    fn parse(&self, text: &str) -> Option<u16>;

    /// Writes the value at `index` in real units, without the unit (e.g. `3.5`, `astar`);
    /// [`Component::parse`] reads it back.
    fn write_value(&self, index: u16, out: &mut fmt::Formatter<'_>) -> fmt::Result;

    /// A real number for the value at `index`, to place it on a plot's numeric axis; `None`
    /// (the default) for values with no natural position.
    fn axis_value(&self, _index: u16) -> Option<f64> {
        None
    }

    /// The admissible values in words, for error messages (by default up to
    /// [`LISTED_VALUES`] values listed, e.g. `one of a, b, c`).
    fn describe_values(&self) -> String {
        let n = self.value_count() as u16;
        let shown = |index| {
            ValueDisplay {
                component: self,
                index,
            }
            .to_string()
        };
        if usize::from(n) <= LISTED_VALUES {
            let all: Vec<String> = (0..n).map(shown).collect();
            format!("one of {}", all.join(", "))
        } else {
            let first: Vec<String> = (0..3).map(shown).collect();
            format!(
                "one of {}, ..., {} ({n} values)",
                first.join(", "),
                shown(n - 1)
            )
        }
    }
}

/// How many values [`Component::describe_values`] lists by default before it elides.
pub const LISTED_VALUES: usize = 12;

/// The admissible values of a component, by kind.
///
/// The explicit one-byte tag lets the hot path tell the kinds apart with one compare (the
/// niche encoding a third variant forces cost Algorithm 2 about 9% on spaces whose
/// similarities are not tabled; `docs/benchmarks.md`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "format::StoredValues", into = "format::StoredValues")]
#[repr(u8)]
#[non_exhaustive]
pub enum Values {
    /// Evenly spaced numbers.
    Numeric(NumericGrid),
    /// Named values in a fixed order.
    Categorical(Categorical),
    /// A user's own kind.
    Custom(CustomComponent),
}

impl Values {
    /// The values as a [`Component`].
    pub fn component(&self) -> &dyn Component {
        match self {
            Values::Numeric(grid) => grid,
            Values::Categorical(categorical) => categorical,
            Values::Custom(custom) => custom.component(),
        }
    }

    /// The kind's name in words: `numeric`, `categorical` or `custom kind `name``.
    pub fn kind_name(&self) -> String {
        match self {
            Values::Numeric(_) => "numeric".to_owned(),
            Values::Categorical(_) => "categorical".to_owned(),
            Values::Custom(custom) => format!("custom kind `{}`", custom.kind()),
        }
    }
}

/// One component of a space: a name, a unit for display and its admissible values.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename = "Component", deny_unknown_fields)]
pub struct NamedComponent {
    /// Name used in configs, reports and behavior strings (e.g. `speed`).
    pub name: String,
    /// Unit shown after the values (e.g. `m/s`); empty for none.
    #[serde(default)]
    pub unit: String,
    /// The admissible values.
    pub values: Values,
}

/// Why a component definition is not usable.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
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
    #[error("component `{name}`: {field} must be {allowed}, got {}", crate::Shown(*.value))]
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
    /// A user's kind that breaks the rules of [`Component`].
    #[error("component `{name}`: {problem}")]
    Kind {
        /// Component name.
        name: String,
        /// What is wrong with the kind.
        problem: KindError,
    },
}

impl NamedComponent {
    /// A component of any kind, checked.
    pub fn new(name: &str, unit: &str, values: Values) -> Result<Self, ComponentError> {
        let component = Self {
            name: name.to_owned(),
            unit: unit.to_owned(),
            values,
        };
        component.validate()?;
        Ok(component)
    }

    /// A numeric grid component of `count` values starting at `min`, `step` apart.
    pub fn numeric(
        name: &str,
        unit: &str,
        min: f64,
        step: f64,
        count: u16,
    ) -> Result<Self, ComponentError> {
        Self::new(
            name,
            unit,
            Values::Numeric(NumericGrid { min, step, count }),
        )
    }

    /// A categorical component with the given labels (equal-or-not similarity).
    pub fn categorical(name: &str, labels: &[&str]) -> Result<Self, ComponentError> {
        Self::new(
            name,
            "",
            Values::Categorical(Categorical::new(labels.iter().copied())),
        )
    }

    /// A component of a user's kind, checked (see [`CustomComponent::new`]).
    pub fn custom<K: ComponentKind>(
        name: &str,
        unit: &str,
        kind: K,
    ) -> Result<Self, ComponentError> {
        let custom = CustomComponent::new(kind).map_err(|problem| ComponentError::Kind {
            name: name.to_owned(),
            problem,
        })?;
        Self::new(name, unit, Values::Custom(custom))
    }

    /// Checks the definition; every constructor and every deserialized space calls this
    /// (a custom kind was checked when it was wrapped).
    pub fn validate(&self) -> Result<(), ComponentError> {
        match &self.values {
            Values::Numeric(grid) => grid.check(&self.name),
            Values::Categorical(categorical) => categorical.check(&self.name),
            Values::Custom(_) => Ok(()),
        }
    }

    /// Number of admissible values.
    #[inline]
    pub fn len(&self) -> usize {
        match &self.values {
            Values::Numeric(grid) => usize::from(grid.count),
            Values::Categorical(categorical) => categorical.labels.len(),
            Values::Custom(custom) => custom.value_count(),
        }
    }

    /// Whether the component has no values (never true for a validated component).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether the values are a numeric grid.
    pub fn is_numeric(&self) -> bool {
        matches!(self.values, Values::Numeric(_))
    }

    /// The number at `index`: the grid value, the kind's axis value, or else the index.
    pub fn numeric_value(&self, index: u16) -> f64 {
        match &self.values {
            Values::Numeric(grid) => grid.value(index),
            other => other
                .component()
                .axis_value(index)
                .unwrap_or(f64::from(index)),
        }
    }

    /// [`NamedComponent::numeric_value`] rounded to 9 decimals, which removes binary noise
    /// such as `0.30000000000000004`.
    pub fn real_value(&self, index: u16) -> f64 {
        numeric::without_binary_noise(self.numeric_value(index))
    }

    /// The index of the grid value nearest to `value` within 1e-6 of a step, or `None` if
    /// `value` is not on the grid or the component is not a numeric grid.
    pub fn index_of_numeric(&self, value: f64) -> Option<u16> {
        match &self.values {
            Values::Numeric(grid) => grid.index_of(value),
            _ => None,
        }
    }

    /// The index of a value given as text: a number on a numeric grid, a label, or
    /// whatever a custom kind reads.
    pub fn index_of_text(&self, text: &str) -> Option<u16> {
        self.values.component().parse(text)
    }

    /// The value at `index` for display, e.g. `3.5` or `astar` (without the unit).
    pub fn display_value(&self, index: u16) -> ValueDisplay<'_> {
        ValueDisplay {
            component: self.values.component(),
            index,
        }
    }

    /// The admissible values in words, e.g. `0.5 to 10 in steps of 0.5`.
    pub fn describe_values(&self) -> String {
        self.values.component().describe_values()
    }

    /// Similarity of the values at `a` and `b`, in `[0, 1]`.
    #[inline]
    pub fn similarity(&self, a: u16, b: u16) -> f64 {
        match &self.values {
            Values::Numeric(grid) => grid.similarity(a, b),
            Values::Categorical(categorical) => categorical.similarity(a, b),
            Values::Custom(custom) => custom.similarity(a, b),
        }
    }

    /// Number of changes between the values at `a` and `b`: the fewest moves between
    /// adjacent values (numeric: grid steps; categorical: 1 for any other label).
    #[inline]
    pub fn changes(&self, a: u16, b: u16) -> u32 {
        match &self.values {
            Values::Numeric(grid) => grid.changes(a, b),
            Values::Categorical(categorical) => categorical.changes(a, b),
            Values::Custom(custom) => custom.changes(a, b),
        }
    }

    /// The values one change away from `index`, in ascending order.
    pub fn adjacent(&self, index: u16) -> impl Iterator<Item = u16> + '_ {
        (0..self.len() as u16).filter(move |&other| self.changes(index, other) == 1)
    }

    /// The largest number of changes between any two values of this component.
    pub fn max_changes(&self) -> u32 {
        match &self.values {
            Values::Numeric(grid) => grid.max_changes(),
            Values::Categorical(categorical) => categorical.max_changes(),
            Values::Custom(custom) => custom.max_changes(),
        }
    }
}

/// Displays one value of a component (see [`NamedComponent::display_value`]).
pub struct ValueDisplay<'a, C: Component + ?Sized = dyn Component + 'a> {
    component: &'a C,
    index: u16,
}

impl<C: Component + ?Sized> fmt::Display for ValueDisplay<'_, C> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.component.write_value(self.index, f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn speed() -> NamedComponent {
        // docs/model.md#movement: speed {0.5, 1.0, ..., 10.0} m/s, 20 values.
        NamedComponent::numeric("speed", "m/s", 0.5, 0.5, 20).unwrap()
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
        let c = NamedComponent::categorical("planner", &["astar", "rrt", "lattice"]).unwrap();
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
        let padding = NamedComponent::numeric("padding", "m", 0.1, 0.1, 20).unwrap();
        assert_eq!(padding.display_value(2).to_string(), "0.3");
    }

    #[test]
    fn deserialization_checks_each_field_where_it_is_read() {
        let read = |text: &str| ron::from_str::<NamedComponent>(text).unwrap_err();
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
        let ok: NamedComponent =
            ron::from_str("(name: \"x\", values: Numeric(min: 0.0, step: 1.0, count: 2))").unwrap();
        assert_eq!(ok.len(), 2);
    }

    #[test]
    fn a_grid_that_overflows_is_refused_naming_its_fields() {
        let err = NamedComponent::numeric("speed", "m/s", 1e308, 1e308, 3).unwrap_err();
        assert!(matches!(err, ComponentError::Overflow { count: 3, .. }));
        assert_eq!(
            err.to_string(),
            "component `speed`: the grid overflows: `min` 1e308 + (`count` 3 - 1) x `step` 1e308 is not a finite number"
        );
        // The largest finite grids stay usable and display their values.
        let huge = NamedComponent::numeric("x", "", 1e300, 1e300, 2).unwrap();
        assert_eq!(huge.real_value(1), 2e300);
    }

    #[test]
    fn invalid_definitions_are_rejected() {
        assert!(matches!(
            NamedComponent::numeric("speed", "m/s", 0.5, -0.5, 20),
            Err(ComponentError::OutOfRange { field: "step", .. })
        ));
        assert!(matches!(
            NamedComponent::numeric("speed", "m/s", 0.5, 0.5, 0),
            Err(ComponentError::Empty(_))
        ));
        assert!(matches!(
            NamedComponent::categorical("x", &[]),
            Err(ComponentError::Empty(_))
        ));
        assert!(matches!(
            NamedComponent::categorical("x", &["a", "a"]),
            Err(ComponentError::DuplicateLabel { .. })
        ));
    }

    #[test]
    fn built_in_kinds_keep_their_stored_form() {
        // Case bases store their space in this form: it must not change.
        let speed = NamedComponent::numeric("speed", "m/s", 0.25, 0.25, 8).unwrap();
        let ron_text = r#"(name:"speed",unit:"m/s",values:Numeric(min:0.25,step:0.25,count:8))"#;
        assert_eq!(ron::to_string(&speed).unwrap(), ron_text);
        assert_eq!(ron::from_str::<NamedComponent>(ron_text).unwrap(), speed);
        let json = r#"{"name":"speed","unit":"m/s","values":{"Numeric":{"min":0.25,"step":0.25,"count":8}}}"#;
        assert_eq!(serde_json::to_string(&speed).unwrap(), json);
        assert_eq!(serde_json::from_str::<NamedComponent>(json).unwrap(), speed);
        let planner = NamedComponent {
            name: "planner".into(),
            unit: String::new(),
            values: Values::Categorical(Categorical {
                labels: vec!["astar".into(), "rrt".into()],
                similarity: Some(vec![vec![1.0, 0.5], vec![0.5, 1.0]]),
            }),
        };
        let ron_text = r#"(name:"planner",unit:"",values:Categorical(labels:["astar","rrt"],similarity:Some([[1.0,0.5],[0.5,1.0]])))"#;
        assert_eq!(ron::to_string(&planner).unwrap(), ron_text);
        assert_eq!(ron::from_str::<NamedComponent>(ron_text).unwrap(), planner);
        let plain = NamedComponent::categorical("planner", &["astar", "rrt"]).unwrap();
        assert_eq!(
            ron::to_string(&plain).unwrap(),
            r#"(name:"planner",unit:"",values:Categorical(labels:["astar","rrt"]))"#
        );
        let named: NamedComponent = ron::from_str(
            r#"Component(name: "planner", values: Categorical(labels: ["astar", "rrt"]))"#,
        )
        .unwrap();
        assert_eq!(named, plain);
    }

    #[test]
    fn values_are_described_in_words() {
        assert_eq!(speed().describe_values(), "0.5 to 10 in steps of 0.5");
        let planner = NamedComponent::categorical("planner", &["astar", "rrt"]).unwrap();
        assert_eq!(planner.describe_values(), "one of astar, rrt");
        assert_eq!(planner.values.kind_name(), "categorical");
    }
}
