//! Writing the session's answers: one JSON object each, with an `ok` field naming what it
//! is or an `error` field saying what went wrong, and behaviors in real units.

use cbr_core::{Behavior, BehaviorSpace};
use serde_json::{Value, json};
use trust::named::named_behavior;
use trust::{EpisodeReport, Evaluated};

/// An error reply: `{"error": message}`.
pub fn error(message: impl std::fmt::Display) -> Value {
    json!({ "error": message.to_string() })
}

/// A behavior in real units: `{"speed": 3.5, "padding": 0.4}`; categorical components give
/// their label.
pub fn behavior(space: &BehaviorSpace, behavior: &Behavior) -> Value {
    Value::Object(named_behavior(space, behavior))
}

/// Evaluated pairs: `[{"behavior": {...}, "time": 12.5}, ...]`.
pub fn evaluated(space: &BehaviorSpace, pairs: &[Evaluated]) -> Value {
    pairs
        .iter()
        .map(|e| json!({ "behavior": behavior(space, &e.behavior), "time": e.time }))
        .collect()
}

/// The summary of a finished episode, under the `ok` name `kind`.
pub fn episode_end(
    kind: &str,
    space: &BehaviorSpace,
    report: &EpisodeReport,
    cases: usize,
) -> Value {
    json!({
        "ok": kind,
        "behavior": behavior(space, &report.settled),
        "trustworthy": report.found_trustworthy,
        "behaviors_evaluated": report.behaviors_evaluated,
        "commands": report.commands,
        "searched": report.searched,
        "reused": report.reused,
        "retained": report.retained.map(|id| id.0),
        "cases": cases,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use cbr_core::Component;

    #[test]
    fn behaviors_are_written_in_real_units() {
        let space = BehaviorSpace::new(vec![
            Component::numeric("padding", "m", 0.1, 0.1, 20).unwrap(),
            Component::categorical("planner", &["astar", "rrt"]).unwrap(),
        ])
        .unwrap();
        let b = Behavior::new(&[2, 1]);
        assert_eq!(
            behavior(&space, &b).to_string(),
            r#"{"padding":0.3,"planner":"rrt"}"#
        );
    }
}
