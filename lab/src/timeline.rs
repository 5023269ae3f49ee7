//! The story of one trial: every command, the trust estimate after it, and the explanation
//! of every switch, as text (`trustcbr explain`) and as a figure (the report's timeline of
//! a sample trial per experiment, the paper's central idea drawn: an estimate that climbs
//! and falls between two thresholds).

use crate::plot::{Area, DrawResult, arm_style, text_width};
use crate::runner::{ExperimentResult, TracedCommand, TrialRecord};
use cbr_core::BehaviorSpace;
use plotters::prelude::*;
use std::fmt::Write as _;
use trust::{Explanation, Next, OutcomeKind, Source, Thresholds};

/// One traced trial and what it needs to be told.
#[derive(Clone, Debug)]
pub struct Timeline {
    /// The experiment's name.
    pub experiment: String,
    /// The arm's name.
    pub arm: String,
    /// The arm's index in the experiment (its colour).
    pub arm_index: usize,
    /// The trial's record.
    pub record: TrialRecord,
    /// Every command, in order.
    pub commands: Vec<TracedCommand>,
    /// The thresholds the estimate is held against.
    pub thresholds: Thresholds,
    /// The names of the domain's observations, in bit order.
    pub observations: Vec<trust::Cause>,
}

/// Switches a sample timeline should show at least and at most, so the figure has
/// something to tell and stays readable.
const SAMPLE_SWITCHES: std::ops::RangeInclusive<u64> = 2..=6;

/// The trial a report draws for an experiment: among the trials its
/// [`sample_arm`](crate::runner::sample_arm)
/// traced as they ran ([`ArmResult::traced`](crate::runner::ArmResult::traced), the
/// first ones, but those too long to keep), the first whose number of switches is in 2 to
/// 6, else the first nearest that range. Returns the arm's index and the trial.
pub fn sample_trial(result: &ExperimentResult) -> Option<(usize, u32)> {
    let arm = result.arms.iter().position(|a| !a.traced.is_empty())?;
    let off_range = |t: &TrialRecord| {
        let switches = t.given_up.len() as u64;
        SAMPLE_SWITCHES
            .start()
            .saturating_sub(switches)
            .max(switches.saturating_sub(*SAMPLE_SWITCHES.end()))
    };
    let ran = &result.arms[arm];
    let chosen = ran
        .trials
        .iter()
        .zip(&ran.traced)
        .filter(|(_, traced)| !traced.is_empty())
        .map(|(t, _)| t)
        .min_by_key(|t| (off_range(t), t.trial))?;
    Some((arm, chosen.trial))
}

/// What the robot perceived, by name (`-` for nothing).
fn perceived(timeline: &Timeline, command: &TracedCommand) -> String {
    let names: Vec<&str> = command
        .outcome
        .observed
        .indices()
        .filter_map(|i| timeline.observations.get(i).map(trust::Cause::as_str))
        .collect();
    if names.is_empty() {
        "-".to_owned()
    } else {
        names.join(",")
    }
}

fn kind_name(kind: OutcomeKind) -> &'static str {
    match kind {
        OutcomeKind::Completed => "completed",
        OutcomeKind::Failed => "failed",
        OutcomeKind::Interrupted => "interrupted",
    }
}

/// The trial as text: each behavior, its commands (how each ended, its weight, what the
/// robot perceived, what the operator stated, the true reason, the estimate after it), and
/// the explanation of each switch and of the end.
pub fn story(timeline: &Timeline, space: &BehaviorSpace) -> String {
    let r = &timeline.record;
    let mut text = format!(
        "{}, arm {}, trial {} (operator {}): {} commands, {} untrustworthy, {} behaviors; thresholds {:+} / {:+}\n",
        timeline.experiment,
        timeline.arm,
        r.trial,
        r.operator,
        r.report.commands,
        r.report.untrustworthy,
        r.report.behaviors_evaluated,
        timeline.thresholds.trustworthy,
        timeline.thresholds.untrustworthy,
    );
    let mut behavior_number = 0;
    let mut starts = true;
    for (i, c) in timeline.commands.iter().enumerate() {
        if starts {
            behavior_number += 1;
            let _ = writeln!(
                text,
                "\nbehavior {behavior_number}: {}",
                space.display(&c.behavior)
            );
            let _ = writeln!(
                text,
                "  {:>4}  {:<11}  {:>6}  {:<24}  {:<22}  {:<22}  {:>7}",
                "#", "outcome", "weight", "perceived", "stated", "true reason", "trust"
            );
            starts = false;
        }
        let cause = |c: Option<trust::Cause>| c.map_or("-".to_owned(), |c| c.to_string());
        let _ = writeln!(
            text,
            "  {:>4}  {:<11}  {:>6.2}  {:<24}  {:<22}  {:<22}  {:>+7.2}",
            i + 1,
            kind_name(c.outcome.kind),
            c.outcome.weight,
            perceived(timeline, c),
            cause(c.outcome.stated),
            cause(c.truth),
            c.estimate
        );
        if let Some(explanation) = &c.explanation {
            let _ = writeln!(text, "  -> {}", explanation.sentence(space));
            starts = true;
        }
    }
    if r.truncated {
        text.push_str("\n(the trial was cut off at the experiment's max_commands)\n");
    }
    text
}

/// A short label of a switch for the figure: `collision -> case 3`, `deadline -> search`
/// (`undecided` when no reason stands out).
pub fn switch_label(explanation: &Explanation) -> String {
    let reason = explanation
        .given_up
        .as_ref()
        .and_then(|g| g.decided_reason())
        .map_or("undecided".to_owned(), |c| c.to_string());
    let next = match &explanation.next {
        Next::Switch {
            source: Source::Case { case, .. },
            ..
        } => format!("case {}", case.0),
        Next::Switch {
            source: Source::Search,
            ..
        } => "search".to_owned(),
        Next::Kept {
            trustworthy: false, ..
        } => "kept (all tried)".to_owned(),
        Next::Kept { .. } => "kept".to_owned(),
    };
    format!("{reason} -> {next}")
}

/// The timeline figure: the estimate after every command (each behavior's estimate starts
/// from zero), both thresholds, and every switch marked and numbered with a short label
/// (the page lists the full explanations under the figure).
pub fn timeline_figure(area: &Area<'_>, timeline: &Timeline) -> DrawResult {
    let n = timeline.commands.len().max(1) as f64;
    let t = timeline.thresholds;
    let (low, high) = timeline
        .commands
        .iter()
        .fold((t.untrustworthy, t.trustworthy), |(lo, hi), c| {
            (lo.min(c.estimate), hi.max(c.estimate))
        });
    let pad = (high - low) * 0.08;
    let switches: Vec<(usize, String)> = timeline
        .commands
        .iter()
        .enumerate()
        .filter_map(|(i, c)| c.explanation.as_ref().map(|e| (i + 1, switch_label(e))))
        .collect();
    let (width, height) = area.dim_in_pixel();
    let key_lines = switches.len() as u32;
    let (plot, key) = area.split_vertically(height.saturating_sub(22 * key_lines + 10));
    let mut chart = ChartBuilder::on(&plot)
        .caption(
            format!(
                "{}: the trust estimate over trial {} ({} arm)",
                timeline.experiment, timeline.record.trial, timeline.arm
            ),
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..n + 0.5, (low - pad)..(high + pad))?;
    chart
        .configure_mesh()
        .light_line_style(TRANSPARENT)
        .x_desc("command (in order)")
        .y_desc("trust estimate of the behavior in use")
        .draw()?;
    let threshold_style = RGBColor(90, 90, 90).stroke_width(1);
    for (value, name) in [
        (t.trustworthy, "trustworthy threshold"),
        (t.untrustworthy, "untrustworthy threshold"),
    ] {
        chart.draw_series(DashedLineSeries::new(
            [(0.0, value), (n + 0.5, value)],
            6,
            4,
            threshold_style,
        ))?;
        chart.draw_series(std::iter::once(Text::new(
            format!("{name} {value:+}"),
            (0.3, value + (high - low) * 0.025),
            ("sans-serif", 13).into_font(),
        )))?;
    }
    let color = arm_style(&timeline.arm, timeline.arm_index).color;
    // Each behavior's estimate, from zero at its first command.
    let mut segment: Vec<(f64, f64)> = vec![(0.0, 0.0)];
    for (i, c) in timeline.commands.iter().enumerate() {
        let x = (i + 1) as f64;
        segment.push((x, c.estimate));
        if c.explanation.is_some() || i + 1 == timeline.commands.len() {
            chart.draw_series(LineSeries::new(segment.clone(), color.stroke_width(2)))?;
            segment = vec![(x, 0.0)];
        }
    }
    // Completed commands as filled circles, untrustworthy ones as crosses.
    chart.draw_series(timeline.commands.iter().enumerate().map(|(i, c)| {
        let at = ((i + 1) as f64, c.estimate);
        if c.outcome.is_untrustworthy() {
            Cross::new(at, 4, RGBColor(180, 40, 40).stroke_width(2)).into_dyn()
        } else {
            Circle::new(at, 3, color.filled()).into_dyn()
        }
    }))?;
    for (k, (at, _)) in switches.iter().enumerate() {
        let x = *at as f64;
        chart.draw_series(LineSeries::new(
            [(x, low - pad), (x, high + pad)],
            RGBColor(150, 150, 150).stroke_width(1),
        ))?;
        chart.draw_series(std::iter::once(Text::new(
            format!("{}", k + 1),
            (x + 0.15, high + pad * 0.4),
            ("sans-serif", 14).into_font().style(FontStyle::Bold),
        )))?;
    }
    let line_width = width.saturating_sub(80);
    for (k, (at, label)) in switches.iter().enumerate() {
        let mut line = format!("{}: after command {at}, {label}", k + 1);
        while text_width(&line, 14) > line_width && line.len() > 4 {
            line.pop();
        }
        key.draw(&Text::new(
            line,
            (72, 22 * k as i32 + 4),
            ("sans-serif", 14).into_font(),
        ))?;
    }
    Ok(())
}
