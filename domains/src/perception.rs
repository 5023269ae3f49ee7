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
//! - `close-pass`: its lidar measured a body gap below [`CLOSE_PASS_GAP`] without touching;
//! - `raised-alarm` (patrol): it labelled an object explosive; it knows its own label, and
//!   believes it.
//!
//! It never perceives an object it drove past unnoticed (it did not see it), a false
//! alarm (it believes its own label), or the operator's deadline (it is not told it).

use crate::Scenario;
use crate::causes::{
    COLLISION, DEADLINE, DETONATION, FALSE_ALARM, STUCK, TOO_CLOSE, TOO_FAST_NEAR_PEOPLE,
};
use crate::detector::Detector;
use crate::trace::{EventKind, Trace};
use trust::{Cause, Hint, Observations};

/// A person within this body-to-body gap counts as near (m): the outer edge of personal
/// space in proxemics (about 1.2 m), the distance strangers keep when they can.
pub const NEAR_PERSON_GAP: f64 = 1.2;
/// Faster than this near a person is fast (m/s): a typical walking pace (about 1.4 m/s).
pub const WALKING_PACE: f64 = 1.4;
/// A body gap the lidar measures below this counts as a close pass (m): about twice the
/// robot's localisation error (0.04 m) plus the scanner's few centimetres of range noise,
/// a gap the robot cannot tell from contact.
pub const CLOSE_PASS_GAP: f64 = 0.1;

/// The robot's clock passed its own planned arrival.
pub const BEHIND_PLAN: Cause = Cause::from_static("behind-plan");
/// It passed a person closely and faster than walking pace.
pub const NEAR_PERSON_FAST: Cause = Cause::from_static("near-person-fast");
/// Its lidar measured a very small body gap.
pub const CLOSE_PASS: Cause = Cause::from_static("close-pass");
/// It labelled an object explosive (patrol): it knows the alarm it raised, not whether the
/// alarm was false.
pub const RAISED_ALARM: Cause = Cause::from_static("raised-alarm");

/// What a movement robot perceives, in bit order ([`lab::Domain::observations`]).
pub const MOVEMENT: [Cause; 5] = [COLLISION, STUCK, BEHIND_PLAN, NEAR_PERSON_FAST, CLOSE_PASS];
/// What a patrol robot perceives, in bit order: the movement robot's, an explosion, and
/// the alarms it raised itself.
pub const PATROL: [Cause; 7] = [
    COLLISION,
    STUCK,
    DETONATION,
    BEHIND_PLAN,
    NEAR_PERSON_FAST,
    CLOSE_PASS,
    RAISED_ALARM,
];

/// What the robot's designer knows an observation hints at, for the explanations'
/// inferences (`trust::explain`): each observation is the robot's own view of one of the
/// operator's reasons, which the robot cannot perceive itself.
/// - `behind-plan` hints at `deadline`: the operator's time limit is not told to the robot,
///   but a run slower than the robot's own plan is the run most likely to miss it;
/// - `near-person-fast` hints at `too-fast-near-people`: it is the same event seen by the
///   robot's lidar and speedometer, with its own thresholds instead of the operator's;
/// - `close-pass` hints at `too-close`: likewise, a small measured gap;
/// - `raised-alarm` (patrol) hints at `false-alarm`: an interruption right after an alarm
///   most plausibly disputes it (the robot believes its label, but knows the operator may
///   not).
pub const MOVEMENT_HINTS: [Hint; 3] = [
    Hint {
        observation: BEHIND_PLAN,
        suggests: DEADLINE,
    },
    Hint {
        observation: NEAR_PERSON_FAST,
        suggests: TOO_FAST_NEAR_PEOPLE,
    },
    Hint {
        observation: CLOSE_PASS,
        suggests: TOO_CLOSE,
    },
];

/// The patrol robot's hints: the movement robot's and `raised-alarm` at `false-alarm`
/// (see [`MOVEMENT_HINTS`]).
pub const PATROL_HINTS: [Hint; 4] = [
    MOVEMENT_HINTS[0],
    MOVEMENT_HINTS[1],
    MOVEMENT_HINTS[2],
    Hint {
        observation: RAISED_ALARM,
        suggests: FALSE_ALARM,
    },
];

/// The hints of `scenario` (see [`MOVEMENT_HINTS`]).
pub fn hints(scenario: Scenario) -> &'static [Hint] {
    match scenario {
        Scenario::Movement => &MOVEMENT_HINTS,
        Scenario::Patrol => &PATROL_HINTS,
    }
}

/// The observations the robot can make in `scenario`, in bit order.
pub fn observations(scenario: Scenario) -> &'static [Cause] {
    match scenario {
        Scenario::Movement => &MOVEMENT,
        Scenario::Patrol => &PATROL,
    }
}

/// What the robot perceived of the run in `trace` up to time `until` (s), the moment the
/// command ended (the outcome's duration), as bits over `declared` (a scenario's
/// [`observations`]; an event whose name is not declared is not reported).
pub fn perceive(trace: &Trace, until: f64, declared: &[Cause]) -> Observations {
    let perceived = trace.events.iter().filter_map(|event| {
        let name = match event.kind {
            EventKind::Collision { .. } => COLLISION,
            EventKind::Stuck => STUCK,
            EventKind::Detonation { .. } => DETONATION,
            EventKind::BehindPlan { .. } => BEHIND_PLAN,
            // Its lidar sees a person who is there, not a spot where one might be.
            EventKind::PassedPerson {
                present: true,
                gap,
                speed,
                ..
            } if gap < NEAR_PERSON_GAP && speed > WALKING_PACE => NEAR_PERSON_FAST,
            EventKind::ClosestPass { gap, .. } if gap < CLOSE_PASS_GAP => CLOSE_PASS,
            // Its own label: it knows it raised the alarm, and believes it right.
            EventKind::Labelled {
                labelled_explosive: true,
                ..
            } => RAISED_ALARM,
            // Not perceivable: an object it never saw, a label it believes, a scan it chose.
            _ => return None,
        };
        Some((event.t, name))
    });
    Observations::named_until(declared, until, perceived)
}

/// The robot's own confidence that the command of `trace` went as it should, up to time
/// `until` (s): the least, over the objects it scanned and labelled, of the chance the
/// `detector` labels an object of the kind it said correctly from a scan like its own (the
/// gap and the time it scanned, both of which it knows). It trusts its label's kind, as it
/// trusts its own alarms; what it doubts is a scan too short or too far for its detector.
/// `None` when it labelled nothing (no self-assessment: a movement run, a patrol that
/// scanned nothing).
pub fn self_assessment(trace: &Trace, until: f64, detector: &Detector) -> Option<f64> {
    let mut scan = None;
    let mut confidence: Option<f64> = None;
    for event in trace.events.iter().take_while(|e| e.t <= until) {
        match event.kind {
            EventKind::Scanned {
                distance, duration, ..
            } => scan = Some((distance, duration)),
            EventKind::Labelled {
                labelled_explosive, ..
            } => {
                if let Some((distance, duration)) = scan.take() {
                    let sure = detector.accuracy(labelled_explosive, duration, distance);
                    confidence = Some(confidence.map_or(sure, |c| c.min(sure)));
                }
            }
            _ => {}
        }
    }
    confidence
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Vec2;

    #[test]
    fn the_robot_doubts_its_worst_scan_and_has_no_self_assessment_without_one() {
        let detector = Detector::default();
        let scanned = |object, distance, duration| EventKind::Scanned {
            object,
            distance,
            duration,
        };
        let labelled = |object, labelled_explosive| EventKind::Labelled {
            object,
            explosive: false,
            labelled_explosive,
        };
        let t = trace(&[
            (1.0, scanned(0, 0.1, 3.0)),
            (1.0, labelled(0, false)),
            (4.0, scanned(1, 1.5, 0.5)),
            (4.0, labelled(1, true)),
            (9.0, EventKind::Arrived { at: O }),
        ]);
        let close = detector.accuracy(false, 3.0, 0.1);
        let far = detector.accuracy(true, 0.5, 1.5);
        assert!(far < close);
        assert_eq!(self_assessment(&t, 2.0, &detector), Some(close));
        assert_eq!(self_assessment(&t, 9.0, &detector), Some(far));
        assert_eq!(self_assessment(&t, 0.5, &detector), None);
    }

    fn trace(events: &[(f64, EventKind)]) -> Trace {
        Trace::of(events)
    }

    const O: Vec2 = Vec2::new(0.0, 0.0);

    /// The bit of observation `name` in the patrol robot's list.
    fn seen(names: &[Cause]) -> Observations {
        Observations::named(&PATROL, names.iter().copied())
    }

    #[test]
    fn each_scenario_declares_what_its_robot_perceives() {
        assert_eq!(observations(Scenario::Movement), MOVEMENT);
        assert!(observations(Scenario::Patrol).contains(&DETONATION));
        assert!(!observations(Scenario::Movement).contains(&DETONATION));
        // Nothing the robot cannot perceive is ever declared.
        for name in ["missed-object", "false-alarm", "deadline", "poor-scan"] {
            assert!(!PATROL.iter().any(|p| p.as_str() == name), "{name}");
        }
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
        assert_eq!(perceive(&t, 1.0, &PATROL), Observations::NONE);
        assert_eq!(perceive(&t, 2.0, &PATROL), seen(&[COLLISION]));
        assert_eq!(
            perceive(&t, 12.0, &PATROL),
            seen(&[COLLISION, NEAR_PERSON_FAST, BEHIND_PLAN])
        );
        // In movement's bit order: collision 0, behind-plan 2, near-person-fast 3.
        assert_eq!(
            perceive(&t, 12.0, &MOVEMENT),
            Observations::NONE.with(0).with(2).with(3)
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
        let fast = seen(&[NEAR_PERSON_FAST]);
        assert_eq!(perceive(&pass(true, 1.0, 2.0), 9.0, &PATROL), fast);
        assert!(perceive(&pass(true, 1.5, 2.0), 9.0, &PATROL).is_empty());
        assert!(perceive(&pass(true, 1.0, 1.0), 9.0, &PATROL).is_empty());
        // An empty spot is nothing to see.
        assert!(perceive(&pass(false, 0.2, 9.0), 9.0, &PATROL).is_empty());
        let close = |gap| trace(&[(1.0, EventKind::ClosestPass { gap, at: O })]);
        assert_eq!(perceive(&close(0.05), 9.0, &PATROL), seen(&[CLOSE_PASS]));
        assert!(perceive(&close(0.3), 9.0, &PATROL).is_empty());
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
        // It knows it raised an alarm; that the alarm was false, it does not: a true alarm
        // looks the same to it.
        assert_eq!(perceive(&t, 500.0, &PATROL), seen(&[RAISED_ALARM]));
        let mut right = t.clone();
        right.events[2].kind = EventKind::Labelled {
            object: 1,
            explosive: true,
            labelled_explosive: true,
        };
        assert_eq!(perceive(&right, 500.0, &PATROL), seen(&[RAISED_ALARM]));
        // Without the alarm, nothing of it is perceived; movement raises none.
        assert!(perceive(&t, 1.5, &PATROL).is_empty());
        assert!(perceive(&t, 500.0, &MOVEMENT).is_empty());
    }
}
