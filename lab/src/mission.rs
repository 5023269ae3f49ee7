//! Missions: long runs of commands in which the operator changes without the robot being
//! told, and operators may grow complacent (docs/missions.md).
//!
//! A *mission* is `commands` commands from one population. It starts with a member drawn
//! at random and the arm's first behavior (the paper's random one, or the case memory's
//! guess for an arm that starts from it, drawn as a trial's first behavior is); at random
//! times (exponential gaps of mean [`Changes::every`] commands) the operator changes:
//! another operator *takes over* (a new person, who starts without trust in the robot) or
//! the same operator's preferences *shift* to another member's (the context changed; its
//! trust in the robot carries over). With [`ContextSwitches`] the robot's context (its
//! cargo, the situation it was sent into) also switches at random times, and the robot is
//! *told* (it knows what it carries): the operator then judges as it does in the new
//! context ([`Domain::operator_in_context`]). The robot runs in mission mode
//! ([`trust::MissionAdapter`]) and is told only outcomes; its commands are driven as a
//! trial's are (the private `drive` module: the first behavior and each command).
//!
//! With a [`Complacency`] model the operator's attention falls as its own trust in the
//! robot builds: each arm then runs twice on the same streams, once ignoring the robot's
//! alerts and once answering them (the operator is asked to supervise and looks afresh:
//! its trust restarts from nothing and its attention is whole again), so the harm done
//! with and without alerts is paired mission by mission.
//!
//! The missions of one arm form a chain (the case base carries from one to the next);
//! chains run in parallel. Every draw comes from a stream named by (seed, mission plan,
//! mission, purpose), the same for every arm.

use crate::arm::{Arm, Initial};
use crate::competence::{CompetenceError, empty_record, true_competence, true_rates};
use crate::domain::check_attention;
use crate::drive::{Command, Drive, first_behavior};
use crate::known_operator::LimitSettings;
use crate::mission_oracle::{OracleRecord, run_oracles};
use crate::runner::{PlanError, fresh_adapter};
use crate::seeds::{Purpose, stream};
use crate::{Domain, FeedbackChannel};
use cbr_core::{Behavior, Context};
use rand::{Rng, RngCore, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::sync::Arc;
use trust::{
    AdapterConfig, Calibration, CompetenceJudge, CompetenceStandard, Decision, MissionAdapter,
    MissionDecision, Outcome, OutcomeKind, OwnRecord, SwitchStart, Verdict,
};

/// When the operator changes during a mission.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Changes {
    /// Mean commands between changes (gaps are exponential, at least one command).
    pub every: f64,
    /// The share of changes that are takeovers by another operator; the others are shifts
    /// of the same operator's preferences.
    pub takeover: f64,
}

/// Announced switches of the robot's context during a mission (docs/missions.md#context-switches):
/// a mission starts in one of `among`, drawn uniformly, and at random times (exponential
/// gaps of mean `every` commands, drawn apart from the operator changes) switches to
/// another of them, uniformly. The robot is told each switch the moment it happens, unless
/// its arm is blind to its context ([`Arm::is_context_blind`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContextSwitches {
    /// The contexts a mission may be in (at least two, each the domain's).
    pub among: Vec<Context>,
    /// Mean commands between switches (gaps are exponential, at least one command).
    pub every: f64,
}

impl ContextSwitches {
    /// Checks the numbers: at least two contexts, none twice, and `every >= 1`.
    pub fn validate(&self) -> Result<(), String> {
        if self.among.len() < 2 {
            return Err(format!(
                "context_switches.among: at least two contexts to switch between, got {}",
                self.among.len()
            ));
        }
        if let Some(i) = (1..self.among.len()).find(|&i| self.among[..i].contains(&self.among[i])) {
            return Err(format!(
                "context_switches.among[{i}]: a context already listed"
            ));
        }
        if !(self.every.is_finite() && self.every >= 1.0) {
            return Err(format!(
                "context_switches.every: a mean number of commands >= 1, got {}",
                cbr_core::Shown(self.every)
            ));
        }
        Ok(())
    }
}

/// How an operator grows complacent: its own trust in the robot is an average of how the
/// commands it watched went, over about `memory` commands, and its attention (the chance
/// it notices a problem it minds) falls linearly with that trust, from 1 with no trust to
/// `floor` with full trust (docs/simulation.md, "Complacency").
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Complacency {
    /// Commands the operator's trust averages over (the weight of the last is `1 / memory`).
    pub memory: f64,
    /// Its attention at full trust.
    pub floor: f64,
}

/// Attention below this is complacency: the operator overlooks more of what it minds
/// than it notices.
pub const COMPLACENT_BELOW: f64 = 0.5;

/// A complacent operator has recovered once its attention is back at or above this,
/// halfway from the complacency bound to full attention (so an attention wavering around
/// the bound is one onset, not many).
pub const RECOVERED_AT: f64 = 0.75;

/// An onset detected within this many commands counts towards the detection target.
pub const DETECTION_WINDOW: u32 = 25;

impl Complacency {
    /// The operator's attention at its own trust `felt` (in `[0, 1]`).
    pub fn attention(&self, felt: f64) -> f64 {
        1.0 - (1.0 - self.floor) * felt
    }

    /// The operator's own trust after watching a command with `outcome`, from `felt`
    /// before it: an average over about `memory` commands of how they went (1 for a
    /// command that went well, 0 for an untrustworthy one).
    pub fn felt_after(&self, felt: f64, outcome: &Outcome) -> f64 {
        let went_well = if outcome.is_untrustworthy() { 0.0 } else { 1.0 };
        felt + (went_well - felt) / self.memory
    }

    /// Checks the numbers: `memory >= 1` and `floor` in `[0, 1]`.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.memory.is_finite() && self.memory >= 1.0) {
            return Err(format!(
                "complacency.memory: a number of commands >= 1, got {}",
                cbr_core::Shown(self.memory)
            ));
        }
        if !(0.0..=1.0).contains(&self.floor) {
            return Err(format!(
                "complacency.floor: an attention in [0, 1], got {}",
                cbr_core::Shown(self.floor)
            ));
        }
        Ok(())
    }
}

impl Changes {
    /// Checks the numbers: `every >= 1` and `takeover` in `[0, 1]`.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.every.is_finite() && self.every >= 1.0) {
            return Err(format!(
                "changes.every: a mean number of commands >= 1, got {}",
                cbr_core::Shown(self.every)
            ));
        }
        if !(0.0..=1.0).contains(&self.takeover) {
            return Err(format!(
                "changes.takeover: a share in [0, 1], got {}",
                cbr_core::Shown(self.takeover)
            ));
        }
        Ok(())
    }
}

/// Missions to run: a population, the changes, maybe complacency, and the arms.
pub struct MissionPlan<'a, D: Domain> {
    /// Its name in reports.
    pub name: String,
    /// The domain.
    pub domain: &'a D,
    /// The population, by name (at least two for changes to change anything).
    pub operators: &'a [(String, D::Operator)],
    /// Missions per arm.
    pub missions: u32,
    /// Commands per mission.
    pub commands: u32,
    /// When the operator changes.
    pub changes: Changes,
    /// When the robot's context switches (`None`: every mission in the default context).
    pub contexts: Option<ContextSwitches>,
    /// How operators grow complacent (`None`: they stay attentive, the paper's).
    pub complacency: Option<Complacency>,
    /// The adapter every arm starts from (see [`ExperimentPlan`](crate::ExperimentPlan)'s `adapter`).
    pub adapter: AdapterConfig,
    /// The arms.
    pub arms: Vec<Arm>,
    /// How every operator explains itself, overriding its own channel.
    pub feedback: Option<FeedbackChannel>,
    /// Runs that estimate whether a behavior is trustworthy for an operator (the truth of
    /// whether a change needed an adaptation).
    pub truth_runs: u32,
    /// How the oracle's knowledge of each operator (its known-operator limit and
    /// trustworthy region) is estimated ([`crate::mission_oracle`]).
    pub limit: LimitSettings,
    /// The standard the robot holds its own competence to (`None`: it does not judge
    /// it): every arm then judges every command's behavior ([`trust::competence`]),
    /// raises an overtrust alert once per settled behavior its operator trusts and it
    /// judges not competent, and its records carry the calibration against the truth
    /// ([`CalibrationRecord`]).
    pub competence: Option<CompetenceStandard>,
    /// Whether an answered overtrust alert offers a safer behavior
    /// ([`trust::CompetenceAlert::offer`]), which the operator takes when it trusts it
    /// too (judged on [`MissionPlan::truth_runs`] commands, as a change's need is);
    /// `false`: the operator only looks afresh.
    pub offer_safer: bool,
}

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

/// A complacency onset (the operator's attention fell below [`COMPLACENT_BELOW`]) and
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

/// Records `change` in a mission's `changes` (nothing counted yet) and returns its place,
/// the change the robot is now waiting to settle after, as the arms and the oracle
/// ([`crate::mission_oracle`]) record them.
pub(crate) fn begin_change(
    changes: &mut Vec<ChangeRecord>,
    change: &Scheduled,
    needed: bool,
) -> usize {
    changes.push(ChangeRecord {
        at: change.at,
        kind: change.kind,
        needed,
        trusted_again: None,
        untrustworthy: 0,
        back: change.back,
        start: None,
        noticed: None,
    });
    changes.len() - 1
}

/// Counts an untrustworthy command into a mission's `total` and into the change it came
/// after while the robot had not yet settled again (`waiting`), as the arms and the oracle
/// ([`crate::mission_oracle`]) count them.
pub(crate) fn count_untrustworthy(
    total: &mut u32,
    changes: &mut [ChangeRecord],
    waiting: Option<usize>,
) {
    *total += 1;
    if let Some(k) = waiting {
        changes[k].untrustworthy += 1;
    }
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
/// (the truth of a behavior: the share of [`MissionPlan::truth_runs`] whole commands that
/// fell short in each part, [`Domain::competence_truth`], against the plan's standard).
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
    /// Answered alerts that offered a safer behavior ([`MissionPlan::offer_safer`]).
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
    fn of(commands: u32) -> Self {
        let every = commands.div_ceil(MAX_TRACE_STEPS).max(1);
        Self {
            every,
            commands,
            steps: Vec::with_capacity(commands.div_ceil(every) as usize),
        }
    }

    /// Adds command `c` (from 0), as a step of its own, to the step it belongs to.
    fn record(&mut self, c: u32, command: MissionStep) {
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
    pub arm: String,
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
    /// Whether the robot's context switched during missions ([`MissionPlan::contexts`]).
    pub context_switches: bool,
    /// Every arm (answering alerts second, for complacency plans), in the plan's order.
    pub arms: Vec<MissionArmResult>,
    /// The oracle's missions, the same missions as every arm's ([`crate::mission_oracle`]).
    pub oracle: Vec<OracleRecord>,
}

impl<D: Domain> MissionPlan<'_, D> {
    /// The mean commands from one change (an operator change or a context switch) to the
    /// next: the gaps of each are memoryless, so together they are of the summed rates.
    pub fn mean_gap(&self) -> f64 {
        let operator_rate = if self.operators.len() < 2 {
            0.0
        } else {
            1.0 / self.changes.every
        };
        let context_rate = self.contexts.as_ref().map_or(0.0, |c| 1.0 / c.every);
        1.0 / (operator_rate + context_rate)
    }

    /// The context of place `context` in the plan's switches (the default without them).
    fn context(&self, context: usize) -> Context {
        self.contexts
            .as_ref()
            .map_or_else(Context::default, |c| c.among[context].clone())
    }

    /// Refuses a plan whose operators grow complacent over a domain that does not model
    /// attention ([`check_attention`]): it would run, and its alerts could change nothing.
    pub fn validate(&self) -> Result<(), PlanError> {
        if let Some(switches) = &self.contexts {
            switches.validate().map_err(|reason| PlanError::Contexts {
                plan: self.name.clone(),
                reason,
            })?;
        }
        if self.competence.is_none()
            && let Some(arm) = self.arms.iter().find(|a| a.competent_passes() > 0)
        {
            return Err(PlanError::Competence {
                plan: self.name.clone(),
                reason: format!(
                    "the arm `{}` prefers behaviors the robot judges competent, and the plan sets no competence standard",
                    arm.name()
                ),
            });
        }
        if let Some(standard) = &self.competence {
            check_competence(self.domain, standard).map_err(|e| PlanError::Competence {
                plan: self.name.clone(),
                reason: e.to_string(),
            })?;
        }
        if self.complacency.is_some() {
            check_attention(self.domain, self.operators).map_err(|reason| {
                PlanError::AttentionNotModelled {
                    plan: self.name.clone(),
                    reason,
                }
            })?;
        }
        Ok(())
    }
}

/// Whether `domain` lets its robot judge its own competence under `standard`: it
/// declares parts its robot can record, gives a truth to measure them against (asked once,
/// on a stream of its own, so no stream of a run is touched), and the standard's bounds
/// are chances.
pub fn check_competence<D: Domain + ?Sized>(
    domain: &D,
    standard: &CompetenceStandard,
) -> Result<(), CompetenceError> {
    empty_record(domain, standard)?;
    let mut probe = ChaCha8Rng::seed_from_u64(0);
    if domain
        .competence_truth(&domain.space().unrank(0), &mut probe)
        .is_none()
    {
        return Err(CompetenceError::NoTruth {
            domain: domain.name().to_owned(),
        });
    }
    Ok(())
}

impl<'a, D: Domain> MissionPlan<'a, D> {
    /// The robot's judge of its own competence for one arm's chain, on a plan with a
    /// standard: an empty record, the domain's predictions, the standard.
    fn judge(&self) -> Option<CompetenceJudge<'a>> {
        let standard = self.competence.clone()?;
        let domain = self.domain;
        let record = empty_record(domain, &standard).expect("checked by MissionPlan::validate");
        Some(CompetenceJudge::new(
            record,
            Arc::new(move |behavior: &Behavior| domain.predict_competence(behavior)),
            standard,
        ))
    }
}

/// The truth of the behaviors' competence on one chain of a plan with a standard, each
/// behavior's learned once from the plan's truth runs on a stream of its own (so every
/// chain finds the same truth).
struct CompetenceTruth<'p, 'a, D: Domain> {
    plan: &'p MissionPlan<'a, D>,
    /// The seed and the plan's place, naming the streams.
    seed: u64,
    index: u64,
    known: HashMap<Behavior, bool>,
}

impl<'p, 'a, D: Domain> CompetenceTruth<'p, 'a, D> {
    /// Whether `behavior` is truly competent under the plan's standard.
    fn competent(&mut self, behavior: Behavior) -> bool {
        let plan = self.plan;
        let (seed, index) = (self.seed, self.index);
        *self.known.entry(behavior).or_insert_with(|| {
            let standard = plan.competence.as_ref().expect("a plan with a standard");
            let mut rng = stream(
                seed,
                index,
                plan.domain.space().rank(&behavior),
                Purpose::CompetenceTruth,
            );
            let rates = true_rates(plan.domain, &behavior, plan.truth_runs, &mut rng)
                .expect("checked by MissionPlan::validate");
            standard.met_by(&true_competence(
                plan.domain.competence_parts(),
                behavior,
                &rates,
            ))
        })
    }
}

/// Runs every plan: each (plan, arm, whether alerts are answered) is a chain of missions,
/// chains in parallel on the current rayon pool, and the plan's oracle runs the same
/// missions ([`crate::mission_oracle::MissionOracle`]). Every plan is checked first
/// ([`MissionPlan::validate`]): a refused plan stops the run before any mission.
pub fn run_missions<D: Domain>(
    plans: &[MissionPlan<'_, D>],
    seed: u64,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Vec<MissionResult>, PlanError> {
    for plan in plans {
        plan.validate()?;
    }
    let oracles = run_oracles(plans, seed)?;
    let chains: Vec<(usize, usize, bool)> = plans
        .iter()
        .enumerate()
        .flat_map(|(p, plan)| {
            let answers: &[bool] = if plan.complacency.is_some() {
                &[false, true]
            } else {
                &[false]
            };
            (0..plan.arms.len()).flat_map(move |a| answers.iter().map(move |&y| (p, a, y)))
        })
        .collect();
    let mut ran = chains
        .par_iter()
        .map(|&(p, a, answers)| run_chain(&plans[p], p as u64, a, answers, seed, &|| progress(p)))
        .collect::<Result<Vec<_>, PlanError>>()?
        .into_iter();
    Ok(plans
        .iter()
        .zip(oracles)
        .map(|(plan, oracle)| {
            let per_arm = if plan.complacency.is_some() { 2 } else { 1 };
            MissionResult {
                name: plan.name.clone(),
                complacency: plan.complacency.is_some(),
                context_switches: plan.contexts.is_some(),
                arms: ran.by_ref().take(plan.arms.len() * per_arm).collect(),
                oracle,
            }
        })
        .collect())
}

/// How many commands of a mission run between two looks at [`crate::interrupt`].
const INTERRUPT_EVERY: u32 = 4096;

fn run_chain<D: Domain>(
    plan: &MissionPlan<'_, D>,
    index: u64,
    arm_index: usize,
    answers_alerts: bool,
    seed: u64,
    progress: &(dyn Fn() + Sync),
) -> Result<MissionArmResult, PlanError> {
    let arm = &plan.arms[arm_index];
    let adapter =
        fresh_adapter(plan.domain, &plan.adapter, arm).map_err(|reason| PlanError::Config {
            plan: plan.name.clone(),
            reason,
        })?;
    let mut adapter = MissionAdapter::new(adapter);
    if let Some(judge) = plan.judge() {
        adapter = adapter
            .with_competence(judge)
            .preferring_competent(arm.competent_passes());
    }
    let mut truth = CompetenceTruth {
        plan,
        seed,
        index,
        known: HashMap::new(),
    };
    let mut missions = Vec::with_capacity(plan.missions as usize);
    let mut traced = MissionTrace::of(plan.commands);
    for mission in 0..plan.missions {
        crate::interrupt::check()?;
        let trace = (mission == 0).then_some(&mut traced);
        let named = StreamName {
            seed,
            plan: index,
            mission,
        };
        missions.push(run_mission(
            plan,
            arm,
            &mut adapter,
            named,
            answers_alerts,
            &mut truth,
            trace,
        )?);
        progress();
    }
    Ok(MissionArmResult {
        arm: arm.name().to_owned(),
        answers_alerts,
        missions,
        traced,
    })
}

/// A change scheduled for a mission: when, what, and the operator and context after it.
pub(crate) struct Scheduled {
    /// The command at which it happens.
    pub(crate) at: u32,
    /// What changes.
    pub(crate) kind: ChangeKind,
    /// The operator after it (its place in the population).
    pub(crate) operator: usize,
    /// The context after it (its place in [`ContextSwitches::among`]; 0 without switches).
    pub(crate) context: usize,
    /// A context switch back to a context the mission was in before.
    pub(crate) back: bool,
}

/// What a mission is whatever the robot does, drawn from its setup stream (and, with
/// context switches, a stream of their own): its first operator and context, its random
/// first behavior and its changes, the same for every arm and the oracle.
pub(crate) struct Course {
    /// The first operator (its place in the population).
    pub(crate) first: usize,
    /// The first context (its place in [`ContextSwitches::among`]; 0 without switches).
    pub(crate) first_context: usize,
    /// The random first behavior (drawn whatever the arm, so arms stay paired).
    pub(crate) drawn: Behavior,
    /// The changes, in order (an operator change before a context switch at the same
    /// command).
    pub(crate) scheduled: Vec<Scheduled>,
}

impl Course {
    /// The course of the mission `named` of `plan`.
    pub(crate) fn of<D: Domain>(plan: &MissionPlan<'_, D>, named: StreamName) -> Self {
        let mission = u64::from(named.mission);
        let mut setup = stream(named.seed, named.plan, mission, Purpose::Setup);
        let first = setup.random_range(0..plan.operators.len());
        let drawn = plan.domain.space().draw(&mut setup);
        let mut scheduled = schedule(plan, first, &mut setup);
        let mut first_context = 0;
        if let Some(switches) = &plan.contexts {
            let mut rng = stream(named.seed, named.plan, mission, Purpose::ContextSwitch);
            let switched;
            (first_context, switched) = switch_contexts(switches, plan.commands, &mut rng);
            scheduled.extend(switched);
            // At a command with both, the operator change comes first.
            scheduled.sort_by_key(|s| (s.at, s.kind == ChangeKind::Context));
            let (mut operator, mut context) = (first, first_context);
            for change in &mut scheduled {
                if change.kind == ChangeKind::Context {
                    change.operator = operator;
                    context = change.context;
                } else {
                    change.context = context;
                    operator = change.operator;
                }
            }
        }
        Self {
            first,
            first_context,
            drawn,
            scheduled,
        }
    }
}

/// The mission's changes after its `first` operator, the same for every arm.
fn schedule<D: Domain>(
    plan: &MissionPlan<'_, D>,
    first: usize,
    setup: &mut dyn RngCore,
) -> Vec<Scheduled> {
    let n = plan.operators.len();
    let mut changes = Vec::new();
    let (mut at, mut operator) = (0.0f64, first);
    loop {
        at += gap(plan.changes.every, setup);
        if at >= f64::from(plan.commands) || n < 2 {
            break;
        }
        let kind = if setup.random::<f64>() < plan.changes.takeover {
            ChangeKind::Takeover
        } else {
            ChangeKind::Shift
        };
        operator = another(n, operator, setup);
        changes.push(Scheduled {
            at: at as u32,
            kind,
            operator,
            context: 0,
            back: false,
        });
    }
    changes
}

/// The commands to the next change: an exponential gap of mean `every`, rounded up, at
/// least one.
fn gap(every: f64, rng: &mut dyn RngCore) -> f64 {
    let u: f64 = rng.random();
    (-every * (1.0 - u).ln()).ceil().max(1.0)
}

/// One of `0..n` other than `current`, uniformly (`n` at least 2).
fn another(n: usize, current: usize, rng: &mut dyn RngCore) -> usize {
    let next = rng.random_range(0..n - 1);
    if next >= current { next + 1 } else { next }
}

/// A mission's first context and its switches (their operator left for the caller), from
/// the mission's own stream of them.
fn switch_contexts(
    switches: &ContextSwitches,
    commands: u32,
    rng: &mut dyn RngCore,
) -> (usize, Vec<Scheduled>) {
    let n = switches.among.len();
    let first = rng.random_range(0..n);
    let mut seen = vec![false; n];
    seen[first] = true;
    let (mut at, mut context) = (0.0f64, first);
    let mut switched = Vec::new();
    loop {
        at += gap(switches.every, rng);
        if at >= f64::from(commands) {
            break;
        }
        context = another(n, context, rng);
        switched.push(Scheduled {
            at: at as u32,
            kind: ChangeKind::Context,
            operator: 0,
            context,
            back: seen[context],
        });
        seen[context] = true;
    }
    (first, switched)
}

/// Every member of a plan's population as it judges in each context of the plan's
/// switches (the member itself in a domain whose operators judge every context alike).
pub(crate) struct Judges<'p, D: Domain> {
    operators: &'p [(String, D::Operator)],
    /// Per context (in [`ContextSwitches::among`]'s order), per member, the member there
    /// when it judges differently from its own file; empty without switches.
    in_context: Vec<Vec<Option<D::Operator>>>,
}

impl<'p, D: Domain> Judges<'p, D> {
    /// The judges of `plan`.
    pub(crate) fn of(plan: &MissionPlan<'p, D>) -> Self {
        let in_context = plan.contexts.as_ref().map_or_else(Vec::new, |switches| {
            switches
                .among
                .iter()
                .map(|context| {
                    plan.operators
                        .iter()
                        .map(|(_, operator)| plan.domain.operator_in_context(operator, context))
                        .collect()
                })
                .collect()
        });
        Self {
            operators: plan.operators,
            in_context,
        }
    }

    /// Member `member` as it judges in context `context`.
    pub(crate) fn judge(&self, member: usize, context: usize) -> &D::Operator {
        self.in_context
            .get(context)
            .and_then(|members| members[member].as_ref())
            .unwrap_or(&self.operators[member].1)
    }
}

/// Whether `behavior` is trustworthy for `operator`: its mean weighted outcome over the
/// plan's truth runs is above 0 (the expected estimate climbs).
fn trustworthy<D: Domain>(
    plan: &MissionPlan<'_, D>,
    behavior: &Behavior,
    operator: &D::Operator,
    rng: &mut dyn RngCore,
) -> bool {
    let sum: f64 = (0..plan.truth_runs)
        .map(|_| {
            plan.domain
                .run(behavior, operator, rng)
                .outcome
                .contribution()
        })
        .sum();
    sum > 0.0
}

/// The operator's own state in a mission: its trust in the robot and whether it is
/// complacent.
struct OperatorState {
    /// Its trust in the robot, in `[0, 1]`.
    felt: f64,
    /// The onset under way, if the operator is complacent.
    onset: Option<usize>,
}

impl OperatorState {
    /// An operator whose trust in the robot starts from nothing, attentive: a new one, or
    /// one asked by an alert to look afresh.
    fn fresh() -> Self {
        Self {
            felt: 0.0,
            onset: None,
        }
    }
}

/// What names a mission's random streams: the master seed, its plan's place in the suite
/// and its number.
#[derive(Clone, Copy)]
pub(crate) struct StreamName {
    /// The master seed.
    pub(crate) seed: u64,
    /// The plan's place in the suite.
    pub(crate) plan: u64,
    /// The mission's number.
    pub(crate) mission: u32,
}

fn run_mission<D: Domain>(
    plan: &MissionPlan<'_, D>,
    arm: &Arm,
    adapter: &mut MissionAdapter<'_>,
    named: StreamName,
    answers_alerts: bool,
    truth: &mut CompetenceTruth<'_, '_, D>,
    mut trace: Option<&mut MissionTrace>,
) -> Result<MissionRecord, PlanError> {
    let StreamName {
        seed,
        plan: index,
        mission,
    } = named;
    let m = u64::from(mission);
    let Course {
        first,
        first_context,
        drawn,
        scheduled,
    } = Course::of(plan, named);
    let told = plan.contexts.is_some() && !arm.is_context_blind();
    if told {
        adapter
            .set_context(plan.context(first_context))
            .expect("no episode is under way between missions");
    }
    let judges = Judges::of(plan);
    let start = first_behavior(arm.initial(), adapter.adapter(), drawn);
    let mut drive = Drive::new(
        &plan.name,
        arm.name(),
        plan.domain,
        plan.feedback,
        None,
        seed,
        index,
        m,
        adapter,
    );
    adapter
        .begin_episode(start.behavior)
        .expect("no episode is under way and the behavior is drawn from the space");
    let mut record = MissionRecord {
        mission,
        learned_start: start.learned.then_some(start.behavior),
        context: plan.context(first_context),
        changes: Vec::new(),
        readaptations: 0,
        false_alarms: 0,
        alerts: Vec::new(),
        onsets: Vec::new(),
        failures: 0,
        overlooked: 0,
        untrustworthy: 0,
        calibration: plan
            .competence
            .as_ref()
            .map(|_| CalibrationRecord::default()),
    };
    let thresholds = adapter.adapter().parameters().thresholds;
    let (mut operator, mut context) = (first, first_context);
    let mut state = OperatorState::fresh();
    let mut behavior = start.behavior;
    let mut upcoming = scheduled.iter().peekable();
    // The last change, while the robot has not settled since, and whether any change
    // happened since the behavior in use settled.
    let mut waiting: Option<usize> = None;
    let mut changed_since_settled = false;
    for c in 0..plan.commands {
        // A long mission stops within a few milliseconds of a request, not at its end.
        if c % INTERRUPT_EVERY == 0 {
            crate::interrupt::check()?;
        }
        let mut marks = Vec::new();
        while let Some(change) = upcoming.next_if(|s| s.at == c) {
            (operator, context) = (change.operator, change.context);
            if change.kind == ChangeKind::Takeover {
                state = OperatorState::fresh();
            }
            let mut truth = stream(
                seed,
                index,
                m << 16 | record.changes.len() as u64,
                Purpose::Truth,
            );
            let needed = !trustworthy(plan, &behavior, judges.judge(operator, context), &mut truth);
            let k = begin_change(&mut record.changes, change, needed);
            waiting = Some(k);
            changed_since_settled = true;
            marks.push(Mark::Change(change.kind));
            if change.kind == ChangeKind::Context && told {
                let switched = adapter
                    .switch_context(plan.context(context), arm.initial() == Initial::Learned)
                    .expect("a mission always has an episode or a watch, in a declared context");
                record.changes[k].start = Some(switched.from);
                if switched.behavior != behavior {
                    record.changes[k].notice(c);
                }
                if switched.gave_up_watch {
                    record.readaptations += 1;
                    marks.push(Mark::Readaptation);
                } else if switched.behavior != behavior {
                    marks.push(Mark::Switch);
                }
                behavior = switched.behavior;
            }
        }
        // `None`: the paper's attentive operator.
        let attention = plan.complacency.map(|model| model.attention(state.felt));
        let level = attention.unwrap_or(1.0);
        if level < COMPLACENT_BELOW && state.onset.is_none() {
            state.onset = Some(record.onsets.len());
            record.onsets.push(OnsetRecord {
                at: c,
                detected_after: None,
                perceivable: 0,
            });
            marks.push(Mark::Onset);
        } else if level >= RECOVERED_AT {
            state.onset = None;
        }
        let judge = judges.judge(operator, context);
        let was_watching = adapter.watching().is_some();
        if let (Some(calibration), Some(watch), Some(robot)) = (
            record.calibration.as_mut(),
            adapter.watching(),
            adapter.competence_judge(),
        ) {
            // The command of a watched behavior: trusted or not, truly competent or not,
            // and what the robot judges of it, as the command is given.
            let trusted = thresholds.verdict(watch.estimate.value) == Verdict::Trustworthy;
            let competent = truth.competent(watch.behavior);
            let judged = matches!(
                robot.calibration(watch.behavior, watch.estimate.value, &thresholds),
                Calibration::Overtrust { .. }
            );
            let overtrusted = trusted && !competent;
            calibration.watched += 1;
            calibration.competent += u32::from(competent);
            calibration.overtrusted += u32::from(overtrusted);
            calibration.judged += u32::from(judged);
            calibration.both += u32::from(overtrusted && judged);
        }
        let Command {
            judgement,
            outcome,
            decision,
        } = drive.command(adapter, &behavior, judge, attention)?;
        record.failures += u32::from(outcome.kind == OutcomeKind::Failed);
        record.overlooked += u32::from(judgement.overlooked.is_some());
        if let Some(k) = state.onset {
            let onset = &mut record.onsets[k];
            if judgement.overlooked.is_some()
                && OwnRecord::has_signal(&outcome)
                && onset.detected_after.is_none()
            {
                onset.perceivable += 1;
            }
        }
        if outcome.is_untrustworthy() {
            count_untrustworthy(&mut record.untrustworthy, &mut record.changes, waiting);
        }
        if let Some(model) = plan.complacency {
            state.felt = model.felt_after(state.felt, &outcome);
        }
        match decision {
            MissionDecision::Episode(Decision::Keep) => {}
            MissionDecision::Alert(_) => {
                record.alerts.push(c);
                marks.push(Mark::Alert);
                if let Some(k) = state.onset {
                    let onset = &mut record.onsets[k];
                    onset.detected_after.get_or_insert(c - onset.at);
                }
                if answers_alerts {
                    // Asked to supervise, the operator looks afresh.
                    state = OperatorState::fresh();
                }
            }
            MissionDecision::Overtrust(alert) => {
                let competent = truth.competent(alert.behavior);
                let calibration = record
                    .calibration
                    .as_mut()
                    .expect("only a plan with a standard judges competence");
                calibration.alerts.push((c, competent));
                marks.push(Mark::Alert);
                if answers_alerts {
                    // Asked to choose, the operator looks afresh at the behavior.
                    state = OperatorState::fresh();
                    if let Some(offer) = alert.offer.filter(|_| plan.offer_safer) {
                        // Offered a safer behavior, it takes it if it trusts it too.
                        let mut judged = stream(
                            seed,
                            index,
                            m << 16 | u64::from(calibration.offered),
                            Purpose::Offer,
                        );
                        calibration.offered += 1;
                        if trustworthy(plan, &offer, judge, &mut judged) {
                            calibration.taken += 1;
                            adapter
                                .accept_offer(offer)
                                .expect("an alert came from a watched behavior of the space");
                            behavior = offer;
                        }
                    }
                }
            }
            MissionDecision::Episode(Decision::Switch { to, .. }) => {
                if let Some(k) = waiting {
                    record.changes[k].notice(c + 1);
                }
                if was_watching {
                    record.readaptations += 1;
                    record.false_alarms += u32::from(!changed_since_settled);
                    marks.push(Mark::Readaptation);
                } else {
                    marks.push(Mark::Switch);
                }
                behavior = to;
            }
            MissionDecision::Episode(Decision::Settled(report)) => {
                behavior = report.settled;
                changed_since_settled = false;
                if report.found_trustworthy
                    && let Some(k) = waiting.take()
                {
                    record.changes[k].trusted_again = Some(c + 1 - record.changes[k].at);
                }
                marks.push(Mark::Settled);
            }
        }
        if let Some(trace) = trace.as_deref_mut() {
            let estimate = adapter.in_use().map_or(0.0, |(_, e)| e.value);
            trace.record(
                c,
                MissionStep {
                    estimate,
                    low: estimate,
                    high: estimate,
                    own_record: adapter.watching().map(|_| adapter.own_record().value()),
                    untrustworthy: outcome.is_untrustworthy(),
                    marks,
                },
            );
        }
    }
    adapter.abandon_episode();
    Ok(record)
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
