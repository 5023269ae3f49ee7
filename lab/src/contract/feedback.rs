//! The operator's feedback channel: how often an operator explains an untrustworthy
//! command, and how often its explanation is wrong.
//!
//! The paper's robot is told nothing ("infers that any interruptions are a result of the
//! operator being unsatisfied"): [`FeedbackChannel::SILENT`], the default. Operators who do
//! explain do it now and then, and not always rightly. A channel turns the truth of a
//! simulated command (the operator's real reason, [`Judgement::truth`](crate::contract::judgement::Judgement::truth))
//! into what the robot is told ([`Outcome::stated`](trust::Outcome)).

use rand::{Rng, RngCore};
use serde::{Deserialize, Serialize};
use trust::{Cause, DeclaredCause};

/// How an operator explains itself.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "ChannelDefinition")]
pub struct FeedbackChannel {
    /// The share of untrustworthy commands (failed or interrupted) the operator explains.
    pub explains: f64,
    /// The share of explanations that name a wrong reason (another declared cause, drawn
    /// uniformly).
    pub wrong: f64,
    /// The share of goal changes ([`crate::experiment::goal_change`]) the operator says were goal
    /// changes ([`trust::Outcome::goal_change`]); 0 by default (and then not written).
    #[serde(skip_serializing_if = "says_none")]
    pub goal_changes: f64,
}

fn says_none(goal_changes: &f64) -> bool {
    *goal_changes <= 0.0
}

/// A channel as written, before it is checked.
#[derive(Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
struct ChannelDefinition {
    #[serde(default)]
    explains: f64,
    #[serde(default)]
    wrong: f64,
    #[serde(default)]
    goal_changes: f64,
}

/// A channel whose shares are not probabilities.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "feedback `{field}` must be a probability in [0, 1], got {}",
    cbr_core::Shown(*.value)
)]
pub struct FeedbackError {
    /// `explains`, `wrong` or `goal_changes`.
    pub field: &'static str,
    /// The value given.
    pub value: f64,
}

impl TryFrom<ChannelDefinition> for FeedbackChannel {
    type Error = FeedbackError;

    fn try_from(d: ChannelDefinition) -> Result<Self, FeedbackError> {
        Self::new(d.explains, d.wrong)?.saying_goal_changes(d.goal_changes)
    }
}

impl Default for FeedbackChannel {
    fn default() -> Self {
        Self::SILENT
    }
}

/// `value` when it is a share (in `[0, 1]`), else the error naming `field`.
fn share(field: &'static str, value: f64) -> Result<f64, FeedbackError> {
    if (0.0..=1.0).contains(&value) {
        Ok(value)
    } else {
        Err(FeedbackError { field, value })
    }
}

impl FeedbackChannel {
    /// The paper's operator: it never explains.
    pub const SILENT: Self = Self {
        explains: 0.0,
        wrong: 0.0,
        goal_changes: 0.0,
    };

    /// A channel explaining a share `explains` of untrustworthy commands, a share `wrong`
    /// of them wrongly.
    pub fn new(explains: f64, wrong: f64) -> Result<Self, FeedbackError> {
        Ok(Self {
            explains: share("explains", explains)?,
            wrong: share("wrong", wrong)?,
            goal_changes: 0.0,
        })
    }

    /// The same channel saying a share `goal_changes` of goal changes.
    pub fn saying_goal_changes(self, goal_changes: f64) -> Result<Self, FeedbackError> {
        Ok(Self {
            goal_changes: share("goal_changes", goal_changes)?,
            ..self
        })
    }

    /// Whether the operator never explains an untrustworthy command (it may still say a
    /// goal change).
    pub fn is_silent(&self) -> bool {
        self.explains <= 0.0
    }

    /// Whether the operator says that a command its goals changed during was stopped for
    /// that. Draws from `rng` only when the channel says some goal changes and not all,
    /// so a channel that says none never changes a random stream.
    pub fn says_goal_change(&self, rng: &mut dyn RngCore) -> bool {
        if self.goal_changes <= 0.0 {
            return false;
        }
        self.goal_changes >= 1.0 || rng.random::<f64>() < self.goal_changes
    }

    /// What the operator says of a command whose real reason is `truth` (`None`: it
    /// completed, nothing to explain), among the domain's `declared` causes. Draws from
    /// `rng` only when there is something to explain and the channel is open, so a silent
    /// channel never changes a random stream.
    pub fn state(
        &self,
        truth: Option<Cause>,
        declared: &[DeclaredCause],
        rng: &mut dyn RngCore,
    ) -> Option<Cause> {
        let truth = truth?;
        if self.is_silent() || rng.random::<f64>() >= self.explains {
            return None;
        }
        if self.wrong <= 0.0 || rng.random::<f64>() >= self.wrong {
            return Some(truth);
        }
        let others: Vec<Cause> = declared
            .iter()
            .map(|d| d.name)
            .filter(|&c| c != truth)
            .collect();
        if others.is_empty() {
            // No other reason to name: the explanation cannot be wrong.
            return Some(truth);
        }
        Some(others[rng.random_range(0..others.len())])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    const SLOW: Cause = Cause::from_static("too-slow");
    const DROP: Cause = Cause::from_static("dropped-item");
    const BUMP: Cause = Cause::from_static("bump");

    fn declared() -> [DeclaredCause; 3] {
        [
            DeclaredCause::new(SLOW),
            DeclaredCause::new(DROP),
            DeclaredCause::new(BUMP),
        ]
    }

    #[test]
    fn a_silent_channel_says_nothing_and_draws_nothing() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let before = rng.clone();
        for _ in 0..100 {
            assert_eq!(
                FeedbackChannel::SILENT.state(Some(SLOW), &declared(), &mut rng),
                None
            );
        }
        assert_eq!(rng, before);
        // A completion is never explained, and draws nothing either.
        let open = FeedbackChannel::new(1.0, 0.5).unwrap();
        assert_eq!(open.state(None, &declared(), &mut rng), None);
        assert_eq!(rng, before);
    }

    #[test]
    fn shares_are_what_the_channel_says() {
        let channel = FeedbackChannel::new(0.3, 0.1).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let n = 100_000;
        let (mut told, mut wrong) = (0, 0);
        for _ in 0..n {
            if let Some(c) = channel.state(Some(SLOW), &declared(), &mut rng) {
                told += 1;
                if c != SLOW {
                    wrong += 1;
                    assert!(c == DROP || c == BUMP);
                }
            }
        }
        let told_share = f64::from(told) / f64::from(n);
        let wrong_share = f64::from(wrong) / f64::from(told);
        assert!((told_share - 0.3).abs() < 0.01, "{told_share}");
        assert!((wrong_share - 0.1).abs() < 0.01, "{wrong_share}");
    }

    #[test]
    fn always_right_and_a_single_cause_cannot_be_wrong() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let honest = FeedbackChannel::new(1.0, 0.0).unwrap();
        assert_eq!(honest.state(Some(DROP), &declared(), &mut rng), Some(DROP));
        let liar = FeedbackChannel::new(1.0, 1.0).unwrap();
        assert_ne!(liar.state(Some(DROP), &declared(), &mut rng), Some(DROP));
        let one = [DeclaredCause::new(DROP)];
        assert_eq!(liar.state(Some(DROP), &one, &mut rng), Some(DROP));
    }

    #[test]
    fn shares_are_checked_when_read() {
        let c: FeedbackChannel = ron::from_str("(explains: 0.3, wrong: 0.1)").unwrap();
        assert_eq!(c, FeedbackChannel::new(0.3, 0.1).unwrap());
        let c: FeedbackChannel = ron::from_str("(explains: 1.0)").unwrap();
        assert_eq!(c.wrong, 0.0);
        let e = ron::from_str::<FeedbackChannel>("(explains: 1.5)").unwrap_err();
        assert!(
            e.code
                .to_string()
                .contains("feedback `explains` must be a probability in [0, 1], got 1.5")
        );
    }
}
