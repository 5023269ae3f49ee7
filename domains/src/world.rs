//! The urban block both tasks run in: roads and landmarks, the static obstacles (houses,
//! parked vehicles, road barriers, traffic cones), the spots where people may be standing,
//! the wheeled UGV, and the two routes.
//!
//! Every number here is a physical choice; `docs/simulation.md` gives the reason for each.
//! The world is data only: planning lives in `planner`, motion in `motion`.

use crate::geometry::{Shape, Vec2};

/// What an obstacle is (for drawing and for reports; the planner treats all alike).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ObstacleKind {
    /// A building.
    House,
    /// A parked car or van.
    Vehicle,
    /// A road barrier.
    Barrier,
    /// A traffic cone.
    Cone,
    /// A person standing still.
    Human,
}

/// One obstacle of the map.
#[derive(Clone, Debug, PartialEq)]
pub struct Obstacle {
    /// What it is.
    pub kind: ObstacleKind,
    /// Its outline.
    pub shape: Shape,
}

/// A place where a person may be standing when a run starts.
#[derive(Clone, Debug, PartialEq)]
pub struct HumanSpot {
    /// What the place is (e.g. `bus stop`).
    pub name: &'static str,
    /// The person's outline when present.
    pub shape: Shape,
    /// Probability that someone stands there during a run.
    pub occupied: f64,
}

/// A road, drawn as a rectangle of carriageway.
#[derive(Clone, Debug, PartialEq)]
pub struct Road {
    /// Street name for the drawing.
    pub name: &'static str,
    /// Lower-left corner.
    pub min: Vec2,
    /// Upper-right corner.
    pub max: Vec2,
}

/// A named place, for the drawing and for defining routes.
#[derive(Clone, Debug, PartialEq)]
pub struct Landmark {
    /// Its name.
    pub name: &'static str,
    /// Where it is.
    pub at: Vec2,
}

/// The wheeled UGV: footprint, drive limits and how precisely it follows a path.
#[derive(Clone, Debug, PartialEq)]
pub struct Robot {
    /// Radius of the disc that covers the footprint (m).
    pub radius: f64,
    /// Longitudinal acceleration limit (m/s^2).
    pub accel: f64,
    /// Braking limit (m/s^2).
    pub decel: f64,
    /// Lateral acceleration allowed in corners before the wheels slip (m/s^2).
    pub lateral_accel: f64,
    /// Arc length over which the path follower rounds a corner (m); a corner turning by
    /// `theta` is driven on a radius `corner_arc / theta`.
    pub corner_arc: f64,
    /// Standard deviation of the localisation error (m).
    pub localisation_sd: f64,
    /// Control lag (s): the cross-track error from lag grows as `lag * speed`.
    pub control_lag: f64,
    /// Distance over which the cross-track error decorrelates (m).
    pub error_correlation: f64,
    /// Time to stop, back off and resume after touching an obstacle (s).
    pub collision_pause: f64,
    /// Time the robot spends re-planning before it reports that no path exists (s).
    pub replan_timeout: f64,
}

impl Robot {
    /// A mid-size wheeled UGV (about 0.9 m across, 2 m/s^2, 10 m/s top speed).
    pub fn wheeled_ugv() -> Self {
        Self {
            radius: 0.45,
            accel: 2.0,
            decel: 3.0,
            lateral_accel: 2.5,
            corner_arc: 2.0,
            localisation_sd: 0.04,
            control_lag: 0.05,
            error_correlation: 2.0,
            collision_pause: 2.0,
            replan_timeout: 5.0,
        }
    }

    /// Standard deviation of the cross-track error at `speed` (m): localisation error and
    /// control lag add in quadrature.
    pub fn cross_track_sd(&self, speed: f64) -> f64 {
        self.localisation_sd.hypot(self.control_lag * speed)
    }

    /// The Ornstein-Uhlenbeck transition of the cross-track error (in units of its
    /// standard deviation) over `distance` metres of path: the correlation kept, `rho`,
    /// and the weight of a fresh standard normal draw, `sqrt(1 - rho^2)`.
    pub fn error_transition(&self, distance: f64) -> (f64, f64) {
        let rho = (-distance / self.error_correlation).exp();
        (rho, (1.0 - rho * rho).sqrt())
    }
}

/// The whole map.
#[derive(Clone, Debug, PartialEq)]
pub struct World {
    /// Upper-right corner of the map; the lower-left is the origin. The map's edge is a
    /// wall the robot keeps its clearance from.
    pub size: Vec2,
    /// Carriageways.
    pub roads: Vec<Road>,
    /// Named places.
    pub landmarks: Vec<Landmark>,
    /// Obstacles that are always there.
    pub obstacles: Vec<Obstacle>,
    /// Places where people may stand; at most 32, since a `u32` says which are occupied.
    pub humans: Vec<HumanSpot>,
    /// The robot.
    pub robot: Robot,
    /// The movement task's route: start and goal.
    pub movement_route: Vec<Vec2>,
    /// The patrol task's route along the street centre lines: start, the junction, goal.
    /// Suspicious objects are placed near it.
    pub patrol_route: Vec<Vec2>,
}

fn obstacle(kind: ObstacleKind, shape: Shape) -> Obstacle {
    Obstacle { kind, shape }
}

impl World {
    /// The urban block: a main street running east with a construction site narrowing it,
    /// a small square in front of a shop, and a side street running north at the east end.
    pub fn urban_block() -> Self {
        use ObstacleKind::*;
        let rect = Shape::rect;
        let mut obstacles = vec![
            // Houses south of the main street.
            obstacle(House, rect(0.0, 0.0, 16.0, 9.0)),
            obstacle(House, rect(19.0, 0.0, 44.0, 9.0)),
            obstacle(House, rect(47.0, 0.0, 63.0, 9.0)),
            // Houses north of it; the shop (middle) is set back behind a small square.
            obstacle(House, rect(0.0, 24.0, 20.0, 50.0)),
            obstacle(House, rect(20.0, 27.5, 40.0, 50.0)),
            obstacle(House, rect(40.0, 24.0, 63.0, 50.0)),
            // Parked cars (4.5 m x 1.8 m) along the kerbs; a delivery van (6 m x 2.4 m)
            // opposite the construction site.
            obstacle(Vehicle, rect(5.0, 12.2, 9.5, 14.0)),
            obstacle(Vehicle, rect(8.0, 20.2, 12.5, 22.0)),
            obstacle(Vehicle, rect(27.0, 19.6, 33.0, 22.0)),
            obstacle(Vehicle, rect(45.0, 12.2, 49.5, 14.0)),
            obstacle(Vehicle, rect(50.0, 20.2, 54.5, 22.0)),
            obstacle(Vehicle, rect(66.2, 28.0, 68.0, 32.5)),
            obstacle(Vehicle, rect(74.0, 42.0, 75.8, 46.5)),
            // Construction site: a barrier across the south half of the main street, from
            // the house wall to just past the centre line, and a barrier closing part of
            // Mill Lane's west lane.
            obstacle(Barrier, rect(29.8, 9.0, 30.2, 17.0)),
            obstacle(Barrier, rect(66.0, 41.0, 69.0, 41.4)),
        ];
        // Cones tapering traffic towards the barrier's tip on both sides.
        for (x, y) in [(26.0, 16.4), (28.0, 16.8), (32.0, 16.8), (34.0, 16.4)] {
            obstacles.push(obstacle(Cone, Shape::circle(x, y, 0.2)));
        }
        // Cones around an open manhole in Mill Lane.
        for (x, y) in [(72.0, 35.0), (74.0, 35.0), (73.0, 36.2), (73.0, 33.8)] {
            obstacles.push(obstacle(Cone, Shape::circle(x, y, 0.2)));
        }
        let human = |name, x, y, occupied| HumanSpot {
            name,
            shape: Shape::circle(x, y, 0.3),
            occupied,
        };
        Self {
            size: Vec2::new(80.0, 50.0),
            roads: vec![
                Road {
                    name: "Main Street",
                    min: Vec2::new(0.0, 12.0),
                    max: Vec2::new(76.0, 22.0),
                },
                Road {
                    name: "Mill Lane",
                    min: Vec2::new(66.0, 0.0),
                    max: Vec2::new(76.0, 50.0),
                },
            ],
            landmarks: vec![
                Landmark {
                    name: "depot",
                    at: Vec2::new(3.0, 17.0),
                },
                Landmark {
                    name: "clinic",
                    at: Vec2::new(48.0, 17.0),
                },
                Landmark {
                    name: "shop",
                    at: Vec2::new(30.0, 27.5),
                },
                Landmark {
                    name: "north gate",
                    at: Vec2::new(71.0, 47.0),
                },
            ],
            obstacles,
            humans: vec![
                human("crossing", 17.0, 16.0, 0.3),
                human("bus stop", 30.0, 23.2, 0.4),
                human("shop door", 35.0, 27.0, 0.3),
                human("lane crossing", 71.0, 25.0, 0.3),
            ],
            robot: Robot::wheeled_ugv(),
            movement_route: vec![Vec2::new(3.0, 17.0), Vec2::new(48.0, 17.0)],
            patrol_route: vec![
                Vec2::new(3.0, 17.0),
                Vec2::new(71.0, 17.0),
                Vec2::new(71.0, 47.0),
            ],
        }
    }

    /// The obstacles present when the people at the spots in `mask` are standing there
    /// (bit `i` set: spot `i` occupied).
    pub fn obstacles_with(&self, mask: u32) -> impl Iterator<Item = &Shape> + '_ {
        self.obstacles.iter().map(|o| &o.shape).chain(
            self.humans
                .iter()
                .enumerate()
                .filter(move |(i, _)| mask & (1 << i) != 0)
                .map(|(_, h)| &h.shape),
        )
    }
}
