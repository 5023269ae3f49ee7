//! Path planning: the shortest path that keeps a given clearance from every obstacle,
//! found by A* (`petgraph`) over a visibility graph of the obstacles grown by that
//! clearance, and the clearance profile along the path that the motion model needs.
//!
//! A path exists or not; when it does not, the robot is stuck. The planner knows nothing
//! of speeds or operators.

use crate::geometry::{Shape, Vec2};
use petgraph::graph::{NodeIndex, UnGraph};

/// Tolerance for "at least the clearance" comparisons (m): grown corners sit exactly at the
/// clearance, and rounding must not make them invalid.
const SLACK: f64 = 1e-7;

/// Spacing of the clearance samples along a path (m): a quarter of the robot's width, fine
/// enough that a corner or a cone is never stepped over.
pub const SAMPLE_SPACING: f64 = 0.25;

/// A search problem: a map edge, obstacles and the clearance the robot's centre keeps.
pub struct Problem<'a> {
    /// Upper-right corner of the map (the lower-left is the origin).
    pub size: Vec2,
    /// Every obstacle present.
    pub obstacles: Vec<&'a Shape>,
    /// Clearance of the robot's centre from every obstacle and the map edge: the robot's
    /// radius plus its padding (m).
    pub clearance: f64,
}

impl Problem<'_> {
    /// The shortest polyline through `waypoints` in order, leg by leg, or `None` when some
    /// leg has no way through.
    pub fn through(&self, waypoints: &[Vec2]) -> Option<Vec<Vec2>> {
        let mut points = vec![*waypoints.first()?];
        for leg in waypoints.windows(2) {
            points.extend(self.shortest_path(leg[0], leg[1])?.into_iter().skip(1));
        }
        Some(points)
    }

    /// The shortest polyline from `start` to `goal` keeping the clearance, or `None` when
    /// there is no way through.
    pub fn shortest_path(&self, start: Vec2, goal: Vec2) -> Option<Vec<Vec2>> {
        let c = self.clearance;
        let clear = |a: Vec2, b: Vec2| {
            self.obstacles
                .iter()
                .all(|o| o.keeps_clear(a, b, c - SLACK))
        };
        let point_clear = |p: Vec2| {
            p.x >= c - SLACK
                && p.y >= c - SLACK
                && p.x <= self.size.x - c + SLACK
                && p.y <= self.size.y - c + SLACK
                && clear(p, p)
        };
        if !point_clear(start) || !point_clear(goal) {
            return None;
        }
        let mut corners = Vec::new();
        for shape in &self.obstacles {
            shape.inflated_vertices(c + 2.0 * SLACK, &mut corners);
        }
        let mut nodes = vec![start, goal];
        nodes.extend(corners.into_iter().filter(|p| point_clear(*p)));

        let mut graph: UnGraph<Vec2, f64> = UnGraph::with_capacity(nodes.len(), nodes.len() * 8);
        let ids: Vec<NodeIndex> = nodes.iter().map(|p| graph.add_node(*p)).collect();
        for i in 0..nodes.len() {
            for j in i + 1..nodes.len() {
                let (a, b) = (nodes[i], nodes[j]);
                if clear(a, b) {
                    graph.add_edge(ids[i], ids[j], a.dist(b));
                }
            }
        }
        let (_, route) = petgraph::algo::astar(
            &graph,
            ids[0],
            |n| n == ids[1],
            |e| *e.weight(),
            |n| graph[n].dist(goal),
        )?;
        Some(route.into_iter().map(|n| graph[n]).collect())
    }
}

/// One point of a path's clearance profile.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Distance along the path (m).
    pub s: f64,
    /// Where it is.
    pub at: Vec2,
    /// Unit normal pointing to the left of the direction of travel.
    pub left: Vec2,
    /// Gap between the robot's body and the nearest obstacle on the left (m).
    pub gap_left: f64,
    /// Gap on the right (m).
    pub gap_right: f64,
    /// Index of the path segment the sample lies on.
    pub segment: usize,
}

/// A planned path with its arc lengths and clearance profile.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// The way-points, start first.
    pub points: Vec<Vec2>,
    /// Arc length at each way-point (m); `arc[0] = 0`.
    pub arc: Vec<f64>,
    /// The clearance profile, every [`SAMPLE_SPACING`] or closer, way-points included.
    pub samples: Vec<Sample>,
}

impl Plan {
    /// Measures `points`: arc lengths, and at every sample the gap between the robot's
    /// body (a disc of `robot_radius`) and the nearest obstacle on each side.
    pub fn new(points: Vec<Vec2>, obstacles: &[&Shape], robot_radius: f64, size: Vec2) -> Self {
        let mut arc = vec![0.0];
        for w in points.windows(2) {
            arc.push(arc[arc.len() - 1] + w[0].dist(w[1]));
        }
        let mut samples = Vec::new();
        for (k, w) in points.windows(2).enumerate() {
            let length = w[0].dist(w[1]);
            let dir = (w[1] - w[0]).unit();
            let n = (length / SAMPLE_SPACING).ceil().max(1.0) as usize;
            let last = k + 2 == points.len();
            for j in 0..n + usize::from(last) {
                let f = j as f64 / n as f64;
                let at = w[0] + (w[1] - w[0]) * f;
                samples.push(Self::measure(
                    arc[k] + length * f,
                    at,
                    dir.left(),
                    k,
                    obstacles,
                    robot_radius,
                    size,
                ));
            }
        }
        Self {
            points,
            arc,
            samples,
        }
    }

    fn measure(
        s: f64,
        at: Vec2,
        left: Vec2,
        segment: usize,
        obstacles: &[&Shape],
        robot_radius: f64,
        size: Vec2,
    ) -> Sample {
        let mut gap_left = f64::INFINITY;
        let mut gap_right = f64::INFINITY;
        let mut note = |toward: Vec2, distance: f64| {
            let gap = distance - robot_radius;
            if toward.dot(left) >= 0.0 {
                gap_left = gap_left.min(gap);
            } else {
                gap_right = gap_right.min(gap);
            }
        };
        for shape in obstacles {
            let near = shape.nearest_point(at);
            note(near - at, at.dist(near));
        }
        // The map's edge is a wall.
        note(Vec2::new(-1.0, 0.0), at.x);
        note(Vec2::new(0.0, -1.0), at.y);
        note(Vec2::new(1.0, 0.0), size.x - at.x);
        note(Vec2::new(0.0, 1.0), size.y - at.y);
        Sample {
            s,
            at,
            left,
            gap_left,
            gap_right,
            segment,
        }
    }

    /// Total length (m).
    pub fn length(&self) -> f64 {
        self.arc[self.arc.len() - 1]
    }

    /// The point at arc length `s` and the segment it lies on.
    pub fn point_at(&self, s: f64) -> (Vec2, usize) {
        let k = self
            .arc
            .partition_point(|&a| a <= s)
            .clamp(1, self.points.len() - 1)
            - 1;
        let length = self.arc[k + 1] - self.arc[k];
        let f = if length > 0.0 {
            ((s - self.arc[k]) / length).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (
            self.points[k] + (self.points[k + 1] - self.points[k]) * f,
            k,
        )
    }

    /// The point of the path nearest to `p`: its arc length and distance.
    pub fn nearest(&self, p: Vec2) -> (f64, f64) {
        let mut best = (0.0, f64::INFINITY);
        for (k, w) in self.points.windows(2).enumerate() {
            let q = crate::geometry::closest_on_segment(p, w[0], w[1]);
            let d = p.dist(q);
            if d < best.1 {
                best = (self.arc[k] + w[0].dist(q), d);
            }
        }
        best
    }

    /// The turning angle at each interior way-point (radians, 0 for straight on); the first
    /// and last entries are 0.
    pub fn turn_angles(&self) -> Vec<f64> {
        let mut angles = vec![0.0; self.points.len()];
        for (i, w) in self.points.windows(3).enumerate() {
            let a = (w[1] - w[0]).unit();
            let b = (w[2] - w[1]).unit();
            angles[i + 1] = a.cross(b).atan2(a.dot(b)).abs();
        }
        angles
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn goes_around_a_box_at_the_clearance() {
        let wall = Shape::rect(4.0, 0.0, 6.0, 6.0);
        let problem = Problem {
            size: Vec2::new(10.0, 10.0),
            obstacles: vec![&wall],
            clearance: 1.0,
        };
        let path = problem
            .shortest_path(Vec2::new(1.0, 1.0), Vec2::new(9.0, 1.0))
            .expect("a way over the wall");
        for w in path.windows(2) {
            assert!(wall.distance_to_segment(w[0], w[1]) >= 1.0 - 1e-6);
        }
        // Longer than the straight climb to the wall's grown top edge and back
        // (2 x |(1,1)-(4,7)| + 2), shorter than bending at square grown corners (3,7), (7,7).
        let length: f64 = path.windows(2).map(|w| w[0].dist(w[1])).sum();
        assert!(length > 2.0 * 45.0_f64.sqrt() + 2.0);
        assert!(length < 2.0 * 40.0_f64.sqrt() + 4.0);
    }

    #[test]
    fn no_way_through_a_gap_narrower_than_twice_the_clearance() {
        // Two walls leave a 3 m gap (y from 4 to 7) across a 10 m wide map.
        let low = Shape::rect(4.0, 0.0, 6.0, 4.0);
        let high = Shape::rect(4.0, 7.0, 6.0, 10.0);
        let mut problem = Problem {
            size: Vec2::new(10.0, 10.0),
            obstacles: vec![&low, &high],
            clearance: 1.4,
        };
        let (a, b) = (Vec2::new(1.5, 5.0), Vec2::new(8.5, 5.0));
        assert!(problem.shortest_path(a, b).is_some());
        problem.clearance = 1.6;
        assert!(problem.shortest_path(a, b).is_none());
    }

    #[test]
    fn samples_measure_the_gap_on_each_side() {
        let cone = Shape::circle(5.0, 1.0, 0.2);
        let plan = Plan::new(
            vec![Vec2::new(0.0, 0.0), Vec2::new(10.0, 0.0)],
            &[&cone],
            0.5,
            Vec2::new(100.0, 100.0),
        );
        let at_cone = plan
            .samples
            .iter()
            .find(|s| (s.s - 5.0).abs() < 1e-9)
            .unwrap();
        // Cone edge 0.8 m to the left; body radius 0.5 m.
        assert!((at_cone.gap_left - 0.3).abs() < 1e-9);
        // The map's lower edge is 0 m to the right: the body overlaps it by 0.5 m.
        assert!((at_cone.gap_right + 0.5).abs() < 1e-9);
        assert_eq!(plan.samples.len(), 41);
    }
}
