//! What a suite may ask for, checked before any work: the sizes that bound its time and
//! memory, the adapter's parameters, the arms and the reference arm, the readings, and each
//! experiment's scenario, population and operators against the catalog.

use super::{RANDOM_OPERATOR, SuiteConfig, SuiteError, arm_named, invalid};
use crate::catalog::{Catalog, domain_of, resolve_readings};
use std::path::Path;

/// The most members a population drawn from a family may have (each needs its own
/// landscape for the report's limit).
pub const MAX_FAMILY_SIZE: usize = 64;

/// The most trials per experiment and arm a config may ask for; all of a suite's trials
/// together are held to [`MAX_SUITE_TRIALS`].
pub const MAX_TRIALS: u32 = 100_000;

/// The most experiments a config may list.
pub const MAX_EXPERIMENTS: usize = 1_000;

/// The most trials a suite may run in all (experiments x arms x trials). Every trial's
/// record is kept until the report is written: about 24 KB each (measured: `reproduce
/// --arms random-walk,case-based` peaks at 207 MB with 7,000 trials and 869 MB with
/// 35,000), so this is about 6 GB, and some 3 minutes of the two cores of the machine of
/// `docs/results.md` for the paper's arms.
pub const MAX_SUITE_TRIALS: u64 = 250_000;

/// The most runs per behavior of a landscape (`landscape_runs`, `landscape --runs`): the
/// default, 200, costs about 2.5 s of the two cores for `reproduce`'s landscapes, so this
/// about 2 minutes.
pub const MAX_LANDSCAPE_RUNS: u32 = 10_000;

/// The most simulated runs the known-operator limit's estimate may ask for, first
/// (`limit.budget`) and second (`limit.candidates` x `limit.candidate_runs`) estimate each:
/// 50 times the defaults' 160,000 and 12,800, which with the landscapes take about 2.5 s of
/// the two cores for `reproduce`.
pub const MAX_LIMIT_RUNS: u64 = 8_000_000;

impl SuiteConfig {
    /// Checks every field against `catalog`; `origin` names the file in errors and anchors
    /// operator files.
    pub fn validate<C: Catalog>(&self, catalog: &C, origin: &Path) -> Result<(), SuiteError> {
        let invalid = |field: String, message: String| invalid(origin, field, message);
        if self.experiments.is_empty() {
            return Err(invalid(
                "experiments".into(),
                "at least one experiment is needed".into(),
            ));
        }
        if self.max_commands == 0 {
            return Err(invalid("max_commands".into(), "must be at least 1".into()));
        }
        if self.trials.get() > MAX_TRIALS {
            return Err(invalid(
                "trials".into(),
                format!(
                    "must be 1 to {MAX_TRIALS}, got {}: every trial's record is kept for the report",
                    self.trials
                ),
            ));
        }
        if self.experiments.len() > MAX_EXPERIMENTS {
            return Err(invalid(
                "experiments".into(),
                format!(
                    "at most {MAX_EXPERIMENTS} experiments, got {}",
                    self.experiments.len()
                ),
            ));
        }
        let trials =
            self.experiments.len() as u64 * self.arms.len() as u64 * u64::from(self.trials.get());
        if trials > MAX_SUITE_TRIALS {
            return Err(invalid(
                "trials".into(),
                format!(
                    "{trials} trials in all ({} experiments x {} arms x {} trials); at most {MAX_SUITE_TRIALS}: every trial's record is kept for the report",
                    self.experiments.len(),
                    self.arms.len(),
                    self.trials
                ),
            ));
        }
        if self.landscape_runs > MAX_LANDSCAPE_RUNS {
            return Err(invalid(
                "landscape_runs".into(),
                format!(
                    "must be 0 to {MAX_LANDSCAPE_RUNS}, got {}",
                    self.landscape_runs
                ),
            ));
        }
        let second = self.limit.candidates as u64 * u64::from(self.limit.candidate_runs);
        let limit_sizes = [
            (
                "limit.runs",
                u64::from(self.limit.runs),
                u64::from(MAX_LANDSCAPE_RUNS),
            ),
            ("limit.budget", self.limit.budget, MAX_LIMIT_RUNS),
            (
                "limit.candidates x limit.candidate_runs",
                second,
                MAX_LIMIT_RUNS,
            ),
        ];
        for (field, size, most) in limit_sizes {
            if size > most {
                return Err(invalid(
                    field.into(),
                    format!("{size} runs; at most {most}"),
                ));
            }
        }
        self.adapter.validate()?;
        super::config::check_arms_choose(&self.adapter, origin)?;
        if let Some(reference) = &self.reference
            && !self.arms.contains(reference)
        {
            return Err(invalid(
                "reference".into(),
                format!(
                    "`{reference}` is not one of the suite's arms ({})",
                    self.arms.join(", ")
                ),
            ));
        }
        if self.arms.is_empty() {
            return Err(invalid("arms".into(), "at least one arm is needed".into()));
        }
        for (i, name) in self.arms.iter().enumerate() {
            if let Err(e) = arm_named(catalog, name, self.adapter.retriever) {
                return Err(invalid(format!("arms[{i}]"), e));
            }
            if self.arms[..i].contains(name) {
                return Err(invalid(
                    format!("arms[{i}]"),
                    format!("`{name}` is listed twice"),
                ));
            }
        }
        let readings = resolve_readings(catalog, &self.readings)
            .map_err(|e| invalid("readings".into(), e.to_string()))?;
        for (i, spec) in self.experiments.iter().enumerate() {
            if let Err(unknown) = domain_of(catalog, &spec.scenario) {
                return Err(invalid(
                    format!("experiments[{i}].scenario"),
                    unknown.to_string(),
                ));
            }
            if let Some(population) = &spec.population {
                let problem = if spec.operator != RANDOM_OPERATOR {
                    Some(format!(
                        "a population's members are drawn per trial: `operator` must be `{RANDOM_OPERATOR}`"
                    ))
                } else if population.family.is_some() && !spec.operator_files.is_empty() {
                    Some("a population is drawn from the family or listed in `operator_files`, not both".to_owned())
                } else if population.family.is_none() && spec.operator_files.is_empty() {
                    Some(
                        "a population needs its members: `operator_files` or a `family`".to_owned(),
                    )
                } else if let Some(family) = &population.family
                    && !(0.0..=1.0).contains(&family.conflict)
                {
                    Some(format!(
                        "`family.conflict` must be in [0, 1], got {}",
                        family.conflict
                    ))
                } else if let Some(family) = &population.family
                    && !(1..=MAX_FAMILY_SIZE).contains(&family.size)
                {
                    Some(format!(
                        "`family.size` must be 1 to {MAX_FAMILY_SIZE}, got {}",
                        family.size
                    ))
                } else {
                    None
                };
                if let Some(problem) = problem {
                    return Err(invalid(format!("experiments[{i}].population"), problem));
                }
            }
            let operators = spec.operators(catalog, origin, &readings)?;
            if spec.operator != RANDOM_OPERATOR
                && !operators.iter().any(|(name, _)| *name == spec.operator)
            {
                let known: Vec<&str> = operators.iter().map(|(n, _)| n.as_str()).collect();
                return Err(invalid(
                    format!("experiments[{i}].operator"),
                    format!(
                        "unknown operator `{}` for {} (known: {}, or `{RANDOM_OPERATOR}`)",
                        spec.operator,
                        spec.scenario,
                        known.join(", ")
                    ),
                ));
            }
            // A trial ends when a behavior reaches the trustworthy threshold; if no
            // operator of the experiment lets one reach it within `max_commands`, every
            // trial would be cut off and report a count that means nothing.
            let thresholds = self.adapter.thresholds;
            let trustworthy = thresholds.trustworthy;
            if let Some((name, completed)) = spec.judges(&operators).find_map(|(name, op)| {
                catalog
                    .completion_weight(op)
                    .filter(|w| {
                        thresholds.verdict(w * (self.max_commands as f64))
                            != trust::Verdict::Trustworthy
                    })
                    .map(|w| (name, w))
            }) {
                return Err(invalid(
                    format!("experiments[{i}]"),
                    format!(
                        "operator `{name}` weighs a completion {completed}, so {} commands (max_commands) can never reach the trustworthy threshold {trustworthy}: every trial would be cut off",
                        self.max_commands
                    ),
                ));
            }
            for (k, (name, _)) in operators.iter().enumerate() {
                if operators[..k].iter().any(|(n, _)| n == name) || name == RANDOM_OPERATOR {
                    return Err(invalid(
                        format!("experiments[{i}].operator_files"),
                        format!("operator name `{name}` is taken"),
                    ));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::UgvCatalog;

    #[test]
    fn config_errors_name_the_place() {
        let origin = Path::new("exp.ron");
        let err =
            SuiteConfig::from_ron(&UgvCatalog, "(seed: 1, trials: 0, experiments: [])", origin)
                .unwrap_err()
                .to_string();
        assert!(err.starts_with("exp.ron:1:"), "{err}");
        let err = SuiteConfig::from_ron(
            &UgvCatalog,
            "(seed: 1, trials: 5,\n experiments: [(scenario: \"movement\", operator: \"careful\")])",
            origin,
        )
        .unwrap_err()
        .to_string();
        assert!(
            err.contains("experiments[0].operator") && err.contains("careful"),
            "{err}"
        );
        let err = SuiteConfig::from_ron(
            &UgvCatalog,
            "(seed: 1, trials: 5,\n  experiments: [(scenario: underwater, operator: \"random\")])",
            origin,
        )
        .unwrap_err()
        .to_string();
        assert!(
            err.starts_with("exp.ron:2:") && err.contains("write `scenario: \"movement\"`"),
            "{err}"
        );
        let err = SuiteConfig::from_ron(
            &UgvCatalog,
            "(seed: 1, trials: 5, adapter: (lambda: 1.5), experiments: [(scenario: \"movement\", operator: \"random\")])",
            origin,
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("lambda"), "{err}");
        let err = SuiteConfig::from_ron(
            &UgvCatalog,
            "(seed: 1, trials: 5, arms: [\"uniform\", \"annealing\"], experiments: [(scenario: \"movement\", operator: \"random\")])",
            origin,
        )
        .unwrap_err()
        .to_string();
        assert!(
            err.contains("arms[1]")
                && err.contains("annealing")
                && err.contains("known: random-walk"),
            "{err}"
        );
        // The reference arm must be one of the arms; by default case-based when it runs.
        let suite = |arms: &str, reference: &str| {
            SuiteConfig::from_ron(
                &UgvCatalog,
                &format!(
                    "(seed: 1, trials: 5, arms: {arms}, {reference} experiments: [(scenario: \"movement\", operator: \"random\")])"
                ),
                origin,
            )
        };
        let err = suite(
            "[\"uniform\", \"case-based\"]",
            "reference: \"random-walk\",",
        )
        .unwrap_err()
        .to_string();
        assert!(
            err.contains("reference")
                && err
                    .contains("`random-walk` is not one of the suite's arms (uniform, case-based)"),
            "{err}"
        );
        let reference = |arms, given| suite(arms, given).unwrap().reference().to_owned();
        assert_eq!(reference("[\"uniform\", \"case-based\"]", ""), "case-based");
        assert_eq!(reference("[\"uniform\", \"model-based\"]", ""), "uniform");
        assert_eq!(
            reference(
                "[\"uniform\", \"model-based\"]",
                "reference: \"model-based\","
            ),
            "model-based"
        );
        let err = SuiteConfig::from_ron(
            &UgvCatalog,
            "(seed: 1, trials: 100001, experiments: [(scenario: \"movement\", operator: \"random\")])",
            origin,
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("trials: must be 1 to 100000"), "{err}");
        // Thresholds no run of commands can reach: every trial would be cut off.
        let err = SuiteConfig::from_ron(
            &UgvCatalog,
            "(seed: 1, trials: 5, max_commands: 100, adapter: (thresholds: (trustworthy: 500.0, untrustworthy: -5.0)), experiments: [(scenario: \"movement\", operator: \"random\")])",
            origin,
        )
        .unwrap_err()
        .to_string();
        assert!(
            err.contains("experiments[0]")
                && err.contains("can never reach the trustworthy threshold 500"),
            "{err}"
        );
        // Case reuse and the search strategy are the arms' business.
        let err = SuiteConfig::from_ron(
            &UgvCatalog,
            "(seed: 1, trials: 5, adapter: (reuse_cases: false), experiments: [(scenario: \"movement\", operator: \"random\")])",
            origin,
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("reuse_cases"), "{err}");
    }

    #[test]
    fn an_unknown_scenario_lists_the_catalog_s() {
        let err = SuiteConfig::from_ron(
            &UgvCatalog,
            "(seed: 1, trials: 5, experiments: [(scenario: \"underwater\", operator: \"random\")])",
            Path::new("exp.ron"),
        )
        .unwrap_err()
        .to_string();
        assert_eq!(
            err,
            "exp.ron: experiments[0].scenario: unknown scenario `underwater` (known: movement, patrol)"
        );
    }

    #[test]
    fn an_operator_whose_weights_are_all_zero_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("numb.ron"),
            "(name: \"numb\", t_complete: 15.0, p_deadline: 0.5, p_collision: 0.5, weights: (completed: 0.0, default: 0.0))",
        )
        .unwrap();
        let config = dir.path().join("suite.ron");
        std::fs::write(
            &config,
            "(seed: 1, trials: 5, experiments: [(scenario: \"movement\", operator: \"numb\", operator_files: [\"numb.ron\"])])",
        )
        .unwrap();
        let err = SuiteConfig::load(&UgvCatalog, &config)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("operator `numb` weighs a completion 0") && err.contains("cut off"),
            "{err}"
        );
    }
}
