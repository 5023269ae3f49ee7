//! Every experiment and arm at once: each arm's value with its 95% interval, one column
//! per experiment, on a log scale: the summary figures (behaviors, commands and
//! untrustworthy commands per trial, the known-operator limit as bars) and the effect
//! sizes (ratios to the reference arm, a bar at 1).

use super::legend::{Key, LEGEND_WIDTH, legend};
use crate::experiment::arm_name::ArmName;
use crate::experiment::record::ArmResult;
use crate::reference::limit::Costs;
use crate::report::entry::ReportEntry;
use crate::report::plot::{
    Area, DrawResult, Overlay, arm_style, category_label, drawing_order, log_ticks, tick_label,
};
use crate::stats::{MeanCi, RatioCi};
use plotters::prelude::*;

/// The experiments' names as a figure's categories, and the scenario they share: without
/// the scenario when every experiment has the same one (a ladder's rungs), so more of them
/// fit side by side (the title names it instead).
fn category_names<'a>(entries: &[ReportEntry<'a>]) -> (Option<&'a str>, Vec<String>) {
    let shared = entries
        .first()
        .map(|first| first.scenario)
        .filter(|scenario| entries.iter().all(|e| e.scenario == *scenario));
    let names = entries
        .iter()
        .map(|e| match shared {
            Some(scenario) => e
                .result
                .name
                .strip_prefix(&format!("{scenario}/"))
                .unwrap_or(&e.result.name)
                .to_owned(),
            None => e.result.name.clone(),
        })
        .collect();
    (shared, names)
}

/// What a summary figure shows of each arm, and of the limit.
#[derive(Clone, Copy)]
pub(super) struct SummaryMetric {
    /// The file name's stem.
    pub(super) stem: &'static str,
    /// The figure's title.
    title: &'static str,
    /// What it measures, for its caption.
    pub(super) what: &'static str,
    /// The y axis's title.
    axis: &'static str,
    /// The arm's mean and CI.
    arm: fn(&ArmResult) -> MeanCi,
    /// The limit's value.
    limit: fn(&Costs) -> f64,
}

/// The three summary figures: behaviors (the paper's metric), commands, untrustworthy
/// commands.
pub(super) const SUMMARY_METRICS: [SummaryMetric; 3] = [
    SummaryMetric {
        stem: "summary",
        title: "Behaviors evaluated per trial: every experiment and arm (mean, 95% CI)",
        what: "Behaviors evaluated per trial (the paper's metric)",
        axis: "behaviors evaluated (log scale)",
        arm: |a| a.behaviors,
        limit: |c| c.behaviors,
    },
    SummaryMetric {
        stem: "summary-commands",
        title: "Commands per trial: every experiment and arm (mean, 95% CI)",
        what: "Commands per trial (how long the operator waited for a trustworthy behavior)",
        axis: "commands (log scale)",
        arm: |a| a.commands,
        limit: |c| c.commands,
    },
    SummaryMetric {
        stem: "summary-untrustworthy",
        title: "Untrustworthy commands per trial: every experiment and arm (mean, 95% CI)",
        what: "Untrustworthy commands per trial (commands that failed or that the operator interrupted)",
        axis: "untrustworthy commands (log scale)",
        arm: |a| a.untrustworthy,
        limit: |c| c.untrustworthy,
    },
];

/// A value with its 95% interval, as a figure of every experiment and arm draws it.
#[derive(Clone, Copy, Debug)]
struct Interval {
    mid: f64,
    low: f64,
    high: f64,
}

impl From<MeanCi> for Interval {
    fn from(m: MeanCi) -> Self {
        Self {
            mid: m.mean,
            low: m.mean - m.ci95,
            high: m.mean + m.ci95,
        }
    }
}

/// What a figure of every experiment (across) and arm (offset within it) shows.
pub(super) struct EveryArm<'a> {
    title: String,
    axis: &'a str,
    /// Per experiment, per arm: the value and its interval (`None`: not drawn).
    values: Vec<Vec<Option<Interval>>>,
    /// Per experiment, a black bar across its arms (`None`: none), and its key.
    bars: Vec<Option<f64>>,
    bar_key: String,
}

/// The summary figure of `metric`: each arm's mean and CI, the limit as bars.
pub(super) fn summary_figure(
    entries: &[ReportEntry<'_>],
    metric: SummaryMetric,
) -> EveryArm<'static> {
    EveryArm {
        title: metric.title.to_owned(),
        axis: metric.axis,
        values: entries
            .iter()
            .map(|e| {
                e.result
                    .arms
                    .iter()
                    .map(|a| Some((metric.arm)(a).into()))
                    .collect()
            })
            .collect(),
        bars: entries
            .iter()
            .map(|e| e.limit.map(|l| (metric.limit)(&l.limit.paper)))
            .collect(),
        bar_key: "known-operator limit".to_owned(),
    }
}

/// The effect-sizes figure: each arm's ratio to the reference arm's mean behaviors
/// evaluated ([`crate::report::effect_sizes`]) with its bootstrap interval, a bar at 1.
pub(super) fn effects_figure(
    entries: &[ReportEntry<'_>],
    effects: &[Vec<Option<RatioCi>>],
) -> EveryArm<'static> {
    let reference = entries.first().map_or("", |e| e.reference);
    EveryArm {
        title: format!("Behaviors evaluated per trial as a ratio to {reference}'s (95% CI)"),
        axis: "ratio to the reference arm (log scale)",
        values: effects
            .iter()
            .map(|effects| {
                effects
                    .iter()
                    .map(|r| {
                        r.map(|r| Interval {
                            mid: r.ratio,
                            low: r.low,
                            high: r.high,
                        })
                    })
                    .collect()
            })
            .collect(),
        bars: vec![Some(1.0); entries.len()],
        bar_key: format!("{reference} (the reference) = 1"),
    }
}

/// Draws `figure`: one column per experiment, each arm's value as its marker with its
/// interval as a vertical line, on a log axis, the bars in black, the legend at the right.
pub(super) fn every_arm_figure(
    area: &Area<'_>,
    overlay: &mut Overlay,
    entries: &[ReportEntry<'_>],
    figure: &EveryArm<'_>,
) -> DrawResult {
    let (width, _) = area.dim_in_pixel();
    let (plot, side) = area.split_horizontally(width.saturating_sub(LEGEND_WIDTH));
    let arms = entries.first().map_or(0, |e| e.result.arms.len()).max(1);
    let drawn = || figure.values.iter().flatten().flatten();
    let top = drawn()
        .map(|v| v.high)
        .chain(figure.bars.iter().flatten().copied())
        .fold(2.0f64, f64::max);
    // The lower ends where they are positive (a mean minus its CI may not be).
    let bottom = drawn()
        .map(|v| if v.low > 0.0 { v.low } else { v.mid })
        .chain(figure.bars.iter().flatten().copied())
        .fold(0.8f64, f64::min)
        .max(0.1);
    let (scenario, names) = category_names(entries);
    let title = match scenario {
        Some(scenario) => format!("{scenario}: {}", figure.title),
        None => figure.title.clone(),
    };
    let mut chart = ChartBuilder::on(&plot)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(60)
        .y_label_area_size(60)
        .build_cartesian_2d(
            -0.5..names.len() as f64 - 0.5,
            (bottom * 0.8..top * 1.3)
                .log_scale()
                .with_key_points(log_ticks(bottom * 0.8, top * 1.3, 420)),
        )?;
    let label = category_label(&names);
    chart
        .configure_mesh()
        .light_line_style(TRANSPARENT)
        .disable_x_mesh()
        .x_labels(names.len().max(1))
        .x_label_formatter(&label)
        .x_label_style(("sans-serif", 11))
        .y_desc(figure.axis)
        .y_label_formatter(&tick_label)
        .draw()?;
    let mut legend_entries = Vec::new();
    let arm_names: Vec<&ArmName> = entries
        .first()
        .map(|e| e.result.arms.iter().map(|a| &a.name).collect())
        .unwrap_or_default();
    for name in &arm_names {
        legend_entries.push((name.to_string(), Key::Marker(arm_style(name))));
    }
    for a in drawing_order(&arm_names) {
        let style = arm_style(arm_names[a]);
        let color = style.color;
        let offset = (a as f64 + 0.5) / arms as f64 * 0.7 - 0.35;
        let points: Vec<(f64, Interval)> = figure
            .values
            .iter()
            .enumerate()
            .filter_map(|(x, values)| {
                values
                    .get(a)
                    .copied()
                    .flatten()
                    .map(|v| (x as f64 + offset, v))
            })
            .collect();
        chart.draw_series(points.iter().map(|&(x, v)| {
            PathElement::new(
                vec![(x, v.low.max(bottom * 0.8)), (x, v.high)],
                color.stroke_width(2),
            )
        }))?;
        overlay.markers(
            style.shape,
            Some((color, 1.0)),
            Some((WHITE, 1.0)),
            points.iter().map(|&(x, v)| {
                let (x, y) = chart.backend_coord(&(x, v.mid));
                ((f64::from(x), f64::from(y)), 4.5)
            }),
        );
    }
    let bars: Vec<(f64, f64)> = figure
        .bars
        .iter()
        .enumerate()
        .filter_map(|(x, bar)| bar.map(|y| (x as f64, y)))
        .collect();
    if !bars.is_empty() {
        chart.draw_series(bars.iter().map(|&(x, y)| {
            PathElement::new(vec![(x - 0.42, y), (x + 0.42, y)], BLACK.stroke_width(2))
        }))?;
        legend_entries.push((figure.bar_key.clone(), Key::Line(BLACK)));
    }
    legend(&side, overlay, &legend_entries)
}
