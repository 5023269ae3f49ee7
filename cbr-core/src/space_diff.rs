//! [`BehaviorSpace::first_difference`]: whether two behavior spaces are the same, and if
//! not, the first thing that differs, in words.
//!
//! Behaviors are value indices, so a behavior recorded in one space means something else in
//! a space of the same shape whose values differ (an edited grid step, reordered labels).
//! Whoever keeps behaviors across runs compares the space they were recorded in with the
//! space in use, and names the first difference so the user knows what changed.

use crate::behavior::BehaviorSpace;
use crate::component::{Categorical, NamedComponent, Values};
use std::fmt;

/// The first difference between two behavior spaces: `what` differs, being `this` in the
/// space asked and `other` in the space compared with.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SpaceDifference {
    /// What differs, e.g. `component 2 (scan_time): step`.
    pub what: String,
    /// Its value in the space asked.
    pub this: String,
    /// Its value in the other space.
    pub other: String,
}

impl fmt::Display for SpaceDifference {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} {} vs {}", self.what, self.this, self.other)
    }
}

impl BehaviorSpace {
    /// The first difference between this space and `other` (component count, then each
    /// component in order: name, unit, kind, grid or labels, similarity table, or a custom
    /// kind's name and definition; then the weights), or `None` when the two are the same
    /// space.
    pub fn first_difference(&self, other: &BehaviorSpace) -> Option<SpaceDifference> {
        let (ours, theirs) = (self.components(), other.components());
        if ours.len() != theirs.len() {
            return Some(difference("number of components", ours.len(), theirs.len()));
        }
        for (k, (a, b)) in ours.iter().zip(theirs).enumerate() {
            if a.name != b.name {
                return Some(difference(
                    &format!("component {k}: name"),
                    format_args!("`{}`", a.name),
                    format_args!("`{}`", b.name),
                ));
            }
            if let Some(mut d) = component_difference(a, b) {
                d.what = format!("component {k} ({}): {}", a.name, d.what);
                return Some(d);
            }
        }
        let weights = self.weights().iter().zip(other.weights()).enumerate();
        for (k, (a, b)) in weights {
            if a != b {
                return Some(difference(
                    &format!("weight of component {k} ({})", ours[k].name),
                    a,
                    b,
                ));
            }
        }
        None
    }
}

fn difference(what: &str, this: impl fmt::Display, other: impl fmt::Display) -> SpaceDifference {
    SpaceDifference {
        what: what.to_owned(),
        this: this.to_string(),
        other: other.to_string(),
    }
}

/// The first difference between two components of the same name.
fn component_difference(a: &NamedComponent, b: &NamedComponent) -> Option<SpaceDifference> {
    if a.unit != b.unit {
        return Some(difference(
            "unit",
            format_args!("`{}`", a.unit),
            format_args!("`{}`", b.unit),
        ));
    }
    match (&a.values, &b.values) {
        (Values::Numeric(this), Values::Numeric(other)) => {
            if this.min != other.min {
                Some(difference("min", this.min, other.min))
            } else if this.step != other.step {
                Some(difference("step", this.step, other.step))
            } else if this.count != other.count {
                Some(difference("count", this.count, other.count))
            } else {
                None
            }
        }
        (Values::Categorical(this), Values::Categorical(other)) => {
            categorical_difference(this, other)
        }
        (Values::Custom(this), Values::Custom(other)) => {
            if this.kind() != other.kind() {
                Some(difference(
                    "kind",
                    format_args!("`{}`", this.kind()),
                    format_args!("`{}`", other.kind()),
                ))
            } else {
                (this != other).then(|| {
                    difference(
                        "definition",
                        this.definition_text(),
                        other.definition_text(),
                    )
                })
            }
        }
        (this, other) => Some(difference("values", this.kind_name(), other.kind_name())),
    }
}

fn categorical_difference(this: &Categorical, other: &Categorical) -> Option<SpaceDifference> {
    let (labels, labels_b) = (&this.labels, &other.labels);
    if labels.len() != labels_b.len() {
        return Some(difference("number of labels", labels.len(), labels_b.len()));
    }
    if let Some(k) = (0..labels.len()).find(|&k| labels[k] != labels_b[k]) {
        return Some(difference(
            &format!("label {k}"),
            format_args!("`{}`", labels[k]),
            format_args!("`{}`", labels_b[k]),
        ));
    }
    (this.similarity != other.similarity).then(|| {
        let shown = |table: &Option<Vec<Vec<f64>>>| match table {
            Some(rows) => format!("{rows:?}"),
            None => "none (1 for equal labels, else 0)".to_owned(),
        };
        difference(
            "similarity table",
            shown(&this.similarity),
            shown(&other.similarity),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn space(scan_step: f64, labels: &[&str], weights: Option<Vec<f64>>) -> BehaviorSpace {
        BehaviorSpace::with_weights(
            vec![
                NamedComponent::numeric("speed", "m/s", 0.5, 0.5, 20).unwrap(),
                NamedComponent::numeric("padding", "m", 0.1, 0.1, 20).unwrap(),
                NamedComponent::numeric("scan_time", "s", 0.5, scan_step, 20).unwrap(),
                NamedComponent::categorical("planner", labels).unwrap(),
            ],
            weights,
        )
        .unwrap()
    }

    fn shown(a: &BehaviorSpace, b: &BehaviorSpace) -> String {
        let d = a.first_difference(b).expect("the spaces differ");
        format!("{}: {} / {}", d.what, d.this, d.other)
    }

    #[test]
    fn a_space_equals_itself() {
        let a = space(0.5, &["astar", "rrt"], None);
        assert_eq!(a.first_difference(&a.clone()), None);
    }

    #[test]
    fn an_edited_grid_step_is_named_with_both_values() {
        let a = space(0.5, &["astar", "rrt"], None);
        let b = space(0.25, &["astar", "rrt"], None);
        let d = a.first_difference(&b).unwrap();
        assert_eq!(d.what, "component 2 (scan_time): step");
        assert_eq!((d.this.as_str(), d.other.as_str()), ("0.5", "0.25"));
        assert_eq!(d.to_string(), "component 2 (scan_time): step 0.5 vs 0.25");
    }

    #[test]
    fn labels_kinds_counts_and_weights_are_named() {
        let a = space(0.5, &["astar", "rrt"], None);
        let mut units = a.components().to_vec();
        units[0].unit = "km/h".into();
        let units = BehaviorSpace::new(units).unwrap();
        assert_eq!(
            shown(&a, &units),
            "component 0 (speed): unit: `m/s` / `km/h`"
        );
        assert_eq!(
            shown(&a, &space(0.5, &["rrt", "astar"], None)),
            "component 3 (planner): label 0: `astar` / `rrt`"
        );
        assert_eq!(
            shown(&a, &space(0.5, &["astar", "rrt", "prm"], None)),
            "component 3 (planner): number of labels: 2 / 3"
        );
        assert_eq!(
            shown(
                &a,
                &space(0.5, &["astar", "rrt"], Some(vec![1.0, 2.0, 1.0, 1.0]))
            ),
            "weight of component 1 (padding): 1 / 2"
        );
        let fewer = BehaviorSpace::new(a.components()[..2].to_vec()).unwrap();
        assert_eq!(shown(&a, &fewer), "number of components: 4 / 2");
        let mut renamed = a.components().to_vec();
        renamed[1].name = "clearance".into();
        let renamed = BehaviorSpace::new(renamed).unwrap();
        assert_eq!(
            shown(&a, &renamed),
            "component 1: name: `padding` / `clearance`"
        );
        let mut kinds = a.components().to_vec();
        kinds[3] = NamedComponent::numeric("planner", "", 0.0, 1.0, 2).unwrap();
        let kinds = BehaviorSpace::new(kinds).unwrap();
        assert_eq!(
            shown(&a, &kinds),
            "component 3 (planner): values: categorical / numeric"
        );
    }
}
