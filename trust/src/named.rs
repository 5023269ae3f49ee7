//! Behaviors as JSON objects of component name to real value, e.g.
//! `{"speed": 3.5, "padding": 0.4}`: the form reports and the service protocol show.

use cbr_core::{Behavior, BehaviorSpace};
use serde_json::{Map, Value, json};

/// The behavior's components by name: numbers for numeric grids (rounded to remove binary
/// noise), the shown value (a label, or a custom kind's text) for other kinds, in the
/// space's component order.
pub fn named_behavior(space: &BehaviorSpace, behavior: &Behavior) -> Map<String, Value> {
    space
        .components()
        .iter()
        .zip(behavior.indices())
        .map(|(c, &i)| {
            let value = if c.is_numeric() {
                json!(c.real_value(i))
            } else {
                json!(c.display_value(i).to_string())
            };
            (c.name.clone(), value)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use cbr_core::NamedComponent;

    #[test]
    fn real_units_and_labels() {
        let space = BehaviorSpace::new(vec![
            NamedComponent::numeric("padding", "m", 0.1, 0.1, 20).unwrap(),
            NamedComponent::categorical("planner", &["astar", "rrt"]).unwrap(),
        ])
        .unwrap();
        // Index 2 of the padding grid is 0.1 + 2 x 0.1 = 0.3 (not 0.30000000000000004).
        let named = named_behavior(&space, &Behavior::new(&[2, 1]));
        assert_eq!(
            Value::Object(named).to_string(),
            r#"{"padding":0.3,"planner":"rrt"}"#
        );
    }
}
