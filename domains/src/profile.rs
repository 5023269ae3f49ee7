//! The speed profile of a drive along a path: the robot accelerates and brakes within its
//! limits, never exceeds the commanded speed, slows for corners and stops where it must.
//! Timing is analytic (trapezoids), so a run costs no time stepping.

/// A point along the path where the speed is capped (a corner, a stop).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Station {
    /// Arc length (m).
    pub s: f64,
    /// Highest speed allowed when passing it (m/s).
    pub limit: f64,
}

/// One stretch between consecutive stations: entry, peak and exit speeds, and the shape of
/// its trapezoid (measured once, read by every time asked of it).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Stretch {
    s0: f64,
    length: f64,
    entry: f64,
    peak: f64,
    exit: f64,
    t0: f64,
    /// Lengths of the speed-up, the cruise and the slow-down (m).
    up: f64,
    cruise: f64,
    /// Time to the end of the speed-up (s).
    t_up: f64,
}

/// Time and speed as functions of arc length for one drive.
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    stretches: Vec<Stretch>,
    accel: f64,
    decel: f64,
    total: f64,
}

impl Profile {
    /// The fastest drive through `stations` (sorted by `s`, first at the start and last at
    /// the goal, both with limit 0) under the speed cap and the two acceleration limits.
    pub fn new(stations: &[Station], cap: f64, accel: f64, decel: f64) -> Self {
        let n = stations.len();
        let mut v: Vec<f64> = stations.iter().map(|st| st.limit.min(cap)).collect();
        for i in 1..n {
            let length = stations[i].s - stations[i - 1].s;
            v[i] = v[i].min((v[i - 1] * v[i - 1] + 2.0 * accel * length).sqrt());
        }
        for i in (0..n.saturating_sub(1)).rev() {
            let length = stations[i + 1].s - stations[i].s;
            v[i] = v[i].min((v[i + 1] * v[i + 1] + 2.0 * decel * length).sqrt());
        }
        let mut stretches = Vec::with_capacity(n.saturating_sub(1));
        let mut t = 0.0;
        for i in 0..n.saturating_sub(1) {
            let length = stations[i + 1].s - stations[i].s;
            let (u, w) = (v[i], v[i + 1]);
            let peak = cap.min(
                ((2.0 * accel * decel * length + decel * u * u + accel * w * w) / (accel + decel))
                    .sqrt(),
            );
            let stretch = Stretch::new(stations[i].s, length, (u, peak, w), t, accel, decel);
            t += stretch.duration(accel, decel);
            stretches.push(stretch);
        }
        Self {
            stretches,
            accel,
            decel,
            total: t,
        }
    }

    /// Duration of the whole drive (s).
    pub fn total(&self) -> f64 {
        self.total
    }

    fn stretch_at(&self, s: f64) -> Option<&Stretch> {
        self.stretch_index(s, None).map(|k| &self.stretches[k])
    }

    /// Time at which the robot passes arc length `s` (s).
    pub fn time_at(&self, s: f64) -> f64 {
        match self.stretch_at(s) {
            Some(st) => st.t0 + st.time_into(s - st.s0, self.accel, self.decel),
            None => 0.0,
        }
    }

    /// The speed at arc length `s` (m/s): on the trapezoid of the stretch containing it.
    pub fn speed_at(&self, s: f64) -> f64 {
        self.time_and_speed_at(s).1
    }

    /// [`Profile::time_at`] and [`Profile::speed_at`] with one look-up of the stretch.
    pub fn time_and_speed_at(&self, s: f64) -> (f64, f64) {
        self.stretch_at(s).map_or((0.0, 0.0), |st| {
            let x = s - st.s0;
            (
                st.t0 + st.time_into(x, self.accel, self.decel),
                st.speed_into(x, self.accel, self.decel),
            )
        })
    }

    /// The highest speed reached on the stretch containing `s` (m/s): a cheap, slightly
    /// high stand-in for the speed at `s`.
    pub fn stretch_peak(&self, s: f64) -> f64 {
        self.stretch_at(s).map_or(0.0, |st| st.peak)
    }

    /// The peak speed of stretch `index` (m/s).
    pub fn peak(&self, index: usize) -> f64 {
        self.stretches[index].peak
    }

    /// Where the stretch after stretch `index` starts (`None`: where the first starts), or
    /// infinity after the last: up to there [`Profile::stretch_index`] answers `index`.
    pub fn next_stretch_start(&self, index: Option<usize>) -> f64 {
        let next = index.map_or(0, |k| k + 1);
        self.stretches.get(next).map_or(f64::INFINITY, |st| st.s0)
    }

    /// The index ([`Profile::peak`]) of the stretch containing `s`, `None` before
    /// the first; the same stretch as [`Profile::stretch_peak`]'s. `from` is a stretch
    /// that starts at or before `s` (the answer for an earlier position), so a walk along
    /// the path finds each stretch by stepping forward rather than by a search.
    pub fn stretch_index(&self, s: f64, from: Option<usize>) -> Option<usize> {
        let mut k = match from {
            Some(k) if self.stretches[k].s0 <= s => k,
            _ => {
                return self
                    .stretches
                    .partition_point(|st| st.s0 <= s)
                    .checked_sub(1);
            }
        };
        while k + 1 < self.stretches.len() && self.stretches[k + 1].s0 <= s {
            k += 1;
        }
        Some(k)
    }
}

impl Stretch {
    /// The stretch of `length` from `s0`, entered at `t0` with the given entry, peak and
    /// exit speeds.
    fn new(
        s0: f64,
        length: f64,
        (entry, peak, exit): (f64, f64, f64),
        t0: f64,
        accel: f64,
        decel: f64,
    ) -> Self {
        let up = ((peak * peak - entry * entry) / (2.0 * accel)).max(0.0);
        let down = ((peak * peak - exit * exit) / (2.0 * decel)).max(0.0);
        Self {
            s0,
            length,
            entry,
            peak,
            exit,
            t0,
            up,
            cruise: (length - up - down).max(0.0),
            t_up: (peak - entry).max(0.0) / accel,
        }
    }

    fn duration(&self, accel: f64, decel: f64) -> f64 {
        self.time_into(self.length, accel, decel)
    }

    fn speed_into(&self, x: f64, accel: f64, decel: f64) -> f64 {
        if self.peak <= 0.0 {
            return 0.0;
        }
        let x = x.clamp(0.0, self.length);
        let rising = (self.entry * self.entry + 2.0 * accel * x).sqrt();
        let falling = (self.exit * self.exit + 2.0 * decel * (self.length - x)).sqrt();
        rising.min(falling).min(self.peak)
    }

    fn time_into(&self, x: f64, accel: f64, decel: f64) -> f64 {
        if self.peak <= 0.0 {
            return 0.0;
        }
        let x = x.clamp(0.0, self.length);
        let (up, cruise, t_up) = (self.up, self.cruise, self.t_up);
        if x <= up {
            let u = self.entry;
            return ((u * u + 2.0 * accel * x).sqrt() - u) / accel;
        }
        if x <= up + cruise {
            return t_up + (x - up) / self.peak;
        }
        // Measured back from the end of the stretch, so the exit speed is exact.
        let left = self.length - x;
        let speed = (self.exit * self.exit + 2.0 * decel * left)
            .sqrt()
            .min(self.peak);
        t_up + cruise / self.peak + (self.peak - speed) / decel
    }
}

/// Time for a straight drive of `length` from standstill to standstill (s).
pub fn point_to_point(length: f64, cap: f64, accel: f64, decel: f64) -> f64 {
    let peak = cap.min((2.0 * accel * decel * length / (accel + decel)).sqrt());
    Stretch::new(0.0, length, (0.0, peak, 0.0), 0.0, accel, decel).duration(accel, decel)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trapezoid_by_hand() {
        // 100 m at 10 m/s with 2 m/s^2 up and 2 m/s^2 down: 5 s up (25 m), 5 s down (25 m),
        // 50 m cruise in 5 s: 15 s.
        let t = point_to_point(100.0, 10.0, 2.0, 2.0);
        assert!((t - 15.0).abs() < 1e-9);
        // Too short to reach the cap: 8 m at 2 m/s^2 both ways peaks at 4 m/s after 2 s.
        let t = point_to_point(8.0, 10.0, 2.0, 2.0);
        assert!((t - 4.0).abs() < 1e-9);
    }

    #[test]
    fn a_stop_in_the_middle_costs_the_ramps() {
        let stations = [
            Station { s: 0.0, limit: 0.0 },
            Station {
                s: 50.0,
                limit: 0.0,
            },
            Station {
                s: 100.0,
                limit: 0.0,
            },
        ];
        let p = Profile::new(&stations, 10.0, 2.0, 2.0);
        // Two 50 m trapezoids: 5 + 5 + 0 cruise... 25 m up, 25 m down, no cruise: 10 s each.
        assert!((p.total() - 20.0).abs() < 1e-9);
        assert!((p.time_at(50.0) - 10.0).abs() < 1e-9);
        assert!((p.time_at(25.0) - 5.0).abs() < 1e-9);
    }

    #[test]
    fn stepping_forward_finds_the_stretch_a_search_finds_and_keeps_it_until_the_next() {
        let stations = [
            Station { s: 0.0, limit: 0.0 },
            Station { s: 7.0, limit: 2.0 },
            Station { s: 7.0, limit: 0.0 },
            Station {
                s: 12.5,
                limit: 3.0,
            },
            Station {
                s: 30.0,
                limit: 0.0,
            },
        ];
        let p = Profile::new(&stations, 6.0, 2.0, 3.0);
        let mut from = None;
        for k in 0..=320 {
            let s = k as f64 * 0.1 - 0.5;
            let found = p.stretch_index(s, from);
            assert_eq!(found, p.stretch_index(s, None), "at {s}");
            if from.is_some() && s < p.next_stretch_start(from) {
                assert_eq!(found, from, "at {s}: before the next stretch starts");
            }
            assert_eq!(
                found.map_or(0.0, |i| p.peak(i)),
                p.stretch_peak(s),
                "at {s}"
            );
            from = found;
        }
    }

    #[test]
    fn time_is_monotone_along_the_path() {
        let stations = [
            Station { s: 0.0, limit: 0.0 },
            Station { s: 7.0, limit: 2.0 },
            Station {
                s: 30.0,
                limit: 0.0,
            },
        ];
        let p = Profile::new(&stations, 6.0, 2.0, 3.0);
        let mut last = 0.0;
        for k in 0..=300 {
            let t = p.time_at(k as f64 * 0.1);
            assert!(t >= last - 1e-12);
            last = t;
        }
        assert!((last - p.total()).abs() < 1e-9);
    }
}
