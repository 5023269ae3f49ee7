//! Goal changes in simulation: interruptions that are not about the behavior, their rate,
//! and what a trial records of them.
//!
//! The paper counts every interruption against the behavior in use and assumes those
//! caused by a change in the operator's goals "occur rarely". An experiment with
//! [`GoalChanges`] lets them happen: the operator's goals change at moments of a Poisson
//! process over task time (a threat appearing, a new tasking arriving, neither of which
//! the robot's behavior causes), at `per_hour` on average; a command under way at such a
//! moment is interrupted then ([`GoalChanging::run_redirected`](crate::GoalChanging::run_redirected)).
//! The process is memoryless, so each command draws the moment of the next change afresh
//! from its start, on a stream of its own ([`crate::seeds::Purpose::GoalChange`]): an
//! experiment without goal changes draws nothing from it and runs as before.
//!
//! Whether the operator says so is its feedback channel's
//! ([`crate::FeedbackChannel::goal_changes`]). A trial records what happened
//! ([`GoalChangeRecord`]): the goal changes, those said, and how the robot's guess of an
//! unsaid one from what it perceived ([`trust::goal_change::looks_like_goal_change`])
//! compares with the truth. docs/simulation.md argues the rates; docs/model.md says how
//! the adapter treats a said goal change.

use crate::Judgement;
use rand::{Rng, RngCore};
use serde::{Deserialize, Serialize};
use trust::{Outcome, OutcomeKind};

/// Goal changes, with the plan's domain as one that models them
/// ([`crate::contract::capability`]: a plan over a domain that does not is refused by the
/// compiler, or where a file's plan enters).
pub type GoalChangesOn<'a, O> = crate::contract::capability::Needing<
    'a,
    GoalChanges,
    dyn crate::GoalChanging<Operator = O> + 'a,
>;

/// How often an operator's goals change, as an experiment sets it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "GoalChangesDefinition")]
pub struct GoalChanges {
    /// Goal changes per hour of task time, on average (in `(0, 3600]`).
    pub per_hour: f64,
}

/// Goal changes as written, before they are checked.
#[derive(Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
struct GoalChangesDefinition {
    per_hour: f64,
}

/// A rate that cannot be used.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "goal_changes `per_hour` must be a number in (0, 3600] (goal changes per hour of task time; leave `goal_changes` out for none), got {}",
    cbr_core::Shown(*.0)
)]
pub struct GoalChangesError(pub f64);

impl TryFrom<GoalChangesDefinition> for GoalChanges {
    type Error = GoalChangesError;

    fn try_from(d: GoalChangesDefinition) -> Result<Self, GoalChangesError> {
        Self::new(d.per_hour)
    }
}

impl GoalChanges {
    /// Goal changes at `per_hour` per hour of task time.
    pub fn new(per_hour: f64) -> Result<Self, GoalChangesError> {
        if per_hour > 0.0 && per_hour <= 3600.0 {
            Ok(Self { per_hour })
        } else {
            Err(GoalChangesError(per_hour))
        }
    }

    /// Seconds from now to the next goal change: exponential with mean `3600 /
    /// per_hour`, one draw from `rng`.
    pub fn next_at(&self, rng: &mut dyn RngCore) -> f64 {
        let u: f64 = rng.random();
        // 1 - u is in (0, 1]: its logarithm is finite.
        -(1.0 - u).ln() * 3600.0 / self.per_hour
    }
}

/// What a trial's goal changes were, for evaluation: how many commands they cut, how
/// many the operator said, and the robot's guess of the unsaid ones against the truth.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct GoalChangeRecord {
    /// Commands a goal change interrupted.
    pub happened: u32,
    /// Of those, the ones the operator said were goal changes.
    pub said: u32,
    /// Unsaid goal changes the robot's guess took for goal changes.
    pub guessed: u32,
    /// Interruptions about the behavior the guess took for goal changes.
    pub false_guesses: u32,
    /// Interruptions about the behavior (every one, guessed or not).
    pub about_behavior: u32,
}

impl GoalChangeRecord {
    /// Adds one command: the domain's `judgement` (the truth) and the `outcome` the robot
    /// was told.
    pub fn record(&mut self, judgement: &Judgement, outcome: &Outcome) {
        let guessed = trust::goal_change::looks_like_goal_change(outcome);
        if judgement.redirected {
            self.happened += 1;
            self.said += u32::from(outcome.goal_change);
            self.guessed += u32::from(guessed);
        } else if outcome.kind == OutcomeKind::Interrupted {
            self.about_behavior += 1;
            self.false_guesses += u32::from(guessed);
        }
    }

    /// Goal changes the operator did not say.
    pub fn unsaid(&self) -> u32 {
        self.happened - self.said
    }

    /// The sum of two records (a report pools an arm's trials).
    #[must_use]
    pub fn plus(self, other: Self) -> Self {
        Self {
            happened: self.happened + other.happened,
            said: self.said + other.said,
            guessed: self.guessed + other.guessed,
            false_guesses: self.false_guesses + other.false_guesses,
            about_behavior: self.about_behavior + other.about_behavior,
        }
    }

    /// The guess's recall: the share of unsaid goal changes it took for goal changes
    /// (`None` without one).
    pub fn recall(&self) -> Option<f64> {
        let unsaid = self.unsaid();
        (unsaid > 0).then(|| f64::from(self.guessed) / f64::from(unsaid))
    }

    /// The guess's precision: the share of its guesses that were goal changes (`None`
    /// without a guess).
    pub fn precision(&self) -> Option<f64> {
        let guesses = self.guessed + self.false_guesses;
        (guesses > 0).then(|| f64::from(self.guessed) / f64::from(guesses))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
    use trust::{Cause, Observations};

    const SLOW: Cause = Cause::from_static("slow");

    #[test]
    fn rates_are_checked() {
        assert!(GoalChanges::new(1.0).is_ok());
        assert!(GoalChanges::new(3600.0).is_ok());
        for bad in [0.0, -1.0, 3600.5, f64::NAN, f64::INFINITY] {
            assert!(GoalChanges::new(bad).is_err(), "{bad}");
        }
        let err: Result<GoalChanges, _> = ron::from_str("(per_hour: 0.0)");
        assert!(
            err.unwrap_err()
                .to_string()
                .contains("goal_changes `per_hour` must be a number in (0, 3600]")
        );
        assert!(ron::from_str::<GoalChanges>("(per_hour: 1.0, said: 1.0)").is_err());
    }

    #[test]
    fn the_moments_are_exponential_with_the_rate_s_mean() {
        let changes = GoalChanges::new(4.0).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let n = 200_000;
        let draws: Vec<f64> = (0..n).map(|_| changes.next_at(&mut rng)).collect();
        let mean = draws.iter().sum::<f64>() / f64::from(n);
        // Mean 900 s; its standard error is 900 / sqrt(n), about 2 s.
        assert!((mean - 900.0).abs() < 10.0, "{mean}");
        // P(T > 900 s) = e^-1.
        let beyond = draws.iter().filter(|&&t| t > 900.0).count() as f64 / f64::from(n);
        assert!((beyond - (-1.0f64).exp()).abs() < 0.005, "{beyond}");
        assert!(draws.iter().all(|t| t.is_finite() && *t >= 0.0));
    }

    #[test]
    fn a_record_counts_the_truth_against_what_was_said_and_guessed() {
        let mut record = GoalChangeRecord::default();
        let cut = Judgement::redirected(1.0, 5.0);
        // Said; unsaid and guessed (nothing perceived); unsaid and missed (a bump seen).
        record.record(&cut, &cut.outcome.saying_goal_change(true));
        record.record(&cut, &cut.outcome);
        let seen = cut.observing(Observations::NONE.with(0));
        record.record(&seen, &seen.outcome);
        // Interruptions about the behavior: one guessed wrongly, one not (perceived).
        let slow = Judgement::interrupted(1.0, SLOW, 9.0);
        record.record(&slow, &slow.outcome);
        let seen_slow = slow.observing(Observations::NONE.with(1));
        record.record(&seen_slow, &seen_slow.outcome);
        // A completion and a failure count for nothing here.
        let done = Judgement::completed(1.0, 9.0);
        record.record(&done, &done.outcome);
        let failed = Judgement::failed(1.0, SLOW, 9.0);
        record.record(&failed, &failed.outcome);
        assert_eq!(
            record,
            GoalChangeRecord {
                happened: 3,
                said: 1,
                guessed: 1,
                false_guesses: 1,
                about_behavior: 2,
            }
        );
        assert_eq!(record.unsaid(), 2);
        assert_eq!(record.recall(), Some(0.5));
        assert_eq!(record.precision(), Some(0.5));
        assert_eq!(GoalChangeRecord::default().recall(), None);
        assert_eq!(record.plus(record).happened, 6);
    }
}
