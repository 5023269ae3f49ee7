//! The report of a set of experiments: the printed tables (the paper's two arms, then
//! every arm with what it costs the operator), `table.md`, `summary.json` (with the
//! report's provenance), `trials.jsonl`, the config used, SVG plots (learning curves,
//! and where the final behaviors land in the behavior space, over the operator's
//! landscape) and `report.html`, the page that holds them all; for a benchmark suite,
//! every arm over the populations of each scenario ([`crate::benchmark`]) in the three.
//! Every file is written atomically.
//!
//! This module is what a report is made of ([`ReportEntry`]) and the folder it writes
//! ([`write_report`]); one submodule each for:
//! - `effects`: every arm against its experiment's reference arm (effect sizes, paired
//!   tests);
//! - `tables`: the Markdown tables and `table.md`;
//! - `summary_json` and `trials_jsonl`: the two machine-readable files;
//! - `page`: `report.html`;
//! - `figures`: the SVG figures, one submodule per kind.

mod effects;
mod figures;
mod page;
mod summary_json;
mod tables;
mod trials_jsonl;

pub use crate::plot::category_label;
pub use effects::{all_effect_sizes, effect_sizes, versus_reference};
pub use figures::{FINALS_LANDSCAPE_RUNS, component_pairs, finals_landscapes};
pub use files::name::file_stems;
pub use summary_json::summary;
pub use tables::{
    arms_table, benchmark_table, best_arms, effects_table, explanations_table, free_first_table,
    goal_changes_table, limit_table, population_table, sample_explanations, table,
};
pub use trials_jsonl::trials_jsonl;

use crate::benchmark::ScenarioBenchmark;
use crate::known_operator::ExperimentLimit;
use crate::landscape::Landscape;
use crate::plot::PlotError;
use crate::runner::ExperimentResult;
use crate::timeline::Timeline;
use cbr_core::BehaviorSpace;
use files::{FileError, write_file_in};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One experiment's results with what the report needs to describe them.
pub struct ReportEntry<'a> {
    /// The results.
    pub result: &'a ExperimentResult,
    /// The scenario (domain) name, e.g. `movement`.
    pub scenario: &'a str,
    /// The configured operator: a name, `random`, or the name of a population.
    pub operator: &'a str,
    /// The behavior space, to show behaviors in real units.
    pub space: &'a BehaviorSpace,
    /// The operator's landscapes the final behaviors are drawn over, one per pair of
    /// [`component_pairs`] ([`finals_landscapes`]); empty to draw them on white.
    pub landscapes: &'a [Landscape],
    /// The known-operator limit of the experiment ([`crate::known_operator`]), when
    /// computed.
    pub limit: Option<&'a ExperimentLimit>,
    /// A sample trial traced command by command ([`crate::timeline`]), when traced.
    pub timeline: Option<&'a Timeline>,
    /// The arm every other arm is tested against (p-values) and measured against (effect
    /// sizes); when it is not among the arms, no arm is.
    pub reference: &'a str,
    /// The master seed of the experiments, from which the effect sizes' bootstrap
    /// streams derive ([`crate::seeds::Purpose::Bootstrap`]).
    pub seed: u64,
}

/// Why the report could not be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReportError {
    /// A file or folder could not be written.
    #[error(transparent)]
    Io(#[from] FileError),
    /// A plot could not be drawn.
    #[error(transparent)]
    Plot(#[from] PlotError),
}

/// Where the report came from: the tool, its version and commit, the command line, and
/// what a replay of its trials must find unchanged.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Provenance {
    /// The program that wrote the report.
    pub tool: String,
    /// Its version.
    pub version: String,
    /// The source commit it was built from, when known.
    pub git_commit: Option<String>,
    /// The command line, program first.
    pub command_line: Vec<String>,
    /// What `explain` checks before it replays a trial of the report (absent in reports
    /// of earlier versions).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub replay: Option<Replay>,
}

/// What a faithful replay of a report's trials needs unchanged, besides the tool and its
/// version: the config it ran, and the cases each arm started from, by content hash.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Replay {
    /// The content hash of the report's `config.ron`, as written.
    pub config: String,
    /// The content hash of the cases each arm started from (a run given saved case bases),
    /// by experiment, then arm; an arm that started from none is not listed.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub starting_cases: BTreeMap<String, BTreeMap<String, String>>,
}

/// `table.md`: every arm of every experiment, with what it costs the operator, its effect
/// against the reference arm and the known-operator limit, and the benchmark of a
/// benchmark suite (`None` for any other) (what [`write_report`] writes).
pub fn table_md(entries: &[ReportEntry<'_>], benchmark: Option<&[ScenarioBenchmark]>) -> String {
    tables::table_md(entries, &all_effect_sizes(entries), benchmark)
}

/// Writes the whole report into `dir` (created if needed): `table.md`, `summary.json`,
/// `trials.jsonl`, `config.ron` (the text given) and the plots, with the benchmark of a
/// benchmark suite (`None` for any other). Returns the files written.
pub fn write_report(
    dir: &Path,
    entries: &[ReportEntry<'_>],
    benchmark: Option<&[ScenarioBenchmark]>,
    config_ron: &str,
    elapsed_s: f64,
    provenance: &Provenance,
) -> Result<Vec<PathBuf>, ReportError> {
    let mut written = Vec::new();
    let mut write = |name: &str, text: &str| -> Result<(), ReportError> {
        written.push(write_file_in(dir, name, text)?);
        Ok(())
    };
    let effects = all_effect_sizes(entries);
    write("table.md", &tables::table_md(entries, &effects, benchmark))?;
    let summary = serde_json::to_string_pretty(&summary_json::summary_of(
        entries, &effects, benchmark, elapsed_s, provenance,
    ))
    .expect("plain data serializes");
    write("summary.json", &(summary + "\n"))?;
    write("trials.jsonl", &trials_jsonl(entries))?;
    write("config.ron", config_ron)?;
    let figures = figures::write_figures(dir, entries, &effects, benchmark, &mut write)?;
    write(
        "report.html",
        &page::html_page(
            entries, &effects, benchmark, config_ron, provenance, &figures,
        ),
    )?;
    Ok(written)
}
