//! Figures of one panel per experiment with a line per arm over its trials in order: the
//! untrustworthy commands summed so far, the case base's size, the share of adaptations
//! from a case, and each arm's distribution of behaviors evaluated.

use super::legend::{Key, LEGEND_WIDTH, legend};
use super::series::{MOVING_AVERAGE_WINDOW, moving_average, thinned};
use crate::experiment::arm_name::ArmName;
use crate::experiment::record::ArmResult;
use crate::report::entry::ReportEntry;
use crate::report::plot::{
    Area, DrawResult, Overlay, arm_style, drawing_order, log_ticks, tick_label,
};
use plotters::prelude::*;

/// At most this many points per curve of a panel of [`small_multiples`].
const PANEL_POINTS: usize = 100;

/// The points of a line, in data units.
type Line = Vec<(f64, f64)>;

/// A figure of one panel per experiment (four a row), one line per arm, the legend at the
/// right.
pub(super) struct Panels {
    title: String,
    x_axis: &'static str,
    y_axis: &'static str,
    /// Whether the x axis is logarithmic (the x values must then be positive).
    log_x: bool,
    /// Per experiment, per arm: the line's points (`None`: the arm is not drawn).
    pub(super) series: Vec<Vec<Option<Line>>>,
}

impl Panels {
    /// Size of one panel (px).
    const PANEL: (u32, u32) = (300, 260);

    pub(super) fn size(&self) -> (u32, u32) {
        let n = self.series.len().max(1);
        let columns = n.min(4) as u32;
        (
            Self::PANEL.0 * columns + LEGEND_WIDTH,
            50 + Self::PANEL.1 * n.div_ceil(4) as u32,
        )
    }
}

/// The figures over trials, each with its file name and caption (HTML).
pub(super) fn over_trials_figures(
    entries: &[ReportEntry<'_>],
) -> [(&'static str, Panels, &'static str); 4] {
    [
        (
            "untrustworthy-over-trials.svg",
            Panels {
                title: "Untrustworthy commands summed over the trials so far".to_owned(),
                x_axis: "trial",
                y_axis: "untrustworthy commands so far",
                log_x: false,
                series: per_trial_lines(entries, |_| true, cumulative_untrustworthy),
            },
            "What the operator has endured: the commands that failed or that it interrupted, \
             summed from the first trial on, one panel per experiment and one line per arm \
             (its marker at the end). A steeper line costs the operator more per trial; a line \
             that bends flatter has learned.",
        ),
        (
            "case-base-over-trials.svg",
            Panels {
                title: "Cases in the base of each arm that reuses cases, after each trial"
                    .to_owned(),
                x_axis: "trial",
                y_axis: "cases",
                log_x: false,
                series: per_trial_lines(entries, |a| a.reuses_cases, case_base_sizes),
            },
            "The case base of each arm that reuses cases (Algorithm 1), trial by trial: the \
             cases it started from, plus one for each trial whose behavior is retained. It \
             levels off once the base covers the situations the operators bring.",
        ),
        (
            "reuse-over-trials.svg",
            Panels {
                title: format!(
                    "Share of adaptations taken from a case (moving average of {MOVING_AVERAGE_WINDOW} trials)"
                ),
                x_axis: "trial",
                y_axis: "share from a case",
                log_x: false,
                series: per_trial_lines(entries, |a| a.reuses_cases, reuse_rates),
            },
            "How often an arm that reuses cases took its next behavior from a stored case \
             rather than from its search, per trial and averaged over the last 25 trials: it \
             rises as the base fills, and stays low where the stored cases seldom fit.",
        ),
        (
            "distributions.svg",
            Panels {
                title: "Behaviors evaluated per trial: each arm's distribution".to_owned(),
                x_axis: "behaviors evaluated (log scale)",
                y_axis: "share of trials",
                log_x: true,
                series: entries
                    .iter()
                    .map(|e| {
                        e.result
                            .arms
                            .iter()
                            .map(|a| Some(ecdf(a.counts())))
                            .collect()
                    })
                    .collect(),
            },
            "Each arm's distribution of behaviors evaluated per trial (the empirical \
             cumulative distribution): across, a number of behaviors (log scale); up, the share \
             of trials that needed at most that many. Further up and left is better; a long \
             tail to the right, which a mean and its CI hide, shows here.",
        ),
    ]
}

/// Per experiment, per arm, a line over its trials in order from `value(arm)` (one value
/// per trial), thinned to [`PANEL_POINTS`]; arms for which `drawn` is false are left out.
fn per_trial_lines(
    entries: &[ReportEntry<'_>],
    drawn: impl Fn(&ArmResult) -> bool,
    value: impl Fn(&ArmResult) -> Vec<f64>,
) -> Vec<Vec<Option<Line>>> {
    entries
        .iter()
        .map(|e| {
            e.result
                .arms
                .iter()
                .map(|arm| {
                    drawn(arm).then(|| {
                        let values = value(arm);
                        thinned(values.len(), PANEL_POINTS)
                            .map(|i| ((i + 1) as f64, values[i]))
                            .collect()
                    })
                })
                .collect()
        })
        .collect()
}

/// Untrustworthy commands summed over the trials so far, trial by trial.
fn cumulative_untrustworthy(arm: &ArmResult) -> Vec<f64> {
    arm.trials
        .iter()
        .scan(0.0, |sum, t| {
            *sum += t.report.untrustworthy as f64;
            Some(*sum)
        })
        .collect()
}

/// Cases in the arm's base after each trial: those it started from and those retained.
fn case_base_sizes(arm: &ArmResult) -> Vec<f64> {
    arm.trials
        .iter()
        .scan(arm.starting_cases as f64, |size, t| {
            *size += f64::from(u8::from(t.report.retained.is_some()));
            Some(*size)
        })
        .collect()
}

/// The share of each trial's adaptations that reused a case (0 for a trial without
/// adaptation), as a moving average of [`MOVING_AVERAGE_WINDOW`] trials.
fn reuse_rates(arm: &ArmResult) -> Vec<f64> {
    let shares: Vec<f64> = arm
        .trials
        .iter()
        .map(|t| {
            let adaptations = t.report.reused + t.report.searched;
            if adaptations == 0 {
                0.0
            } else {
                f64::from(t.report.reused) / f64::from(adaptations)
            }
        })
        .collect();
    moving_average(&shares, MOVING_AVERAGE_WINDOW)
}

/// The empirical distribution of `counts` as the steps of its cumulative share:
/// `(count, share of trials with at most that count)`, each step's foot then its top.
fn ecdf(mut counts: Vec<f64>) -> Vec<(f64, f64)> {
    counts.sort_by(f64::total_cmp);
    let n = counts.len() as f64;
    let mut steps = Vec::new();
    let mut below = 0.0;
    for (k, &c) in counts.iter().enumerate() {
        if counts.get(k + 1) != Some(&c) {
            let share = (k + 1) as f64 / n;
            steps.push((c, below));
            steps.push((c, share));
            below = share;
        }
    }
    steps
}

/// Draws `figure`: a panel per experiment, each arm's line in its colour (the paper's two
/// last) with its marker at the line's end, a shared legend at the right.
pub(super) fn small_multiples(
    area: &Area<'_>,
    overlay: &mut Overlay,
    entries: &[ReportEntry<'_>],
    figure: &Panels,
) -> DrawResult {
    let (width, _) = area.dim_in_pixel();
    let (top, body) = area.split_vertically(50);
    top.draw(&Text::new(
        figure.title.as_str(),
        (10, 12),
        ("sans-serif", 20).into_font(),
    ))?;
    let (panels_area, side) = body.split_horizontally(width.saturating_sub(LEGEND_WIDTH));
    let columns = entries.len().clamp(1, 4);
    let panels = panels_area.split_evenly((entries.len().div_ceil(4).max(1), columns));
    let names: Vec<&ArmName> = entries
        .first()
        .map(|e| e.result.arms.iter().map(|a| &a.name).collect())
        .unwrap_or_default();
    let scale = |v: f64| if figure.log_x { v.max(1e-9).log10() } else { v };
    for ((panel, e), series) in panels.iter().zip(entries).zip(&figure.series) {
        let points = || series.iter().flatten().flatten();
        let (mut x0, mut x1) = points().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.0), b.max(p.0))
        });
        // Plotters never ends placing ticks on an empty or infinite range.
        if !x0.is_finite() {
            (x0, x1) = (1.0, 2.0);
        } else if x1 <= x0 {
            x1 = x0 + 1.0;
        }
        if figure.log_x {
            (x0, x1) = (x0 * 0.9, x1 * 1.1);
        }
        let y1 = match points().map(|p| p.1).fold(0.0f64, f64::max) {
            most if most > 0.0 => most * 1.05,
            _ => 1.0,
        };
        let mut chart = ChartBuilder::on(panel)
            .caption(&e.result.name, ("sans-serif", 14))
            .margin(8)
            .margin_right(14)
            .x_label_area_size(36)
            .y_label_area_size(48)
            .build_cartesian_2d(scale(x0)..scale(x1), 0.0..y1)?;
        let mut mesh = chart.configure_mesh();
        mesh.light_line_style(TRANSPARENT)
            .x_label_formatter(&tick_label)
            .y_label_formatter(&tick_label)
            .label_style(("sans-serif", 11))
            .axis_desc_style(("sans-serif", 12))
            .x_desc(figure.x_axis)
            .y_desc(figure.y_axis)
            .y_labels(5);
        // A log axis is drawn in log10 units: its ticks and labels are placed by hand.
        mesh.x_labels(if figure.log_x { 0 } else { 5 });
        mesh.draw()?;
        if figure.log_x {
            let at: Vec<(f64, (f64, f64))> = log_ticks(x0, x1, 220)
                .into_iter()
                .map(|t| {
                    let (px, py) = chart.backend_coord(&(scale(t), 0.0));
                    (t, (f64::from(px), f64::from(py)))
                })
                .collect();
            overlay.segments(
                BLACK,
                1.0,
                at.iter().map(|&(_, (x, y))| ((x, y), (x, y + 5.0))),
            );
            overlay.texts(
                11,
                at.iter()
                    .map(|&(t, (x, y))| ((x, y + 12.0), BLACK, tick_label(&t))),
            );
        }
        for a in drawing_order(&names) {
            let Some(Some(line)) = series.get(a) else {
                continue;
            };
            let style = arm_style(names[a]);
            chart.draw_series(LineSeries::new(
                line.iter().map(|&(x, y)| (scale(x), y)),
                style.color.stroke_width(2),
            ))?;
            if let Some(&(x, y)) = line.last() {
                let (px, py) = chart.backend_coord(&(scale(x), y));
                overlay.markers(
                    style.shape,
                    Some((style.color, 1.0)),
                    Some((WHITE, 1.0)),
                    [((f64::from(px), f64::from(py)), 4.0)],
                );
            }
        }
    }
    let drawn: Vec<(String, Key)> = names
        .iter()
        .enumerate()
        .filter(|&(a, _)| {
            figure
                .series
                .iter()
                .any(|s| matches!(s.get(a), Some(Some(_))))
        })
        .map(|(_, name)| (name.to_string(), Key::LineMarker(arm_style(name))))
        .collect();
    legend(&side, overlay, &drawn)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distributions_step_by_hand() {
        // Counts 1, 1, 3, 2: half of the trials at 1, three quarters at 2, all at 3.
        assert_eq!(
            ecdf(vec![1.0, 1.0, 3.0, 2.0]),
            [
                (1.0, 0.0),
                (1.0, 0.5),
                (2.0, 0.5),
                (2.0, 0.75),
                (3.0, 0.75),
                (3.0, 1.0)
            ]
        );
        assert_eq!(ecdf(Vec::new()), []);
    }
}
