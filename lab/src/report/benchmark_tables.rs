//! A benchmark suite's tables (Markdown, in `table.md` and as HTML on the page): per
//! scenario, every arm's geometric mean ratios to the populations' known-operator limits
//! with their wins, ties and losses ([`benchmark_table`]), and the split of each arm's
//! excess into what telling members apart costs and what learning costs
//! ([`benchmark_split_table`]).

use crate::population::benchmark::{LimitRatio, ScenarioBenchmark, WinsTiesLosses};
use std::fmt::Write as _;

/// A geometric mean ratio to the limit with its interval, `1.59 [1.13, 2.25]`, and the
/// populations it is over when some had no usable ratio; `—` when none had.
fn limit_ratio_cell(ratio: Option<LimitRatio>, populations: usize) -> String {
    let Some(LimitRatio {
        ratio,
        populations: counted,
    }) = ratio
    else {
        return "—".to_owned();
    };
    let cell = format!("{:.2} [{:.2}, {:.2}]", ratio.ratio, ratio.low, ratio.high);
    if counted < populations {
        format!("{cell} ({counted} of {populations} populations)")
    } else {
        cell
    }
}

/// Wins, ties and losses as `3/1/0`; `—` for a reference against itself.
fn wins_ties_losses_cell(tally: Option<WinsTiesLosses>) -> String {
    tally.map_or("—".to_owned(), |t| {
        format!("{}/{}/{}", t.wins, t.ties, t.losses)
    })
}

/// A scenario's benchmark ([`crate::population::benchmark`]), one row per arm: its geometric mean
/// ratios to the limit over the populations with their bootstrap intervals, its wins,
/// ties and losses against each reference arm that ran, and its untrustworthy commands'
/// ratio to the limit over the windows of trials.
pub fn benchmark_table(benchmark: &ScenarioBenchmark) -> String {
    let mut out = String::from(
        "| Arm | Behaviors × limit [95% CI] | Commands × limit [95% CI] | Untrustworthy × limit [95% CI] |",
    );
    for reference in &benchmark.references {
        let _ = write!(out, " W/T/L vs {reference} |");
    }
    for window in &benchmark.windows {
        let _ = write!(
            out,
            " Untrustworthy × limit, trials {}–{} |",
            window.first, window.last
        );
    }
    out.push_str("\n|---|");
    out.push_str(&"---:|".repeat(3 + benchmark.references.len() + benchmark.windows.len()));
    out.push('\n');
    let populations = benchmark.populations.len();
    for arm in &benchmark.arms {
        let _ = write!(out, "| {} |", arm.arm);
        for ratio in arm.to_limit {
            let _ = write!(out, " {} |", limit_ratio_cell(ratio, populations));
        }
        for tally in &arm.versus {
            let _ = write!(out, " {} |", wins_ties_losses_cell(*tally));
        }
        untrustworthy_window_cells(&mut out, &arm.windows);
    }
    if benchmark.arms.len() > 1 {
        let best = &benchmark.best_of_each_population;
        let _ = write!(out, "| {BEST_OF_EACH_POPULATION} |");
        for ratio in best.to_limit {
            let _ = write!(out, " {} |", optional_ratio_cell(ratio));
        }
        out.push_str(&" — |".repeat(benchmark.references.len()));
        untrustworthy_window_cells(&mut out, &best.windows);
    }
    out
}

/// A row's last cells: the untrustworthy commands' ratio over each window of trials
/// (per window, per [`crate::population::benchmark::Metric::ALL`]), then the row's end.
fn untrustworthy_window_cells(out: &mut String, windows: &[[Option<f64>; 3]]) {
    for [_, _, untrustworthy] in windows {
        let _ = write!(out, " {} |", optional_ratio_cell(*untrustworthy));
    }
    out.push('\n');
}

/// A ratio to two decimals, `—` when there is none.
fn optional_ratio_cell(ratio: Option<f64>) -> String {
    ratio.map_or("—".to_owned(), ratio_cell)
}

/// The label of the benchmark table's last row.
const BEST_OF_EACH_POPULATION: &str = "best arm of each population, after the fact (not an arm)";

/// A scenario's excess over the limit split in two, when its populations have a population
/// reference: the reference's geometric mean ratio to the limit (what telling members
/// apart costs), then each arm's to the reference (what learning costs), with bootstrap
/// intervals over the populations that have one. Empty when none has.
pub fn benchmark_split_table(benchmark: &ScenarioBenchmark) -> String {
    if benchmark
        .population_reference_to_limit
        .iter()
        .all(Option::is_none)
    {
        return String::new();
    }
    let populations = benchmark.populations.len();
    let mut out = String::from(
        "| Arm or reference | Behaviors × [95% CI] | Commands × [95% CI] | Untrustworthy × [95% CI] |\n|---|---:|---:|---:|\n",
    );
    let mut row = |label: &str, ratios: &[Option<LimitRatio>; 3]| {
        let _ = write!(out, "| {label} |");
        for ratio in ratios {
            let _ = write!(out, " {} |", limit_ratio_cell(*ratio, populations));
        }
        out.push('\n');
    };
    row(
        "population reference (× limit: telling members apart)",
        &benchmark.population_reference_to_limit,
    );
    for arm in &benchmark.arms {
        row(
            &format!("{} (× population reference: learning)", arm.arm),
            &arm.to_population_reference,
        );
    }
    out
}

/// What the split of the excess over the limit is, in one paragraph (Markdown and the page).
pub(super) const SPLIT_NOTE: &str = "An arm's ratio to the limit is the population reference's ratio to the limit (an agent that knows every operator of the population and how often each appears, but not which it faces, updates its posterior after every command and re-plans after every rejection: what telling operators apart costs) times the arm's ratio to the population reference (what learning costs). Geometric means over the populations with a reference, with 95% percentile bootstrap intervals over populations; the reference is simulated, its mean and standard error in the limit table (docs/search-strategies.md explains it).";

/// The title of a scenario's benchmark table.
pub(super) fn benchmark_title(benchmark: &ScenarioBenchmark) -> String {
    format!(
        "{}: {} populations",
        benchmark.scenario,
        benchmark.populations.len()
    )
}

/// The title of the benchmark's section.
pub(super) const BENCHMARK_TITLE: &str = "Benchmark: every arm over the populations of each scenario, against their known-operator limits";

/// What the benchmark's numbers are, in one paragraph (Markdown and the page).
pub(super) const BENCHMARK_NOTE: &str = "Each ratio is an arm's mean per trial on a population divided by that population's known-operator limit (a random first behavior); the table gives their geometric mean over the populations with a 95% percentile bootstrap interval over populations. W/T/L counts the populations where the arm's untrustworthy commands were significantly fewer, not significantly different, or significantly more than the reference arm's (Wilcoxon signed-rank test, trial by trial, p < 0.05). The last row takes on each population the lowest ratio of any arm, picked after seeing the trials, and gives the geometric mean of those minima: how far each arm is from everything the suite ran. It is not an arm (no rule fixed in advance picks a different arm on each population, and the least of many noisy means flatters itself), so it has no interval and no test.";

/// What the benchmark's section says when no population experiment had a limit.
pub(super) const NO_BENCHMARK: &str =
    "No population experiment has a known-operator limit to measure against.";

/// The benchmark's section of `table.md`: the note, then a table per scenario; a sentence
/// when no population had a limit.
pub(super) fn benchmark_section(benchmarks: &[ScenarioBenchmark]) -> String {
    let mut out = format!("\n## {BENCHMARK_TITLE}\n\n{BENCHMARK_NOTE}\n");
    if benchmarks.is_empty() {
        let _ = writeln!(out, "\n{NO_BENCHMARK}");
    }
    for benchmark in benchmarks {
        let _ = write!(
            out,
            "\n### {}\n\n{}",
            benchmark_title(benchmark),
            benchmark_table(benchmark)
        );
        let split = benchmark_split_table(benchmark);
        if !split.is_empty() {
            let _ = write!(out, "\n{SPLIT_NOTE}\n\n{split}");
        }
    }
    out
}

/// A ratio to the limit, `—` when the limit is 0 (nothing to divide by).
pub(super) fn ratio_cell(ratio: f64) -> String {
    if ratio.is_finite() {
        format!("{ratio:.2}")
    } else {
        "—".to_owned()
    }
}
