//! Path planning: the shortest path that keeps a given clearance from every obstacle,
//! found by A* (`petgraph`) over a visibility graph of the obstacles grown by that
//! clearance, and the clearance profile along the path that the motion model needs.
//!
//! A path exists or not; when it does not, the robot is stuck. The planner knows nothing
//! of speeds or operators.

use crate::geometry::{BoundedShape, Shape, Vec2, within};
use crate::world::Robot;
use petgraph::graph::{NodeIndex, UnGraph};

/// Tolerance for "at least the clearance" comparisons (m): grown corners sit exactly at the
/// clearance, and rounding must not make them invalid.
const SLACK: f64 = 1e-7;

/// Spacing of the clearance samples along a path (m): a quarter of the robot's width, fine
/// enough that a corner or a cone is never stepped over.
pub const SAMPLE_SPACING: f64 = 0.25;

/// A search problem: a map edge, obstacles and the clearance the robot's centre keeps.
/// Obstacles are either fixed or optional (a person who may or may not be standing
/// there); one visibility graph serves every combination of the optional ones.
pub struct Problem<'a> {
    /// Upper-right corner of the map (the lower-left is the origin).
    pub size: Vec2,
    /// Obstacles that are always present.
    pub fixed: Vec<&'a Shape>,
    /// Obstacles that may be present (at most 32); bit `i` of a presence mask is number `i`.
    pub optional: Vec<&'a Shape>,
    /// Clearance of the robot's centre from every obstacle and the map edge: the robot's
    /// radius plus its padding (m).
    pub clearance: f64,
}

/// The visibility graph of a [`Problem`] through a list of way-points: every grown-corner
/// point and straight edge that keeps the clearance from the fixed obstacles, each marked
/// with the optional obstacles that would block it.
pub struct VisibilityGraph {
    nodes: Vec<Vec2>,
    edges: Vec<(usize, usize, f64, u32)>,
    /// The nodes of the way-points, in order; `None` when a fixed obstacle covers one.
    waypoints: Vec<Option<(usize, u32)>>,
}

/// The obstacles of a [`Problem`] with their boxes, computed once per visibility graph.
struct Obstacles {
    fixed: Vec<BoundedShape>,
    optional: Vec<BoundedShape>,
}

impl Problem<'_> {
    /// Which optional obstacles segment `a`-`b` comes closer to than the clearance, or
    /// `None` when a fixed obstacle or the map edge does.
    fn blockers(&self, obstacles: &Obstacles, a: Vec2, b: Vec2) -> Option<u32> {
        let c = self.clearance - SLACK;
        let inside = |p: Vec2| within(p, self.size, c);
        if !(inside(a) && inside(b) && obstacles.fixed.iter().all(|o| o.keeps_clear(a, b, c))) {
            return None;
        }
        Some(
            obstacles
                .optional
                .iter()
                .enumerate()
                .filter(|(_, o)| !o.keeps_clear(a, b, c))
                .fold(0, |mask, (i, _)| mask | 1 << i),
        )
    }

    /// The visibility graph through `waypoints`.
    pub fn visibility(&self, waypoints: &[Vec2]) -> VisibilityGraph {
        let bounded = |shapes: &[&Shape]| shapes.iter().map(|s| BoundedShape::new(s)).collect();
        let obstacles = Obstacles {
            fixed: bounded(&self.fixed),
            optional: bounded(&self.optional),
        };
        let mut corners = Vec::new();
        for shape in self.fixed.iter().chain(&self.optional) {
            shape.inflated_vertices(self.clearance + 2.0 * SLACK, &mut corners);
        }
        let mut nodes = Vec::new();
        let mut node_blockers = Vec::new();
        let mut waypoint_nodes = Vec::new();
        for &p in waypoints {
            let blockers = self.blockers(&obstacles, p, p);
            waypoint_nodes.push(blockers.map(|b| (nodes.len(), b)));
            nodes.push(p);
            node_blockers.push(blockers.unwrap_or(u32::MAX));
        }
        for p in corners {
            if let Some(b) = self.blockers(&obstacles, p, p) {
                nodes.push(p);
                node_blockers.push(b);
            }
        }
        let mut edges = Vec::new();
        for i in 0..nodes.len() {
            if node_blockers[i] == u32::MAX {
                continue;
            }
            for j in i + 1..nodes.len() {
                if node_blockers[j] == u32::MAX {
                    continue;
                }
                if let Some(b) = self.blockers(&obstacles, nodes[i], nodes[j]) {
                    edges.push((i, j, nodes[i].dist(nodes[j]), b));
                }
            }
        }
        VisibilityGraph {
            nodes,
            edges,
            waypoints: waypoint_nodes,
        }
    }

    /// The shortest polyline through `waypoints` with every optional obstacle present.
    pub fn through(&self, waypoints: &[Vec2]) -> Option<Vec<Vec2>> {
        let all = if self.optional.len() >= 32 {
            u32::MAX
        } else {
            (1u32 << self.optional.len()) - 1
        };
        self.visibility(waypoints).route(all)
    }
}

impl VisibilityGraph {
    /// The shortest polyline through the way-points, leg by leg, with the optional
    /// obstacles in `present` standing; `None` when some leg has no way through.
    pub fn route(&self, present: u32) -> Option<Vec<Vec2>> {
        let mut graph: UnGraph<Vec2, f64> =
            UnGraph::with_capacity(self.nodes.len(), self.edges.len());
        let ids: Vec<NodeIndex> = self.nodes.iter().map(|p| graph.add_node(*p)).collect();
        for &(i, j, length, blockers) in &self.edges {
            if blockers & present == 0 {
                graph.add_edge(ids[i], ids[j], length);
            }
        }
        let mut legs = Vec::with_capacity(self.waypoints.len());
        for w in &self.waypoints {
            match w {
                Some((node, blockers)) if blockers & present == 0 => legs.push(ids[*node]),
                _ => return None,
            }
        }
        let mut points = vec![graph[*legs.first()?]];
        for leg in legs.windows(2) {
            let goal = graph[leg[1]];
            let (_, route) = petgraph::algo::astar(
                &graph,
                leg[0],
                |n| n == leg[1],
                |e| *e.weight(),
                |n| graph[n].dist(goal),
            )?;
            points.extend(route.into_iter().skip(1).map(|n| graph[n]));
        }
        Some(points)
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
    /// The turning angle at each way-point ([`Plan::turn_angles`]).
    turns: Vec<f64>,
    /// Each sample's smaller gap ([`Sample::gap`]), side by side: a drive looks at many
    /// samples' gaps and draws at fewer.
    gaps: Vec<f64>,
    /// The least gap of each block of [`GAP_BLOCK`] samples, so a drive skips the blocks
    /// far from every obstacle without looking at their samples.
    block_gaps: Vec<f64>,
    /// The robot's error correlation length the transitions are for (m).
    error_correlation: f64,
    /// Per sample, [`Robot::error_transition`] from the sample before it (the first: from
    /// the start), so a drive drawing the error at neighbouring samples needs no `exp`.
    transitions: Vec<(f64, f64)>,
}

/// Samples per block of [`Plan::samples_closer_than`]'s index (at most 32: a block's close
/// samples are the bits of a `u32`).
const GAP_BLOCK: usize = 16;
const _: () = assert!(GAP_BLOCK <= 32);

impl Plan {
    /// Measures `points` for `robot`: arc lengths, at every sample the gap between the
    /// robot's body (a disc of its radius) and the nearest obstacle on each side, and the
    /// cross-track error's transition from the sample before.
    pub fn new(points: Vec<Vec2>, obstacles: &[&Shape], robot: &Robot, size: Vec2) -> Self {
        let robot_radius = robot.radius;
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
        let turns = turn_angles(&points);
        let gaps: Vec<f64> = samples.iter().map(Sample::gap).collect();
        let block_gaps = gaps
            .chunks(GAP_BLOCK)
            .map(|block| block.iter().copied().fold(f64::INFINITY, f64::min))
            .collect();
        let mut from = 0.0;
        let transitions = samples
            .iter()
            .map(|sample| {
                let transition = robot.error_transition(sample.s - from);
                from = sample.s;
                transition
            })
            .collect();
        Self {
            points,
            arc,
            samples,
            turns,
            gaps,
            block_gaps,
            error_correlation: robot.error_correlation,
            transitions,
        }
    }

    /// Per sample `k`, [`Robot::error_transition`] from sample `k - 1` to sample `k`, when
    /// this plan was measured for a robot with `robot`'s error correlation.
    pub fn error_transitions(&self, robot: &Robot) -> Option<&[(f64, f64)]> {
        (robot.error_correlation == self.error_correlation).then_some(&self.transitions[..])
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

    /// The point of the path nearest to `p`: its arc length and distance. The first
    /// segment at the least distance wins a tie.
    ///
    /// Segments are compared by squared distance; distances (a `hypot` each) are compared
    /// only when two squared distances are too close to tell apart, and the arc length is
    /// measured for the winner alone, so the answer is the one comparing every segment's
    /// distance would give, bit for bit.
    pub fn nearest(&self, p: Vec2) -> (f64, f64) {
        // Squared distances further apart than this order the distances the same way
        // (each is within a few ulps of the true value, as is `hypot`).
        const APART: f64 = 1.0 + 1e-12;
        let mut best: Option<(usize, Vec2, f64)> = None;
        for (k, w) in self.points.windows(2).enumerate() {
            let q = crate::geometry::closest_on_segment(p, w[0], w[1]);
            let squared = (p - q).dot(p - q);
            let closer = match best {
                None => true,
                Some((_, _, least)) if squared > least * APART => false,
                Some((_, _, least)) if squared * APART < least => true,
                Some((_, at, _)) => p.dist(q) < p.dist(at),
            };
            if closer {
                best = Some((k, q, squared));
            }
        }
        best.map_or((0.0, f64::INFINITY), |(k, q, _)| {
            (self.arc[k] + self.points[k].dist(q), p.dist(q))
        })
    }

    /// The turning angle at each interior way-point (radians, 0 for straight on); the first
    /// and last entries are 0.
    pub fn turn_angles(&self) -> &[f64] {
        &self.turns
    }

    /// The samples whose gap on either side is below `gap`, with their indices, in order,
    /// and always the last sample (the goal).
    pub fn samples_closer_than(&self, gap: f64) -> CloseSamples<'_> {
        CloseSamples {
            plan: self,
            gap,
            first: 0,
            next_block: 0,
            pending: 0,
        }
    }
}

/// The iterator of [`Plan::samples_closer_than`]: it steps over whole blocks whose least gap
/// is not below the bound, and marks the close samples of the others in a bit mask (no
/// branch per sample, whose outcome would change from run to run).
pub struct CloseSamples<'a> {
    plan: &'a Plan,
    gap: f64,
    /// The first sample of the block `pending` marks, and the next block to look at.
    first: usize,
    next_block: usize,
    /// Bit `i`: sample `first + i` is close and not yet yielded.
    pending: u32,
}

impl<'a> Iterator for CloseSamples<'a> {
    type Item = (usize, &'a Sample);

    #[inline]
    fn next(&mut self) -> Option<Self::Item> {
        let plan = self.plan;
        while self.pending == 0 {
            let last = plan.samples.len() - 1;
            // The next block worth a look; the one holding the goal always is.
            let mut block = self.next_block;
            while block < plan.block_gaps.len()
                && plan.block_gaps[block] >= self.gap
                && (block + 1) * GAP_BLOCK <= last
            {
                block += 1;
            }
            if block == plan.block_gaps.len() {
                return None;
            }
            let first = block * GAP_BLOCK;
            let gaps = &plan.gaps[first..plan.gaps.len().min(first + GAP_BLOCK)];
            let mut close = 0;
            for (i, &gap) in gaps.iter().enumerate() {
                close |= u32::from(gap < self.gap) << i;
            }
            if last < first + GAP_BLOCK {
                close |= 1 << (last - first);
            }
            (self.first, self.next_block, self.pending) = (first, block + 1, close);
        }
        let k = self.first + self.pending.trailing_zeros() as usize;
        self.pending &= self.pending - 1;
        Some((k, &plan.samples[k]))
    }
}

impl Sample {
    /// The smaller of the two gaps (m).
    pub fn gap(&self) -> f64 {
        self.gap_left.min(self.gap_right)
    }
}

/// The turning angle at each interior way-point of `points` (radians, 0 for straight on);
/// the first and last entries are 0.
fn turn_angles(points: &[Vec2]) -> Vec<f64> {
    let mut angles = vec![0.0; points.len()];
    for (i, w) in points.windows(3).enumerate() {
        let a = (w[1] - w[0]).unit();
        let b = (w[2] - w[1]).unit();
        angles[i + 1] = a.cross(b).atan2(a.dot(b)).abs();
    }
    angles
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn robot(radius: f64) -> Robot {
        Robot {
            radius,
            ..Robot::wheeled_ugv()
        }
    }

    #[test]
    fn goes_around_a_box_at_the_clearance() {
        let wall = Shape::rect(4.0, 0.0, 6.0, 6.0);
        let problem = Problem {
            size: Vec2::new(10.0, 10.0),
            fixed: vec![&wall],
            optional: vec![],
            clearance: 1.0,
        };
        let path = problem
            .through(&[Vec2::new(1.0, 1.0), Vec2::new(9.0, 1.0)])
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
            fixed: vec![&low, &high],
            optional: vec![],
            clearance: 1.4,
        };
        let route = [Vec2::new(1.5, 5.0), Vec2::new(8.5, 5.0)];
        assert!(problem.through(&route).is_some());
        problem.clearance = 1.6;
        assert!(problem.through(&route).is_none());
    }

    #[test]
    fn an_optional_obstacle_blocks_only_when_present() {
        // A 4 m gap (y from 3 to 7); a person in its middle leaves two 1.7 m gaps.
        let low = Shape::rect(4.0, 0.0, 6.0, 3.0);
        let high = Shape::rect(4.0, 7.0, 6.0, 10.0);
        let person = Shape::circle(5.0, 5.0, 0.3);
        let problem = Problem {
            size: Vec2::new(10.0, 10.0),
            fixed: vec![&low, &high],
            optional: vec![&person],
            clearance: 1.2,
        };
        let graph = problem.visibility(&[Vec2::new(1.5, 5.0), Vec2::new(8.5, 5.0)]);
        let free = graph.route(0).expect("passes when nobody is there");
        assert_eq!(free.len(), 2, "straight through");
        assert!(graph.route(1).is_none());
    }

    proptest! {
        /// The squared-distance scan answers exactly as comparing every segment's
        /// distance does, ties (a corner nearest to two segments) included.
        #[test]
        fn nearest_equals_the_distance_scan(
            corners in proptest::collection::vec((0.0f64..20.0, 0.0f64..20.0), 2..8),
            px in -5.0f64..25.0, py in -5.0f64..25.0, at_corner: bool,
        ) {
            let points: Vec<Vec2> = corners.iter().map(|&(x, y)| Vec2::new(x, y)).collect();
            let plan = Plan::new(points.clone(), &[], &robot(0.5), Vec2::new(20.0, 20.0));
            let p = if at_corner { points[points.len() / 2] } else { Vec2::new(px, py) };
            let mut expected = (0.0, f64::INFINITY);
            for (k, w) in points.windows(2).enumerate() {
                let q = crate::geometry::closest_on_segment(p, w[0], w[1]);
                if p.dist(q) < expected.1 {
                    expected = (plan.arc[k] + w[0].dist(q), p.dist(q));
                }
            }
            let found = plan.nearest(p);
            prop_assert_eq!(found.0.to_bits(), expected.0.to_bits());
            prop_assert_eq!(found.1.to_bits(), expected.1.to_bits());
        }
    }

    #[test]
    fn the_close_samples_are_those_a_full_scan_finds() {
        let cones = [Shape::circle(5.0, 6.0, 0.2), Shape::circle(9.3, 4.2, 0.2)];
        let plan = Plan::new(
            vec![
                Vec2::new(1.0, 5.0),
                Vec2::new(13.0, 5.0),
                Vec2::new(13.0, 14.0),
            ],
            &[&cones[0], &cones[1]],
            &robot(0.5),
            Vec2::new(100.0, 100.0),
        );
        let last = plan.samples.len() - 1;
        for gap in [-1.0, 0.0, 0.3, 0.6, 1.0, 2.0, f64::INFINITY] {
            let scan: Vec<usize> = (0..plan.samples.len())
                .filter(|&k| plan.samples[k].gap() < gap || k == last)
                .collect();
            let found: Vec<usize> = plan.samples_closer_than(gap).map(|(k, _)| k).collect();
            assert_eq!(found, scan, "gap {gap}");
        }
    }

    #[test]
    fn stored_error_transitions_are_the_robots_between_neighbouring_samples() {
        let plan = Plan::new(
            vec![
                Vec2::new(1.0, 5.0),
                Vec2::new(13.0, 5.0),
                Vec2::new(13.7, 14.1),
            ],
            &[],
            &robot(0.5),
            Vec2::new(100.0, 100.0),
        );
        let transitions = plan.error_transitions(&robot(0.5)).unwrap();
        for (pair, &transition) in plan.samples.windows(2).zip(&transitions[1..]) {
            let ds = pair[1].s - pair[0].s;
            assert_eq!(transition, robot(0.5).error_transition(ds));
        }
        let other = Robot {
            error_correlation: 3.0,
            ..robot(0.5)
        };
        assert_eq!(plan.error_transitions(&other), None);
    }

    #[test]
    fn samples_measure_the_gap_on_each_side() {
        let cone = Shape::circle(5.0, 1.0, 0.2);
        let plan = Plan::new(
            vec![Vec2::new(0.0, 0.0), Vec2::new(10.0, 0.0)],
            &[&cone],
            &robot(0.5),
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
