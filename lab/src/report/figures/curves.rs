//! The learning curves of an experiment: each arm's moving average of behaviors evaluated
//! over the trials in order, with its 95% band.

use super::legend::{Key, LEGEND_WIDTH, legend};
use super::series::{MOVING_AVERAGE_WINDOW, moving_average, thinned};
use crate::experiment::arm_name::ArmName;
use crate::report::entry::ReportEntry;
use crate::report::plot::{
    Area, DrawResult, Overlay, arm_styles, drawing_order, log_ticks, tick_label,
};
use crate::stats::mean_ci95;
use plotters::prelude::*;

/// At most this many points per learning curve (and one more: the last).
const CURVE_POINTS: usize = 200;

/// The 95% confidence band of the moving average: mean ± t * sd / sqrt(n) over the same
/// window, per trial.
fn moving_band(values: &[f64], window: usize) -> Vec<(f64, f64)> {
    (0..values.len())
        .map(|i| {
            let from = (i + 1).saturating_sub(window);
            let m = mean_ci95(&values[from..=i]).expect("a non-empty window");
            (m.mean - m.ci95, m.mean + m.ci95)
        })
        .collect()
}

/// The learning curves of an experiment: each arm's moving average of behaviors
/// evaluated with its 95% band, and each trial's count as a faint dot when `dots` (the
/// SVG file has them, the page does not: they are most of its weight).
pub(super) fn learning_curves(
    area: &Area<'_>,
    overlay: &mut Overlay,
    e: &ReportEntry<'_>,
    dots: bool,
) -> DrawResult {
    let trials = e.result.trials().max(1) as u32;
    let top = e
        .result
        .arms
        .iter()
        .flat_map(|s| s.trials.iter().map(|t| t.report.behaviors_evaluated))
        .max()
        .unwrap_or(1)
        .max(2) as f64;
    let (width, _) = area.dim_in_pixel();
    let (plot, side) = area.split_horizontally(width.saturating_sub(LEGEND_WIDTH));
    let mut chart = ChartBuilder::on(&plot)
        .caption(
            format!("{}: behaviors evaluated per trial", e.result.name),
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(
            0u32..trials,
            (0.8f64..top * 1.2)
                .log_scale()
                .with_key_points(log_ticks(0.8, top * 1.2, 400)),
        )?;
    chart
        .configure_mesh()
        .light_line_style(TRANSPARENT)
        .x_desc("trial (in order; the case base grows)")
        .y_desc("behaviors evaluated (log scale)")
        .y_label_formatter(&tick_label)
        .draw()?;
    let names: Vec<&ArmName> = e.result.arms.iter().map(|a| &a.name).collect();
    let styles = arm_styles(&names);
    for index in drawing_order(&names) {
        let (s, style) = (&e.result.arms[index], styles[index]);
        let color = style.color;
        let counts = s.counts();
        if dots {
            chart.draw_series(
                counts
                    .iter()
                    .enumerate()
                    .map(|(i, &c)| Circle::new((i as u32, c), 2, color.mix(0.25).filled())),
            )?;
        }
        let band = moving_band(&counts, MOVING_AVERAGE_WINDOW);
        let kept: Vec<usize> = thinned(band.len(), CURVE_POINTS).collect();
        let outline: Vec<(u32, f64)> = kept
            .iter()
            .map(|&i| (i as u32, band[i].1.max(0.8)))
            .chain(kept.iter().rev().map(|&i| (i as u32, band[i].0.max(0.8))))
            .collect();
        chart.draw_series(std::iter::once(Polygon::new(
            outline,
            color.mix(0.18).filled(),
        )))?;
        let average = moving_average(&counts, MOVING_AVERAGE_WINDOW);
        chart.draw_series(LineSeries::new(
            thinned(average.len(), CURVE_POINTS).map(|i| (i as u32, average[i])),
            color.stroke_width(3),
        ))?;
        // The arm's marker on its line at eight places, staggered by arm so that markers
        // of lines that run together do not hide each other.
        let stagger = trials as usize / (8 * names.len().max(1));
        overlay.markers(
            style.shape,
            Some((color, 1.0)),
            Some((WHITE, 1.0)),
            (0..8)
                .map(|k| k * trials as usize / 8 + index * stagger)
                .filter_map(|i| average.get(i).map(|&m| (i, m)))
                .map(|(i, m)| {
                    let (x, y) = chart.backend_coord(&(i as u32, m));
                    ((f64::from(x), f64::from(y)), 4.5)
                }),
        );
    }
    side.draw(&Text::new(
        format!("moving average of {MOVING_AVERAGE_WINDOW}, 95% CI band"),
        (8, 30),
        ("sans-serif", 12).into_font(),
    ))?;
    let entries: Vec<(String, Key)> = names
        .iter()
        .zip(&styles)
        .map(|(name, &style)| (name.to_string(), Key::LineMarker(style)))
        .collect();
    legend(&side, overlay, &entries)
}
