//! A suite's report: its results and estimates as the report's entries (and, for a
//! benchmark suite, its benchmark), the printed tables, and the report folder, made to
//! rerun by itself (operator files copied in).

use super::{ReportEstimates, SuiteConfig, SuiteError, SuiteResults};
use files::{read_text, write_file_in};
use lab::benchmark::{BenchmarkPopulation, ScenarioBenchmark, benchmarks};
use lab::known_operator::ExperimentLimit;
use lab::landscape::Landscape;
use lab::report::{Provenance, ReportEntry, file_stems, write_report};
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
                })
            })
            .collect();
        benchmarks(&populations, config.seed)
    })
}

/// The results table in Markdown.
pub fn suite_table(config: &SuiteConfig, results: &SuiteResults) -> String {
    lab::report::table(&entries(config, results, &[], &[]))
}

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
    let (portable, copies) = config.with_operator_files_in(REPORT_OPERATORS, origin);
    let entries = entries(config, results, &estimates.landscapes, &estimates.limits);
    let mut written = write_report(
        dir,
        &entries,
        report_benchmark(config, &entries).as_deref(),
        &portable.to_ron(),
        elapsed_s,
        provenance,
    )?;
    for (source, copy) in copies {
        written.push(write_file_in(dir, copy, &read_text(&source)?)?);
    }
    Ok(written)
}

/// The folder of a report that holds copies of the operator files its config names.
const REPORT_OPERATORS: &str = "operators";

impl SuiteConfig {
    /// The `config.ron` a report of this config (read from `origin`) holds: the config
    /// with its operator files' copies in the report named instead.
    pub fn report_ron(&self, origin: &Path) -> String {
        self.with_operator_files_in(REPORT_OPERATORS, origin)
            .0
            .to_ron()
    }

    /// This config with every operator file moved into `folder` (relative names, one
    /// copy per distinct file), and the (source, copy) pairs to copy: sources resolved
    /// against `origin`'s directory.
    fn with_operator_files_in(
        &self,
        folder: &str,
        origin: &Path,
    ) -> (Self, Vec<(PathBuf, PathBuf)>) {
        let base = origin.parent().unwrap_or(Path::new("."));
        let mut sources: Vec<PathBuf> = Vec::new();
        for spec in &self.experiments {
            for file in &spec.operator_files {
                let source = base.join(file);
                if !sources.contains(&source) {
                    sources.push(source);
                }
            }
        }
        let stems = file_stems(sources.iter().map(|p| {
            p.file_stem()
                .map_or_else(String::new, |s| s.to_string_lossy().into_owned())
        }));
        let copies: Vec<(PathBuf, PathBuf)> = sources
            .into_iter()
            .zip(stems)
            .map(|(source, stem)| (source, Path::new(folder).join(format!("{stem}.ron"))))
            .collect();
        let mut portable = self.clone();
        for spec in &mut portable.experiments {
            for file in &mut spec.operator_files {
                let source = base.join(&*file);
                *file = copies
                    .iter()
                    .find(|(s, _)| *s == source)
                    .expect("every file was collected")
                    .1
                    .clone();
            }
        }
        (portable, copies)
    }
}
