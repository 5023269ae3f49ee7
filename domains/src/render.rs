//! Drawing one run as SVG with plotters: the map and its obstacles, the people who were
//! standing around, the planned and the driven path, collisions, the patrol's objects
//! with their true and assigned labels, and how the operator judged the run; a scale bar
//! in metres and a legend of what this run's picture holds (patrol objects only in patrol
//! runs).

use crate::geometry::{Shape, Vec2};
use crate::map_labels::{Horizontal, Label, LabelPlacer, MapRect, Role, Vertical};
use crate::operator::OperatorModel;
use crate::trace::EventKind;
use crate::ugv::{Run, UgvDomain};
use crate::world::ObstacleKind;
use cbr_core::Behavior;
use lab::report::plot::{Area, DrawResult, svg, text_width};
use lab::{Domain, Judgement};
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::path::Path;

/// Pixels per metre.
const SCALE: f64 = 10.0;
/// Blank border left and right of the map (px).
const MARGIN: u32 = 20;
/// Height of the title band above the map (px).
const HEADER: u32 = 70;
/// Room right of the map for the labels of objects near its east edge (px).
const LABEL_ROOM: u32 = 140;
/// Height of a row of the legend (px).
const LEGEND_ROW: u32 = 20;
/// Font size of the legend (px).
const LEGEND_FONT: u32 = 13;
/// Length of the scale bar (m).
const SCALE_BAR_M: f64 = 10.0;

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

/// Describes how a run ended and why, in words, e.g. `interrupted (collision) after
/// 7.3 s` (a drawing shows the operator's true reason: it is for people, not the robot).
pub fn describe(judgement: &Judgement) -> String {
    let outcome = &judgement.outcome;
    let kind = format!("{:?}", outcome.kind).to_lowercase();
    match judgement.truth {
        Some(cause) => format!("{kind} ({cause}) after {:.1} s", outcome.duration_s),
        None => format!("{kind} after {:.1} s", outcome.duration_s),
    }
}

/// Fill and outline of an obstacle kind.
fn obstacle_colors(kind: ObstacleKind) -> (RGBColor, RGBColor) {
    match kind {
        ObstacleKind::House => (RGBColor(217, 199, 167), RGBColor(138, 115, 80)),
        ObstacleKind::Vehicle => (RGBColor(123, 156, 196), RGBColor(52, 85, 122)),
        ObstacleKind::Barrier => (RGBColor(224, 64, 43), RGBColor(122, 29, 16)),
        ObstacleKind::Cone => (RGBColor(255, 140, 26), RGBColor(153, 77, 0)),
        ObstacleKind::Human => (RGBColor(142, 68, 173), RGBColor(74, 31, 92)),
    }
}

fn obstacle_name(kind: ObstacleKind) -> &'static str {
    match kind {
        ObstacleKind::House => "house",
        ObstacleKind::Vehicle => "vehicle",
        ObstacleKind::Barrier => "barrier",
        ObstacleKind::Cone => "traffic cone",
        ObstacleKind::Human => "person",
    }
}

const PLANNED: RGBColor = RGBColor(31, 95, 191);
const DRIVEN: RGBColor = RGBColor(17, 17, 17);
const COLLISION: RGBColor = RGBColor(214, 39, 40);
const EXPLOSIVE: RGBColor = RGBColor(214, 39, 40);
const HARMLESS: RGBColor = RGBColor(44, 160, 44);
const SPUR: RGBColor = RGBColor(85, 85, 85);
const ABSENT: RGBColor = RGBColor(187, 143, 206);

/// What a legend entry shows beside its text.
#[derive(Clone, Copy)]
enum Symbol {
    Dashed(RGBColor),
    Line(RGBColor),
    Cross,
    Disc(RGBColor, RGBColor),
    Ring(RGBColor),
    Square,
    Spur,
    Block(RGBColor, RGBColor),
}

/// The legend entries of a run's picture: only what it can show.
fn legend_entries(domain: &UgvDomain, run: &Run<'_>) -> Vec<(Symbol, String)> {
    let world = domain.world();
    let mut entries = vec![
        (Symbol::Dashed(PLANNED), "planned path".to_owned()),
        (
            Symbol::Line(DRIVEN),
            "driven path (the whole simulated drive)".to_owned(),
        ),
        (Symbol::Cross, "collision".to_owned()),
        (Symbol::Square, "start, goal".to_owned()),
    ];
    if !world.humans.is_empty() {
        let (fill, line) = obstacle_colors(ObstacleKind::Human);
        entries.push((Symbol::Disc(fill, line), "person standing".to_owned()));
        entries.push((Symbol::Ring(ABSENT), "where a person may stand".to_owned()));
    }
    let mut kinds: Vec<ObstacleKind> = Vec::new();
    for o in &world.obstacles {
        if !kinds.contains(&o.kind) {
            kinds.push(o.kind);
        }
    }
    for kind in kinds {
        let (fill, line) = obstacle_colors(kind);
        entries.push((Symbol::Block(fill, line), obstacle_name(kind).to_owned()));
    }
    if !run.objects.is_empty() {
        entries.push((
            Symbol::Disc(EXPLOSIVE, BLACK),
            "explosive object".to_owned(),
        ));
        entries.push((Symbol::Disc(HARMLESS, BLACK), "harmless object".to_owned()));
        entries.push((
            Symbol::Spur,
            "scanned from (ring); text: truth/label given".to_owned(),
        ));
    }
    entries
}

/// Width of a legend entry (px): symbol, gap, text, gap to the next.
fn entry_width(label: &str) -> u32 {
    24 + 6 + text_width(label, LEGEND_FONT) + 16
}

/// The legend's rows: entries in order, a new row when the next would pass `width`.
fn legend_rows(entries: &[(Symbol, String)], width: u32) -> Vec<Vec<usize>> {
    let mut rows: Vec<Vec<usize>> = vec![Vec::new()];
    let mut used = 0;
    for (k, (_, label)) in entries.iter().enumerate() {
        let w = entry_width(label);
        if used + w > width && !rows.last().expect("one row at least").is_empty() {
            rows.push(Vec::new());
            used = 0;
        }
        rows.last_mut().expect("one row at least").push(k);
        used += w;
    }
    rows
}

fn draw_symbol(area: &Area<'_>, symbol: Symbol, (x, y): (i32, i32)) -> DrawResult {
    match symbol {
        Symbol::Dashed(color) => area.draw(&DashedPathElement::new(
            vec![(x, y), (x + 24, y)],
            6,
            4,
            color.stroke_width(2),
        ))?,
        Symbol::Line(color) => area.draw(&PathElement::new(
            vec![(x, y), (x + 24, y)],
            color.stroke_width(1),
        ))?,
        Symbol::Cross => cross(area, (x + 12, y), 5)?,
        Symbol::Disc(fill, line) => {
            area.draw(&Circle::new((x + 12, y), 4, fill.filled()))?;
            area.draw(&Circle::new((x + 12, y), 4, line.stroke_width(1)))?;
        }
        Symbol::Ring(color) => area.draw(&Circle::new((x + 12, y), 4, color.stroke_width(1)))?,
        Symbol::Square => square(area, (x + 12, y))?,
        Symbol::Spur => {
            area.draw(&DashedPathElement::new(
                vec![(x, y), (x + 20, y)],
                2,
                2,
                SPUR.stroke_width(1),
            ))?;
            area.draw(&Circle::new((x + 2, y), 2.5, DRIVEN.stroke_width(1)))?;
        }
        Symbol::Block(fill, line) => {
            area.draw(&Rectangle::new(
                [(x + 4, y - 6), (x + 20, y + 6)],
                fill.filled(),
            ))?;
            area.draw(&Rectangle::new(
                [(x + 4, y - 6), (x + 20, y + 6)],
                line.stroke_width(1),
            ))?;
        }
    }
    Ok(())
}

/// A red x of half-size `size` px at `at` (px).
fn cross(area: &Area<'_>, (x, y): (i32, i32), size: i32) -> DrawResult {
    for (a, b) in [
        ((x - size, y - size), (x + size, y + size)),
        ((x - size, y + size), (x + size, y - size)),
    ] {
        area.draw(&PathElement::new(vec![a, b], COLLISION.stroke_width(3)))?;
    }
    Ok(())
}

/// The white square of a route's start or goal at `at` (px).
fn square(area: &Area<'_>, (x, y): (i32, i32)) -> DrawResult {
    area.draw(&Rectangle::new(
        [(x - 4, y - 4), (x + 4, y + 4)],
        WHITE.filled(),
    ))?;
    area.draw(&Rectangle::new(
        [(x - 4, y - 4), (x + 4, y + 4)],
        BLACK.stroke_width(2),
    ))?;
    Ok(())
}

/// The map's coordinates: metres, east and north.
type Map<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

fn shape(
    map: &mut Map<'_, '_>,
    shape: &Shape,
    fill: Option<RGBColor>,
    line: ShapeStyle,
) -> DrawResult {
    match shape {
        Shape::Circle { center, radius } => {
            let r = radius * SCALE;
            if let Some(fill) = fill {
                map.draw_series(std::iter::once(Circle::new(
                    (center.x, center.y),
                    r,
                    fill.filled(),
                )))?;
            }
            map.draw_series(std::iter::once(Circle::new((center.x, center.y), r, line)))?;
        }
        Shape::Polygon(v) => {
            let points: Vec<(f64, f64)> = v.iter().map(|p| (p.x, p.y)).collect();
            if let Some(fill) = fill {
                map.draw_series(std::iter::once(Polygon::new(points.clone(), fill.filled())))?;
            }
            let mut closed = points;
            closed.push(closed[0]);
            map.draw_series(std::iter::once(PathElement::new(closed, line)))?;
        }
    }
    Ok(())
}

fn draw(
    domain: &UgvDomain,
    run: &Run<'_>,
    outcome: &Judgement,
    title: &str,
    operator: &str,
) -> String {
    let world = domain.world();
    let (map_w, map_h) = (
        (world.size.x * SCALE).round() as u32,
        (world.size.y * SCALE).round() as u32,
    );
    let width = map_w + 2 * MARGIN + LABEL_ROOM;
    let entries = legend_entries(domain, run);
    let rows = legend_rows(&entries, width - 2 * MARGIN);
    // Below the map: the scale bar, then the legend's rows.
    let footer = 16 + 30 + LEGEND_ROW * rows.len() as u32 + 8;
    let height = HEADER + map_h + footer;
    let stuck = if run.plan.is_none() {
        " | no path keeps the padding: stuck"
    } else {
        ""
    };
    let verdict = format!(
        "operator {operator}: {} | collisions: {}{stuck}",
        describe(outcome),
        run.trace.collisions()
    );
    svg(Path::new("run.svg"), (width, height), |root| {
        root.draw(&Text::new(
            title,
            (MARGIN as i32, 12),
            ("sans-serif", 17).into_font().style(FontStyle::Bold),
        ))?;
        root.draw(&Text::new(
            verdict.as_str(),
            (MARGIN as i32, 38),
            ("sans-serif", 17).into_font(),
        ))?;
        let map_area = root.clone().shrink((MARGIN, HEADER), (map_w, map_h));
        let mut map =
            ChartBuilder::on(&map_area).build_cartesian_2d(0.0..world.size.x, 0.0..world.size.y)?;
        draw_map(&mut map, domain, run)?;
        footer_keys(root, &entries, &rows, HEADER + map_h)
    })
    .expect("drawing into a string with the built-in font cannot fail")
}

/// Everything drawn in map coordinates.
fn draw_map(map: &mut Map<'_, '_>, domain: &UgvDomain, run: &Run<'_>) -> DrawResult {
    let world = domain.world();
    let corners = [(0.0, 0.0), (world.size.x, world.size.y)];
    map.draw_series(std::iter::once(Rectangle::new(
        corners,
        RGBColor(238, 242, 230).filled(),
    )))?;
    map.draw_series(world.roads.iter().map(|road| {
        Rectangle::new(
            [(road.min.x, road.min.y), (road.max.x, road.max.y)],
            RGBColor(200, 200, 200).filled(),
        )
    }))?;
    map.draw_series(std::iter::once(Rectangle::new(
        corners,
        RGBColor(85, 85, 85).stroke_width(1),
    )))?;
    for obstacle in &world.obstacles {
        let (fill, line) = obstacle_colors(obstacle.kind);
        shape(map, &obstacle.shape, Some(fill), line.stroke_width(1))?;
    }
    for (i, spot) in world.humans.iter().enumerate() {
        if run.humans & (1 << i) != 0 {
            let (fill, line) = obstacle_colors(ObstacleKind::Human);
            shape(map, &spot.shape, Some(fill), line.stroke_width(1))?;
        } else {
            shape(map, &spot.shape, None, ABSENT.stroke_width(1))?;
        }
    }
    if let Some(plan) = run.plan {
        let points: Vec<(f64, f64)> = plan.points.iter().map(|p| (p.x, p.y)).collect();
        map.draw_series(std::iter::once(DashedPathElement::new(
            points,
            6,
            4,
            PLANNED.stroke_width(2),
        )))?;
    }
    if !run.driven.is_empty() {
        let points: Vec<(f64, f64)> = run.driven.iter().map(|p| (p.x, p.y)).collect();
        map.draw_series(std::iter::once(PathElement::new(
            points,
            DRIVEN.stroke_width(1),
        )))?;
    }
    for fate in &run.objects {
        let at = (fate.object.at.x, fate.object.at.y);
        if let Some(from) = fate.scanned_from {
            map.draw_series(std::iter::once(DashedPathElement::new(
                vec![(from.x, from.y), at],
                2,
                2,
                SPUR.stroke_width(1),
            )))?;
            map.draw_series(std::iter::once(Circle::new(
                (from.x, from.y),
                2.5,
                DRIVEN.stroke_width(1),
            )))?;
        }
        let color = if fate.object.explosive {
            EXPLOSIVE
        } else {
            HARMLESS
        };
        map.draw_series(std::iter::once(Circle::new(at, 4, color.filled())))?;
        map.draw_series(std::iter::once(Circle::new(at, 4, BLACK.stroke_width(1))))?;
    }
    // Marks of a fixed size in pixels, anchored at a point of the map.
    let mark = |at: Vec2, size: i32| {
        EmptyElement::at((at.x, at.y))
            + PathElement::new(
                vec![(-size, -size), (size, size)],
                COLLISION.stroke_width(3),
            )
            + PathElement::new(
                vec![(-size, size), (size, -size)],
                COLLISION.stroke_width(3),
            )
    };
    map.draw_series(
        run.trace
            .events
            .iter()
            .filter_map(|event| match event.kind {
                EventKind::Collision { at } => Some(mark(at, 5)),
                _ => None,
            }),
    )?;
    let route = domain.route();
    map.draw_series([route[0], route[route.len() - 1]].map(|p| {
        EmptyElement::at((p.x, p.y))
            + Rectangle::new([(-4, -4), (4, 4)], WHITE.filled())
            + Rectangle::new([(-4, -4), (4, 4)], BLACK.stroke_width(2))
    }))?;
    let labels = map_labels(domain, run);
    map.draw_series(labels.iter().filter_map(|label| {
        label.leader_from.map(|from| {
            PathElement::new(
                vec![(from.x, from.y), (label.at.x, label.at.y)],
                SPUR.stroke_width(1),
            )
        })
    }))?;
    map.draw_series(labels.into_iter().map(|label| {
        let color = match label.role {
            Role::Street => RGBColor(102, 102, 102),
            Role::Place => RGBColor(51, 51, 51),
            Role::Route | Role::Object => BLACK,
        };
        let style = if label.role == Role::Route {
            FontStyle::Bold
        } else {
            FontStyle::Normal
        };
        let font = ("sans-serif", label.font)
            .into_font()
            .style(style)
            .color(&color);
        let horizontal = match label.horizontal {
            Horizontal::Left => HPos::Left,
            Horizontal::Center => HPos::Center,
            Horizontal::Right => HPos::Right,
        };
        let vertical = match label.vertical {
            Vertical::Top => VPos::Top,
            Vertical::Center => VPos::Center,
            Vertical::Bottom => VPos::Bottom,
        };
        Text::new(
            label.text,
            (label.at.x, label.at.y),
            font.pos(Pos::new(horizontal, vertical)),
        )
    }))?;
    Ok(())
}

/// Font size of landmark names (px).
const PLACE_FONT: u32 = 13;
/// Font size of street names (px).
const STREET_FONT: u32 = 12;
/// Font size of an object's truth/label text (px).
const OBJECT_FONT: u32 = 12;
/// Font size of the start and goal labels (px, bold).
const ROUTE_FONT: u32 = 13;

/// The map's labels, none covering another or a marked point: street names inside their
/// street, then start and goal, landmarks, and each patrol object's truth and label
/// (`truth/label`).
pub fn map_labels(domain: &UgvDomain, run: &Run<'_>) -> Vec<Label> {
    let world = domain.world();
    let mut placer = LabelPlacer::new(
        SCALE,
        MapRect {
            min: Vec2::new(0.0, 0.0),
            max: Vec2::new(world.size.x + f64::from(LABEL_ROOM) / SCALE, world.size.y),
        },
    );
    let px = |n: f64| n / SCALE;
    let route = domain.route();
    for at in [route[0], route[route.len() - 1]] {
        placer.mark(MapRect::around(at, px(5.0)));
    }
    for fate in &run.objects {
        placer.mark(MapRect::around(fate.object.at, px(5.0)));
        if let Some(from) = fate.scanned_from {
            placer.mark(MapRect::around(from, px(3.5)));
        }
    }
    for event in &run.trace.events {
        if let EventKind::Collision { at } = event.kind {
            placer.mark(MapRect::around(at, px(6.0)));
        }
    }
    for road in &world.roads {
        placer.fixed(
            road.name,
            STREET_FONT,
            Vec2::new(road.min.x + 1.0, road.min.y + 0.5),
            Horizontal::Left,
            Vertical::Bottom,
        );
    }
    placer.beside("start", ROUTE_FONT, Role::Route, route[0]);
    placer.beside("goal", ROUTE_FONT, Role::Route, route[route.len() - 1]);
    for landmark in &world.landmarks {
        placer.beside(landmark.name, PLACE_FONT, Role::Place, landmark.at);
    }
    for fate in &run.objects {
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
        placer.beside(
            &format!("{truth}/{label}"),
            OBJECT_FONT,
            Role::Object,
            fate.object.at,
        );
    }
    placer.into_labels()
}

/// The scale bar and the legend below the map, whose bottom edge is `top` px down.
fn footer_keys(
    root: &DrawingArea<SVGBackend<'_>, Shift>,
    entries: &[(Symbol, String)],
    rows: &[Vec<usize>],
    top: u32,
) -> DrawResult {
    let (x0, y0) = (MARGIN as i32, top as i32 + 16);
    let length = (SCALE_BAR_M * SCALE).round() as i32;
    let half = length / 2;
    for (k, fill) in [(0, BLACK), (1, WHITE)] {
        root.draw(&Rectangle::new(
            [(x0 + k * half, y0), (x0 + (k + 1) * half, y0 + 5)],
            fill.filled(),
        ))?;
    }
    root.draw(&Rectangle::new(
        [(x0, y0), (x0 + length, y0 + 5)],
        BLACK.stroke_width(1),
    ))?;
    let ticks = TextStyle::from(("sans-serif", LEGEND_FONT).into_font())
        .pos(Pos::new(HPos::Center, VPos::Top));
    for (at, label) in [(0, "0"), (half, "5"), (length, "10 m")] {
        root.draw(&Text::new(label, (x0 + at, y0 + 8), ticks.clone()))?;
    }
    let text = TextStyle::from(("sans-serif", LEGEND_FONT).into_font())
        .pos(Pos::new(HPos::Left, VPos::Center));
    for (r, row) in rows.iter().enumerate() {
        let y = y0 + 30 + (LEGEND_ROW as i32) * r as i32 + LEGEND_ROW as i32 / 2;
        let mut x = x0;
        for &k in row {
            let (symbol, label) = &entries[k];
            draw_symbol(root, *symbol, (x, y))?;
            root.draw(&Text::new(label.as_str(), (x + 30, y), text.clone()))?;
            x += entry_width(label) as i32;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Scenario, builtin_operators};

    /// Whether plotters wrote `text` as one text element (its content on its own line).
    fn has_text(svg: &str, text: &str) -> bool {
        svg.contains(&format!("\n{text}\n</text>"))
    }

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
        assert!(svg.contains("speed=2"));
        let labels = svg.matches("\nharmless/").count() + svg.matches("\nexplosive/").count();
        assert_eq!(labels, 6, "six objects");
        for key in ["planned path", "explosive object", "10 m", "start", "goal"] {
            assert!(has_text(&svg, key), "{key}");
        }
    }

    #[test]
    fn a_movement_legend_has_no_patrol_objects() {
        let domain = UgvDomain::new(Scenario::Movement);
        let b = domain.space().parse("speed=7,padding=0.1").unwrap();
        let op = &builtin_operators(Scenario::Movement)[0];
        let svg = render_run(&domain, &b, op, 1);
        assert!(has_text(&svg, "collision") && has_text(&svg, "10 m"));
        for patrol_only in ["explosive object", "harmless object"] {
            assert!(!has_text(&svg, patrol_only), "{patrol_only}");
        }
        assert!(!svg.contains("scanned from"));
    }

    #[test]
    fn no_label_covers_another_on_any_patrol_run() {
        let domain = UgvDomain::new(Scenario::Patrol);
        let world = domain.world();
        let mut runs = 0;
        for behavior in [
            "speed=0.5,padding=0.5,scan_time=1,scan_distance=1",
            "speed=2,padding=0.3,scan_time=2,scan_distance=0.5",
            "speed=4,padding=0.1,scan_time=0.5,scan_distance=0.25",
        ] {
            let b = domain.space().parse(behavior).unwrap();
            for seed in 0..40 {
                let run = domain.simulate(&b, &mut ChaCha8Rng::seed_from_u64(seed), true);
                let labels = map_labels(&domain, &run);
                // Streets, landmarks, start, goal and every object.
                let expected = world.roads.len() + world.landmarks.len() + 2 + run.objects.len();
                assert_eq!(labels.len(), expected);
                for (i, a) in labels.iter().enumerate() {
                    for b in &labels[i + 1..] {
                        assert_eq!(
                            a.covers.overlap(&b.covers),
                            0.0,
                            "{behavior}, seed {seed}: `{}` covers `{}`",
                            a.text,
                            b.text
                        );
                    }
                }
                runs += 1;
            }
        }
        assert_eq!(runs, 120);
    }

    #[test]
    fn legend_rows_wrap_at_the_width() {
        let entries: Vec<(Symbol, String)> =
            (0..5).map(|_| (Symbol::Cross, "x".repeat(10))).collect();
        // Each entry: 24 + 6 + ceil(10 * 0.6 * 13 / 1.24) + 16 = 109 px; 250 px hold two.
        assert_eq!(entry_width("xxxxxxxxxx"), 109);
        assert_eq!(
            legend_rows(&entries, 250),
            [vec![0, 1], vec![2, 3], vec![4]]
        );
    }

    #[test]
    fn describes_outcomes() {
        let o = Judgement::interrupted(1.0, crate::causes::COLLISION, 7.25);
        assert_eq!(describe(&o), "interrupted (collision) after 7.2 s");
        assert_eq!(
            describe(&Judgement::completed(1.0, 12.0)),
            "completed after 12.0 s"
        );
    }
}
