//! What a UGV operator may state up front ([`lab::Domain::statements`]), and, for
//! simulation, whether an operator file makes each statement true
//! (docs/simulation.md#stated-preferences).
//!
//! Each name speaks of one preference of the operator files, in words an operator would
//! use: `hurry` (the deadline), `avoid-bumps` (collisions), `keep-away-from-people` (the
//! comfort preference), `keep-clear` (the clearance preference), and in patrol
//! `scan-every-object` (an object driven past unscanned), `no-false-alarms` (a harmless
//! object labelled explosive) and `scan-closely` (the scan standard). An operator minds
//! what it reacts to more often than not: the preference is on and its reaction
//! probability is at least [`MINDS_AT`].

use crate::operator::OperatorModel;
use crate::scenario::Scenario;
use cbr_core::Statement;
use std::sync::LazyLock;

/// The reaction probability from which an operator minds what a statement names: it
/// reacts more often than not. A person asked what matters to them names what they act
/// on most of the time, not what they act on now and then.
pub const MINDS_AT: f64 = 0.5;

/// The movement operator's statements, in order.
pub const MOVEMENT: [&str; 4] = [
    "hurry",
    "avoid-bumps",
    "keep-away-from-people",
    "keep-clear",
];

/// The patrol operator's statements: the movement operator's, then the patrol's own.
pub const PATROL: [&str; 7] = [
    MOVEMENT[0],
    MOVEMENT[1],
    MOVEMENT[2],
    MOVEMENT[3],
    "scan-every-object",
    "no-false-alarms",
    "scan-closely",
];

static MOVEMENT_NAMES: LazyLock<Vec<String>> =
    LazyLock::new(|| MOVEMENT.iter().map(|s| (*s).to_owned()).collect());
static PATROL_NAMES: LazyLock<Vec<String>> =
    LazyLock::new(|| PATROL.iter().map(|s| (*s).to_owned()).collect());

/// The statements of `scenario`.
pub fn names(scenario: Scenario) -> &'static [String] {
    match scenario {
        Scenario::Movement => &MOVEMENT_NAMES,
        Scenario::Patrol => &PATROL_NAMES,
    }
}

/// The reaction probability of `operator` to what statement `name` names (0 for a
/// preference it does not have).
fn reaction(operator: &OperatorModel, name: &str) -> f64 {
    match name {
        "hurry" => operator.p_deadline,
        "avoid-bumps" => operator.p_collision,
        "keep-away-from-people" => operator.comfort.map_or(0.0, |c| c.p),
        "keep-clear" => operator.clearance.map_or(0.0, |c| c.p),
        "scan-every-object" => operator.p_missed_object,
        "no-false-alarms" => operator.p_false_alarm,
        "scan-closely" => operator.scan_standard.map_or(0.0, |s| s.p),
        other => unreachable!("`{other}` is not a UGV statement"),
    }
}

/// Whether `operator` minds each statement of `scenario`, in order.
pub fn truth(scenario: Scenario, operator: &OperatorModel) -> Vec<Statement> {
    names(scenario)
        .iter()
        .map(|name| Statement::new(name, reaction(operator, name) >= MINDS_AT))
        .collect()
}
