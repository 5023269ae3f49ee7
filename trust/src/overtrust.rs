//! Overtrust: an operator who trusts the robot while the robot is not earning it.
//!
//! An operator who has come to trust a robot watches it less: problems it would have
//! stopped the robot for go unnoticed, its reactions keep the robot's trust estimate high,
//! and the adapter, which listens only to the operator, sees nothing wrong. So in mission
//! mode ([`crate::mission_mode`]) the robot also keeps its **own record** of the behavior it has
//! settled on, from what it perceives itself and from the self-assessment its domain may
//! give ([`Outcome::confidence`]), and raises an [`Alert`] when the operator's trust is
//! high while its own record says it is not earning it.
//!
//! **Signals.** A command carries a signal for every observation the robot perceived (a
//! bump, running behind its plan, passing a person fast) and one more, *doubt*, when its
//! self-assessed confidence is below [`DOUBT_BELOW`] (one chance in ten or more that the
//! command went wrong in a way it cannot see, such as a wrong label).
//!
//! **What the signals mean to the operator.** While the operator is still deciding
//! whether to trust a behavior (every command of an adaptation episode) it is taken to be
//! attentive: an operator grows complacent only once it trusts the robot. From those
//! commands the record learns, for each signal, how often operators react (fail or
//! interrupt the command) when it is present. It keeps two counts: every operator's in the
//! robot's context since the robot started (the fleet's prior, `(reacted + 1) / (seen +
//! 2)`, kept per context, [`OwnRecord::enter_context`]: in an emergency operators let
//! bumps pass that they stop the robot for with hazardous cargo), and the current
//! operator's, forgotten when the robot is told a new operator begins
//! ([`OwnRecord::forget_operator`]) or that its context switched. The current operator's rate is its own counts shrunk
//! towards the prior with the weight of [`PRIOR_WEIGHT`] commands. Commands without a
//! signal are counted too, for the *base rate* `b` at which the operator reacts to
//! something the robot did not perceive: during adaptation most behaviors are poor, so a
//! bump often comes with a missed deadline, and the operator's reaction belongs to both.
//! Taking the two causes as independent, the reaction the signal itself provokes is
//! `q = (p_s - b) / (1 - b)` (0 if negative), `p_s` the signal's rate; on a trusted
//! behavior, where little else goes wrong, that is what the robot expects. A command's
//! rate `p` is the largest `q` among its signals: what the operator, attentive, would most
//! surely have stopped.
//!
//! **The own record.** While a settled behavior is under watch, the record weighs each
//! command with a signal as evidence of a *lapse*, an operator who notices only
//! [`LAPSE`] of what it minds, against an attentive one (Page's cumulative sum of the
//! log-likelihood ratio): a reaction adds `ln(LAPSE)` (it noticed), a command let pass adds
//! `ln((1 - LAPSE p) / (1 - p))`, and the sum never falls below 0. Commands with no signal
//! say nothing either way. The record is the robot's account of what it saw go wrong and
//! what the operator let pass: trust that this account does not support is not earned.
//!
//! **The alert.** When the evidence reaches [`ALERT_EVIDENCE`] (a lapse a hundred times
//! likelier than attention) while the operator's estimate of the behavior is above 0 (its
//! reactions, on balance, still approve of it), the mission decides
//! [`crate::MissionDecision::Alert`]: the robot keeps its behavior and asks its operator to
//! supervise it. The evidence then starts again from 0.

use crate::{Observations, Outcome};
use cbr_core::{Behavior, Context};
use serde::{Deserialize, Serialize};

/// A self-assessed confidence below this is a signal of doubt.
pub const DOUBT_BELOW: f64 = 0.9;

/// The lapse the record tests for: an operator who notices half of what it minds (it then
/// overlooks more than it notices).
pub const LAPSE: f64 = 0.5;

/// The evidence that raises an alert: `ln(100)`, a lapse a hundred times likelier than
/// attention (decisive on Jeffreys' scale).
pub const ALERT_EVIDENCE: f64 = 4.605_170_185_988_092;

/// How many commands' worth the fleet's prior weighs in an operator's reaction rates.
pub const PRIOR_WEIGHT: f64 = 2.0;

/// Signal numbers: the observations, doubt, then "no signal" (the base rate).
const SIGNALS: usize = Observations::CAPACITY + 2;
/// The doubt signal's number.
const DOUBT: usize = Observations::CAPACITY;
/// The count of commands without a signal.
const NONE: usize = Observations::CAPACITY + 1;

/// The robot's own record of the behavior it settled on, and what it learned of how its
/// operator reacts to each signal.
#[derive(Clone, Debug, PartialEq)]
pub struct OwnRecord {
    reacted: [u32; SIGNALS],
    seen: [u32; SIGNALS],
    fleet_reacted: [u32; SIGNALS],
    fleet_seen: [u32; SIGNALS],
    /// The context the fleet's counts above are of.
    context: Context,
    /// The fleet's counts (reacted, seen) in the other contexts the robot has been in.
    other_contexts: Vec<(Context, [u32; SIGNALS], [u32; SIGNALS])>,
    value: f64,
    commands: u64,
    unacknowledged: u64,
}

impl Default for OwnRecord {
    fn default() -> Self {
        Self {
            reacted: [0; SIGNALS],
            seen: [0; SIGNALS],
            fleet_reacted: [0; SIGNALS],
            fleet_seen: [0; SIGNALS],
            context: Context::default(),
            other_contexts: Vec::new(),
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
    /// The robot's own record: the evidence of a lapse (at least [`ALERT_EVIDENCE`]).
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

    /// Whether `outcome` carries a signal: something perceived, or doubt.
    pub fn has_signal(outcome: &Outcome) -> bool {
        Self::signals(outcome).next().is_some()
    }

    /// Learns from a command the operator judged attentively (one of an adaptation
    /// episode) how it reacts to the command's signals, or to a command without one.
    pub fn learn(&mut self, outcome: &Outcome) {
        let reacted = u32::from(outcome.is_untrustworthy());
        let mut signals = Self::signals(outcome).peekable();
        let counted: Vec<usize> = if signals.peek().is_some() {
            signals.collect()
        } else {
            vec![NONE]
        };
        for signal in counted {
            self.seen[signal] += 1;
            self.reacted[signal] += reacted;
            self.fleet_seen[signal] += 1;
            self.fleet_reacted[signal] += reacted;
        }
    }

    /// Forgets how the current operator reacts (a new operator begins); what every
    /// operator taught stays.
    pub fn forget_operator(&mut self) {
        self.reacted = [0; SIGNALS];
        self.seen = [0; SIGNALS];
    }

    /// The robot is in `context` from now on: the fleet's counts are those learned in it
    /// (none yet in a context it was never in); those of the context it leaves are kept.
    pub fn enter_context(&mut self, context: &Context) {
        if *context == self.context {
            return;
        }
        let (reacted, seen) = match self.other_contexts.iter().position(|(c, ..)| c == context) {
            Some(i) => {
                let (_, reacted, seen) = self.other_contexts.swap_remove(i);
                (reacted, seen)
            }
            None => ([0; SIGNALS], [0; SIGNALS]),
        };
        let left = std::mem::replace(&mut self.context, context.clone());
        let left_reacted = std::mem::replace(&mut self.fleet_reacted, reacted);
        let left_seen = std::mem::replace(&mut self.fleet_seen, seen);
        self.other_contexts.push((left, left_reacted, left_seen));
    }

    /// Starts a new record (a behavior settled, or an alert was raised).
    pub fn restart(&mut self) {
        self.value = 0.0;
        self.commands = 0;
        self.unacknowledged = 0;
    }

    /// How often the current operator, attentive, reacts to commands with `signal` (or,
    /// for [`NONE`], to commands without one).
    fn reaction_rate(&self, signal: usize) -> f64 {
        let fleet = (f64::from(self.fleet_reacted[signal]) + 1.0)
            / (f64::from(self.fleet_seen[signal]) + 2.0);
        (f64::from(self.reacted[signal]) + PRIOR_WEIGHT * fleet)
            / (f64::from(self.seen[signal]) + PRIOR_WEIGHT)
    }

    /// What `outcome` adds to the evidence of a lapse: nothing without a signal; with
    /// one, `ln(LAPSE)` if the operator reacted, else `ln((1 - LAPSE p) / (1 - p))`, `p`
    /// the largest reaction rate among its signals.
    pub fn score(&self, outcome: &Outcome) -> f64 {
        let base = self.reaction_rate(NONE);
        let Some(p) = Self::signals(outcome)
            .map(|s| ((self.reaction_rate(s) - base) / (1.0 - base)).max(0.0))
            .reduce(f64::max)
        else {
            return 0.0;
        };
        if p <= 0.0 {
            // A signal this operator does not mind: nothing to expect either way.
            return 0.0;
        }
        if outcome.is_untrustworthy() {
            LAPSE.ln()
        } else {
            ((1.0 - LAPSE * p) / (1.0 - p)).ln()
        }
    }

    /// Records a command of the watched behavior; returns the evidence of a lapse.
    pub fn record(&mut self, outcome: &Outcome) -> f64 {
        self.value = (self.value + self.score(outcome)).max(0.0);
        self.commands += 1;
        if !outcome.is_untrustworthy() && Self::has_signal(outcome) {
            self.unacknowledged += 1;
        }
        self.value
    }

    /// The alert to raise for `behavior` when the operator's `estimate` of it is above 0
    /// and the evidence of a lapse has reached [`ALERT_EVIDENCE`].
    pub fn alert(&self, behavior: Behavior, estimate: f64) -> Option<Alert> {
        (estimate > 0.0 && self.value >= ALERT_EVIDENCE).then_some(Alert {
            behavior,
            estimate,
            own_record: self.value,
            commands: self.commands,
            unacknowledged: self.unacknowledged,
        })
    }

    /// The evidence of a lapse so far.
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

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    #[test]
    fn reaction_rates_shrink_the_operator_s_counts_towards_the_fleet_s() {
        let mut record = OwnRecord::default();
        // Nothing learned: a signal's rate and the base rate are both 1/2, so the signal
        // itself provokes nothing and says nothing.
        assert_eq!(record.score(&bumped(false)), 0.0);
        assert_eq!(record.score(&bumped(true)), 0.0);
        assert_eq!(record.score(&Outcome::completed(1.0, 1.0)), 0.0);
        // Four commands without a signal, let pass: the fleet's base rate 1/6, the
        // operator's (0 + 2/6) / (4 + 2) = 1/18.
        for _ in 0..4 {
            record.learn(&Outcome::completed(1.0, 1.0));
        }
        // Reacted to 3 bumps of 4: the fleet's rate (3 + 1) / (4 + 2) = 2/3, the
        // operator's (3 + 2 x 2/3) / (4 + 2) = 13/18, the bump's own (13/18 - 1/18) /
        // (17/18) = 12/17; a bump let pass adds ln((1 - 6/17) / (5/17)) = ln 2.2.
        for reacted in [true, true, false, true] {
            record.learn(&bumped(reacted));
        }
        assert!(close(record.score(&bumped(false)), 2.2f64.ln()));
        assert!(close(record.score(&bumped(true)), 0.5f64.ln()));
        // A new operator: its own counts go, the fleet's stay: base 1/6, bump 2/3, its own
        // (2/3 - 1/6) / (5/6) = 3/5; ln((1 - 0.3) / 0.4) = ln 1.75.
        record.forget_operator();
        assert!(close(record.score(&bumped(false)), 1.75f64.ln()));
        // Two signals: the larger rate (a late command, never seen, provokes nothing).
        let both = bumped(false).observing(Observations::NONE.with(LATE).with(BUMP));
        assert!(close(record.score(&both), 1.75f64.ln()));
    }

    #[test]
    fn the_fleet_s_reactions_are_kept_per_context() {
        let mut record = OwnRecord::default();
        // Normal cargo: 4 commands without a signal let pass, 3 bumps of 4 stopped (as
        // above: a new operator's bump let pass adds ln 1.75).
        for _ in 0..4 {
            record.learn(&Outcome::completed(1.0, 1.0));
        }
        for reacted in [true, true, false, true] {
            record.learn(&bumped(reacted));
        }
        record.forget_operator();
        assert!(close(record.score(&bumped(false)), 1.75f64.ln()));
        // An emergency, never met: nothing learned there, a bump says nothing.
        let emergency = cbr_core::ContextSpace::new(vec![cbr_core::ContextVariable::new(
            "situation",
            &["routine", "emergency"],
        )])
        .unwrap()
        .context([("situation", "emergency")])
        .unwrap();
        record.enter_context(&emergency);
        assert_eq!(record.score(&bumped(false)), 0.0);
        // There operators let bumps pass as often as anything else: still nothing.
        for _ in 0..4 {
            record.learn(&Outcome::completed(1.0, 1.0));
            record.learn(&bumped(false));
        }
        record.forget_operator();
        assert_eq!(record.score(&bumped(false)), 0.0);
        // Back to normal cargo: what operators taught there is as it was.
        record.enter_context(&Context::default());
        assert!(close(record.score(&bumped(false)), 1.75f64.ln()));
    }

    #[test]
    fn doubt_is_a_signal_below_nine_tenths_of_confidence() {
        let mut record = OwnRecord::default();
        let doubtful = Outcome::failed(1.0, 1.0).assessing(Some(0.8));
        record.learn(&doubtful);
        // Doubt: fleet 2/3, operator (1 + 4/3) / 3 = 7/9; base 1/2; its own (7/9 - 1/2) /
        // (1/2) = 5/9; ln((1 - 5/18) / (4/9)) = ln(13/8).
        let passed = Outcome::completed(1.0, 1.0).assessing(Some(0.5));
        assert!(close(record.score(&passed), (13.0f64 / 8.0).ln()));
        // Confident enough: no signal.
        assert_eq!(
            record.score(&Outcome::completed(1.0, 1.0).assessing(Some(0.9))),
            0.0
        );
    }

    #[test]
    fn an_alert_needs_high_trust_and_decisive_evidence() {
        let mut record = OwnRecord::default();
        // Attentive: 8 commands without a signal let pass (base: fleet 1/10, operator
        // 0.2 / 10 = 0.02) and 8 bumps all stopped (fleet 9/10, operator 9.8 / 10 =
        // 0.98): the bump's own rate 0.96 / 0.98 = 48/49, and a bump let pass adds
        // ln((25/49) / (1/49)) = ln 25.
        for _ in 0..8 {
            record.learn(&Outcome::completed(1.0, 1.0));
            record.learn(&bumped(true));
        }
        let b = Behavior::new(&[0]);
        let step = 25f64.ln();
        assert!(close(record.record(&bumped(false)), step));
        assert_eq!(record.alert(b, 5.0), None);
        // A reaction takes ln 2 off; the sum never goes below 0.
        assert!(close(record.record(&bumped(true)), step - 2f64.ln()));
        assert!(close(record.record(&bumped(false)), 2.0 * step - 2f64.ln()));
        let alert = record.alert(b, 3.0).unwrap();
        assert_eq!((alert.commands, alert.unacknowledged), (3, 2));
        assert_eq!(
            record.alert(b, 0.0),
            None,
            "the operator's trust is not high"
        );
        record.restart();
        for _ in 0..5 {
            record.record(&bumped(true));
        }
        assert_eq!(record.value(), 0.0);
    }
}
