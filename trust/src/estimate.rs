//! The inverse trust estimate (docs/model.md#the-trust-estimate).
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
    /// The kind as the protocol spells it (`completed`, `failed`, `interrupted`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Completed => "completed",
            Self::Failed => "failed",
            Self::Interrupted => "interrupted",
        }
    }

    /// The sign the outcome contributes to the estimate: +1 or -1.
    pub fn sign(self) -> f64 {
        match self {
            Self::Completed => 1.0,
            Self::Failed | Self::Interrupted => -1.0,
        }
    }
}

/// What the robot perceived itself during one command: which of its domain's declared
/// observations (the lab's `Domain::observations`, at most
/// [`Observations::CAPACITY`]) happened, as bits in the order the domain declares them.
///
/// Observations come from the robot's own sensors and clock (a bump, being stuck, an
/// explosion, running behind its own plan). They are never the operator's reason: that is
/// the truth of the simulated run (the lab's `Judgement::truth`), which no searcher sees.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Observations(u32);

impl Observations {
    /// Nothing perceived.
    pub const NONE: Self = Self(0);
    /// How many observations a domain may declare.
    pub const CAPACITY: usize = 32;

    /// The set with the domain's observation number `index` added (an index at or above
    /// [`Observations::CAPACITY`] is ignored).
    #[must_use]
    pub const fn with(self, index: usize) -> Self {
        if index < Self::CAPACITY {
            Self(self.0 | 1 << index)
        } else {
            self
        }
    }

    /// The set of the observations `names`, numbered by their places in the domain's
    /// `declared` observations (the lab's `Domain::observations`, in its order); a name
    /// not declared is left out.
    ///
    /// ```
    /// use trust::{Cause, Observations};
    ///
    /// const STOP: Cause = Cause::from_static("safety-stop");
    /// const LATE: Cause = Cause::from_static("behind-plan");
    /// const DECLARED: [Cause; 2] = [STOP, LATE];
    ///
    /// let seen = Observations::named(&DECLARED, [LATE]);
    /// assert_eq!(seen, Observations::NONE.with(1));
    /// assert!(seen.contains_named(&DECLARED, LATE));
    /// assert!(!seen.contains_named(&DECLARED, STOP));
    /// assert_eq!(Observations::named(&DECLARED, [Cause::from_static("glare")]), Observations::NONE);
    /// ```
    pub fn named(declared: &[Cause], names: impl IntoIterator<Item = Cause>) -> Self {
        names
            .into_iter()
            .filter_map(|name| declared.iter().position(|&d| d == name))
            .fold(Self::NONE, Self::with)
    }

    /// What the robot had perceived when a command ended `until` seconds in: the set of
    /// the observations among `timed` (each `(time, name)`, the moment the robot perceived
    /// it, in any order) made at or before `until`, numbered as [`Observations::named`]
    /// numbers them. A simulated run's trace may go on past the moment the operator
    /// stopped it; what came after was never perceived.
    ///
    /// ```
    /// use trust::{Cause, Observations};
    ///
    /// const STOP: Cause = Cause::from_static("safety-stop");
    /// const DROP: Cause = Cause::from_static("dropped-item");
    /// const DECLARED: [Cause; 2] = [STOP, DROP];
    ///
    /// let trace = [(2.0, STOP), (7.5, DROP), (4.0, STOP)];
    /// assert_eq!(Observations::named_until(&DECLARED, 5.0, trace), Observations::NONE.with(0));
    /// assert_eq!(Observations::named_until(&DECLARED, 7.5, trace), Observations::NONE.with(0).with(1));
    /// assert_eq!(Observations::named_until(&DECLARED, 1.0, trace), Observations::NONE);
    /// ```
    pub fn named_until(
        declared: &[Cause],
        until: f64,
        timed: impl IntoIterator<Item = (f64, Cause)>,
    ) -> Self {
        let perceived = timed.into_iter().filter(|&(t, _)| t <= until);
        Self::named(declared, perceived.map(|(_, name)| name))
    }

    /// Whether the observation `name`, numbered by its place in the domain's `declared`
    /// observations, happened (`false` for a name not declared).
    pub fn contains_named(self, declared: &[Cause], name: Cause) -> bool {
        declared
            .iter()
            .position(|&d| d == name)
            .is_some_and(|index| self.contains(index))
    }

    /// Whether observation number `index` happened.
    pub const fn contains(self, index: usize) -> bool {
        index < Self::CAPACITY && self.0 & (1 << index) != 0
    }

    /// Whether nothing was perceived.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// The numbers of the observations that happened, in increasing order.
    pub fn indices(self) -> impl Iterator<Item = usize> {
        (0..Self::CAPACITY).filter(move |&i| self.contains(i))
    }

    /// The set as bits (bit `i`: observation `i`).
    pub const fn bits(self) -> u32 {
        self.0
    }

    /// A set from bits (bit `i`: observation `i`).
    pub const fn from_bits(bits: u32) -> Self {
        Self(bits)
    }
}

fn nothing_observed(observed: &Observations) -> bool {
    observed.is_empty()
}

/// The result of one command as the robot knows it: how it ended, how much it weighs, how
/// long it took, what the robot perceived, and the operator's stated reason when the
/// operator gave one.
///
/// This is everything a searcher, the adapter and `serve` are told. The operator's true
/// reason is not here: a simulated run returns it beside the outcome, in the lab's `Judgement`,
/// for evaluation only.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Outcome {
    /// How the command ended.
    pub kind: OutcomeKind,
    /// Its weight `w >= 0` (the paper keeps weights in `[0, 1]`). It may depend only on what
    /// the robot perceives (a detonation weighs more because the robot hears it).
    pub weight: f64,
    /// Task time spent on the command, in seconds.
    pub duration_s: f64,
    /// What the robot perceived during the command.
    #[serde(default, skip_serializing_if = "nothing_observed")]
    pub observed: Observations,
    /// The reason the operator stated for a failure or an interruption, one of the domain's
    /// declared causes, when it gave one (it may be wrong); `None` when it said nothing.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stated: Option<Cause>,
    /// The robot's own confidence, in `[0, 1]`, that the command went as it should, when
    /// the domain gives it a self-assessment (a detector's confidence in its labels);
    /// `None` when it has none. The overtrust monitor reads it ([`crate::overtrust`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub confidence: Option<f64>,
    /// The operator said it stopped the robot because its goals changed (a threat
    /// appeared, it sent the robot elsewhere), not because of the behavior: a distinct
    /// statement, only of an interruption and never beside a stated reason. A said goal
    /// change counts neither for nor against the behavior ([`Outcome::contribution`] is
    /// 0, [`Outcome::is_untrustworthy`] is `false`); an unsaid one is an interruption like
    /// any other (docs/model.md, "Goal changes").
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub goal_change: bool,
}

/// Why an outcome cannot be recorded.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum OutcomeError {
    /// The weight is negative or not a number.
    #[error("weight must be a finite number >= 0, got {}", cbr_core::Shown(*.0))]
    Weight(f64),
    /// The duration is negative or not a number.
    #[error("duration_s must be a finite number >= 0, got {}", cbr_core::Shown(*.0))]
    Duration(f64),
    /// The self-assessed confidence is not a probability.
    #[error("confidence must be a number in [0, 1], got {}", cbr_core::Shown(*.0))]
    Confidence(f64),
    /// A goal change said of an outcome that is not an interruption, or beside a stated
    /// reason.
    #[error(
        "goal_change is said only of an interruption with no stated reason (the operator stopped the robot for something other than the behavior), got outcome `{kind}`{}",
        if *.stated { " with a stated reason" } else { "" }
    )]
    GoalChange {
        /// How the command ended.
        kind: &'static str,
        /// Whether a reason was stated beside it.
        stated: bool,
    },
}

impl Outcome {
    /// An outcome of any kind: how it ended, its weight and how long it took (nothing
    /// perceived, nothing stated), for callers that know the kind only at run time.
    pub const fn new(kind: OutcomeKind, weight: f64, duration_s: f64) -> Self {
        Self {
            kind,
            weight,
            duration_s,
            observed: Observations::NONE,
            stated: None,
            confidence: None,
            goal_change: false,
        }
    }

    /// A completion with weight `weight` that took `duration_s` seconds.
    pub const fn completed(weight: f64, duration_s: f64) -> Self {
        Self::new(OutcomeKind::Completed, weight, duration_s)
    }

    /// A failure.
    pub const fn failed(weight: f64, duration_s: f64) -> Self {
        Self::new(OutcomeKind::Failed, weight, duration_s)
    }

    /// An interruption.
    pub const fn interrupted(weight: f64, duration_s: f64) -> Self {
        Self::new(OutcomeKind::Interrupted, weight, duration_s)
    }

    /// The same outcome with what the robot perceived.
    #[must_use]
    pub fn observing(self, observed: Observations) -> Self {
        Self { observed, ..self }
    }

    /// The same outcome with the operator's stated reason.
    #[must_use]
    pub fn stating(self, reason: Option<Cause>) -> Self {
        Self {
            stated: reason,
            ..self
        }
    }

    /// The same outcome with the robot's own confidence that the command went as it should.
    #[must_use]
    pub fn assessing(self, confidence: Option<f64>) -> Self {
        Self { confidence, ..self }
    }

    /// The same outcome with the operator saying (or not) that its goals changed
    /// ([`Outcome::goal_change`]).
    #[must_use]
    pub fn saying_goal_change(self, goal_change: bool) -> Self {
        Self {
            goal_change,
            ..self
        }
    }

    /// Whether the command failed or was interrupted (what the operator endured) for a
    /// reason that may be the behavior's: every failure and interruption but a said goal
    /// change.
    pub fn is_untrustworthy(&self) -> bool {
        self.kind != OutcomeKind::Completed && !self.goal_change
    }

    /// Checks that the numbers are usable.
    pub fn validate(&self) -> Result<(), OutcomeError> {
        if !(self.weight.is_finite() && self.weight >= 0.0) {
            return Err(OutcomeError::Weight(self.weight));
        }
        if !(self.duration_s.is_finite() && self.duration_s >= 0.0) {
            return Err(OutcomeError::Duration(self.duration_s));
        }
        if let Some(c) = self.confidence.filter(|c| !(0.0..=1.0).contains(c)) {
            return Err(OutcomeError::Confidence(c));
        }
        if self.goal_change && (self.kind != OutcomeKind::Interrupted || self.stated.is_some()) {
            return Err(OutcomeError::GoalChange {
                kind: self.kind.name(),
                stated: self.stated.is_some(),
            });
        }
        Ok(())
    }

    /// The signed, weighted contribution `w * cmd` to the estimate: 0 for a said goal
    /// change, which is not about the behavior.
    pub fn contribution(&self) -> f64 {
        if self.goal_change {
            0.0
        } else {
            self.weight * self.kind.sign()
        }
    }
}

/// How far short of a threshold a sum may fall and still have reached it.
///
/// The paper's arithmetic is exact: with weights of 1/3, fifteen commands of one kind
/// reach a threshold of 5. A weight is a binary float, so fifteen `0.3333333333333333`s
/// sum to `4.999999999999999`: without a tolerance the verdict would come one command
/// late. Every comparison of an estimate with a threshold (the adapter's, mission mode's
/// watch, `serve`'s, the Python package's, the known-operator limit's and every report's)
/// goes through [`Thresholds::verdict`], which counts a sum within this distance of a
/// threshold as having reached it (docs/model.md, "The trust estimate"). It is far above
/// the rounding of any sum an estimate makes (each of its additions errs by at most half
/// an ulp of 5, about 4.4e-16, and an estimate starts again from 0 with every behavior)
/// and far below any weight an operator writes.
pub const THRESHOLD_TOLERANCE: f64 = 1e-9;

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
    "thresholds must be finite with untrustworthy < 0 < trustworthy, each more than 1e-9 from 0 (every behavior's estimate starts at 0, so a verdict needs evidence), got untrustworthy = {}, trustworthy = {}",
    cbr_core::Shown(*.untrustworthy),
    cbr_core::Shown(*.trustworthy)
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
    /// The verdict on an estimate of `value`: trustworthy at or above the trustworthy
    /// threshold, untrustworthy at or below the untrustworthy one, each within
    /// [`THRESHOLD_TOLERANCE`], and undecided between.
    pub fn verdict(&self, value: f64) -> Verdict {
        if value >= self.trustworthy - THRESHOLD_TOLERANCE {
            Verdict::Trustworthy
        } else if value <= self.untrustworthy + THRESHOLD_TOLERANCE {
            Verdict::Untrustworthy
        } else {
            Verdict::Undecided
        }
    }

    /// Checks that both are finite and ordered.
    pub fn validate(&self) -> Result<(), ThresholdError> {
        if self.trustworthy.is_finite()
            && self.untrustworthy.is_finite()
            && self.untrustworthy < -THRESHOLD_TOLERANCE
            && THRESHOLD_TOLERANCE < self.trustworthy
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

    /// The verdict under `thresholds` ([`Thresholds::verdict`]).
    pub fn verdict(&self, thresholds: &Thresholds) -> Verdict {
        thresholds.verdict(self.value)
    }
}

/// The farthest from 0 a trust threshold may be for the tool to accept it: a million
/// unit-weight commands, the longest trial it runs; it also keeps the known-operator
/// limit's states (estimates in integer steps) within `i64`. Checked where thresholds come
/// in (a suite's `adapter.thresholds`, a `serve` domain file) and by the limit itself.
pub const MAX_THRESHOLD: f64 = 1e6;

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
        e.record(&Outcome::interrupted(1.0 / 3.0, 5.0).stating(Some(TOO_SLOW)));
        e.record(&Outcome::failed(1.0, 40.0).stating(Some(DROPPED)));
        // 1/3 - 1/3 - 1 = -1
        assert!((e.value + 1.0).abs() < 1e-12);
        assert_eq!(e.elapsed_s, 65.0);
        assert_eq!(e.commands, 3);
        assert_eq!(e.verdict(&t), Verdict::Undecided);
        // Four more failures of weight 1: -1 - 4 = -5 <= -5.
        for _ in 0..4 {
            e.record(&Outcome::failed(1.0, 1.0));
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
    fn observations_are_bits_in_declared_order() {
        let seen = Observations::NONE.with(0).with(3).with(40);
        assert_eq!(seen.bits(), 0b1001);
        assert!(seen.contains(3) && !seen.contains(1) && !seen.contains(40));
        assert_eq!(seen.indices().collect::<Vec<_>>(), [0, 3]);
        assert!(Observations::NONE.is_empty());
        // An outcome with nothing perceived or stated is written as before.
        let plain = Outcome::completed(1.0, 2.0);
        assert_eq!(
            serde_json::to_string(&plain).unwrap(),
            r#"{"kind":"completed","weight":1.0,"duration_s":2.0}"#
        );
        let told = Outcome::failed(1.0, 2.0)
            .observing(seen)
            .stating(Some(DROPPED));
        let text = serde_json::to_string(&told).unwrap();
        assert_eq!(
            text,
            r#"{"kind":"failed","weight":1.0,"duration_s":2.0,"observed":9,"stated":"dropped-item"}"#
        );
        assert_eq!(serde_json::from_str::<Outcome>(&text).unwrap(), told);
    }

    /// The commands after which an estimate fed `outcomes` in turn first reaches a verdict.
    fn verdict_after(outcomes: impl IntoIterator<Item = Outcome>) -> Option<(usize, Verdict)> {
        let thresholds = Thresholds::default();
        let mut estimate = TrustEstimate::default();
        outcomes.into_iter().enumerate().find_map(|(i, o)| {
            estimate.record(&o);
            let verdict = estimate.verdict(&thresholds);
            (verdict != Verdict::Undecided).then_some((i + 1, verdict))
        })
    }

    #[test]
    fn fifteen_weights_of_a_third_reach_a_threshold_as_in_the_paper() {
        // As written in the operator files: the float nearest 1/3.
        let third: f64 = "0.3333333333333333".parse().unwrap();
        let mut sum = 0.0;
        for _ in 0..15 {
            sum -= third;
        }
        // The float sum falls short of -5 by one ulp; the verdict does not.
        assert!(sum > -5.0);
        assert_eq!(Thresholds::default().verdict(sum), Verdict::Untrustworthy);
        let interrupted = Outcome::interrupted(third, 1.0);
        assert_eq!(
            verdict_after(std::iter::repeat_n(interrupted, 20)),
            Some((15, Verdict::Untrustworthy))
        );
        let completed = Outcome::completed(third, 1.0);
        assert_eq!(
            verdict_after(std::iter::repeat_n(completed, 20)),
            Some((15, Verdict::Trustworthy))
        );
        // Fourteen are not enough: 14/3 is 1/3 short.
        assert_eq!(verdict_after(std::iter::repeat_n(interrupted, 14)), None);
    }

    #[test]
    fn mixed_weights_reach_a_threshold_when_their_exact_sum_does() {
        let third = 1.0 / 3.0;
        // A detonation (1) and twelve interruptions (1/3 each): exactly -5 at the 13th.
        let detonation = Outcome::failed(1.0, 1.0);
        let interrupted = Outcome::interrupted(third, 1.0);
        let outcomes = std::iter::once(detonation).chain(std::iter::repeat_n(interrupted, 20));
        assert_eq!(verdict_after(outcomes), Some((13, Verdict::Untrustworthy)));
        // Completions and interruptions in turn, then fifteen completions: the pairs cancel
        // exactly in the paper's arithmetic, so +5 comes with the fifteenth completion.
        let completed = Outcome::completed(third, 1.0);
        let outcomes = [completed, interrupted]
            .repeat(40)
            .into_iter()
            .chain(std::iter::repeat_n(completed, 15));
        assert_eq!(verdict_after(outcomes), Some((95, Verdict::Trustworthy)));
        // 4.9 is short of 5 by far more than the tolerance.
        assert_eq!(Thresholds::default().verdict(4.9), Verdict::Undecided);
        assert_eq!(
            Thresholds::default().verdict(5.0 - 2.0 * THRESHOLD_TOLERANCE),
            Verdict::Undecided
        );
    }

    #[test]
    fn weights_read_from_ron_text_reach_a_threshold_after_fifteen_commands() {
        // The patrol operators' weights, as their files write them.
        let weights: crate::OutcomeWeights = ron::from_str(
            r#"(completed: 0.3333333333333333, default: 0.3333333333333333, by_cause: { "detonation": 1.0 })"#,
        )
        .unwrap();
        let slow = Cause::from_static("deadline");
        let interrupted = Outcome::interrupted(weights.of(slow), 120.0);
        assert_eq!(
            verdict_after(std::iter::repeat_n(interrupted, 20)),
            Some((15, Verdict::Untrustworthy))
        );
        let completed = Outcome::completed(weights.completed, 100.0);
        assert_eq!(
            verdict_after(std::iter::repeat_n(completed, 20)),
            Some((15, Verdict::Trustworthy))
        );
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
