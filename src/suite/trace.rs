//! One trial of a suite replayed command by command, exactly as the suite ran it: the
//! report's sample timelines and `trustcbr explain` (and the Python `explain`), which
//! replays a report folder's trials from its `config.ron`, arms this tool cannot build
//! (arms written in Python) left out and named when asked for.

use super::plan::{Parts, arm_named, plans};
use super::replay::{ReplayError, check_replay};
use super::{StartingCases, SuiteConfig, SuiteError};
use crate::catalog::Catalog;
use cbr_core::BehaviorSpace;
use files::read_text;
use lab::Domain;
use lab::report::timeline::Timeline;
use lab::{Arm, ArmName, ExperimentPlan, PlanError, TracedCommand, TrialRecord, trace_trial};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Replays trial `trial` of arm `arm` of experiment `k` ([`trace_trial`]).
fn timeline<D: Domain>(
    plan: &ExperimentPlan<'_, D>,
    config: &SuiteConfig,
    k: usize,
    arm: usize,
    trial: u32,
) -> Result<Timeline, PlanError> {
    let (record, commands) = trace_trial(plan, k as u64, arm, trial, config.seed)?;
    Ok(timeline_of(plan, config, arm, record, commands))
}

/// The timeline of a traced trial of arm `arm`.
pub(super) fn timeline_of<D: Domain>(
    plan: &ExperimentPlan<'_, D>,
    config: &SuiteConfig,
    arm: usize,
    record: TrialRecord,
    commands: Vec<TracedCommand>,
) -> Timeline {
    Timeline {
        experiment: plan.name.clone(),
        arm: plan.arms[arm].arm_name().clone(),
        record,
        commands,
        thresholds: config.adapter.thresholds,
        observations: plan.domain.observations().to_vec(),
    }
}

/// Why a trial cannot be told ([`trace_suite_trial`]).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TraceError {
    /// The suite cannot be run.
    #[error(transparent)]
    Suite(#[from] SuiteError),
    /// No experiment has that name.
    #[error("no experiment is named `{name}` (the config's: {known})")]
    Experiment {
        /// The name given.
        name: String,
        /// The experiments' names.
        known: String,
    },
    /// The experiment has no arm of that name.
    #[error("experiment `{experiment}` has no arm `{name}` (its arms: {known})")]
    Arm {
        /// The experiment.
        experiment: String,
        /// The name given.
        name: String,
        /// The arms.
        known: String,
    },
    /// The path given is not a report folder.
    #[error("{}: not a report folder (it has no config.ron)", .0.display())]
    NotAReport(PathBuf),
    /// The arm is in the report but this tool cannot build it (an arm written in Python,
    /// or another tool's).
    #[error(
        "arm `{arm}` cannot be replayed: it is neither a built-in arm nor one of {tool}'s own (an arm written in Python? the Python `trustcbr.explain` replays it given its factory); {}",
        replayable_arms(.replayable)
    )]
    NotReplayable {
        /// The arm asked for.
        arm: String,
        /// The tool's name.
        tool: String,
        /// The report's arms it can replay.
        replayable: Vec<ArmName>,
    },
    /// The report's config, case bases or tool differ from what ran ([`check_replay`]).
    #[error(transparent)]
    Replay(#[from] ReplayError),
    /// The trial is beyond the experiment's.
    #[error("experiment `{experiment}` ran trials 0 to {last}, not {trial}")]
    Trial {
        /// The experiment.
        experiment: String,
        /// The trial given.
        trial: u32,
        /// The last trial.
        last: u32,
    },
}

/// `the report's replayable arms: a, b`, or that it has none.
fn replayable_arms(arms: &[ArmName]) -> String {
    if arms.is_empty() {
        "no arm of the report can be replayed".to_owned()
    } else {
        format!(
            "the report's replayable arms: {}",
            ArmName::join(arms, ", ")
        )
    }
}

/// A report's config read for replay: the arms `catalog` can build, and the ones it
/// cannot, which are left out (a trial of one arm does not depend on the others: every
/// stream is named by experiment and trial, not by arm).
pub struct Replayable {
    /// The config, with the replayable arms only (its `reference` dropped when it is
    /// not one of them).
    pub config: SuiteConfig,
    /// The arms left out, in config order.
    pub left_out: Vec<ArmName>,
}

/// Reads the suite config `text` (from `origin`) for replay ([`Replayable`]).
pub fn replayable_config<C: Catalog>(
    catalog: &C,
    text: &str,
    origin: &Path,
) -> Result<Replayable, TraceError> {
    let mut config = SuiteConfig::parse(text, origin)?;
    config.choose_left_out_operators(catalog, origin);
    let retriever = config.adapter.retriever;
    let (kept, left_out): (Vec<ArmName>, Vec<ArmName>) = config
        .arms
        .iter()
        .cloned()
        .partition(|name| arm_named(catalog, name, retriever).is_ok());
    if kept.is_empty() {
        return Err(TraceError::NotReplayable {
            arm: left_out.first().map(ArmName::to_string).unwrap_or_default(),
            tool: catalog.tool().name,
            replayable: Vec::new(),
        });
    }
    config.arms = kept;
    if config
        .reference
        .as_ref()
        .is_some_and(|r| left_out.iter().any(|a| a == r.as_str()))
    {
        config.reference = None;
    }
    config.validate(catalog, origin)?;
    Ok(Replayable { config, left_out })
}

/// Replays one trial of the report folder `report` (its `config.ron`), as `trustcbr
/// explain` does: experiment and arm by name; an arm the catalog cannot build is refused
/// naming the report's arms it can replay.
pub fn trace_report_trial<C: Catalog>(
    catalog: &C,
    report: &Path,
    starting: Option<&StartingCases>,
    experiment: &str,
    arm: &str,
    trial: u32,
) -> Result<ReplayedTrial, TraceError> {
    let origin = report.join("config.ron");
    // Absent is no report; anything else there is read, and refused as what it is (a
    // link to a device, a folder) if it is no regular file.
    if std::fs::symlink_metadata(&origin).is_err() {
        return Err(TraceError::NotAReport(report.to_owned()));
    }
    let text = read_text(&origin).map_err(SuiteError::from)?;
    let Replayable { config, left_out } = replayable_config(catalog, &text, &origin)?;
    if left_out.iter().any(|a| a == arm) {
        return Err(TraceError::NotReplayable {
            arm: arm.to_owned(),
            tool: catalog.tool().name,
            replayable: config.arms.clone(),
        });
    }
    let warnings = check_replay(catalog, report, &config, &text, starting, experiment, arm)?;
    let (timeline, space) =
        trace_suite_trial(catalog, &config, &origin, starting, experiment, arm, trial)?;
    Ok(ReplayedTrial {
        timeline,
        space,
        warnings,
    })
}

/// A report's trial replayed ([`trace_report_trial`]).
#[derive(Debug)]
pub struct ReplayedTrial {
    /// The trial, command by command.
    pub timeline: Timeline,
    /// Its experiment's behavior space.
    pub space: Arc<BehaviorSpace>,
    /// What the report cannot show about its replay (an earlier version's report records
    /// no hashes of its config and case bases), to be shown beside the story.
    pub warnings: Vec<String>,
}

/// Replays one trial of a suite (experiment and arm by name), exactly as the suite ran it,
/// and returns its timeline with the experiment's behavior space.
pub fn trace_suite_trial<C: Catalog>(
    catalog: &C,
    config: &SuiteConfig,
    origin: &Path,
    starting: Option<&StartingCases>,
    experiment: &str,
    arm: &str,
    trial: u32,
) -> Result<(Timeline, Arc<BehaviorSpace>), TraceError> {
    let parts = Parts::of(catalog, config, origin)?;
    let plans = plans(&parts, catalog, config, origin, starting)?;
    let k = plans
        .iter()
        .position(|p| p.name == experiment)
        .ok_or_else(|| TraceError::Experiment {
            name: experiment.to_owned(),
            known: plans
                .iter()
                .map(|p| p.name.as_str())
                .collect::<Vec<_>>()
                .join(", "),
        })?;
    let plan = &plans[k];
    let a = plan
        .arms
        .iter()
        .position(|a| a.name() == arm)
        .ok_or_else(|| TraceError::Arm {
            experiment: experiment.to_owned(),
            name: arm.to_owned(),
            known: plan
                .arms
                .iter()
                .map(Arm::name)
                .collect::<Vec<_>>()
                .join(", "),
        })?;
    if trial >= plan.trials {
        return Err(TraceError::Trial {
            experiment: experiment.to_owned(),
            trial,
            last: plan.trials - 1,
        });
    }
    let timeline = timeline(plan, config, k, a, trial).map_err(SuiteError::from)?;
    Ok((timeline, parts.domain(k).space().clone()))
}
