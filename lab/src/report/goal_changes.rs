//! What an arm's trials tell of goal changes ([`crate::experiment::goal_change`]), for
//! the report's goal-change table and `summary.json`.

use crate::experiment::goal_change::GoalChangeRecord;
use crate::experiment::record::{ArmResult, TrialRecord};
use crate::reference::known_operator::ExperimentLimit;
use crate::stats::{MeanCi, mean_ci95_or_zero};
use cbr_core::BehaviorSpace;

/// What an arm's trials tell of goal changes, for a report.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmGoalChanges {
    /// Behaviors given up per trial.
    pub given_up: MeanCi,
    /// Behaviors given up per trial that the trial's operator trusts (in its trustworthy
    /// region, [`crate::reference::known_operator::KnownOperator::trusted`], learned without goal
    /// changes): given up wrongly. `None` without the experiment's limit.
    pub wrongly_given_up: Option<MeanCi>,
    /// Untrustworthy commands per trial that were about the behavior: those the adapter
    /// counted, less the unsaid goal changes it counted among them.
    pub untrustworthy_about_behavior: MeanCi,
    /// The trials' goal changes pooled (`None`: the experiment has none).
    pub record: Option<GoalChangeRecord>,
}

impl ArmGoalChanges {
    /// The figures of `arm`'s trials, judged against `limit`'s regions when given.
    pub fn of(arm: &ArmResult, space: &BehaviorSpace, limit: Option<&ExperimentLimit>) -> Self {
        let per_trial = |f: &dyn Fn(&TrialRecord) -> f64| {
            mean_ci95_or_zero(&arm.trials.iter().map(f).collect::<Vec<f64>>())
        };
        let unsaid = |t: &TrialRecord| t.goal_changes.map_or(0, |r| r.unsaid());
        Self {
            given_up: per_trial(&|t| t.report.evaluated.len() as f64),
            wrongly_given_up: limit.map(|limit| {
                per_trial(&|t| {
                    t.report
                        .evaluated
                        .iter()
                        .filter(|e| {
                            limit.trusts(&t.operator, space.rank(&e.behavior)) == Some(true)
                        })
                        .count() as f64
                })
            }),
            untrustworthy_about_behavior: per_trial(&|t| {
                t.report.untrustworthy.saturating_sub(u64::from(unsaid(t))) as f64
            }),
            record: arm
                .trials
                .iter()
                .map(|t| t.goal_changes)
                .reduce(|a, b| Some(a?.plus(b?)))
                .flatten(),
        }
    }
}

/// Whether any trial of `arms` ran with goal changes.
pub fn any_goal_changes<'a>(mut arms: impl Iterator<Item = &'a ArmResult>) -> bool {
    arms.any(|arm| arm.trials.iter().any(|t| t.goal_changes.is_some()))
}
