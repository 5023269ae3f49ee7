//! What a suite's report estimates from the config alone, beside the experiments: the
//! landscapes behind each experiment's final behaviors and its known-operator limit (once
//! per scenario and operator).

use super::plan::Parts;
use super::{SuiteConfig, SuiteError, invalid};
use crate::catalog::{Catalog, OperatorOf};
use cbr_core::Context;
use lab::Domain;
use lab::reference::known_operator::{
    ExperimentLimit, KnownLimitError, KnownOperator, known_operator,
};
use lab::reference::landscape::Landscape;
use lab::reference::population_reference::ReferencePlan;
use lab::report::finals_landscapes;
use lab::seeds::{Purpose, stream_seed};
use std::path::Path;

/// The known-operator limit of each operator a suite's experiments draw from, computed
/// once per scenario and operator (an operator of a `random` experiment is usually also
/// an experiment's own). Operator number `i` in order of first use draws from the seed
/// `stream_seed(seed, 0, i, Limit)`.
#[derive(Default)]
struct OperatorLimits {
    known: Vec<((String, String), KnownOperator)>,
}

impl OperatorLimits {
    /// The limit of operator `name` (`operator`) in experiment `k`'s scenario.
    fn of<C: Catalog>(
        &mut self,
        parts: &Parts<C>,
        config: &SuiteConfig,
        k: usize,
        name: &str,
        operator: &OperatorOf<C>,
    ) -> Result<usize, KnownLimitError> {
        let key = (config.experiments[k].scenario.clone(), name.to_owned());
        if let Some(i) = self.known.iter().position(|(known, _)| *known == key) {
            return Ok(i);
        }
        let seed = stream_seed(config.seed, 0, self.known.len() as u64, Purpose::Limit);
        let known = known_operator(
            parts.domain(k),
            operator,
            config.adapter.thresholds,
            config.limit,
            seed,
        )?;
        self.known.push((key, known));
        Ok(self.known.len() - 1)
    }
}

/// An operator of an experiment in one of its trials' contexts: its name there (with
/// `@context` when it judges otherwise there), the operator as it judges there when it
/// does, and the operator itself.
type InContext<'a, C> = (String, Option<OperatorOf<C>>, &'a OperatorOf<C>);

/// What a suite's report estimates beside the experiments' results, from the config alone:
/// the landscapes behind each experiment's final behaviors and its known-operator limit
/// ([`run_suite_with_report`](super::run_suite_with_report)). Independent of the results, so it is computed while the
/// experiments run.
pub struct ReportEstimates {
    /// Per experiment, its landscapes (empty when `landscape_runs` is 0).
    pub(super) landscapes: Vec<Vec<Landscape>>,
    /// Per experiment, its limit (none when the limit's `runs` is 0).
    pub(super) limits: Vec<Option<ExperimentLimit>>,
}

/// Estimates, on the current rayon pool, the landscape of each experiment's operators
/// behind its final behaviors and each experiment's known-operator limit (once per scenario
/// and operator), over `parts`.
pub(super) fn estimate_parts<C: Catalog>(
    parts: &Parts<C>,
    config: &SuiteConfig,
    origin: &Path,
) -> Result<ReportEstimates, SuiteError> {
    let mut landscapes = Vec::with_capacity(config.experiments.len());
    let mut limits = Vec::with_capacity(config.experiments.len());
    let mut operator_limits = OperatorLimits::default();
    for (k, spec) in config.experiments.iter().enumerate() {
        let fail = |reason: String| invalid(origin, format!("experiments[{k}]"), reason);
        let domain = parts.domain(k);
        // In contexts, each operator judges as it does in each context of the cycle: the
        // pairs a trial draws, equally often.
        let cycle = match &spec.contexts {
            None => vec![Context::default()],
            Some(c) => c
                .trial_contexts(domain.contexts())
                .map_err(|(field, reason)| fail(format!("{field}: {reason}")))?
                .cycle()
                .to_vec(),
        };
        let in_contexts: Vec<InContext<'_, C>> = spec
            .judges(&parts.operators[k])
            .flat_map(|(name, op)| {
                cycle.iter().map(
                    move |context| match domain.operator_in_context(op, context) {
                        Some(there) => (format!("{name}@{context}"), Some(there), op),
                        None => (name.clone(), None, op),
                    },
                )
            })
            .collect();
        let judges: Vec<(&String, &OperatorOf<C>)> = in_contexts
            .iter()
            .map(|(name, there, op)| (name, there.as_ref().unwrap_or(op)))
            .collect();
        if config.landscape_runs > 0 {
            let operators: Vec<&OperatorOf<C>> = judges.iter().map(|(_, op)| *op).collect();
            landscapes.push(
                finals_landscapes(
                    parts.domain(k),
                    &operators,
                    k as u64,
                    config.seed,
                    config.landscape_runs,
                    &|| {},
                )
                .map_err(|e| fail(e.to_string()))?,
            );
        }
        if config.limit.runs > 0 {
            let of_each = judges
                .iter()
                .map(|(name, op)| operator_limits.of(parts, config, k, name, op))
                .collect::<Result<Vec<usize>, _>>()
                .map_err(|e| fail(e.to_string()))?;
            let known: Vec<(&str, &KnownOperator)> = judges
                .iter()
                .zip(&of_each)
                .map(|((name, _), &i)| (name.as_str(), &operator_limits.known[i].1))
                .collect();
            // The population reference of experiment `k` draws from the seed
            // `stream_seed(seed, k, 0, PopulationReference)`.
            let reference = ReferencePlan {
                thresholds: config.adapter.thresholds,
                episodes: config.limit.reference_episodes,
                seed: stream_seed(config.seed, k as u64, 0, Purpose::PopulationReference),
            };
            limits.push(Some(
                ExperimentLimit::of(&known, Some(reference)).map_err(|e| fail(e.to_string()))?,
            ));
        }
    }
    Ok(ReportEstimates { landscapes, limits })
}
