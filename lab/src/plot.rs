//! What every figure of the reports and landscapes shares: drawing into an SVG string with
//! plotters, the arms' colours, the probability colour map, axis titles with units, tick
//! labels for categories and counts, and a conservative estimate of text width for
//! layouts (plotters' SVG backend cannot measure text, and underestimates it).

use cbr_core::NamedComponent;
use plotters::prelude::*;
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
    let mut svg = String::new();
    {
        let area = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        let drawn = area
            .fill(&WHITE)
            .map_err(|e| e.into())
            .and_then(|()| draw(&area))
            .and_then(|()| area.present().map_err(|e| e.into()));
        drawn.map_err(|e| PlotError {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
    }
    Ok(svg)
}

/// The colour of the arm at `index` (the paper's two arms keep red and blue).
pub fn arm_color(index: usize) -> RGBColor {
    const PALETTE: [RGBColor; 10] = [
        RGBColor(214, 96, 77),
        RGBColor(67, 147, 195),
        RGBColor(120, 120, 120),
        RGBColor(27, 158, 119),
        RGBColor(117, 112, 179),
        RGBColor(230, 171, 2),
        RGBColor(231, 41, 138),
        RGBColor(102, 166, 30),
        RGBColor(140, 81, 10),
        RGBColor(1, 102, 94),
    ];
    PALETTE[index % PALETTE.len()]
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

/// Labels integers on a log axis (`3`, `10`, `100`) and nothing in between, so counts
/// never read `1.0` and no label is drawn twice.
pub fn integer_label(v: &f64) -> String {
    if (v - v.round()).abs() < 1e-9 && *v >= 1.0 {
        format!("{}", v.round())
    } else {
        String::new()
    }
}

/// The width (px) of `text` drawn with plotters at font size `size`, overestimated for
/// laying out figures so that nothing is clipped: plotters' SVG backend writes the size
/// as `size / 1.24` pixels, and 0.6 em a character is wider than the digits (0.56 em) and
/// most letters of common sans-serif fonts.
pub fn text_width(text: &str, size: u32) -> u32 {
    (text.chars().count() as f64 * 0.6 * f64::from(size) / 1.24).ceil() as u32
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
        assert_eq!(integer_label(&10.0), "10");
        assert_eq!(integer_label(&2.5), "");
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
