//! Driving one leg between the packing station and a shelf, with people and forklifts
//! crossing at the aisle ends.
//!
//! The speed profile is a trapezoid: the robot accelerates and brakes at its gentle
//! nominal rate and cruises at its speed (or peaks lower on a short leg). The leg passes
//! an aisle end every [`AISLE_PITCH`]; at each, someone crosses with probability
//! [`P_CROSSING`], stepping out from behind the rack end at a distance ahead uniform in
//! [`EMERGENCE_M`]. The robot reacts after [`REACTION_S`] and brakes just hard enough to
//! stop short (never more gently than its nominal rate); if that would take more than its
//! safety brake gives ([`MAX_BRAKE`]), it hits. A stop costs the time lost braking and
//! accelerating again plus a wait for the crossing to clear (longer after a collision).
//! Reasons for every number: the crate's README ("Driving").

use rand::{Rng, RngCore};
use std::ops::ControlFlow;
use trustcbr::rand;

/// Nominal acceleration and braking (m/s^2): gentle, for the load on board.
pub const NOMINAL_ACCEL: f64 = 0.5;
/// The safety brake's deceleration (m/s^2) for a loaded robot on a sealed concrete floor.
pub const MAX_BRAKE: f64 = 2.0;
/// Time from a person emerging to the brakes acting (s): lidar frame, safety controller,
/// brake.
pub const REACTION_S: f64 = 0.3;
/// Distance between aisle ends along a leg (m): a 3 m aisle between two 1.2 m racks.
pub const AISLE_PITCH: f64 = 5.4;
/// Probability that someone crosses at an aisle end as the robot passes.
pub const P_CROSSING: f64 = 0.05;
/// Distance ahead (m) at which a crossing person or forklift comes into view from behind
/// a rack end: uniform between these.
pub const EMERGENCE_M: (f64, f64) = (0.5, 4.0);
/// Time the crossing takes to clear after the robot stopped (s).
pub const CROSSING_WAIT_S: f64 = 2.0;
/// Time a collision costs beyond the stop (s): the safety field is reset and the robot
/// checked before it goes on.
pub const COLLISION_PAUSE_S: f64 = 5.0;

/// The highest speed (m/s) on a leg of `distance` m commanded at `speed`: the cruise
/// speed, or less when the leg is too short to reach it.
pub fn peak_speed(distance: f64, speed: f64) -> f64 {
    speed.min((NOMINAL_ACCEL * distance).sqrt())
}

/// Time (s) to drive `distance` m from rest to rest at `speed`, without stops.
pub fn leg_time(distance: f64, speed: f64) -> f64 {
    let v = peak_speed(distance, speed);
    distance / v + v / NOMINAL_ACCEL
}

/// Time (s) at which the stop-free profile of a `distance` m leg at `speed` reaches `x` m.
pub fn time_at(x: f64, distance: f64, speed: f64) -> f64 {
    let v = peak_speed(distance, speed);
    let ramp = v * v / (2.0 * NOMINAL_ACCEL);
    if x < ramp {
        (2.0 * x / NOMINAL_ACCEL).sqrt()
    } else if x <= distance - ramp {
        v / NOMINAL_ACCEL + (x - ramp) / v
    } else {
        leg_time(distance, speed) - (2.0 * (distance - x) / NOMINAL_ACCEL).sqrt()
    }
}

/// How the robot stopped for a crossing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stop {
    /// The deceleration it braked at (m/s^2): what the load on board felt.
    pub decel: f64,
    /// Whether it hit the crossing.
    pub collided: bool,
    /// Time lost against driving through (s).
    pub time_lost: f64,
}

/// The stop of a robot at `speed` m/s for a crossing that comes into view `ahead` m away.
pub fn stop_for(speed: f64, ahead: f64) -> Stop {
    let braking_room = ahead - speed * REACTION_S;
    let needed = if braking_room > 0.0 {
        speed * speed / (2.0 * braking_room)
    } else {
        f64::INFINITY
    };
    let collided = needed > MAX_BRAKE;
    let decel = if collided {
        MAX_BRAKE
    } else {
        needed.max(NOMINAL_ACCEL)
    };
    let wait = if collided {
        CROSSING_WAIT_S + COLLISION_PAUSE_S
    } else {
        CROSSING_WAIT_S
    };
    Stop {
        decel,
        collided,
        time_lost: speed / (2.0 * decel) + speed / (2.0 * NOMINAL_ACCEL) + wait,
    }
}

/// Drives a leg of `distance` m at `speed` m/s. `at_stop(t, stop)` hears of every stop
/// for a crossing, `t` s after the leg began, and may end the leg (`Break`; with `B = Infallible` it cannot). Returns the
/// leg's time, or `Break` when `at_stop` ended it. Draws one uniform per aisle end, and
/// one more per crossing.
pub fn drive_leg<B>(
    distance: f64,
    speed: f64,
    rng: &mut dyn RngCore,
    mut at_stop: impl FnMut(f64, Stop) -> ControlFlow<B>,
) -> ControlFlow<B, f64> {
    let v = peak_speed(distance, speed);
    let mut lost = 0.0;
    let mut x = AISLE_PITCH;
    while x < distance {
        if rng.random::<f64>() < P_CROSSING {
            let (near, far) = EMERGENCE_M;
            let ahead = near + (far - near) * rng.random::<f64>();
            let stop = stop_for(v, ahead);
            at_stop(time_at(x, distance, speed) + lost, stop)?;
            lost += stop.time_lost;
        }
        x += AISLE_PITCH;
    }
    ControlFlow::Continue(leg_time(distance, speed) + lost)
}
