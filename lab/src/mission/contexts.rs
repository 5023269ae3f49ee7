//! What announced context switches cost each arm of a mission plan
//! (docs/missions.md#context-switches): its untrustworthy commands per switch, and per
//! switch back to a context the mission was in before, as multiples of the oracle's
//! ([`crate::mission::oracle`]); each arm told its context against its twin blind to it
//! (`NAME+context-blind`), switch by switch on the same missions; and the switches back of
//! each told arm by what it went on with ([`SwitchStart`]), beside what the oracle paid
//! on the same switches, which says where an arm's excess over the oracle comes from.

use crate::experiment::arm_name::ArmName;
use crate::experiment::trial_contexts::blind_twin;
use crate::mission::record::OracleRecord;
use crate::mission::summary::{
    ChangeFigures, OracleFigure, arm_label, fine_ci, interval_json, oracle_multiple, times,
};
use crate::mission::{ChangeKind, ChangeRecord, MissionArmResult, MissionResult};
use crate::stats::{MeanCi, RatioCi, mean_ci95_or_zero, wilcoxon_signed_rank};
use crate::targets::{SIGNIFICANCE, SWITCH_BACK_TIMES_ORACLE};
use serde_json::{Value, json};
use std::fmt::Write as _;
use trust::SwitchStart;

/// How one agent (an arm or the oracle) met a plan's context switches.
#[derive(Clone, Debug, PartialEq)]
pub struct SwitchFigures {
    /// Every switch.
    pub all: ChangeFigures,
    /// The switches back to a context the mission was in before.
    pub back: ChangeFigures,
}

impl SwitchFigures {
    /// The figures of the context switches among `changes`.
    pub fn of<'a>(changes: impl IntoIterator<Item = &'a ChangeRecord>) -> Self {
        let switches: Vec<&ChangeRecord> = changes
            .into_iter()
            .filter(|c| c.kind == ChangeKind::Context)
            .collect();
        Self {
            all: ChangeFigures::of(switches.iter().copied()),
            back: ChangeFigures::of(switches.iter().copied().filter(|c| c.back)),
        }
    }

    /// The mean untrustworthy commands per switch back, if there was one.
    fn per_switch_back(&self) -> Option<f64> {
        self.back.untrustworthy_per_change.map(|v| v.mean)
    }
}

/// The untrustworthy commands of each switch back of `arm`, in mission order.
fn switches_back_of(arm: &MissionArmResult) -> Vec<f64> {
    arm.missions
        .iter()
        .flat_map(|m| &m.changes)
        .filter(|c| c.kind == ChangeKind::Context && c.back)
        .map(|c| f64::from(c.untrustworthy))
        .collect()
}

/// A told arm's switches back on which it went on the same way, and what they cost it
/// and the oracle (on the same switches of the same missions).
#[derive(Clone, Debug, PartialEq)]
pub struct SwitchesBackFrom {
    /// What the arm went on with.
    pub start: SwitchStart,
    /// Switches back it went on this way.
    pub switches: usize,
    /// Of those, switches after which the behavior in use was not trustworthy.
    pub needed: usize,
    /// The arm's untrustworthy commands per switch back.
    pub untrustworthy: MeanCi,
    /// The oracle's on the same switches.
    pub oracle: MeanCi,
}

/// The switches back of `arm` by what it went on with ([`SwitchStart`], in its order of
/// declaration; kinds it never chose are left out), each beside the oracle's cost on the
/// same switches. Empty for an arm blind to its context (it is never told of a switch).
pub fn switches_back_by_start(
    arm: &MissionArmResult,
    oracle: &[OracleRecord],
) -> Vec<SwitchesBackFrom> {
    let mut paired: Vec<(SwitchStart, &ChangeRecord, &ChangeRecord)> = Vec::new();
    // An arm's missions and the oracle's are the same missions, in the same order.
    for (mission, reference) in arm.missions.iter().zip(oracle) {
        debug_assert_eq!(mission.mission, reference.mission);
        for (change, theirs) in mission.changes.iter().zip(&reference.changes) {
            if let Some(start) = change.start.filter(|_| change.back) {
                debug_assert_eq!((change.at, change.kind), (theirs.at, theirs.kind));
                paired.push((start, change, theirs));
            }
        }
    }
    [
        SwitchStart::Kept,
        SwitchStart::Resumed,
        SwitchStart::Guessed,
        SwitchStart::Restarted,
    ]
    .into_iter()
    .filter_map(|start| {
        let these: Vec<_> = paired.iter().filter(|p| p.0 == start).collect();
        if these.is_empty() {
            return None;
        }
        let of = |pick: fn(&(SwitchStart, &ChangeRecord, &ChangeRecord)) -> u32| {
            mean_ci95_or_zero(&these.iter().map(|p| f64::from(pick(p))).collect::<Vec<_>>())
        };
        Some(SwitchesBackFrom {
            start,
            switches: these.len(),
            needed: these.iter().filter(|p| p.1.needed).count(),
            untrustworthy: of(|p| p.1.untrustworthy),
            oracle: of(|p| p.2.untrustworthy),
        })
    })
    .collect()
}

/// How a report names a [`SwitchStart`]: as `missions.jsonl` spells it.
fn start_name(start: SwitchStart) -> String {
    json!(start).as_str().unwrap_or_default().to_owned()
}

/// An arm told its context against its blind twin, over the switches back: the same
/// switches at the same commands of the same missions, paired one by one.
#[derive(Clone, Debug, PartialEq)]
pub struct VersusBlindTwin {
    /// The arm told its context.
    pub arm: ArmName,
    /// Its twin blind to the context.
    pub twin: ArmName,
    /// The switches back paired.
    pub switches: usize,
    /// The told arm's untrustworthy commands per switch back.
    pub told: MeanCi,
    /// The twin's.
    pub blind: MeanCi,
    /// The paired difference, told minus blind.
    pub difference: MeanCi,
    /// The Wilcoxon signed-rank test's p-value (1 when every pair ties).
    pub wilcoxon_p: f64,
}

/// Every arm of `result` told its context against its blind twin, where the plan runs
/// both (and they met the same switches, as arms of one plan do).
pub fn versus_blind_twins(result: &MissionResult) -> Vec<VersusBlindTwin> {
    result
        .arms
        .iter()
        .filter_map(|told| {
            let name = blind_twin(&told.arm)?;
            let twin = result
                .arms
                .iter()
                .find(|a| a.arm == name && a.answers_alerts == told.answers_alerts)?;
            let (a, b) = (switches_back_of(told), switches_back_of(twin));
            if a.len() != b.len() {
                return None;
            }
            let difference: Vec<f64> = a.iter().zip(&b).map(|(x, y)| x - y).collect();
            Some(VersusBlindTwin {
                arm: told.arm.clone(),
                twin: twin.arm.clone(),
                switches: a.len(),
                told: mean_ci95_or_zero(&a),
                blind: mean_ci95_or_zero(&b),
                difference: mean_ci95_or_zero(&difference),
                wilcoxon_p: wilcoxon_signed_rank(&a, &b).unwrap_or(1.0),
            })
        })
        .collect()
}

/// The targets on a plan with context switches (docs/missions.md#context-switches): the
/// best arm's untrustworthy commands per switch back at most 1.5 times the oracle's, and
/// each arm told its context fewer than its blind twin (paired, significant). One line
/// each; none for a plan without switches.
pub fn switch_targets(result: &MissionResult, plan: usize) -> Vec<String> {
    if !result.context_switches {
        return Vec::new();
    }
    let mut lines = Vec::new();
    let oracle = SwitchFigures::of(result.oracle.iter().flat_map(|m| &m.changes));
    let best = result
        .arms
        .iter()
        .enumerate()
        .filter_map(|(a, arm)| {
            let figures = SwitchFigures::of(arm.missions.iter().flat_map(|m| &m.changes));
            Some((a, arm.arm.as_str(), figures.per_switch_back()?))
        })
        .min_by(|a, b| a.2.total_cmp(&b.2));
    if let (Some((a, arm, value)), Some(reference)) = (best, oracle.per_switch_back()) {
        lines.push(format!(
            "best arm after a switch back ({arm}): {value:.2} untrustworthy commands per switch, {} x the oracle's {reference:.2} (target at most {SWITCH_BACK_TIMES_ORACLE} x): {}",
            times(oracle_multiple(result, plan, a, OracleFigure::UntrustworthyPerSwitchBack)),
            if value <= SWITCH_BACK_TIMES_ORACLE * reference {
                "met"
            } else {
                "missed"
            }
        ));
    }
    for v in versus_blind_twins(result) {
        let better = v.difference.mean < 0.0 && v.wilcoxon_p < SIGNIFICANCE;
        lines.push(format!(
            "{}: {:.2} untrustworthy commands per switch back, its blind twin {:.2} (paired difference {:.2} ± {:.2} over {} switches, Wilcoxon p = {:.2e}): {}",
            v.arm,
            v.told.mean,
            v.blind.mean,
            v.difference.mean,
            v.difference.ci95,
            v.switches,
            v.wilcoxon_p,
            if better { "fewer told, met" } else { "not fewer told, missed" }
        ));
    }
    lines
}

/// The context switches section of a plan's `missions.md`; `None` for a plan without
/// switches.
pub fn switches_markdown(result: &MissionResult, plan: usize) -> Option<String> {
    if !result.context_switches {
        return None;
    }
    let oracle = SwitchFigures::of(result.oracle.iter().flat_map(|m| &m.changes));
    let mut md = String::from(
        "\nAnnounced context switches (the robot is told, unless its arm is blind to its context; a switch back is to a context the mission was in before; multiples of the oracle's with the 95% interval of a paired bootstrap over missions):\n\n| arm | switches needing adaptation | adapted to | untrustworthy commands per switch | × oracle | per switch back | × oracle |\n|---|---:|---:|---:|---:|---:|---:|\n",
    );
    let row = |md: &mut String, label: &str, f: &SwitchFigures, multiples: [String; 2]| {
        let [all, back] = multiples;
        let _ = writeln!(
            md,
            "| {label} | {} of {} | {} | {} | {all} | {} | {back} |",
            f.all.needed,
            f.all.changes,
            f.all.adapted,
            fine_ci(f.all.untrustworthy_per_change),
            fine_ci(f.back.untrustworthy_per_change),
        );
    };
    for (a, arm) in result.arms.iter().enumerate() {
        let multiple = |figure| times(oracle_multiple(result, plan, a, figure));
        row(
            &mut md,
            &arm_label(&arm.arm, arm.answers_alerts),
            &SwitchFigures::of(arm.missions.iter().flat_map(|m| &m.changes)),
            [
                multiple(OracleFigure::UntrustworthyPerSwitch),
                multiple(OracleFigure::UntrustworthyPerSwitchBack),
            ],
        );
    }
    row(&mut md, "oracle", &oracle, ["1".to_owned(), "1".to_owned()]);
    let twins = versus_blind_twins(result);
    if !twins.is_empty() {
        md.push_str("\nTold against blind, switch by switch back (the same switches of the same missions):\n\n| arm | blind twin | switches back | told | blind | told − blind | Wilcoxon p |\n|---|---|---:|---:|---:|---:|---:|\n");
        for v in &twins {
            let _ = writeln!(
                md,
                "| {} | {} | {} | {:.2} | {:.2} | {:.2} ± {:.2} | {:.2e} |",
                v.arm,
                v.twin,
                v.switches,
                v.told.mean,
                v.blind.mean,
                v.difference.mean,
                v.difference.ci95,
                v.wilcoxon_p
            );
        }
    }
    let by_start: Vec<(String, Vec<SwitchesBackFrom>)> = result
        .arms
        .iter()
        .map(|arm| {
            (
                arm_label(&arm.arm, arm.answers_alerts),
                switches_back_by_start(arm, &result.oracle),
            )
        })
        .filter(|(_, rows)| !rows.is_empty())
        .collect();
    if !by_start.is_empty() {
        md.push_str("\nSwitches back by what the told robot went on with (kept: its watched behavior; resumed: the behavior it last settled on in that context; guessed: its case memory's first guess there; restarted: the episode under way, begun again), beside the oracle on the same switches:\n\n| arm | went on with | switches back | needing adaptation | untrustworthy per switch back | oracle, same switches |\n|---|---|---:|---:|---:|---:|\n");
        for (arm, rows) in &by_start {
            for r in rows {
                let _ = writeln!(
                    md,
                    "| {arm} | {} | {} | {} | {:.2} ± {:.2} | {:.2} ± {:.2} |",
                    start_name(r.start),
                    r.switches,
                    r.needed,
                    r.untrustworthy.mean,
                    r.untrustworthy.ci95,
                    r.oracle.mean,
                    r.oracle.ci95
                );
            }
        }
    }
    Some(md)
}

/// A multiple of the oracle's with its interval in `summary.json`.
fn multiple_json(multiple: Option<RatioCi>) -> Value {
    multiple.map_or(
        Value::Null,
        |m| json!({"ratio": m.ratio, "ci95": interval_json(Some(m))}),
    )
}

/// The context switches of a plan in `summary.json`: per arm and for the oracle, the
/// figures of every switch and of the switches back, and each told arm against its
/// blind twin; `None` for a plan without switches.
pub fn switches_json(result: &MissionResult, plan: usize) -> Option<Value> {
    if !result.context_switches {
        return None;
    }
    let figures = |f: &ChangeFigures| {
        json!({
            "switches": f.changes,
            "needed": f.needed,
            "adapted": f.adapted,
            "untrustworthy_per_switch": f.untrustworthy_per_change,
        })
    };
    let both = |f: &SwitchFigures| json!({"all": figures(&f.all), "back": figures(&f.back)});
    Some(json!({
        "oracle": both(&SwitchFigures::of(result.oracle.iter().flat_map(|m| &m.changes))),
        "arms": result.arms.iter().enumerate().map(|(a, arm)| json!({
            "arm": arm.arm,
            "answers_alerts": arm.answers_alerts,
            "figures": both(&SwitchFigures::of(arm.missions.iter().flat_map(|m| &m.changes))),
            "x_oracle": {
                "all": multiple_json(oracle_multiple(result, plan, a, OracleFigure::UntrustworthyPerSwitch)),
                "back": multiple_json(oracle_multiple(result, plan, a, OracleFigure::UntrustworthyPerSwitchBack)),
            },
            "back_by_start": switches_back_by_start(arm, &result.oracle).iter().map(|r| json!({
                "start": start_name(r.start),
                "switches": r.switches,
                "needed": r.needed,
                "untrustworthy_per_switch": r.untrustworthy,
                "oracle_per_switch": r.oracle,
            })).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
        "versus_blind": versus_blind_twins(result).iter().map(|v| json!({
            "arm": v.arm,
            "twin": v.twin,
            "switches_back": v.switches,
            "told": v.told,
            "blind": v.blind,
            "difference": v.difference,
            "wilcoxon_p": v.wilcoxon_p,
        })).collect::<Vec<_>>(),
        "targets": switch_targets(result, plan),
    }))
}
