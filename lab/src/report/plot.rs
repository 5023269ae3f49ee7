//! What every figure of the reports and landscapes shares: drawing into an SVG string with
//! plotters, the arms' colours, the probability colour map, axis titles with units, tick
//! labels for categories and counts, and a conservative estimate of text width for
//! layouts (plotters' SVG backend cannot measure text, and underestimates it).

use crate::experiment::arm_name::{ArmName, Initial};
use cbr_core::NamedComponent;
use plotters::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A drawing area of the SVG backend, in pixels.
pub type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;
/// What drawing into an [`Area`] returns.
pub type DrawResult = Result<(), Box<dyn std::error::Error + 'static>>;

/// A figure could not be drawn.
#[derive(Debug, thiserror::Error)]
#[error("plot {path}: {message}")]
pub struct PlotError {
    /// The figure's file.
    pub path: PathBuf,
    /// What went wrong.
    pub message: String,
}

/// Draws a `size` (pixels) figure on a white background with `draw` and returns its SVG
/// text; `path` names the figure in errors.
pub fn svg(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(&Area<'_>) -> DrawResult,
) -> Result<String, PlotError> {
    svg_with(path, size, |area, _| draw(area))
}

/// [`svg`] with an [`Overlay`]: what `draw` puts into it is written on top of what it
/// draws with plotters.
pub fn svg_with(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(&Area<'_>, &mut Overlay) -> DrawResult,
) -> Result<String, PlotError> {
    let mut svg = String::new();
    let mut overlay = Overlay::default();
    {
        let area = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        let drawn = area
            .fill(&WHITE)
            .map_err(|e| e.into())
            .and_then(|()| draw(&area, &mut overlay))
            .and_then(|()| area.present().map_err(|e| e.into()));
        drawn.map_err(|e| PlotError {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
    }
    let mut svg = compact(&svg);
    if !overlay.svg.is_empty() {
        let end = svg.rfind("</svg>").unwrap_or(svg.len());
        svg.insert_str(end, &overlay.svg);
    }
    Ok(svg)
}

/// Plotters' SVG text without what changes nothing: `opacity="1"` and
/// `stroke-width="1"` (the defaults), black and white in six digits, and font sizes to 16
/// digits (rounded to 0.1 px).
fn compact(svg: &str) -> String {
    let svg = svg
        .replace(" opacity=\"1\"", "")
        .replace(" stroke-width=\"1\"", "")
        .replace("\"#000000\"", "\"#000\"")
        .replace("\"#FFFFFF\"", "\"#FFF\"");
    let mut out = String::with_capacity(svg.len());
    let mut rest = svg.as_str();
    const FONT_SIZE: &str = "font-size=\"";
    while let Some(at) = rest.find(FONT_SIZE) {
        let (before, after) = rest.split_at(at + FONT_SIZE.len());
        out.push_str(before);
        let end = after.find('"').unwrap_or(after.len());
        match after[..end].parse::<f64>() {
            Ok(size) => out.push_str(&px(size)),
            Err(_) => out.push_str(&after[..end]),
        }
        rest = &after[end..];
    }
    out.push_str(rest);
    out
}

/// The Okabe-Ito colours (safe under the common colour-vision deficiencies) without
/// yellow, which reads poorly on white, and a neutral grey.
const ARM_COLORS: [RGBColor; 8] = [
    RGBColor(213, 94, 0),
    RGBColor(0, 114, 178),
    RGBColor(0, 0, 0),
    RGBColor(230, 159, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
    RGBColor(120, 120, 120),
];

/// A marker's shape (as the strategies' registry names it: [`trust::search::Marker`]).
pub use trust::search::Marker as Shape;

const SHAPES: [Shape; 9] = [
    Shape::Circle,
    Shape::Square,
    Shape::Diamond,
    Shape::TriangleUp,
    Shape::TriangleDown,
    Shape::Pentagon,
    Shape::Hexagon,
    Shape::Star,
    Shape::Plus,
];

/// How a marker is drawn.
pub trait Outline {
    /// The vertices of the shape centred on `(x, y)` with the area of a disc of radius
    /// `r` (pixels); `None` for the disc itself.
    fn vertices(self, at: (f64, f64), r: f64) -> Option<Vec<(f64, f64)>>;

    /// The shape as one SVG element, centred on `at`, of the area of a disc of radius `r`
    /// (pixels); the style comes from the enclosing group.
    fn element(self, at: (f64, f64), r: f64) -> String;
}

impl Outline for Shape {
    fn vertices(self, (x, y): (f64, f64), r: f64) -> Option<Vec<(f64, f64)>> {
        use std::f64::consts::{FRAC_PI_2, PI, TAU};
        // A regular n-gon with circumradius R has area n/2 R^2 sin(2 pi / n).
        let polygon = |n: usize, turn: f64| {
            let big = r * (TAU / (n as f64 * (TAU / n as f64).sin())).sqrt();
            (0..n)
                .map(|k| {
                    let a = turn + TAU * k as f64 / n as f64;
                    (x + big * a.cos(), y - big * a.sin())
                })
                .collect::<Vec<_>>()
        };
        Some(match self {
            Shape::Circle => return None,
            Shape::Square => polygon(4, PI / 4.0),
            Shape::Diamond => polygon(4, 0.0),
            Shape::TriangleUp => polygon(3, FRAC_PI_2),
            Shape::TriangleDown => polygon(3, -FRAC_PI_2),
            Shape::Pentagon => polygon(5, FRAC_PI_2),
            Shape::Hexagon => polygon(6, 0.0),
            Shape::Star => {
                // Outer radius 1.6 r and inner 0.65 r: about the disc's area.
                (0..10)
                    .map(|k| {
                        let a = FRAC_PI_2 + PI * k as f64 / 5.0;
                        let radius = if k % 2 == 0 { 1.6 * r } else { 0.65 * r };
                        (x + radius * a.cos(), y - radius * a.sin())
                    })
                    .collect()
            }
            Shape::Plus => {
                // Half-arms a long and b wide: area 8ab - 4b^2, 3.5 r^2 with
                // a = 1.25 r and b = 0.42 r (a disc: 3.14 r^2).
                let (a, b) = (1.25 * r, 0.42 * r);
                [
                    (b, a),
                    (b, b),
                    (a, b),
                    (a, -b),
                    (b, -b),
                    (b, -a),
                    (-b, -a),
                    (-b, -b),
                    (-a, -b),
                    (-a, b),
                    (-b, b),
                    (-b, a),
                ]
                .into_iter()
                .map(|(dx, dy)| (x + dx, y - dy))
                .collect()
            }
        })
    }

    fn element(self, at: (f64, f64), r: f64) -> String {
        match self.vertices(at, r) {
            None => format!(
                "<circle cx=\"{}\" cy=\"{}\" r=\"{}\"/>",
                px(at.0),
                px(at.1),
                px(r)
            ),
            Some(points) => {
                let mut d = String::new();
                for (k, (x, y)) in points.into_iter().enumerate() {
                    let _ = write!(d, "{}{} {}", if k == 0 { 'M' } else { 'L' }, px(x), px(y));
                }
                format!("<path d=\"{d}Z\"/>")
            }
        }
    }
}

/// How an arm is drawn in every figure: its colour and its marker's shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ArmStyle {
    /// The colour of its lines and markers.
    pub color: RGBColor,
    /// The shape of its markers.
    pub shape: Shape,
}

/// The styles of a figure's arms, in the order of `names` ([`arm_style`] of each).
pub fn arm_styles(names: &[&ArmName]) -> Vec<ArmStyle> {
    names.iter().map(|name| arm_style(name)).collect()
}

/// The style of the arm named `name`, by its name alone, the same in every figure of every
/// report and sweep: a built-in arm's is the look the strategies' registry gives it
/// ([`crate::experiment::arm::builtin_arms`]; the paper's two: vermillion discs and blue
/// squares); a built-in arm with suffixes ([`crate::experiment::arm::NameOptions`]: blind
/// to context or deaf to statements, starting from the case memory's guess) has its base
/// arm's marker in another colour for each, never one of the paper's two; any other arm
/// (a user's) one of the palette's colours but the paper's two and a marker, both drawn
/// from its name.
pub fn arm_style(name: &ArmName) -> ArmStyle {
    let options = name.options();
    let Some(builtin) = crate::experiment::arm::builtin_arm(name.base()) else {
        let drawn = name_hash(name.as_str());
        let others = ARM_COLORS.len() as u64 - 2;
        return ArmStyle {
            color: ARM_COLORS[2 + (drawn % others) as usize],
            shape: SHAPES[((drawn / others) % SHAPES.len() as u64) as usize],
        };
    };
    let [r, g, b] = builtin.look.colour;
    let color = RGBColor(r, g, b);
    // An arm deaf to statements is drawn as one blind to context: each is its twin's
    // counterpart, and a suite compares one kind of twin at a time.
    let unaware = options.context_blind || options.ignores_statements;
    let shift = match (unaware, options.initial) {
        (false, Initial::Random) => None,
        (false, Initial::Learned) => Some(3),
        (true, Initial::Random) => Some(5),
        (true, Initial::Learned) => Some(1),
    };
    // A variant's colour is its base arm's palette place moved on by its suffixes', among
    // the colours but the paper's two.
    let color = match shift {
        None => color,
        Some(shift) => {
            let place = ARM_COLORS.iter().position(|&c| c == color).unwrap_or(0);
            ARM_COLORS[2 + (place + shift) % (ARM_COLORS.len() - 2)]
        }
    };
    ArmStyle {
        color,
        shape: builtin.look.marker,
    }
}

/// A stable hash of an arm's name (FNV-1a), from which a user's arm draws its style.
fn name_hash(name: &str) -> u64 {
    name.bytes().fold(0xcbf2_9ce4_8422_2325, |hash, byte| {
        (hash ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// The order in which to draw arms named `names` so that the paper's two
/// (`random-walk`, then `case-based`) come last, on top of the others.
pub fn drawing_order(names: &[&ArmName]) -> Vec<usize> {
    let paper = &crate::experiment::arm::builtin_arms()[..2];
    let rank = |name: &ArmName| {
        paper
            .iter()
            .position(|arm| *name == arm.name)
            .map_or(0, |place| place + 1)
    };
    let mut order: Vec<usize> = (0..names.len()).collect();
    order.sort_by_key(|&i| rank(names[i]));
    order
}

/// A pixel coordinate or length for SVG text: rounded to 0.1 px, without a trailing
/// `.0`.
fn px(v: f64) -> String {
    let tenths = (v * 10.0).round() / 10.0;
    if tenths == tenths.trunc() {
        format!("{}", tenths as i64)
    } else {
        format!("{tenths:.1}")
    }
}

/// `#RRGGBB`.
fn hex(color: RGBColor) -> String {
    format!("#{:02X}{:02X}{:02X}", color.0, color.1, color.2)
}

/// The data layers of a figure, written as compact SVG on top of what plotters drew
/// (axes, titles, keys): cells as one path per colour, segments as one path per style,
/// markers grouped by style with fractional sizes (plotters rounds radii to whole
/// pixels). Coordinates are pixels of the whole figure, rounded to 0.1 px.
#[derive(Debug, Default)]
pub struct Overlay {
    svg: String,
    /// The groups drawn so far, by id, with the origin each was drawn at.
    groups: std::collections::BTreeMap<String, (f64, f64)>,
}

impl Overlay {
    /// What `draw` adds, as a group named `id` drawn relative to `origin` (pixels); when a
    /// group of that id was drawn before, a reference to it moved to `origin` instead
    /// (the caller makes sure the two drawings would be the same). Ids must be unique in
    /// the page the figure goes into.
    pub fn group(&mut self, id: &str, origin: (f64, f64), draw: impl FnOnce(&mut Self)) {
        if let Some(&(x, y)) = self.groups.get(id) {
            let _ = writeln!(
                self.svg,
                "<use href=\"#{id}\" transform=\"translate({} {})\"/>",
                px(origin.0 - x),
                px(origin.1 - y)
            );
        } else {
            self.groups.insert(id.to_owned(), origin);
            let _ = writeln!(self.svg, "<g id=\"{id}\">");
            draw(self);
            self.svg.push_str("</g>\n");
        }
    }

    /// Filled rectangles, each `(colour, corner, opposite corner)`.
    pub fn rects(&mut self, rects: impl IntoIterator<Item = (RGBColor, (f64, f64), (f64, f64))>) {
        let mut by_color: std::collections::BTreeMap<(u8, u8, u8), String> = Default::default();
        for (color, (x0, y0), (x1, y1)) in rects {
            let d = by_color.entry((color.0, color.1, color.2)).or_default();
            let (x, y) = (x0.min(x1), y0.min(y1));
            let _ = write!(
                d,
                "M{} {}h{}v{}h-{}z",
                px(x),
                px(y),
                px((x1 - x0).abs()),
                px((y1 - y0).abs()),
                px((x1 - x0).abs())
            );
        }
        for ((r, g, b), d) in by_color {
            let _ = writeln!(
                self.svg,
                "<path fill=\"{}\" d=\"{d}\"/>",
                hex(RGBColor(r, g, b))
            );
        }
    }

    /// Line segments of one colour and width (pixels).
    pub fn segments(
        &mut self,
        color: RGBColor,
        width: f64,
        segments: impl IntoIterator<Item = ((f64, f64), (f64, f64))>,
    ) {
        let mut d = String::new();
        for ((x0, y0), (x1, y1)) in segments {
            let _ = write!(d, "M{} {}L{} {}", px(x0), px(y0), px(x1), px(y1));
        }
        if !d.is_empty() {
            let _ = writeln!(
                self.svg,
                "<path fill=\"none\" stroke=\"{}\" stroke-width=\"{}\" stroke-linecap=\"square\" d=\"{d}\"/>",
                hex(color),
                px(width)
            );
        }
    }

    /// Markers of one shape and style, each `(centre, r)` with the area of a disc of
    /// radius `r` (pixels): filled with `fill` at `opacity` when given, outlined with
    /// `stroke` (colour, width) when given.
    pub fn markers(
        &mut self,
        shape: Shape,
        fill: Option<(RGBColor, f64)>,
        stroke: Option<(RGBColor, f64)>,
        markers: impl IntoIterator<Item = ((f64, f64), f64)>,
    ) {
        let fill = fill.map_or("fill=\"none\"".to_owned(), |(c, opacity)| {
            if opacity < 1.0 {
                format!("fill=\"{}\" fill-opacity=\"{opacity}\"", hex(c))
            } else {
                format!("fill=\"{}\"", hex(c))
            }
        });
        let stroke = stroke.map_or(String::new(), |(c, width)| {
            format!(" stroke=\"{}\" stroke-width=\"{}\"", hex(c), px(width))
        });
        let mut group = format!("<g {fill}{stroke}>\n");
        let mut any = false;
        for (at, r) in markers {
            group.push_str(&shape.element(at, r));
            group.push('\n');
            any = true;
        }
        if any {
            self.svg.push_str(&group);
            self.svg.push_str("</g>\n");
        }
    }

    /// Text of font size `size` (as plotters' sizes) centred on each point.
    pub fn texts(
        &mut self,
        size: u32,
        texts: impl IntoIterator<Item = ((f64, f64), RGBColor, String)>,
    ) {
        let _ = writeln!(
            self.svg,
            "<g font-family=\"sans-serif\" font-size=\"{}\" text-anchor=\"middle\" dominant-baseline=\"central\">",
            px(f64::from(size) / 1.24)
        );
        for ((x, y), color, text) in texts {
            let _ = writeln!(
                self.svg,
                "<text x=\"{}\" y=\"{}\" fill=\"{}\">{}</text>",
                px(x),
                px(y),
                hex(color),
                text.replace('&', "&amp;").replace('<', "&lt;")
            );
        }
        self.svg.push_str("</g>\n");
    }
}

/// A perceptually ordered colour for a probability (viridis): dark blue (0) through teal
/// to yellow (1).
pub fn probability_color(p: f64) -> RGBColor {
    const STOPS: [(f64, [f64; 3]); 5] = [
        (0.0, [68.0, 1.0, 84.0]),
        (0.25, [59.0, 82.0, 139.0]),
        (0.5, [33.0, 145.0, 140.0]),
        (0.75, [94.0, 201.0, 98.0]),
        (1.0, [253.0, 231.0, 37.0]),
    ];
    let p = p.clamp(0.0, 1.0);
    let k = STOPS
        .iter()
        .rposition(|(at, _)| *at <= p)
        .unwrap_or(0)
        .min(3);
    let ((a, ca), (b, cb)) = (STOPS[k], STOPS[k + 1]);
    let f = (p - a) / (b - a);
    let mix = |i: usize| (ca[i] + (cb[i] - ca[i]) * f).round() as u8;
    RGBColor(mix(0), mix(1), mix(2))
}

/// A component's axis title: its name and unit, e.g. `speed (m/s)`; the name alone for a
/// component without unit (categories).
pub fn axis_title(component: &NamedComponent) -> String {
    if component.unit.is_empty() {
        component.name.clone()
    } else {
        format!("{} ({})", component.name, component.unit)
    }
}

/// The real values of a component, one label per index.
pub fn value_labels(component: &NamedComponent) -> Vec<String> {
    (0..component.len())
        .map(|i| component.display_value(i as u16).to_string())
        .collect()
}

/// Labels the categories of an axis whose category `i` sits at `i`: `labels[i]` at the
/// integers, nothing in between.
pub fn category_label(labels: &[String]) -> impl Fn(&f64) -> String + '_ {
    move |v: &f64| {
        let i = v.round();
        if (v - i).abs() < 1e-6 && i >= 0.0 && (i as usize) < labels.len() {
            labels[i as usize].clone()
        } else {
            String::new()
        }
    }
}

/// Ticks a reader can interpolate between on a log axis from `low` to `high` drawn
/// `pixels` long: 1, 1.5, 2, 3, 5, 7 times each power of ten in the range, or only 1, 2,
/// 5, or only the powers of ten, whichever is the densest whose closest labels are at
/// least 15 px apart.
pub fn log_ticks(low: f64, high: f64, pixels: u32) -> Vec<f64> {
    let per_decade = f64::from(pixels) / (high / low).log10();
    let steps: &[f64] = if 1.5f64.log10() * per_decade >= 15.0 {
        &[1.0, 1.5, 2.0, 3.0, 5.0, 7.0]
    } else if 2f64.log10() * per_decade >= 15.0 {
        &[1.0, 2.0, 5.0]
    } else {
        &[1.0]
    };
    let mut ticks = Vec::new();
    let mut magnitude = 10f64.powf(low.log10().floor());
    while magnitude <= high {
        for step in steps {
            let v = step * magnitude;
            if (low..=high).contains(&v) {
                ticks.push(v);
            }
        }
        magnitude *= 10.0;
    }
    ticks
}

/// A tick label of [`log_ticks`]: `1.5`, `20`, `0.3`, with no trailing zeros.
pub fn tick_label(v: &f64) -> String {
    let s = format!("{:.3}", v);
    s.trim_end_matches('0').trim_end_matches('.').to_owned()
}

/// The width (px) of `text` drawn with plotters at font size `size`, overestimated for
/// laying out figures so that nothing is clipped: plotters' SVG backend writes the size
/// as `size / 1.24` pixels, and 0.6 em a character is wider than the digits (0.56 em) and
/// most letters of common sans-serif fonts.
pub fn text_width(text: &str, size: u32) -> u32 {
    (text.chars().count() as f64 * 0.6 * f64::from(size) / 1.24).ceil() as u32
}

/// `labels` with only every `step`-th kept (the others empty), `step` the smallest that
/// leaves `gap` px between labels drawn at font size `size` in cells `cell_width` px wide,
/// so that labels never overlap.
pub fn sparse_labels(labels: &[String], size: u32, gap: f64, cell_width: f64) -> Vec<String> {
    let widest = labels
        .iter()
        .map(|l| text_width(l, size))
        .max()
        .unwrap_or(0);
    let step = ((f64::from(widest) + gap) / cell_width).ceil().max(1.0) as usize;
    labels
        .iter()
        .enumerate()
        .map(|(i, l)| {
            if i % step == 0 {
                l.clone()
            } else {
                String::new()
            }
        })
        .collect()
}

/// `text` broken into lines at spaces so that each is at most `width` px wide at font
/// size `size` by [`text_width`] (a word wider than that gets a line of its own).
pub fn wrap(text: &str, size: u32, width: u32) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split_whitespace() {
        match lines.last_mut() {
            Some(line) if text_width(&format!("{line} {word}"), size) <= width => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_owned()),
        }
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compact_svg_by_hand() {
        assert_eq!(
            compact(
                "<text font-size=\"10.483870967741936\" opacity=\"1\" fill=\"#000000\">a</text>"
            ),
            "<text font-size=\"10.5\" fill=\"#000\">a</text>"
        );
        let mut overlay = Overlay::default();
        overlay.group("a", (1.0, 2.0), |o| {
            o.segments(BLACK, 1.0, [((0.0, 0.0), (1.0, 1.0))])
        });
        overlay.group("a", (11.0, 2.0), |_| unreachable!("drawn once"));
        assert!(overlay.svg.starts_with("<g id=\"a\">\n<path"));
        assert!(
            overlay
                .svg
                .ends_with("<use href=\"#a\" transform=\"translate(10 0)\"/>\n")
        );
    }

    #[test]
    fn arms_keep_their_style_and_the_paper_s_two_come_last() {
        let arm_style = |name: &str| arm_style(&ArmName::parse(name).unwrap());
        let names_of = |names: &[&str]| -> Vec<ArmName> {
            names.iter().map(|n| ArmName::parse(n).unwrap()).collect()
        };
        assert_eq!(arm_style("random-walk").color, RGBColor(213, 94, 0));
        assert_eq!(arm_style("random-walk").shape, Shape::Circle);
        assert_eq!(arm_style("case-based").color, RGBColor(0, 114, 178));
        assert_eq!(arm_style("case-based").shape, Shape::Square);
        let names = crate::experiment::arm::builtin_arm_names();
        let builtin: Vec<ArmStyle> = names.iter().map(|a| arm_style(a)).collect();
        // No two built-in arms alike, and none but the paper's two in their colours.
        for (i, a) in builtin.iter().enumerate() {
            assert!(builtin[..i].iter().all(|b| b != a));
            assert!(i < 2 || builtin[..2].iter().all(|b| b.color != a.color));
        }
        // A learned start, a blind arm and both keep their base arm's shape, each in a
        // colour of its own.
        for (k, name) in names.iter().enumerate() {
            let varied = [
                "+learned-start",
                "+context-blind",
                "+context-blind+learned-start",
            ]
            .map(|suffixes| arm_style(&format!("{name}{suffixes}")));
            for (i, style) in varied.iter().enumerate() {
                assert_eq!(style.shape, builtin[k].shape);
                assert_ne!(style.color, builtin[k].color);
                assert!(builtin[..2].iter().all(|b| b.color != style.color));
                assert!(varied[..i].iter().all(|v| v.color != style.color));
            }
        }
        // A user's arm: its style is its name's, never the paper's colours, wherever it
        // is listed.
        let mine = arm_style("my-annealing");
        let listed = names_of(&["x", "my-annealing"]);
        assert_eq!(arm_styles(&listed.iter().collect::<Vec<_>>())[1], mine);
        assert!(builtin[..2].iter().all(|b| b.color != mine.color));
        assert_eq!(
            drawing_order(
                &names_of(&["uniform", "case-based", "random-walk", "x"])
                    .iter()
                    .collect::<Vec<_>>()
            ),
            [0, 3, 2, 1]
        );
        // A disc's element, and a square of the same area (side r sqrt(pi)).
        assert_eq!(
            Shape::Circle.element((1.0, 2.04), 2.5),
            "<circle cx=\"1\" cy=\"2\" r=\"2.5\"/>"
        );
        let square = Shape::Square.vertices((0.0, 0.0), 1.0).unwrap();
        let side = (square[0].0 - square[1].0).abs();
        assert!((side * side - std::f64::consts::PI).abs() < 1e-9);
    }

    #[test]
    fn colors_at_the_ends_and_between() {
        assert_eq!(probability_color(0.0), RGBColor(0x44, 0x01, 0x54));
        assert_eq!(probability_color(1.0), RGBColor(0xfd, 0xe7, 0x25));
        assert_eq!(probability_color(0.5), RGBColor(0x21, 0x91, 0x8c));
        assert_eq!(probability_color(-1.0), probability_color(0.0));
    }

    #[test]
    fn labels_by_hand() {
        let labels = vec!["a".to_owned(), "b".to_owned()];
        let label = category_label(&labels);
        assert_eq!(
            (label(&1.0), label(&0.5), label(&2.0)),
            ("b".into(), String::new(), String::new())
        );
        assert_eq!(
            log_ticks(0.9, 25.0, 300),
            [1.0, 1.5, 2.0, 3.0, 5.0, 7.0, 10.0, 15.0, 20.0]
        );
        assert_eq!(log_ticks(0.5, 2000.0, 300).len(), 12);
        assert_eq!(log_ticks(0.5, 2000.0, 100), [1.0, 10.0, 100.0, 1000.0]);
        assert_eq!(
            (tick_label(&1.5), tick_label(&20.0)),
            ("1.5".into(), "20".into())
        );
        let speed = NamedComponent::numeric("speed", "m/s", 0.5, 0.5, 3).unwrap();
        assert_eq!(axis_title(&speed), "speed (m/s)");
        assert_eq!(value_labels(&speed), ["0.5", "1", "1.5"]);
        let mode = NamedComponent::categorical("mode", &["x", "y"]).unwrap();
        assert_eq!(axis_title(&mode), "mode");
        // 3 * 0.6 * 10 / 1.24 = 14.5.
        assert_eq!(text_width("0.5", 10), 15);
        // "aa bb" is ceil(5 * 0.6 * 10 / 1.24) = 25 px: too wide for 20.
        assert_eq!(wrap("aa bb  cc", 10, 20), ["aa", "bb", "cc"]);
        assert_eq!(wrap("aa bb cc", 10, 25), ["aa bb", "cc"]);
        assert_eq!(wrap("", 10, 25), Vec::<String>::new());
    }
}
