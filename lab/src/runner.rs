//! Running experiments: trials through the adapter, any number of paired arms, parallel
//! chains.
//!
//! The case base (and what a learning search and the explanations learn) persists across
//! an experiment's trials, so the trials of one (experiment, arm) pair form a sequential
//! *chain*; chains run in parallel on the current rayon pool, and so do the trials of a
//! chain whose arm reads nothing from earlier episodes. Every random draw comes from a
//! stream named by (seed, experiment, trial, purpose), and trial `i` of every arm gets the
//! same streams (operator and random initial behavior, simulated runs, search), so arms
//! are paired trial by trial and results do not depend on the number of threads; an arm
//! that starts from the case memory's guess draws the random behavior all the same. A
//! trial's first behavior and its commands are driven as a mission's are
//! (the private `drive` module).

use crate::arm::{Arm, Initial};
use crate::domain::{AttentionNotModelled, GoalChangesNotModelled, check_goal_changes};
use crate::drive::{Command, Drive, first_behavior};
use crate::known_operator::KnownLimitError;
use crate::seeds::{Purpose, stream};
use crate::stating::Stating;
use crate::stats::{MeanCi, mean_ci95_or_zero, paired_t_test, wilcoxon_signed_rank};
use crate::{Domain, FeedbackChannel, GoalChangeRecord, GoalChanges, TrialContexts};
use cbr_core::{Behavior, Context, Statement};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::sync::Arc;
use trust::{
    AdapterConfig, Cause, ConfigError, Decision, EpisodeReport, Explanation, Outcome,
    SetSimilarity, Source, TrustAdapter, TrustCaseBase, TrustMemory, UndeclaredCause,
};

/// Which operator judges each trial.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OperatorChoice {
    /// Always the operator at this index.
    Fixed(usize),
    /// One drawn uniformly per trial.
    Random,
}

/// One experiment to run.
pub struct ExperimentPlan<'a, D: Domain> {
    /// Name used in reports, e.g. `movement/speed-focused`.
    pub name: String,
    /// The domain and the operators available in it, with their names.
    pub domain: &'a D,
    /// The operators, by name.
    pub operators: &'a [(String, D::Operator)],
    /// Which operator judges each trial.
    pub choice: OperatorChoice,
    /// Number of trials per arm.
    pub trials: u32,
    /// The adapter every arm starts from: its thresholds, `lambda`, retention and unit of
    /// time are every arm's; whether cases are reused, the search strategy and the
    /// retriever are each arm's own, and replace the config's.
    pub adapter: AdapterConfig,
    /// The arms compared, paired trial by trial; every other arm is tested against the
    /// first.
    pub arms: Vec<Arm>,
    /// Commands after which a trial is abandoned as unfinished (a guard against operators
    /// whose outcomes never reach a threshold).
    pub max_commands: u64,
    /// How every operator of the plan explains itself, overriding each operator's own
    /// channel ([`Domain::feedback`]); `None` keeps the operators' own.
    pub feedback: Option<FeedbackChannel>,
    /// How often the operators' goals change ([`crate::goal_change`]); `None`, the
    /// paper's assumption: never.
    pub goal_changes: Option<GoalChanges>,
    /// The contexts the trials run in, and whether the robot is told them
    /// ([`crate::context`]); `None`: every trial in the default context, as the paper's.
    pub contexts: Option<TrialContexts>,
    /// What the operators state up front ([`crate::stating`]); `None`, the paper's
    /// operators: nothing.
    pub stated: Option<Stating>,
}

/// Why experiments cannot be run.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PlanError {
    /// Thresholds or lambda are unusable.
    #[error("{plan}: {reason}")]
    Config {
        /// The plan's name.
        plan: String,
        /// What is wrong.
        reason: ConfigError,
    },
    /// A plan has no arm.
    #[error("{plan}: no arm to run")]
    NoArms {
        /// The plan's name.
        plan: String,
    },
    /// The domain reported a judgement whose true reason it does not declare.
    #[error("{plan}: domain `{domain}` reported an outcome whose {reason}")]
    UndeclaredCause {
        /// The plan's name.
        plan: String,
        /// The domain's name.
        domain: String,
        /// The cause and the declared ones (boxed: a rare error should not make every
        /// result that may carry one larger).
        reason: Box<UndeclaredCause>,
    },
    /// Two arms of a plan share a name.
    #[error("{plan}: two arms are named `{arm}`")]
    DuplicateArm {
        /// The plan's name.
        plan: String,
        /// The name.
        arm: String,
    },
    /// An arm's searcher broke its contract: it proposed a behavior outside the space, or
    /// one the episode had already evaluated.
    #[error(
        "{plan}: the search of arm `{arm}` proposed {behavior}, which {problem}; a searcher proposes behaviors of the space that the episode has not evaluated (trust::testing::check_searcher checks a searcher for this)"
    )]
    Searcher {
        /// The plan's name.
        plan: String,
        /// The arm's name.
        arm: String,
        /// The behavior, in real units (as value indices when outside the space).
        behavior: String,
        /// What is wrong with it.
        problem: &'static str,
    },
    /// A mission plan's context switches are unusable.
    #[error("{plan}: {reason}")]
    Contexts {
        /// The plan's name.
        plan: String,
        /// Why.
        reason: String,
    },
    /// A plan's operators state preferences up front in a domain that declares no names
    /// to state them in ([`Domain::statements`]).
    #[error(
        "{plan}: domain `{domain}` declares no statements (Domain::statements), so its operators have nothing to state: remove `stated`"
    )]
    NoStatements {
        /// The plan's name.
        plan: String,
        /// The domain's name.
        domain: String,
    },
    /// A plan sets a competence standard its domain cannot judge.
    #[error("{plan}: {reason}")]
    Competence {
        /// The plan's name.
        plan: String,
        /// Why.
        reason: String,
    },
    /// A plan's operators grow complacent, but its domain does not model attention
    /// ([`crate::domain::check_attention`]).
    #[error("{plan}: {reason}")]
    AttentionNotModelled {
        /// The plan's name.
        plan: String,
        /// The domain that keeps the default [`Domain::run_attending`].
        reason: AttentionNotModelled,
    },
    /// A plan's operators' goals change, but its domain does not model goal changes
    /// ([`crate::domain::check_goal_changes`]).
    #[error("{plan}: {reason}")]
    GoalChangesNotModelled {
        /// The plan's name.
        plan: String,
        /// The domain that keeps the default [`Domain::run_redirected`].
        reason: GoalChangesNotModelled,
    },
    /// A mission plan's oracle could not learn an operator's landscape
    /// ([`crate::mission_oracle`]).
    #[error("{plan}: the mission oracle, operator `{operator}`: {reason}")]
    Oracle {
        /// The plan's name.
        plan: String,
        /// The operator's name.
        operator: String,
        /// Why its known-operator estimate failed.
        reason: KnownLimitError,
    },
    /// A stop was requested ([`crate::interrupt`]) before every trial had run.
    #[error(transparent)]
    Interrupted(#[from] crate::Interrupted),
}

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
    /// [`trace_trial`] replays a trial with them, and [`ArmResult::samples`] keeps a few.
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
    fn score(
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
    pub name: String,
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
            name: name.to_owned(),
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
        self.arms.iter().find(|a| a.name == name)
    }

    /// Trials per arm.
    pub fn trials(&self) -> usize {
        self.arms.first().map_or(0, |a| a.trials.len())
    }
}

/// Runs every plan with every arm, chains in parallel on the current rayon pool.
/// `progress(plan_index)` is called after every finished trial.
pub fn run_experiments<D: Domain>(
    plans: &[ExperimentPlan<'_, D>],
    seed: u64,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Vec<ExperimentResult>, PlanError> {
    for plan in plans {
        plan.validate()?;
    }
    let chains: Vec<(usize, usize)> = plans
        .iter()
        .enumerate()
        .flat_map(|(p, plan)| (0..plan.arms.len()).map(move |a| (p, a)))
        .collect();
    let mut outcomes = chains
        .par_iter()
        .map(|&(p, a)| run_chain(&plans[p], p as u64, a, seed, &|| progress(p)))
        .collect::<Result<Vec<ArmResult>, PlanError>>()?
        .into_iter();
    // Chains come back in plan order, arms in order within a plan.
    Ok(plans
        .iter()
        .map(|plan| {
            let mut arms: Vec<ArmResult> = outcomes.by_ref().take(plan.arms.len()).collect();
            let first = arms[0].counts();
            for arm in &mut arms[1..] {
                let counts = arm.counts();
                arm.versus_first = Some(PairedTests {
                    t_test_p: paired_t_test(&first, &counts).unwrap_or(1.0),
                    wilcoxon_p: wilcoxon_signed_rank(&first, &counts).unwrap_or(1.0),
                });
            }
            ExperimentResult {
                name: plan.name.clone(),
                arms,
            }
        })
        .collect())
}

impl<D: Domain> ExperimentPlan<'_, D> {
    fn validate(&self) -> Result<(), PlanError> {
        let config = |reason: ConfigError| PlanError::Config {
            plan: self.name.clone(),
            reason,
        };
        self.adapter.validate().map_err(config)?;
        if self.arms.is_empty() {
            return Err(PlanError::NoArms {
                plan: self.name.clone(),
            });
        }
        for (i, arm) in self.arms.iter().enumerate() {
            if self.arms[..i].iter().any(|a| a.name() == arm.name()) {
                return Err(PlanError::DuplicateArm {
                    plan: self.name.clone(),
                    arm: arm.name().to_owned(),
                });
            }
        }
        if self.stated.is_some() && self.domain.statements().is_empty() {
            return Err(PlanError::NoStatements {
                plan: self.name.clone(),
                domain: self.domain.name().to_owned(),
            });
        }
        if self.goal_changes.is_some() {
            check_goal_changes(self.domain, self.operators).map_err(|reason| {
                PlanError::GoalChangesNotModelled {
                    plan: self.name.clone(),
                    reason,
                }
            })?;
        }
        Ok(())
    }

    /// Whether no operator of the plan ever states a reason: its channel, or every
    /// operator's own, is silent, so explanations learn nothing across episodes.
    fn never_told(&self) -> bool {
        match self.feedback {
            Some(channel) => channel.is_silent(),
            None => self
                .operators
                .iter()
                .all(|(_, operator)| self.domain.feedback(operator).is_silent()),
        }
    }

    /// A fresh adapter for `arm`, from its starting cases.
    fn adapter(&self, arm: &Arm) -> Result<TrustAdapter, PlanError> {
        fresh_adapter(self.domain, &self.adapter, arm).map_err(|reason| PlanError::Config {
            plan: self.name.clone(),
            reason,
        })
    }
}

/// A fresh adapter for `arm` over `domain`'s space, from the arm's starting cases, its
/// own case reuse, retriever and searcher and the rest of `adapter`, explaining itself in
/// the domain's terms. Its search stream is reseeded before every episode.
pub(crate) fn fresh_adapter<D: Domain>(
    domain: &D,
    adapter: &AdapterConfig,
    arm: &Arm,
) -> Result<TrustAdapter, ConfigError> {
    let space = domain.space();
    let measure = SetSimilarity::of_domain(
        space.clone(),
        adapter.lambda,
        Arc::new(domain.contexts().clone()),
    )?;
    let retriever = arm.build_retriever(measure);
    let cases = arm.starting_cases().cloned().unwrap_or_default();
    let parameters = AdapterConfig {
        reuse_cases: arm.reuses_cases(),
        ..*adapter
    }
    .parameters();
    Ok(TrustAdapter::with_parts(
        space.clone(),
        parameters,
        TrustMemory::new(cases, retriever),
        arm.build_searcher(space),
        ChaCha8Rng::seed_from_u64(0),
    )?
    .with_vocabulary(crate::vocabulary(domain)))
}

/// What one trial of a chain leaves for its arm's result.
struct ChainTrial {
    record: TrialRecord,
    /// Explanations of its given-up behaviors, at most [`SAMPLE_EXPLANATIONS`].
    samples: Vec<ExplanationSample>,
    /// Every command, when the trial is traced.
    traced: Option<Vec<TracedCommand>>,
}

fn run_chain<D: Domain>(
    plan: &ExperimentPlan<'_, D>,
    experiment: u64,
    arm_index: usize,
    seed: u64,
    progress: &(dyn Fn() + Sync),
) -> Result<ArmResult, PlanError> {
    let arm = &plan.arms[arm_index];
    let starting_cases = arm.starting_cases().map_or(0, |c| c.len());
    let mut adapter = plan.adapter(arm)?;
    let traces = sample_arm(&plan.arms) == Some(arm_index);
    // One trial, with the explanations of its given-up behaviors (at most as many as the
    // samples need) and, for the first traced trials of the sample arm, every command.
    let one = |adapter: &mut TrustAdapter, trial: u32| -> Result<ChainTrial, PlanError> {
        crate::interrupt::check()?;
        let mut commands = Vec::new();
        let tracing = traces && trial < TRACED_TRIALS;
        let (record, explanations) =
            run_trial(plan, adapter, experiment, trial, arm, seed, &mut |step| {
                if tracing && (commands.len() as u64) < MAX_TRACED_COMMANDS {
                    commands.push(TracedCommand::of(&step));
                }
            })?;
        if record.report.commands > MAX_TRACED_COMMANDS {
            commands = Vec::new();
        }
        let samples = explanations
            .into_iter()
            .filter(|x| x.given_up.is_some())
            .zip(&record.given_up)
            .take(SAMPLE_EXPLANATIONS)
            .map(|(explanation, given_up)| ExplanationSample {
                trial,
                explanation,
                truth: given_up.truth,
            })
            .collect();
        progress();
        Ok(ChainTrial {
            record,
            samples,
            traced: tracing.then_some(commands),
        })
    };
    // Every trial reads what earlier ones left: the case base (reused, or guessed a first
    // behavior from), a learning search, and what the explanations learned from the
    // reasons operators stated (trust::explain), so a chain runs in order. Where an arm
    // reads none of these (it reads no case, its search forgets, and no operator of the
    // plan ever states a reason), trials are independent: each gets a fresh adapter and
    // they run in parallel, with the same records; the cases the episodes would have
    // retained are counted.
    let independent = !arm.reads_cases() && !adapter.learns_across_episodes() && plan.never_told();
    let outputs: Vec<ChainTrial> = if independent {
        (0..plan.trials)
            .into_par_iter()
            .map(|trial| one(&mut plan.adapter(arm)?, trial))
            .collect::<Result<_, PlanError>>()?
    } else {
        (0..plan.trials)
            .map(|trial| one(&mut adapter, trial))
            .collect::<Result<_, PlanError>>()?
    };
    let mut trials = Vec::with_capacity(outputs.len());
    let mut samples = Vec::new();
    let mut traced = Vec::new();
    for output in outputs {
        let wanted = SAMPLE_EXPLANATIONS - samples.len();
        samples.extend(output.samples.into_iter().take(wanted));
        traced.extend(output.traced);
        trials.push(output.record);
    }
    let (cases_acquired, final_cases) = if independent {
        let retained = trials
            .iter()
            .filter(|t| t.report.retained.is_some())
            .count();
        (retained, None)
    } else {
        (
            adapter.cases().len() - starting_cases,
            arm.reads_cases().then(|| adapter.cases().clone()),
        )
    };
    let summary = |values: Vec<f64>| mean_ci95_or_zero(&values);
    let of = |value: fn(&TrialRecord) -> f64| summary(trials.iter().map(value).collect());
    let mut explained = ExplanationCheck::default();
    for t in &trials {
        explained.add(&t.explained);
    }
    Ok(ArmResult {
        name: arm.name().to_owned(),
        reuses_cases: arm.reuses_cases(),
        initial: arm.initial(),
        starting_cases,
        behaviors: of(|t| t.report.behaviors_evaluated as f64),
        commands: of(|t| t.report.commands as f64),
        untrustworthy: of(|t| t.report.untrustworthy as f64),
        found_share: of(|t| f64::from(u8::from(t.report.found_trustworthy))),
        cases_acquired,
        final_cases,
        versus_first: None,
        explained,
        samples,
        traced,
        trials,
    })
}

/// One command of a trial, as [`trace_trial`] shows it.
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
    fn of(step: &Step<'_>) -> Self {
        Self {
            behavior: step.behavior,
            outcome: *step.outcome,
            truth: step.truth,
            estimate: step.estimate,
            explanation: step.explanation.cloned(),
        }
    }
}

/// Replays trial `trial` of arm `arm` in plan `experiment` (its index in the suite, which
/// names its random streams) and returns its record and every command. Trials are
/// paired by their streams, so the replay is exactly the trial the suite ran; what the
/// adapter carries across episodes is rebuilt by replaying the trials before it first.
pub fn trace_trial<D: Domain>(
    plan: &ExperimentPlan<'_, D>,
    experiment: u64,
    arm: usize,
    trial: u32,
    seed: u64,
) -> Result<(TrialRecord, Vec<TracedCommand>), PlanError> {
    plan.validate()?;
    let arm = &plan.arms[arm];
    let mut adapter = plan.adapter(arm)?;
    for earlier in 0..trial {
        run_trial(
            plan,
            &mut adapter,
            experiment,
            earlier,
            arm,
            seed,
            &mut |_| {},
        )?;
    }
    let mut commands = Vec::new();
    let (record, _) = run_trial(
        plan,
        &mut adapter,
        experiment,
        trial,
        arm,
        seed,
        &mut |step| {
            commands.push(TracedCommand::of(&step));
        },
    )?;
    Ok((record, commands))
}

/// One trial: an episode from its initial behavior ([`first_behavior`]) until the adapter
/// settles, command after command ([`Drive::command`], the operator attentive). Every
/// judgement's true reason must be one the domain declares; the adapter is told only the
/// outcome, with the reason the operator's feedback channel states.
fn run_trial<D: Domain>(
    plan: &ExperimentPlan<'_, D>,
    adapter: &mut TrustAdapter,
    experiment: u64,
    trial: u32,
    arm: &Arm,
    seed: u64,
    observe: &mut dyn FnMut(Step<'_>),
) -> Result<(TrialRecord, Vec<Explanation>), PlanError> {
    let mut setup = stream(seed, experiment, u64::from(trial), Purpose::Setup);
    let operator_index = match plan.choice {
        OperatorChoice::Fixed(i) => i,
        OperatorChoice::Random => setup.random_range(0..plan.operators.len()),
    };
    let (operator_name, operator) = &plan.operators[operator_index];
    let context = plan
        .contexts
        .as_ref()
        .map_or_else(Context::default, |c| c.of_trial(trial).clone());
    let in_context = plan.domain.operator_in_context(operator, &context);
    let operator = in_context.as_ref().unwrap_or(operator);
    if plan.contexts.is_some() {
        // A context-blind arm, as the paper's robot, is never told it.
        let told = if arm.is_context_blind() {
            Context::default()
        } else {
            context.clone()
        };
        adapter
            .set_context(told)
            .expect("no episode is under way between trials");
    }
    let stated = plan.stated.map_or_else(Vec::new, |stating| {
        let mut draws = stream(seed, experiment, u64::from(trial), Purpose::Statements);
        stating.draw(&plan.domain.true_statements(operator), &mut draws)
    });
    let drawn = adapter.space().draw(&mut setup);
    let start = first_behavior(arm.initial(), adapter, drawn);
    let mut drive = Drive::new(
        &plan.name,
        arm.name(),
        plan.domain,
        plan.feedback,
        plan.goal_changes,
        seed,
        experiment,
        u64::from(trial),
        adapter,
    );
    adapter
        .begin_episode_hearing(
            start.behavior,
            if arm.ignores_statements() {
                Vec::new()
            } else {
                stated.clone()
            },
        )
        .expect("no episode is under way, the behavior is drawn from the space and the domain states each name once");
    let mut behavior = start.behavior;
    let mut runs = 0u64;
    let mut true_causes = BTreeMap::new();
    let mut behavior_truth: BTreeMap<Cause, u32> = BTreeMap::new();
    let mut explained = ExplanationCheck::default();
    let mut given_up = Vec::new();
    let mut estimate = 0.0;
    let mut goal_changes = plan.goal_changes.map(|_| GoalChangeRecord::default());
    let perceived = plan.domain.observations();
    let (report, truncated) = loop {
        let Command {
            judgement,
            outcome,
            decision,
        } = drive.command(adapter, &behavior, operator, None)?;
        if let Some(cause) = judgement.truth {
            *true_causes.entry(cause).or_insert(0) += 1;
            *behavior_truth.entry(cause).or_insert(0) += 1;
        }
        if let Some(record) = &mut goal_changes {
            record.record(&judgement, &outcome);
        }
        runs += 1;
        estimate += outcome.contribution();
        let explanation = match &decision {
            Decision::Keep => None,
            Decision::Switch { explanation, .. } => Some(&**explanation),
            Decision::Settled(report) => report.explanations.last(),
        };
        observe(Step {
            behavior,
            outcome: &outcome,
            truth: judgement.truth,
            estimate,
            explanation,
        });
        if let Some(explanation) = explanation
            && let Some(account) = &explanation.given_up
        {
            let scored = explained.score(&account.leading_reasons(), &behavior_truth, perceived);
            given_up.push(GivenUpRecord {
                reason: account.decided_reason(),
                next: explanation.next.source(),
                truth: scored.map(|(truth, _)| truth),
                right: scored.is_some_and(|(_, right)| right),
            });
        }
        match decision {
            Decision::Keep => {}
            Decision::Switch { to, .. } => {
                behavior = to;
                behavior_truth.clear();
                estimate = 0.0;
            }
            Decision::Settled(report) => break (report, false),
        }
        if runs >= plan.max_commands {
            let report = adapter.abandon_episode().expect("an episode is under way");
            break (report, true);
        }
    };
    let mut report = report;
    let explanations = std::mem::take(&mut report.explanations);
    // An experiment keeps every trial's record for its report: no spare capacity.
    given_up.shrink_to_fit();
    report.evaluated.shrink_to_fit();
    Ok((
        TrialRecord {
            trial,
            arm: arm.name().to_owned(),
            operator: operator_name.clone(),
            initial: start.behavior,
            learned_start: start.learned,
            report,
            truncated,
            true_causes,
            explained,
            given_up,
            goal_changes,
            context,
            stated,
        },
        explanations,
    ))
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
