//! The watch of a settled behavior: how a robot on a mission ([`crate::mission_mode`]) keeps
//! estimating the trust of the behavior an episode settled on.
//!
//! The paper's adapter stops at the first trustworthy behavior (the end of an *episode*).
//! On a mission the robot keeps estimating the trust of the behavior it settled on,
//! command after command, and adapts again when that estimate falls to the untrustworthy
//! threshold: the operator's preferences changed, another operator took over, or the
//! behavior was trusted by luck. This module is the estimate kept meanwhile ([`Watch`]);
//! what the robot does with it is [`crate::mission_mode`]'s.
//!
//! **How the estimate is kept.** The paper's sum of weighted outcomes would bank every
//! completion: after a hundred good commands it would take a hundred failures to notice a
//! change. So while the robot watches a settled behavior, the estimate is *capped at the
//! trustworthy threshold*: it starts there (a behavior settles when its estimate reaches
//! it) and a completion never lifts it above it. A change is then noticed after as many
//! net untrustworthy commands as it takes to go from the trustworthy threshold to the
//! untrustworthy one (10 unit weights at the paper's +5 / -5), however long the behavior
//! served, and a behavior that keeps earning trust is never given up by a run of bad luck
//! shorter than that. Every time the estimate touches the cap, the time and command counts
//! of the watch restart: the evaluated pair of a behavior given up in a mission records
//! how long it took to fall from trusted to untrustworthy ([`Watch::estimate`]). A
//! behavior kept because every behavior had been tried (no trustworthy one) is watched
//! from an estimate of 0.

use crate::{Outcome, Thresholds, TrustEstimate, Verdict};
use cbr_core::Behavior;

/// A settled behavior under watch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Watch {
    /// The behavior settled on.
    pub behavior: Behavior,
    /// Its estimate, capped at the trustworthy threshold; its time and command counts
    /// since the estimate last stood at the cap.
    pub estimate: TrustEstimate,
    /// Untrustworthy commands since the estimate last stood at the cap.
    pub untrustworthy: u64,
    /// Commands since the behavior settled.
    pub commands: u64,
}

impl Watch {
    /// A watch over `behavior`, which an episode settled on: a trustworthy one is watched
    /// from the trustworthy threshold (its estimate reached it, and the cap keeps it
    /// there), one kept because every behavior had been tried from 0.
    pub fn settled(behavior: Behavior, trustworthy: bool, thresholds: &Thresholds) -> Self {
        let start = if trustworthy {
            thresholds.trustworthy
        } else {
            0.0
        };
        Self {
            behavior,
            estimate: TrustEstimate {
                value: start,
                ..TrustEstimate::default()
            },
            untrustworthy: 0,
            commands: 0,
        }
    }

    /// Records one command of the watched behavior (a valid outcome); returns whether the
    /// estimate touched the cap (the watch's counts restarted).
    pub fn record(&mut self, outcome: &Outcome, thresholds: &Thresholds) -> bool {
        self.estimate.record(outcome);
        self.commands += 1;
        if outcome.is_untrustworthy() {
            self.untrustworthy += 1;
        }
        let capped = thresholds.verdict(self.estimate.value) == Verdict::Trustworthy;
        if capped {
            self.estimate = TrustEstimate {
                value: thresholds.trustworthy,
                ..TrustEstimate::default()
            };
            self.untrustworthy = 0;
        }
        capped
    }

    /// Whether the estimate has fallen to the untrustworthy threshold (by the thresholds'
    /// one rule, [`Thresholds::verdict`]).
    pub fn fallen(&self, thresholds: &Thresholds) -> bool {
        thresholds.verdict(self.estimate.value) == Verdict::Untrustworthy
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn behavior() -> Behavior {
        Behavior::new(&[1, 2])
    }

    #[test]
    fn completions_never_bank_trust_above_the_cap_and_ten_failures_give_the_behavior_up() {
        let t = Thresholds::default();
        let mut watch = Watch::settled(behavior(), true, &t);
        assert_eq!(watch.estimate.value, 5.0);
        for _ in 0..100 {
            assert!(watch.record(&Outcome::completed(1.0, 2.0), &t));
        }
        assert_eq!(watch.estimate.value, 5.0);
        assert_eq!(watch.estimate.commands, 0);
        for i in 1..=10 {
            assert!(!watch.fallen(&t));
            assert!(!watch.record(&Outcome::interrupted(1.0, 3.0), &t));
            assert_eq!(watch.estimate.value, 5.0 - f64::from(i));
        }
        assert!(watch.fallen(&t));
        // The evaluated pair's time: the ten commands since the estimate left the cap.
        assert_eq!(watch.estimate.commands, 10);
        assert_eq!(watch.estimate.elapsed_s, 30.0);
        assert_eq!(watch.untrustworthy, 10);
        assert_eq!(watch.commands, 110);
    }

    #[test]
    fn a_completion_back_to_the_cap_restarts_the_counts() {
        let t = Thresholds::default();
        let mut watch = Watch::settled(behavior(), true, &t);
        watch.record(&Outcome::failed(0.5, 1.0), &t);
        assert_eq!(watch.estimate.value, 4.5);
        assert_eq!(watch.untrustworthy, 1);
        assert!(watch.record(&Outcome::completed(1.0, 1.0), &t));
        assert_eq!(watch.estimate.value, 5.0);
        assert_eq!((watch.untrustworthy, watch.estimate.commands), (0, 0));
    }

    #[test]
    fn a_behavior_kept_without_trust_is_watched_from_zero() {
        let t = Thresholds::default();
        let watch = Watch::settled(behavior(), false, &t);
        assert_eq!(watch.estimate.value, 0.0);
    }
}
