//! What a mission suite reports of the robot's judgement of its own competence, on a plan
//! with a competence standard (docs/missions.md, "Overtrust, second design"): per arm,
//! how often its operators trusted a behavior that was truly not competent (overtrust),
//! how often the robot judged so, how its overtrust alerts fell, and the harm done; and,
//! for an arm preferring competent behaviors beside the arm it is built on
//! ([`crate::PREFERS_COMPETENT`]), what the preference cut and cost, paired by mission.

use crate::experiment::arm_name::ArmName;
use crate::experiment::arm_name::NameOptions;
use crate::mission::{CalibrationRecord, MissionArmResult};
use crate::stats::{MeanCi, mean_ci95_or_zero, wilcoxon_signed_rank};
use crate::targets::{
    FALSE_OVERTRUST_ALERTS, PREFERENCE_COST, PREFERENCE_HARM_CUT, PREFERENCE_SIGNIFICANCE,
};
use serde_json::{Value, json};
use std::fmt::Write as _;

/// One arm's calibration over its missions.
#[derive(Clone, Debug, PartialEq)]
pub struct CalibrationSummary {
    /// The arm's name.
    pub arm: ArmName,
    /// Whether the operator answered the robot's alerts.
    pub answers_alerts: bool,
    /// Missions run.
    pub missions: usize,
    /// The commands of watched behaviors, summed over the missions.
    pub totals: CalibrationRecord,
    /// Overtrust alerts per mission.
    pub alerts: MeanCi,
    /// Missions with an overtrust alert on a truly competent behavior.
    pub false_alert_missions: usize,
    /// Missions in which a truly competent behavior was watched.
    pub competent_missions: usize,
    /// Harm per mission.
    pub harm: MeanCi,
}

impl CalibrationSummary {
    /// The summary of `arm`'s missions; `None` when they carry no calibration (a plan
    /// without a competence standard).
    pub fn of(arm: &MissionArmResult) -> Option<Self> {
        let records: Vec<&CalibrationRecord> = arm
            .missions
            .iter()
            .map(|m| m.calibration.as_ref())
            .collect::<Option<_>>()?;
        let mut totals = CalibrationRecord::default();
        for r in &records {
            totals.watched += r.watched;
            totals.overtrusted += r.overtrusted;
            totals.judged += r.judged;
            totals.both += r.both;
            totals.competent += r.competent;
            totals.offered += r.offered;
            totals.taken += r.taken;
        }
        let alerts: Vec<f64> = records.iter().map(|r| r.alerts.len() as f64).collect();
        Some(Self {
            arm: arm.arm.clone(),
            answers_alerts: arm.answers_alerts,
            missions: records.len(),
            totals,
            alerts: mean_ci95_or_zero(&alerts),
            false_alert_missions: records.iter().filter(|r| r.false_alerts() > 0).count(),
            competent_missions: records.iter().filter(|r| r.competent > 0).count(),
            harm: mean_ci95_or_zero(&arm.harms()),
        })
    }

    /// The arm's name, and whether alerts were answered.
    fn label(&self) -> String {
        if self.answers_alerts {
            format!("{}, alerts answered", self.arm)
        } else {
            self.arm.to_string()
        }
    }

    /// The share of missions with a competent watched behavior that had a false alert.
    pub fn false_alert_rate(&self) -> Option<f64> {
        (self.competent_missions > 0)
            .then(|| self.false_alert_missions as f64 / self.competent_missions as f64)
    }
}

/// What preferring competent behaviors did to an arm, on the same missions.
#[derive(Clone, Debug, PartialEq)]
pub struct Preference {
    /// The arm preferring competent behaviors.
    pub arm: ArmName,
    /// The arm it is built on.
    pub base: ArmName,
    /// Whether the operator answered the robot's alerts (both arms alike).
    pub answers_alerts: bool,
    /// Harm per mission of the base arm and of the preferring one.
    pub harm: (MeanCi, MeanCi),
    /// The share of the base arm's harm the preference removed (negative: it added harm).
    pub harm_cut: f64,
    /// The preferring arm's untrustworthy commands over the base arm's.
    pub untrustworthy_ratio: f64,
    /// The Wilcoxon signed-rank p-value of the paired harm differences.
    pub wilcoxon_p: f64,
}

impl Preference {
    /// The preference of every arm named `X+competent` whose base `X` ran beside it (with
    /// alerts answered alike).
    pub fn all(arms: &[MissionArmResult]) -> Vec<Self> {
        arms.iter()
            .filter_map(|arm| {
                let options = arm.arm.options();
                let base_name = arm.arm.with_options(NameOptions {
                    prefers_competent: false,
                    ..options
                });
                let base = arms.iter().find(|b| {
                    options.prefers_competent
                        && b.arm == base_name
                        && b.answers_alerts == arm.answers_alerts
                })?;
                Some(Self::between(base, arm))
            })
            .collect()
    }

    fn between(base: &MissionArmResult, arm: &MissionArmResult) -> Self {
        let untrustworthy = |a: &MissionArmResult| -> f64 {
            a.missions.iter().map(|m| f64::from(m.untrustworthy)).sum()
        };
        let (without, with) = (base.harms(), arm.harms());
        let (before, after) = (mean_ci95_or_zero(&without), mean_ci95_or_zero(&with));
        let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { f64::NAN };
        Self {
            arm: arm.arm.clone(),
            base: base.arm.clone(),
            answers_alerts: arm.answers_alerts,
            harm: (before, after),
            harm_cut: 1.0 - ratio(after.mean, before.mean),
            untrustworthy_ratio: ratio(untrustworthy(arm), untrustworthy(base)),
            wilcoxon_p: wilcoxon_signed_rank(&without, &with).unwrap_or(1.0),
        }
    }

    /// The target, checked.
    fn target(&self) -> String {
        let (cut, cost) = (PREFERENCE_HARM_CUT, PREFERENCE_COST);
        let met = self.harm_cut >= cut
            && self.untrustworthy_ratio <= cost
            && self.wilcoxon_p < PREFERENCE_SIGNIFICANCE;
        format!(
            "{}{}: harm per mission {:.2} -> {:.2} against `{}` ({:+.0}%, paired Wilcoxon p = {:.2e}) at {:.2} x its untrustworthy commands (target: a cut of at least {:.0}% at most {cost} x, significant): {}",
            self.arm,
            if self.answers_alerts {
                ", alerts answered"
            } else {
                ""
            },
            self.harm.0.mean,
            self.harm.1.mean,
            self.base,
            -100.0 * self.harm_cut,
            self.wilcoxon_p,
            self.untrustworthy_ratio,
            100.0 * cut,
            if met { "met" } else { "missed" }
        )
    }
}

/// `part / whole` as a percentage, `-` for nothing.
fn percent(part: u32, whole: u32) -> String {
    if whole == 0 {
        "-".to_owned()
    } else {
        format!("{:.1}%", 100.0 * f64::from(part) / f64::from(whole))
    }
}

/// The calibration section of a plan's report, `None` without a competence standard.
pub fn calibration_markdown(arms: &[MissionArmResult]) -> Option<String> {
    let summaries: Vec<CalibrationSummary> = arms
        .iter()
        .map(CalibrationSummary::of)
        .collect::<Option<_>>()?;
    let mut md = String::from(
        "\nThe robot's own competence (commands of a settled behavior; overtrust: the operator's estimate at the trustworthy threshold while the behavior is truly not competent under the plan's standard):\n\n| arm | watched commands | of a competent behavior | overtrusted | judged overtrust by the robot | of the overtrusted, judged so | of those judged, overtrusted | overtrust alerts per mission | missions with a false overtrust alert | harm per mission |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for s in &summaries {
        let t = &s.totals;
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {:.2} ± {:.2} | {} | {:.2} ± {:.2} |",
            s.label(),
            t.watched,
            percent(t.competent, t.watched),
            percent(t.overtrusted, t.watched),
            percent(t.judged, t.watched),
            percent(t.both, t.overtrusted),
            percent(t.both, t.judged),
            s.alerts.mean,
            s.alerts.ci95,
            match s.false_alert_rate() {
                Some(rate) => format!(
                    "{} of {} ({:.1}%)",
                    s.false_alert_missions,
                    s.competent_missions,
                    100.0 * rate
                ),
                None => "-".to_owned(),
            },
            s.harm.mean,
            s.harm.ci95,
        );
    }
    md.push('\n');
    for s in summaries.iter().filter(|s| s.totals.offered > 0) {
        let _ = writeln!(
            md,
            "- {}: {} answered alerts offered a safer behavior; the operator took {} ({}), trusting it too",
            s.label(),
            s.totals.offered,
            s.totals.taken,
            percent(s.totals.taken, s.totals.offered)
        );
    }
    for s in summaries.iter().filter(|s| !s.answers_alerts) {
        let _ = writeln!(md, "- {}", false_alert_target(s));
    }
    for preference in Preference::all(arms) {
        let _ = writeln!(md, "- {}", preference.target());
    }
    Some(md)
}

/// The target on false overtrust alerts, checked on one arm's summary.
fn false_alert_target(s: &CalibrationSummary) -> String {
    match s.false_alert_rate() {
        Some(rate) => format!(
            "{}: false overtrust alerts on {:.1}% of the missions whose watched behavior was competent (target at most {:.0}%): {}",
            s.arm,
            100.0 * rate,
            100.0 * FALSE_OVERTRUST_ALERTS,
            if rate <= FALSE_OVERTRUST_ALERTS {
                "met"
            } else {
                "missed"
            }
        ),
        None => format!(
            "{}: no mission watched a competent behavior, so no false overtrust alert could be judged",
            s.arm
        ),
    }
}

/// The calibration of `arm` (one of the plan's `arms`) for `summary.json`, with what the
/// preference for competent behaviors did for an arm that has one; `None` without a
/// competence standard.
pub fn calibration_json(arm: &MissionArmResult, arms: &[MissionArmResult]) -> Option<Value> {
    let s = CalibrationSummary::of(arm)?;
    let t = &s.totals;
    let mut calibration = json!({
        "watched": t.watched,
        "competent": t.competent,
        "overtrusted": t.overtrusted,
        "judged": t.judged,
        "overtrusted_and_judged": t.both,
        "alerts_per_mission": s.alerts,
        "missions_with_a_false_alert": s.false_alert_missions,
        "missions_with_a_competent_behavior": s.competent_missions,
        "target": (!s.answers_alerts).then(|| false_alert_target(&s)),
        "preference": Preference::all(arms)
            .into_iter()
            .find(|p| p.arm == arm.arm && p.answers_alerts == arm.answers_alerts)
            .map(|p| json!({
            "base": p.base,
            "harm_per_mission": {"base": p.harm.0.mean, "preferring": p.harm.1.mean},
            "harm_cut": p.harm_cut,
            "untrustworthy_ratio": p.untrustworthy_ratio,
            "wilcoxon_p": p.wilcoxon_p,
            "target": p.target(),
        })),
    });
    // Only where an answered alert offered something, so other reports stay as they were.
    if t.offered > 0 {
        calibration["offers"] = json!({ "offered": t.offered, "taken": t.taken });
    }
    Some(calibration)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mission::{MissionRecord, MissionTrace};

    fn mission(calibration: Option<CalibrationRecord>, failures: u32) -> MissionRecord {
        MissionRecord {
            mission: 0,
            learned_start: None,
            context: Default::default(),
            changes: Vec::new(),
            readaptations: 0,
            false_alarms: 0,
            alerts: Vec::new(),
            onsets: Vec::new(),
            failures,
            overlooked: 0,
            untrustworthy: 0,
            calibration,
        }
    }

    #[test]
    fn a_preference_is_its_arm_against_the_arm_it_is_built_on_mission_by_mission() {
        let arm = |name: &str, harms: &[u32], untrustworthy: u32| MissionArmResult {
            arm: name.parse().unwrap(),
            answers_alerts: false,
            missions: harms
                .iter()
                .map(|&h| MissionRecord {
                    untrustworthy,
                    ..mission(Some(CalibrationRecord::default()), h)
                })
                .collect(),
            traced: MissionTrace::default(),
        };
        let base: Vec<u32> = (1..=12).map(|k| 2 * k).collect();
        let halved: Vec<u32> = (1..=12).collect();
        let arms = [
            arm("uniform", &base, 10),
            arm("uniform+competent", &halved, 11),
            arm("case-based+competent", &[1; 12], 1),
        ];
        // Only a preferring arm whose base ran beside it.
        let [p] = Preference::all(&arms).try_into().unwrap();
        assert_eq!(
            (p.arm.as_str(), p.base.as_str()),
            ("uniform+competent", "uniform")
        );
        // Harm 13 -> 6.5: half cut; 132 untrustworthy commands against 120.
        assert_eq!((p.harm.0.mean, p.harm.1.mean), (13.0, 6.5));
        assert_eq!(p.harm_cut, 0.5);
        assert!((p.untrustworthy_ratio - 1.1).abs() < 1e-12);
        // Twelve positive differences 1..12: W = 78 against 39 expected, sd sqrt(162.5):
        // z = 3.06, p = 0.0022.
        assert!((p.wilcoxon_p - 0.0022).abs() < 1e-4, "{}", p.wilcoxon_p);
        assert!(p.target().ends_with(": met"), "{}", p.target());
        let json = calibration_json(&arms[1], &arms).unwrap();
        assert_eq!(json["preference"]["base"], "uniform");
        assert_eq!(
            calibration_json(&arms[0], &arms).unwrap()["preference"],
            Value::Null
        );
    }

    #[test]
    fn a_summary_sums_the_watched_commands_and_counts_false_alerts_by_mission() {
        let calibrated = |watched, competent, alerts: Vec<(u32, bool)>| CalibrationRecord {
            watched,
            overtrusted: watched - competent,
            judged: 2,
            both: 1,
            competent,
            offered: alerts.len() as u32,
            taken: u32::from(competent > 0),
            alerts,
        };
        let arm = MissionArmResult {
            arm: "a".parse().unwrap(),
            answers_alerts: false,
            missions: vec![
                mission(Some(calibrated(10, 10, vec![(3, true)])), 1),
                mission(Some(calibrated(10, 4, vec![(5, false), (9, true)])), 3),
                mission(Some(calibrated(6, 0, vec![])), 2),
            ],
            traced: MissionTrace::default(),
        };
        let s = CalibrationSummary::of(&arm).unwrap();
        assert_eq!(
            (s.totals.watched, s.totals.competent, s.totals.overtrusted),
            (26, 14, 12)
        );
        assert_eq!((s.totals.judged, s.totals.both), (6, 3));
        assert_eq!((s.totals.offered, s.totals.taken), (3, 2));
        assert_eq!(s.alerts.mean, 1.0);
        // Two missions watched a competent behavior; both had a false alert.
        assert_eq!((s.false_alert_missions, s.competent_missions), (2, 2));
        assert_eq!(s.false_alert_rate(), Some(1.0));
        assert_eq!(s.harm.mean, 2.0);
        let md = calibration_markdown(std::slice::from_ref(&arm)).unwrap();
        assert!(
            md.contains("| a | 26 | 53.8% | 46.2% | 23.1% | 25.0% | 50.0% | 1.00 ± "),
            "{md}"
        );
        assert!(md.contains("(target at most 5%): missed"), "{md}");
        assert!(
            md.contains(
                "- a: 3 answered alerts offered a safer behavior; the operator took 2 (66.7%)"
            ),
            "{md}"
        );
        // Without a standard: nothing.
        let blind = MissionArmResult {
            missions: vec![mission(None, 0)],
            ..arm
        };
        assert_eq!(calibration_markdown(&[blind]), None);
    }
}
