//! Sweeps: a suite run over several seeds and over values of named parameters, aggregated
//! across seeds.
//!
//! A [`SweepConfig`] (RON) names a base suite, the seeds, and the parameters to vary
//! ([`Parameter`]: lambda, thresholds, the retention reading, the unit of `t`, the arms,
//! and any reading the catalog's domain declares, such as the UGV patrol weight reading). Its *cells* are the base and, one parameter at a time, each
//! of its other values (or, with `design: grid`, every combination). Every (cell, seed)
//! pair is one *run* of the suite, summarised into a small JSON file
//! (`runs/CELL/seed-SEED.json`); the report (the folder `report/` beside the runs, swapped
//! in whole) aggregates the runs of each cell across seeds (mean of the per-seed means,
//! with a 95% confidence interval over seeds).
//!
//! Runs are independent, so a sweep can be split: `--shard I/N` runs every N-th run and
//! writes only its run files, and [`merge`] rebuilds the report from shard folders. The
//! report is a function of the run files alone (no timings, fixed order), so a merged
//! report is byte-for-byte the report of a single run.
//!
//! One idea per file: the sweep as written (`config`); its cells and runs, checked
//! (`cells`); one run, its summary and its file (`runs`); the folder a sweep writes into
//! (`folder`); merging shard folders (`merge`); the report (`report`) and its plots
//! (`plot`).

mod cells;
mod config;
mod folder;
mod merge;
mod plot;
mod report;
mod runs;

pub use cells::{Cell, RunId, Sweep};
pub use config::{Design, Parameter, SuiteSource, SweepConfig};
pub use folder::{REPORT_DIR, prepare_dir, remove_earlier_sweep, write_config};
pub use merge::merge;
pub use report::write_report;
pub use runs::{ArmMeans, RunSummary, write_run};

use crate::config_file::{ConfigFileError, from_config_file_errors};
use crate::suite::SuiteError;
use std::path::PathBuf;

/// Why a sweep cannot be run or merged.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SweepError {
    /// The sweep file cannot be read or parsed, a value of it is out of range, or a file
    /// of the sweep's folder cannot be read or written.
    #[error(transparent)]
    File(#[from] ConfigFileError),
    /// A cell's suite is invalid or could not run.
    #[error("cell {cell}: {reason}")]
    Suite {
        /// The cell's label.
        cell: String,
        /// Why.
        reason: SuiteError,
    },
    /// A run file is unreadable, or does not belong in its place, when merging.
    #[error("{path}: {message}")]
    Run {
        /// The run file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// Runs no folder holds, when merging.
    #[error(
        "{} of {total} runs are in none of the folders ({}): {}; run the shards that hold them first",
        runs.len(),
        folders.iter().map(|d| d.display().to_string()).collect::<Vec<_>>().join(", "),
        runs.iter().map(|r| r.display().to_string()).collect::<Vec<_>>().join(", ")
    )]
    Missing {
        /// The missing run files, relative to a folder.
        runs: Vec<PathBuf>,
        /// How many runs the sweep has.
        total: usize,
        /// The folders looked in.
        folders: Vec<PathBuf>,
    },
    /// A folder for a sweep's files cannot be used, or holds other files.
    #[error(transparent)]
    Folder(#[from] lab::folder::ReportFolderError),
    /// The report could not be written: the earlier report is left as it was.
    #[error(
        "{}: the report could not be written, and the folder is left as it was (the report is written beside it first, and that folder is removed): {reason}",
        path.display()
    )]
    Unwritten {
        /// The report's folder.
        path: PathBuf,
        /// The file that could not be written, and why.
        reason: files::FileError,
    },
    /// A plot could not be drawn.
    #[error("plot {path}: {message}")]
    Plot {
        /// The plot file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

from_config_file_errors!(SweepError);
