//! Goal changes: interruptions that are not about the behavior (docs/model.md, "Goal
//! changes").
//!
//! The paper counts every interruption against the behavior in use and assumes that those
//! caused by a change in the operator's goals "occur rarely". An operator may say that its
//! goals changed ([`Outcome::goal_change`]): the adapter then counts the command against
//! nothing. When it does not say so, the robot can only guess from what it perceived;
//! [`looks_like_goal_change`] is that guess, measured against the simulator's truth by the
//! laboratory's reports and used by nothing that decides.

use crate::estimate::{Outcome, OutcomeKind};

/// Whether `outcome` looks like an unsaid goal change: an interruption the operator gave
/// no reason for, during which the robot perceived nothing at all. Every reaction an
/// operator has to the behavior itself follows something that happened on the run, and
/// the robot perceives much of what happens (a bump, a close pass, running late); an
/// operator whose goals changed stops the robot whatever it was doing. The guess errs both
/// ways: a goal change that came after something was perceived is missed, and a reaction
/// to something the robot cannot perceive is taken for a goal change.
///
/// ```
/// use trust::goal_change::looks_like_goal_change;
/// use trust::{Observations, Outcome};
///
/// assert!(looks_like_goal_change(&Outcome::interrupted(1.0, 30.0)));
/// // Something was perceived: more likely a reaction to it.
/// let bumped = Outcome::interrupted(1.0, 30.0).observing(Observations::NONE.with(0));
/// assert!(!looks_like_goal_change(&bumped));
/// // Said, it is no guess; a failure is the robot's own.
/// assert!(!looks_like_goal_change(&Outcome::interrupted(1.0, 30.0).saying_goal_change(true)));
/// assert!(!looks_like_goal_change(&Outcome::failed(1.0, 30.0)));
/// ```
pub fn looks_like_goal_change(outcome: &Outcome) -> bool {
    outcome.kind == OutcomeKind::Interrupted
        && !outcome.goal_change
        && outcome.stated.is_none()
        && outcome.observed.is_empty()
}
