//! The causes of failure of the UGV tasks, as the movement and patrol scenarios declare
//! them ([`lab::Domain::causes`]).
//!
//! A movement run can end early by the deadline, a collision or a stuck robot, and, for
//! operators with the preferences that watch them, by passing people too fast or anything
//! too close; a patrol run adds the three endings its suspicious objects bring (an object
//! left unscanned, a harmless one labelled explosive, an explosive labelled harmless going
//! off) and a scan the operator does not believe. The paper's six come first, so their
//! columns keep their places in reports. No cause declares a default weight: the paper
//! gives weights per operator, so an operator file's `weights` say what each cause weighs
//! (`docs/simulation.md`); and only for the causes the robot perceives itself
//! ([`PERCEIVED`]).

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

/// The robot passed a standing person closer than the operator's comfort distance and
/// faster than its comfort speed.
pub const TOO_FAST_NEAR_PEOPLE: Cause = Cause::from_static("too-fast-near-people");
/// The robot's body passed closer to an obstacle or person than the operator finds safe.
pub const TOO_CLOSE: Cause = Cause::from_static("too-close");
/// The robot scanned an object from too far or too briefly for the operator to believe
/// its label.
pub const POOR_SCAN: Cause = Cause::from_static("poor-scan");

/// Every UGV cause, in the order reports list them.
pub const ALL: [Cause; 9] = [
    DEADLINE,
    COLLISION,
    STUCK,
    MISSED_OBJECT,
    FALSE_ALARM,
    DETONATION,
    TOO_FAST_NEAR_PEOPLE,
    TOO_CLOSE,
    POOR_SCAN,
];

/// The causes an operator's weights may name: those the robot perceives itself
/// ([`crate::perception`]), so that what a command is worth never depends on something
/// the robot cannot know happened.
pub const PERCEIVED: [Cause; 3] = [COLLISION, STUCK, DETONATION];

/// The causes a movement run can end with.
pub const MOVEMENT: [DeclaredCause; 5] = [
    DeclaredCause::new(DEADLINE),
    DeclaredCause::new(COLLISION),
    DeclaredCause::new(STUCK),
    DeclaredCause::new(TOO_FAST_NEAR_PEOPLE),
    DeclaredCause::new(TOO_CLOSE),
];

/// The causes a patrol run can end with: every UGV cause.
pub const PATROL: [DeclaredCause; 9] = [
    DeclaredCause::new(DEADLINE),
    DeclaredCause::new(COLLISION),
    DeclaredCause::new(STUCK),
    DeclaredCause::new(MISSED_OBJECT),
    DeclaredCause::new(FALSE_ALARM),
    DeclaredCause::new(DETONATION),
    DeclaredCause::new(TOO_FAST_NEAR_PEOPLE),
    DeclaredCause::new(TOO_CLOSE),
    DeclaredCause::new(POOR_SCAN),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patrol_declares_every_cause_and_movement_the_first_three_and_two_preferences() {
        let names = |d: &[DeclaredCause]| d.iter().map(|c| c.name).collect::<Vec<_>>();
        assert_eq!(names(&PATROL), ALL);
        assert_eq!(names(&MOVEMENT)[..3], ALL[..3]);
        assert_eq!(names(&MOVEMENT)[3..], ALL[6..8]);
        let shown: Vec<String> = ALL.iter().map(Cause::to_string).collect();
        assert_eq!(
            shown,
            [
                "deadline",
                "collision",
                "stuck",
                "missed-object",
                "false-alarm",
                "detonation",
                "too-fast-near-people",
                "too-close",
                "poor-scan"
            ]
        );
    }
}
