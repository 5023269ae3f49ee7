//! The report of a set of experiments: the printed tables (the paper's two arms, then
//! every arm with what it costs the operator), `table.md`, `summary.json` (with the
//! report's provenance), `trials.jsonl`, the config used, SVG plots (learning curves,
//! and where the final behaviors land in the behavior space, over the operator's
//! landscape) and `report.html`, the page that holds them all; for a benchmark suite,
//! every arm over the populations of each scenario ([`crate::population::benchmark`]) in the three.
//! Every file is written atomically.
//!
//! This module is what a report is made of ([`ReportEntry`]) and the folder it writes
//! ([`write_report`]); one submodule each for:
//! - `effects`: every arm against its experiment's reference arm (effect sizes, paired
//!   tests);
//! - `tables`: the Markdown tables and `table.md`;
//! - `summary_json` and `trials_jsonl`: the two machine-readable files;
//! - `page`: `report.html`;
//! - `figures`: the SVG figures, one submodule per kind;
//! - [`plot`], [`heatmap`] and [`timeline`]: the figure kinds other folders draw too
//!   (mission figures among them).
//!
//! Imports every folder but [`mission`](crate::mission).

mod benchmark_tables;
mod effects;
mod entry;
mod figures;
mod goal_changes;
pub mod heatmap;
mod page;
pub mod plot;
mod summary_json;
mod tables;
pub mod timeline;
mod trials_jsonl;

pub use crate::report::plot::category_label;
pub use benchmark_tables::{benchmark_split_table, benchmark_table};
pub use effects::{all_effect_sizes, effect_sizes, versus_reference};
pub use entry::{Provenance, Replay, ReportEntry, ReportError};
pub use figures::{FINALS_LANDSCAPE_RUNS, component_pairs, finals_landscapes};
pub use files::name::file_stems;
pub use summary_json::summary;
pub use tables::{
    arms_table, best_arms, effects_table, explanations_table, free_first_table, goal_changes_table,
    limit_table, population_table, sample_explanations, table,
};
pub use trials_jsonl::trials_jsonl;

use crate::population::benchmark::ScenarioBenchmark;
use files::write_file_in;

use std::path::{Path, PathBuf};

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
