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
/// (start, direction, length), the obstacles an object keeps clear of with their bounding
/// boxes, and which of them each square metre of the map needs to be measured against.
#[derive(Clone, Debug, PartialEq)]
pub struct PatrolGround {
    legs: Vec<(Vec2, Vec2, f64)>,
    total: f64,
    size: Vec2,
    obstacles: Vec<BoundedShape>,
    /// The clearance the cells were sorted for (m).
    clearance: f64,
    /// Cells per row of the map, and rows.
    columns: usize,
    rows: usize,
    /// Per cell (row by row), where its list starts in `listed`; one more entry marks the
    /// end of the last.
    cell_starts: Vec<usize>,
    /// Per cell, the obstacles whose box grown by `clearance` reaches into it.
    listed: Vec<usize>,
}

/// Side of a cell of [`PatrolGround`]'s index (m).
const CELL: f64 = 1.0;

impl PatrolGround {
    /// The ground of `world`'s patrol route, indexed for objects keeping `clearance` from
    /// every obstacle (a smaller clearance is served as well, a larger one measures every
    /// obstacle).
    pub fn new(world: &World, clearance: f64) -> Self {
        let legs: Vec<(Vec2, Vec2, f64)> = world
            .patrol_route
            .windows(2)
            .map(|w| (w[0], (w[1] - w[0]).unit(), w[0].dist(w[1])))
            .collect();
        let obstacles: Vec<BoundedShape> = world
            .obstacles
            .iter()
            .map(|o| BoundedShape::new(&o.shape))
            .collect();
        let columns = (world.size.x / CELL).ceil().max(1.0) as usize;
        let rows = (world.size.y / CELL).ceil().max(1.0) as usize;
        let mut cells = vec![Vec::new(); columns * rows];
        for (i, obstacle) in obstacles.iter().enumerate() {
            // The same grown box as `BoundedShape::keeps_clear`'s quick answer: a point in
            // no cell the box reaches is outside it, so that answer is "clear".
            let (min, max) = obstacle.bounds();
            let (low, high) = (
                cell_of(min.x - clearance, min.y - clearance, columns, rows),
                cell_of(max.x + clearance, max.y + clearance, columns, rows),
            );
            for row in low.1..=high.1 {
                for column in low.0..=high.0 {
                    cells[row * columns + column].push(i);
                }
            }
        }
        let mut cell_starts = Vec::with_capacity(cells.len() + 1);
        let mut listed = Vec::new();
        for cell in cells {
            cell_starts.push(listed.len());
            listed.extend(cell);
        }
        cell_starts.push(listed.len());
        Self {
            total: legs.iter().map(|leg| leg.2).sum(),
            legs,
            size: world.size,
            obstacles,
            clearance,
            columns,
            rows,
            cell_starts,
            listed,
        }
    }

    /// Whether `at` keeps `clearance` from every obstacle ([`BoundedShape::keeps_clear`]),
    /// measuring only the obstacles listed for its cell when the index serves `clearance`.
    fn keeps_clear(&self, at: Vec2, clearance: f64) -> bool {
        let keeps_clear = |o: &BoundedShape| o.keeps_clear(at, at, clearance);
        if clearance > self.clearance {
            return self.obstacles.iter().all(keeps_clear);
        }
        let (column, row) = cell_of(at.x, at.y, self.columns, self.rows);
        let cell = row * self.columns + column;
        self.listed[self.cell_starts[cell]..self.cell_starts[cell + 1]]
            .iter()
            .all(|&i| keeps_clear(&self.obstacles[i]))
    }
}

/// The cell (column, row) of the point `(x, y)`, points off the map in the nearest cell.
/// Never decreasing in `x` and `y`, so a box's corner cells bound the cells of its points.
fn cell_of(x: f64, y: f64, columns: usize, rows: usize) -> (usize, usize) {
    // `as` truncates towards zero and saturates (NaN gives 0): the floor, with every
    // point left of or below the map in the first column or row.
    let column = ((x / CELL) as usize).min(columns - 1);
    let row = ((y / CELL) as usize).min(rows - 1);
    (column, row)
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
            let open =
                within(at, ground.size, self.free_space) && ground.keeps_clear(at, self.free_space);
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
    use proptest::prelude::*;
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

    proptest! {
        /// The index answers as measuring every obstacle does, for the clearance it was
        /// built for, smaller and larger ones, on and off the map.
        #[test]
        fn the_cells_answer_as_every_obstacle_does(
            x in -2.0f64..82.0, y in -2.0f64..52.0, clearance in 0.0f64..1.0,
        ) {
            let world = World::urban_block();
            let ground = PatrolGround::new(&world, 0.5);
            let at = Vec2::new(x, y);
            let everyone = ground.obstacles.iter().all(|o| o.keeps_clear(at, at, clearance));
            prop_assert_eq!(ground.keeps_clear(at, clearance), everyone);
        }
    }

    #[test]
    fn a_cell_lists_the_obstacles_near_it() {
        let world = World::urban_block();
        let ground = PatrolGround::new(&world, 0.5);
        let listed = |x: f64, y: f64| {
            let cell = (y as usize) * ground.columns + x as usize;
            ground.listed[ground.cell_starts[cell]..ground.cell_starts[cell + 1]].to_vec()
        };
        // Mid-carriageway, 2 m from everything: nothing to measure. Next to the barrier
        // (x 29.8..30.2, y 9..17), grown by 0.5 m: the barrier (index 13) alone.
        assert_eq!(listed(40.5, 17.5), Vec::<usize>::new());
        assert_eq!(listed(29.5, 12.5), vec![13]);
    }

    #[test]
    fn objects_lie_in_open_ground_with_up_to_three_explosives() {
        let world = World::urban_block();
        let setup = PatrolSetup::default();
        let ground = PatrolGround::new(&world, setup.free_space);
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
