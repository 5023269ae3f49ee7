//! The legend strip right of a chart: a key (a line, the arm's marker, or both) and a
//! label per entry.

use crate::report::plot::{Area, ArmStyle, DrawResult, Overlay};
use plotters::prelude::*;

/// Width of the legend strip right of a chart, in pixels.
pub(super) const LEGEND_WIDTH: u32 = 250;

/// What a legend entry draws before its label.
pub(super) enum Key {
    /// A line (a series drawn as a line).
    Line(RGBColor),
    /// The arm's marker (a series drawn as markers).
    Marker(ArmStyle),
    /// A line with the arm's marker on it.
    LineMarker(ArmStyle),
}

/// Draws a legend of `entries` (label, key) in `area`, top to bottom; markers go into
/// `overlay`.
pub(super) fn legend(
    area: &Area<'_>,
    overlay: &mut Overlay,
    entries: &[(String, Key)],
) -> DrawResult {
    let (left, top) = area.get_base_pixel();
    for (k, (label, key)) in entries.iter().enumerate() {
        let y = 60 + 22 * k as i32;
        let (line, marker) = match key {
            Key::Line(color) => (Some(*color), None),
            Key::Marker(style) => (None, Some(style)),
            Key::LineMarker(style) => (Some(style.color), Some(style)),
        };
        if let Some(color) = line {
            area.draw(&PathElement::new(
                vec![(8, y), (32, y)],
                color.stroke_width(3),
            ))?;
        }
        if let Some(style) = marker {
            let at = (f64::from(left + 20), f64::from(top + y));
            overlay.markers(
                style.shape,
                Some((style.color, 1.0)),
                Some((WHITE, 1.0)),
                [(at, 5.0)],
            );
        }
        area.draw(&Text::new(
            label.clone(),
            (40, y - 7),
            ("sans-serif", 13).into_font(),
        ))?;
    }
    Ok(())
}
