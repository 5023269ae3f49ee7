//! The inverse trust estimate (SPEC section 2).
//!
//! Every command the operator issues ends completed (+1), failed (-1) or interrupted (-1),
//! weighted by `w`. The estimate of a behavior is the weighted sum since it was adopted;
//! two thresholds turn it into a verdict.

use crate::cause::Cause;
use serde::{Deserialize, Serialize};

/// How a command ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum OutcomeKind {
    /// The robot completed the command (+1).
    Completed,
    /// The robot failed the command (-1).
    Failed,
    /// The operator stopped the robot (-1).
    Interrupted,
}

impl OutcomeKind {
    /// The sign the outcome contributes to the estimate: +1 or -1.
    pub fn sign(self) -> f64 {
        match self {
            Self::Completed => 1.0,
            Self::Failed | Self::Interrupted => -1.0,
        }
    }
}

/// The result of one command: how it ended, how much it weighs, why, and how long it took.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Outcome {
    /// How the command ended.
    pub kind: OutcomeKind,
    /// Its weight `w >= 0` (the paper keeps weights in `[0, 1]`).
    pub weight: f64,
    /// Why it failed or was interrupted, one of the domain's declared causes; `None` for
    /// completions or when unstated.
    #[serde(default)]
    pub cause: Option<Cause>,
    /// Task time spent on the command, in seconds.
    pub duration_s: f64,
}

/// Why an outcome cannot be recorded.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum OutcomeError {
    /// The weight is negative or not a number.
    #[error("weight must be a finite number >= 0, got {0}")]
    Weight(f64),
    /// The duration is negative or not a number.
    #[error("duration_s must be a finite number >= 0, got {0}")]
    Duration(f64),
}

impl Outcome {
    /// An outcome of any kind: how it ended, its weight, why (`None` for completions or
    /// when unstated) and how long it took, for callers that know the kind only at run
    /// time.
    pub fn new(kind: OutcomeKind, weight: f64, cause: Option<Cause>, duration_s: f64) -> Self {
        Self {
            kind,
            weight,
            cause,
            duration_s,
        }
    }

    /// A completion with weight `weight` that took `duration_s` seconds.
    pub fn completed(weight: f64, duration_s: f64) -> Self {
        Self {
            kind: OutcomeKind::Completed,
            weight,
            cause: None,
            duration_s,
        }
    }

    /// A failure with a cause.
    pub fn failed(weight: f64, cause: Cause, duration_s: f64) -> Self {
        Self {
            kind: OutcomeKind::Failed,
            weight,
            cause: Some(cause),
            duration_s,
        }
    }

    /// An interruption with a cause.
    pub fn interrupted(weight: f64, cause: Cause, duration_s: f64) -> Self {
        Self {
            kind: OutcomeKind::Interrupted,
            weight,
            cause: Some(cause),
            duration_s,
        }
    }

    /// Checks that the numbers are usable.
    pub fn validate(&self) -> Result<(), OutcomeError> {
        if !(self.weight.is_finite() && self.weight >= 0.0) {
            return Err(OutcomeError::Weight(self.weight));
        }
        if !(self.duration_s.is_finite() && self.duration_s >= 0.0) {
            return Err(OutcomeError::Duration(self.duration_s));
        }
        Ok(())
    }

    /// The signed, weighted contribution `w * cmd` to the estimate.
    pub fn contribution(&self) -> f64 {
        self.weight * self.kind.sign()
    }
}

/// The two thresholds of the estimate. Deserialization checks them ([`Thresholds::validate`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "ThresholdsDefinition")]
pub struct Thresholds {
    /// At or above this the behavior is trustworthy (`tau_T`, paper: +5).
    pub trustworthy: f64,
    /// At or below this the behavior is untrustworthy (`tau_UT`, paper: -5).
    pub untrustworthy: f64,
}

impl Default for Thresholds {
    fn default() -> Self {
        Self {
            trustworthy: 5.0,
            untrustworthy: -5.0,
        }
    }
}

/// Thresholds that cannot be used.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "thresholds must be finite with untrustworthy < 0 < trustworthy (every behavior's estimate starts at 0, so a verdict needs evidence), got untrustworthy = {untrustworthy}, trustworthy = {trustworthy}"
)]
pub struct ThresholdError {
    /// The trustworthy threshold given.
    pub trustworthy: f64,
    /// The untrustworthy threshold given.
    pub untrustworthy: f64,
}

/// The thresholds as written, before they are checked.
#[derive(Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
struct ThresholdsDefinition {
    trustworthy: f64,
    untrustworthy: f64,
}

impl TryFrom<ThresholdsDefinition> for Thresholds {
    type Error = ThresholdError;

    fn try_from(d: ThresholdsDefinition) -> Result<Self, ThresholdError> {
        let thresholds = Self {
            trustworthy: d.trustworthy,
            untrustworthy: d.untrustworthy,
        };
        thresholds.validate()?;
        Ok(thresholds)
    }
}

impl Thresholds {
    /// Checks that both are finite and ordered.
    pub fn validate(&self) -> Result<(), ThresholdError> {
        if self.trustworthy.is_finite()
            && self.untrustworthy.is_finite()
            && self.untrustworthy < 0.0
            && 0.0 < self.trustworthy
        {
            Ok(())
        } else {
            Err(ThresholdError {
                trustworthy: self.trustworthy,
                untrustworthy: self.untrustworthy,
            })
        }
    }
}

/// What the estimate says about the behavior in use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Verdict {
    /// The estimate reached the trustworthy threshold: keep the behavior.
    Trustworthy,
    /// The estimate reached the untrustworthy threshold: adapt.
    Untrustworthy,
    /// Keep evaluating.
    Undecided,
}

/// The running estimate of one behavior since it was adopted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TrustEstimate {
    /// `sum_i w_i * cmd_i`.
    pub value: f64,
    /// Task seconds spent with the behavior (the `t` of an evaluated pair).
    pub elapsed_s: f64,
    /// Commands recorded.
    pub commands: u32,
}

impl TrustEstimate {
    /// Adds one command's outcome (assumed valid).
    pub fn record(&mut self, outcome: &Outcome) {
        self.value += outcome.contribution();
        self.elapsed_s += outcome.duration_s;
        self.commands += 1;
    }

    /// The verdict under `thresholds`.
    pub fn verdict(&self, thresholds: &Thresholds) -> Verdict {
        if self.value >= thresholds.trustworthy {
            Verdict::Trustworthy
        } else if self.value <= thresholds.untrustworthy {
            Verdict::Untrustworthy
        } else {
            Verdict::Undecided
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TOO_SLOW: Cause = Cause::from_static("too-slow");
    const DROPPED: Cause = Cause::from_static("dropped-item");

    #[test]
    fn weighted_sum_and_verdicts() {
        let t = Thresholds::default();
        let mut e = TrustEstimate::default();
        // Completions and slow runs weigh 1/3, a dropped item 1.
        e.record(&Outcome::completed(1.0 / 3.0, 20.0));
        e.record(&Outcome::interrupted(1.0 / 3.0, TOO_SLOW, 5.0));
        e.record(&Outcome::failed(1.0, DROPPED, 40.0));
        // 1/3 - 1/3 - 1 = -1
        assert!((e.value + 1.0).abs() < 1e-12);
        assert_eq!(e.elapsed_s, 65.0);
        assert_eq!(e.commands, 3);
        assert_eq!(e.verdict(&t), Verdict::Undecided);
        // Four more failures of weight 1: -1 - 4 = -5 <= -5.
        for _ in 0..4 {
            e.record(&Outcome::failed(1.0, DROPPED, 1.0));
        }
        assert_eq!(e.verdict(&t), Verdict::Untrustworthy);
        let mut good = TrustEstimate::default();
        for _ in 0..5 {
            good.record(&Outcome::completed(1.0, 1.0));
        }
        // 5 completions of weight 1: 5 >= 5.
        assert_eq!(good.verdict(&t), Verdict::Trustworthy);
    }

    #[test]
    fn thresholds_are_checked_when_read() {
        let e = ron::from_str::<Thresholds>("(trustworthy: -5.0, untrustworthy: 5.0)").unwrap_err();
        assert!(
            e.code
                .to_string()
                .contains("untrustworthy < 0 < trustworthy")
        );
        assert!(
            ron::from_str::<Thresholds>("(trustworthy: 5.0, untrustworthy: -5.0, x: 1)").is_err()
        );
        let t: Thresholds = ron::from_str("(trustworthy: 2.0, untrustworthy: -1.0)").unwrap();
        assert_eq!(t.untrustworthy, -1.0);
    }

    #[test]
    fn bad_numbers_are_rejected() {
        assert_eq!(
            Outcome::completed(f64::NAN, 1.0)
                .validate()
                .unwrap_err()
                .to_string(),
            "weight must be a finite number >= 0, got NaN"
        );
        assert!(Outcome::completed(-1.0, 1.0).validate().is_err());
        assert!(Outcome::completed(1.0, -1.0).validate().is_err());
        assert!(Outcome::completed(3.0, 0.0).validate().is_ok());
        // Inverted, and both on one side of the starting estimate 0 (a verdict before
        // any command): refused.
        for (trustworthy, untrustworthy) in [(-5.0, 5.0), (-1.0, -5.0), (5.0, 1.0), (5.0, 0.0)] {
            assert!(
                Thresholds {
                    trustworthy,
                    untrustworthy
                }
                .validate()
                .is_err(),
                "{trustworthy} / {untrustworthy}"
            );
        }
    }
}
