//! Plane geometry for the 2-D world: points, segments, and obstacle shapes (circles and
//! convex polygons) with the distances the planner and the motion model need.
//!
//! Not a general geometry library: it holds exactly the queries the simulator makes.

use serde::{Deserialize, Serialize};
use std::ops::{Add, Mul, Sub};

/// A point or vector in metres; `x` east, `y` north.
#[derive(Clone, Copy, Debug, PartialEq, Default, Serialize, Deserialize)]
pub struct Vec2 {
    /// East coordinate (m).
    pub x: f64,
    /// North coordinate (m).
    pub y: f64,
}

impl Vec2 {
    /// The point `(x, y)`.
    pub const fn new(x: f64, y: f64) -> Self {
        Self { x, y }
    }
    /// Dot product.
    pub fn dot(self, o: Vec2) -> f64 {
        self.x * o.x + self.y * o.y
    }
    /// The z component of the cross product: positive when `o` is to the left of `self`.
    pub fn cross(self, o: Vec2) -> f64 {
        self.x * o.y - self.y * o.x
    }
    /// Euclidean length, `sqrt(x^2 + y^2)`: within an ulp or two of `hypot` and several
    /// times cheaper (no overflow guard is needed: the world is a few hundred metres).
    pub fn norm(self) -> f64 {
        self.dot(self).sqrt()
    }
    /// Distance to `o`.
    pub fn dist(self, o: Vec2) -> f64 {
        (self - o).norm()
    }
    /// The unit vector in this direction (zero stays zero).
    pub fn unit(self) -> Vec2 {
        let n = self.norm();
        if n > 0.0 { self * (1.0 / n) } else { self }
    }
    /// This vector turned 90 degrees counter-clockwise (the left normal of a heading).
    pub fn left(self) -> Vec2 {
        Vec2::new(-self.y, self.x)
    }
}

impl Add for Vec2 {
    type Output = Vec2;
    fn add(self, o: Vec2) -> Vec2 {
        Vec2::new(self.x + o.x, self.y + o.y)
    }
}

impl Sub for Vec2 {
    type Output = Vec2;
    fn sub(self, o: Vec2) -> Vec2 {
        Vec2::new(self.x - o.x, self.y - o.y)
    }
}

impl Mul<f64> for Vec2 {
    type Output = Vec2;
    fn mul(self, k: f64) -> Vec2 {
        Vec2::new(self.x * k, self.y * k)
    }
}

/// Whether `p` lies in the map `[0, size.x] x [0, size.y]` at least `margin` from its edge.
pub fn within(p: Vec2, size: Vec2, margin: f64) -> bool {
    p.x >= margin && p.y >= margin && p.x <= size.x - margin && p.y <= size.y - margin
}

/// The point of segment `a`-`b` nearest to `p`.
pub fn closest_on_segment(p: Vec2, a: Vec2, b: Vec2) -> Vec2 {
    let ab = b - a;
    let len2 = ab.dot(ab);
    if len2 == 0.0 {
        return a;
    }
    let t = ((p - a).dot(ab) / len2).clamp(0.0, 1.0);
    a + ab * t
}

/// Distance from `p` to segment `a`-`b`.
pub fn point_segment_distance(p: Vec2, a: Vec2, b: Vec2) -> f64 {
    p.dist(closest_on_segment(p, a, b))
}

/// Whether the closed segments `a`-`b` and `c`-`d` intersect.
fn segments_intersect(a: Vec2, b: Vec2, c: Vec2, d: Vec2) -> bool {
    let d1 = (b - a).cross(c - a);
    let d2 = (b - a).cross(d - a);
    let d3 = (d - c).cross(a - c);
    let d4 = (d - c).cross(b - c);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    (d1 == 0.0 && point_segment_distance(c, a, b) == 0.0)
        || (d2 == 0.0 && point_segment_distance(d, a, b) == 0.0)
        || (d3 == 0.0 && point_segment_distance(a, c, d) == 0.0)
        || (d4 == 0.0 && point_segment_distance(b, c, d) == 0.0)
}

/// Distance between segments `a`-`b` and `c`-`d` (0 when they cross).
pub fn segment_segment_distance(a: Vec2, b: Vec2, c: Vec2, d: Vec2) -> f64 {
    if segments_intersect(a, b, c, d) {
        return 0.0;
    }
    point_segment_distance(a, c, d)
        .min(point_segment_distance(b, c, d))
        .min(point_segment_distance(c, a, b))
        .min(point_segment_distance(d, a, b))
}

/// The outline of an obstacle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Shape {
    /// A disc: a person, a traffic cone.
    Circle {
        /// Centre.
        center: Vec2,
        /// Radius (m).
        radius: f64,
    },
    /// A convex polygon with vertices in counter-clockwise order: a house, a vehicle,
    /// a barrier.
    Polygon(Vec<Vec2>),
}

impl Shape {
    /// An axis-aligned rectangle `[x0, x1] x [y0, y1]`.
    pub fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Self {
        Shape::Polygon(vec![
            Vec2::new(x0, y0),
            Vec2::new(x1, y0),
            Vec2::new(x1, y1),
            Vec2::new(x0, y1),
        ])
    }

    /// A disc.
    pub fn circle(x: f64, y: f64, radius: f64) -> Self {
        Shape::Circle {
            center: Vec2::new(x, y),
            radius,
        }
    }

    fn edges(vertices: &[Vec2]) -> impl Iterator<Item = (Vec2, Vec2)> + '_ {
        (0..vertices.len()).map(move |i| (vertices[i], vertices[(i + 1) % vertices.len()]))
    }

    fn contains(vertices: &[Vec2], p: Vec2) -> bool {
        Self::edges(vertices).all(|(a, b)| (b - a).cross(p - a) >= 0.0)
    }

    /// The lower-left and upper-right corners of the smallest box around the shape.
    pub fn bounds(&self) -> (Vec2, Vec2) {
        match self {
            Shape::Circle { center, radius } => (
                *center - Vec2::new(*radius, *radius),
                *center + Vec2::new(*radius, *radius),
            ),
            Shape::Polygon(v) => v.iter().fold(
                (
                    Vec2::new(f64::INFINITY, f64::INFINITY),
                    Vec2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
                ),
                |(lo, hi), p| {
                    (
                        Vec2::new(lo.x.min(p.x), lo.y.min(p.y)),
                        Vec2::new(hi.x.max(p.x), hi.y.max(p.y)),
                    )
                },
            ),
        }
    }

    /// Distance from `p` to the shape (0 inside).
    pub fn distance_to_point(&self, p: Vec2) -> f64 {
        match self {
            Shape::Circle { center, radius } => (p.dist(*center) - radius).max(0.0),
            Shape::Polygon(v) => {
                if Self::contains(v, p) {
                    return 0.0;
                }
                Self::edges(v)
                    .map(|(a, b)| point_segment_distance(p, a, b))
                    .fold(f64::INFINITY, f64::min)
            }
        }
    }

    /// Distance from segment `a`-`b` to the shape (0 when they touch).
    pub fn distance_to_segment(&self, a: Vec2, b: Vec2) -> f64 {
        match self {
            Shape::Circle { center, radius } => {
                (point_segment_distance(*center, a, b) - radius).max(0.0)
            }
            Shape::Polygon(v) => {
                if Self::contains(v, a) || Self::contains(v, b) {
                    return 0.0;
                }
                if a == b {
                    // What `segment_segment_distance` computes for a point, without its
                    // crossing test: a crossing puts one of these three at 0 anyway.
                    return Self::edges(v)
                        .map(|(c, d)| {
                            point_segment_distance(a, c, d)
                                .min(c.dist(a))
                                .min(d.dist(a))
                        })
                        .fold(f64::INFINITY, f64::min);
                }
                Self::edges(v)
                    .map(|(c, d)| segment_segment_distance(a, b, c, d))
                    .fold(f64::INFINITY, f64::min)
            }
        }
    }

    /// The point of the shape nearest to `p` (`p` itself when inside).
    pub fn nearest_point(&self, p: Vec2) -> Vec2 {
        match self {
            Shape::Circle { center, radius } => {
                let d = p - *center;
                if d.norm() <= *radius {
                    p
                } else {
                    *center + d.unit() * *radius
                }
            }
            Shape::Polygon(v) => {
                if Self::contains(v, p) {
                    return p;
                }
                Self::edges(v)
                    .map(|(a, b)| closest_on_segment(p, a, b))
                    .min_by(|x, y| p.dist(*x).total_cmp(&p.dist(*y)))
                    .unwrap_or(p)
            }
        }
    }

    /// Way-points around the shape grown by `margin`: the corners of a polygon whose
    /// edges are tangent to the grown outline, so a path bending at them keeps `margin`.
    /// A disc gets the eight corners of the circumscribed octagon; a polygon corner turning
    /// by `phi` gets `ceil(phi / 45 deg)` corners on its rounded grown arc, which lets a
    /// path squeeze past two corners as closely as the true grown shapes allow.
    pub fn inflated_vertices(&self, margin: f64, out: &mut Vec<Vec2>) {
        use std::f64::consts::FRAC_PI_4;
        match self {
            Shape::Circle { center, radius } => {
                let r = (radius + margin) / (FRAC_PI_4 / 2.0).cos();
                for k in 0..8 {
                    let a = FRAC_PI_4 * f64::from(k);
                    out.push(*center + Vec2::new(a.cos(), a.sin()) * r);
                }
            }
            Shape::Polygon(v) => {
                let n = v.len();
                for i in 0..n {
                    let prev = v[(i + n - 1) % n];
                    let next = v[(i + 1) % n];
                    // Outward normals of a counter-clockwise polygon point to the right.
                    let n1 = (v[i] - prev).unit().left() * -1.0;
                    let n2 = (next - v[i]).unit().left() * -1.0;
                    let from = n1.y.atan2(n1.x);
                    let turn = n1.cross(n2).atan2(n1.dot(n2)).max(0.0);
                    let pieces = (turn / FRAC_PI_4).ceil().max(1.0);
                    let step = turn / pieces;
                    let r = margin / (step / 2.0).cos();
                    for j in 0..pieces as usize {
                        let a = from + step * (j as f64 + 0.5);
                        out.push(v[i] + Vec2::new(a.cos(), a.sin()) * r);
                    }
                }
            }
        }
    }
}

/// A shape with its bounding box, computed once: the form in which the planner and the
/// object placement test the same shapes again and again.
#[derive(Clone, Debug, PartialEq)]
pub struct BoundedShape {
    shape: Shape,
    min: Vec2,
    max: Vec2,
}

impl BoundedShape {
    /// `shape` and its box ([`Shape::bounds`]).
    pub fn new(shape: &Shape) -> Self {
        let (min, max) = shape.bounds();
        Self {
            shape: shape.clone(),
            min,
            max,
        }
    }

    /// The lower-left and upper-right corners of the shape's box.
    pub fn bounds(&self) -> (Vec2, Vec2) {
        (self.min, self.max)
    }

    /// Whether every point of segment `a`-`b` is at least `clearance` from the shape,
    /// with a quick answer when the segment's box is that far from the shape's box.
    pub fn keeps_clear(&self, a: Vec2, b: Vec2, clearance: f64) -> bool {
        let (min, max) = (self.min, self.max);
        let far = a.x.max(b.x) < min.x - clearance
            || a.x.min(b.x) > max.x + clearance
            || a.y.max(b.y) < min.y - clearance
            || a.y.min(b.y) > max.y + clearance;
        far || self.shape.distance_to_segment(a, b) >= clearance
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn point_segment_distance_by_hand() {
        let (a, b) = (Vec2::new(0.0, 0.0), Vec2::new(4.0, 0.0));
        assert_eq!(point_segment_distance(Vec2::new(2.0, 3.0), a, b), 3.0);
        assert_eq!(point_segment_distance(Vec2::new(7.0, 4.0), a, b), 5.0);
    }

    #[test]
    fn segment_distances_by_hand() {
        let square = Shape::rect(0.0, 0.0, 2.0, 2.0);
        // A horizontal segment 1 m above the square.
        let d = square.distance_to_segment(Vec2::new(-1.0, 3.0), Vec2::new(3.0, 3.0));
        assert!((d - 1.0).abs() < 1e-12);
        // A segment crossing it.
        assert_eq!(
            square.distance_to_segment(Vec2::new(-1.0, 1.0), Vec2::new(3.0, 1.0)),
            0.0
        );
        let disc = Shape::circle(0.0, 0.0, 1.0);
        let d = disc.distance_to_segment(Vec2::new(-5.0, 3.0), Vec2::new(5.0, 3.0));
        assert!((d - 2.0).abs() < 1e-12);
    }

    #[test]
    fn inflated_rectangle_corners_keep_the_margin_and_hug_the_corner() {
        let rect = Shape::rect(0.0, 0.0, 2.0, 1.0);
        let mut out = Vec::new();
        rect.inflated_vertices(0.5, &mut out);
        // Two way-points per right-angle corner, 0.5 / cos(22.5 deg) from it.
        assert_eq!(out.len(), 8);
        let r = 0.5 / (std::f64::consts::PI / 8.0).cos();
        assert!((out[0].dist(Vec2::new(0.0, 0.0)) - r).abs() < 1e-12);
        for i in 0..8 {
            let (a, b) = (out[i], out[(i + 1) % 8]);
            assert!(rect.distance_to_segment(a, b) >= 0.5 - 1e-9);
        }
    }

    proptest! {
        /// The quick answer from the stored box never contradicts the exact distance.
        #[test]
        fn bounded_shapes_keep_clear_exactly_when_the_distance_says_so(
            ax in -5.0f64..15.0, ay in -5.0f64..15.0,
            bx in -5.0f64..15.0, by in -5.0f64..15.0,
            clearance in 0.0f64..3.0, point: bool,
        ) {
            let a = Vec2::new(ax, ay);
            let b = if point { a } else { Vec2::new(bx, by) };
            for shape in [Shape::rect(2.0, 3.0, 6.0, 4.5), Shape::circle(7.0, 7.0, 0.3)] {
                let bounded = BoundedShape::new(&shape);
                prop_assert_eq!((bounded.min, bounded.max), shape.bounds());
                prop_assert_eq!(
                    bounded.keeps_clear(a, b, clearance),
                    shape.distance_to_segment(a, b) >= clearance
                );
            }
        }
    }

    proptest! {
        /// A point's distance to a polygon is the segment computation's, bit for bit,
        /// corners and crossings included.
        #[test]
        fn a_point_is_a_segment_of_length_zero(
            px in -3.0f64..9.0, py in -3.0f64..9.0, corner in 0usize..8, on_corner: bool,
        ) {
            let shape = Shape::Polygon(vec![
                Vec2::new(0.0, 0.0),
                Vec2::new(4.1, 0.3),
                Vec2::new(5.0, 3.7),
                Vec2::new(1.3, 6.0),
            ]);
            let Shape::Polygon(v) = &shape else { unreachable!() };
            // Just outside a corner, where the corner's own distance decides.
            let centre = Vec2::new(2.6, 2.5);
            let near = v[corner % 4] + (v[corner % 4] - centre) * 1e-9;
            let p = if on_corner { near } else { Vec2::new(px, py) };
            let expected = if Shape::contains(v, p) {
                0.0
            } else {
                Shape::edges(v)
                    .map(|(c, d)| segment_segment_distance(p, p, c, d))
                    .fold(f64::INFINITY, f64::min)
            };
            prop_assert_eq!(shape.distance_to_segment(p, p).to_bits(), expected.to_bits());
        }
    }

    #[test]
    fn inflated_circle_vertices_keep_the_margin() {
        let disc = Shape::circle(1.0, 1.0, 0.3);
        let mut out = Vec::new();
        disc.inflated_vertices(0.7, &mut out);
        for i in 0..8 {
            let (a, b) = (out[i], out[(i + 1) % 8]);
            assert!(disc.distance_to_segment(a, b) >= 0.7 - 1e-9);
        }
    }
}
