//! The explosives detector: a counting sensor (a trace-vapour or radiation counter) whose
//! accuracy rises with scan time and falls with distance.
//!
//! Model. The detector counts particles for the scan time `T`. A harmless object gives
//! only background, at rate `b`; an explosive adds a signal at rate
//! `s(d) = s0 / (1 + (d / d0)^2)`: inverse-square spreading from the source, with the
//! sensor's near-field saturation at `d0`. The detector calls "explosive" when the count
//! exceeds the midpoint of the two expected counts, `(b + s/2) T`. With the normal
//! approximation of Poisson counts,
//!
//! - P(correct | harmless)  = Phi((s T / 2) / sqrt(b T))
//! - P(correct | explosive) = Phi((s T / 2) / sqrt((b + s) T))
//!
//! Both grow as `sqrt(T)` and with `s(d)`, so time and distance trade off: the same
//! accuracy needs a scan `(1 + (d/d0)^2)^2` times longer at distance `d` than at contact.

use serde::{Deserialize, Serialize};

/// Detector physics.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Detector {
    /// Background count rate (counts/s).
    pub background: f64,
    /// Signal count rate of an explosive at contact (counts/s).
    pub signal_at_contact: f64,
    /// Distance at which the signal has fallen to half (m).
    pub half_signal_distance: f64,
}

impl Default for Detector {
    fn default() -> Self {
        Self {
            background: 20.0,
            signal_at_contact: 40.0,
            half_signal_distance: 0.5,
        }
    }
}

impl Detector {
    /// Signal rate at distance `d` (counts/s).
    pub fn signal(&self, distance: f64) -> f64 {
        let r = distance / self.half_signal_distance;
        self.signal_at_contact / (1.0 + r * r)
    }

    /// Probability that an object is labelled correctly after scanning it for
    /// `scan_time` seconds from `distance` metres.
    pub fn accuracy(&self, explosive: bool, scan_time: f64, distance: f64) -> f64 {
        let s = self.signal(distance);
        let noise_rate = if explosive {
            self.background + s
        } else {
            self.background
        };
        let z = (s * scan_time / 2.0) / (noise_rate * scan_time).sqrt();
        normal_cdf(z)
    }
}

/// The standard normal distribution function, from the complementary error function
/// (Numerical Recipes' Chebyshev fit, relative error below 1.2e-7).
pub fn normal_cdf(z: f64) -> f64 {
    0.5 * erfc(-z / std::f64::consts::SQRT_2)
}

fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let poly = -z * z - 1.265_512_23
        + t * (1.000_023_68
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_203_98
                                + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    let r = t * poly.exp();
    if x >= 0.0 { r } else { 2.0 - r }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn normal_cdf_known_values() {
        assert!((normal_cdf(0.0) - 0.5).abs() < 1e-7);
        assert!((normal_cdf(1.0) - 0.841_344_746).abs() < 1e-6);
        assert!((normal_cdf(-1.959_964) - 0.025).abs() < 1e-6);
    }

    #[test]
    fn accuracy_by_hand() {
        let d = Detector::default();
        // At 0.5 m the signal is half of 40: 20 counts/s. Harmless, 1 s: z = 10 / sqrt(20).
        let expected = normal_cdf(10.0 / 20.0_f64.sqrt());
        assert!((d.accuracy(false, 1.0, 0.5) - expected).abs() < 1e-12);
        // Explosive: noise from 40 counts/s: z = 10 / sqrt(40).
        let expected = normal_cdf(10.0 / 40.0_f64.sqrt());
        assert!((d.accuracy(true, 1.0, 0.5) - expected).abs() < 1e-12);
    }

    #[test]
    fn time_and_distance_trade_off() {
        let d = Detector::default();
        // (1 + (1/0.5)^2)^2 / (1 + (0.5/0.5)^2)^2 = 25 / 4: 1 s at 0.5 m equals 6.25 s at 1 m.
        let near = d.accuracy(false, 1.0, 0.5);
        let far = d.accuracy(false, 6.25, 1.0);
        assert!((near - far).abs() < 1e-12);
    }

    proptest! {
        #[test]
        fn accuracy_is_monotone(t in 0.1f64..10.0, dt in 0.01f64..5.0,
                                dist in 0.0f64..3.0, dd in 0.01f64..2.0,
                                explosive: bool) {
            let d = Detector::default();
            let a = d.accuracy(explosive, t, dist);
            prop_assert!(d.accuracy(explosive, t + dt, dist) >= a);
            prop_assert!(d.accuracy(explosive, t, dist + dd) <= a);
            prop_assert!((0.5..=1.0).contains(&a));
        }
    }
}
