//! Running a suite: its experiments over the catalog's domains on the current rayon pool,
//! with a sample trial of each traced for the report, and the report's estimates beside
//! them when asked.

use super::estimates::{ReportEstimates, estimate_parts};
use super::plan::{Parts, plans};
use super::trace::timeline_of;
use super::{StartingCases, SuiteConfig, SuiteError};
use crate::catalog::Catalog;
use cbr_core::BehaviorSpace;
use lab::Domain;
use lab::report::timeline::{Timeline, sample_trial};
use lab::{ExperimentResult, run_experiments};
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

/// A suite's results, ready for reporting.
pub struct SuiteResults {
    /// One result per experiment, in config order.
    pub results: Vec<ExperimentResult>,
    /// The behavior space of each experiment, in config order.
    pub spaces: Vec<Arc<BehaviorSpace>>,
    /// A sample trial of each experiment traced command by command
    /// ([`lab::report::timeline::sample_trial`]), in config order.
    pub timelines: Vec<Option<Timeline>>,
}

/// Runs every experiment of `config` (operator files relative to `origin`) over the
/// domains of `catalog` on the current rayon pool, arms that reuse cases starting from
/// `starting` when given; `progress(experiment)` is called after every trial. No trial is
/// traced (see [`run_suite_with_report`]).
pub fn run_suite<C: Catalog>(
    catalog: &C,
    config: &SuiteConfig,
    origin: &Path,
    starting: Option<&StartingCases>,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<SuiteResults, SuiteError> {
    let parts = Parts::of(catalog, config, origin)?;
    run_parts(&parts, catalog, config, origin, starting, progress, false)
}

/// [`run_suite`] and [`ReportEstimates`] together, over one domain per scenario: the
/// report's landscapes and limits depend on the config alone, so they are estimated on the
/// current rayon pool while the experiments run, filling the cores the experiments'
/// ordered chains leave idle, and the domains' caches (plans) serve both. A sample trial
/// of each experiment is traced for the report's timelines. Returns the results, the
/// experiments' own run time (s) and the estimates.
pub fn run_suite_with_report<C: Catalog>(
    catalog: &C,
    config: &SuiteConfig,
    origin: &Path,
    starting: Option<&StartingCases>,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<(SuiteResults, f64, ReportEstimates), SuiteError> {
    let parts = Parts::of(catalog, config, origin)?;
    let (run, estimates) = rayon::join(
        || {
            let started = Instant::now();
            let results = run_parts(&parts, catalog, config, origin, starting, progress, true);
            (results, started.elapsed().as_secs_f64())
        },
        || estimate_parts(&parts, config, origin),
    );
    Ok((run.0?, run.1, estimates?))
}

/// The experiments of `config` over `parts`, with a sample trial of each traced when
/// `trace` (for a report).
fn run_parts<C: Catalog>(
    parts: &Parts<C>,
    catalog: &C,
    config: &SuiteConfig,
    origin: &Path,
    starting: Option<&StartingCases>,
    progress: &(dyn Fn(usize) + Sync),
    trace: bool,
) -> Result<SuiteResults, SuiteError> {
    let plans = plans(parts, catalog, config, origin, starting)?;
    let results = run_experiments(&plans, config.seed, progress)?;
    let timelines = plans
        .iter()
        .zip(&results)
        .map(|(plan, result)| {
            // The trial as it ran: the sample arm traced its first trials.
            sample_trial(result).filter(|_| trace).map(|(arm, trial)| {
                let ran = &result.arms[arm];
                timeline_of(
                    plan,
                    config,
                    arm,
                    ran.trials[trial as usize].clone(),
                    ran.traced[trial as usize].clone(),
                )
            })
        })
        .collect();
    let spaces = (0..config.experiments.len())
        .map(|k| parts.domain(k).space().clone())
        .collect();
    Ok(SuiteResults {
        results,
        spaces,
        timelines,
    })
}
