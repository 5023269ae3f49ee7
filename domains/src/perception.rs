//! What the robot itself perceives of a run: its own sensors and clock, up to the moment
//! the command ended. This is not why the operator interrupted (the outcome's cause is
//! the truth, kept for evaluation); it is what a strategy may relate an interruption to.
//!
//! The robot perceives:
//! - `collision`: its bumper and its drive's stall tell it when it touched something;
//! - `stuck`: its planner found no way through;
//! - `detonation`: an explosion is heard, felt and seen;
//! - `behind-plan`: its clock passed the arrival its own plan promised (nominal drive plus
//!   the stops it made); this is its own expectation, not the operator's deadline;
//! - `near-person-fast`: it passed a person (its lidar sees people) within
//!   [`NEAR_PERSON_GAP`] faster than [`WALKING_PACE`] (it knows its speed); an empty spot
//!   where people often stand is nothing its sensors see;
//! - `close-pass`: its lidar measured a body gap below [`CLOSE_PASS_GAP`] without touching.
//!
//! It never perceives an object it drove past unnoticed (it did not see it), a false
//! alarm (it believes its own label), or the operator's deadline (it is not told it).

use crate::Scenario;
use crate::trace::{EventKind, Trace};
use std::fmt;

/// A person within this body-to-body gap counts as near (m): the outer edge of personal
/// space in proxemics (about 1.2 m), the distance strangers keep when they can.
pub const NEAR_PERSON_GAP: f64 = 1.2;
/// Faster than this near a person is fast (m/s): a typical walking pace (about 1.4 m/s).
pub const WALKING_PACE: f64 = 1.4;
/// A body gap the lidar measures below this counts as a close pass (m): about twice the
/// robot's localisation error (0.04 m) plus the scanner's few centimetres of range noise,
/// a gap the robot cannot tell from contact.
pub const CLOSE_PASS_GAP: f64 = 0.1;

/// The names of the observations, in bit order.
pub const OBSERVATIONS: [&str; 6] = [
    "collision",
    "stuck",
    "detonation",
    "behind-plan",
    "near-person-fast",
    "close-pass",
];

/// A set of observations: bit `i` is [`OBSERVATIONS`]`[i]`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Perceived(pub u8);

impl Perceived {
    /// The robot touched an obstacle.
    pub const COLLISION: Perceived = Perceived(1 << 0);
    /// The robot found no way through.
    pub const STUCK: Perceived = Perceived(1 << 1);
    /// An explosive went off.
    pub const DETONATION: Perceived = Perceived(1 << 2);
    /// The robot's clock passed its own planned arrival.
    pub const BEHIND_PLAN: Perceived = Perceived(1 << 3);
    /// It passed a person closely and faster than walking pace.
    pub const NEAR_PERSON_FAST: Perceived = Perceived(1 << 4);
    /// Its lidar measured a very small body gap.
    pub const CLOSE_PASS: Perceived = Perceived(1 << 5);

    /// The empty set.
    pub const NONE: Perceived = Perceived(0);

    /// Whether every observation of `other` is in `self`.
    pub fn contains(self, other: Perceived) -> bool {
        self.0 & other.0 == other.0
    }

    /// Whether the set is empty.
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// `self` with `other`'s observations added.
    pub fn with(self, other: Perceived) -> Perceived {
        Perceived(self.0 | other.0)
    }

    /// The names of the observations in the set, in bit order.
    pub fn names(self) -> impl Iterator<Item = &'static str> {
        OBSERVATIONS
            .iter()
            .enumerate()
            .filter(move |(i, _)| self.0 & (1 << i) != 0)
            .map(|(_, name)| *name)
    }

    /// The observation named `name`, if there is one.
    pub fn named(name: &str) -> Option<Perceived> {
        OBSERVATIONS
            .iter()
            .position(|n| *n == name)
            .map(|i| Perceived(1 << i))
    }

    /// The observations the robot can make in `scenario`.
    pub fn reportable(scenario: Scenario) -> Perceived {
        let common = Self::COLLISION
            .with(Self::STUCK)
            .with(Self::BEHIND_PLAN)
            .with(Self::NEAR_PERSON_FAST)
            .with(Self::CLOSE_PASS);
        match scenario {
            Scenario::Movement => common,
            Scenario::Patrol => common.with(Self::DETONATION),
        }
    }
}

impl fmt::Display for Perceived {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = self.names().collect();
        f.write_str(&names.join(","))
    }
}

/// The names of the observations the robot can make in `scenario`, in bit order.
pub fn observations(scenario: Scenario) -> Vec<&'static str> {
    Perceived::reportable(scenario).names().collect()
}

/// What the robot perceived of the run in `trace` up to time `until` (s): the moment the
/// command ended (the outcome's duration).
pub fn perceive(trace: &Trace, until: f64) -> Perceived {
    let mut seen = Perceived::NONE;
    for event in trace.events.iter().take_while(|e| e.t <= until) {
        let observed = match event.kind {
            EventKind::Collision { .. } => Perceived::COLLISION,
            EventKind::Stuck => Perceived::STUCK,
            EventKind::Detonation { .. } => Perceived::DETONATION,
            EventKind::BehindPlan { .. } => Perceived::BEHIND_PLAN,
            // Its lidar sees a person who is there, not a spot where one might be.
            EventKind::PassedPerson {
                present: true,
                gap,
                speed,
                ..
            } if gap < NEAR_PERSON_GAP && speed > WALKING_PACE => Perceived::NEAR_PERSON_FAST,
            EventKind::ClosestPass { gap, .. } if gap < CLOSE_PASS_GAP => Perceived::CLOSE_PASS,
            // Not perceivable: an object it never saw, a label it believes, a scan it chose.
            _ => Perceived::NONE,
        };
        seen = seen.with(observed);
    }
    seen
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Vec2;

    fn trace(events: &[(f64, EventKind)]) -> Trace {
        let mut t = Trace::default();
        for (time, kind) in events {
            t.push(*time, *kind);
        }
        t
    }

    const O: Vec2 = Vec2::new(0.0, 0.0);

    #[test]
    fn names_and_bits_agree() {
        for (i, name) in OBSERVATIONS.iter().enumerate() {
            assert_eq!(Perceived::named(name), Some(Perceived(1 << i)));
        }
        assert_eq!(Perceived::named("missed-object"), None);
        assert_eq!(
            observations(Scenario::Movement),
            [
                "collision",
                "stuck",
                "behind-plan",
                "near-person-fast",
                "close-pass"
            ]
        );
        assert!(observations(Scenario::Patrol).contains(&"detonation"));
        let both = Perceived::COLLISION.with(Perceived::CLOSE_PASS);
        assert_eq!(both.to_string(), "collision,close-pass");
    }

    #[test]
    fn only_what_happened_before_the_end_is_perceived() {
        let t = trace(&[
            (2.0, EventKind::Collision { at: O }),
            (
                5.0,
                EventKind::PassedPerson {
                    person: 0,
                    present: true,
                    gap: 0.5,
                    speed: 3.0,
                },
            ),
            (9.0, EventKind::BehindPlan { planned: 9.0 }),
            (12.0, EventKind::Arrived { at: O }),
        ]);
        assert_eq!(perceive(&t, 1.0), Perceived::NONE);
        assert_eq!(perceive(&t, 2.0), Perceived::COLLISION);
        assert_eq!(
            perceive(&t, 12.0),
            Perceived::COLLISION
                .with(Perceived::NEAR_PERSON_FAST)
                .with(Perceived::BEHIND_PLAN)
        );
    }

    #[test]
    fn thresholds() {
        let pass = |present, gap, speed| {
            trace(&[(
                1.0,
                EventKind::PassedPerson {
                    person: 0,
                    present,
                    gap,
                    speed,
                },
            )])
        };
        assert!(perceive(&pass(true, 1.0, 2.0), 9.0).contains(Perceived::NEAR_PERSON_FAST));
        assert!(perceive(&pass(true, 1.5, 2.0), 9.0).is_empty());
        assert!(perceive(&pass(true, 1.0, 1.0), 9.0).is_empty());
        // An empty spot is nothing to see.
        assert!(perceive(&pass(false, 0.2, 9.0), 9.0).is_empty());
        let close = |gap| trace(&[(1.0, EventKind::ClosestPass { gap, at: O })]);
        assert_eq!(perceive(&close(0.05), 9.0), Perceived::CLOSE_PASS);
        assert!(perceive(&close(0.3), 9.0).is_empty());
    }

    #[test]
    fn missed_objects_false_alarms_and_deadlines_are_not_perceived() {
        let t = trace(&[
            (1.0, EventKind::MissedObject { object: 0 }),
            (
                2.0,
                EventKind::Scanned {
                    object: 1,
                    distance: 2.0,
                    duration: 0.5,
                },
            ),
            (
                2.0,
                EventKind::Labelled {
                    object: 1,
                    explosive: false,
                    labelled_explosive: true,
                },
            ),
            // Long after any deadline.
            (500.0, EventKind::Arrived { at: O }),
        ]);
        assert!(perceive(&t, 500.0).is_empty());
    }
}
