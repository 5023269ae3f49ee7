//! One arm's missions summed up ([`MissionSummary`]) and the figures every mission table
//! shares: how changes were met ([`ChangeFigures`]), multiples of the oracle
//! ([`OracleFigure`], [`oracle_multiple`]), harm with and without alerts answered
//! ([`HarmComparison`]), and how a figure is printed.

use crate::experiment::arm_name::ArmName;
use crate::mission::record::OracleRecord;
use crate::mission::{
    ChangeKind, ChangeRecord, DETECTION_WINDOW, MissionArmResult, MissionRecord, MissionResult,
};
use crate::seeds::{Purpose, stream};
use crate::stats::{
    MeanCi, RatioCi, mean_ci95, mean_ci95_or_zero, paired_bootstrap_ratio, wilcoxon_signed_rank,
};
use serde_json::{Value, json};

/// One arm's missions summed up.
#[derive(Clone, Debug, PartialEq)]
pub struct MissionSummary {
    /// The arm's name.
    pub arm: ArmName,
    /// Whether the operator answered the robot's alerts.
    pub answers_alerts: bool,
    /// Missions run.
    pub missions: usize,
    /// Changes in all.
    pub changes: usize,
    /// Changes after which the behavior in use was not trustworthy for the new operator.
    pub needed: usize,
    /// Of those, changes after which the robot settled on a trustworthy behavior again
    /// before the next change or the mission's end.
    pub adapted: usize,
    /// Commands from a change until trusted again, over the needed changes adapted to.
    pub trusted_again: Option<MeanCi>,
    /// Untrustworthy commands per change, over every change.
    pub untrustworthy_per_change: Option<MeanCi>,
    /// Re-adaptations per mission.
    pub readaptations: MeanCi,
    /// Re-adaptations without any change since the behavior settled, in all.
    pub false_alarms: u32,
    /// Missions with at least one alert.
    pub missions_alerted: usize,
    /// Complacency onsets in all.
    pub onsets: usize,
    /// Of those, onsets an alert followed within [`DETECTION_WINDOW`] commands.
    pub detected_in_window: usize,
    /// Onsets during which, before any alert, the operator overlooked a problem that came
    /// with something the robot perceived (detectable in principle).
    pub perceivable_onsets: usize,
    /// Of those, onsets an alert followed within [`DETECTION_WINDOW`] commands.
    pub perceivable_detected: usize,
    /// The median detection delay (commands) of the onsets detected at all.
    pub median_delay: Option<f64>,
    /// Harm per mission (failures and problems nobody noticed).
    pub harm: MeanCi,
}

pub(crate) fn median(mut values: Vec<f64>) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    values.sort_by(f64::total_cmp);
    let n = values.len();
    Some(if n % 2 == 1 {
        values[n / 2]
    } else {
        (values[n / 2 - 1] + values[n / 2]) / 2.0
    })
}

/// The operator changes among `changes` (the context switches are reported apart:
/// [`crate::mission::contexts`]).
pub(crate) fn operator_changes<'a>(
    changes: impl IntoIterator<Item = &'a ChangeRecord>,
) -> impl Iterator<Item = &'a ChangeRecord> {
    changes
        .into_iter()
        .filter(|c| c.kind != ChangeKind::Context)
}

/// How an agent met a plan's changes: the figures an arm and the oracle share.
#[derive(Clone, Debug, PartialEq)]
pub struct ChangeFigures {
    /// Changes in all.
    pub changes: usize,
    /// Changes after which the behavior in use was not trustworthy for the new operator.
    pub needed: usize,
    /// Of those, changes after which a trustworthy behavior was settled on again before the
    /// next change or the mission's end.
    pub adapted: usize,
    /// Commands from a change until trusted again, over the needed changes adapted to.
    pub trusted_again: Option<MeanCi>,
    /// Untrustworthy commands per change, over every change.
    pub untrustworthy_per_change: Option<MeanCi>,
}

impl ChangeFigures {
    /// The figures of these changes.
    pub fn of<'a>(changes: impl IntoIterator<Item = &'a ChangeRecord>) -> Self {
        let changes: Vec<&ChangeRecord> = changes.into_iter().collect();
        let needed: Vec<_> = changes.iter().filter(|c| c.needed).collect();
        let again: Vec<f64> = needed
            .iter()
            .filter_map(|c| c.trusted_again.map(f64::from))
            .collect();
        let per_change: Vec<f64> = changes.iter().map(|c| f64::from(c.untrustworthy)).collect();
        Self {
            changes: changes.len(),
            needed: needed.len(),
            adapted: again.len(),
            trusted_again: mean_ci95(&again),
            untrustworthy_per_change: mean_ci95(&per_change),
        }
    }
}

/// The oracle's missions of a plan summed up.
#[derive(Clone, Debug, PartialEq)]
pub struct OracleSummary {
    /// Missions run.
    pub missions: usize,
    /// How it met the changes.
    pub figures: ChangeFigures,
    /// Episodes it began at a change, per mission.
    pub readaptations: MeanCi,
    /// Harm per mission.
    pub harm: MeanCi,
}

impl OracleSummary {
    /// Sums up the oracle's `missions`.
    pub fn of(missions: &[OracleRecord]) -> Self {
        let per_mission = |f: fn(&OracleRecord) -> f64| {
            mean_ci95_or_zero(&missions.iter().map(f).collect::<Vec<_>>())
        };
        Self {
            missions: missions.len(),
            figures: ChangeFigures::of(operator_changes(missions.iter().flat_map(|m| &m.changes))),
            readaptations: per_mission(|m| f64::from(m.readaptations)),
            harm: per_mission(|m| f64::from(m.harm())),
        }
    }
}

/// Resamples of the paired bootstrap over missions behind a multiple of the oracle's.
pub const ORACLE_MULTIPLE_RESAMPLES: usize = 2000;

/// What a multiple of the oracle's counts, per mission.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OracleFigure {
    /// Untrustworthy commands after operator changes.
    UntrustworthyPerChange,
    /// Harm done.
    HarmPerMission,
    /// Untrustworthy commands after context switches.
    UntrustworthyPerSwitch,
    /// Untrustworthy commands after switches back to a context the mission was in before.
    UntrustworthyPerSwitchBack,
}

impl OracleFigure {
    /// The figure's count in one mission's changes (and harm).
    fn count(self, changes: &[ChangeRecord], harm: u32) -> f64 {
        let sum = |pick: fn(&ChangeRecord) -> bool| -> f64 {
            changes
                .iter()
                .filter(|c| pick(c))
                .map(|c| f64::from(c.untrustworthy))
                .sum()
        };
        match self {
            Self::UntrustworthyPerChange => sum(|c| c.kind != ChangeKind::Context),
            Self::HarmPerMission => f64::from(harm),
            Self::UntrustworthyPerSwitch => sum(|c| c.kind == ChangeKind::Context),
            Self::UntrustworthyPerSwitchBack => sum(|c| c.kind == ChangeKind::Context && c.back),
        }
    }
}

/// Arm number `index` of plan number `plan` of a report: its `figure` as a multiple of the
/// oracle's on the same missions, with the paired bootstrap's 95% interval over missions
/// (each mission's two counts drawn together, [`ORACLE_MULTIPLE_RESAMPLES`] times, from
/// the stream `(0, plan, 4 * index + figure, Bootstrap)`, so a report is the same every
/// time). The arm and the oracle meet the same changes of the same missions, so the ratio
/// of their totals is the ratio of their means per change (or per mission). `None` when
/// the oracle's total is 0.
pub fn oracle_multiple(
    result: &MissionResult,
    plan: usize,
    index: usize,
    figure: OracleFigure,
) -> Option<RatioCi> {
    let arm = &result.arms[index];
    let (mut counts, mut reference) = (Vec::new(), Vec::new());
    for (mission, oracle) in arm.missions.iter().zip(&result.oracle) {
        debug_assert_eq!(mission.mission, oracle.mission);
        counts.push(figure.count(&mission.changes, mission.harm()));
        reference.push(figure.count(&oracle.changes, oracle.harm()));
    }
    let mut rng = stream(
        0,
        plan as u64,
        4 * index as u64 + figure as u64,
        Purpose::Bootstrap,
    );
    paired_bootstrap_ratio(&counts, &reference, ORACLE_MULTIPLE_RESAMPLES, &mut rng)
}

/// A multiple of the oracle's figure with its interval, `-` when it has none.
pub(crate) fn times(multiple: Option<RatioCi>) -> String {
    multiple.map_or("-".to_owned(), |m| {
        format!("{:.1} [{:.1}, {:.1}]", m.ratio, m.low, m.high)
    })
}

/// A multiple's interval in `summary.json`: `[low, high]`, `null` without a multiple.
pub(crate) fn interval_json(multiple: Option<RatioCi>) -> Value {
    multiple.map_or(Value::Null, |m| json!([m.low, m.high]))
}

impl MissionSummary {
    /// Sums up `arm`'s missions.
    pub fn of(arm: &MissionArmResult) -> Self {
        let ChangeFigures {
            changes,
            needed,
            adapted,
            trusted_again,
            untrustworthy_per_change,
        } = ChangeFigures::of(operator_changes(
            arm.missions.iter().flat_map(|m| &m.changes),
        ));
        let onsets: Vec<_> = arm.missions.iter().flat_map(|m| &m.onsets).collect();
        let delays: Vec<f64> = onsets
            .iter()
            .filter_map(|o| o.detected_after.map(f64::from))
            .collect();
        let per_mission = |f: fn(&MissionRecord) -> f64| {
            mean_ci95_or_zero(&arm.missions.iter().map(f).collect::<Vec<_>>())
        };
        Self {
            arm: arm.arm.clone(),
            answers_alerts: arm.answers_alerts,
            missions: arm.missions.len(),
            changes,
            needed,
            adapted,
            trusted_again,
            untrustworthy_per_change,
            readaptations: per_mission(|m| f64::from(m.readaptations)),
            false_alarms: arm.missions.iter().map(|m| m.false_alarms).sum(),
            missions_alerted: arm.missions.iter().filter(|m| !m.alerts.is_empty()).count(),
            onsets: onsets.len(),
            detected_in_window: delays
                .iter()
                .filter(|&&d| d <= f64::from(DETECTION_WINDOW))
                .count(),
            perceivable_onsets: onsets.iter().filter(|o| o.perceivable > 0).count(),
            perceivable_detected: onsets
                .iter()
                .filter(|o| {
                    o.perceivable > 0 && o.detected_after.is_some_and(|d| d <= DETECTION_WINDOW)
                })
                .count(),
            median_delay: median(delays),
            harm: per_mission(|m| f64::from(m.harm())),
        }
    }

    /// The arm's name in tables: `ARM` or `ARM, alerts answered`.
    pub fn label(&self) -> String {
        arm_label(&self.arm, self.answers_alerts)
    }
}

/// An arm's name in a report's tables: `ARM`, or `ARM, alerts answered`.
pub(crate) fn arm_label(arm: &ArmName, answers_alerts: bool) -> String {
    if answers_alerts {
        format!("{arm}, alerts answered")
    } else {
        arm.to_string()
    }
}

/// The harm of one arm's missions with and without alerts answered, paired by mission.
#[derive(Clone, Debug, PartialEq)]
pub struct HarmComparison {
    /// The arm.
    pub arm: ArmName,
    /// Harm per mission when alerts are ignored.
    pub ignored: MeanCi,
    /// Harm per mission when alerts are answered.
    pub answered: MeanCi,
    /// The paired difference, ignored minus answered.
    pub difference: MeanCi,
    /// The Wilcoxon signed-rank test's p-value (1 when every pair ties).
    pub wilcoxon_p: f64,
}

/// The paired harm comparison of every arm of a complacency plan.
pub fn harm_comparisons(result: &MissionResult) -> Vec<HarmComparison> {
    result
        .arms
        .iter()
        .filter(|a| !a.answers_alerts)
        .filter_map(|ignored| {
            let answered = result
                .arms
                .iter()
                .find(|a| a.answers_alerts && a.arm == ignored.arm)?;
            let (without, with) = (ignored.harms(), answered.harms());
            let difference: Vec<f64> = without.iter().zip(&with).map(|(a, b)| a - b).collect();
            Some(HarmComparison {
                arm: ignored.arm.clone(),
                ignored: mean_ci95_or_zero(&without),
                answered: mean_ci95_or_zero(&with),
                difference: mean_ci95_or_zero(&difference),
                wilcoxon_p: wilcoxon_signed_rank(&without, &with).unwrap_or(1.0),
            })
        })
        .collect()
}

pub(crate) fn ci(value: Option<MeanCi>) -> String {
    value.map_or("-".to_owned(), |v| format!("{:.1} ± {:.1}", v.mean, v.ci95))
}

/// A mean and its interval to two decimals, for figures often a fraction of one (the
/// oracle's untrustworthy commands per change or per switch).
pub(crate) fn fine_ci(value: Option<MeanCi>) -> String {
    value.map_or("-".to_owned(), |v| format!("{:.2} ± {:.2}", v.mean, v.ci95))
}

pub(crate) fn share(part: usize, whole: usize) -> String {
    if whole == 0 {
        "-".to_owned()
    } else {
        format!(
            "{part} of {whole} ({:.0}%)",
            100.0 * part as f64 / whole as f64
        )
    }
}
