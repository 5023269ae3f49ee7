//! Driving a planned path: the speed profile (commanded speed, acceleration limits, corner
//! slow-downs, stops) and the non-deterministic part, the cross-track error.
//!
//! The cross-track error is an Ornstein-Uhlenbeck process in arc length: correlated over
//! [`Robot::error_correlation`] metres, with a spread that grows with speed
//! ([`Robot::cross_track_sd`]). It is drawn exactly (the OU transition over any distance)
//! at the plan's clearance samples that are close enough to an obstacle to matter; where
//! it exceeds the gap to an obstacle the robot touches it, stops, backs off and goes on
//! (losing [`Robot::collision_pause`] plus the time to brake and accelerate again).

use crate::geometry::Vec2;
use crate::planner::Plan;
use crate::profile::{Profile, Station};
use crate::trace::{EventKind, Trace};
use crate::world::Robot;
use rand::{Rng, RngCore};
use rand_distr::StandardNormal;

/// A point of interest along the path: the robot either passes it or stops there for
/// `dwell` seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mark {
    /// Arc length (m).
    pub s: f64,
    /// Seconds spent stopped there (0: drive past without stopping).
    pub dwell: f64,
}

/// What the drive produced besides the events it wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct Drive {
    /// When the robot reached each mark (s), in the order given.
    pub mark_times: Vec<f64>,
    /// When the robot passed each watched arc length and its speed there (s, m/s), in the
    /// order given.
    pub watched: Vec<(f64, f64)>,
    /// The arrival its own plan promised: the nominal drive plus the dwells (s).
    pub planned: f64,
    /// When it arrived at the goal (s).
    pub arrival: f64,
    /// Where it stopped.
    pub end: Vec2,
}

/// Samples whose gap exceeds this many standard deviations of the cross-track error are
/// not drawn: the chance of touching there is below 1e-9.
const NEGLIGIBLE_SD: f64 = 6.0;

/// Drives `plan` at commanded `speed`, stopping at the marks with a dwell, writing
/// collisions and the arrival into `trace`. `marks` must be sorted by `s`. When `track` is
/// given, the driven positions (planned point plus cross-track error) are appended to it.
///
/// Also written, from quantities the drive has anyway (no random draw): the least gap
/// between body and obstacle at the samples it drew the error at, without a collision
/// there (a `ClosestPass`), and, when collisions delayed the arrival past the planned one,
/// a `BehindPlan` at the planned arrival. `watch` (sorted arc lengths) are timed as the
/// marks are, with the speed there, into [`Drive::watched`].
#[allow(clippy::too_many_arguments)]
pub fn drive(
    plan: &Plan,
    robot: &Robot,
    speed: f64,
    marks: &[Mark],
    watch: &[f64],
    rng: &mut dyn RngCore,
    trace: &mut Trace,
    track: Option<&mut Vec<Vec2>>,
) -> Drive {
    let profile = profile(plan, robot, speed, marks);
    let mut mark_times = Vec::with_capacity(marks.len());
    let mut watched = Vec::with_capacity(watch.len());
    let mut next_watch = 0;
    let watch_at = |i: usize| watch.get(i).copied().unwrap_or(f64::INFINITY);
    let mut next_watch_at = watch_at(0);
    // The least body gap at a drawn sample without a collision: (gap, sample, the delay
    // then, the error there); timed once, at the end.
    let mut least: Option<(f64, usize, f64, f64)> = None;
    let mut collided = false;
    let mut next_mark = 0;
    let mut delay = 0.0;
    // The error in units of its standard deviation: a stationary OU process in arc length.
    let mut x: f64 = rng.sample(StandardNormal);
    let mut x_at = 0.0;
    let mut drawn: Vec<(usize, f64)> = Vec::new();
    let recording = track.is_some();
    if recording {
        drawn.push((0, x));
    }
    let spread_at_speed = robot.cross_track_sd(speed);
    let negligible = NEGLIGIBLE_SD * spread_at_speed;
    // The stretch of the profile the last drawn sample lay on, where the next one starts,
    // its peak speed and the error's spread at that speed (computed once per stretch, not
    // per sample).
    let mut stretch = None;
    let mut next_stretch_at = f64::NEG_INFINITY;
    let mut speed_and_spread = (0.0, robot.cross_track_sd(0.0));
    // The plan's stored transitions from each sample's predecessor (from the start for
    // the first), and the sample whose stored transition applies: the one after the
    // sample the error was last drawn at.
    let transitions = plan.error_transitions(robot).unwrap_or_default();
    let mut neighbour = 0;
    let last = plan.samples.len() - 1;
    let mut error = 0.0;
    // Samples far from every obstacle draw nothing and change nothing, so only the close
    // ones (and the goal) are visited; the marks passed on the way are timed on arrival
    // at the next visited sample, with the delay that held there all along.
    let mark_at = |i: usize| marks.get(i).map_or(f64::INFINITY, |m| m.s);
    let mut next_mark_at = mark_at(0);
    for (k, sample) in plan.samples_closer_than(negligible) {
        // Marks and watched points in the order the robot passes them: a watched point
        // before a stop is passed before its dwell.
        while next_mark_at.min(next_watch_at) <= sample.s {
            if next_watch_at <= next_mark_at {
                let (t, v) = profile.time_and_speed_at(next_watch_at);
                watched.push((t + delay, v));
                next_watch += 1;
                next_watch_at = watch_at(next_watch);
            } else {
                mark_times.push(profile.time_at(next_mark_at) + delay);
                delay += marks[next_mark].dwell;
                next_mark += 1;
                next_mark_at = mark_at(next_mark);
            }
        }
        let (rho, fresh) = match transitions.get(k) {
            Some(&stored) if k == neighbour => stored,
            _ => robot.error_transition(sample.s - x_at),
        };
        x = rho * x + fresh * rng.sample::<f64, _>(StandardNormal);
        x_at = sample.s;
        neighbour = k + 1;
        if sample.s >= next_stretch_at {
            let here = profile.stretch_index(sample.s, stretch);
            if here != stretch {
                stretch = here;
                let v = here.map_or(0.0, |i| profile.peak(i));
                // Most stretches cruise at the commanded speed.
                let spread = if v == speed {
                    spread_at_speed
                } else {
                    robot.cross_track_sd(v)
                };
                speed_and_spread = (v, spread);
            }
            next_stretch_at = profile.next_stretch_start(here);
        }
        let (v, spread) = speed_and_spread;
        error = spread * x;
        if error > sample.gap_left || -error > sample.gap_right {
            let at = sample.at + sample.left * error;
            trace.push(
                profile.time_at(sample.s) + delay,
                EventKind::Collision { at },
            );
            delay += robot.collision_pause + v / (2.0 * robot.decel) + v / (2.0 * robot.accel);
            collided = true;
            // The robot backs off onto its path.
            x = 0.0;
        } else {
            let gap = (sample.gap_left - error).min(sample.gap_right + error);
            if least.is_none_or(|(g, _, _, _)| gap < g) {
                least = Some((gap, k, delay, error));
            }
        }
        if recording {
            drawn.push((k, x));
        }
    }
    let goal = &plan.samples[last];
    let end = goal.at + goal.left * error;
    while next_mark < marks.len() {
        mark_times.push(profile.total() + delay);
        delay += marks[next_mark].dwell;
        next_mark += 1;
    }
    // Beyond the goal: reached on arrival.
    while next_watch < watch.len() {
        watched.push((profile.total() + delay, 0.0));
        next_watch += 1;
    }
    let arrival = profile.total() + delay;
    let planned = profile.total() + marks.iter().map(|m| m.dwell).sum::<f64>();
    if let Some((gap, k, delay_then, error_then)) = least {
        let sample = &plan.samples[k];
        let at = sample.at + sample.left * error_then;
        let t = profile.time_at(sample.s) + delay_then;
        trace.insert_sorted(t, EventKind::ClosestPass { gap, at });
    }
    // Only collisions delay a drive beyond its plan (compared as a flag: the sums of the
    // dwells are added in different orders).
    if collided {
        trace.insert_sorted(planned, EventKind::BehindPlan { planned });
    }
    trace.push(arrival, EventKind::Arrived { at: end });
    if let Some(track) = track {
        fill_track(plan, robot, &profile, &drawn, track);
    }
    Drive {
        mark_times,
        watched,
        planned,
        arrival,
        end,
    }
}

/// The driven positions at every sample: where the error was drawn, the drawn value; in
/// between, the error's expected value given its two drawn neighbours (the mean of the
/// Ornstein-Uhlenbeck bridge). Draws nothing, so a recorded run is the same run.
fn fill_track(
    plan: &Plan,
    robot: &Robot,
    profile: &Profile,
    drawn: &[(usize, f64)],
    track: &mut Vec<Vec2>,
) {
    let k = 1.0 / robot.error_correlation;
    for pair in drawn.windows(2) {
        let ((i, xi), (j, xj)) = (pair[0], pair[1]);
        let (si, sj) = (plan.samples[i].s, plan.samples[j].s);
        for sample in &plan.samples[i..j] {
            let span = (k * (sj - si)).sinh();
            let x = if span > 0.0 {
                (xi * (k * (sj - sample.s)).sinh() + xj * (k * (sample.s - si)).sinh()) / span
            } else {
                xi
            };
            let error = robot.cross_track_sd(profile.stretch_peak(sample.s)) * x;
            track.push(sample.at + sample.left * error);
        }
    }
    if let Some(&(j, xj)) = drawn.last() {
        let sample = &plan.samples[j];
        track.push(
            sample.at + sample.left * robot.cross_track_sd(profile.stretch_peak(sample.s)) * xj,
        );
    }
}

/// The speed profile: standstill at both ends and at every mark with a dwell, corners
/// taken no faster than the lateral-acceleration limit allows on the rounding arc.
fn profile(plan: &Plan, robot: &Robot, speed: f64, marks: &[Mark]) -> Profile {
    let angles = plan.turn_angles();
    let last = plan.points.len() - 1;
    let corners = plan
        .arc
        .iter()
        .zip(angles)
        .enumerate()
        .map(|(i, (&s, &theta))| {
            let limit = if i == 0 || i == last {
                0.0
            } else if theta > 0.0 {
                (robot.lateral_accel * robot.corner_arc / theta).sqrt()
            } else {
                f64::INFINITY
            };
            Station { s, limit }
        });
    let stops = marks
        .iter()
        .filter(|m| m.dwell > 0.0)
        .map(|m| Station { s: m.s, limit: 0.0 });
    // Both are sorted along the path: merge them, a corner before a stop at the same place.
    let mut stops = stops.peekable();
    let mut stations = Vec::with_capacity(plan.points.len() + marks.len());
    for corner in corners {
        while let Some(stop) = stops.next_if(|stop| stop.s.total_cmp(&corner.s).is_lt()) {
            stations.push(stop);
        }
        stations.push(corner);
    }
    stations.extend(stops);
    Profile::new(&stations, speed, robot.accel, robot.decel)
}

/// Duration of the drive along `plan` at `speed` with no collisions and no stops (s).
pub fn nominal_duration(plan: &Plan, robot: &Robot, speed: f64) -> f64 {
    profile(plan, robot, speed, &[]).total()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn straight(length: f64) -> Plan {
        Plan::new(
            vec![Vec2::new(10.0, 10.0), Vec2::new(10.0 + length, 10.0)],
            &[],
            &Robot::wheeled_ugv(),
            Vec2::new(1000.0, 1000.0),
        )
    }

    #[test]
    fn an_open_straight_drive_takes_the_trapezoid_time() {
        let robot = Robot::wheeled_ugv();
        let plan = straight(40.0);
        let mut trace = Trace::default();
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let d = drive(&plan, &robot, 4.0, &[], &[], &mut rng, &mut trace, None);
        // 4 m/s: 2 s up (4 m), 4/3 s down (8/3 m), the rest cruising.
        let expected = 2.0 + 4.0 / 3.0 + (40.0 - 4.0 - 8.0 / 3.0) / 4.0;
        assert!((d.arrival - expected).abs() < 1e-9);
        assert_eq!(trace.collisions(), 0);
        // In the open nothing is close: the only gap measured is at the goal (always
        // visited), no delay; then the arrival.
        assert_eq!(trace.events.len(), 2);
        assert!(matches!(trace.events[0].kind, EventKind::ClosestPass { gap, .. } if gap > 9.0));
        assert_eq!(d.planned, d.arrival);
    }

    #[test]
    fn a_dwell_adds_its_time_and_the_stop() {
        let robot = Robot::wheeled_ugv();
        let plan = straight(40.0);
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let marks = [Mark {
            s: 20.0,
            dwell: 3.0,
        }];
        let d = drive(
            &plan,
            &robot,
            4.0,
            &marks,
            &[],
            &mut rng,
            &mut Trace::default(),
            None,
        );
        // Two 20 m drives from standstill to standstill, plus 3 s.
        let leg = 2.0 + 4.0 / 3.0 + (20.0 - 4.0 - 8.0 / 3.0) / 4.0;
        assert!((d.arrival - (2.0 * leg + 3.0)).abs() < 1e-9);
        assert!((d.mark_times[0] - leg).abs() < 1e-9);
    }

    #[test]
    fn watched_points_are_timed_with_their_speed_and_only_later_dwells() {
        let robot = Robot::wheeled_ugv();
        let plan = straight(40.0);
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let marks = [Mark {
            s: 20.0,
            dwell: 3.0,
        }];
        let mut trace = Trace::default();
        let d = drive(
            &plan,
            &robot,
            4.0,
            &marks,
            &[10.0, 20.0, 30.0],
            &mut rng,
            &mut trace,
            None,
        );
        let leg = 2.0 + 4.0 / 3.0 + (20.0 - 4.0 - 8.0 / 3.0) / 4.0;
        // 10 m: cruising at 4 m/s, 4 m of speed-up (2 s) and 6 m at 4 m/s; no dwell yet.
        assert!((d.watched[0].0 - 3.5).abs() < 1e-9);
        assert!((d.watched[0].1 - 4.0).abs() < 1e-9);
        // At the stop: standing, before its dwell.
        assert!((d.watched[1].0 - leg).abs() < 1e-9);
        assert!(d.watched[1].1.abs() < 1e-9);
        // 30 m: the dwell behind it.
        assert!((d.watched[2].0 - (leg + 3.0 + 3.5)).abs() < 1e-9);
        assert_eq!(d.planned, d.arrival);
    }
}
