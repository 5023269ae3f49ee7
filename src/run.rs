//! A suite run as `reproduce` and `run` do it, with its report folder: the one path the
//! command line and the Python package (`python/`) share.
//!
//! [`run_with_report`] checks the config, prepares the folders, runs the experiments with
//! the report's estimates on a worker pool and writes the report; [`Ran`] holds what the
//! caller prints or hands back ([`Ran::trials_jsonl`], [`Ran::summary`]: the report's
//! `trials.jsonl` and `summary.json`, also without a folder). [`run_missions_with_report`]
//! does the same for a mission suite.

use crate::catalog::Catalog;
use crate::mission_suite::{MissionSuiteConfig, run_mission_suite, write_mission_report};
use crate::suite::{
    ReportEstimates, StartingCases, SuiteConfig, SuiteResults, check_save_targets,
    report_benchmark, report_entries, report_replay, run_suite_with_report, save_case_bases,
    write_suite_report,
};
use anyhow::{Context, Result};
use lab::report::{Provenance, Replay};
use std::num::NonZeroUsize;
use std::path::{Path, PathBuf};

/// Where and how a suite runs.
#[derive(Clone, Debug, Default)]
pub struct RunSettings {
    /// The report folder (written whole beside it, then swapped for an earlier report); `None` writes no report.
    pub out: Option<PathBuf>,
    /// Start case-reusing arms from the case bases saved in this folder.
    pub starting: Option<StartingCases>,
    /// Save the case base each case-reusing arm ends every experiment with, here.
    pub save_cases: Option<PathBuf>,
    /// Worker threads (default: one per core).
    pub threads: Option<NonZeroUsize>,
    /// The command line recorded in the report's provenance.
    pub command_line: Vec<String>,
}

/// A finished suite run.
pub struct Ran {
    /// The config that ran.
    pub config: SuiteConfig,
    /// The experiments' results.
    pub results: SuiteResults,
    /// The report's landscapes and limits.
    pub estimates: ReportEstimates,
    /// The experiments' own run time (s).
    pub elapsed_s: f64,
    /// The worker threads used.
    pub threads: usize,
    /// Who ran it.
    pub provenance: Provenance,
    /// The report's files, when a folder was asked for.
    pub written: Vec<PathBuf>,
    /// The case bases saved, when asked for.
    pub saved: Vec<PathBuf>,
    /// What the config's operator files are relative to (made absolute, so a report
    /// written later reads the same files wherever the process has moved to).
    pub origin: PathBuf,
}

impl Ran {
    /// The report's `trials.jsonl`: one JSON object per trial.
    pub fn trials_jsonl(&self) -> String {
        lab::report::trials_jsonl(&report_entries(
            &self.config,
            &self.results,
            &self.estimates,
        ))
    }

    /// The report's `table.md`: every arm, with what it costs the operator (and the
    /// benchmark of a benchmark suite).
    pub fn table_md(&self) -> String {
        let entries = report_entries(&self.config, &self.results, &self.estimates);
        lab::report::table_md(
            &entries,
            report_benchmark(&self.config, &entries).as_deref(),
        )
    }

    /// Writes the report folder `out` after the run, byte for byte the folder the run
    /// would have written there (`--out`, [`RunSettings::out`]): the same results,
    /// estimates, run time and provenance. An earlier report at `out` is replaced, as a
    /// run replaces it. Returns the files written.
    pub fn write_report(&self, out: &Path) -> Result<Vec<PathBuf>> {
        write_staged(out, |dir| {
            write_suite_report(
                dir,
                &self.config,
                &self.origin,
                &self.results,
                &self.estimates,
                self.elapsed_s,
                &self.provenance,
            )
        })
    }

    /// The report's `summary.json` document.
    pub fn summary(&self) -> serde_json::Value {
        let entries = report_entries(&self.config, &self.results, &self.estimates);
        lab::report::summary(
            &entries,
            report_benchmark(&self.config, &entries).as_deref(),
            self.elapsed_s,
            &self.provenance,
        )
    }
}

/// Runs `config` (operator files relative to `origin`) as `trustcbr run` does: the config
/// checked, and the files the saved case bases will replace (each absent or a case base
/// saved earlier), the folders prepared before any work (a refused run creates none), the
/// experiments and the report's estimates on a pool of `settings.threads` workers,
/// `progress(experiment)` after every trial, then the report and the saved case bases.
pub fn run_with_report<C: Catalog>(
    catalog: &C,
    config: SuiteConfig,
    origin: &Path,
    settings: &RunSettings,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Ran> {
    run_with_report_checked(catalog, config, origin, settings, progress, &|| Ok(()))
}

/// [`run_with_report`], with `before_writing` asked once the experiments have run and
/// before anything is written: an error stops the run there, leaving the report folder
/// (and an earlier report in it) and the case bases untouched. A caller whose arms cannot
/// fail inside the runner (a Python arm keeps its exception) says so here.
pub fn run_with_report_checked<C: Catalog>(
    catalog: &C,
    config: SuiteConfig,
    origin: &Path,
    settings: &RunSettings,
    progress: &(dyn Fn(usize) + Sync),
    before_writing: &dyn Fn() -> Result<()>,
) -> Result<Ran> {
    config.validate(catalog, origin)?;
    if let Some(dir) = settings.starting.as_ref().map(|s| &s.dir) {
        anyhow::ensure!(dir.is_dir(), "--cases {}: no such folder", dir.display());
    }
    if let Some(dir) = &settings.save_cases {
        check_save_targets(catalog, dir, &config)?;
    }
    if let Some(out) = &settings.out {
        lab::folder::prepare_output_dir(out)?;
    }
    if let Some(dir) = &settings.save_cases {
        files::output::ensure_writable_dir(dir)?;
    }
    // What `explain` checks of this report, taken before the run: the cases read then.
    let replay = report_replay(
        catalog,
        &config,
        origin,
        &config.report_ron(origin),
        settings.starting.as_ref(),
    )?;
    let (pool, threads) = worker_pool(settings.threads)?;
    let (results, elapsed_s, estimates) = pool.install(|| {
        run_suite_with_report(
            catalog,
            &config,
            origin,
            settings.starting.as_ref(),
            progress,
        )
    })?;
    before_writing()?;
    let provenance = provenance(catalog, &settings.command_line, Some(replay));
    let mut ran = Ran {
        config,
        results,
        estimates,
        elapsed_s,
        threads,
        provenance,
        written: Vec::new(),
        saved: Vec::new(),
        origin: absolute(origin),
    };
    if let Some(out) = &settings.out {
        ran.written = ran.write_report(out)?;
    }
    if let Some(dir) = &settings.save_cases {
        ran.saved = save_case_bases(dir, &ran.config, &ran.results)?;
    }
    Ok(ran)
}

/// `origin` made absolute against the working directory (as it is when it cannot be).
fn absolute(origin: &Path) -> PathBuf {
    std::path::absolute(origin).unwrap_or_else(|_| origin.to_owned())
}

/// Writes a report whole into a fresh folder beside `out` with `write`, then swaps it in
/// for `out` (an earlier report there is replaced); returns the files as named in `out`.
fn write_staged(
    out: &Path,
    write: impl FnOnce(&Path) -> Result<Vec<PathBuf>, crate::SuiteError>,
) -> Result<Vec<PathBuf>> {
    let staged = lab::folder::begin_report(out)?;
    let written = write(staged.path()).with_context(|| unwritten(out))?;
    let written = lab::folder::in_place(&staged, written);
    lab::folder::finish_report(staged)?;
    Ok(written)
}

/// Where and how a mission suite runs.
#[derive(Clone, Debug, Default)]
pub struct MissionSettings {
    /// The report folder (written whole beside it, then swapped for an earlier report);
    /// `None` writes no report.
    pub out: Option<PathBuf>,
    /// Worker threads (default: one per core).
    pub threads: Option<NonZeroUsize>,
    /// The command line recorded in the report's provenance.
    pub command_line: Vec<String>,
}

/// A finished mission suite run.
pub struct MissionsRan {
    /// The config that ran.
    pub config: MissionSuiteConfig,
    /// Every plan's results, in config order.
    pub results: Vec<lab::mission::MissionResult>,
    /// The missions' run time (s).
    pub elapsed_s: f64,
    /// The worker threads used.
    pub threads: usize,
    /// The report's files, when a folder was asked for.
    pub written: Vec<PathBuf>,
    /// What the config's operator files are relative to (made absolute).
    pub origin: PathBuf,
    /// What wrote the report: the tool, its version and commit, the command line.
    pub provenance: Provenance,
}

impl MissionsRan {
    /// Writes the report folder `out` after the run, byte for byte the folder the run
    /// would have written there; an earlier report at `out` is replaced. Returns the
    /// files written.
    pub fn write_report(&self, out: &Path) -> Result<Vec<PathBuf>> {
        write_staged(out, |dir| {
            write_mission_report(
                dir,
                &self.config,
                &self.origin,
                &self.results,
                &self.provenance,
            )
        })
    }

    /// The report's `missions.jsonl`: one JSON object per mission.
    pub fn missions_jsonl(&self) -> String {
        lab::mission::report::missions_jsonl(&self.results)
    }

    /// The report's `summary.json` document.
    pub fn summary(&self) -> serde_json::Value {
        lab::mission::report::missions_json(&self.results)
    }

    /// The report's `missions.md`.
    pub fn table_md(&self) -> String {
        lab::mission::report::missions_markdown(&self.results)
    }
}

/// Runs a mission suite (operator files relative to `origin`) as `trustcbr run` does: the
/// report folder `out` prepared before any work, the missions on a pool of `threads`
/// workers, `progress(plan)` after every mission, then the report (when `out` is given).
/// `before_writing` is asked once the missions have run, as [`run_with_report_checked`]
/// asks it.
pub fn run_missions_with_report<C: Catalog>(
    catalog: &C,
    config: MissionSuiteConfig,
    origin: &Path,
    settings: &MissionSettings,
    progress: &(dyn Fn(usize) + Sync),
    before_writing: &dyn Fn() -> Result<()>,
) -> Result<MissionsRan> {
    config.validate(catalog, origin)?;
    if let Some(out) = &settings.out {
        lab::folder::prepare_output_dir(out)?;
    }
    let (pool, threads) = worker_pool(settings.threads)?;
    let started = std::time::Instant::now();
    let results = pool.install(|| run_mission_suite(catalog, &config, origin, progress))?;
    let elapsed_s = started.elapsed().as_secs_f64();
    before_writing()?;
    let mut ran = MissionsRan {
        config,
        results,
        elapsed_s,
        threads,
        written: Vec::new(),
        origin: absolute(origin),
        provenance: provenance(catalog, &settings.command_line, None),
    };
    if let Some(out) = &settings.out {
        ran.written = ran.write_report(out)?;
    }
    Ok(ran)
}

/// What wrote a report: `catalog`'s tool, its version and commit, `command_line`, and for
/// an experiment report what a replay of it checks.
fn provenance<C: Catalog>(
    catalog: &C,
    command_line: &[String],
    replay: Option<Replay>,
) -> Provenance {
    let tool = catalog.tool();
    Provenance {
        tool: tool.name,
        version: tool.version,
        git_commit: tool.git_commit,
        command_line: command_line.to_vec(),
        replay,
    }
}

/// What a report that failed to write says: it was written into a fresh folder beside
/// `out` (the path its error names), which is removed, and `out` is as it was.
fn unwritten(out: &Path) -> String {
    format!(
        "{}: the report could not be written, and the folder is left as it was (the report is written beside it first, and that folder is removed)",
        out.display()
    )
}

/// The missions of each plan of `config`, for a progress display: (plan name, missions
/// in all arms).
pub fn missions_per_plan(config: &MissionSuiteConfig) -> Vec<(String, u64)> {
    config
        .missions
        .iter()
        .map(|spec| {
            let doubled = if spec.complacency.is_some() { 2 } else { 1 };
            let chains = config.arms.len() as u64 * doubled;
            (spec.name.clone(), chains * u64::from(spec.count.get()))
        })
        .collect()
}

/// A rayon pool of `threads` workers (default: one per core), and its size.
pub fn worker_pool(threads: Option<NonZeroUsize>) -> Result<(rayon::ThreadPool, usize)> {
    let threads = threads.map_or_else(
        || std::thread::available_parallelism().map_or(1, NonZeroUsize::get),
        NonZeroUsize::get,
    );
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("cannot start the worker threads")?;
    Ok((pool, threads))
}
