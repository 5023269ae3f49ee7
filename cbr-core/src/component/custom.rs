//! A user's own kind of component: the [`ComponentKind`] a user implements, and
//! [`CustomComponent`], such a kind checked once and ready for a space.
//!
//! A kind is checked exhaustively when it is wrapped, so every method of a space may assume
//! it is well formed: similarity in `[0, 1]`, symmetric, 1 on the diagonal; adjacency
//! symmetric, never from a value to itself, connecting every value; every shown value
//! parses back to its index; axis values finite; the definition reads back to itself. The
//! number of changes between two values is the shortest path of adjacent values between
//! them. Similarities and changes are tabled here once, so retrieval and search read no
//! trait object, and custom kinds have at most [`MAX_CUSTOM_VALUES`] values.
//!
//! A kind is stored as its name and its *definition*, the kind's own serde form held as a
//! self-describing value: `Custom(kind: "log-grid", definition: {"min": 1.0, ...})` in RON,
//! `{"Custom": {"kind": "log-grid", "definition": {...}}}` in JSON. Reading it back finds
//! the kind by name in the registry ([`super::register_component_kind`]).

use super::{Component, ValueDisplay};
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::collections::VecDeque;
use std::fmt;
use std::sync::Arc;

/// Largest number of values of a custom kind (every pair is checked, and its similarity
/// and number of changes tabled, when the kind is wrapped: at most 10 MiB).
pub const MAX_CUSTOM_VALUES: usize = 1024;

/// A user's kind of component that can be stored: a [`Component`] with a serde form and a
/// unique name.
///
/// Its serde form is its definition (e.g. a log-scale grid's `min`, `ratio` and `count`);
/// it must read back to the same definition, and it should refuse invalid definitions
/// when read, as the built-in kinds do. Register the kind with
/// [`super::register_component_kind`] before reading a space that uses it.
pub trait ComponentKind: Component + Serialize + DeserializeOwned + 'static {
    /// The name the kind is stored and registered under, e.g. `log-grid`.
    const KIND: &'static str;
}

/// A user's kind of component, checked and ready for a space (cheap to clone).
#[derive(Clone)]
pub struct CustomComponent {
    inner: Arc<Checked>,
}

struct Checked {
    kind: &'static str,
    component: Box<dyn Component>,
    definition: serde_json::Value,
    len: usize,
    /// Similarity of values `a` and `b` at `a * len + b` (the hot path reads no trait
    /// object).
    similarities: Vec<f64>,
    /// Number of changes between values `a` and `b` at `a * len + b`.
    changes: Vec<u16>,
    max_changes: u32,
}

/// Why a user's kind of component is not usable.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("kind `{kind}`: {problem}")]
pub struct KindError {
    /// The kind's name ([`ComponentKind::KIND`]).
    pub kind: String,
    /// What is wrong with it.
    pub problem: KindProblem,
}

/// What is wrong with a user's kind of component (values are named as the kind shows them).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum KindProblem {
    /// No values, or more than [`MAX_CUSTOM_VALUES`].
    #[error("it has {0} values; a custom kind has 1 to {MAX_CUSTOM_VALUES}")]
    ValueCount(usize),
    /// A similarity outside `[0, 1]` (or `NaN`).
    #[error("the similarity of `{a}` to `{b}` is {similarity}; it must be in [0, 1]")]
    SimilarityOutOfRange {
        /// The first value.
        a: String,
        /// The second value.
        b: String,
        /// The similarity given.
        similarity: f64,
    },
    /// A value whose similarity to itself is not 1.
    #[error("the similarity of `{value}` to itself is {similarity}; it must be 1")]
    SimilarityNotOneOnDiagonal {
        /// The value.
        value: String,
        /// The similarity given.
        similarity: f64,
    },
    /// Similarity that depends on the order of its arguments.
    #[error(
        "the similarity is not symmetric: `{a}` to `{b}` is {a_to_b}, `{b}` to `{a}` is {b_to_a}"
    )]
    SimilarityAsymmetric {
        /// The first value.
        a: String,
        /// The second value.
        b: String,
        /// `similarity(a, b)`.
        a_to_b: f64,
        /// `similarity(b, a)`.
        b_to_a: f64,
    },
    /// A value adjacent to itself.
    #[error("`{0}` is adjacent to itself; a change must move to another value")]
    SelfAdjacent(String),
    /// Adjacency that depends on the order of its arguments.
    #[error("adjacency is not symmetric: `{from}` is adjacent to `{to}`, but not the reverse")]
    AdjacencyAsymmetric {
        /// The value adjacent to `to`.
        from: String,
        /// The value `from` is adjacent to.
        to: String,
    },
    /// Two values no sequence of changes connects.
    #[error(
        "`{to}` cannot be reached from `{from}` by changes; adjacency must connect every value"
    )]
    Disconnected {
        /// Where the changes start.
        from: String,
        /// The value they cannot reach.
        to: String,
    },
    /// A shown value that does not parse back to its index.
    #[error("value {index} is shown as `{shown}`, which parses to {parsed:?}, not Some({index})")]
    ShownValueDoesNotParse {
        /// The value's index.
        index: u16,
        /// How the kind shows it.
        shown: String,
        /// What parsing the shown text gives.
        parsed: Option<u16>,
    },
    /// An axis value that is not a finite number.
    #[error("the axis value of `{value}` is {axis}; it must be a finite number")]
    AxisNotFinite {
        /// The value.
        value: String,
        /// The axis value given.
        axis: f64,
    },
    /// A definition that cannot be written, or does not read back to itself.
    #[error("its definition does not round-trip: {0}")]
    Definition(String),
}

impl CustomComponent {
    /// Checks `component` (see the module documentation) and wraps it.
    pub fn new<K: ComponentKind>(component: K) -> Result<Self, KindError> {
        let fail = |problem| KindError {
            kind: K::KIND.to_owned(),
            problem,
        };
        let definition = definition_of(&component).map_err(fail)?;
        let reread = K::deserialize(&definition)
            .and_then(|read| serde_json::to_value(&read))
            .map_err(|e| fail(KindProblem::Definition(e.to_string())))?;
        if reread != definition {
            return Err(fail(KindProblem::Definition(format!(
                "{definition} reads back as {reread}"
            ))));
        }
        let len = component.value_count();
        if len == 0 || len > MAX_CUSTOM_VALUES {
            return Err(fail(KindProblem::ValueCount(len)));
        }
        let (similarities, neighbours) =
            check_similarity_and_adjacency(&component).map_err(fail)?;
        let changes = path_lengths(&component, &neighbours).map_err(fail)?;
        check_values(&component).map_err(fail)?;
        let max_changes = changes.iter().copied().max().map_or(0, u32::from);
        Ok(Self {
            inner: Arc::new(Checked {
                kind: K::KIND,
                component: Box::new(component),
                definition,
                len,
                similarities,
                changes,
                max_changes,
            }),
        })
    }

    /// The kind's name ([`ComponentKind::KIND`]).
    pub fn kind(&self) -> &'static str {
        self.inner.kind
    }

    /// The user's component.
    pub fn component(&self) -> &dyn Component {
        self.inner.component.as_ref()
    }

    /// The definition as text, e.g. `{"count":8,"min":1.0,"ratio":2.0}`.
    pub fn definition_text(&self) -> String {
        self.inner.definition.to_string()
    }

    pub(super) fn definition(&self) -> &serde_json::Value {
        &self.inner.definition
    }

    /// Number of values.
    pub fn value_count(&self) -> usize {
        self.inner.len
    }

    /// Similarity of the values at `a` and `b` (tabled when the kind was checked).
    #[inline]
    pub fn similarity(&self, a: u16, b: u16) -> f64 {
        self.inner.similarities[usize::from(a) * self.inner.len + usize::from(b)]
    }

    /// Number of changes between the values at `a` and `b`: the fewest steps between
    /// adjacent values that lead from one to the other.
    #[inline]
    pub fn changes(&self, a: u16, b: u16) -> u32 {
        u32::from(self.inner.changes[usize::from(a) * self.inner.len + usize::from(b)])
    }

    /// The largest number of changes between two values.
    pub fn max_changes(&self) -> u32 {
        self.inner.max_changes
    }
}

impl PartialEq for CustomComponent {
    /// Same kind, same definition.
    fn eq(&self, other: &Self) -> bool {
        self.kind() == other.kind() && self.definition() == other.definition()
    }
}

impl fmt::Debug for CustomComponent {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("CustomComponent")
            .field("kind", &self.kind())
            .field("definition", self.definition())
            .finish()
    }
}

fn definition_of(component: &impl Serialize) -> Result<serde_json::Value, KindProblem> {
    serde_json::to_value(component).map_err(|e| KindProblem::Definition(e.to_string()))
}

fn shown(component: &dyn Component, index: u16) -> String {
    ValueDisplay { component, index }.to_string()
}

/// Checks every pair's similarity and adjacency; gives the similarity table (row-major)
/// and each value's adjacent values.
fn check_similarity_and_adjacency(
    c: &dyn Component,
) -> Result<(Vec<f64>, Vec<Vec<u16>>), KindProblem> {
    let n = c.value_count() as u16;
    let len = usize::from(n);
    let mut similarities = vec![1.0; len * len];
    let mut neighbours = vec![Vec::new(); len];
    for a in 0..n {
        let itself = c.similarity(a, a);
        if itself != 1.0 {
            return Err(KindProblem::SimilarityNotOneOnDiagonal {
                value: shown(c, a),
                similarity: itself,
            });
        }
        if c.adjacent(a, a) {
            return Err(KindProblem::SelfAdjacent(shown(c, a)));
        }
        for b in a + 1..n {
            let (a_to_b, b_to_a) = (c.similarity(a, b), c.similarity(b, a));
            for (x, y, similarity) in [(a, b, a_to_b), (b, a, b_to_a)] {
                if !(0.0..=1.0).contains(&similarity) {
                    return Err(KindProblem::SimilarityOutOfRange {
                        a: shown(c, x),
                        b: shown(c, y),
                        similarity,
                    });
                }
            }
            if a_to_b != b_to_a {
                return Err(KindProblem::SimilarityAsymmetric {
                    a: shown(c, a),
                    b: shown(c, b),
                    a_to_b,
                    b_to_a,
                });
            }
            let (row_a, row_b) = (usize::from(a) * len, usize::from(b) * len);
            similarities[row_a + usize::from(b)] = a_to_b;
            similarities[row_b + usize::from(a)] = a_to_b;
            match (c.adjacent(a, b), c.adjacent(b, a)) {
                (true, true) => {
                    neighbours[usize::from(a)].push(b);
                    neighbours[usize::from(b)].push(a);
                }
                (false, false) => {}
                (a_to_b, _) => {
                    let (from, to) = if a_to_b { (a, b) } else { (b, a) };
                    return Err(KindProblem::AdjacencyAsymmetric {
                        from: shown(c, from),
                        to: shown(c, to),
                    });
                }
            }
        }
    }
    Ok((similarities, neighbours))
}

/// The number of changes between every pair of values (breadth-first from each value),
/// row-major; every value must be reachable from every other.
fn path_lengths(c: &dyn Component, neighbours: &[Vec<u16>]) -> Result<Vec<u16>, KindProblem> {
    let n = neighbours.len();
    let mut table = vec![u16::MAX; n * n];
    let mut queue = VecDeque::with_capacity(n);
    for from in 0..n {
        let row = &mut table[from * n..(from + 1) * n];
        row[from] = 0;
        queue.push_back(from);
        while let Some(at) = queue.pop_front() {
            let next = row[at] + 1;
            for &to in &neighbours[at] {
                let to = usize::from(to);
                if row[to] == u16::MAX {
                    row[to] = next;
                    queue.push_back(to);
                }
            }
        }
        if let Some(to) = row.iter().position(|&d| d == u16::MAX) {
            return Err(KindProblem::Disconnected {
                from: shown(c, from as u16),
                to: shown(c, to as u16),
            });
        }
    }
    Ok(table)
}

/// Checks that every shown value parses back to its index and axis values are finite.
fn check_values(c: &dyn Component) -> Result<(), KindProblem> {
    for index in 0..c.value_count() as u16 {
        let text = shown(c, index);
        let parsed = c.parse(&text);
        if parsed != Some(index) {
            return Err(KindProblem::ShownValueDoesNotParse {
                index,
                shown: text,
                parsed,
            });
        }
        if let Some(axis) = c.axis_value(index).filter(|a| !a.is_finite()) {
            return Err(KindProblem::AxisNotFinite { value: text, axis });
        }
    }
    Ok(())
}
