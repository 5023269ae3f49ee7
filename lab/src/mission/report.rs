//! What a mission suite reports per arm (docs/missions.md): how it met the changes, its
//! false alarms, its alerts against complacency onsets, the harm done with and without
//! alerts answered, and its untrustworthy commands per change and harm per mission as
//! multiples of the oracle's ([`crate::mission::oracle`]), as tables (`missions.md`), data
//! (`summary.json`, one record per mission in `missions.jsonl`) and a timeline figure per
//! plan.

use crate::mission::calibration::{calibration_json, calibration_markdown};
use crate::mission::contexts::{switch_targets, switches_json, switches_markdown};
use crate::mission::noticing::{noticing_json, noticing_markdown};
use crate::mission::summary::{
    MissionSummary, OracleFigure, OracleSummary, ci, fine_ci, harm_comparisons, interval_json,
    oracle_multiple, share, times,
};
use crate::mission::{DETECTION_WINDOW, MissionResult};
use crate::targets::{FALSE_ALERTS, ONSETS_DETECTED, SIGNIFICANCE};
use serde_json::{Value, json};
use std::fmt::Write as _;

/// The targets of docs/missions.md, checked on a plan's summaries: detection and harm on
/// complacency plans, false alerts on the others. One line each.
pub fn targets(result: &MissionResult, summaries: &[MissionSummary]) -> Vec<String> {
    let mut lines = Vec::new();
    if result.complacency {
        for s in summaries.iter().filter(|s| !s.answers_alerts) {
            let rate = (s.onsets > 0).then(|| s.detected_in_window as f64 / s.onsets as f64);
            lines.push(format!(
                "{}: {} of complacency onsets detected within {DETECTION_WINDOW} commands (target at least {:.0}%): {}",
                s.arm,
                rate.map_or("none".to_owned(), |r| format!("{:.0}%", 100.0 * r)),
                100.0 * ONSETS_DETECTED,
                match rate {
                    Some(r) if r >= ONSETS_DETECTED => "met",
                    Some(_) => "missed",
                    None => "no onset",
                }
            ));
        }
        for h in harm_comparisons(result) {
            let lower = h.difference.mean > 0.0 && h.wilcoxon_p < SIGNIFICANCE;
            lines.push(format!(
                "{}: harm per mission {:.2} without alerts, {:.2} with (paired difference {:.2} ± {:.2}, Wilcoxon p = {:.2e}): {}",
                h.arm,
                h.ignored.mean,
                h.answered.mean,
                h.difference.mean,
                h.difference.ci95,
                h.wilcoxon_p,
                if lower { "lower with alerts, met" } else { "not lower with alerts, missed" }
            ));
        }
    } else {
        for s in summaries {
            let rate = s.missions_alerted as f64 / s.missions.max(1) as f64;
            lines.push(format!(
                "{}: false alerts on {:.1}% of missions without complacency (target at most {:.0}%): {}",
                s.arm,
                100.0 * rate,
                100.0 * FALSE_ALERTS,
                if rate <= FALSE_ALERTS { "met" } else { "missed" }
            ));
        }
    }
    lines
}

/// The markdown tables of every plan (`missions.md`).
pub fn missions_markdown(results: &[MissionResult]) -> String {
    let mut md = String::from("# Missions\n\n");
    for (p, result) in results.iter().enumerate() {
        let summaries: Vec<MissionSummary> = result.arms.iter().map(MissionSummary::of).collect();
        let missions = summaries.first().map_or(0, |s| s.missions);
        let _ = writeln!(md, "## {}\n\n{missions} missions per arm.\n", result.name);
        md.push_str(
            "| arm | changes needing adaptation | adapted to | commands until trusted again | untrustworthy commands per change | re-adaptations per mission | false alarms | missions with an alert | onsets detected within 25 commands | of those with a perceivable problem overlooked | median delay | harm per mission |\n",
        );
        md.push_str("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
        for s in &summaries {
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {} | {:.2} ± {:.2} | {} | {} | {} | {} | {} | {:.2} ± {:.2} |",
                s.label(),
                share(s.needed, s.changes),
                share(s.adapted, s.needed),
                ci(s.trusted_again),
                ci(s.untrustworthy_per_change),
                s.readaptations.mean,
                s.readaptations.ci95,
                s.false_alarms,
                share(s.missions_alerted, s.missions),
                share(s.detected_in_window, s.onsets),
                share(s.perceivable_detected, s.perceivable_onsets),
                s.median_delay.map_or("-".to_owned(), |d| format!("{d:.0}")),
                s.harm.mean,
                s.harm.ci95,
            );
        }
        let oracle = OracleSummary::of(&result.oracle);
        let _ = writeln!(
            md,
            "| oracle | {} | {} | {} | {} | {:.2} ± {:.2} | - | - | - | - | - | {:.2} ± {:.2} |",
            share(oracle.figures.needed, oracle.figures.changes),
            share(oracle.figures.adapted, oracle.figures.needed),
            ci(oracle.figures.trusted_again),
            fine_ci(oracle.figures.untrustworthy_per_change),
            oracle.readaptations.mean,
            oracle.readaptations.ci95,
            oracle.harm.mean,
            oracle.harm.ci95,
        );
        md.push_str(
            "\nAgainst the oracle (told of every change, knowing every operator's landscape; its re-adaptations are the episodes it began at a change; it minimises untrustworthy commands, not harm, so an arm may do less harm than it; multiples with the 95% interval of a paired bootstrap over missions):\n\n| arm | untrustworthy commands per change | × oracle | harm per mission | × oracle |\n|---|---:|---:|---:|---:|\n",
        );
        for (a, s) in summaries.iter().enumerate() {
            let _ = writeln!(
                md,
                "| {} | {} | {} | {:.2} | {} |",
                s.label(),
                ci(s.untrustworthy_per_change),
                times(oracle_multiple(
                    result,
                    p,
                    a,
                    OracleFigure::UntrustworthyPerChange
                )),
                s.harm.mean,
                times(oracle_multiple(result, p, a, OracleFigure::HarmPerMission)),
            );
        }
        let _ = writeln!(
            md,
            "| oracle | {} | 1 | {:.2} | 1 |",
            fine_ci(oracle.figures.untrustworthy_per_change),
            oracle.harm.mean,
        );
        if let Some(section) = noticing_markdown(result) {
            md.push_str(&section);
        }
        if let Some(section) = switches_markdown(result, p) {
            md.push_str(&section);
        }
        md.push('\n');
        for line in targets(result, &summaries)
            .into_iter()
            .chain(switch_targets(result, p))
        {
            let _ = writeln!(md, "- {line}");
        }
        if let Some(section) = calibration_markdown(&result.arms) {
            md.push_str(&section);
        }
        md.push('\n');
    }
    md
}

/// The summaries of every plan (the mission report's `summary.json`).
pub fn missions_json(results: &[MissionResult]) -> Value {
    Value::Array(
        results
            .iter()
            .enumerate()
            .map(|(p, result)| {
                let summaries: Vec<MissionSummary> =
                    result.arms.iter().map(MissionSummary::of).collect();
                let oracle = OracleSummary::of(&result.oracle);
                let mut plan = json!({
                    "plan": result.name,
                    "recommended": crate::RECOMMENDED_ARM,
                    "oracle": {
                        "missions": oracle.missions,
                        "changes": oracle.figures.changes,
                        "needed": oracle.figures.needed,
                        "adapted": oracle.figures.adapted,
                        "commands_until_trusted_again": oracle.figures.trusted_again,
                        "untrustworthy_per_change": oracle.figures.untrustworthy_per_change,
                        "readaptations_per_mission": oracle.readaptations,
                        "harm_per_mission": oracle.harm,
                    },
                    "complacency": result.complacency,
                    "noticing": noticing_json(result),
                    "targets": targets(result, &summaries),
                    "harm_with_and_without_alerts": harm_comparisons(result).iter().map(|h| json!({
                        "arm": h.arm,
                        "ignored": h.ignored,
                        "answered": h.answered,
                        "difference": h.difference,
                        "wilcoxon_p": h.wilcoxon_p,
                    })).collect::<Vec<_>>(),
                    "arms": summaries.iter().zip(&result.arms).enumerate().map(|(a, (s, arm))| {
                        let untrustworthy = oracle_multiple(result, p, a, OracleFigure::UntrustworthyPerChange);
                        let harm = oracle_multiple(result, p, a, OracleFigure::HarmPerMission);
                        let mut summary = json!({
                        "arm": s.arm,
                        "answers_alerts": s.answers_alerts,
                        "missions": s.missions,
                        "changes": s.changes,
                        "needed": s.needed,
                        "adapted": s.adapted,
                        "commands_until_trusted_again": s.trusted_again,
                        "untrustworthy_per_change": s.untrustworthy_per_change,
                        "readaptations_per_mission": s.readaptations,
                        "false_alarms": s.false_alarms,
                        "missions_alerted": s.missions_alerted,
                        "onsets": s.onsets,
                        "detected_within_25": s.detected_in_window,
                        "perceivable_onsets": s.perceivable_onsets,
                        "perceivable_detected_within_25": s.perceivable_detected,
                        "median_detection_delay": s.median_delay,
                        "harm_per_mission": s.harm,
                        "untrustworthy_per_change_x_oracle": untrustworthy.map(|m| m.ratio),
                        "untrustworthy_per_change_x_oracle_ci95": interval_json(untrustworthy),
                        "harm_per_mission_x_oracle": harm.map(|m| m.ratio),
                        "harm_per_mission_x_oracle_ci95": interval_json(harm),
                        });
                        // Only a plan with a competence standard has a calibration.
                        if let Some(calibration) = calibration_json(arm, &result.arms) {
                            summary["calibration"] = calibration;
                        }
                        summary
                    }).collect::<Vec<_>>(),
                });
                if let Some(switches) = switches_json(result, p) {
                    plan["context_switches"] = switches;
                }
                plan
            })
            .collect(),
    )
}

/// One JSON line per mission of every arm (`missions.jsonl`).
pub fn missions_jsonl(results: &[MissionResult]) -> String {
    let mut out = String::new();
    for result in results {
        for arm in &result.arms {
            for m in &arm.missions {
                let line = json!({
                    "plan": result.name,
                    "arm": arm.arm,
                    "answers_alerts": arm.answers_alerts,
                    "harm": m.harm(),
                    "record": m,
                });
                out.push_str(&line.to_string());
                out.push('\n');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mission::record::{
        ChangeKind, ChangeRecord, MissionArmResult, MissionRecord, MissionTrace, OnsetRecord,
        OracleRecord,
    };

    fn mission(changes: Vec<ChangeRecord>, onsets: Vec<OnsetRecord>, harm: u32) -> MissionRecord {
        MissionRecord {
            mission: 0,
            learned_start: None,
            context: Default::default(),
            changes,
            readaptations: 1,
            false_alarms: 1,
            alerts: vec![3],
            onsets,
            failures: harm,
            overlooked: 0,
            untrustworthy: 0,
            calibration: None,
        }
    }

    fn change(needed: bool, trusted_again: Option<u32>, untrustworthy: u32) -> ChangeRecord {
        ChangeRecord {
            at: 10,
            kind: ChangeKind::Shift,
            needed,
            trusted_again,
            untrustworthy,
            back: false,
            start: None,
            noticed: None,
        }
    }

    #[test]
    fn a_summary_by_hand() {
        let arm = MissionArmResult {
            arm: "a".parse().unwrap(),
            answers_alerts: false,
            missions: vec![
                mission(
                    vec![change(true, Some(20), 4), change(false, None, 0)],
                    vec![OnsetRecord {
                        at: 5,
                        detected_after: Some(10),
                        perceivable: 1,
                    }],
                    2,
                ),
                mission(
                    vec![change(true, None, 8), change(true, Some(40), 6)],
                    vec![
                        OnsetRecord {
                            at: 5,
                            detected_after: Some(30),
                            perceivable: 0,
                        },
                        OnsetRecord {
                            at: 50,
                            detected_after: None,
                            perceivable: 2,
                        },
                    ],
                    4,
                ),
            ],
            traced: MissionTrace::default(),
        };
        let s = MissionSummary::of(&arm);
        assert_eq!((s.changes, s.needed, s.adapted), (4, 3, 2));
        assert_eq!(s.trusted_again.unwrap().mean, 30.0);
        assert_eq!(s.untrustworthy_per_change.unwrap().mean, 4.5);
        assert_eq!((s.false_alarms, s.missions_alerted), (2, 2));
        assert_eq!((s.onsets, s.detected_in_window), (3, 1));
        assert_eq!((s.perceivable_onsets, s.perceivable_detected), (2, 1));
        assert_eq!(s.median_delay, Some(20.0));
        assert_eq!(s.harm.mean, 3.0);
        let answered = MissionArmResult {
            answers_alerts: true,
            missions: vec![
                mission(Vec::new(), Vec::new(), 1),
                mission(Vec::new(), Vec::new(), 1),
            ],
            ..arm.clone()
        };
        let result = MissionResult {
            name: "p".into(),
            complacency: true,
            context_switches: false,
            arms: vec![arm, answered],
            oracle: Vec::new(),
        };
        let [h] = harm_comparisons(&result).try_into().unwrap();
        assert_eq!(
            (h.ignored.mean, h.answered.mean, h.difference.mean),
            (3.0, 1.0, 2.0)
        );
        let lines = targets(&result, std::slice::from_ref(&s));
        // The oracle on the same two missions: 1.5 untrustworthy commands per change (3 and
        // 0 in each) and 1 harm per mission, so the arm's 4.5 and 3.0 are 3 times its
        // figures. Over missions the arm's untrustworthy commands are 4 and 14 against the
        // oracle's 3 and 3: a resample of the first mission twice gives 8 / 6, of the
        // second twice 28 / 6, each a quarter of the time, so the interval runs from 4/3
        // to 14/3.
        let oracle_record = |changes: Vec<ChangeRecord>, failures| OracleRecord {
            mission: 0,
            changes,
            readaptations: 1,
            failures,
            overlooked: 0,
            untrustworthy: 3,
        };
        let seen = || oracle_record(vec![change(true, Some(5), 3), change(false, None, 0)], 1);
        let oracle = OracleSummary::of(&[seen(), seen()]);
        assert_eq!(oracle.figures.untrustworthy_per_change.unwrap().mean, 1.5);
        assert_eq!((oracle.figures.needed, oracle.figures.adapted), (2, 2));
        let with_oracle = |oracle: Vec<OracleRecord>| MissionResult {
            oracle,
            ..result.clone()
        };
        let paired = with_oracle(vec![seen(), seen()]);
        let untrustworthy =
            oracle_multiple(&paired, 0, 0, OracleFigure::UntrustworthyPerChange).unwrap();
        assert!((untrustworthy.ratio - 3.0).abs() < 1e-12);
        assert!((untrustworthy.low - 4.0 / 3.0).abs() < 1e-12);
        assert!((untrustworthy.high - 14.0 / 3.0).abs() < 1e-12);
        let harm = oracle_multiple(&paired, 0, 0, OracleFigure::HarmPerMission).unwrap();
        assert!((harm.ratio - 3.0).abs() < 1e-12);
        assert_eq!(
            times(Some(harm)),
            format!("3.0 [{:.1}, {:.1}]", harm.low, harm.high)
        );
        // An oracle that endured nothing and did no harm has no multiple.
        let flawless = || oracle_record(vec![change(false, None, 0)], 0);
        let flawless = with_oracle(vec![flawless(), flawless()]);
        assert_eq!(
            oracle_multiple(&flawless, 0, 0, OracleFigure::UntrustworthyPerChange),
            None
        );
        assert_eq!(
            oracle_multiple(&flawless, 0, 0, OracleFigure::HarmPerMission),
            None
        );
        assert_eq!(times(None), "-");
        assert!(lines[0].contains("33% of complacency onsets") && lines[0].ends_with("missed"));
    }
}
