//! Operator models as data: what a simulated operator watches in a run's trace and how it
//! reacts (SPEC section 8). A new operator is a RON file; no code.
//!
//! The operator reads the trace in time order. At its deadline `t_complete` it interrupts
//! with probability `p_deadline` (the paper's `p_alpha`); if it lets the robot go on, it
//! gives up at `give_up_factor x t_complete` and counts the run as failed. On every
//! collision it interrupts with probability `p_collision` (`p_gamma`); it always interrupts
//! a stuck robot; it interrupts when an object is driven past unscanned
//! (`p_missed_object`) or a harmless one is labelled explosive (`p_false_alarm`). A
//! detonation fails the run. Reaching the goal completes it.
//!
//! An operator is read against the causes its scenario declares ([`crate::causes`]):
//! `weights.by_cause` may name only those (quoted, `by_cause: {"detonation": 1.0}`).

use crate::Scenario;
use crate::causes::{COLLISION, DEADLINE, DETONATION, FALSE_ALARM, MISSED_OBJECT, STUCK};
use crate::trace::{EventKind, Trace};
use cbr_core::{FileError, RonError, parse_ron, read_text};
use rand::{Rng, RngCore};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use trust::{DeclaredCause, Judgement, OutcomeWeights, WeightsError};

fn one() -> f64 {
    1.0
}

fn give_up_factor() -> f64 {
    2.0
}

/// A simulated operator.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OperatorModel {
    /// The operator's name (e.g. `speed-focused`).
    pub name: String,
    /// The time the operator allows for the task (s).
    pub t_complete: f64,
    /// Probability of interrupting when `t_complete` passes (`p_alpha`).
    pub p_deadline: f64,
    /// Probability of interrupting on each collision (`p_gamma`).
    pub p_collision: f64,
    /// Probability of interrupting when the robot drives past an object without scanning it.
    #[serde(default = "one")]
    pub p_missed_object: f64,
    /// Probability of interrupting when the robot labels a harmless object explosive.
    #[serde(default = "one")]
    pub p_false_alarm: f64,
    /// The operator gives up at this multiple of `t_complete`: the run fails (cause
    /// deadline).
    #[serde(default = "give_up_factor")]
    pub give_up_factor: f64,
    /// Outcome weights.
    #[serde(default)]
    pub weights: OutcomeWeights,
}

/// Why an operator file cannot be used.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OperatorError {
    /// The file could not be read.
    #[error(transparent)]
    Io(#[from] FileError),
    /// The file is not a valid operator in RON.
    #[error(transparent)]
    Syntax(#[from] RonError),
    /// A weight is out of range, or `weights.by_cause` names a cause the scenario does not
    /// declare.
    #[error("{file}: operator `{operator}`: {reason}")]
    Weights {
        /// The file.
        file: PathBuf,
        /// The operator's name.
        operator: String,
        /// What is wrong with the weights.
        reason: WeightsError,
    },
    /// A value is out of its allowed range.
    #[error("{file}: operator `{operator}`: `{field}` must be {allowed}, got {value}")]
    Range {
        /// The file.
        file: PathBuf,
        /// The operator's name.
        operator: String,
        /// The field, e.g. `p_collision` or `weights.by_cause.detonation`.
        field: String,
        /// The allowed range.
        allowed: &'static str,
        /// The value given.
        value: f64,
    },
}

impl OperatorModel {
    /// Parses and validates an operator for a scenario that declares `causes` (its
    /// `weights.by_cause` may name only those; their declared default weights fill the
    /// causes it leaves out); `origin` names the source in errors.
    pub fn from_ron(
        text: &str,
        origin: &Path,
        causes: &[DeclaredCause],
    ) -> Result<Self, OperatorError> {
        let mut model: Self = parse_ron(text, origin)?;
        model.validate(origin)?;
        model
            .weights
            .check(causes)
            .map_err(|reason| OperatorError::Weights {
                file: origin.to_owned(),
                operator: model.name.clone(),
                reason,
            })?;
        Ok(model)
    }

    /// Reads, parses and validates an operator file for a scenario that declares `causes`.
    pub fn load(path: &Path, causes: &[DeclaredCause]) -> Result<Self, OperatorError> {
        let text = read_text(path)?;
        Self::from_ron(&text, path, causes)
    }

    fn validate(&self, origin: &Path) -> Result<(), OperatorError> {
        let fail = |field: String, allowed, value| OperatorError::Range {
            file: origin.to_owned(),
            operator: self.name.clone(),
            field,
            allowed,
            value,
        };
        let probabilities = [
            ("p_deadline", self.p_deadline),
            ("p_collision", self.p_collision),
            ("p_missed_object", self.p_missed_object),
            ("p_false_alarm", self.p_false_alarm),
        ];
        for (field, value) in probabilities {
            if !(0.0..=1.0).contains(&value) {
                return Err(fail(field.into(), "a probability in [0, 1]", value));
            }
        }
        if !(self.t_complete.is_finite() && self.t_complete > 0.0) {
            return Err(fail(
                "t_complete".into(),
                "a finite number > 0",
                self.t_complete,
            ));
        }
        if !(self.give_up_factor.is_finite() && self.give_up_factor >= 1.0) {
            return Err(fail(
                "give_up_factor".into(),
                "a finite number >= 1",
                self.give_up_factor,
            ));
        }
        Ok(())
    }

    /// Watches a run and decides how it ends, and why (the truth). Random reactions draw
    /// from `rng`.
    pub fn judge(&self, trace: &Trace, rng: &mut dyn RngCore) -> Judgement {
        let give_up = self.t_complete * self.give_up_factor;
        let interrupt = |cause, t| Judgement::interrupted(self.weights.of(cause), cause, t);
        let mut deadline_seen = false;
        let mut react = |p: f64| rng.random::<f64>() < p;
        for event in &trace.events {
            if !deadline_seen && event.t > self.t_complete {
                deadline_seen = true;
                if react(self.p_deadline) {
                    return interrupt(DEADLINE, self.t_complete);
                }
            }
            if event.t > give_up {
                return Judgement::failed(self.weights.of(DEADLINE), DEADLINE, give_up);
            }
            match event.kind {
                EventKind::Collision { .. } if react(self.p_collision) => {
                    return interrupt(COLLISION, event.t);
                }
                EventKind::Stuck => return interrupt(STUCK, event.t),
                EventKind::MissedObject { .. } if react(self.p_missed_object) => {
                    return interrupt(MISSED_OBJECT, event.t);
                }
                EventKind::Labelled {
                    explosive: false,
                    labelled_explosive: true,
                    ..
                } if react(self.p_false_alarm) => {
                    return interrupt(FALSE_ALARM, event.t);
                }
                EventKind::Detonation { .. } => {
                    return Judgement::failed(self.weights.of(DETONATION), DETONATION, event.t);
                }
                EventKind::Arrived { .. } => {
                    return Judgement::completed(self.weights.completed, event.t);
                }
                _ => {}
            }
        }
        // A trace always ends with an arrival or a stuck robot; an empty one means the
        // robot never started.
        interrupt(STUCK, 0.0)
    }
}

/// The operators of SPEC section 8 for `scenario`, from the RON files shipped with the crate.
pub fn builtin_operators(scenario: Scenario) -> Vec<OperatorModel> {
    let sources: &[(&str, &str)] = match scenario {
        Scenario::Movement => &[
            (
                "operators/movement/speed-focused.ron",
                include_str!("../operators/movement/speed-focused.ron"),
            ),
            (
                "operators/movement/safety-focused.ron",
                include_str!("../operators/movement/safety-focused.ron"),
            ),
            (
                "operators/movement/balanced.ron",
                include_str!("../operators/movement/balanced.ron"),
            ),
        ],
        Scenario::Patrol => &[
            (
                "operators/patrol/speed-focused.ron",
                include_str!("../operators/patrol/speed-focused.ron"),
            ),
            (
                "operators/patrol/detection-focused.ron",
                include_str!("../operators/patrol/detection-focused.ron"),
            ),
        ],
    };
    sources
        .iter()
        .map(|(path, text)| {
            OperatorModel::from_ron(text, Path::new(path), scenario.causes())
                .expect("shipped operators are valid")
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Vec2;
    use proptest::prelude::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
    use trust::OutcomeKind;

    fn trace(events: &[(f64, EventKind)]) -> Trace {
        let mut t = Trace::default();
        for (time, kind) in events {
            t.push(*time, *kind);
        }
        t
    }

    fn operator(p_deadline: f64, p_collision: f64) -> OperatorModel {
        OperatorModel {
            name: "test".into(),
            t_complete: 15.0,
            p_deadline,
            p_collision,
            p_missed_object: 1.0,
            p_false_alarm: 1.0,
            give_up_factor: 2.0,
            weights: OutcomeWeights::default(),
        }
    }

    const HIT: EventKind = EventKind::Collision {
        at: Vec2::new(0.0, 0.0),
    };
    const ARRIVED: EventKind = EventKind::Arrived {
        at: Vec2::new(0.0, 0.0),
    };

    #[test]
    fn builtin_operators_have_the_spec_names_and_numbers() {
        let movement = builtin_operators(Scenario::Movement);
        let names: Vec<&str> = movement.iter().map(|o| o.name.as_str()).collect();
        assert_eq!(names, ["speed-focused", "safety-focused", "balanced"]);
        assert_eq!(movement[1].p_collision, 0.95);
        assert_eq!(movement[1].weights.of(COLLISION), 1.0);
        let patrol = builtin_operators(Scenario::Patrol);
        let names: Vec<&str> = patrol.iter().map(|o| o.name.as_str()).collect();
        assert_eq!(names, ["speed-focused", "detection-focused"]);
        assert_eq!(patrol[0].t_complete, 120.0);
        assert_eq!(patrol[0].weights.of(DETONATION), 1.0);
        assert!((patrol[0].weights.of(COLLISION) - 1.0 / 3.0).abs() < 1e-15);
        assert!((patrol[0].weights.completed - 1.0 / 3.0).abs() < 1e-15);
    }

    #[test]
    fn a_clean_run_in_time_completes() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let outcome = operator(1.0, 1.0).judge(&trace(&[(12.5, ARRIVED)]), &mut rng);
        assert_eq!(outcome, Judgement::completed(1.0, 12.5));
    }

    #[test]
    fn certain_reactions() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let late = trace(&[(4.0, HIT), (40.0, ARRIVED)]);
        // Interrupted on the collision, at its time.
        let o = operator(1.0, 1.0).judge(&late, &mut rng);
        assert_eq!(o, Judgement::interrupted(1.0, COLLISION, 4.0));
        // Interrupted at the deadline.
        let o = operator(1.0, 0.0).judge(&late, &mut rng);
        assert_eq!(o, Judgement::interrupted(1.0, DEADLINE, 15.0));
        // Let go on, then given up on at twice the deadline.
        let o = operator(0.0, 0.0).judge(&late, &mut rng);
        assert_eq!(o, Judgement::failed(1.0, DEADLINE, 30.0));
    }

    #[test]
    fn patrol_events() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let op = &builtin_operators(Scenario::Patrol)[1];
        let false_alarm = EventKind::Labelled {
            object: 0,
            explosive: false,
            labelled_explosive: true,
        };
        let o = op.judge(&trace(&[(20.0, false_alarm), (60.0, ARRIVED)]), &mut rng);
        assert_eq!(o.truth, Some(FALSE_ALARM));
        assert_eq!(o.outcome.kind, OutcomeKind::Interrupted);
        let boom = EventKind::Detonation { object: 2 };
        let o = op.judge(&trace(&[(50.0, boom), (60.0, ARRIVED)]), &mut rng);
        assert_eq!(o, Judgement::failed(1.0, DETONATION, 50.0));
        let missed = EventKind::MissedObject { object: 1 };
        let o = op.judge(&trace(&[(10.0, missed), (60.0, ARRIVED)]), &mut rng);
        assert_eq!(o.truth, Some(MISSED_OBJECT));
    }

    #[test]
    fn errors_name_the_place_and_the_field() {
        let origin = Path::new("ops/x.ron");
        let read = |text: &str| {
            OperatorModel::from_ron(text, origin, Scenario::Movement.causes())
                .unwrap_err()
                .to_string()
        };
        let err = read("(name: \"x\",\n t_complete: 15.0,\n p_deadlin: 1.0)");
        assert!(err.starts_with("ops/x.ron:3:"), "{err}");
        let err = read("(name: \"x\", t_complete: 15.0, p_deadline: 1.5, p_collision: 0.1)");
        assert!(
            err.contains("`p_deadline` must be a probability in [0, 1], got 1.5"),
            "{err}"
        );
        let err = read("(name: \"x\", t_complete: 0.0, p_deadline: 1.0, p_collision: 0.1)");
        assert!(err.contains("`t_complete`"), "{err}");
        let err = read(
            "(name: \"x\", t_complete: 9.0, p_deadline: 1.0, p_collision: 0.1,
                     weights: (by_cause: { \"collision\": -2.0 }))",
        );
        assert!(
            err.contains("`weights.by_cause.collision` must be a finite number >= 0"),
            "{err}"
        );
        // A cause name that breaks the rule is named where it is written.
        let err = read(
            "(name: \"x\", t_complete: 9.0, p_deadline: 1.0, p_collision: 0.1,
                     weights: (by_cause: { \"Collision\": 2.0 }))",
        );
        assert!(err.starts_with("ops/x.ron:2:"), "{err}");
        assert!(err.contains("cause `Collision` has 'C' at byte 0"), "{err}");
    }

    #[test]
    fn an_operator_names_only_its_scenarios_causes() {
        let text = "(name: \"bomb-averse\", t_complete: 9.0, p_deadline: 1.0, p_collision: 0.1,
                     weights: (by_cause: { \"detonation\": 3.0 }))";
        let origin = Path::new("ops/bomb-averse.ron");
        let err = OperatorModel::from_ron(text, origin, Scenario::Movement.causes())
            .unwrap_err()
            .to_string();
        assert_eq!(
            err,
            "ops/bomb-averse.ron: operator `bomb-averse`: `weights.by_cause`: cause `detonation` is not declared (declared: deadline, collision, stuck)"
        );
        let op = OperatorModel::from_ron(text, origin, Scenario::Patrol.causes()).unwrap();
        assert_eq!(op.weights.of(DETONATION), 3.0);
    }

    #[test]
    fn a_declared_default_weight_comes_between_by_cause_and_default() {
        // A domain declaring `collision` at 0.5 and `stuck` at 0.25; the operator sets
        // `stuck` itself and leaves `collision` and `deadline` out.
        let causes = [
            DeclaredCause::new(DEADLINE),
            DeclaredCause::with_default_weight(COLLISION, 0.5).unwrap(),
            DeclaredCause::with_default_weight(STUCK, 0.25).unwrap(),
        ];
        let text = "(name: \"x\", t_complete: 9.0, p_deadline: 1.0, p_collision: 0.1,
                     weights: (default: 2.0, by_cause: { \"stuck\": 4.0 }))";
        let op = OperatorModel::from_ron(text, Path::new("x.ron"), &causes).unwrap();
        assert_eq!(op.weights.of(STUCK), 4.0);
        assert_eq!(op.weights.of(COLLISION), 0.5);
        assert_eq!(op.weights.of(DEADLINE), 2.0);
    }

    proptest! {
        #[test]
        fn p_collision_zero_never_interrupts_for_a_collision(
            seed: u64, hits in proptest::collection::vec(0.0f64..40.0, 0..20), p_deadline in 0.0f64..=1.0,
        ) {
            let mut events: Vec<(f64, EventKind)> = hits.iter().map(|&t| (t, HIT)).collect();
            events.push((50.0, ARRIVED));
            let mut t = trace(&events);
            t.sort();
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let o = operator(p_deadline, 0.0).judge(&t, &mut rng);
            prop_assert_ne!(o.truth, Some(COLLISION));
        }
    }
}
