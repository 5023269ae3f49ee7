//! The story of one trial: every command, the trust estimate after it, and the explanation
//! of every switch, as text (`trustcbr explain`) and as a figure (the report's timeline of
//! a sample trial per experiment, the paper's central idea drawn: an estimate that climbs
//! and falls between two thresholds).

use crate::experiment::arm_name::ArmName;
use crate::experiment::record::{ExperimentResult, TracedCommand, TrialRecord};
use crate::report::plot::{Area, DrawResult, arm_style, text_width};
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
    pub arm: ArmName,
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
/// [`sample_arm`](crate::experiment::record::sample_arm)
/// traced as they ran ([`ArmResult::traced`](crate::experiment::record::ArmResult::traced), the
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

/// The columns of the story's table of commands: each header, and whether its cells are
/// right-aligned (numbers) or left-aligned (names).
const COLUMNS: [(&str, Align); 7] = [
    ("#", Align::Right),
    ("outcome", Align::Left),
    ("weight", Align::Right),
    ("perceived", Align::Left),
    ("stated", Align::Left),
    ("true reason", Align::Left),
    ("trust", Align::Right),
];

/// Where a cell's text stands in its column.
#[derive(Clone, Copy)]
enum Align {
    Left,
    Right,
}

/// The cells of command number `number` (from 1), one per column of [`COLUMNS`].
fn command_cells(number: usize, timeline: &Timeline, c: &TracedCommand) -> [String; 7] {
    let cause = |c: Option<trust::Cause>| c.map_or("-".to_owned(), |c| c.to_string());
    [
        number.to_string(),
        OutcomeKind::name(c.outcome.kind).to_owned(),
        format!("{:.2}", c.outcome.weight),
        perceived(timeline, c),
        if c.outcome.goal_change {
            "goal change".to_owned()
        } else {
            cause(c.outcome.stated)
        },
        cause(c.truth),
        format!("{:+.2}", c.estimate),
    ]
}

/// One line of the table: the cells padded to `widths`, two spaces apart, indented by two.
fn table_line<S: AsRef<str>>(cells: &[S], widths: &[usize; 7]) -> String {
    let padded: Vec<String> = cells
        .iter()
        .zip(widths)
        .zip(COLUMNS)
        .map(|((cell, &width), (_, align))| match align {
            Align::Left => format!("{:<width$}", cell.as_ref()),
            Align::Right => format!("{:>width$}", cell.as_ref()),
        })
        .collect();
    format!("  {}", padded.join("  ")).trim_end().to_owned()
}

/// The trial as text: each behavior, its commands (how each ended, its weight, what the
/// robot perceived, what the operator stated, the true reason, the estimate after it), and
/// the explanation of each switch and of the end. Every behavior's table has the same
/// columns, each as wide as its widest cell in the whole trial (a long list of what was
/// perceived widens its column, and the others stay in line).
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
    if !r.context.is_default() {
        let _ = write!(text, "in context {}", r.context);
        if r.report.context != r.context {
            let _ = write!(
                text,
                " (the arm was told {}: it is blind to it)",
                r.report.context
            );
        }
        text.push('\n');
    }
    if !r.stated.is_empty() {
        let said: Vec<String> = r.stated.iter().map(ToString::to_string).collect();
        let _ = writeln!(text, "the operator stated up front: {}", said.join(", "));
    }
    let rows: Vec<[String; 7]> = timeline
        .commands
        .iter()
        .enumerate()
        .map(|(i, c)| command_cells(i + 1, timeline, c))
        .collect();
    let mut widths = COLUMNS.map(|(header, _)| header.chars().count());
    for row in &rows {
        for (width, cell) in widths.iter_mut().zip(row) {
            *width = (*width).max(cell.chars().count());
        }
    }
    let header = table_line(&COLUMNS.map(|(header, _)| header), &widths);
    let mut behavior_number = 0;
    let mut starts = true;
    for (c, row) in timeline.commands.iter().zip(&rows) {
        if starts {
            behavior_number += 1;
            let _ = writeln!(
                text,
                "\nbehavior {behavior_number}: {}",
                space.display(&c.behavior)
            );
            let _ = writeln!(text, "{header}");
            starts = false;
        }
        let _ = writeln!(text, "{}", table_line(row, &widths));
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
    let color = arm_style(&timeline.arm).color;
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

#[cfg(test)]
mod tests {
    use super::*;
    use cbr_core::{Behavior, NamedComponent};
    use trust::{Cause, EpisodeReport, Grounds, Observations, Outcome};

    /// Two behaviors: the first given up after one interruption on which the robot
    /// perceived all five of its observations, the second kept after one completion.
    fn timeline() -> (Timeline, BehaviorSpace) {
        let space = BehaviorSpace::new(vec![
            NamedComponent::categorical("gripper", &["suction", "fingers"]).unwrap(),
        ])
        .unwrap();
        let (suction, fingers) = (Behavior::new(&[0]), Behavior::new(&[1]));
        let everything = (0..5).fold(Observations::NONE, Observations::with);
        let commands = vec![
            TracedCommand {
                behavior: suction,
                outcome: Outcome::interrupted(1.0, 10.0).observing(everything),
                truth: Some(Cause::from_static("collision")),
                estimate: -1.0,
                explanation: Some(Explanation {
                    given_up: None,
                    next: Next::Switch {
                        behavior: fingers,
                        source: Source::Search,
                        grounds: Grounds::Matches {
                            matched: 0,
                            given_up: 0,
                        },
                    },
                }),
            },
            TracedCommand {
                behavior: fingers,
                outcome: Outcome::completed(0.5, 8.0),
                truth: None,
                estimate: 0.5,
                explanation: Some(Explanation {
                    given_up: None,
                    next: Next::Kept {
                        behavior: fingers,
                        trustworthy: true,
                        commands: 1,
                        estimate: 0.5,
                    },
                }),
            },
        ];
        let record = TrialRecord {
            trial: 3,
            arm: "random-walk".into(),
            operator: "balanced".into(),
            initial: suction,
            learned_start: false,
            report: EpisodeReport {
                settled: fingers,
                found_trustworthy: true,
                behaviors_evaluated: 2,
                commands: 2,
                untrustworthy: 1,
                searched: 1,
                reused: 0,
                settled_from_search: true,
                retained: None,
                evaluated: Vec::new(),
                context: cbr_core::Context::default(),
                explanations: Vec::new(),
            },
            truncated: false,
            true_causes: Default::default(),
            explained: Default::default(),
            given_up: Vec::new(),
            goal_changes: None,
            context: cbr_core::Context::default(),
            stated: Vec::new(),
        };
        let observations = [
            "collision",
            "stuck",
            "behind-plan",
            "near-person-fast",
            "close-pass",
        ]
        .map(Cause::from_static)
        .to_vec();
        let timeline = Timeline {
            experiment: "picking".into(),
            arm: "random-walk".parse().unwrap(),
            record,
            commands,
            thresholds: Thresholds {
                trustworthy: 0.5,
                untrustworthy: -1.0,
            },
            observations,
        };
        (timeline, space)
    }

    #[test]
    fn a_long_list_of_what_was_perceived_widens_its_column_and_the_others_stay_in_line() {
        let (timeline, space) = timeline();
        // The perceived column is as wide as its widest cell, 55 characters
        // (9 + 5 + 11 + 16 + 10 for the names, 4 commas); every other column as wide as its
        // header or its widest cell: `#` 1, outcome 11 (`interrupted`), weight 6, stated 6,
        // true reason 11, trust 5; two spaces between columns, two before the first.
        let header = format!(
            "  #  outcome      weight  perceived{}  stated  true reason  trust",
            " ".repeat(55 - 9)
        );
        let expected = [
            "picking, arm random-walk, trial 3 (operator balanced): 2 commands, 1 untrustworthy, 2 behaviors; thresholds +0.5 / -1".to_owned(),
            String::new(),
            "behavior 1: gripper=suction".to_owned(),
            header.clone(),
            "  1  interrupted    1.00  collision,stuck,behind-plan,near-person-fast,close-pass  -       collision    -1.00".to_owned(),
            "  -> Now gripper=fingers: search.".to_owned(),
            String::new(),
            "behavior 2: gripper=fingers".to_owned(),
            header,
            format!("  2  completed      0.50  -{}-       -            +0.50", " ".repeat(54 + 2)),
            "  -> Keeping gripper=fingers: trusted after 1 command (estimate +0.50).".to_owned(),
        ];
        let told = story(&timeline, &space);
        assert_eq!(told.lines().collect::<Vec<_>>(), expected, "{told}");
        // Every line of a table has its trust right-aligned at the same column.
        let table: Vec<&str> = told
            .lines()
            .filter(|l| l.starts_with("  ") && !l.starts_with("  ->"))
            .collect();
        assert_eq!(table.len(), 4);
        assert!(table.iter().all(|l| l.len() == table[0].len()), "{told}");
    }
}
