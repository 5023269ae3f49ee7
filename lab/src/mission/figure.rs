//! The mission timeline figure: the trust estimate of the behavior in use over a whole
//! mission, the robot's own record of a settled behavior, both thresholds, the changes of
//! operator (which the robot is not told of), re-adaptations, alerts and complacency
//! onsets. A mission traced command by command is drawn point by point; a long one,
//! summarised ([`crate::mission::MissionTrace`]), is drawn a step at a time, with the band
//! of estimates each step's commands reached.

use crate::mission::{ChangeKind, Mark, MissionArmResult, MissionStep};
use crate::report::plot::{Area, DrawResult, arm_style};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use trust::Thresholds;

/// The figure's chart: commands of the mission by trust estimate.
type Chart<'c, 'b> = ChartContext<'c, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

const CHANGE: RGBColor = RGBColor(120, 120, 120);
const READAPTATION: RGBColor = RGBColor(200, 40, 40);
const ALERT: RGBColor = RGBColor(230, 140, 0);
const ONSET: RGBColor = RGBColor(120, 60, 170);
const OWN: RGBColor = RGBColor(40, 40, 40);

/// Draws `arm`'s first mission of plan `plan` against `thresholds`.
pub fn mission_figure(
    area: &Area<'_>,
    plan: &str,
    arm: &MissionArmResult,
    thresholds: &Thresholds,
) -> DrawResult {
    let steps = &arm.traced.steps;
    let every = f64::from(arm.traced.every.max(1));
    // Where step `i` starts and ends, in commands.
    let start = |i: usize| i as f64 * every;
    let end = |i: usize| ((i + 1) as f64 * every).min(f64::from(arm.traced.commands));
    let n = (steps.len() as f64 * every)
        .min(f64::from(arm.traced.commands))
        .max(1.0);
    let (low, high) = (thresholds.untrustworthy - 1.5, thresholds.trustworthy + 2.5);
    let clamp = |v: f64| v.clamp(low, high);
    let (plot, key) = area.split_vertically(area.dim_in_pixel().1.saturating_sub(30));
    let answered = if arm.answers_alerts {
        ", alerts answered"
    } else {
        ""
    };
    let mut chart = ChartBuilder::on(&plot)
        .caption(
            format!("{plan}: mission 0 ({} arm{answered})", arm.arm),
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..n, low..high)?;
    // A summarised mission is long: its commands in thousands keep the labels short.
    let thousands = |x: &f64| {
        if x.abs() >= 1000.0 {
            format!("{}k", x / 1000.0)
        } else {
            format!("{x:.0}")
        }
    };
    let mut mesh = chart.configure_mesh();
    mesh.light_line_style(TRANSPARENT)
        .x_desc("command of the mission")
        .y_desc("trust estimate of the behavior in use");
    if arm.traced.every > 1 {
        mesh.x_label_formatter(&thousands);
    }
    mesh.draw()?;
    for value in [thresholds.trustworthy, thresholds.untrustworthy] {
        chart.draw_series(DashedLineSeries::new(
            [(0.0, value), (n, value)],
            6,
            4,
            RGBColor(90, 90, 90).stroke_width(1),
        ))?;
    }
    // Changes first, under the estimate.
    draw_changes(&mut chart, steps, &start, n, (low, high))?;
    let color = arm_style(&arm.arm).color;
    if arm.traced.every > 1 {
        // The band of estimates each step's commands reached, under the line.
        let band: Vec<(f64, f64)> = steps
            .iter()
            .enumerate()
            .map(|(i, s)| (end(i), clamp(s.high)))
            .chain(
                steps
                    .iter()
                    .enumerate()
                    .rev()
                    .map(|(i, s)| (end(i), clamp(s.low))),
            )
            .collect();
        chart.draw_series(std::iter::once(Polygon::new(
            band,
            color.mix(0.25).filled(),
        )))?;
    }
    chart.draw_series(LineSeries::new(
        steps
            .iter()
            .enumerate()
            .map(|(i, s)| (end(i), clamp(s.estimate))),
        color.stroke_width(1),
    ))?;
    draw_own_record(&mut chart, steps, &end, &clamp)?;
    draw_marks(&mut chart, steps, &end, high - 1.0)?;
    draw_key(&key, arm.traced.every, color)
}

/// Draws a vertical line and its label at every change of operator or context.
fn draw_changes(
    chart: &mut Chart<'_, '_>,
    steps: &[MissionStep],
    start: &dyn Fn(usize) -> f64,
    n: f64,
    (low, high): (f64, f64),
) -> DrawResult {
    for (i, step) in steps.iter().enumerate() {
        for mark in &step.marks {
            if let Mark::Change(kind) = mark {
                let x = start(i);
                chart.draw_series(LineSeries::new(
                    [(x, low), (x, high)],
                    CHANGE.stroke_width(2),
                ))?;
                let label = match kind {
                    ChangeKind::Takeover => "takeover",
                    ChangeKind::Shift => "shift",
                    ChangeKind::Context => "context",
                };
                chart.draw_series(std::iter::once(Text::new(
                    label,
                    (x + n * 0.004, high - 0.3),
                    ("sans-serif", 12).into_font().color(&CHANGE),
                )))?;
            }
        }
    }
    Ok(())
}

/// Draws the robot's own record where a behavior is settled, one dashed segment per watch.
fn draw_own_record(
    chart: &mut Chart<'_, '_>,
    steps: &[MissionStep],
    end: &dyn Fn(usize) -> f64,
    clamp: &dyn Fn(f64) -> f64,
) -> DrawResult {
    let mut segment: Vec<(f64, f64)> = Vec::new();
    for (i, step) in steps.iter().enumerate() {
        match step.own_record {
            Some(v) => segment.push((end(i), clamp(v))),
            None if !segment.is_empty() => {
                chart.draw_series(DashedLineSeries::new(
                    std::mem::take(&mut segment),
                    3,
                    3,
                    OWN.stroke_width(1),
                ))?;
            }
            None => {}
        }
    }
    if !segment.is_empty() {
        chart.draw_series(DashedLineSeries::new(segment, 3, 3, OWN.stroke_width(1)))?;
    }
    Ok(())
}

/// Draws the re-adaptations, alerts and complacency onsets in a row under `top`.
fn draw_marks(
    chart: &mut Chart<'_, '_>,
    steps: &[MissionStep],
    end: &dyn Fn(usize) -> f64,
    top: f64,
) -> DrawResult {
    for (i, step) in steps.iter().enumerate() {
        let x = end(i);
        for mark in &step.marks {
            match mark {
                Mark::Readaptation => {
                    chart.draw_series(std::iter::once(TriangleMarker::new(
                        (x, top),
                        6,
                        READAPTATION.filled(),
                    )))?;
                }
                Mark::Alert => {
                    chart.draw_series(std::iter::once(Circle::new(
                        (x, top - 0.5),
                        5,
                        ALERT.filled(),
                    )))?;
                }
                Mark::Onset => {
                    chart.draw_series(std::iter::once(Cross::new(
                        (x, top - 1.0),
                        5,
                        ONSET.stroke_width(2),
                    )))?;
                }
                Mark::Change(_) | Mark::Switch | Mark::Settled => {}
            }
        }
    }
    Ok(())
}

/// Draws the figure's key in one row: the estimate (with its band when a step holds
/// `every` commands), the own record, and the marks.
fn draw_key(key: &Area<'_>, every: u32, color: RGBColor) -> DrawResult {
    let mut x = 72;
    let estimate = if every > 1 {
        format!("estimate (range per {})", every)
    } else {
        "estimate".to_owned()
    };
    for (label, colour) in [
        (estimate.as_str(), color),
        ("own record (dashed)", OWN),
        ("operator change", CHANGE),
        ("re-adaptation (triangle)", READAPTATION),
        ("alert (dot)", ALERT),
        ("complacency onset (cross)", ONSET),
    ] {
        key.draw(&Rectangle::new([(x, 8), (x + 12, 20)], colour.filled()))?;
        key.draw(&Text::new(
            label,
            (x + 16, 6),
            ("sans-serif", 13).into_font(),
        ))?;
        x += 30 + crate::report::plot::text_width(label, 13) as i32;
    }
    Ok(())
}
