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
//! (the private `driver` module).

use crate::experiment::arm::Arm;
use crate::experiment::driver::{Command, Drive, first_behavior};
use crate::experiment::plan::*;
use crate::experiment::record::*;
use crate::seeds::{Purpose, stream};
use crate::stats::{mean_ci95_or_zero, paired_t_test, wilcoxon_signed_rank};
use crate::{Domain, GoalChangeRecord};
use cbr_core::Context;
use rand::Rng;
use rayon::prelude::*;
use std::collections::BTreeMap;
use trust::{Cause, Decision, Explanation, TrustAdapter};

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
        name: arm.arm_name().clone(),
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
