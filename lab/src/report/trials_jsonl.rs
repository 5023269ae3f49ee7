//! `trials.jsonl`: one JSON line per trial, experiments and arms in order, with each
//! given-up behavior's attributed and true reasons.

use super::entry::ReportEntry;
use crate::experiment::goal_change::GoalChangeRecord;
use crate::experiment::record::{GivenUpRecord, TrialRecord};
use cbr_core::{Context, Statement};
use serde::Serialize;
use serde_json::{Map, Value};
use std::collections::BTreeMap;
use trust::Cause;
use trust::named::named_behavior;

#[derive(Serialize)]
struct TrialLine<'a> {
    experiment: &'a str,
    scenario: &'a str,
    operator: &'a str,
    arm: &'a str,
    trial: u32,
    behaviors_evaluated: u64,
    commands: u64,
    untrustworthy: u64,
    found_trustworthy: bool,
    #[serde(rename = "final")]
    final_behavior: Map<String, Value>,
    initial: Map<String, Value>,
    /// Whether the initial behavior was the case memory's guess (left out when not).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    learned_start: bool,
    searched: u32,
    reused: u32,
    retained: bool,
    truncated: bool,
    /// The operator's true reasons for the untrustworthy commands (evaluation only).
    true_causes: &'a BTreeMap<Cause, u32>,
    /// Every behavior given up: the reason its explanation settled on, the most frequent
    /// true reason (evaluation only), and whether it was right.
    given_up: Vec<GivenUpLine>,
    /// The trial's goal changes (evaluation only; left out when the experiment has none).
    #[serde(skip_serializing_if = "Option::is_none")]
    goal_changes: Option<GoalChangeRecord>,
    /// The context the trial ran in (left out when the default one).
    #[serde(skip_serializing_if = "Context::is_default")]
    context: &'a Context,
    /// The context the robot was told, when it differs from the trial's (a robot not
    /// told its context is told the default one).
    #[serde(skip_serializing_if = "Option::is_none")]
    told: Option<&'a Context>,
    /// What the operator stated up front (left out when nothing).
    #[serde(skip_serializing_if = "<[Statement]>::is_empty")]
    stated: &'a [Statement],
    /// Whether the arm did not hear it (left out when it did, or nothing was stated).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    unheard: bool,
}

/// A given-up behavior in `trials.jsonl` (how the next behavior was chosen is counted by
/// the line's `searched` and `reused`; a trial is told whole by `trustcbr explain`).
#[derive(Serialize)]
struct GivenUpLine {
    reason: Option<Cause>,
    truth: Option<Cause>,
    right: bool,
}

impl From<&GivenUpRecord> for GivenUpLine {
    fn from(record: &GivenUpRecord) -> Self {
        Self {
            reason: record.reason,
            truth: record.truth,
            right: record.right,
        }
    }
}

/// `trials.jsonl`: one JSON object per trial, experiments in order, arms in order.
pub fn trials_jsonl(entries: &[ReportEntry<'_>]) -> String {
    let mut out = String::new();
    for e in entries {
        for arm in &e.result.arms {
            let deaf = arm.name.options().ignores_statements;
            for t in &arm.trials {
                let line = trial_line(e, t, deaf);
                out.push_str(&serde_json::to_string(&line).expect("plain data serializes"));
                out.push('\n');
            }
        }
    }
    out
}

/// The line of trial `t`, of an arm that ignores statements when `deaf`.
fn trial_line<'a>(e: &'a ReportEntry<'_>, t: &'a TrialRecord, deaf: bool) -> TrialLine<'a> {
    TrialLine {
        experiment: &e.result.name,
        scenario: e.scenario,
        operator: &t.operator,
        arm: &t.arm,
        trial: t.trial,
        behaviors_evaluated: t.report.behaviors_evaluated,
        commands: t.report.commands,
        untrustworthy: t.report.untrustworthy,
        found_trustworthy: t.report.found_trustworthy,
        final_behavior: named_behavior(e.space, &t.report.settled),
        initial: named_behavior(e.space, &t.initial),
        learned_start: t.learned_start,
        searched: t.report.searched,
        reused: t.report.reused,
        retained: t.report.retained.is_some(),
        truncated: t.truncated,
        true_causes: &t.true_causes,
        given_up: t.given_up.iter().map(GivenUpLine::from).collect(),
        goal_changes: t.goal_changes,
        context: &t.context,
        told: (t.report.context != t.context).then_some(&t.report.context),
        stated: &t.stated,
        unheard: deaf && !t.stated.is_empty(),
    }
}
