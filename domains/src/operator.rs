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
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use trust::{Cause, DeclaredCause, Outcome, UndeclaredCause, find_declared};

/// How much each outcome weighs in the trust estimate.
///
/// The weight of a failure or interruption with a cause is the operator's `by_cause`
/// entry for it; without one, the default weight the scenario declares for the cause
/// (filled into `by_cause` when the operator is read, [`OperatorModel::from_ron`]);
/// without that, the operator's `default`. The UGV causes declare no default weight, so
/// for them `by_cause`, then `default`, decide.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Weights {
    /// Weight of a completion.
    #[serde(default = "one")]
    pub completed: f64,
    /// Weight of a failure or interruption whose cause is not listed in `by_cause`.
    #[serde(default = "one")]
    pub default: f64,
    /// Weights of failures and interruptions by cause (causes the scenario declares).
    #[serde(default)]
    pub by_cause: BTreeMap<Cause, f64>,
}

impl Default for Weights {
    fn default() -> Self {
        Self {
            completed: 1.0,
            default: 1.0,
            by_cause: BTreeMap::new(),
        }
    }
}

impl Weights {
    /// Every weight times `factor`.
    pub fn scaled(&self, factor: f64) -> Self {
        Self {
            completed: self.completed * factor,
            default: self.default * factor,
            by_cause: self
                .by_cause
                .iter()
                .map(|(&cause, &w)| (cause, w * factor))
                .collect(),
        }
    }

    /// The weight of a failure or interruption with `cause`.
    pub fn of(&self, cause: Cause) -> f64 {
        self.by_cause.get(&cause).copied().unwrap_or(self.default)
    }
}

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
    pub weights: Weights,
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
    /// The name is neither a built-in operator of the scenario nor an existing file.
    #[error("no operator `{name}` for {scenario}: built-in ones are {known}; or give a RON file")]
    Unknown {
        /// The name given.
        name: String,
        /// The scenario.
        scenario: Scenario,
        /// The built-in names.
        known: String,
    },
    /// `weights.by_cause` names a cause the scenario does not declare.
    #[error("{file}: operator `{operator}`: `weights.by_cause`: {reason}")]
    UndeclaredCause {
        /// The file.
        file: PathBuf,
        /// The operator's name.
        operator: String,
        /// The cause and the declared ones (boxed: a rare error should not make every
        /// result that may carry one larger).
        reason: Box<UndeclaredCause>,
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
        model.check_causes(origin, causes)?;
        for declared in causes {
            if let Some(weight) = declared.default_weight {
                model
                    .weights
                    .by_cause
                    .entry(declared.name)
                    .or_insert(weight);
            }
        }
        Ok(model)
    }

    /// Reads, parses and validates an operator file for a scenario that declares `causes`.
    pub fn load(path: &Path, causes: &[DeclaredCause]) -> Result<Self, OperatorError> {
        let text = read_text(path)?;
        Self::from_ron(&text, path, causes)
    }

    fn check_causes(&self, origin: &Path, causes: &[DeclaredCause]) -> Result<(), OperatorError> {
        for &cause in self.weights.by_cause.keys() {
            find_declared(causes, cause).map_err(|reason| OperatorError::UndeclaredCause {
                file: origin.to_owned(),
                operator: self.name.clone(),
                reason: Box::new(reason),
            })?;
        }
        Ok(())
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
        let weights = [
            ("weights.completed".to_owned(), self.weights.completed),
            ("weights.default".to_owned(), self.weights.default),
        ]
        .into_iter()
        .chain(
            self.weights
                .by_cause
                .iter()
                .map(|(c, w)| (format!("weights.by_cause.{c}"), *w)),
        );
        for (field, value) in weights {
            if !(value.is_finite() && value >= 0.0) {
                return Err(fail(field, "a finite number >= 0", value));
            }
        }
        Ok(())
    }

    /// Watches a run and decides how it ends. Random reactions draw from `rng`.
    pub fn judge(&self, trace: &Trace, rng: &mut dyn RngCore) -> Outcome {
        let give_up = self.t_complete * self.give_up_factor;
        let interrupt = |cause, t| Outcome::interrupted(self.weights.of(cause), cause, t);
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
                return Outcome::failed(self.weights.of(DEADLINE), DEADLINE, give_up);
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
                    return Outcome::failed(self.weights.of(DETONATION), DETONATION, event.t);
                }
                EventKind::Arrived { .. } => {
                    return Outcome::completed(self.weights.completed, event.t);
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

/// The operator named `name_or_path`: a built-in operator of `scenario` by name, or else
/// an operator RON file at that path.
pub fn find_operator(
    scenario: Scenario,
    name_or_path: &str,
) -> Result<OperatorModel, OperatorError> {
    let builtin = builtin_operators(scenario);
    if let Some(op) = builtin.iter().find(|o| o.name == name_or_path) {
        return Ok(op.clone());
    }
    let path = Path::new(name_or_path);
    if path.exists() {
        return OperatorModel::load(path, scenario.causes());
    }
    Err(OperatorError::Unknown {
        name: name_or_path.to_owned(),
        scenario,
        known: builtin
            .iter()
            .map(|o| o.name.as_str())
            .collect::<Vec<_>>()
            .join(", "),
    })
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
            weights: Weights::default(),
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
        assert_eq!(outcome, Outcome::completed(1.0, 12.5));
    }

    #[test]
    fn certain_reactions() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let late = trace(&[(4.0, HIT), (40.0, ARRIVED)]);
        // Interrupted on the collision, at its time.
        let o = operator(1.0, 1.0).judge(&late, &mut rng);
        assert_eq!(o, Outcome::interrupted(1.0, COLLISION, 4.0));
        // Interrupted at the deadline.
        let o = operator(1.0, 0.0).judge(&late, &mut rng);
        assert_eq!(o, Outcome::interrupted(1.0, DEADLINE, 15.0));
        // Let go on, then given up on at twice the deadline.
        let o = operator(0.0, 0.0).judge(&late, &mut rng);
        assert_eq!(o, Outcome::failed(1.0, DEADLINE, 30.0));
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
        assert_eq!(o.cause, Some(FALSE_ALARM));
        assert_eq!(o.kind, OutcomeKind::Interrupted);
        let boom = EventKind::Detonation { object: 2 };
        let o = op.judge(&trace(&[(50.0, boom), (60.0, ARRIVED)]), &mut rng);
        assert_eq!(o, Outcome::failed(1.0, DETONATION, 50.0));
        let missed = EventKind::MissedObject { object: 1 };
        let o = op.judge(&trace(&[(10.0, missed), (60.0, ARRIVED)]), &mut rng);
        assert_eq!(o.cause, Some(MISSED_OBJECT));
    }

    #[test]
    fn operators_are_found_by_name_or_file() {
        let op = find_operator(Scenario::Patrol, "detection-focused").unwrap();
        assert_eq!(op.p_deadline, 0.05);
        let err = find_operator(Scenario::Movement, "detection-focused").unwrap_err();
        assert!(
            err.to_string()
                .contains("speed-focused, safety-focused, balanced"),
            "{err}"
        );
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
            prop_assert_ne!(o.cause, Some(COLLISION));
        }
    }
}
