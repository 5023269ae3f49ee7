//! The causes of failure of the UGV tasks, as the movement and patrol scenarios declare
//! them ([`trust::Domain::causes`]).
//!
//! A movement run can end early only by the deadline, a collision or a stuck robot; a
//! patrol run adds the three endings its suspicious objects bring (an object left
//! unscanned, a harmless one labelled explosive, an explosive labelled harmless going
//! off). No cause declares a default weight: the paper gives weights per operator, so an
//! operator file's `weights` say what each cause weighs (`docs/simulation.md`).

use trust::{Cause, DeclaredCause};

/// The task was not done in the time the operator allows.
pub const DEADLINE: Cause = Cause::from_static("deadline");
/// The robot hit an obstacle.
pub const COLLISION: Cause = Cause::from_static("collision");
/// The robot could not go on (no way through).
pub const STUCK: Cause = Cause::from_static("stuck");
/// The robot left a suspicious object unscanned.
pub const MISSED_OBJECT: Cause = Cause::from_static("missed-object");
/// The robot labelled a harmless object explosive.
pub const FALSE_ALARM: Cause = Cause::from_static("false-alarm");
/// An explosive the robot labelled harmless went off.
pub const DETONATION: Cause = Cause::from_static("detonation");

/// Every UGV cause, in the order reports list them.
pub const ALL: [Cause; 6] = [
    DEADLINE,
    COLLISION,
    STUCK,
    MISSED_OBJECT,
    FALSE_ALARM,
    DETONATION,
];

/// The causes a movement run can end with.
pub const MOVEMENT: [DeclaredCause; 3] = [
    DeclaredCause::new(DEADLINE),
    DeclaredCause::new(COLLISION),
    DeclaredCause::new(STUCK),
];

/// The causes a patrol run can end with: every UGV cause.
pub const PATROL: [DeclaredCause; 6] = [
    DeclaredCause::new(DEADLINE),
    DeclaredCause::new(COLLISION),
    DeclaredCause::new(STUCK),
    DeclaredCause::new(MISSED_OBJECT),
    DeclaredCause::new(FALSE_ALARM),
    DeclaredCause::new(DETONATION),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patrol_declares_every_cause_and_movement_the_first_three() {
        let names = |d: &[DeclaredCause]| d.iter().map(|c| c.name).collect::<Vec<_>>();
        assert_eq!(names(&PATROL), ALL);
        assert_eq!(names(&MOVEMENT), ALL[..3]);
        let shown: Vec<String> = ALL.iter().map(Cause::to_string).collect();
        assert_eq!(
            shown,
            [
                "deadline",
                "collision",
                "stuck",
                "missed-object",
                "false-alarm",
                "detonation"
            ]
        );
    }
}
