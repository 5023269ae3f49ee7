//! The plot of a sweep over one parameter: behaviors evaluated against its values, one
//! panel per experiment and one line per arm, with intervals over seeds.

use super::report::{Series, aggregate};
use super::{Parameter, Sweep, SweepError};
use lab::ArmName;
use lab::report::category_label;
use lab::report::plot::{ArmStyle, arm_style, drawing_order, log_ticks, sparse_labels, tick_label};
use plotters::prelude::*;
use std::path::Path;

/// One panel per experiment: behaviors evaluated (log scale) against the parameter's
/// values, one line per arm (its colour and marker as in every report) with its
/// confidence interval over seeds, the paper's two arms on top; the legend right of the
/// panels.
pub(super) fn plot_parameter(
    sweep: &Sweep,
    parameter: &Parameter,
    series: &Series,
    order: &[String],
    arm_order: &[Vec<ArmName>],
    path: &Path,
) -> Result<String, SweepError> {
    // The cells on this parameter's axis: the base, and those varying it, in value order.
    let prefix = format!("{}=", parameter.name());
    let mut axis: Vec<(String, usize)> = Vec::new();
    for i in 0..parameter.len() {
        let mut suite = sweep.cells[0].suite.clone();
        let label = parameter.apply(i, &mut suite);
        let cell = sweep
            .cells
            .iter()
            .position(|c| c.suite == suite && (c.label == label || c.label == "base"))
            .unwrap_or(0);
        axis.push((label.trim_start_matches(&prefix).to_owned(), cell));
    }
    let arms: Vec<ArmName> = arm_order.first().cloned().unwrap_or_default();
    let styles: Vec<ArmStyle> = arms.iter().map(arm_style).collect();
    let columns = order.len().clamp(1, 4);
    let rows = order.len().div_ceil(columns).max(1);
    let (panel_width, legend_width) = (340u32, 230u32);
    let size = (
        panel_width * columns as u32 + legend_width,
        300 * rows as u32 + 60,
    );
    let svg = lab::report::plot::svg_with(path, size, |area, overlay| {
        let (title, body) = area.split_vertically(40);
        title.titled(
            &format!(
                "Sweep over {}: behaviors evaluated (mean over {} seeds, 95% CI)",
                parameter.name(),
                sweep.config.seeds.len()
            ),
            ("sans-serif", 18),
        )?;
        let (panels_area, legend_area) = body.split_horizontally(panel_width * columns as u32);
        let panels = panels_area.split_evenly((rows, columns));
        let labels: Vec<String> = axis.iter().map(|(l, _)| l.clone()).collect();
        for (panel, experiment) in panels.iter().zip(order) {
            let mut top: f64 = 1.0;
            for (_, cell) in &axis {
                for arm in &arms {
                    if let Some((v, _, _)) = series.get(&(*cell, experiment.clone(), arm.clone())) {
                        let (m, ci) = aggregate(v);
                        top = top.max(m + ci.unwrap_or(0.0));
                    }
                }
            }
            let n = axis.len();
            let mut chart = ChartBuilder::on(panel)
                .caption(experiment, ("sans-serif", 14))
                .margin(8)
                .margin_right(16)
                .x_label_area_size(44)
                .y_label_area_size(50)
                .build_cartesian_2d(
                    -0.5..n as f64 - 0.5,
                    (0.9f64..top * 1.3)
                        .log_scale()
                        .with_key_points(log_ticks(0.9, top * 1.3, 190)),
                )?;
            // Every `step`-th value is labelled so that labels never overlap.
            let (plot_width, _) = chart.plotting_area().dim_in_pixel();
            let cell_width = f64::from(plot_width.max(1)) / n as f64;
            let sparse = sparse_labels(&labels, 12, 6.0, cell_width);
            let label = category_label(&sparse);
            chart
                .configure_mesh()
                .disable_x_mesh()
                .light_line_style(TRANSPARENT)
                .x_labels(n)
                .x_label_formatter(&label)
                .y_label_formatter(&tick_label)
                .label_style(("sans-serif", 12))
                .x_desc(parameter.name())
                .y_desc("behaviors evaluated (log scale)")
                .draw()?;
            for k in drawing_order(&arms.iter().collect::<Vec<_>>()) {
                let (arm, style) = (&arms[k], styles[k]);
                let points: Vec<(f64, f64, Option<f64>)> = axis
                    .iter()
                    .enumerate()
                    .filter_map(|(x, (_, cell))| {
                        series
                            .get(&(*cell, experiment.clone(), arm.clone()))
                            .map(|(v, _, _)| {
                                let (m, ci) = aggregate(v);
                                (x as f64, m, ci)
                            })
                    })
                    .collect();
                chart.draw_series(LineSeries::new(
                    points.iter().map(|&(x, m, _)| (x, m)),
                    style.color.stroke_width(2),
                ))?;
                chart.draw_series(points.iter().filter_map(|&(x, m, ci)| {
                    ci.map(|ci| {
                        PathElement::new(
                            vec![(x, (m - ci).max(0.9)), (x, m + ci)],
                            style.color.stroke_width(1),
                        )
                    })
                }))?;
                overlay.markers(
                    style.shape,
                    Some((style.color, 1.0)),
                    Some((WHITE, 1.0)),
                    points.iter().map(|&(x, m, _)| {
                        let (px, py) = chart.backend_coord(&(x, m));
                        ((f64::from(px), f64::from(py)), 4.0)
                    }),
                );
            }
        }
        // The legend, right of the panels: each arm's line and marker.
        let (left, base) = legend_area.get_base_pixel();
        for (k, (arm, style)) in arms.iter().zip(&styles).enumerate() {
            let y = 30 + 20 * k as i32;
            legend_area.draw(&PathElement::new(
                vec![(8, y), (32, y)],
                style.color.stroke_width(2),
            ))?;
            overlay.markers(
                style.shape,
                Some((style.color, 1.0)),
                Some((WHITE, 1.0)),
                [((f64::from(left + 20), f64::from(base + y)), 4.0)],
            );
            legend_area.draw(&Text::new(
                arm.as_str(),
                (40, y - 7),
                ("sans-serif", 12).into_font(),
            ))?;
        }
        Ok(())
    });
    svg.map_err(|e| SweepError::Plot {
        path: e.path,
        message: e.message,
    })
}
