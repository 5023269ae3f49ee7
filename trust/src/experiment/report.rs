//! The report of a set of experiments: the printed table, `table.md`, `summary.json`,
//! `trials.jsonl`, the config used, and SVG plots (learning curves and where the final
//! behaviors land in the behavior space). Every file is written atomically.

use super::runner::{ExperimentResult, Strategy, StrategyResult, TrialRecord};
use crate::named::named_behavior;
use cbr_core::{BehaviorSpace, FileError, write_atomically};
use plotters::prelude::*;
use serde::Serialize;
use serde_json::{Map, Value, json};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// One experiment's results with what the report needs to describe them.
pub struct ReportEntry<'a> {
    /// The results.
    pub result: &'a ExperimentResult,
    /// The scenario (domain) name, e.g. `movement`.
    pub scenario: &'a str,
    /// The configured operator: a name, or `random`.
    pub operator: &'a str,
    /// The behavior space, to show behaviors in real units.
    pub space: &'a BehaviorSpace,
}

/// Why the report could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// A file or folder could not be written.
    #[error(transparent)]
    Io(#[from] FileError),
    /// A plot could not be drawn.
    #[error("plot {path}: {message}")]
    Plot {
        /// The plot file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

/// Trials averaged by the moving average of the learning-curve plots.
const MOVING_AVERAGE_WINDOW: usize = 25;

/// The Markdown table of the experiments, as printed and as `table.md`.
pub fn table(entries: &[ReportEntry<'_>]) -> String {
    let mut out = String::new();
    out.push_str("| Scenario | Operator | Trials | Random walk: behaviors evaluated (mean ± 95% CI) | Case-based: behaviors evaluated (mean ± 95% CI) | Cases acquired | Paired t-test p |\n");
    out.push_str("|---|---|---:|---:|---:|---:|---:|\n");
    for e in entries {
        let [rw, cb] = &e.result.strategies;
        let _ = writeln!(
            out,
            "| {} | {} | {} | {:.2} ± {:.2} | {:.2} ± {:.2} | {} | {} |",
            e.scenario,
            e.operator,
            rw.trials.len(),
            rw.behaviors.mean,
            rw.behaviors.ci95,
            cb.behaviors.mean,
            cb.behaviors.ci95,
            cb.cases_acquired,
            format_p(e.result.p_value)
        );
    }
    out
}

fn format_p(p: f64) -> String {
    if p < 1e-4 {
        format!("{p:.1e}")
    } else {
        format!("{p:.4}")
    }
}

/// The `summary.json` document.
pub fn summary(entries: &[ReportEntry<'_>], elapsed_s: f64) -> Value {
    let experiments: Vec<Value> = entries
        .iter()
        .map(|e| {
            let mut strategies = Map::new();
            for s in &e.result.strategies {
                strategies.insert(s.strategy.name().to_owned(), strategy_summary(s));
            }
            json!({
                "name": e.result.name,
                "scenario": e.scenario,
                "operator": e.operator,
                "trials": e.result.strategies[0].trials.len(),
                "p_value": e.result.p_value,
                "strategies": strategies,
            })
        })
        .collect();
    json!({ "elapsed_s": elapsed_s, "experiments": experiments })
}

fn strategy_summary(s: &StrategyResult) -> Value {
    let n = s.trials.len().max(1) as f64;
    json!({
        "mean": s.behaviors.mean,
        "ci95": s.behaviors.ci95,
        "cases_acquired": s.cases_acquired,
        "found_trustworthy": s.trials.iter().filter(|t| t.report.found_trustworthy).count(),
        "truncated": s.trials.iter().filter(|t| t.truncated).count(),
        "mean_runs": s.trials.iter().map(|t| t.runs as f64).sum::<f64>() / n,
    })
}

#[derive(Serialize)]
struct TrialLine<'a> {
    experiment: &'a str,
    scenario: &'a str,
    operator: &'a str,
    strategy: &'static str,
    trial: u32,
    behaviors_evaluated: u64,
    runs: u64,
    found_trustworthy: bool,
    #[serde(rename = "final")]
    final_behavior: Map<String, Value>,
    initial: Map<String, Value>,
    searched: u32,
    reused: u32,
    retained: bool,
    truncated: bool,
}

/// `trials.jsonl`: one JSON object per trial, experiments in order, random walk first.
pub fn trials_jsonl(entries: &[ReportEntry<'_>]) -> String {
    let mut out = String::new();
    for e in entries {
        for s in &e.result.strategies {
            for t in &s.trials {
                let line = trial_line(e, t);
                out.push_str(&serde_json::to_string(&line).expect("plain data serializes"));
                out.push('\n');
            }
        }
    }
    out
}

fn trial_line<'a>(e: &'a ReportEntry<'_>, t: &'a TrialRecord) -> TrialLine<'a> {
    TrialLine {
        experiment: &e.result.name,
        scenario: e.scenario,
        operator: &t.operator,
        strategy: t.strategy.name(),
        trial: t.trial,
        behaviors_evaluated: t.report.behaviors_evaluated,
        runs: t.runs,
        found_trustworthy: t.report.found_trustworthy,
        final_behavior: named_behavior(e.space, &t.report.settled),
        initial: named_behavior(e.space, &t.initial),
        searched: t.report.searched,
        reused: t.report.reused,
        retained: t.report.retained.is_some(),
        truncated: t.truncated,
    }
}

/// Writes the whole report into `dir` (created if needed): `table.md`, `summary.json`,
/// `trials.jsonl`, `config.ron` (the text given) and the plots. Returns the files written.
pub fn write_report(
    dir: &Path,
    entries: &[ReportEntry<'_>],
    config_ron: &str,
    elapsed_s: f64,
) -> Result<Vec<PathBuf>, ReportError> {
    std::fs::create_dir_all(dir).map_err(|reason| FileError {
        path: dir.to_owned(),
        reason,
    })?;
    let mut written = Vec::new();
    let mut write = |name: &str, text: &str| -> Result<(), ReportError> {
        let path = dir.join(name);
        write_atomically(&path, text.as_bytes()).map_err(|reason| FileError {
            path: path.clone(),
            reason,
        })?;
        written.push(path);
        Ok(())
    };
    write("table.md", &table(entries))?;
    let summary =
        serde_json::to_string_pretty(&summary(entries, elapsed_s)).expect("plain data serializes");
    write("summary.json", &(summary + "\n"))?;
    write("trials.jsonl", &trials_jsonl(entries))?;
    write("config.ron", config_ron)?;
    for e in entries {
        let stem = e.result.name.replace('/', "-");
        let name = format!("curves-{stem}.svg");
        write(
            &name,
            &plot(&dir.join(&name), |area| learning_curves(area, e))?,
        )?;
        // One heatmap per pair of components: the first two, then the next two, ...
        let components = e.space.components();
        for first in (0..components.len()).step_by(2) {
            let second = (first + 1).min(components.len() - 1);
            let name = if first == 0 {
                format!("finals-{stem}.svg")
            } else {
                format!(
                    "finals-{stem}-{}-{}.svg",
                    components[first].name, components[second].name
                )
            };
            let svg = plot(&dir.join(&name), |area| {
                final_behaviors(area, e, (first, second))
            })?;
            write(&name, &svg)?;
        }
    }
    Ok(written)
}

type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;
type DrawResult = Result<(), Box<dyn std::error::Error + 'static>>;

fn plot(path: &Path, draw: impl FnOnce(&Area<'_>) -> DrawResult) -> Result<String, ReportError> {
    let mut svg = String::new();
    {
        let area = SVGBackend::with_string(&mut svg, (1000, 520)).into_drawing_area();
        let drawn = area
            .fill(&WHITE)
            .map_err(|e| e.into())
            .and_then(|()| draw(&area))
            .and_then(|()| area.present().map_err(|e| e.into()));
        drawn.map_err(|e| ReportError::Plot {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
    }
    Ok(svg)
}

fn strategy_color(strategy: Strategy) -> RGBColor {
    match strategy {
        Strategy::RandomWalk => RGBColor(214, 96, 77),
        Strategy::CaseBased => RGBColor(67, 147, 195),
    }
}

fn moving_average(values: &[f64], window: usize) -> Vec<f64> {
    let mut out = Vec::with_capacity(values.len());
    let mut sum = 0.0;
    for (i, v) in values.iter().enumerate() {
        sum += v;
        if i >= window {
            sum -= values[i - window];
        }
        out.push(sum / (i + 1).min(window) as f64);
    }
    out
}

fn learning_curves(area: &Area<'_>, e: &ReportEntry<'_>) -> DrawResult {
    let trials = e.result.strategies[0].trials.len().max(1) as u32;
    let top = e
        .result
        .strategies
        .iter()
        .flat_map(|s| s.trials.iter().map(|t| t.report.behaviors_evaluated))
        .max()
        .unwrap_or(1)
        .max(2) as f64;
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!("{}: behaviors evaluated per trial", e.result.name),
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0u32..trials, (0.8f64..top * 1.2).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("trial")
        .y_desc("behaviors evaluated (log scale)")
        .draw()?;
    for s in &e.result.strategies {
        let color = strategy_color(s.strategy);
        let counts = s.counts();
        chart.draw_series(
            counts
                .iter()
                .enumerate()
                .map(|(i, &c)| Circle::new((i as u32, c), 2, color.mix(0.35).filled())),
        )?;
        chart
            .draw_series(LineSeries::new(
                moving_average(&counts, MOVING_AVERAGE_WINDOW)
                    .into_iter()
                    .enumerate()
                    .map(|(i, m)| (i as u32, m)),
                color.stroke_width(3),
            ))?
            .label(format!(
                "{} (moving average of {MOVING_AVERAGE_WINDOW})",
                s.strategy.name()
            ))
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(3))
            });
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()?;
    Ok(())
}

/// Heatmaps of where each strategy's final behaviors land, over components `x` and `y`.
fn final_behaviors(area: &Area<'_>, e: &ReportEntry<'_>, (x, y): (usize, usize)) -> DrawResult {
    let components = e.space.components();
    let (nx, ny) = (components[x].len(), components[y].len());
    let panels = area.split_evenly((1, 2));
    for (panel, s) in panels.iter().zip(&e.result.strategies) {
        let mut counts = vec![0u32; nx * ny];
        for t in &s.trials {
            let b = t.report.settled;
            counts[usize::from(b.get(x)) * ny + usize::from(b.get(y))] += 1;
        }
        let most = counts.iter().copied().max().unwrap_or(0).max(1);
        let mut chart = ChartBuilder::on(panel)
            .caption(
                format!(
                    "{}: final behaviors, {} (darker: more trials)",
                    e.result.name,
                    s.strategy.name()
                ),
                ("sans-serif", 15),
            )
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(-0.5..nx as f64 - 0.5, -0.5..ny as f64 - 0.5)?;
        // Cells are centred on their index; label each index with its real value.
        let label = |component: usize, n: usize| {
            move |v: &f64| {
                let i = v.round();
                if (v - i).abs() < 1e-6 && i >= 0.0 && (i as usize) < n {
                    components[component].display_value(i as u16).to_string()
                } else {
                    String::new()
                }
            }
        };
        let (x_label, y_label) = (label(x, nx), label(y, ny));
        chart
            .configure_mesh()
            .disable_mesh()
            .x_labels(nx.min(20))
            .y_labels(ny.min(20))
            .x_desc(components[x].name.as_str())
            .y_desc(components[y].name.as_str())
            .x_label_formatter(&x_label)
            .y_label_formatter(&y_label)
            .draw()?;
        let color = strategy_color(s.strategy);
        chart.draw_series(
            (0..nx)
                .flat_map(|i| (0..ny).map(move |j| (i, j)))
                .filter(|&(i, j)| counts[i * ny + j] > 0)
                .map(|(i, j)| {
                    let share = f64::from(counts[i * ny + j]) / f64::from(most);
                    let (cx, cy) = (i as f64, j as f64);
                    Rectangle::new(
                        [(cx - 0.5, cy - 0.5), (cx + 0.5, cy + 0.5)],
                        color.mix(0.15 + 0.85 * share).filled(),
                    )
                }),
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moving_average_by_hand() {
        // Window 2 over 1, 3, 5, 7: 1, (1+3)/2, (3+5)/2, (5+7)/2.
        assert_eq!(
            moving_average(&[1.0, 3.0, 5.0, 7.0], 2),
            vec![1.0, 2.0, 4.0, 6.0]
        );
    }

    #[test]
    fn p_values_are_readable() {
        assert_eq!(format_p(0.01234), "0.0123");
        assert_eq!(format_p(3.0e-9), "3.0e-9");
    }
}
