//! What the UGV perceives itself during a run, apart from why its operator reacted.
//!
//! The robot has bump sensors, knows when its planner finds no way through, and hears an
//! explosion: a collision, being stuck and a detonation are events it perceives. It does
//! not perceive a missed object (it did not notice it), a false alarm (it believes its
//! label) or the operator's deadline (the operator's private expectation). An outcome's
//! [`Observations`] hold, in the order of [`MOVEMENT`] or [`PATROL`], the events of the run
//! up to the moment the command ended.

use crate::Scenario;
use crate::causes::{COLLISION, DETONATION, STUCK};
use crate::trace::{EventKind, Trace};
use trust::{Cause, Observations};

/// What a movement robot perceives: a bump, being stuck.
pub const MOVEMENT: [Cause; 2] = [COLLISION, STUCK];
/// What a patrol robot perceives: a bump, being stuck, an explosion.
pub const PATROL: [Cause; 3] = [COLLISION, STUCK, DETONATION];

/// The observations a scenario's robot can report, in bit order.
pub fn observations(scenario: Scenario) -> &'static [Cause] {
    match scenario {
        Scenario::Movement => &MOVEMENT,
        Scenario::Patrol => &PATROL,
    }
}

/// What the robot perceived of `trace` up to `until` seconds (the end of the command), as
/// bits over `declared` (a scenario's [`observations`]).
pub fn perceive(trace: &Trace, until: f64, declared: &[Cause]) -> Observations {
    let bit = |name: Cause| declared.iter().position(|&d| d == name);
    trace
        .events
        .iter()
        .take_while(|e| e.t <= until)
        .filter_map(|e| match e.kind {
            EventKind::Collision { .. } => bit(COLLISION),
            EventKind::Stuck => bit(STUCK),
            EventKind::Detonation { .. } => bit(DETONATION),
            _ => None,
        })
        .fold(Observations::NONE, Observations::with)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Vec2;

    fn trace(events: &[(f64, EventKind)]) -> Trace {
        let mut t = Trace::default();
        for &(time, kind) in events {
            t.push(time, kind);
        }
        t
    }

    #[test]
    fn the_robot_perceives_its_own_events_up_to_the_end_of_the_command() {
        let hit = EventKind::Collision {
            at: Vec2::new(1.0, 1.0),
        };
        let run = trace(&[
            (2.0, EventKind::MissedObject { object: 0 }),
            (
                3.0,
                EventKind::Labelled {
                    object: 1,
                    explosive: false,
                    labelled_explosive: true,
                },
            ),
            (4.0, hit),
            (9.0, EventKind::Detonation { object: 2 }),
        ]);
        // Interrupted at 3 s: a missed object and a false alarm are not perceived.
        assert!(perceive(&run, 3.0, &PATROL).is_empty());
        // At 5 s the bump is; at 10 s the explosion too.
        assert_eq!(perceive(&run, 5.0, &PATROL), Observations::NONE.with(0));
        assert_eq!(
            perceive(&run, 10.0, &PATROL),
            Observations::NONE.with(0).with(2)
        );
        // Movement declares no detonation: none is reported there.
        assert_eq!(perceive(&run, 10.0, &MOVEMENT), Observations::NONE.with(0));
        let stuck = trace(&[(5.0, EventKind::Stuck)]);
        assert_eq!(perceive(&stuck, 5.0, &MOVEMENT), Observations::NONE.with(1));
    }
}
