//! The patrol task's own physics: where the suspicious objects lie, whether the robot's
//! camera spots one as it drives by, and what the detour to scan it costs.
//!
//! Spotting: the camera sees out to `range`; an object at lateral distance `d` from the
//! path stays in view over a chord `2 sqrt(range^2 - d^2)`, i.e. for `chord / v * fps`
//! frames at speed `v`. Each frame finds the object with probability
//! `p_frame / (1 + (v * exposure / blur_tolerance)^2)`: motion blur of `v * exposure`
//! metres smears the object's features. Faster means fewer and blurrier frames.

use crate::geometry::{BoundedShape, Vec2, within};
use crate::world::World;
use rand::{Rng, RngCore};
use serde::{Deserialize, Serialize};

/// The patrol's objects and the robot's camera.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PatrolSetup {
    /// Suspicious objects placed per run.
    pub objects: usize,
    /// At most this many of them are explosive (uniform from 0).
    pub max_explosive: usize,
    /// Objects lie this far from the street centre line, either side (m).
    pub lateral_band: (f64, f64),
    /// And at least this far from any building, vehicle, barrier or cone (m).
    pub free_space: f64,
    /// Camera range (m).
    pub camera_range: f64,
    /// Camera frame rate (frames/s).
    pub frame_rate: f64,
    /// Probability that one sharp frame shows the object as suspicious.
    pub p_frame: f64,
    /// Exposure time of a frame (s).
    pub exposure: f64,
    /// Motion blur (m) at which a frame's detection probability halves.
    pub blur_tolerance: f64,
    /// Seconds between labelling an explosive harmless and its detonation.
    pub fuse: f64,
}

impl Default for PatrolSetup {
    fn default() -> Self {
        Self {
            objects: 6,
            max_explosive: 3,
            lateral_band: (1.0, 4.0),
            free_space: 0.5,
            camera_range: 5.0,
            frame_rate: 10.0,
            p_frame: 0.25,
            exposure: 0.02,
            blur_tolerance: 0.1,
            fuse: 10.0,
        }
    }
}

/// A suspicious object.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SuspiciousObject {
    /// Where it lies.
    pub at: Vec2,
    /// Whether it is an explosive.
    pub explosive: bool,
}

/// The ground the objects are placed on, measured once per world: the patrol line's legs
/// (start, direction, length) and the obstacles an object keeps clear of, with their
/// bounding boxes.
#[derive(Clone, Debug, PartialEq)]
pub struct PatrolGround {
    legs: Vec<(Vec2, Vec2, f64)>,
    total: f64,
    size: Vec2,
    obstacles: Vec<BoundedShape>,
}

impl PatrolGround {
    /// The ground of `world`'s patrol route.
    pub fn new(world: &World) -> Self {
        let legs: Vec<(Vec2, Vec2, f64)> = world
            .patrol_route
            .windows(2)
            .map(|w| (w[0], (w[1] - w[0]).unit(), w[0].dist(w[1])))
            .collect();
        Self {
            total: legs.iter().map(|leg| leg.2).sum(),
            legs,
            size: world.size,
            obstacles: world
                .obstacles
                .iter()
                .map(|o| BoundedShape::new(&o.shape))
                .collect(),
        }
    }
}

impl PatrolSetup {
    /// Places the run's objects near the patrol route, in open ground; between 0 and
    /// `max_explosive` of them (uniform) are explosive.
    pub fn place(&self, ground: &PatrolGround, rng: &mut dyn RngCore) -> Vec<SuspiciousObject> {
        let mut objects = Vec::with_capacity(self.objects);
        while objects.len() < self.objects {
            let mut s = rng.random_range(0.0..ground.total);
            let mut k = 0;
            while k + 1 < ground.legs.len() && s > ground.legs[k].2 {
                s -= ground.legs[k].2;
                k += 1;
            }
            let (start, dir, _) = ground.legs[k];
            let side = if rng.random::<bool>() { 1.0 } else { -1.0 };
            let offset = rng.random_range(self.lateral_band.0..self.lateral_band.1) * side;
            let at = start + dir * s + dir.left() * offset;
            let open = within(at, ground.size, self.free_space)
                && ground
                    .obstacles
                    .iter()
                    .all(|o| o.keeps_clear(at, at, self.free_space));
            if open {
                objects.push(SuspiciousObject {
                    at,
                    explosive: false,
                });
            }
        }
        let explosive = rng.random_range(0..=self.max_explosive.min(self.objects));
        // A partial Fisher-Yates shuffle picks which ones.
        let mut order: Vec<usize> = (0..self.objects).collect();
        for i in 0..explosive {
            let j = rng.random_range(i..self.objects);
            order.swap(i, j);
            objects[order[i]].explosive = true;
        }
        objects
    }

    /// Probability that the camera spots an object `distance` metres from the path while
    /// the robot drives by at `speed`.
    pub fn p_spot(&self, distance: f64, speed: f64) -> f64 {
        if distance >= self.camera_range {
            return 0.0;
        }
        let chord = 2.0 * (self.camera_range.powi(2) - distance * distance).sqrt();
        let frames = chord / speed * self.frame_rate;
        let blur = speed * self.exposure / self.blur_tolerance;
        let p = self.p_frame / (1.0 + blur * blur);
        1.0 - (1.0 - p).powf(frames)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn spotting_by_hand() {
        let setup = PatrolSetup::default();
        // 3 m off the path at 2 m/s: chord 8 m, 40 frames; blur 0.04 m: p = 0.25 / 1.16.
        let p: f64 = 0.25 / 1.16;
        let expected = 1.0 - (1.0 - p).powf(40.0);
        assert!((setup.p_spot(3.0, 2.0) - expected).abs() < 1e-12);
        assert_eq!(setup.p_spot(5.0, 2.0), 0.0);
    }

    #[test]
    fn spotting_falls_with_speed_and_distance() {
        let setup = PatrolSetup::default();
        for k in 1..20 {
            let v = 0.5 * f64::from(k);
            assert!(setup.p_spot(2.0, v + 0.5) < setup.p_spot(2.0, v));
            assert!(setup.p_spot(4.5, v) < setup.p_spot(2.0, v));
        }
        assert!(setup.p_spot(4.5, 3.0) < setup.p_spot(4.0, 3.0));
    }

    #[test]
    fn objects_lie_in_open_ground_with_up_to_three_explosives() {
        let world = World::urban_block();
        let setup = PatrolSetup::default();
        let ground = PatrolGround::new(&world);
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let mut seen = [false; 4];
        for _ in 0..200 {
            let objects = setup.place(&ground, &mut rng);
            assert_eq!(objects.len(), 6);
            let explosive = objects.iter().filter(|o| o.explosive).count();
            seen[explosive] = true;
            for o in &objects {
                assert!(
                    world
                        .obstacles
                        .iter()
                        .all(|x| x.shape.distance_to_point(o.at) >= 0.5)
                );
            }
        }
        assert_eq!(seen, [true; 4]);
    }
}
