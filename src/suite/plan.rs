//! From a checked config to the runner's plans: arms by name (the catalog's own, then the
//! built-in ones), one domain per scenario and each experiment's operators, and the
//! [`ExperimentPlan`]s, arms that read cases starting from saved ones when asked.

use super::{RANDOM_OPERATOR, StartingCases, SuiteConfig, SuiteError, invalid};
use crate::catalog::{Catalog, OperatorOf, UnknownScenario, domain_of, resolve_readings};
use files::name::check_file_name;
use lab::Domain;
use lab::contract::capability::Needing;
use lab::report::file_stems;
use lab::{
    Arm, ArmName, CONTEXT_BLIND, ExperimentPlan, IGNORES_STATEMENTS, LEARNED_START, OperatorChoice,
    PREFERS_COMPETENT, check_goal_changes,
};
use std::path::Path;
use trust::RetrieverKind;

/// The arm `name` names: the catalog's own arm of its base, or else a built-in one, with
/// the options its suffixes add ([`lab::NameOptions`]); the error lists every name
/// known. An arm's name is a file name (its saved case base is `EXPERIMENT/ARM.ron`), so a
/// name that is not one ([`check_file_name`]) is refused here, for every suite kind, sweep
/// and `serve --arm`, and so is an arm whose name would differ from the one asked for.
pub fn arm_named<C: Catalog>(
    catalog: &C,
    name: &ArmName,
    retriever: RetrieverKind,
) -> Result<Arm, String> {
    let own = catalog.arms(retriever);
    let arm = match own.iter().find(|a| a.name() == name.base()) {
        Some(arm) => arm.clone(),
        None => Arm::builtin(name.base(), retriever).map_err(|_| {
            let known: Vec<&str> = lab::builtin_arm_names()
                .into_iter()
                .chain(own.iter().map(Arm::name))
                .collect();
            format!(
                "unknown arm `{name}` (known: {}; each also as NAME{CONTEXT_BLIND}, NAME{IGNORES_STATEMENTS}, NAME{LEARNED_START} and NAME{PREFERS_COMPETENT})",
                known.join(", ")
            )
        })?,
    };
    let arm = arm.with_name_options(name.options());
    check_file_name("arm", arm.name()).map_err(|e| e.to_string())?;
    if arm.arm_name() != name {
        return Err(format!(
            "the arm `{name}` calls itself `{}`; an arm must keep the name it is given",
            arm.name()
        ));
    }
    Ok(arm)
}

/// What a suite's experiments need from the catalog: one domain per scenario (built once,
/// so its caches serve every experiment of that scenario) and each experiment's operators,
/// as the suite's readings read them.
pub(super) struct Parts<C: Catalog> {
    domains: Vec<C::Domain>,
    /// The index in `domains` of each experiment's domain.
    domain_index: Vec<usize>,
    /// Each experiment's operators.
    pub(super) operators: Vec<Vec<(String, OperatorOf<C>)>>,
}

impl<C: Catalog> Parts<C> {
    pub(super) fn of(catalog: &C, config: &SuiteConfig, origin: &Path) -> Result<Self, SuiteError> {
        let readings = resolve_readings(catalog, &config.readings)
            .map_err(|e| invalid(origin, "readings".into(), e.to_string()))?;
        let mut scenarios: Vec<&str> = Vec::new();
        let mut domain_index = Vec::with_capacity(config.experiments.len());
        for spec in &config.experiments {
            let k = scenarios
                .iter()
                .position(|s| *s == spec.scenario)
                .unwrap_or_else(|| {
                    scenarios.push(&spec.scenario);
                    scenarios.len() - 1
                });
            domain_index.push(k);
        }
        let domains = scenarios
            .iter()
            .map(|s| domain_of(catalog, s))
            .collect::<Result<Vec<C::Domain>, UnknownScenario>>()
            .map_err(|e| invalid(origin, "experiments".into(), e.to_string()))?;
        let operators = config
            .experiments
            .iter()
            .map(|spec| spec.operators(catalog, origin, &readings))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            domains,
            domain_index,
            operators,
        })
    }

    /// The domain of experiment `k`.
    pub(super) fn domain(&self, k: usize) -> &C::Domain {
        &self.domains[self.domain_index[k]]
    }
}

/// The experiment plans of `config` over `parts`, arms that reuse cases starting from
/// `starting` when given.
pub(super) fn plans<'p, C: Catalog>(
    parts: &'p Parts<C>,
    catalog: &C,
    config: &SuiteConfig,
    origin: &Path,
    starting: Option<&StartingCases>,
) -> Result<Vec<ExperimentPlan<'p, C::Domain>>, SuiteError> {
    let invalid = |field: String, message: String| invalid(origin, field, message);
    let arms = config
        .arms
        .iter()
        .map(|name| arm_named(catalog, name, config.adapter.retriever))
        .collect::<Result<Vec<Arm>, String>>()
        .map_err(|e| invalid("arms".into(), e))?;
    let stems = file_stems(config.experiments.iter().map(|s| s.name()));
    let mut plans: Vec<ExperimentPlan<'_, C::Domain>> = Vec::new();
    for (k, (spec, stem)) in config.experiments.iter().zip(&stems).enumerate() {
        let (domain, operators) = (parts.domain(k), &parts.operators[k]);
        let mut plan_arms = Vec::with_capacity(arms.len());
        for arm in &arms {
            let saved = match starting {
                Some(s) if arm.reads_cases() => s.load(
                    stem,
                    arm.name(),
                    &spec.scenario,
                    domain.space(),
                    domain.contexts(),
                )?,
                _ => None,
            };
            plan_arms.push(match saved {
                Some(cases) => arm.clone().with_starting_cases(cases),
                None => arm.clone(),
            });
        }
        let choice = if spec.operator == RANDOM_OPERATOR {
            OperatorChoice::Random
        } else {
            OperatorChoice::Fixed(
                operators
                    .iter()
                    .position(|(n, _)| *n == spec.operator)
                    .ok_or_else(|| {
                        invalid(
                            "experiments".into(),
                            format!("unknown operator `{}`", spec.operator),
                        )
                    })?,
            )
        };
        let contexts = spec
            .trial_contexts(domain.contexts())
            .map_err(|(field, reason)| invalid(format!("experiments[{k}].{field}"), reason))?;
        let goal_changes = spec
            .goal_changes
            .map(|changes| {
                check_goal_changes(domain).map(|changing| Needing {
                    setting: changes,
                    capability: changing,
                })
            })
            .transpose()
            .map_err(|e| invalid(format!("experiments[{k}].goal_changes"), e.to_string()))?;
        plans.push(ExperimentPlan {
            name: spec.name(),
            domain,
            operators,
            choice,
            trials: config.trials.get(),
            adapter: config.adapter.clone(),
            arms: plan_arms,
            max_commands: config.max_commands,
            feedback: spec.feedback,
            goal_changes,
            contexts,
            stated: spec.stated,
        });
    }
    Ok(plans)
}
