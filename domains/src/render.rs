//! Drawing one run as SVG: the map and its obstacles, the people who were standing around,
//! the planned and the driven path, collisions, the patrol's objects with their true and
//! assigned labels, and how the operator judged the run.

use crate::geometry::{Shape, Vec2};
use crate::operator::OperatorModel;
use crate::svg::Svg;
use crate::trace::EventKind;
use crate::ugv::{Run, UgvDomain};
use crate::world::ObstacleKind;
use cbr_core::Behavior;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use trust::{Domain, Outcome};

/// Pixels per metre.
const SCALE: f64 = 10.0;
/// Blank border around the map (px).
const MARGIN: f64 = 20.0;
/// Height of the title band above the map (px).
const HEADER: f64 = 70.0;
/// Room right of the map for the labels of objects near its east edge (px).
const LABEL_ROOM: f64 = 140.0;
/// Height of the legend below the map (px).
const FOOTER: f64 = 50.0;

/// Simulates the run of `behavior` with `seed` exactly as [`Domain::run`] does with a
/// `ChaCha8Rng` seeded from `seed`, and draws it.
pub fn render_run(
    domain: &UgvDomain,
    behavior: &Behavior,
    operator: &OperatorModel,
    seed: u64,
) -> String {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let run = domain.simulate(behavior, &mut rng, true);
    let outcome = operator.judge(&run.trace, &mut rng);
    let title = format!(
        "{} | {} | seed {}",
        domain.name(),
        domain.space().display(behavior),
        seed
    );
    draw(domain, &run, &outcome, &title, &operator.name)
}

/// Describes an outcome in words, e.g. `interrupted (collision) after 7.3 s`.
pub fn describe(outcome: &Outcome) -> String {
    let kind = format!("{:?}", outcome.kind).to_lowercase();
    match outcome.cause {
        Some(cause) => format!("{kind} ({cause}) after {:.1} s", outcome.duration_s),
        None => format!("{kind} after {:.1} s", outcome.duration_s),
    }
}

struct Canvas {
    svg: Svg,
    height_m: f64,
}

impl Canvas {
    fn at(&self, p: Vec2) -> (f64, f64) {
        (MARGIN + p.x * SCALE, HEADER + (self.height_m - p.y) * SCALE)
    }

    fn shape(&mut self, shape: &Shape, style: &str) {
        match shape {
            Shape::Circle { center, radius } => {
                let (x, y) = self.at(*center);
                self.svg.circle(x, y, radius * SCALE, style);
            }
            Shape::Polygon(v) => {
                let points: Vec<(f64, f64)> = v.iter().map(|p| self.at(*p)).collect();
                self.svg.poly(&points, true, style);
            }
        }
    }

    fn path(&mut self, points: &[Vec2], style: &str) {
        let points: Vec<(f64, f64)> = points.iter().map(|p| self.at(*p)).collect();
        self.svg.poly(&points, false, style);
    }

    fn cross(&mut self, p: Vec2, size: f64, style: &str) {
        let (x, y) = self.at(p);
        self.svg
            .line((x - size, y - size), (x + size, y + size), style);
        self.svg
            .line((x - size, y + size), (x + size, y - size), style);
    }
}

fn obstacle_style(kind: ObstacleKind) -> &'static str {
    match kind {
        ObstacleKind::House => r##"fill="#d9c7a7" stroke="#8a7350""##,
        ObstacleKind::Vehicle => r##"fill="#7b9cc4" stroke="#34557a""##,
        ObstacleKind::Barrier => r##"fill="#e0402b" stroke="#7a1d10""##,
        ObstacleKind::Cone => r##"fill="#ff8c1a" stroke="#994d00""##,
        ObstacleKind::Human => r##"fill="#8e44ad" stroke="#4a1f5c""##,
    }
}

fn draw(
    domain: &UgvDomain,
    run: &Run<'_>,
    outcome: &Outcome,
    title: &str,
    operator: &str,
) -> String {
    let world = domain.world();
    let width = world.size.x * SCALE + 2.0 * MARGIN + LABEL_ROOM;
    let height = world.size.y * SCALE + HEADER + FOOTER;
    let mut c = Canvas {
        svg: Svg::new(width, height),
        height_m: world.size.y,
    };
    let (x0, y0) = c.at(Vec2::new(0.0, world.size.y));
    c.svg.rect(
        x0,
        y0,
        world.size.x * SCALE,
        world.size.y * SCALE,
        r##"fill="#eef2e6" stroke="#555""##,
    );
    for road in &world.roads {
        let (x, y) = c.at(Vec2::new(road.min.x, road.max.y));
        let (w, h) = (
            (road.max - road.min).x * SCALE,
            (road.max - road.min).y * SCALE,
        );
        c.svg.rect(x, y, w, h, r##"fill="#c8c8c8""##);
    }
    for obstacle in &world.obstacles {
        c.shape(&obstacle.shape, obstacle_style(obstacle.kind));
    }
    for (i, spot) in world.humans.iter().enumerate() {
        if run.humans & (1 << i) != 0 {
            c.shape(&spot.shape, obstacle_style(ObstacleKind::Human));
        } else {
            c.shape(
                &spot.shape,
                r##"fill="none" stroke="#8e44ad" stroke-dasharray="2,2""##,
            );
        }
    }
    for landmark in &world.landmarks {
        let (x, y) = c.at(landmark.at);
        c.svg
            .text(x + 4.0, y - 4.0, 11.0, landmark.name, r##"fill="#333""##);
    }
    for road in &world.roads {
        let (x, y) = c.at(Vec2::new(road.min.x + 1.0, road.min.y + 0.5));
        c.svg.text(x, y, 10.0, road.name, r##"fill="#666""##);
    }
    if let Some(plan) = run.plan {
        c.path(
            &plan.points,
            r##"fill="none" stroke="#1f5fbf" stroke-width="1.5" stroke-dasharray="6,4""##,
        );
    }
    if !run.driven.is_empty() {
        c.path(
            &run.driven,
            r##"fill="none" stroke="#111" stroke-width="1.5""##,
        );
    }
    for fate in &run.objects {
        let color = if fate.object.explosive {
            "#d62728"
        } else {
            "#2ca02c"
        };
        let (x, y) = c.at(fate.object.at);
        if let Some(from) = fate.scanned_from {
            let (fx, fy) = c.at(from);
            c.svg.line(
                (fx, fy),
                (x, y),
                r##"stroke="#555" stroke-dasharray="2,2""##,
            );
            c.svg.circle(
                fx,
                fy,
                2.5,
                r##"fill="none" stroke="#111" stroke-width="1""##,
            );
        }
        c.svg
            .circle(x, y, 4.0, &format!(r##"fill="{color}" stroke="#000""##));
        let label = match fate.labelled_explosive {
            Some(true) => "explosive",
            Some(false) => "harmless",
            None => "unscanned",
        };
        let truth = if fate.object.explosive {
            "explosive"
        } else {
            "harmless"
        };
        c.svg.text(
            x + 6.0,
            y + 4.0,
            10.0,
            &format!("{truth}/{label}"),
            r##"fill="#000""##,
        );
    }
    for event in &run.trace.events {
        if let EventKind::Collision { at } = event.kind {
            c.cross(at, 5.0, r##"stroke="#d62728" stroke-width="2.5""##);
        }
    }
    let route = domain.route();
    for (p, name) in [(route[0], "start"), (route[route.len() - 1], "goal")] {
        let (x, y) = c.at(p);
        c.svg.rect(
            x - 4.0,
            y - 4.0,
            8.0,
            8.0,
            r##"fill="#fff" stroke="#000" stroke-width="1.5""##,
        );
        c.svg
            .text(x + 6.0, y + 12.0, 11.0, name, r##"font-weight="bold""##);
    }
    c.svg
        .text(MARGIN, 24.0, 14.0, title, r##"font-weight="bold""##);
    let stuck = if run.plan.is_none() {
        " | no path keeps the padding: stuck"
    } else {
        ""
    };
    c.svg.text(
        MARGIN,
        48.0,
        14.0,
        &format!(
            "operator {operator}: {} | collisions: {}{stuck}",
            describe(outcome),
            run.trace.collisions()
        ),
        "",
    );
    let legend = [
        "dashed blue: planned path | black: driven path (the whole simulated drive) | red x: collision",
        "dots: objects (red explosive, green harmless; text: truth/label), ring: where it was scanned from | purple: people (dashed: absent)",
    ];
    for (k, line) in legend.iter().enumerate() {
        let y = height - 30.0 + 15.0 * k as f64;
        c.svg.text(MARGIN, y, 11.0, line, r##"fill="#333""##);
    }
    c.svg.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Scenario, builtin_operators};

    #[test]
    fn a_patrol_drawing_shows_every_part() {
        let domain = UgvDomain::new(Scenario::Patrol);
        let b = domain
            .space()
            .parse("speed=2,padding=0.3,scan_time=2,scan_distance=0.5")
            .unwrap();
        let op = &builtin_operators(Scenario::Patrol)[1];
        let svg = render_run(&domain, &b, op, 4);
        // The same outcome as the domain's own run with that seed.
        let expected = domain.run(&b, op, &mut ChaCha8Rng::seed_from_u64(4));
        assert!(svg.contains(&describe(&expected)));
        assert!(svg.contains("stroke-dasharray=\"6,4\""), "planned path");
        assert!(svg.contains("stroke=\"#111\""), "driven path");
        assert_eq!(svg.matches("r=\"4.00\"").count(), 6, "six objects");
        assert!(svg.contains("harmless/") || svg.contains("explosive/"));
        assert!(svg.contains("speed=2"));
    }

    #[test]
    fn describes_outcomes() {
        let o = Outcome::interrupted(1.0, crate::causes::COLLISION, 7.25);
        assert_eq!(describe(&o), "interrupted (collision) after 7.2 s");
        assert_eq!(
            describe(&Outcome::completed(1.0, 12.0)),
            "completed after 12.0 s"
        );
    }
}
