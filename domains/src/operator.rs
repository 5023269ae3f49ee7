//! Operator models as data: what a simulated operator watches in a run's trace and how it
//! reacts (docs/model.md#the-operators). A new operator is a RON file; no code.
//!
//! The operator reads the trace in time order. At its deadline `t_complete` it interrupts
//! with probability `p_deadline` (the paper's `p_alpha`); if it lets the robot go on, it
//! gives up at `give_up_factor x t_complete` and counts the run as failed. On every
//! collision it interrupts with probability `p_collision` (`p_gamma`); it always interrupts
//! a stuck robot; it interrupts when an object is driven past unscanned
//! (`p_missed_object`) or a harmless one is labelled explosive (`p_false_alarm`). A
//! detonation fails the run. Reaching the goal completes it.
//!
//! Three further preferences, each off unless the file turns it on (an operator without
//! them judges, and draws random numbers, exactly as before they existed):
//! - `comfort`: interrupts (probability `p`) when the robot passes a standing person
//!   closer than `distance` (body to body) faster than `speed` (cause
//!   `too-fast-near-people`); with `expected_too`, also where people are expected to stand,
//!   occupied or not;
//! - `clearance`: interrupts (probability `p`) when the robot's body passes closer than
//!   `gap` to anything without touching it, at the run's closest pass (cause `too-close`);
//! - `scan_standard`: interrupts (probability `p`) when a scan was made from farther than
//!   `max_distance` or lasted less than `min_time` (cause `poor-scan`; patrol).
//!
//! And `contexts`, off unless the file states it: how the preferences change with the
//! robot's context ([`ContextPreferences`]: `t_complete`, `p_deadline`, `p_collision`,
//! `comfort` and `clearance` replaced where its `when` holds;
//! docs/simulation.md#context).
//!
//! An operator is read against the causes its scenario declares ([`crate::causes`]) by
//! the lab's loader ([`lab::contract::operator_file`]): `weights.by_cause` may name only those
//! (quoted, `by_cause: {"detonation": 1.0}`), and of those only the causes the robot
//! perceives itself ([`crate::causes::PERCEIVED`]); the UGV's own rule refuses a
//! preference whose cause the scenario does not declare ([`UndeclaredPreference`]). An
//! operator's attention scales its reactions through [`lab::contract::attention::Attending`], and its
//! deadline and giving up are the lab's [`Patience`](lab::contract::patience::Patience).

use crate::Scenario;
use crate::causes::{
    COLLISION, DEADLINE, DETONATION, FALSE_ALARM, MISSED_OBJECT, PERCEIVED, POOR_SCAN, STUCK,
    TOO_CLOSE, TOO_FAST_NEAR_PEOPLE,
};
use crate::trace::{EventKind, Trace};
use cbr_core::Context;
use lab::contract::operator_file::{self, OperatorData, OperatorFileError, RangeCheck};
use lab::{FeedbackChannel, Judgement, SimulatedOperator, StandardFields};
use rand::RngCore;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;
use trust::{Cause, DeclaredCause, OutcomeWeights};

fn one() -> f64 {
    1.0
}

/// A comfort speed near people: passing a standing person closer than `distance` faster
/// than `speed` interrupts with probability `p`. With `expected_too`, the operator minds
/// the places where people are expected to stand (a crossing, a bus stop) the same way,
/// whether or not someone is there: people step out from behind parked vehicles.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Comfort {
    /// Body-to-body gap below which a person is near (m).
    pub distance: f64,
    /// Highest speed the operator accepts near a person (m/s).
    pub speed: f64,
    /// Probability of interrupting on such a pass.
    pub p: f64,
    /// Whether passing an empty spot where people stand counts as passing a person.
    #[serde(default)]
    pub expected_too: bool,
}

/// A clearance that feels unsafe even without a collision: the run's closest pass below
/// `gap` interrupts with probability `p`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Clearance {
    /// Least body gap the operator accepts (m).
    pub gap: f64,
    /// Probability of interrupting on a closer pass.
    pub p: f64,
}

/// What a scan must be for the operator to believe its label: a scan from farther than
/// `max_distance` or shorter than `min_time` interrupts with probability `p`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScanStandard {
    /// Greatest body-to-object distance accepted (m).
    pub max_distance: f64,
    /// Shortest scan accepted (s).
    pub min_time: f64,
    /// Probability of interrupting on a poorer scan.
    pub p: f64,
}

/// How an operator's preferences change in a context of the robot's
/// (docs/simulation.md#context): where the robot's context gives every variable of `when`
/// its value, each preference given here replaces the operator's own.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContextPreferences {
    /// The context it applies in: variables of the UGV's context with their values
    /// (`{"cargo": "hazardous"}`); the variables left out may take any value.
    #[serde(deserialize_with = "declared_context")]
    pub when: BTreeMap<String, String>,
    /// The time allowed for the task there (s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub t_complete: Option<f64>,
    /// Probability of interrupting when `t_complete` passes there.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub p_deadline: Option<f64>,
    /// Probability of interrupting on each collision there.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub p_collision: Option<f64>,
    /// A comfort speed near people there (turned on, or replaced).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub comfort: Option<Comfort>,
    /// A least acceptable body gap there (turned on, or replaced).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clearance: Option<Clearance>,
}

impl ContextPreferences {
    /// Whether `context` gives every variable of `when` its value.
    pub fn applies_in(&self, context: &Context) -> bool {
        let contexts = crate::job_context::contexts();
        self.when
            .iter()
            .all(|(variable, value)| contexts.value(context, variable) == Some(value.as_str()))
    }
}

/// A `when` of the UGV's context: each variable declared, each value one it may take
/// (kept as written, so that naming a default value still restricts the context).
fn declared_context<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<BTreeMap<String, String>, D::Error> {
    let when = cbr_core::unique_keys::each_variable_once(d)?;
    let named = when.iter().map(|(k, v)| (k.as_str(), v.as_str()));
    crate::job_context::contexts()
        .context(named)
        .map_err(|e| serde::de::Error::custom(format_args!("field `when`: {e}")))?;
    Ok(when)
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
    #[serde(default = "lab::contract::patience::default_give_up_factor")]
    pub give_up_factor: f64,
    /// Outcome weights.
    #[serde(default)]
    pub weights: OutcomeWeights,
    /// A comfort speed near people (off when absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub comfort: Option<Comfort>,
    /// A least acceptable body gap (off when absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clearance: Option<Clearance>,
    /// A standard scans must meet (off when absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scan_standard: Option<ScanStandard>,
    /// How the operator explains itself (`(explains: 0.3, wrong: 0.1)`); silent, as the
    /// paper's operator, when absent. An experiment's `feedback` overrides it.
    #[serde(default)]
    pub feedback: FeedbackChannel,
    /// How its preferences change with the robot's context, in order, a later entry
    /// replacing what an earlier one set (off when absent: it judges every context
    /// alike, as the paper's operators do).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub contexts: Vec<ContextPreferences>,
}

/// Why an operator file cannot be used: the lab's operator-file errors, with the UGV's
/// own rule ([`UndeclaredPreference`]).
pub type OperatorError = OperatorFileError<UndeclaredPreference>;

/// A preference is on whose cause the scenario does not declare.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "`{field}` needs cause `{cause}`, which this scenario does not declare (declared: {declared})"
)]
pub struct UndeclaredPreference {
    /// The preference, e.g. `scan_standard`.
    pub field: &'static str,
    /// Its cause.
    pub cause: Cause,
    /// The causes the scenario declares.
    pub declared: String,
}

// The UGV's operator keeps its standard fields as plain fields (the file format and the
// Python binding name them), so it implements the accessors by hand.
impl SimulatedOperator for OperatorModel {
    fn feedback(&self) -> FeedbackChannel {
        self.feedback
    }

    fn completion_weight(&self) -> Option<f64> {
        Some(self.weights.completed)
    }
}

impl StandardFields for OperatorModel {
    fn name(&self) -> &str {
        &self.name
    }

    fn give_up_factor(&self) -> f64 {
        self.give_up_factor
    }

    fn weights(&self) -> &OutcomeWeights {
        &self.weights
    }

    fn weights_mut(&mut self) -> &mut OutcomeWeights {
        &mut self.weights
    }
}

impl OperatorData for OperatorModel {
    type Invalid = UndeclaredPreference;
    const PERCEIVED: Option<&'static [Cause]> = Some(&PERCEIVED);

    /// Every probability, then every amount, then the deadline (the loader checks the
    /// patience, `give_up_factor`, after these).
    fn validate(&self, check: &mut RangeCheck) {
        check.probability("p_deadline", self.p_deadline);
        check.probability("p_collision", self.p_collision);
        check.probability("p_missed_object", self.p_missed_object);
        check.probability("p_false_alarm", self.p_false_alarm);
        if let Some(c) = self.comfort {
            check.probability("comfort.p", c.p);
        }
        if let Some(c) = self.clearance {
            check.probability("clearance.p", c.p);
        }
        if let Some(c) = self.scan_standard {
            check.probability("scan_standard.p", c.p);
        }
        if let Some(c) = self.comfort {
            check.non_negative("comfort.distance", c.distance);
            check.non_negative("comfort.speed", c.speed);
        }
        if let Some(c) = self.clearance {
            check.non_negative("clearance.gap", c.gap);
        }
        if let Some(c) = self.scan_standard {
            check.non_negative("scan_standard.max_distance", c.max_distance);
            check.non_negative("scan_standard.min_time", c.min_time);
        }
        check.positive("t_complete", self.t_complete);
        for (i, c) in self.contexts.iter().enumerate() {
            let field = |name: &str| format!("contexts[{i}].{name}");
            if let Some(p) = c.p_deadline {
                check.probability(&field("p_deadline"), p);
            }
            if let Some(p) = c.p_collision {
                check.probability(&field("p_collision"), p);
            }
            if let Some(comfort) = c.comfort {
                check.probability(&field("comfort.p"), comfort.p);
                check.non_negative(&field("comfort.distance"), comfort.distance);
                check.non_negative(&field("comfort.speed"), comfort.speed);
            }
            if let Some(clearance) = c.clearance {
                check.probability(&field("clearance.p"), clearance.p);
                check.non_negative(&field("clearance.gap"), clearance.gap);
            }
            if let Some(t) = c.t_complete {
                check.positive(&field("t_complete"), t);
            }
        }
    }

    /// Every preference that is on has its cause declared.
    fn check_rules(&self, declared: &[DeclaredCause]) -> Result<(), UndeclaredPreference> {
        let in_some_context = |on: fn(&ContextPreferences) -> bool| self.contexts.iter().any(on);
        let on = [
            (
                "comfort",
                self.comfort.is_some() || in_some_context(|c| c.comfort.is_some()),
                TOO_FAST_NEAR_PEOPLE,
            ),
            (
                "clearance",
                self.clearance.is_some() || in_some_context(|c| c.clearance.is_some()),
                TOO_CLOSE,
            ),
            ("scan_standard", self.scan_standard.is_some(), POOR_SCAN),
        ];
        for (field, is_on, cause) in on {
            if is_on && !declared.iter().any(|d| d.name == cause) {
                let names: Vec<Cause> = declared.iter().map(|d| d.name).collect();
                return Err(UndeclaredPreference {
                    field,
                    cause,
                    declared: trust::cause::list_causes(&names),
                });
            }
        }
        Ok(())
    }
}

impl OperatorModel {
    /// Parses and validates an operator for a scenario that declares `causes` (its
    /// `weights.by_cause` may name only those, and of those only the causes the robot
    /// perceives itself; their declared default weights fill the causes it leaves out);
    /// `origin` names the source in errors ([`lab::contract::operator_file::from_ron`]).
    pub fn from_ron(
        text: &str,
        origin: &Path,
        causes: &[DeclaredCause],
    ) -> Result<Self, OperatorError> {
        operator_file::from_ron(text, origin, causes)
    }

    /// Reads, parses and validates an operator file for a scenario that declares `causes`
    /// ([`lab::contract::operator_file::load`]).
    pub fn load(path: &Path, causes: &[DeclaredCause]) -> Result<Self, OperatorError> {
        operator_file::load(path, causes)
    }

    /// The operator as it judges in `context`: every entry of its `contexts` that applies
    /// there, in order, replacing the preferences it gives.
    pub fn in_context(&self, context: &Context) -> OperatorModel {
        let mut there = self.clone();
        for c in self.contexts.iter().filter(|c| c.applies_in(context)) {
            there.t_complete = c.t_complete.unwrap_or(there.t_complete);
            there.p_deadline = c.p_deadline.unwrap_or(there.p_deadline);
            there.p_collision = c.p_collision.unwrap_or(there.p_collision);
            there.comfort = c.comfort.or(there.comfort);
            there.clearance = c.clearance.or(there.clearance);
        }
        there
    }

    /// Watches a run and decides how it ends, and why (the truth). Random reactions draw
    /// from `rng`.
    pub fn judge(&self, trace: &Trace, rng: &mut dyn RngCore) -> Judgement {
        self.judge_attending(trace, 1.0, rng)
    }

    /// [`OperatorModel::judge`] by an operator whose `attention`, in `[0, 1]`, is the chance
    /// it notices what it would react to (docs/simulation.md, "Complacency"): a reaction
    /// it would have had with probability `p` happens with probability `p * attention`,
    /// on the same draw, so at attention 1 this is exactly `judge`. What it overlooks lets
    /// the run go on, and the first such cause is the judgement's `overlooked`. A robot
    /// stuck, a detonation and a task past the operator's patience are noticed whatever
    /// the attention: the robot stops, the explosion is heard, the task never ends.
    pub fn judge_attending(
        &self,
        trace: &Trace,
        attention: f64,
        rng: &mut dyn RngCore,
    ) -> Judgement {
        let patience = self.patience(self.t_complete, self.p_deadline, DEADLINE);
        let interrupt = |cause, t| Some(Judgement::interrupted(self.weights.of(cause), cause, t));
        let events = trace.events.iter().map(|event| (event.t, event.kind));
        self.judge_run(
            &patience,
            events,
            attention,
            rng,
            |attending, rng, t, kind| match kind {
                EventKind::Collision { .. }
                    if attending.react(rng, self.p_collision, COLLISION) =>
                {
                    interrupt(COLLISION, t)
                }
                EventKind::Stuck => interrupt(STUCK, t),
                EventKind::MissedObject { .. }
                    if attending.react(rng, self.p_missed_object, MISSED_OBJECT) =>
                {
                    interrupt(MISSED_OBJECT, t)
                }
                EventKind::Labelled {
                    explosive: false,
                    labelled_explosive: true,
                    ..
                } if attending.react(rng, self.p_false_alarm, FALSE_ALARM) => {
                    interrupt(FALSE_ALARM, t)
                }
                EventKind::PassedPerson {
                    present,
                    gap,
                    speed,
                    ..
                } if self.comfort.is_some_and(|c| {
                    (present || c.expected_too)
                        && gap < c.distance
                        && speed > c.speed
                        && attending.react(rng, c.p, TOO_FAST_NEAR_PEOPLE)
                }) =>
                {
                    interrupt(TOO_FAST_NEAR_PEOPLE, t)
                }
                EventKind::ClosestPass { gap, .. }
                    if self
                        .clearance
                        .is_some_and(|c| gap < c.gap && attending.react(rng, c.p, TOO_CLOSE)) =>
                {
                    interrupt(TOO_CLOSE, t)
                }
                EventKind::Scanned {
                    distance, duration, ..
                } if self.scan_standard.is_some_and(|c| {
                    (distance > c.max_distance || duration < c.min_time)
                        && attending.react(rng, c.p, POOR_SCAN)
                }) =>
                {
                    interrupt(POOR_SCAN, t)
                }
                EventKind::Detonation { .. } => Some(Judgement::failed(
                    self.weights.of(DETONATION),
                    DETONATION,
                    t,
                )),
                EventKind::Arrived { .. } => Some(Judgement::completed(self.weights.completed, t)),
                _ => None,
            },
        )
    }
}

/// The paper's operators for `scenario` (docs/model.md#the-operators), from the RON files
/// shipped with the crate.
pub fn builtin_operators(scenario: Scenario) -> Vec<OperatorModel> {
    let causes = scenario.causes();
    let shipped = match scenario {
        Scenario::Movement => lab::shipped_operators!(
            causes,
            [
                "operators/movement/speed-focused.ron",
                "operators/movement/safety-focused.ron",
                "operators/movement/balanced.ron",
            ]
        ),
        Scenario::Patrol => lab::shipped_operators!(
            causes,
            [
                "operators/patrol/speed-focused.ron",
                "operators/patrol/detection-focused.ron",
            ]
        ),
    };
    shipped.expect("shipped operators are valid")
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
        Trace::of(events)
    }

    /// A run with two collisions and a false alarm before it arrives.
    fn eventful() -> Trace {
        trace(&[
            (
                2.0,
                EventKind::Collision {
                    at: Vec2::new(0.0, 0.0),
                },
            ),
            (
                4.0,
                EventKind::Collision {
                    at: Vec2::new(1.0, 0.0),
                },
            ),
            (
                6.0,
                EventKind::Labelled {
                    object: 0,
                    explosive: false,
                    labelled_explosive: true,
                },
            ),
            (
                30.0,
                EventKind::Arrived {
                    at: Vec2::new(2.0, 0.0),
                },
            ),
        ])
    }

    #[test]
    fn an_attentive_operator_judges_exactly_as_the_paper_s() {
        let t = eventful();
        for operator in builtin_operators(Scenario::Patrol) {
            for seed in 0..200 {
                let paper = operator.judge(&t, &mut ChaCha8Rng::seed_from_u64(seed));
                let attending =
                    operator.judge_attending(&t, 1.0, &mut ChaCha8Rng::seed_from_u64(seed));
                assert_eq!(paper, attending);
                assert_eq!(attending.overlooked, None);
            }
        }
    }

    #[test]
    fn an_operator_who_notices_nothing_overlooks_the_first_problem_and_lets_the_run_finish() {
        let t = eventful();
        let mut operator = builtin_operators(Scenario::Patrol).remove(0);
        operator.p_collision = 1.0;
        let judged = operator.judge_attending(&t, 0.0, &mut ChaCha8Rng::seed_from_u64(3));
        assert_eq!(judged.outcome.kind, OutcomeKind::Completed);
        assert_eq!(judged.overlooked, Some(COLLISION));
        // Half attentive, over many draws: about half the runs stopped at a collision.
        let stopped = (0..2000)
            .filter(|&seed| {
                let j = operator.judge_attending(&t, 0.5, &mut ChaCha8Rng::seed_from_u64(seed));
                j.truth == Some(COLLISION) && j.outcome.duration_s == 2.0
            })
            .count();
        assert!((900..1100).contains(&stopped), "{stopped}");
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
            comfort: None,
            clearance: None,
            scan_standard: None,
            feedback: FeedbackChannel::SILENT,
            contexts: Vec::new(),
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

    /// An operator who minds bumps more with hazardous cargo, and in an emergency with it
    /// wants the task sooner and minds bumps less than then but more than usual.
    const CARGO_MINDED: &str = "(name: \"cargo-minded\", t_complete: 90.0, p_deadline: 0.5,
        p_collision: 0.05,
        contexts: [
            (when: {\"cargo\": \"hazardous\"}, p_collision: Some(0.9),
             comfort: Some((distance: 1.5, speed: 1.0, p: 0.8))),
            (when: {\"cargo\": \"hazardous\", \"situation\": \"emergency\"},
             t_complete: Some(60.0), p_collision: Some(0.5)),
            (when: {\"situation\": \"routine\"}, p_deadline: Some(0.25)),
        ])";

    #[test]
    fn an_operator_judges_by_the_preferences_it_states_for_the_robots_context() {
        let op = OperatorModel::from_ron(
            CARGO_MINDED,
            Path::new("cargo-minded.ron"),
            Scenario::Movement.causes(),
        )
        .unwrap();
        let contexts = crate::job_context::contexts();
        let at = |settings: &[(&str, &str)]| {
            op.in_context(&contexts.context(settings.iter().copied()).unwrap())
        };
        let preferences = |o: &OperatorModel| (o.t_complete, o.p_deadline, o.p_collision);
        // The default context is routine: only the third entry applies.
        assert_eq!(preferences(&at(&[])), (90.0, 0.25, 0.05));
        assert_eq!(at(&[]).comfort, None);
        let hazardous = at(&[("cargo", "hazardous")]);
        assert_eq!(preferences(&hazardous), (90.0, 0.25, 0.9));
        assert_eq!(hazardous.comfort.unwrap().speed, 1.0);
        // Both entries for hazardous cargo apply in an emergency, the later last; the
        // routine one does not.
        let rushed = at(&[("cargo", "hazardous"), ("situation", "emergency")]);
        assert_eq!(preferences(&rushed), (60.0, 0.5, 0.5));
        assert!(rushed.comfort.is_some());
        assert_eq!(
            preferences(&at(&[("situation", "emergency")])),
            (90.0, 0.5, 0.05)
        );
        // The stated preferences judge: at hazardous cargo's 0.9 most bumps interrupt.
        let bumped = trace(&[
            (
                2.0,
                EventKind::Collision {
                    at: Vec2::new(0.0, 0.0),
                },
            ),
            (
                30.0,
                EventKind::Arrived {
                    at: Vec2::new(2.0, 0.0),
                },
            ),
        ]);
        let interrupted = |o: &OperatorModel| {
            (0..1000)
                .filter(|&seed| {
                    o.judge(&bumped, &mut ChaCha8Rng::seed_from_u64(seed)).truth == Some(COLLISION)
                })
                .count()
        };
        assert!(interrupted(&at(&[])) < 100);
        assert!(interrupted(&hazardous) > 850);
    }

    #[test]
    fn a_context_preference_is_checked_where_it_is_written() {
        let origin = Path::new("ops/c.ron");
        let read = |text: &str| {
            OperatorModel::from_ron(text, origin, Scenario::Movement.causes())
                .unwrap_err()
                .to_string()
        };
        let head = "(name: \"c\", t_complete: 9.0, p_deadline: 1.0, p_collision: 0.1,\n";
        let err = read(&format!(
            "{head} contexts: [(when: {{\"cargo\": \"toxic\"}})])"
        ));
        assert!(err.starts_with("ops/c.ron:2:"), "{err}");
        assert!(
            err.contains(
                "field `when`: context variable `cargo` may be normal, hazardous, not `toxic`"
            ),
            "{err}"
        );
        let err = read(&format!(
            "{head} contexts: [(when: {{\"weather\": \"rain\"}})])"
        ));
        assert!(err.contains("unknown context variable `weather`"), "{err}");
        let err = read(&format!(
            "{head} contexts: [(when: {{}}, p_collision: Some(1.5))])"
        ));
        assert!(
            err.contains("`contexts[0].p_collision` must be a probability in [0, 1], got 1.5"),
            "{err}"
        );
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
            "ops/bomb-averse.ron: operator `bomb-averse`: `weights.by_cause`: cause `detonation` is not declared (declared: deadline, collision, stuck, too-fast-near-people, too-close)"
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

    fn pass(gap: f64, speed: f64) -> EventKind {
        EventKind::PassedPerson {
            person: 0,
            present: true,
            gap,
            speed,
        }
    }

    #[test]
    fn comfort_interrupts_a_fast_close_pass_only() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut op = operator(0.0, 0.0);
        op.comfort = Some(Comfort {
            distance: 3.6,
            speed: 1.4,
            p: 1.0,
            expected_too: false,
        });
        let judge = |op: &OperatorModel, kind, rng: &mut ChaCha8Rng| {
            op.judge(&trace(&[(6.0, kind), (12.0, ARRIVED)]), rng)
        };
        let o = judge(&op, pass(2.0, 3.0), &mut rng);
        assert_eq!(o, Judgement::interrupted(1.0, TOO_FAST_NEAR_PEOPLE, 6.0));
        // Far enough, or slow enough: no complaint.
        assert_eq!(
            judge(&op, pass(4.0, 3.0), &mut rng).outcome.kind,
            OutcomeKind::Completed
        );
        assert_eq!(
            judge(&op, pass(0.5, 1.0), &mut rng).outcome.kind,
            OutcomeKind::Completed
        );
        // An empty spot counts only for an operator who expects people there.
        let empty = EventKind::PassedPerson {
            person: 0,
            present: false,
            gap: 0.5,
            speed: 3.0,
        };
        assert_eq!(
            judge(&op, empty, &mut rng).outcome.kind,
            OutcomeKind::Completed
        );
        op.comfort.as_mut().unwrap().expected_too = true;
        let o = judge(&op, empty, &mut rng);
        assert_eq!(o, Judgement::interrupted(1.0, TOO_FAST_NEAR_PEOPLE, 6.0));
        // Off: the same pass is ignored.
        op.comfort = None;
        assert_eq!(
            judge(&op, pass(0.5, 9.0), &mut rng).outcome.kind,
            OutcomeKind::Completed
        );
    }

    #[test]
    fn clearance_interrupts_a_close_pass() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut op = operator(0.0, 0.0);
        op.clearance = Some(Clearance { gap: 0.25, p: 1.0 });
        let close = |gap| EventKind::ClosestPass {
            gap,
            at: Vec2::new(0.0, 0.0),
        };
        let o = op.judge(&trace(&[(3.0, close(0.1)), (12.0, ARRIVED)]), &mut rng);
        assert_eq!(o, Judgement::interrupted(1.0, TOO_CLOSE, 3.0));
        let o = op.judge(&trace(&[(3.0, close(0.4)), (12.0, ARRIVED)]), &mut rng);
        assert_eq!(o.outcome.kind, OutcomeKind::Completed);
    }

    #[test]
    fn scan_standard_interrupts_a_far_or_short_scan() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut op = operator(0.0, 0.0);
        op.scan_standard = Some(ScanStandard {
            max_distance: 0.5,
            min_time: 2.5,
            p: 1.0,
        });
        let scan = |distance, duration| EventKind::Scanned {
            object: 0,
            distance,
            duration,
        };
        for (distance, duration, believed) in [
            (0.5, 2.5, true),
            (0.25, 5.0, true),
            (0.75, 5.0, false),
            (0.25, 2.0, false),
        ] {
            let t = trace(&[(10.0, scan(distance, duration)), (14.0, ARRIVED)]);
            let o = op.judge(&t, &mut rng);
            if believed {
                assert_eq!(o.outcome.kind, OutcomeKind::Completed);
            } else {
                assert_eq!(o, Judgement::interrupted(1.0, POOR_SCAN, 10.0));
            }
        }
    }

    #[test]
    fn a_preference_that_is_off_draws_nothing() {
        // The paper's operator ignores the measurements: the same generator state after
        // judging a trace with them as without them.
        let op = operator(0.5, 0.5);
        let plain = trace(&[(4.0, HIT), (20.0, ARRIVED)]);
        let measured = trace(&[
            (2.0, pass(0.1, 9.0)),
            (4.0, HIT),
            (
                5.0,
                EventKind::ClosestPass {
                    gap: 0.01,
                    at: Vec2::new(0.0, 0.0),
                },
            ),
            (16.0, EventKind::BehindPlan { planned: 16.0 }),
            (20.0, ARRIVED),
        ]);
        for seed in 0..50 {
            let mut a = ChaCha8Rng::seed_from_u64(seed);
            let mut b = ChaCha8Rng::seed_from_u64(seed);
            assert_eq!(op.judge(&plain, &mut a), op.judge(&measured, &mut b));
            assert_eq!(
                rand::RngCore::next_u64(&mut a),
                rand::RngCore::next_u64(&mut b)
            );
        }
    }

    #[test]
    fn weights_name_only_perceived_causes() {
        let origin = Path::new("ops/w.ron");
        let text = |cause: &str| {
            format!(
                "(name: \"w\", t_complete: 9.0, p_deadline: 1.0, p_collision: 0.1,
                  weights: (by_cause: {{ \"{cause}\": 2.0 }}))"
            )
        };
        for cause in ["collision", "stuck", "detonation"] {
            OperatorModel::from_ron(&text(cause), origin, Scenario::Patrol.causes()).unwrap();
        }
        for cause in ["deadline", "missed-object", "false-alarm", "poor-scan"] {
            let err = OperatorModel::from_ron(&text(cause), origin, Scenario::Patrol.causes())
                .unwrap_err()
                .to_string();
            assert_eq!(
                err,
                format!(
                    "ops/w.ron: operator `w`: `weights.by_cause.{cause}`: weights may name only causes the robot perceives itself (collision, stuck, detonation)"
                )
            );
        }
    }

    #[test]
    fn preferences_parse_and_are_checked() {
        let origin = Path::new("ops/p.ron");
        let text = "(name: \"p\", t_complete: 60.0, p_deadline: 0.05, p_collision: 0.95,
                     comfort: Some((distance: 3.6, speed: 1.4, p: 0.95)),
                     clearance: Some((gap: 0.25, p: 0.95)))";
        let op = OperatorModel::from_ron(text, origin, Scenario::Movement.causes()).unwrap();
        assert_eq!(op.comfort.unwrap().speed, 1.4);
        assert_eq!(op.clearance.unwrap().gap, 0.25);
        let scans = "(name: \"p\", t_complete: 60.0, p_deadline: 0.05, p_collision: 0.95,
                     scan_standard: Some((max_distance: 0.5, min_time: 2.5, p: 0.95)))";
        let err = OperatorModel::from_ron(scans, origin, Scenario::Movement.causes())
            .unwrap_err()
            .to_string();
        assert!(
            err.contains(
                "`scan_standard` needs cause `poor-scan`, which this scenario does not declare"
            ),
            "{err}"
        );
        OperatorModel::from_ron(scans, origin, Scenario::Patrol.causes()).unwrap();
        let bad = "(name: \"p\", t_complete: 60.0, p_deadline: 0.05, p_collision: 0.95,
                   comfort: Some((distance: 3.6, speed: 1.4, p: 1.5)))";
        let err = OperatorModel::from_ron(bad, origin, Scenario::Movement.causes())
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("`comfort.p` must be a probability in [0, 1], got 1.5"),
            "{err}"
        );
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
