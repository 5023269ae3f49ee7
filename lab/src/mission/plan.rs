//! What a mission suite's plan is: how often the operator changes ([`Changes`]), the
//! context switches ([`ContextSwitches`]), the complacency model ([`Complacency`]) and the
//! plan itself ([`MissionPlan`]), checked before any mission runs.

use crate::contract::capability::{Needing, check_self_judging};
use crate::experiment::arm::Arm;
use crate::experiment::plan::PlanError;
use crate::experiment::simulate::Attention;
use crate::reference::competence_truth::{CompetenceError, empty_record};
use crate::reference::known_operator::LimitSettings;
use crate::{Attentive, SelfJudging};
use crate::{Domain, FeedbackChannel};
use cbr_core::{Behavior, Context};
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use trust::{AdapterConfig, CompetenceJudge, CompetenceStandard, Outcome};

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

/// Operators who grow complacent, with the plan's domain as one that models attention
/// ([`crate::contract::capability`]: a plan over a domain that does not is refused by the
/// compiler, or where a file's plan enters).
pub type ComplacencyOn<'a, O> = Needing<'a, Complacency, dyn Attentive<Operator = O> + 'a>;

impl<'a, O> ComplacencyOn<'a, O> {
    /// The operator's attention at its own trust `felt` ([`Complacency::attention`]),
    /// with the domain that models it.
    pub(crate) fn attention(&self, felt: f64) -> Attention<'a, O> {
        (self.setting.attention(felt), self.capability)
    }
}

/// A competence standard, with the plan's domain as one whose robot judges itself.
pub type CompetenceOn<'a, O> = Needing<'a, CompetenceStandard, dyn SelfJudging<Operator = O> + 'a>;

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
    /// How operators grow complacent, with the domain as one that models attention
    /// (`None`: they stay attentive, the paper's).
    pub complacency: Option<ComplacencyOn<'a, D::Operator>>,
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
    /// trustworthy region) is estimated ([`crate::mission::oracle`]).
    pub limit: LimitSettings,
    /// The standard the robot holds its own competence to (`None`: it does not judge
    /// it): every arm then judges every command's behavior ([`trust::competence`]),
    /// raises an overtrust alert once per settled behavior its operator trusts and it
    /// judges not competent, and its records carry the calibration against the truth
    /// ([`CalibrationRecord`](crate::mission::CalibrationRecord)). With it, the domain as
    /// one whose robot judges itself.
    pub competence: Option<CompetenceOn<'a, D::Operator>>,
    /// Whether an answered overtrust alert offers a safer behavior
    /// ([`trust::CompetenceAlert::offer`]), which the operator takes when it trusts it
    /// too (judged on [`MissionPlan::truth_runs`] commands, as a change's need is);
    /// `false`: the operator only looks afresh.
    pub offer_safer: bool,
    /// A change detector beside the paper's thresholds for every arm
    /// ([`trust::MissionAdapter::detecting_changes`]; `None`: the thresholds alone).
    pub change_detector: Option<trust::ChangeDetector>,
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
    pub(crate) fn context(&self, context: usize) -> Context {
        self.contexts
            .as_ref()
            .map_or_else(Context::default, |c| c.among[context].clone())
    }

    /// Refuses a plan whose context switches are not usable, an arm that prefers
    /// competent behaviors without a standard, and a standard the domain's parts cannot
    /// be held to.
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
        if let Some(competence) = &self.competence {
            empty_record(competence.capability, &competence.setting).map_err(|e| {
                PlanError::Competence {
                    plan: self.name.clone(),
                    reason: e.to_string(),
                }
            })?;
        }
        Ok(())
    }
}

/// Whether `domain` lets its robot judge its own competence under `standard`, checked
/// where a plan read from a file enters: it models it ([`crate::SelfJudging`]), declares
/// parts its robot can record, and the standard's bounds are chances. The domain as one
/// whose robot judges itself when it does.
pub fn check_competence<'d, D: Domain + ?Sized>(
    domain: &'d D,
    standard: &CompetenceStandard,
) -> Result<&'d dyn SelfJudging<Operator = D::Operator>, CompetenceError> {
    let judging = check_self_judging(domain)?;
    empty_record(judging, standard)?;
    Ok(judging)
}

impl<'a, D: Domain> MissionPlan<'a, D> {
    /// The robot's judge of its own competence for one arm's chain, on a plan with a
    /// standard: an empty record, the domain's predictions, the standard.
    pub(crate) fn judge(&self) -> Option<CompetenceJudge<'a>> {
        let Needing {
            setting: standard,
            capability: judging,
        } = self.competence.clone()?;
        let record = empty_record(judging, &standard).expect("checked by MissionPlan::validate");
        Some(CompetenceJudge::new(
            record,
            Arc::new(move |behavior: &Behavior| judging.predict_competence(behavior)),
            standard,
        ))
    }
}
