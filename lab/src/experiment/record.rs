//! What an experiment's trials leave: a trial's record ([`TrialRecord`]), an arm's
//! results ([`ArmResult`]) with its paired tests and the check of its explanations
//! ([`ExplanationCheck`]), and an experiment's ([`ExperimentResult`]).

use crate::experiment::arm::{Arm, ArmName, Initial};

use crate::GoalChangeRecord;
use crate::stats::MeanCi;
use cbr_core::{Behavior, Context, Statement};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use trust::{Cause, EpisodeReport, Explanation, Outcome, Source, TrustCaseBase};

/// The outcome of one trial.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrialRecord {
    /// Trial number, from 0; trials with the same number are paired across arms.
    pub trial: u32,
    /// The arm's name.
    pub arm: String,
    /// The operator that judged this trial.
    pub operator: String,
    /// The behavior the trial started with.
    pub initial: Behavior,
    /// Whether it was the case memory's guess (an arm with [`Initial::Learned`] whose
    /// memory held a case) rather than the trial's random draw.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub learned_start: bool,
    /// How the episode ended.
    pub report: EpisodeReport,
    /// Whether the trial hit `max_commands` and was abandoned.
    pub truncated: bool,
    /// The operator's true reasons for the trial's untrustworthy commands, counted by
    /// cause: for evaluation only (the adapter was told only what the robot perceived and
    /// what the operator stated).
    #[serde(default)]
    pub true_causes: BTreeMap<Cause, u32>,
    /// How the explanations of the trial's given-up behaviors compare with the truth (for
    /// evaluation only).
    #[serde(default)]
    pub explained: ExplanationCheck,
    /// Every behavior the trial gave up, in order: the reason its explanation settled on,
    /// how the next one was chosen, and the truth. The full explanations are taken out of
    /// `report` (its `explanations` is empty) to keep an experiment's records small;
    /// [`trace_trial`](crate::trace_trial) replays a trial with them, and [`ArmResult::samples`] keeps a few.
    #[serde(default)]
    pub given_up: Vec<GivenUpRecord>,
    /// What the trial's goal changes were (for evaluation only); `None` when the plan has
    /// none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub goal_changes: Option<GoalChangeRecord>,
    /// The context the trial ran in (left out when the default one); the report's own
    /// `context` is the one the robot was told.
    #[serde(default, skip_serializing_if = "Context::is_default")]
    pub context: Context,
    /// What the trial's operator stated up front (left out when nothing).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stated: Vec<Statement>,
}

/// One behavior a trial gave up, as its explanation put it and as it was.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct GivenUpRecord {
    /// The reason the explanation settled on (`None`: none was attributed, or no reason
    /// stood out).
    pub reason: Option<Cause>,
    /// How the next behavior was chosen (`None`: every behavior had been tried and the
    /// episode ended).
    pub next: Option<Source>,
    /// The operator's most frequent true reason on the behavior's untrustworthy commands
    /// (the first by name in a tie; `None` when they carry none): for evaluation only.
    pub truth: Option<Cause>,
    /// Whether the explanation was right ([`ExplanationCheck`]'s rule).
    pub right: bool,
}

/// An explanation an arm gave, kept whole for the report, with the truth.
#[derive(Clone, Debug, PartialEq)]
pub struct ExplanationSample {
    /// The trial.
    pub trial: u32,
    /// The explanation of a switch.
    pub explanation: Explanation,
    /// The operator's most frequent true reason on the behavior given up.
    pub truth: Option<Cause>,
}

/// Explanations each arm keeps whole ([`ArmResult::samples`]): its first switches.
pub const SAMPLE_EXPLANATIONS: usize = 2;

/// Trials of an experiment's [`sample_arm`] traced command by command as they run
/// ([`ArmResult::traced`]).
pub const TRACED_TRIALS: u32 = 25;

/// The most commands of a traced trial kept ([`ArmResult::traced`]): a longer trial's
/// trace is dropped (empty), so the traces of an experiment hold at most
/// [`TRACED_TRIALS`] times this many commands whatever `max_commands` allows
/// (`trustcbr::limits::TRACED_COMMANDS`).
pub const MAX_TRACED_COMMANDS: u64 = 100_000;

/// The arm whose first trials an experiment traces: the paper's case-based arm when it
/// runs, else the second arm, else the first.
pub fn sample_arm(arms: &[Arm]) -> Option<usize> {
    arms.iter()
        .position(|a| a.name() == "case-based")
        .or_else(|| (arms.len() > 1).then_some(1))
        .or_else(|| (!arms.is_empty()).then_some(0))
}

/// How often the first reason an explanation gives for a given-up behavior is the
/// operator's most frequent true reason on that behavior's untrustworthy commands. An
/// explanation that settles on one reason is right when it is among the most frequent
/// true reasons; one whose first reasons tie (no reason stands out) is right only when
/// they are exactly the most frequent true reasons, tied as well. Behaviors whose
/// untrustworthy commands carry no true reason are not counted. *Perceivable* truths are
/// those the robot perceives itself (an observation is named after them).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ExplanationCheck {
    /// Given-up behaviors counted.
    pub given_up: u32,
    /// Those whose first attributed reason was right.
    pub right: u32,
    /// Given-up behaviors whose true reason is one the robot perceives.
    pub perceivable: u32,
    /// Those whose first attributed reason was right.
    pub perceivable_right: u32,
}

impl ExplanationCheck {
    /// Adds another's counts.
    pub fn add(&mut self, other: &ExplanationCheck) {
        self.given_up += other.given_up;
        self.right += other.right;
        self.perceivable += other.perceivable;
        self.perceivable_right += other.perceivable_right;
    }

    /// The share right overall, among perceivable truths and among the rest (`None` where
    /// nothing was counted).
    pub fn shares(&self) -> [Option<f64>; 3] {
        let share = |right: u32, of: u32| (of > 0).then(|| f64::from(right) / f64::from(of));
        [
            share(self.right, self.given_up),
            share(self.perceivable_right, self.perceivable),
            share(
                self.right - self.perceivable_right,
                self.given_up - self.perceivable,
            ),
        ]
    }

    /// Scores one given-up behavior: `leading` are the reasons its explanation puts first
    /// ([`trust::GivenUp::leading_reasons`]), `truth` the true reasons of its untrustworthy
    /// commands, counted. Returns the most frequent true reason (the first by name in a
    /// tie) and whether the explanation was right; `None` when no true reason was given
    /// (not counted).
    pub(crate) fn score(
        &mut self,
        leading: &[Cause],
        truth: &BTreeMap<Cause, u32>,
        perceived: &[Cause],
    ) -> Option<(Cause, bool)> {
        let &most = truth.values().max()?;
        let modes: Vec<Cause> = truth
            .iter()
            .filter(|&(_, &n)| n == most)
            .map(|(&c, _)| c)
            .collect();
        let right = match leading {
            [] => false,
            [one] => modes.contains(one),
            tied => {
                let mut tied = tied.to_vec();
                tied.sort_unstable();
                tied == modes
            }
        };
        self.given_up += 1;
        self.right += u32::from(right);
        if perceived.contains(&modes[0]) {
            self.perceivable += 1;
            self.perceivable_right += u32::from(right);
        }
        Some((modes[0], right))
    }
}

/// Two arms' per-trial counts of behaviors evaluated, compared pair by pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairedTests {
    /// Paired t-test p-value.
    pub t_test_p: f64,
    /// Wilcoxon signed-rank test p-value (counts are heavy-tailed).
    pub wilcoxon_p: f64,
}

/// One arm's results in an experiment.
#[derive(Clone, Debug, PartialEq)]
pub struct ArmResult {
    /// The arm's name.
    pub name: ArmName,
    /// Whether the arm reuses cases.
    pub reuses_cases: bool,
    /// How the arm's episodes start.
    pub initial: Initial,
    /// Cases the arm started from (0: an empty case base).
    pub starting_cases: usize,
    /// Behaviors evaluated per trial (the paper's metric).
    pub behaviors: MeanCi,
    /// Commands until the trial ended.
    pub commands: MeanCi,
    /// Commands that failed or were interrupted (what the operator endured).
    pub untrustworthy: MeanCi,
    /// Share of trials that found a trustworthy behavior.
    pub found_share: MeanCi,
    /// Cases retained during the experiment.
    pub cases_acquired: usize,
    /// The case base at the end (arms that read cases only: [`Arm::reads_cases`]).
    pub final_cases: Option<TrustCaseBase>,
    /// This arm against the first arm (`None` for the first arm).
    pub versus_first: Option<PairedTests>,
    /// How its explanations compare with the truth, over every trial.
    pub explained: ExplanationCheck,
    /// Its first explanations of switches, kept whole (at most [`SAMPLE_EXPLANATIONS`]).
    pub samples: Vec<ExplanationSample>,
    /// Its first [`TRACED_TRIALS`] trials command by command, as they ran, when it is the
    /// experiment's [`sample_arm`] (empty otherwise): what a report's timeline draws. A
    /// trial of more than [`MAX_TRACED_COMMANDS`] commands is kept empty.
    pub traced: Vec<Vec<TracedCommand>>,
    /// Every trial, in order.
    pub trials: Vec<TrialRecord>,
}

impl ArmResult {
    /// Behaviors evaluated in each trial, in trial order.
    pub fn counts(&self) -> Vec<f64> {
        self.trials
            .iter()
            .map(|t| t.report.behaviors_evaluated as f64)
            .collect()
    }

    /// Trials cut off by `max_commands`.
    pub fn truncated(&self) -> usize {
        self.trials.iter().filter(|t| t.truncated).count()
    }

    /// For unit tests: the arm `name` of `trials`, each of them (found trustworthy,
    /// untrustworthy commands) after 2 behaviors in 10 commands, in the default context.
    #[cfg(test)]
    pub(crate) fn of_trials(name: &str, trials: &[(bool, u64)]) -> Self {
        let untrustworthy: Vec<f64> = trials.iter().map(|&(_, u)| u as f64).collect();
        let mean = crate::stats::mean_ci95_or_zero(&untrustworthy);
        let records = trials
            .iter()
            .enumerate()
            .map(|(k, &(found, untrustworthy))| TrialRecord {
                trial: k as u32,
                arm: name.to_owned(),
                operator: "o".to_owned(),
                initial: Behavior::new(&[0]),
                learned_start: false,
                report: EpisodeReport {
                    settled: Behavior::new(&[0]),
                    found_trustworthy: found,
                    behaviors_evaluated: 2,
                    commands: 10,
                    untrustworthy,
                    searched: 0,
                    reused: 0,
                    settled_from_search: false,
                    retained: None,
                    evaluated: Vec::new(),
                    context: Context::default(),
                    explanations: Vec::new(),
                },
                truncated: false,
                true_causes: BTreeMap::new(),
                explained: ExplanationCheck::default(),
                given_up: Vec::new(),
                goal_changes: None,
                context: Context::default(),
                stated: Vec::new(),
            })
            .collect();
        ArmResult {
            name: ArmName::parse(name).expect("a test's arm name"),
            reuses_cases: false,
            initial: Initial::Random,
            starting_cases: 0,
            behaviors: mean,
            commands: mean,
            untrustworthy: mean,
            found_share: mean,
            cases_acquired: 0,
            final_cases: None,
            versus_first: None,
            explained: ExplanationCheck::default(),
            samples: Vec::new(),
            traced: Vec::new(),
            trials: records,
        }
    }
}

/// One experiment's results.
#[derive(Clone, Debug, PartialEq)]
pub struct ExperimentResult {
    /// The plan's name.
    pub name: String,
    /// Every arm, in the plan's order.
    pub arms: Vec<ArmResult>,
}

impl ExperimentResult {
    /// The arm named `name`.
    pub fn arm(&self, name: &str) -> Option<&ArmResult> {
        self.arms.iter().find(|a| a.name == *name)
    }

    /// Trials per arm.
    pub fn trials(&self) -> usize {
        self.arms.first().map_or(0, |a| a.trials.len())
    }
}

/// One command of a trial, as [`trace_trial`](crate::trace_trial) shows it.
#[derive(Clone, Copy, Debug)]
pub struct Step<'a> {
    /// The behavior the command ran with.
    pub behavior: Behavior,
    /// What the robot was told and perceived.
    pub outcome: &'a Outcome,
    /// The operator's true reason (evaluation only).
    pub truth: Option<Cause>,
    /// The behavior's trust estimate after the command.
    pub estimate: f64,
    /// The explanation of the decision the command led to (a switch or the end).
    pub explanation: Option<&'a Explanation>,
}

/// One command of a traced trial, owned.
#[derive(Clone, Debug, PartialEq)]
pub struct TracedCommand {
    /// The behavior the command ran with.
    pub behavior: Behavior,
    /// What the robot was told and perceived.
    pub outcome: Outcome,
    /// The operator's true reason (evaluation only).
    pub truth: Option<Cause>,
    /// The behavior's trust estimate after the command.
    pub estimate: f64,
    /// The explanation of the decision the command led to (a switch or the end).
    pub explanation: Option<Explanation>,
}

impl TracedCommand {
    /// The command a step shows, owned.
    pub(crate) fn of(step: &Step<'_>) -> Self {
        Self {
            behavior: step.behavior,
            outcome: *step.outcome,
            truth: step.truth,
            estimate: step.estimate,
            explanation: step.explanation.cloned(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: Cause = Cause::from_static("a");
    const B: Cause = Cause::from_static("b");
    const C: Cause = Cause::from_static("c");

    #[test]
    fn explanations_are_scored_by_hand() {
        let truth = |counts: &[(Cause, u32)]| counts.iter().copied().collect::<BTreeMap<_, _>>();
        let mut check = ExplanationCheck::default();
        // One reason settled on, the most frequent truth: right; `a` is perceivable.
        assert_eq!(
            check.score(&[A], &truth(&[(A, 3), (B, 1)]), &[A]),
            Some((A, true))
        );
        // Settled on `b` where `a` is more frequent: wrong.
        check.score(&[B], &truth(&[(A, 3), (B, 1)]), &[A]);
        // The truth ties: a reason among the tied ones is right.
        assert_eq!(
            check.score(&[B], &truth(&[(A, 2), (B, 2)]), &[]),
            Some((A, true))
        );
        // The explanation ties: right only with the very same tie.
        check.score(&[A, B], &truth(&[(A, 2), (B, 2), (C, 1)]), &[]);
        check.score(&[A, B], &truth(&[(A, 2), (C, 1)]), &[]);
        // Nothing attributed: wrong; no true reason: not counted.
        check.score(&[], &truth(&[(C, 1)]), &[]);
        assert_eq!(check.score(&[A], &truth(&[]), &[A]), None);
        assert_eq!(
            check,
            ExplanationCheck {
                given_up: 6,
                right: 3,
                perceivable: 2,
                perceivable_right: 1,
            }
        );
        let [all, perceivable, rest] = check.shares();
        assert_eq!(all, Some(0.5));
        assert_eq!(perceivable, Some(0.5));
        assert_eq!(rest, Some(0.5));
        assert_eq!(ExplanationCheck::default().shares(), [None, None, None]);
    }
}
