//! A change detector for missions: a sequential test on the watched behavior's own record,
//! beside the paper's thresholds (docs/missions.md, "A change detector").
//!
//! On a mission the robot watches the behavior an episode settled on ([`crate::watch`]):
//! its estimate, capped at the trustworthy threshold, must fall all the way to the
//! untrustworthy one before the behavior is given up (30 net untrustworthy commands of
//! weight 1/3 at the paper's thresholds). When the operator changes unannounced, that is
//! slow. This detector asks a sharper question of the same commands: has the behavior's
//! own rate of untrustworthy commands risen from what it was when it was trusted?
//!
//! **The test: a Bernoulli CUSUM** (Page, 1954). Before the change, a command is
//! untrustworthy with probability at most `q0`, an upper bound on the behavior's own rate:
//! the [`CREDIBILITY`] (95%) quantile of its posterior `Beta(f + 1, n - f + 1)` after `f`
//! untrustworthy commands of `n`, at least [`Q0_LEAST`]. The record is the
//! episode that settled on it, then every watched command up to the statistic's last
//! return to 0 (commands that gave no evidence of a change), so the bound tightens as the
//! behavior serves, and is bounded afresh each time that record has grown by a tenth.
//! After the change, a command is untrustworthy with probability at least `q1 =` [`Q1`]
//! `= 1/2` (while the bound is 1/2 or more, no such rise can be told and the test waits),
//! where a
//! behavior stops earning trust at equal weights (the estimate's drift is then 0 or
//! below). Each command adds its log-likelihood ratio, `ln(q1 / q0)` when untrustworthy,
//! `ln((1 - q1) / (1 - q0))` otherwise, to `S`, kept at 0 or above; the detector raises
//! when `S >= h`. Of the tests for a change from one known rate to another, this one is
//! optimal (Moustakides, 1986: the least worst-case detection delay for its false alarm
//! rate); a larger rise than `q1` is detected sooner.
//!
//! **Its false alarm rate, derived.** While the rate stays at `q0`, `exp(S)` restarted at
//! each return to 0 is a likelihood ratio, a martingale of mean 1 under `q0`; by Ville's
//! inequality one climb from 0 reaches `h` with probability at most `exp(-h)`, so the
//! average number of commands between false alarms is at least `exp(h)` (Lorden, 1971).
//! With `h = ln(N / alpha)` a watch of `N` commands raises falsely with probability at
//! most `alpha`: the default, [`ChangeDetector::default`], is `N / alpha = 8,000` (`h` =
//! 8.99): at most 5% of missions of 400 commands without a change, and 1.25% of missions
//! of 100. The bound holds whenever the behavior's rate is at most `q0`: below it, `exp(S)`
//! is a supermartingale (`E[exp(step)]` grows with the rate and is 1 at `q0`), also when
//! `q0` is set from earlier commands only, as here. Hence `q0`
//! is an upper credible bound, not the rate's estimate: a short settling episode, which
//! ended because it went well, understates the rate, and a point estimate (Laplace's rule)
//! raised false alarms on many more missions than the bound allows (docs/missions.md).
//! The bound is still not a guarantee: the rate may exceed its 95% bound, and a behavior
//! trusted by luck (the paper's watch gives such behaviors up too) is not told apart from
//! a change.

use crate::Outcome;
use serde::{Deserialize, Serialize};

/// The rate of untrustworthy commands the test looks for after a change: the rate at
/// which a behavior stops earning trust at equal weights.
pub const Q1: f64 = 0.5;

/// How sure the test is that the behavior's pre-change rate is at most the `q0` it
/// assumes: `q0` is this quantile of the rate's posterior.
pub const CREDIBILITY: f64 = 0.95;

/// The least pre-change rate the test assumes: a behavior that settled without an
/// untrustworthy command is taken to have about one in a hundred.
pub const Q0_LEAST: f64 = 0.01;

/// The change detector's one setting.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChangeDetector {
    /// The watched commands per false alarm the test allows at least (`exp(h)`): `N /
    /// alpha` for at most `alpha` false alarms over watches of `N` commands; at least 2.
    pub commands_per_false_alarm: f64,
}

impl Default for ChangeDetector {
    /// At most 5% false alarms over watches of 400 commands.
    fn default() -> Self {
        Self {
            commands_per_false_alarm: 8_000.0,
        }
    }
}

/// A change detector's setting that cannot be used.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("commands_per_false_alarm is {0}; it must be a finite number of at least 2")]
pub struct ChangeDetectorError(pub f64);

impl ChangeDetector {
    /// Checks the setting.
    pub fn validate(&self) -> Result<(), ChangeDetectorError> {
        let n = self.commands_per_false_alarm;
        if n.is_finite() && n >= 2.0 {
            Ok(())
        } else {
            Err(ChangeDetectorError(n))
        }
    }

    /// The test's threshold `h = ln(commands per false alarm)`.
    pub fn threshold(&self) -> f64 {
        self.commands_per_false_alarm.ln()
    }

    /// A test of the behavior that settled after `commands` commands, `untrustworthy` of
    /// them untrustworthy.
    pub fn watch(&self, commands: u64, untrustworthy: u64) -> Cusum {
        let mut test = Cusum {
            up: 0.0,
            down: 0.0,
            threshold: self.threshold(),
            statistic: 0.0,
            clean: (commands, untrustworthy.min(commands)),
            pending: (0, 0),
            bounded_at: 0,
        };
        test.bound_rate();
        test
    }
}

/// The [`CREDIBILITY`] quantile of the rate of untrustworthy commands after `untrustworthy`
/// of `commands` (a uniform prior: the posterior is `Beta(f + 1, n - f + 1)`), by
/// bisection. For whole parameters the Beta's distribution function is a binomial tail,
/// `P(X <= x) = P(Binomial(n + 1, x) >= f + 1)`.
fn upper_bound(commands: u64, untrustworthy: u64) -> f64 {
    let trials = commands + 1;
    let at_least = untrustworthy + 1;
    let cdf = |x: f64| {
        // 1 - P(Binomial(trials, x) < at_least), the terms summed in logs.
        let (ln_x, ln_rest) = (x.ln(), (1.0 - x).ln());
        let mut ln_choose = 0.0; // ln C(trials, k), k from 0
        let mut below = 0.0;
        for k in 0..at_least {
            below += (ln_choose + k as f64 * ln_x + (trials - k) as f64 * ln_rest).exp();
            ln_choose += ((trials - k) as f64).ln() - ((k + 1) as f64).ln();
        }
        1.0 - below
    };
    let (mut low, mut high) = (0.0, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (low + high);
        if cdf(mid) < CREDIBILITY {
            low = mid;
        } else {
            high = mid;
        }
    }
    0.5 * (low + high)
}

/// The CUSUM of one watched behavior (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cusum {
    /// What an untrustworthy command adds: `ln(q1 / q0)`.
    up: f64,
    /// What any other command adds: `ln((1 - q1) / (1 - q0))`, below 0.
    down: f64,
    threshold: f64,
    statistic: f64,
    /// The record `q0` is bounded from: the settling episode's commands and untrustworthy
    /// ones, then every watched command up to the statistic's last return to 0.
    clean: (u64, u64),
    /// The watched commands (and untrustworthy ones) since the statistic last stood at 0.
    pending: (u64, u64),
    /// The commands of `clean` when `q0` was last bounded.
    bounded_at: u64,
}

impl Cusum {
    /// Records one watched command; returns whether the test raises (a change).
    pub fn record(&mut self, outcome: &Outcome) -> bool {
        let untrustworthy = outcome.is_untrustworthy();
        let step = if untrustworthy { self.up } else { self.down };
        self.pending.0 += 1;
        self.pending.1 += u64::from(untrustworthy);
        self.statistic = (self.statistic + step).max(0.0);
        if self.statistic == 0.0 {
            // No evidence of a change in the commands since the last return to 0: they
            // join the record the pre-change rate is bounded from.
            self.clean.0 += self.pending.0;
            self.clean.1 += self.pending.1;
            self.pending = (0, 0);
            if self.clean.0 * 10 >= self.bounded_at * 11 {
                self.bound_rate();
            }
        }
        self.statistic >= self.threshold
    }

    /// Sets `q0` to the upper bound of the clean record's rate, and the steps with it.
    fn bound_rate(&mut self) {
        let (commands, untrustworthy) = self.clean;
        let q0 = upper_bound(commands, untrustworthy).max(Q0_LEAST);
        (self.up, self.down) = if q0 < Q1 {
            ((Q1 / q0).ln(), ((1.0 - Q1) / (1.0 - q0)).ln())
        } else {
            // The record cannot rule out a rate of 1/2 already: no rise to 1/2 can be
            // told from it, and the test waits (the thresholds still watch).
            (0.0, 0.0)
        };
        self.bounded_at = commands;
    }

    /// The statistic `S`.
    pub fn statistic(&self) -> f64 {
        self.statistic
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn the_test_by_hand() {
        // Settled after 9 commands, none untrustworthy: the posterior is Beta(1, 10), whose
        // 95% quantile solves 1 - (1 - q)^10 = 0.95: 1 - 0.05^(1/10) = 0.25887.
        assert!((upper_bound(9, 0) - (1.0 - 0.05f64.powf(0.1))).abs() < 1e-9);
        // After 3 of 3 untrustworthy, Beta(4, 1): q^4 = 0.95.
        assert!((upper_bound(3, 3) - 0.95f64.powf(0.25)).abs() < 1e-9);
        // After 19 commands, none untrustworthy: q0 = 1 - 0.05^(1/20) = 0.13911.
        let q0 = 1.0 - 0.05f64.powf(1.0 / 20.0);
        assert!((upper_bound(19, 0) - q0).abs() < 1e-9);
        let detector = ChangeDetector::default();
        assert!((detector.threshold() - 8_000f64.ln()).abs() < 1e-12);
        let mut test = detector.watch(19, 0);
        let (up, down) = ((0.5 / q0).ln(), (0.5 / (1.0 - q0)).ln());
        assert!(!test.record(&Outcome::completed(1.0 / 3.0, 1.0)));
        assert_eq!(test.statistic(), 0.0, "kept at 0 or above");
        assert!(!test.record(&Outcome::failed(1.0 / 3.0, 1.0)));
        assert!((test.statistic() - up).abs() < 1e-12);
        assert!(!test.record(&Outcome::completed(1.0 / 3.0, 1.0)));
        assert!((test.statistic() - (up + down)).abs() < 1e-12);
        // From 0, untrustworthy commands alone raise it after ceil(h / up) = 8 of them
        // (up = ln(0.5 / 0.13911) = 1.2794, and 8.987 / 1.2794 = 7.02).
        let mut fresh = detector.watch(19, 0);
        let raised: Vec<bool> = (0..8)
            .map(|_| fresh.record(&Outcome::interrupted(1.0 / 3.0, 1.0)))
            .collect();
        assert_eq!(
            raised,
            [false, false, false, false, false, false, false, true]
        );
        // q0 is at least Q0_LEAST; a record that cannot rule out 1/2 leaves the test
        // waiting.
        let clean = detector.watch(100_000, 0);
        assert!((clean.up - (Q1 / Q0_LEAST).ln()).abs() < 1e-12);
        let mut rough = detector.watch(10, 4);
        assert_eq!((rough.up, rough.down), (0.0, 0.0));
        assert!((0..100).all(|_| !rough.record(&Outcome::interrupted(1.0, 1.0))));
    }

    #[test]
    fn the_bound_tightens_with_the_commands_that_showed_no_change() {
        // Settled after 9 commands: q0 = 0.25887.
        let mut test = ChangeDetector::default().watch(9, 0);
        assert!((test.up - (0.5 / (1.0 - 0.05f64.powf(0.1))).ln()).abs() < 1e-9);
        // 290 completions, each leaving the statistic at 0, join the record: after 299
        // commands without an untrustworthy one, q0 = 1 - 0.05^(1/300) = 0.009937, kept at
        // Q0_LEAST = 0.01 (bounded afresh at each tenth of growth, so from 290 or fewer
        // of them: at most 1 - 0.05^(1/265) = 0.0112).
        for _ in 0..290 {
            assert!(!test.record(&Outcome::completed(1.0, 1.0)));
        }
        assert_eq!(test.clean, (299, 0));
        assert!(test.up >= (0.5f64 / 0.0112).ln() && test.up <= (0.5f64 / Q0_LEAST).ln() + 1e-12);
        // Commands while the statistic is above 0 wait: they may be the change's.
        test.record(&Outcome::failed(1.0, 1.0));
        assert_eq!((test.clean, test.pending), ((299, 0), (1, 1)));
    }

    #[test]
    fn settings_outside_the_range_are_refused() {
        for bad in [1.0, 0.0, -5.0, f64::NAN, f64::INFINITY] {
            let detector = ChangeDetector {
                commands_per_false_alarm: bad,
            };
            assert!(detector.validate().is_err(), "{bad}");
        }
        assert!(ChangeDetector::default().validate().is_ok());
        let read: ChangeDetector = ron::from_str("(commands_per_false_alarm: 400.0)").unwrap();
        assert_eq!(read.commands_per_false_alarm, 400.0);
    }

    #[test]
    fn false_alarms_stay_within_the_bound_when_the_rate_is_known() {
        // 2,000 watches of 400 commands at the rate the test assumes (q0 = 0.13911 after
        // 19 commands without an untrustworthy one): the bound allows 5% of them to raise;
        // the test must not exceed it (a binomial allowance of three standard deviations
        // over 5% of 2,000 is 129).
        let detector = ChangeDetector::default();
        let q0 = upper_bound(19, 0);
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut raised = 0;
        for _ in 0..2_000 {
            let mut test = detector.watch(19, 0);
            if (0..400).any(|_| {
                let failed = rng.random::<f64>() < q0;
                test.record(&if failed {
                    Outcome::failed(1.0, 1.0)
                } else {
                    Outcome::completed(1.0, 1.0)
                })
            }) {
                raised += 1;
            }
        }
        assert!(raised <= 129, "{raised} of 2000");
    }
}
