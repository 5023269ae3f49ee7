//! Behaviors as JSON objects of component name to real value, e.g.
//! `{"speed": 3.5, "padding": 0.4}`: the form reports and the service protocol show.

use cbr_core::{Behavior, BehaviorSpace, NamedComponent};
use serde_json::{Map, Value, json};

/// The behavior's components by name, in the space's component order: numbers for numeric
/// grids (rounded to remove binary noise) and for a custom kind's values shown as numbers
/// that read back (a log grid's `0.25`), the shown value (a label, a custom kind's text)
/// otherwise.
pub fn named_behavior(space: &BehaviorSpace, behavior: &Behavior) -> Map<String, Value> {
    space
        .components()
        .iter()
        .zip(behavior.indices())
        .map(|(c, &i)| (c.name.clone(), named_value(c, i)))
        .collect()
}

/// Value `i` of component `c` in real units: a number for a numeric component (and for a
/// custom kind's value that is a number and reads back from it), its label otherwise.
pub fn named_value(c: &NamedComponent, i: u16) -> Value {
    let text = c.display_value(i).to_string();
    // A custom kind's value that is a number, and reads back from that number.
    let number = text
        .parse::<f64>()
        .ok()
        .filter(|x| x.is_finite() && c.values.component().parse(&x.to_string()) == Some(i));
    if c.is_numeric() {
        json!(c.real_value(i))
    } else if let Some(number) = number {
        json!(number)
    } else {
        json!(text)
    }
}

/// Every component of `space` with all its values in real units, in the space's order:
/// `[{"name": "speed", "unit": "m/s", "values": [0.5, 1.0, ...]}, ...]`.
pub fn named_space(space: &BehaviorSpace) -> Value {
    space
        .components()
        .iter()
        .map(|c| {
            let values: Vec<Value> = (0..c.len()).map(|i| named_value(c, i as u16)).collect();
            json!({ "name": c.name, "unit": c.unit, "values": values })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

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
