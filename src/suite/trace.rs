//! One trial of a suite replayed command by command, exactly as the suite ran it: the
//! report's sample timelines and `trustcbr explain`.

use super::plan::{Parts, plans};
use super::{StartingCases, SuiteConfig, SuiteError};
use crate::catalog::Catalog;
use cbr_core::BehaviorSpace;
use lab::Domain;
use lab::timeline::Timeline;
use lab::{Arm, ExperimentPlan, PlanError, TracedCommand, TrialRecord, trace_trial};
use std::path::Path;
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
        arm: plan.arms[arm].name().to_owned(),
        arm_index: arm,
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
