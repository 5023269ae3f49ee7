//! A suite's report: its results and estimates as the report's entries (and, for a
//! benchmark suite, its benchmark), the printed tables, and the report folder, made to
//! rerun by itself (operator files copied in: `portable`).

use super::portable::{OperatorCopy, copy_operator_files, relocate_operator_files};
use super::{ReportEstimates, SuiteConfig, SuiteError, SuiteResults};
use lab::population::benchmark::{BenchmarkPopulation, ScenarioBenchmark, benchmarks};
use lab::reference::known_operator::ExperimentLimit;
use lab::reference::landscape::Landscape;
use lab::report::{Provenance, ReportEntry, write_report};
use std::path::{Path, PathBuf};

/// The report entries of a suite's results, with the landscapes of each experiment when
/// given.
fn entries<'a>(
    config: &'a SuiteConfig,
    results: &'a SuiteResults,
    landscapes: &'a [Vec<Landscape>],
    limits: &'a [Option<ExperimentLimit>],
) -> Vec<ReportEntry<'a>> {
    config
        .experiments
        .iter()
        .zip(&results.results)
        .zip(&results.spaces)
        .enumerate()
        .map(|(k, ((spec, result), space))| ReportEntry {
            timeline: results.timelines.get(k).and_then(Option::as_ref),
            landscapes: landscapes.get(k).map_or(&[], Vec::as_slice),
            limit: limits.get(k).and_then(Option::as_ref),
            result,
            scenario: &spec.scenario,
            operator: spec
                .population
                .as_ref()
                .map_or(&spec.operator, |population| &population.name),
            space,
            reference: config.reference(),
            seed: config.seed,
        })
        .collect()
}

/// The report entries of a suite's results with its report's estimates: what the report's
/// tables, `summary.json` and `trials.jsonl` are made from.
pub fn report_entries<'a>(
    config: &'a SuiteConfig,
    results: &'a SuiteResults,
    estimates: &'a ReportEstimates,
) -> Vec<ReportEntry<'a>> {
    entries(config, results, &estimates.landscapes, &estimates.limits)
}

/// The benchmark of a benchmark suite (`benchmark: true`) from its report `entries`: every
/// population experiment with a known-operator limit, by scenario; `None` for any other
/// suite.
pub fn report_benchmark(
    config: &SuiteConfig,
    entries: &[ReportEntry<'_>],
) -> Option<Vec<ScenarioBenchmark>> {
    config.benchmark.then(|| {
        let populations: Vec<BenchmarkPopulation<'_>> = config
            .experiments
            .iter()
            .zip(entries)
            .filter(|(spec, _)| spec.population.is_some())
            .filter_map(|(_, e)| {
                e.limit.map(|limit| BenchmarkPopulation {
                    scenario: e.scenario,
                    result: e.result,
                    limit: limit.limit.paper,
                    limit_law: &limit.law,
                    population_reference: limit.population_reference.map(|r| r.paper),
                })
            })
            .collect();
        benchmarks(&populations, config.seed)
    })
}

/// The paper's Table 1 in Markdown (the first two arms of every experiment), under a line
/// saying what its numbers are ([`PAPER_TABLE_HEADING`]), as `reproduce` and `run` print
/// it and Python's `Results.paper_table` holds it.
pub fn suite_table(config: &SuiteConfig, results: &SuiteResults) -> String {
    format!(
        "{PAPER_TABLE_HEADING}\n\n{}",
        lab::report::table(&entries(config, results, &[], &[]))
    )
}

/// What the paper's table shows, above it wherever it is printed alone (two lines that
/// fit a terminal of 100 columns, as the rest of `reproduce`'s output does).
pub const PAPER_TABLE_HEADING: &str = concat!(
    "Behaviors evaluated per trial, the first two arms: mean ± the half-width of its 95% confidence\n",
    "interval (Student's t over the trials); the cases the second arm acquired; the paired t-test's p."
);

/// One line per experiment: the arm that needed the fewest behaviors, against the first.
pub fn suite_best_arms(config: &SuiteConfig, results: &SuiteResults) -> String {
    lab::report::best_arms(&entries(config, results, &[], &[]))
}

/// Writes the report folder for a suite run, with its [`ReportEstimates`]: the landscapes
/// behind each experiment's final behaviors and each experiment's known-operator limit. The
/// report reruns by itself: every operator file the config names (relative to `origin`)
/// is copied into `DIR/operators/`, and the `config.ron` written names those copies.
pub fn write_suite_report(
    dir: &Path,
    config: &SuiteConfig,
    origin: &Path,
    results: &SuiteResults,
    estimates: &ReportEstimates,
    elapsed_s: f64,
    provenance: &Provenance,
) -> Result<Vec<PathBuf>, SuiteError> {
    let (portable, copies) = config.portable(origin);
    let entries = entries(config, results, &estimates.landscapes, &estimates.limits);
    let mut written = write_report(
        dir,
        &entries,
        report_benchmark(config, &entries).as_deref(),
        &portable.to_ron(),
        elapsed_s,
        provenance,
    )?;
    written.extend(copy_operator_files(dir, &copies)?);
    Ok(written)
}

impl SuiteConfig {
    /// The `config.ron` a report of this config (read from `origin`) holds: the config
    /// with its operator files' copies in the report named instead.
    pub fn report_ron(&self, origin: &Path) -> String {
        self.portable(origin).0.to_ron()
    }

    /// This config as its report holds it, naming the copies of its operator files
    /// (relative to `origin`), and the copies to make.
    fn portable(&self, origin: &Path) -> (Self, Vec<OperatorCopy>) {
        let mut portable = self.clone();
        let copies = relocate_operator_files(
            portable
                .experiments
                .iter_mut()
                .map(|spec| &mut spec.operator_files),
            origin,
        );
        (portable, copies)
    }
}
