//! The report's SVG figures: every experiment and arm at once (`every_arm`), per-trial
//! lines over the trials of every experiment (`over_trials`), the learning curves of an
//! experiment (`curves`), where its final behaviors land (`finals`) and a benchmark
//! scenario's untrustworthy commands to settle (`ecdf`); what they share
//! (the legend, moving averages, thinning a long curve); and [`write_figures`], which draws
//! them all, writes each as a file and hands the page the same text with a caption.

mod curves;
mod ecdf;
mod every_arm;
mod finals;
mod legend;
mod over_trials;
mod series;

pub use finals::{FINALS_LANDSCAPE_RUNS, component_pairs, finals_landscapes};

use super::effects::BOOTSTRAP_RESAMPLES;
use super::page::{Figure, escape};
use crate::population::benchmark::ScenarioBenchmark;
use crate::report::entry::{ReportEntry, ReportError};
use crate::report::plot::{PlotError, svg, svg_with};
use crate::report::timeline::{Timeline, timeline_figure};
use crate::stats::RatioCi;
use cbr_core::BehaviorSpace;
use curves::learning_curves;
use ecdf::ecdf_figure;
use every_arm::{SUMMARY_METRICS, effects_figure, every_arm_figure, summary_figure};
use files::name::file_stems;
use finals::{FinalsLayout, final_behaviors, finals_caption, finals_subtitle};
use over_trials::{over_trials_figures, small_multiples};
use series::MOVING_AVERAGE_WINDOW;
use std::fmt::Write as _;
use std::path::Path;

/// Draws every figure of the report from `entries`, their `effects` and the `benchmark` of
/// a benchmark suite, writes each as its own SVG file in `dir` through `write`, and returns
/// them for the page, in the page's order.
pub(super) fn write_figures(
    dir: &Path,
    entries: &[ReportEntry<'_>],
    effects: &[Vec<Option<RatioCi>>],
    benchmark: Option<&[ScenarioBenchmark]>,
    write: &mut impl FnMut(&str, &str) -> Result<(), ReportError>,
) -> Result<Vec<Figure>, ReportError> {
    // Every figure is written as its own SVG file and the same text goes into the page.
    let mut figures: Vec<Figure> = Vec::new();
    every_arm_figures(dir, entries, effects, write, &mut figures)?;
    for (e, stem) in entries
        .iter()
        .zip(file_stems(entries.iter().map(|e| &e.result.name)))
    {
        experiment_figures(dir, e, &stem, write, &mut figures)?;
        finals_figures(dir, e, &stem, write, &mut figures)?;
    }
    benchmark_figures(dir, benchmark.unwrap_or_default(), write, &mut figures)?;
    Ok(figures)
}

/// The figures of every experiment and arm at once: one per summary metric, the effect
/// sizes, and the per-trial lines over trials that have a line to draw.
fn every_arm_figures(
    dir: &Path,
    entries: &[ReportEntry<'_>],
    effects: &[Vec<Option<RatioCi>>],
    write: &mut impl FnMut(&str, &str) -> Result<(), ReportError>,
    figures: &mut Vec<Figure>,
) -> Result<(), ReportError> {
    for metric in SUMMARY_METRICS {
        let name = format!("{}.svg", metric.stem);
        let summary_svg = svg_with(&dir.join(&name), (1200, 560), |area, overlay| {
            every_arm_figure(area, overlay, entries, &summary_figure(entries, metric))
        })?;
        write(&name, &summary_svg)?;
        figures.push(Figure::new(
            "Every experiment and arm",
            summary_svg,
            format!(
                "{}: the mean per trial of each arm (its marker, offset within its \
                 experiment; key at the right) with its 95% confidence interval (the vertical \
                 line), one column per experiment, on a log axis (lower is better). The black \
                 bar is the known-operator limit: an agent that knows the operator's outcome \
                 distribution of every behavior, starting from a random behavior as the arms do.",
                metric.what
            ),
        ));
    }
    let reference = entries.first().map_or("", |e| e.reference);
    let name = "effect-sizes.svg";
    let drawn = svg_with(&dir.join(name), (1200, 560), |area, overlay| {
        every_arm_figure(area, overlay, entries, &effects_figure(entries, effects))
    })?;
    write(name, &drawn)?;
    figures.push(Figure::new(
        "Every experiment and arm",
        drawn,
        format!(
            "Effect sizes: each arm's mean behaviors evaluated per trial divided by the \
             reference arm's ({}; the black bar at 1), with the 95% interval of a paired \
             bootstrap ({BOOTSTRAP_RESAMPLES} resamples of the trials, the same trials for both \
             arms), on a log axis. Below 1 the arm needs fewer behaviors than the reference; \
             an interval that crosses 1 is no evidence of a difference.",
            escape(reference)
        ),
    ));
    // A figure with no line at all (no arm reuses cases) is left out.
    for (name, panels, caption) in over_trials_figures(entries) {
        if panels.series.iter().flatten().all(Option::is_none) {
            continue;
        }
        let drawn = svg_with(&dir.join(name), panels.size(), |area, overlay| {
            small_multiples(area, overlay, entries, &panels)
        })?;
        write(name, &drawn)?;
        figures.push(Figure::new(
            "Every experiment and arm",
            drawn,
            caption.to_owned(),
        ));
    }
    Ok(())
}

/// One experiment's learning curves and, when a trial was traced, its timeline.
fn experiment_figures(
    dir: &Path,
    e: &ReportEntry<'_>,
    stem: &str,
    write: &mut impl FnMut(&str, &str) -> Result<(), ReportError>,
    figures: &mut Vec<Figure>,
) -> Result<(), ReportError> {
    let name = format!("curves-{stem}.svg");
    let curves = |dots: bool| {
        svg_with(&dir.join(&name), (1250, 520), |area, overlay| {
            learning_curves(area, overlay, e, dots)
        })
    };
    write(&name, &curves(true)?)?;
    figures.push(Figure::new(
        &e.result.name,
        curves(false)?,
        format!(
            "Behaviors evaluated in each trial, trials in order: the moving average over \
             {MOVING_AVERAGE_WINDOW} trials (the line, with the arm's marker at eight places) \
             and its 95% band, on a log axis (lower is better). An arm that learns across \
             trials (a growing case base, a searcher's memory) falls as trials go on; one \
             that does not stays level. Each trial's count is a dot in \
             <code>{name}</code> and a line of <code>trials.jsonl</code>."
        ),
    ));
    if let Some(timeline) = e.timeline {
        let name = format!("timeline-{stem}.svg");
        let switches = timeline
            .commands
            .iter()
            .filter(|c| c.explanation.is_some())
            .count() as u32;
        let drawn = svg(&dir.join(&name), (1250, 480 + 22 * switches), |area| {
            timeline_figure(area, timeline)
        })?;
        write(&name, &drawn)?;
        figures.push(Figure::new(
            &e.result.name,
            drawn,
            timeline_caption(timeline, e.space),
        ));
    }
    Ok(())
}

/// Where one experiment's final behaviors land, one figure per pair of components, over
/// the operator's landscape when it was computed.
fn finals_figures(
    dir: &Path,
    e: &ReportEntry<'_>,
    stem: &str,
    write: &mut impl FnMut(&str, &str) -> Result<(), ReportError>,
    figures: &mut Vec<Figure>,
) -> Result<(), ReportError> {
    // One figure per pair of components: the first two, then the next two, ...
    let components = e.space.components();
    for (k, (x, y)) in component_pairs(e.space).into_iter().enumerate() {
        let name = if k == 0 {
            format!("finals-{stem}.svg")
        } else {
            format!(
                "finals-{stem}-{}-{}.svg",
                components[x].name, components[y].name
            )
        };
        // The id of the heatmap every arm's panel shares, unique in the page.
        let id = format!("cells-{}", name.trim_end_matches(".svg"));
        let grid = e
            .landscapes
            .iter()
            .find(|l| l.fixed == [x, y])
            .map(|l| l.grid(e.space, x, y))
            .transpose()
            .map_err(|reason| PlotError {
                path: dir.join(&name),
                message: reason.to_string(),
            })?;
        let layout = FinalsLayout::new(e.result.arms.len(), &finals_subtitle(e, grid.as_ref()));
        let finals = svg_with(&dir.join(&name), layout.size(), |area, overlay| {
            final_behaviors(area, overlay, e, (x, y), grid.as_ref(), &layout, &id)
        })?;
        write(&name, &finals)?;
        figures.push(Figure::new(
            &e.result.name,
            finals,
            finals_caption(e, (x, y), grid.as_ref()),
        ));
    }
    Ok(())
}

/// A benchmark suite's figure per scenario: untrustworthy commands to settle.
fn benchmark_figures(
    dir: &Path,
    benchmarks: &[ScenarioBenchmark],
    write: &mut impl FnMut(&str, &str) -> Result<(), ReportError>,
    figures: &mut Vec<Figure>,
) -> Result<(), ReportError> {
    for (b, stem) in benchmarks
        .iter()
        .zip(file_stems(benchmarks.iter().map(|b| &b.scenario)))
    {
        let name = format!("benchmark-{stem}-ecdf.svg");
        let drawn = svg_with(&dir.join(&name), (1200, 560), |area, overlay| {
            ecdf_figure(area, overlay, b)
        })?;
        write(&name, &drawn)?;
        figures.push(Figure::new(
            &format!("Benchmark: {}", b.scenario),
            drawn,
            format!(
                "Untrustworthy commands to settle: for each arm, the share of its (population, \
                 trial) pairs over the scenario's {} populations that ended on a trustworthy \
                 behavior within N untrustworthy commands, as N grows (higher and further left \
                 is better; a pair that never settled is never counted). The dashed curve is \
                 the known-operator limit: the probability that an agent that knows each \
                 operator, under the paper's protocol (a random first behavior, then the best \
                 order of the rest), settles within N, pooled over the populations as the \
                 pairs are.",
                b.populations.len()
            ),
        ));
    }
    Ok(())
}

/// The caption of a timeline: how to read it, and every explanation of the trial in full.
fn timeline_caption(timeline: &Timeline, space: &BehaviorSpace) -> String {
    let mut caption = format!(
        "The trust estimate of the behavior in use after every command of trial {} of the {} arm \
         (operator {}): completions (dots) raise it, failures and interruptions (crosses) lower \
         it; a behavior is given up when its estimate reaches the untrustworthy threshold and \
         kept when it reaches the trustworthy one. The numbered lines are the adapter's decisions, \
         explained as it explained them (only from what it was told and perceived):<ol>",
        timeline.record.trial,
        escape(timeline.arm.as_str()),
        escape(&timeline.record.operator)
    );
    for c in &timeline.commands {
        if let Some(x) = &c.explanation {
            let _ = write!(caption, "<li>{}</li>", escape(&x.sentence(space)));
        }
    }
    caption.push_str("</ol>");
    caption
}
