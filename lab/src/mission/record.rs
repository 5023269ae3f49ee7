//! What a mission leaves: each change and how it was met ([`ChangeRecord`]), complacency
//! onsets ([`OnsetRecord`]), a mission's record ([`MissionRecord`]) and trace
//! ([`MissionTrace`]), and an arm's and a plan's results ([`MissionArmResult`],
//! [`MissionResult`]).

use crate::experiment::arm_name::ArmName;
use cbr_core::{Behavior, Context};
use serde::{Deserialize, Serialize};
use trust::SwitchStart;

/// What changed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ChangeKind {
    /// Another operator took over.
    Takeover,
    /// The operator's preferences shifted to another member's.
    Shift,
    /// The robot's context switched, and the robot was told (unless blind to it); the
    /// operator judges as it does in the new context.
    Context,
}

/// One change of a mission and how the robot met it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ChangeRecord {
    /// The command at which it happened (from 0; the command is the new operator's).
    pub at: u32,
    /// What changed.
    pub kind: ChangeKind,
    /// Whether the behavior in use was not trustworthy for the new operator (its mean
    /// weighted outcome, over the plan's truth runs, at most 0): the robot had to adapt.
    pub needed: bool,
    /// Commands from the change until the robot next settled on a trustworthy behavior,
    /// if it did before the next change or the mission's end.
    pub trusted_again: Option<u32>,
    /// Untrustworthy commands from the change until then (or until the next change or the
    /// end).
    pub untrustworthy: u32,
    /// A context switch back to a context the mission was in before.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub back: bool,
    /// At a context switch the robot was told of, what it went on with
    /// ([`trust::SwitchStart`]); `None` for every other change, and for the oracle.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start: Option<SwitchStart>,
    /// When the robot gave up the behavior it used at the change, before the next change
    /// or the mission's end (`None`: it did not).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noticed: Option<Noticed>,
}

/// When a robot gave up the behavior it used at a change ([`ChangeRecord::noticed`]):
/// what noticing the change cost, apart from what searching after it cost.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Noticed {
    /// Commands from the change until it gave the behavior up (0: at the change).
    pub after: u32,
    /// The change's untrustworthy commands until then.
    pub untrustworthy: u32,
}

impl ChangeRecord {
    /// Records that the behavior in use at the change was given up `at` a command (the
    /// command's own outcome counted), unless it was already.
    pub(crate) fn notice(&mut self, at: u32) {
        self.noticed.get_or_insert(Noticed {
            after: at - self.at,
            untrustworthy: self.untrustworthy,
        });
    }
}

/// A complacency onset (the operator's attention fell below [`COMPLACENT_BELOW`](crate::mission::COMPLACENT_BELOW)) and
/// when the robot raised an alert after it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct OnsetRecord {
    /// The command at which attention fell below the bound.
    pub at: u32,
    /// Commands from the onset to the first alert while the operator stayed complacent.
    pub detected_after: Option<u32>,
    /// Commands, while complacent and before any alert, whose overlooked problem came with
    /// something the robot perceived (a signal of its own record): the evidence the robot
    /// could have had.
    pub perceivable: u32,
}

/// One mission of one arm.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MissionRecord {
    /// The mission's number.
    pub mission: u32,
    /// The case memory's guess the mission started from (an arm that starts from it,
    /// once its memory holds a case); `None`: the mission's random behavior.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub learned_start: Option<Behavior>,
    /// The context the mission started in (the default without context switches).
    #[serde(default, skip_serializing_if = "Context::is_default")]
    pub context: Context,
    /// Every change, in order.
    pub changes: Vec<ChangeRecord>,
    /// Times the robot gave up a behavior it had settled on.
    pub readaptations: u32,
    /// Of those, times no change had happened since the behavior settled.
    pub false_alarms: u32,
    /// Commands at which the robot raised an alert.
    pub alerts: Vec<u32>,
    /// Complacency onsets.
    pub onsets: Vec<OnsetRecord>,
    /// Commands that failed (the harm happened: a detonation, a task given up).
    pub failures: u32,
    /// Commands with a problem the operator overlooked.
    pub overlooked: u32,
    /// Untrustworthy commands in all.
    pub untrustworthy: u32,
    /// The robot's judgement of its own competence against the truth, on a plan with a
    /// competence standard.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub calibration: Option<CalibrationRecord>,
}

/// How the robot's judgement of its own competence met the truth during one mission
/// (the truth of a behavior: the share of [`MissionPlan::truth_runs`](crate::mission::MissionPlan::truth_runs) whole commands that
/// fell short in each part, [`SelfJudging::competence_truth`](crate::SelfJudging::competence_truth), against the plan's standard).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CalibrationRecord {
    /// Commands of a watched (settled) behavior.
    pub watched: u32,
    /// Of those, commands whose operator trusted the behavior (its estimate at the
    /// trustworthy threshold) while it was truly not competent: overtrust.
    pub overtrusted: u32,
    /// Of the watched commands, those the robot judged overtrust.
    pub judged: u32,
    /// Commands both overtrusted and judged so.
    pub both: u32,
    /// Watched commands of a behavior truly competent.
    pub competent: u32,
    /// The overtrust alerts raised: the command, and whether the behavior was truly
    /// competent (a false alert).
    pub alerts: Vec<(u32, bool)>,
    /// Answered alerts that offered a safer behavior ([`MissionPlan::offer_safer`](crate::mission::MissionPlan::offer_safer)).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub offered: u32,
    /// Of those, offers the operator took (it trusts the offered behavior too).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub taken: u32,
}

fn is_zero(n: &u32) -> bool {
    *n == 0
}

impl CalibrationRecord {
    /// Overtrust alerts raised on a behavior that was truly competent.
    pub fn false_alerts(&self) -> usize {
        self.alerts
            .iter()
            .filter(|(_, competent)| *competent)
            .count()
    }
}

impl MissionRecord {
    /// Harm done: failures and problems nobody noticed.
    pub fn harm(&self) -> u32 {
        self.failures + self.overlooked
    }
}

/// What happened at one command of a traced mission.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Mark {
    /// The operator changed.
    Change(ChangeKind),
    /// The robot gave up a behavior it had settled on.
    Readaptation,
    /// The robot switched behavior during an episode.
    Switch,
    /// The robot settled.
    Settled,
    /// The robot raised an alert.
    Alert,
    /// The operator became complacent.
    Onset,
}

/// One step of a traced mission: one command, or in a long mission a run of commands
/// summarised ([`MissionTrace`]): the estimate of the behavior in use after it, its lowest
/// and highest estimate, the robot's own record, and what happened.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MissionStep {
    /// The estimate after the step's last command.
    pub estimate: f64,
    /// The lowest estimate after any of its commands.
    pub low: f64,
    /// The highest estimate after any of its commands.
    pub high: f64,
    /// The robot's own record of a settled behavior after its last command (`None` during
    /// an episode).
    pub own_record: Option<f64>,
    /// Whether a command of it was untrustworthy.
    pub untrustworthy: bool,
    /// What happened during it, each mark once.
    pub marks: Vec<Mark>,
}

/// The most steps a traced mission keeps: a mission of more commands is summarised, each
/// step standing for the same number of commands, so a trace's memory and its figure are
/// bounded whatever a mission's length (`trustcbr::limits::FIGURE_POINTS`).
pub const MAX_TRACE_STEPS: u32 = 2_000;

/// A mission traced step by step for its figure: every command, or for a mission of more
/// than [`MAX_TRACE_STEPS`] commands, runs of `every` commands summarised as one step
/// (the estimate after the run's last command, the lowest and highest after any, the own
/// record after the last, whether any was untrustworthy, each kind of mark once).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MissionTrace {
    /// Commands per step: 1 for a mission of at most [`MAX_TRACE_STEPS`] commands.
    pub every: u32,
    /// The mission's commands.
    pub commands: u32,
    /// The steps, in order (the last may stand for fewer commands).
    pub steps: Vec<MissionStep>,
}

impl MissionTrace {
    /// An empty trace of a mission of `commands` commands.
    pub(crate) fn of(commands: u32) -> Self {
        let every = commands.div_ceil(MAX_TRACE_STEPS).max(1);
        Self {
            every,
            commands,
            steps: Vec::with_capacity(commands.div_ceil(every) as usize),
        }
    }

    /// Adds command `c` (from 0), as a step of its own, to the step it belongs to.
    pub(crate) fn record(&mut self, c: u32, command: MissionStep) {
        match self.steps.last_mut() {
            Some(step) if !c.is_multiple_of(self.every) => {
                step.estimate = command.estimate;
                step.low = step.low.min(command.low);
                step.high = step.high.max(command.high);
                step.own_record = command.own_record;
                step.untrustworthy |= command.untrustworthy;
                for mark in command.marks {
                    if !step.marks.contains(&mark) {
                        step.marks.push(mark);
                    }
                }
            }
            _ => self.steps.push(command),
        }
    }
}

/// One arm's missions.
#[derive(Clone, Debug, PartialEq)]
pub struct MissionArmResult {
    /// The arm's name.
    pub arm: ArmName,
    /// Whether the operator answered the robot's alerts.
    pub answers_alerts: bool,
    /// Every mission, in order.
    pub missions: Vec<MissionRecord>,
    /// The first mission, step by step.
    pub traced: MissionTrace,
}

impl MissionArmResult {
    /// The harm done in each mission ([`MissionRecord::harm`]), in order.
    pub fn harms(&self) -> Vec<f64> {
        self.missions.iter().map(|m| f64::from(m.harm())).collect()
    }
}

/// A mission plan's results.
#[derive(Clone, Debug, PartialEq)]
pub struct MissionResult {
    /// The plan's name.
    pub name: String,
    /// Whether operators could grow complacent.
    pub complacency: bool,
    /// Whether the robot's context switched during missions ([`MissionPlan::contexts`](crate::mission::MissionPlan::contexts)).
    pub context_switches: bool,
    /// Every arm (answering alerts second, for complacency plans), in the plan's order.
    pub arms: Vec<MissionArmResult>,
    /// The oracle's missions, the same missions as every arm's ([`crate::mission::oracle`]).
    pub oracle: Vec<OracleRecord>,
}

/// One mission of the oracle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OracleRecord {
    /// The mission's number.
    pub mission: u32,
    /// Every change, in order, counted as an arm's are.
    pub changes: Vec<ChangeRecord>,
    /// Episodes it began at a change (keeping the behavior in use would cost more, or it
    /// was still adapting).
    pub readaptations: u32,
    /// Commands that failed.
    pub failures: u32,
    /// Commands with a problem the operator overlooked.
    pub overlooked: u32,
    /// Untrustworthy commands in all.
    pub untrustworthy: u32,
}

impl OracleRecord {
    /// Harm done: failures and problems nobody noticed (as [`MissionRecord::harm`]).
    pub fn harm(&self) -> u32 {
        self.failures + self.overlooked
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn command(estimate: f64, untrustworthy: bool, marks: Vec<Mark>) -> MissionStep {
        MissionStep {
            estimate,
            low: estimate,
            high: estimate,
            own_record: None,
            untrustworthy,
            marks,
        }
    }

    #[test]
    fn a_short_mission_is_traced_command_by_command() {
        let mut trace = MissionTrace::of(3);
        for (c, e) in [1.0, -1.0, 0.0].into_iter().enumerate() {
            trace.record(c as u32, command(e, e < 0.0, vec![]));
        }
        assert_eq!(trace.every, 1);
        assert_eq!(trace.steps.len(), 3);
        assert_eq!(trace.steps[1], command(-1.0, true, vec![]));
    }

    #[test]
    fn a_long_mission_is_summarised_in_equal_runs_of_commands() {
        // 5,000 commands in at most 2,000 steps: 3 commands a step, 1,667 steps.
        let mut trace = MissionTrace::of(5_000);
        assert_eq!(trace.every, 3);
        let change = Mark::Change(ChangeKind::Takeover);
        for c in 0..5_000u32 {
            let marks = match c {
                0 | 1 => vec![change, Mark::Switch],
                4 => vec![Mark::Alert],
                _ => vec![],
            };
            trace.record(c, command(f64::from(c % 7) - 3.0, c == 2, marks));
        }
        assert_eq!(trace.steps.len(), 1_667);
        // Commands 0, 1, 2: estimates -3, -2, -1.
        assert_eq!(
            trace.steps[0],
            MissionStep {
                estimate: -1.0,
                low: -3.0,
                high: -1.0,
                own_record: None,
                untrustworthy: true,
                marks: vec![change, Mark::Switch],
            }
        );
        // Commands 3, 4, 5: estimates 0, 1, 2; the alert at 4.
        assert_eq!((trace.steps[1].low, trace.steps[1].high), (0.0, 2.0));
        assert_eq!(trace.steps[1].marks, [Mark::Alert]);
        // The last step stands for command 4,998 and 4,999 alone.
        assert_eq!(trace.steps[1_666].estimate, f64::from(4_999 % 7) - 3.0);
    }
}
