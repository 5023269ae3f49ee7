//! Random behavior spaces for property tests (feature `testing`): the one generator every
//! crate's property tests and conformance kits draw spaces from.
//!
//! [`behavior_spaces`] draws spaces of the [`SpaceShape`] asked for: how many components,
//! how many values each, whether categorical components may carry a similarity table,
//! and whether component weights are drawn (some of them 0, never all).

use crate::{BehaviorSpace, Categorical, NamedComponent, Values};
use proptest::prelude::*;
use std::ops::RangeInclusive;

/// What spaces [`behavior_spaces`] draws.
#[derive(Clone, Debug, PartialEq)]
pub struct SpaceShape {
    /// How many components (at least 1).
    pub components: RangeInclusive<usize>,
    /// How many values a component has (at least 1).
    pub values: RangeInclusive<u16>,
    /// Whether a categorical component may carry a similarity table (symmetric, 1 on the
    /// diagonal, other entries in `[0, 1]`).
    pub similarity_tables: bool,
    /// Whether weights are drawn (each 1, 0 or in `[0.1, 3)`; not all 0); otherwise equal.
    pub weights: bool,
}

impl SpaceShape {
    /// One to three numeric or plain categorical components of one to five values, equal
    /// weights.
    pub fn small() -> Self {
        Self {
            components: 1..=3,
            values: 1..=5,
            similarity_tables: false,
            weights: false,
        }
    }

    /// `small` with similarity tables and drawn weights.
    pub fn mixed() -> Self {
        Self {
            similarity_tables: true,
            weights: true,
            ..Self::small()
        }
    }
}

/// The largest number of values a tabled categorical component gets (its table is drawn
/// whole).
const MAX_TABLED_VALUES: usize = 6;

/// Random spaces of `shape`. Numeric components are grids from 0 in steps of 0.5;
/// categorical ones are labelled `v0, v1, ...`; components are named `c0, c1, ...`.
pub fn behavior_spaces(shape: SpaceShape) -> impl Strategy<Value = BehaviorSpace> {
    let kinds = if shape.similarity_tables { 3u8 } else { 2 };
    let table_entries = MAX_TABLED_VALUES * MAX_TABLED_VALUES;
    let component = (
        shape.values.clone(),
        0..kinds,
        prop::collection::vec(0.0f64..=1.0, table_entries),
    );
    let most = *shape.components.end();
    let weight = prop_oneof![Just(1.0), Just(0.0), 0.1f64..3.0];
    (
        prop::collection::vec(component, shape.components.clone()),
        prop::collection::vec(weight, most),
    )
        .prop_map(move |(specs, weights)| {
            let components: Vec<NamedComponent> = specs
                .iter()
                .enumerate()
                .map(|(k, (n, kind, table))| component_of(k, *n, *kind, table))
                .collect();
            let weights = shape.weights.then(|| {
                let mut w = weights[..components.len()].to_vec();
                if w.iter().all(|&x| x == 0.0) {
                    w[0] = 1.0;
                }
                w
            });
            BehaviorSpace::with_weights(components, weights).expect("a valid space")
        })
}

/// Component `k`: numeric (`kind` 0), plain categorical (1) or categorical with a table
/// read from `table` (2, at most [`MAX_TABLED_VALUES`] values).
fn component_of(k: usize, n: u16, kind: u8, table: &[f64]) -> NamedComponent {
    let name = format!("c{k}");
    let labels = |n: usize| (0..n).map(|i| format!("v{i}")).collect::<Vec<_>>();
    match kind {
        0 => NamedComponent::numeric(&name, "", 0.0, 0.5, n).expect("a valid grid"),
        1 => NamedComponent {
            name,
            unit: String::new(),
            values: Values::Categorical(Categorical::new(labels(usize::from(n)))),
        },
        _ => {
            let n = usize::from(n).min(MAX_TABLED_VALUES);
            let similarity = (0..n)
                .map(|i| {
                    (0..n)
                        .map(|j| {
                            if i == j {
                                1.0
                            } else {
                                table[i.min(j) * MAX_TABLED_VALUES + i.max(j)]
                            }
                        })
                        .collect()
                })
                .collect();
            NamedComponent {
                name,
                unit: String::new(),
                values: Values::Categorical(Categorical {
                    labels: labels(n),
                    similarity: Some(similarity),
                }),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    proptest! {
        #[test]
        fn spaces_have_the_shape_asked_for(space in behavior_spaces(SpaceShape::mixed())) {
            prop_assert!((1..=3).contains(&space.components().len()));
            for c in space.components() {
                prop_assert!((1..=5).contains(&c.len()));
            }
        }
    }
}
