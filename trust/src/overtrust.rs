//! Overtrust: an operator who trusts the robot while the robot is not earning it.
//!
//! An operator who has come to trust a robot watches it less: problems it would have
//! stopped the robot for go unnoticed, its reactions keep the robot's trust estimate high,
//! and the adapter, which listens only to the operator, sees nothing wrong. So in mission
//! mode the robot also keeps its **own record** of the behavior it has settled on, from
//! what it perceives itself and from the self-assessment its domain may give
//! ([`Outcome::confidence`]), and raises an [`Alert`] when the operator's trust is high
//! while its own record says it is not earning it.
//!
//! **Signals.** A command carries a signal for every observation the robot perceived (a
//! bump, running behind its plan, passing a person fast) and one more, *doubt*, when its
//! self-assessed confidence is below [`DOUBT_BELOW`] (one chance in ten or more that the
//! command went wrong in a way it cannot see, such as a wrong label).
//!
//! **What the signals mean to this operator.** While the operator is still deciding whether
//! to trust a behavior (every command of an adaptation episode) it is taken to be
//! attentive: an operator grows complacent only once it trusts the robot. The record
//! learns from those commands, for each signal, how often this operator reacted (failed or
//! interrupted the command) when the signal was present: `(reacted + 1) / (seen + 2)`, so a
//! signal never seen counts for one half. What it learned is forgotten when the robot is
//! told a new operator begins ([`OwnRecord::forget_operator`]).
//!
//! **The own record.** It is an estimate of the settled behavior's trust in the operator's
//! own scale: a command with no signal scores `+1` (nothing the robot saw would have
//! bothered the operator), a command with signals scores `1 - 2p`, where `p` is the
//! largest learned reaction rate among its signals (`+1` for a signal the operator never
//! reacted to, `-1` for one it always reacted to). Like the watched estimate
//! ([`crate::watch`]) it is capped at the trustworthy threshold, and it starts at 0 when
//! the behavior settles: the robot has no record of its own yet.
//!
//! **The alert.** When the own record falls to the untrustworthy threshold while the
//! operator's estimate of the same behavior is still above 0 (the operator's reactions, on
//! balance, still approve of it), the adapter decides [`crate::Decision::Alert`]: the
//! robot keeps its behavior and asks its operator to supervise it. The own record then
//! starts again from 0, so a next alert needs as much new evidence.

use crate::{Observations, Outcome, Thresholds};
use cbr_core::Behavior;
use serde::{Deserialize, Serialize};

/// A self-assessed confidence below this is a signal of doubt.
pub const DOUBT_BELOW: f64 = 0.9;

/// Signal numbers: the observations, then doubt.
const SIGNALS: usize = Observations::CAPACITY + 1;
/// The doubt signal's number.
const DOUBT: usize = Observations::CAPACITY;

/// The robot's own record of the behavior it settled on, and what it learned of how its
/// operator reacts to each signal.
#[derive(Clone, Debug, PartialEq)]
pub struct OwnRecord {
    reacted: [u32; SIGNALS],
    seen: [u32; SIGNALS],
    value: f64,
    commands: u64,
    unacknowledged: u64,
}

impl Default for OwnRecord {
    fn default() -> Self {
        Self {
            reacted: [0; SIGNALS],
            seen: [0; SIGNALS],
            value: 0.0,
            commands: 0,
            unacknowledged: 0,
        }
    }
}

/// The robot asks its operator to supervise it: the operator's trust is high while the
/// robot's own record says it is not earning it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Alert {
    /// The behavior in use.
    pub behavior: Behavior,
    /// The operator's estimate of it (above 0).
    pub estimate: f64,
    /// The robot's own record of it (at or below the untrustworthy threshold).
    pub own_record: f64,
    /// Commands the own record covers.
    pub commands: u64,
    /// Of those, commands with a signal the operator did not react to.
    pub unacknowledged: u64,
}

impl OwnRecord {
    /// The signal numbers of `outcome`: its observations, then doubt.
    fn signals(outcome: &Outcome) -> impl Iterator<Item = usize> {
        let doubt = outcome.confidence.is_some_and(|c| c < DOUBT_BELOW);
        outcome.observed.indices().chain(doubt.then_some(DOUBT))
    }

    /// Learns from a command the operator judged attentively (one of an adaptation
    /// episode) how it reacts to the command's signals.
    pub fn learn(&mut self, outcome: &Outcome) {
        let reacted = u32::from(outcome.is_untrustworthy());
        for signal in Self::signals(outcome) {
            self.seen[signal] += 1;
            self.reacted[signal] += reacted;
        }
    }

    /// Forgets how the operator reacts (a new operator begins).
    pub fn forget_operator(&mut self) {
        self.reacted = [0; SIGNALS];
        self.seen = [0; SIGNALS];
    }

    /// Starts a new record (a behavior settled, or an alert was raised).
    pub fn restart(&mut self) {
        self.value = 0.0;
        self.commands = 0;
        self.unacknowledged = 0;
    }

    /// How often the operator reacted, when attentive, to commands with `signal`.
    fn reaction_rate(&self, signal: usize) -> f64 {
        (f64::from(self.reacted[signal]) + 1.0) / (f64::from(self.seen[signal]) + 2.0)
    }

    /// What `outcome` adds to the own record: `+1` without a signal, else `1 - 2p` with
    /// `p` the largest reaction rate among its signals.
    pub fn score(&self, outcome: &Outcome) -> f64 {
        Self::signals(outcome)
            .map(|s| self.reaction_rate(s))
            .reduce(f64::max)
            .map_or(1.0, |p| 1.0 - 2.0 * p)
    }

    /// Records a command of the watched behavior; returns the record's value.
    pub fn record(&mut self, outcome: &Outcome, thresholds: &Thresholds) -> f64 {
        self.value = (self.value + self.score(outcome)).min(thresholds.trustworthy);
        self.commands += 1;
        if !outcome.is_untrustworthy() && Self::signals(outcome).next().is_some() {
            self.unacknowledged += 1;
        }
        self.value
    }

    /// The alert to raise for `behavior` when the operator's `estimate` of it is above 0
    /// and the own record has fallen to the untrustworthy threshold.
    pub fn alert(
        &self,
        behavior: Behavior,
        estimate: f64,
        thresholds: &Thresholds,
    ) -> Option<Alert> {
        (estimate > 0.0 && self.value <= thresholds.untrustworthy).then_some(Alert {
            behavior,
            estimate,
            own_record: self.value,
            commands: self.commands,
            unacknowledged: self.unacknowledged,
        })
    }

    /// The record's value.
    pub fn value(&self) -> f64 {
        self.value
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const BUMP: usize = 0;
    const LATE: usize = 1;

    fn bumped(reacted: bool) -> Outcome {
        let o = if reacted {
            Outcome::interrupted(1.0, 1.0)
        } else {
            Outcome::completed(1.0, 1.0)
        };
        o.observing(Observations::NONE.with(BUMP))
    }

    #[test]
    fn reaction_rates_are_learned_with_one_half_before_any_evidence() {
        let mut record = OwnRecord::default();
        assert_eq!(record.score(&bumped(false)), 0.0);
        // Reacted to 3 bumps of 4: (3 + 1) / (4 + 2) = 2/3, so a bump scores 1 - 4/3.
        for reacted in [true, true, false, true] {
            record.learn(&bumped(reacted));
        }
        assert!((record.score(&bumped(false)) - (1.0 - 4.0 / 3.0)).abs() < 1e-12);
        // No signal: +1. A late command, a signal never seen: 0.
        assert_eq!(record.score(&Outcome::completed(1.0, 1.0)), 1.0);
        let late = Outcome::completed(1.0, 1.0).observing(Observations::NONE.with(LATE));
        assert_eq!(record.score(&late), 0.0);
        // Both: the larger rate, 2/3.
        let both = late.observing(Observations::NONE.with(LATE).with(BUMP));
        assert!((record.score(&both) - (1.0 - 4.0 / 3.0)).abs() < 1e-12);
        record.forget_operator();
        assert_eq!(record.score(&bumped(false)), 0.0);
    }

    #[test]
    fn doubt_is_a_signal_below_nine_tenths_of_confidence() {
        let mut record = OwnRecord::default();
        let doubtful = Outcome::failed(1.0, 1.0).assessing(Some(0.8));
        record.learn(&doubtful);
        record.learn(&doubtful);
        // Reacted 2 of 2: (2 + 1) / (2 + 2) = 3/4.
        assert_eq!(record.score(&doubtful), -0.5);
        assert_eq!(
            record.score(&Outcome::completed(1.0, 1.0).assessing(Some(0.9))),
            1.0
        );
    }

    #[test]
    fn an_alert_needs_high_trust_and_an_own_record_at_the_untrustworthy_threshold() {
        let t = Thresholds::default();
        let mut record = OwnRecord::default();
        // The operator reacted to every bump of 8 while attentive: p = 0.9, a bump scores -0.8.
        for _ in 0..8 {
            record.learn(&bumped(true));
        }
        let b = Behavior::new(&[0]);
        // Seven unacknowledged bumps: -5.6, at or below -5.
        for i in 1..=7 {
            let value = record.record(&bumped(false), &t);
            assert!((value + 0.8 * f64::from(i)).abs() < 1e-9);
            assert_eq!(record.alert(b, 5.0, &t).is_some(), i == 7);
        }
        assert_eq!(
            record.alert(b, 0.0, &t),
            None,
            "the operator's trust is not high"
        );
        let alert = record.alert(b, 3.0, &t).unwrap();
        assert_eq!((alert.commands, alert.unacknowledged), (7, 7));
        record.restart();
        assert_eq!(record.value(), 0.0);
        // Good commands are capped at the trustworthy threshold.
        for _ in 0..20 {
            record.record(&Outcome::completed(1.0, 1.0), &t);
        }
        assert_eq!(record.value(), 5.0);
    }
}
