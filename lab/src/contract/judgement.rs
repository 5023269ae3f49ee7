//! What one simulated command yields: the [`Outcome`] the robot is told and, beside it,
//! the operator's true reason, which only evaluation reads ([`Judgement`]).
//!
//! It lives in `lab`, not in `trust`, so that nothing a robot embeds can name the truth of
//! a run.

use trust::{Cause, Observations, Outcome, OutcomeKind, OutcomeWeights};

/// One simulated command as a domain's run yields it: the [`Outcome`] the robot is told
/// (what it perceived, nothing stated yet: the operator's feedback channel adds a stated
/// reason, see [`FeedbackChannel`](crate::FeedbackChannel)) and the *truth*, the
/// operator's real reason for a failure or interruption, which only evaluation reads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Judgement {
    /// What the robot knows of the command.
    pub outcome: Outcome,
    /// Why the operator really reacted: one of the domain's declared causes; `None` for a
    /// completion.
    pub truth: Option<Cause>,
    /// A problem an attentive operator would have reacted to but this one overlooked (its
    /// attention was low: [`Attentive::run_attending`](crate::Attentive::run_attending));
    /// the run went on past it. `None` for an attentive operator. For evaluation only, as
    /// the truth.
    pub overlooked: Option<Cause>,
    /// The operator stopped the command because its goals changed, not because of the
    /// behavior ([`GoalChanging::run_redirected`](crate::GoalChanging::run_redirected));
    /// `truth` is then `None`. For evaluation only, as the truth: the robot is told only if
    /// the operator says so ([`trust::Outcome::goal_change`]).
    pub redirected: bool,
}

impl Judgement {
    /// A completion: nothing to explain.
    pub fn completed(weight: f64, duration_s: f64) -> Self {
        Self {
            outcome: Outcome::completed(weight, duration_s),
            truth: None,
            overlooked: None,
            redirected: false,
        }
    }

    /// An interruption because the operator's goals changed, `at_s` seconds in, weighed
    /// `weight` (what the operator's interruptions weigh when the robot cannot tell why).
    pub fn redirected(weight: f64, at_s: f64) -> Self {
        Self {
            redirected: true,
            ..Self::new(OutcomeKind::Interrupted, weight, None, at_s)
        }
    }

    /// A failure whose real reason is `truth`.
    pub fn failed(weight: f64, truth: Cause, duration_s: f64) -> Self {
        Self {
            outcome: Outcome::failed(weight, duration_s),
            truth: Some(truth),
            overlooked: None,
            redirected: false,
        }
    }

    /// An interruption whose real reason is `truth`.
    pub fn interrupted(weight: f64, truth: Cause, duration_s: f64) -> Self {
        Self {
            outcome: Outcome::interrupted(weight, duration_s),
            truth: Some(truth),
            overlooked: None,
            redirected: false,
        }
    }

    /// A judgement of any kind (`truth` `None` for completions), for callers that know the
    /// kind only at run time.
    pub fn new(kind: OutcomeKind, weight: f64, truth: Option<Cause>, duration_s: f64) -> Self {
        Self {
            outcome: Outcome::new(kind, weight, duration_s),
            truth,
            overlooked: None,
            redirected: false,
        }
    }

    /// A judgement of `kind` whose real reason is `truth`, weighed as an operator with
    /// `weights` weighs it: a failure or an interruption by `truth`'s weight
    /// ([`OutcomeWeights::of`]), a completion by `weights.completed` (and no truth).
    pub fn weighed(
        kind: OutcomeKind,
        truth: Cause,
        duration_s: f64,
        weights: &OutcomeWeights,
    ) -> Self {
        match kind {
            OutcomeKind::Completed => Self::completed(weights.completed, duration_s),
            OutcomeKind::Failed | OutcomeKind::Interrupted => {
                Self::new(kind, weights.of(truth), Some(truth), duration_s)
            }
        }
    }

    /// The same judgement with what the robot perceived.
    #[must_use]
    pub fn observing(self, observed: Observations) -> Self {
        Self {
            outcome: self.outcome.observing(observed),
            ..self
        }
    }

    /// The same judgement with the robot's own confidence in the command.
    #[must_use]
    pub fn assessing(self, confidence: Option<f64>) -> Self {
        Self {
            outcome: self.outcome.assessing(confidence),
            ..self
        }
    }

    /// The same judgement with a problem the operator overlooked.
    #[must_use]
    pub fn overlooking(self, overlooked: Option<Cause>) -> Self {
        Self { overlooked, ..self }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TOO_SLOW: Cause = Cause::from_static("too-slow");

    #[test]
    fn a_judgement_keeps_the_truth_beside_the_outcome() {
        let j = Judgement::interrupted(0.5, TOO_SLOW, 3.0).observing(Observations::NONE.with(1));
        assert_eq!(j.truth, Some(TOO_SLOW));
        assert_eq!(
            j.outcome.stated, None,
            "nothing is stated until a channel says so"
        );
        assert!(j.outcome.observed.contains(1));
        assert!(j.outcome.is_untrustworthy());
        assert_eq!(Judgement::completed(1.0, 1.0).truth, None);
    }

    #[test]
    fn a_weighed_judgement_takes_its_cause_s_weight_or_the_completion_s() {
        let weights = OutcomeWeights {
            completed: 0.25,
            default: 2.0,
            by_cause: [(TOO_SLOW, 4.0)].into_iter().collect(),
        };
        let bump = Cause::from_static("bump");
        assert_eq!(
            Judgement::weighed(OutcomeKind::Interrupted, TOO_SLOW, 3.0, &weights),
            Judgement::interrupted(4.0, TOO_SLOW, 3.0)
        );
        assert_eq!(
            Judgement::weighed(OutcomeKind::Failed, bump, 5.0, &weights),
            Judgement::failed(2.0, bump, 5.0)
        );
        assert_eq!(
            Judgement::weighed(OutcomeKind::Completed, bump, 6.0, &weights),
            Judgement::completed(0.25, 6.0)
        );
    }
}
