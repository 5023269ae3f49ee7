//! Running experiments: trials through the adapter, paired strategies, parallel chains.
//!
//! The case base persists across an experiment's trials, so the trials of one
//! (experiment, strategy) pair form a sequential *chain*; chains run in parallel on the
//! current rayon pool. Every random draw comes from a stream named by (seed, experiment,
//! trial, purpose), so results do not depend on the number of threads.

use super::seeds::{Purpose, stream, stream_seed};
use super::stats::{MeanCi, mean_ci95, paired_t_test};
use crate::{
    AdapterConfig, ConfigError, Decision, Domain, EpisodeReport, TrustAdapter, TrustCaseBase,
};
use cbr_core::Behavior;
use rand::Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// The two strategies the paper compares.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Strategy {
    /// The search strategy alone (the paper: random walk).
    RandomWalk,
    /// Algorithm 1, with the search strategy as fallback.
    CaseBased,
}

impl Strategy {
    /// Both strategies, in report order.
    pub const BOTH: [Strategy; 2] = [Strategy::RandomWalk, Strategy::CaseBased];

    /// The name used in reports (`random-walk`, `case-based`).
    pub fn name(self) -> &'static str {
        match self {
            Strategy::RandomWalk => "random-walk",
            Strategy::CaseBased => "case-based",
        }
    }
}

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
    /// Number of trials per strategy.
    pub trials: u32,
    /// The adapter's parameters; `reuse_cases` is set per strategy.
    pub adapter: AdapterConfig,
    /// Commands after which a trial is abandoned as unfinished (a guard against operators
    /// whose outcomes never reach a threshold).
    pub max_commands: u64,
}

/// The outcome of one trial.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrialRecord {
    /// Trial number, from 0; trials with the same number are paired across strategies.
    pub trial: u32,
    /// The strategy.
    pub strategy: Strategy,
    /// The operator that judged this trial.
    pub operator: String,
    /// The behavior the trial started with.
    pub initial: Behavior,
    /// How the episode ended.
    pub report: EpisodeReport,
    /// Runs (commands) performed.
    pub runs: u64,
    /// Whether the trial hit `max_commands` and was abandoned.
    pub truncated: bool,
}

/// One strategy's results in an experiment.
#[derive(Clone, Debug, PartialEq)]
pub struct StrategyResult {
    /// The strategy.
    pub strategy: Strategy,
    /// Behaviors evaluated per trial: mean and 95% confidence half-width.
    pub behaviors: MeanCi,
    /// Cases in the case base at the end of the experiment.
    pub cases_acquired: usize,
    /// Every trial, in order.
    pub trials: Vec<TrialRecord>,
}

impl StrategyResult {
    /// Behaviors evaluated in each trial, in trial order.
    pub fn counts(&self) -> Vec<f64> {
        self.trials
            .iter()
            .map(|t| t.report.behaviors_evaluated as f64)
            .collect()
    }
}

/// One experiment's results.
#[derive(Clone, Debug, PartialEq)]
pub struct ExperimentResult {
    /// The plan's name.
    pub name: String,
    /// Random walk, then case-based.
    pub strategies: [StrategyResult; 2],
    /// Paired t-test p-value of behaviors evaluated (random walk vs case-based).
    pub p_value: f64,
}

/// Runs every plan with both strategies, chains in parallel on the current rayon pool.
/// `progress(plan_index)` is called after every finished trial.
pub fn run_experiments<D: Domain>(
    plans: &[ExperimentPlan<'_, D>],
    seed: u64,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Vec<ExperimentResult>, ConfigError> {
    for plan in plans {
        plan.adapter.validate()?;
    }
    let chains: Vec<(usize, Strategy)> = (0..plans.len())
        .flat_map(|p| Strategy::BOTH.map(|s| (p, s)))
        .collect();
    let mut outcomes: Vec<StrategyResult> = chains
        .par_iter()
        .map(|&(p, strategy)| run_chain(&plans[p], p as u64, strategy, seed, &|| progress(p)))
        .collect::<Result<_, _>>()?;
    let mut results = Vec::with_capacity(plans.len());
    // Chains come back in plan order, random walk before case-based.
    for plan in plans.iter().rev() {
        let case_based = outcomes.pop().expect("two chains per plan");
        let random_walk = outcomes.pop().expect("two chains per plan");
        let p_value = paired_t_test(&random_walk.counts(), &case_based.counts()).unwrap_or(1.0);
        results.push(ExperimentResult {
            name: plan.name.clone(),
            strategies: [random_walk, case_based],
            p_value,
        });
    }
    results.reverse();
    Ok(results)
}

fn run_chain<D: Domain>(
    plan: &ExperimentPlan<'_, D>,
    experiment: u64,
    strategy: Strategy,
    seed: u64,
    progress: &(dyn Fn() + Sync),
) -> Result<StrategyResult, ConfigError> {
    let space = plan.domain.space().clone();
    let config = AdapterConfig {
        reuse_cases: strategy == Strategy::CaseBased,
        ..plan.adapter.clone()
    };
    let new_adapter =
        || TrustAdapter::new(space.clone(), config.clone(), TrustCaseBase::new(), seed);
    let independent = !config.reuse_cases && !config.search.learns_across_episodes();
    let (trials, cases_acquired) = if independent {
        // Nothing read from one episode carries to the next (the case base is never
        // consulted and the search forgets), so trials can run in any order. Each gets a
        // fresh adapter; the cases the episodes would have retained are counted.
        let trials: Vec<TrialRecord> = (0..plan.trials)
            .into_par_iter()
            .map(|trial| {
                let record =
                    run_trial(plan, &mut new_adapter()?, experiment, trial, strategy, seed);
                progress();
                Ok(record)
            })
            .collect::<Result<_, ConfigError>>()?;
        let retained = trials
            .iter()
            .filter(|t| t.report.retained.is_some())
            .count();
        (trials, retained)
    } else {
        let mut adapter = new_adapter()?;
        let trials: Vec<TrialRecord> = (0..plan.trials)
            .map(|trial| {
                let record = run_trial(plan, &mut adapter, experiment, trial, strategy, seed);
                progress();
                record
            })
            .collect();
        (trials, adapter.cases().len())
    };
    let mut result = StrategyResult {
        strategy,
        behaviors: MeanCi {
            mean: 0.0,
            ci95: 0.0,
        },
        cases_acquired,
        trials,
    };
    if let Some(behaviors) = mean_ci95(&result.counts()) {
        result.behaviors = behaviors;
    }
    Ok(result)
}

/// One trial: an episode from a drawn initial behavior until the adapter settles.
fn run_trial<D: Domain>(
    plan: &ExperimentPlan<'_, D>,
    adapter: &mut TrustAdapter,
    experiment: u64,
    trial: u32,
    strategy: Strategy,
    seed: u64,
) -> TrialRecord {
    let space = plan.domain.space();
    let mut setup = stream(seed, experiment, u64::from(trial), Purpose::Setup);
    let operator_index = match plan.choice {
        OperatorChoice::Fixed(i) => i,
        OperatorChoice::Random => setup.random_range(0..plan.operators.len()),
    };
    let (operator_name, operator) = &plan.operators[operator_index];
    let initial = space.draw(&mut setup);
    adapter.reseed(stream_seed(
        seed,
        experiment,
        u64::from(trial),
        Purpose::Search,
    ));
    let mut runs_rng = stream(seed, experiment, u64::from(trial), Purpose::Runs);
    adapter
        .begin_episode(initial)
        .expect("no episode is under way and the behavior is drawn from the space");
    let mut behavior = initial;
    let mut runs = 0u64;
    let (report, truncated) = loop {
        let outcome = plan.domain.run(&behavior, operator, &mut runs_rng);
        runs += 1;
        match adapter
            .record(&outcome)
            .expect("domains report valid outcomes")
        {
            Decision::Keep => {}
            Decision::Switch { to, .. } => behavior = to,
            Decision::Settled(report) => break (report, false),
        }
        if runs >= plan.max_commands {
            let report = adapter.abandon_episode().expect("an episode is under way");
            break (report, true);
        }
    };
    TrialRecord {
        trial,
        strategy,
        operator: operator_name.clone(),
        initial,
        report,
        runs,
        truncated,
    }
}
