//! The context a problem is met in: what the reasoner knows of its situation besides the
//! problem itself (a robot's cargo, the situation it was dispatched into).
//!
//! A domain declares its [`ContextSpace`]: named [`ContextVariable`]s, each with the values
//! it may take, the one that holds when nothing is said (its default) and, optionally, how
//! similar two of its values are. A [`Context`] names the values that differ from their
//! defaults, so the *default context* is the empty one, and two contexts of a space are the
//! same context exactly when they are equal. A case, a query or an episode without a
//! context is in the default context, which is how data from before contexts existed is
//! read.
//!
//! The similarity of two contexts is the product over the variables of their values'
//! similarity: by default 1 for the same value and 0 otherwise (an exact match), or the
//! table the domain declares for the variable.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;

/// One variable of a domain's context.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContextVariable {
    /// Its name, unique in its space.
    pub name: String,
    /// The values it may take, in order; the first is its default.
    pub values: Vec<String>,
    /// How similar two of its values are, `similarity[i][j]` for `values[i]` and
    /// `values[j]`, each in `[0, 1]`, 1 on the diagonal, symmetric; absent: an exact match
    /// (1 on the diagonal, 0 elsewhere).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub similarity: Option<Vec<Vec<f64>>>,
}

impl ContextVariable {
    /// A variable named `name` taking `values`, the first its default, matched exactly.
    pub fn new(name: &str, values: &[&str]) -> Self {
        Self {
            name: name.to_owned(),
            values: values.iter().map(|v| (*v).to_owned()).collect(),
            similarity: None,
        }
    }

    /// The value that holds when nothing is said.
    pub fn default_value(&self) -> &str {
        &self.values[0]
    }

    /// The position of `value` among the variable's values.
    fn position(&self, value: &str) -> Option<usize> {
        self.values.iter().position(|v| v == value)
    }

    /// The similarity of the values at positions `a` and `b`.
    fn value_similarity(&self, a: usize, b: usize) -> f64 {
        match &self.similarity {
            Some(table) => table[a][b],
            None => f64::from(u8::from(a == b)),
        }
    }

    fn check(&self) -> Result<(), ContextError> {
        let variable = || self.name.clone();
        if self.name.is_empty() {
            return Err(ContextError::EmptyName);
        }
        if self.values.is_empty() {
            return Err(ContextError::NoValues(variable()));
        }
        for (i, value) in self.values.iter().enumerate() {
            if value.is_empty() || self.values[..i].contains(value) {
                return Err(ContextError::BadValue {
                    variable: variable(),
                    value: value.clone(),
                });
            }
        }
        let Some(table) = &self.similarity else {
            return Ok(());
        };
        let n = self.values.len();
        if table.len() != n || table.iter().any(|row| row.len() != n) {
            return Err(ContextError::TableShape {
                variable: variable(),
                values: n,
            });
        }
        for (i, row) in table.iter().enumerate() {
            for (j, &s) in row.iter().enumerate() {
                let fits = (0.0..=1.0).contains(&s) && (i != j || s == 1.0) && s == table[j][i];
                if !fits {
                    return Err(ContextError::TableEntry {
                        variable: variable(),
                        row: i,
                        column: j,
                        similarity: s,
                    });
                }
            }
        }
        Ok(())
    }
}

/// The context variables a domain declares.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "Vec<ContextVariable>", into = "Vec<ContextVariable>")]
pub struct ContextSpace {
    variables: Vec<ContextVariable>,
}

/// A context space, a context or a context similarity that cannot be.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ContextError {
    /// A variable without a name.
    #[error("a context variable needs a name")]
    EmptyName,
    /// Two variables of one space share a name.
    #[error("context variable `{0}` is declared twice")]
    DuplicateVariable(String),
    /// A variable that may take no value.
    #[error("context variable `{0}` needs at least one value")]
    NoValues(String),
    /// An empty or repeated value in a variable's declaration.
    #[error("context variable `{variable}`: value `{value}` is empty or repeated")]
    BadValue {
        /// The variable.
        variable: String,
        /// The value.
        value: String,
    },
    /// A similarity table that is not one row and column per value.
    #[error("context variable `{variable}`: its similarity must be {values} rows of {values}")]
    TableShape {
        /// The variable.
        variable: String,
        /// How many values it has.
        values: usize,
    },
    /// A similarity outside `[0, 1]`, not 1 on the diagonal or not symmetric.
    #[error(
        "context variable `{variable}`: similarity[{row}][{column}] = {similarity} must be in \
         [0, 1], 1 on the diagonal and equal to similarity[{column}][{row}]"
    )]
    TableEntry {
        /// The variable.
        variable: String,
        /// The entry's row.
        row: usize,
        /// The entry's column.
        column: usize,
        /// The entry.
        similarity: f64,
    },
    /// A context naming a variable the space does not declare.
    #[error("unknown context variable `{variable}`; the domain declares: {declared}")]
    UnknownVariable {
        /// The name given.
        variable: String,
        /// The declared names, comma-separated (`none` when there are none).
        declared: String,
    },
    /// A context giving a variable a value it may not take.
    #[error("context variable `{variable}` may be {allowed}, not `{value}`")]
    UnknownValue {
        /// The variable.
        variable: String,
        /// The value given.
        value: String,
        /// Its values, comma-separated.
        allowed: String,
    },
}

impl TryFrom<Vec<ContextVariable>> for ContextSpace {
    type Error = ContextError;

    fn try_from(variables: Vec<ContextVariable>) -> Result<Self, ContextError> {
        Self::new(variables)
    }
}

impl From<ContextSpace> for Vec<ContextVariable> {
    fn from(space: ContextSpace) -> Self {
        space.variables
    }
}

impl ContextSpace {
    /// The space of a domain that declares no context: its one context is the default.
    pub const NONE: ContextSpace = ContextSpace {
        variables: Vec::new(),
    };

    /// A space of `variables`, each checked: a name unique in the space, at least one
    /// value, values non-empty and distinct, a similarity table (if any) square, in
    /// `[0, 1]`, 1 on the diagonal and symmetric.
    pub fn new(variables: Vec<ContextVariable>) -> Result<Self, ContextError> {
        for (i, variable) in variables.iter().enumerate() {
            variable.check()?;
            if variables[..i].iter().any(|v| v.name == variable.name) {
                return Err(ContextError::DuplicateVariable(variable.name.clone()));
            }
        }
        Ok(Self { variables })
    }

    /// The declared variables, in order.
    pub fn variables(&self) -> &[ContextVariable] {
        &self.variables
    }

    /// Whether the space declares no variable (every context is the default one).
    pub fn is_empty(&self) -> bool {
        self.variables.is_empty()
    }

    fn variable(&self, name: &str) -> Result<&ContextVariable, ContextError> {
        self.variables
            .iter()
            .find(|v| v.name == name)
            .ok_or_else(|| ContextError::UnknownVariable {
                variable: name.to_owned(),
                declared: if self.variables.is_empty() {
                    "none".to_owned()
                } else {
                    self.variables
                        .iter()
                        .map(|v| v.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                },
            })
    }

    /// The context that sets each named variable to its value (the rest at their defaults),
    /// checked against the declaration; a later setting of a variable replaces an earlier.
    pub fn context<'a>(
        &self,
        settings: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<Context, ContextError> {
        let mut values = BTreeMap::new();
        for (name, value) in settings {
            let variable = self.variable(name)?;
            if variable.position(value).is_none() {
                return Err(ContextError::UnknownValue {
                    variable: name.to_owned(),
                    value: value.to_owned(),
                    allowed: variable.values.join(", "),
                });
            }
            if value == variable.default_value() {
                values.remove(name);
            } else {
                values.insert(name.to_owned(), value.to_owned());
            }
        }
        Ok(Context(values))
    }

    /// The value `context` gives `variable` (its default when the context says nothing),
    /// or `None` when the space does not declare it.
    pub fn value<'a>(&'a self, context: &'a Context, variable: &str) -> Option<&'a str> {
        let declared = self.variables.iter().find(|v| v.name == variable)?;
        Some(context.get(variable).unwrap_or(declared.default_value()))
    }

    /// The similarity of two contexts of the space: the product over its variables of
    /// their values' similarity. Contexts are taken as this space's (values it does not
    /// declare count as different from every other).
    pub fn similarity(&self, a: &Context, b: &Context) -> f64 {
        if a == b {
            return 1.0;
        }
        let mut product = 1.0;
        for variable in &self.variables {
            let position = |c: &Context| {
                c.get(&variable.name)
                    .map_or(Some(0), |value| variable.position(value))
            };
            product *= match (position(a), position(b)) {
                (Some(i), Some(j)) => variable.value_similarity(i, j),
                _ => 0.0,
            };
        }
        product
    }
}

/// How two contexts compare in retrieval: exactly (the default) or by a space's declared
/// similarities ([`ContextSpace::similarity`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub enum ContextSimilarity {
    /// 1 for the same context, 0 for any other.
    #[default]
    Exact,
    /// The product of the declared similarities of the space's variables.
    Declared(std::sync::Arc<ContextSpace>),
}

impl ContextSimilarity {
    /// The similarity of `a` and `b`, in `[0, 1]`; 1 whenever they are equal.
    pub fn similarity(&self, a: &Context, b: &Context) -> f64 {
        match self {
            ContextSimilarity::Exact => f64::from(u8::from(a == b)),
            ContextSimilarity::Declared(space) => space.similarity(a, b),
        }
    }
}

/// The values of a context's variables that differ from their defaults; empty for the
/// default context. Built by [`ContextSpace::context`] (a context read from outside is
/// checked by passing its [`Context::iter`] to it); serialized as a map from variable to
/// value.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Context(
    #[serde(deserialize_with = "crate::unique_keys::each_variable_once")] BTreeMap<String, String>,
);

impl Context {
    /// Whether this is the default context (every variable at its default).
    pub fn is_default(&self) -> bool {
        self.0.is_empty()
    }

    /// The value this context gives `variable`, if it differs from the default.
    pub fn get(&self, variable: &str) -> Option<&str> {
        self.0.get(variable).map(String::as_str)
    }

    /// Every variable set away from its default, with its value, by name.
    pub fn iter(&self) -> impl Iterator<Item = (&str, &str)> + '_ {
        self.0.iter().map(|(k, v)| (k.as_str(), v.as_str()))
    }
}

impl fmt::Display for Context {
    /// `default`, or `name=value` pairs joined by commas.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_default() {
            return f.write_str("default");
        }
        let pairs: Vec<String> = self.iter().map(|(k, v)| format!("{k}={v}")).collect();
        f.write_str(&pairs.join(","))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ugv() -> ContextSpace {
        ContextSpace::new(vec![
            ContextVariable::new("cargo", &["normal", "hazardous"]),
            ContextVariable::new("situation", &["routine", "emergency"]),
        ])
        .unwrap()
    }

    #[test]
    fn defaults_are_dropped_so_equal_contexts_are_the_same() {
        let space = ugv();
        let a = space
            .context([("cargo", "hazardous"), ("situation", "routine")])
            .unwrap();
        let b = space.context([("cargo", "hazardous")]).unwrap();
        assert_eq!(a, b);
        assert_eq!(a.to_string(), "cargo=hazardous");
        assert!(space.context([("cargo", "normal")]).unwrap().is_default());
        assert_eq!(space.value(&a, "situation"), Some("routine"));
        assert_eq!(space.value(&a, "cargo"), Some("hazardous"));
        assert_eq!(space.value(&a, "weather"), None);
        // A later setting replaces an earlier one, also back to the default.
        let back = space
            .context([("cargo", "hazardous"), ("cargo", "normal")])
            .unwrap();
        assert_eq!(back, Context::default());
    }

    #[test]
    fn bad_contexts_say_what_is_allowed() {
        let space = ugv();
        let err = space.context([("cargo", "liquid")]).unwrap_err();
        assert_eq!(
            err.to_string(),
            "context variable `cargo` may be normal, hazardous, not `liquid`"
        );
        let err = space.context([("weather", "rain")]).unwrap_err();
        assert_eq!(
            err.to_string(),
            "unknown context variable `weather`; the domain declares: cargo, situation"
        );
        let none = ContextSpace::default().context([("cargo", "normal")]);
        assert!(none.unwrap_err().to_string().ends_with("declares: none"));
    }

    #[test]
    fn declarations_are_checked() {
        let twice = ContextSpace::new(vec![
            ContextVariable::new("cargo", &["normal"]),
            ContextVariable::new("cargo", &["hazardous"]),
        ]);
        assert_eq!(twice, Err(ContextError::DuplicateVariable("cargo".into())));
        assert_eq!(
            ContextSpace::new(vec![ContextVariable::new("cargo", &[])]),
            Err(ContextError::NoValues("cargo".into()))
        );
        assert!(ContextSpace::new(vec![ContextVariable::new("cargo", &["a", "a"])]).is_err());
        let mut lopsided = ContextVariable::new("situation", &["routine", "emergency"]);
        lopsided.similarity = Some(vec![vec![1.0, 0.5], vec![0.25, 1.0]]);
        let err = ContextSpace::new(vec![lopsided]).unwrap_err();
        assert!(matches!(
            err,
            ContextError::TableEntry {
                row: 0,
                column: 1,
                ..
            }
        ));
        let mut short = ContextVariable::new("situation", &["routine", "emergency"]);
        short.similarity = Some(vec![vec![1.0]]);
        assert!(matches!(
            ContextSpace::new(vec![short]),
            Err(ContextError::TableShape { values: 2, .. })
        ));
    }

    #[test]
    fn hand_computed_similarities() {
        let mut situation = ContextVariable::new("situation", &["routine", "emergency"]);
        situation.similarity = Some(vec![vec![1.0, 0.25], vec![0.25, 1.0]]);
        let space = ContextSpace::new(vec![
            ContextVariable::new("cargo", &["normal", "hazardous"]),
            situation,
        ])
        .unwrap();
        let routine = Context::default();
        let emergency = space.context([("situation", "emergency")]).unwrap();
        let hazardous_emergency = space
            .context([("situation", "emergency"), ("cargo", "hazardous")])
            .unwrap();
        // Declared: the situation's table says 0.25; cargo matches (both normal): 1.
        assert_eq!(space.similarity(&routine, &emergency), 0.25);
        // Cargo differs and is matched exactly: 0.
        assert_eq!(space.similarity(&emergency, &hazardous_emergency), 0.0);
        assert_eq!(space.similarity(&emergency, &emergency), 1.0);
        let declared = ContextSimilarity::Declared(std::sync::Arc::new(space));
        assert_eq!(declared.similarity(&routine, &emergency), 0.25);
        // Exact: 1 or 0.
        assert_eq!(
            ContextSimilarity::Exact.similarity(&routine, &emergency),
            0.0
        );
        assert_eq!(
            ContextSimilarity::Exact.similarity(&routine, &Context::default()),
            1.0
        );
    }

    #[test]
    fn contexts_and_spaces_read_back_from_text() {
        let space = ugv();
        let context = space.context([("cargo", "hazardous")]).unwrap();
        let json = serde_json::to_string(&context).unwrap();
        assert_eq!(json, r#"{"cargo":"hazardous"}"#);
        let read: Context = serde_json::from_str(&json).unwrap();
        assert_eq!(space.context(read.iter()).unwrap(), context);
        let foreign: Context = serde_json::from_str(r#"{"cargo":"liquid"}"#).unwrap();
        assert!(space.context(foreign.iter()).is_err());
        let text = ron::to_string(&space).unwrap();
        let back: ContextSpace = ron::from_str(&text).unwrap();
        assert_eq!(back, space);
        let refused = ron::from_str::<ContextSpace>(r#"[(name: "cargo", values: [])]"#);
        assert!(
            refused
                .unwrap_err()
                .to_string()
                .contains("at least one value")
        );
    }
}
