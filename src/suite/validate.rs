//! What a suite may ask for, checked before any work: the sizes that bound its time and
//! memory ([`crate::limits`]), the adapter's parameters, the arms and the reference arm,
//! the readings, and each experiment's scenario, population and operators against the
//! catalog.
//!
//! The checks every suite kind shares (experiment suites, mission suites and, through
//! their cells' suites, sweeps) are functions here, one implementation each:
//! [`check_adapter`] (thresholds, lambda), [`check_arms`] (names, duplicates),
//! [`check_distinct`] (experiment and plan names) and [`ExperimentSpec::check`] (scenario,
//! population, operators, whether the thresholds can be reached).

use super::{ExperimentSpec, RANDOM_OPERATOR, SuiteConfig, SuiteError, arm_named, invalid};
use crate::catalog::{Catalog, OperatorOf, Readings, domain_of, resolve_readings};
use crate::limits::{
    self, BoundError, EXPERIMENTS, FAMILY_SIZE, LANDSCAPE_RUNS, LIMIT_RUNS, MAX_COMMANDS,
    OPERATOR_FILES, OPERATORS_IN_CONTEXTS, REFERENCE_EPISODES, SUITE_TRIALS, TRIALS, shown,
};
use files::name::check_file_name;
use lab::{
    Arm, ArmName, CONTEXT_BLIND, Domain, IGNORES_STATEMENTS, Instance, Split, TrialContexts,
};
use std::path::Path;
use trust::{AdapterConfig, RetrieverKind, Verdict};

/// A [`BoundError`] of the file `origin`, as a [`SuiteError`].
pub(crate) fn over(origin: &Path, error: BoundError) -> SuiteError {
    invalid(origin, error.field().to_owned(), error.problem())
}

impl SuiteConfig {
    /// Checks every field against `catalog`; `origin` names the file in errors and anchors
    /// operator files.
    pub fn validate<C: Catalog>(&self, catalog: &C, origin: &Path) -> Result<(), SuiteError> {
        let over = |error| over(origin, error);
        let invalid = |field: String, message: String| invalid(origin, field, message);
        let experiments = self.experiments.len() as u64;
        EXPERIMENTS
            .check("experiments", experiments)
            .map_err(over)?;
        MAX_COMMANDS
            .check("max_commands", self.max_commands)
            .map_err(over)?;
        TRIALS
            .check("trials", u64::from(self.trials.get()))
            .map_err(over)?;
        let trials = experiments * self.arms.len() as u64 * u64::from(self.trials.get());
        SUITE_TRIALS
            .check_total(
                "trials",
                trials,
                format!(
                    " in all ({} experiments x {} arms x {} trials)",
                    self.experiments.len(),
                    self.arms.len(),
                    self.trials
                ),
            )
            .map_err(over)?;
        LANDSCAPE_RUNS
            .check("landscape_runs", u64::from(self.landscape_runs))
            .map_err(over)?;
        let second = self.limit.candidates as u64 * u64::from(self.limit.candidate_runs);
        LANDSCAPE_RUNS
            .check_total("limit.runs", u64::from(self.limit.runs), String::new())
            .map_err(over)?;
        LIMIT_RUNS
            .check_total("limit.budget", self.limit.budget, String::new())
            .map_err(over)?;
        LIMIT_RUNS
            .check_total(
                "limit.candidates x limit.candidate_runs",
                second,
                String::new(),
            )
            .map_err(over)?;
        REFERENCE_EPISODES
            .check(
                "limit.reference_episodes",
                self.limit.reference_episodes as u64,
            )
            .map_err(over)?;
        if self.limit.reference_episodes == 1 {
            return Err(invalid(
                "limit.reference_episodes".into(),
                "got 1; must be 0 (no population reference) or at least 2 (one episode has no standard error)"
                    .into(),
            ));
        }
        check_adapter(&self.adapter, origin)?;
        check_arms(catalog, &self.arms, self.adapter.retriever, origin)?;
        if let Some(i) = self.arms.iter().position(|a| a.options().prefers_competent) {
            return Err(invalid(
                format!("arms[{i}]"),
                format!(
                    "`{}` prefers behaviors the robot judges competent, which only a mission plan with a competence standard judges (docs/missions.md); an experiment's episodes settle on the first trusted behavior",
                    self.arms[i]
                ),
            ));
        }
        if let Some(reference) = &self.reference
            && !self.arms.iter().any(|arm| arm == reference.as_str())
        {
            return Err(invalid(
                "reference".into(),
                format!(
                    "`{reference}` is not one of the suite's arms ({})",
                    ArmName::join(&self.arms, ", ")
                ),
            ));
        }
        let readings = resolve_readings(catalog, &self.readings)
            .map_err(|e| invalid("readings".into(), e.to_string()))?;
        let mut told_a_context = false;
        for (i, spec) in self.experiments.iter().enumerate() {
            let field = format!("experiments[{i}]");
            let (operators, contexts) = spec.check(catalog, &field, origin, &readings)?;
            told_a_context |= contexts.is_some_and(|t| t.cycle().iter().any(|c| !c.is_default()));
            if spec.operator != RANDOM_OPERATOR
                && !operators.iter().any(|(name, _)| *name == spec.operator)
            {
                let known: Vec<&str> = operators.iter().map(|(n, _)| n.as_str()).collect();
                // Left out beside one file and not chosen: a config built by hand rather
                // than read (reading chooses it, `ExperimentSpec::operator`).
                let problem = if spec.operator.is_empty() {
                    format!(
                        "is left out: write `operator: \"NAME\"` with NAME one of the experiment's operators ({}), or `operator: \"{RANDOM_OPERATOR}\"`",
                        known.join(", ")
                    )
                } else {
                    format!(
                        "unknown operator `{}` for {} (known: {}, or `{RANDOM_OPERATOR}`)",
                        spec.operator,
                        spec.scenario,
                        known.join(", ")
                    )
                };
                return Err(invalid(format!("{field}.operator"), problem));
            }
            spec.check_reachable(
                catalog,
                &operators,
                &field,
                origin,
                &self.adapter,
                (
                    self.max_commands,
                    "max_commands",
                    "every trial would be cut off",
                ),
            )?;
        }
        let names: Vec<String> = self.experiments.iter().map(ExperimentSpec::name).collect();
        check_distinct("experiments", "experiment", &names, origin)?;
        self.check_twins(catalog, origin, told_a_context)
    }

    /// Refuses an arm that is blind to the context, or deaf to statements, where that
    /// changes nothing, so it would run as its twin under another name: a deaf arm where no
    /// experiment has operators state anything; a blind arm where no trial runs in a
    /// context other than the default (`told_a_context`, as the experiments' checks
    /// resolved their contexts); a built-in blind arm that reuses
    /// no case and whose search ignores the context; a built-in deaf arm whose search
    /// hears no statement ([`cbr_core::Searcher::reads_context`],
    /// [`cbr_core::Searcher::hears_statements`]). A user's arm is taken at its word: its
    /// searcher says it may read both unless it says otherwise, and it is not built here.
    fn check_twins<C: Catalog>(
        &self,
        catalog: &C,
        origin: &Path,
        told_a_context: bool,
    ) -> Result<(), SuiteError> {
        let invalid = |i: usize, message: String| invalid(origin, format!("arms[{i}]"), message);
        if !self.experiments.iter().any(|e| e.stated.is_some())
            && let Some(i) = self
                .arms
                .iter()
                .position(|a| a.options().ignores_statements)
        {
            return Err(invalid(
                i,
                format!(
                    "`{}` ignores what operators state up front, and no experiment here has `stated`: nothing is stated, so the arm is its twin that hears; give an experiment `stated` or drop the arm's +ignores-statements",
                    self.arms[i]
                ),
            ));
        }
        let Some(first) = self.experiments.first() else {
            return Ok(());
        };
        let domain = domain_of(catalog, &first.scenario)
            .map_err(|unknown| invalid(0, unknown.to_string()))?;
        let space = domain.space();
        for (i, name) in self.arms.iter().enumerate() {
            let options = name.options();
            if options.context_blind && !told_a_context {
                return Err(invalid(
                    i,
                    format!(
                        "`{name}` is blind to the robot's context, and no trial here runs in a context other than the default: the arm is its sighted twin; give an experiment `contexts` with another context, or drop the arm's {CONTEXT_BLIND}"
                    ),
                ));
            }
            let Ok(arm) = Arm::builtin_named(name, self.adapter.retriever) else {
                continue;
            };
            let searcher = arm.build_searcher(space);
            if options.context_blind && !arm.reads_cases() && !searcher.reads_context() {
                return Err(invalid(
                    i,
                    format!(
                        "`{name}` is blind to the robot's context, but it reuses no case and its search (`{}`) ignores the context: the arm is its sighted twin; drop the arm's {CONTEXT_BLIND}",
                        searcher.name()
                    ),
                ));
            }
            if options.ignores_statements && !searcher.hears_statements() {
                return Err(invalid(
                    i,
                    format!(
                        "`{name}` ignores what operators state up front, but its search (`{}`) hears no statement: the arm is its twin that hears; drop the arm's {IGNORES_STATEMENTS}",
                        searcher.name()
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Checks the adapter parameters every suite kind shares: the adapter's own rules
/// ([`AdapterConfig::validate`]: thresholds that bracket 0, lambda in `(0, 1]`),
/// thresholds at most [`trust::MAX_THRESHOLD`] from 0, and nothing set that is each
/// arm's choice (case reuse, search).
pub(crate) fn check_adapter(adapter: &AdapterConfig, origin: &Path) -> Result<(), SuiteError> {
    adapter.validate()?;
    limits::check_thresholds("adapter.thresholds", &adapter.thresholds)
        .map_err(|e| over(origin, e))?;
    super::config::check_arms_choose(adapter, origin)
}

/// Checks a suite's arms, whatever its kind: at least one, each known to `catalog` (or
/// built in), a file name, and listed once.
pub(crate) fn check_arms<C: Catalog>(
    catalog: &C,
    arms: &[ArmName],
    retriever: RetrieverKind,
    origin: &Path,
) -> Result<(), SuiteError> {
    if arms.is_empty() {
        return Err(invalid(
            origin,
            "arms".into(),
            "at least one arm is needed".into(),
        ));
    }
    for (i, name) in arms.iter().enumerate() {
        if let Err(e) = arm_named(catalog, name, retriever) {
            return Err(invalid(origin, format!("arms[{i}]"), e));
        }
        if arms[..i].contains(name) {
            return Err(invalid(
                origin,
                format!("arms[{i}]"),
                format!("`{name}` is listed twice"),
            ));
        }
    }
    Ok(())
}

/// Refuses two of `names` (of the `field`'s entries, each a `what`) that are equal: a
/// report, `explain` and saved case bases find each by its name.
pub(crate) fn check_distinct(
    field: &str,
    what: &str,
    names: &[String],
    origin: &Path,
) -> Result<(), SuiteError> {
    for (i, name) in names.iter().enumerate() {
        if let Some(first) = names[..i].iter().position(|n| n == name) {
            return Err(invalid(
                origin,
                format!("{field}[{i}]"),
                format!(
                    "the {what} `{name}` is already {field}[{first}]; each {what} needs its own name (the report and `explain` find it by name)"
                ),
            ));
        }
    }
    Ok(())
}

/// What [`ExperimentSpec::check`] finds: the experiment's operators by name, and the
/// contexts its trials run in when it has `contexts`.
pub(crate) type Checked<C> = (Vec<(String, OperatorOf<C>)>, Option<TrialContexts>);

impl ExperimentSpec {
    /// Checks who operates an experiment or a mission plan (at `field`), whatever the
    /// suite's kind: its scenario, its population (a family's conflict and size, its
    /// members listed or drawn, not both; built-in members named only in a population,
    /// each known and named once), an `operator` left out with nothing to choose it by
    /// ([`ExperimentSpec::operator`]), and its operators, loaded as `readings` read them
    /// (file names as names, none named twice or `random`). Returns the operators, and the
    /// contexts its trials run in when it has `contexts`.
    pub(crate) fn check<C: Catalog>(
        &self,
        catalog: &C,
        field: &str,
        origin: &Path,
        readings: &Readings,
    ) -> Result<Checked<C>, SuiteError> {
        let invalid = |field: String, message: String| invalid(origin, field, message);
        let domain = domain_of(catalog, &self.scenario)
            .map_err(|unknown| invalid(format!("{field}.scenario"), unknown.to_string()))?;
        let trial_contexts = self
            .trial_contexts(domain.contexts())
            .map_err(|(name, reason)| invalid(format!("{field}.{name}"), reason))?;
        let contexts = trial_contexts.as_ref().map_or(1, |t| t.cycle().len());
        OPERATOR_FILES
            .check(
                &format!("{field}.operator_files"),
                self.operator_files.len() as u64,
            )
            .map_err(|e| over(origin, e))?;
        if self.goal_changes.is_none() && self.feedback.is_some_and(|c| c.goal_changes > 0.0) {
            return Err(invalid(
                format!("{field}.feedback.goal_changes"),
                "the operators would say goal changes, but none happen: add `goal_changes: Some((per_hour: ...))` beside `feedback`, or leave `goal_changes` out of the channel".into(),
            ));
        }
        if let Some(population) = &self.population {
            let problem = if self.operator != RANDOM_OPERATOR {
                Some(format!(
                    "a population's members are drawn per trial: `operator` must be `{RANDOM_OPERATOR}`"
                ))
            } else if population.family.is_some() && !self.operator_files.is_empty() {
                Some(
                    "a population is drawn from the family or listed in `operator_files`, not both"
                        .to_owned(),
                )
            } else if population.family.is_some() && !self.builtin_operators.is_empty() {
                Some(
                    "a population is drawn from the family or listed in `builtin_operators`, not both"
                        .to_owned(),
                )
            } else if population.family.is_none()
                && self.operator_files.is_empty()
                && self.builtin_operators.is_empty()
            {
                Some(
                    "a population needs its members: `builtin_operators`, `operator_files` or a `family`"
                        .to_owned(),
                )
            } else if let Some(family) = &population.family
                && !(0.0..=1.0).contains(&family.conflict)
            {
                Some(format!(
                    "`family.conflict` must be in [0, 1], got {}",
                    shown(family.conflict)
                ))
            } else if let Some(family) = &population.family
                && let Err(e) = FAMILY_SIZE.check("family.size", family.size as u64)
            {
                Some(format!("`{}` {}", e.field(), e.problem()))
            } else {
                check_file_name("population", &population.name)
                    .err()
                    .map(|e| e.to_string())
            };
            if let Some(problem) = problem {
                return Err(invalid(format!("{field}.population"), problem));
            }
            if population.family.is_none()
                && let Err((k, problem)) =
                    self.builtin_members(catalog.operators(&self.scenario, readings))
            {
                return Err(invalid(format!("{field}.builtin_operators[{k}]"), problem));
            }
        } else if !self.builtin_operators.is_empty() {
            return Err(invalid(
                format!("{field}.builtin_operators"),
                format!(
                    "built-in operators are named as a population's members: add `population: Some((name: ...))`, or leave them out (without a population every built-in operator of {} takes part)",
                    self.scenario
                ),
            ));
        } else if self.operator.is_empty() && self.operator_files.is_empty() {
            let builtins: Vec<String> = catalog
                .operators(&self.scenario, readings)
                .into_iter()
                .map(|(name, _)| name)
                .collect();
            return Err(invalid(
                format!("{field}.operator"),
                self.operator_left_out(&builtins),
            ));
        }
        let operators = self.operators(catalog, origin, readings)?;
        if operators.is_empty() {
            return Err(invalid(
                field.to_owned(),
                "the experiment has no operator".into(),
            ));
        }
        let judges = self.judges(&operators).count();
        if self.contexts.is_some() {
            OPERATORS_IN_CONTEXTS
                .check_total(
                    &format!("{field}.contexts.cycle"),
                    (judges * contexts) as u64,
                    format!(" ({judges} operators x {contexts} contexts)"),
                )
                .map_err(|e| over(origin, e))?;
        }
        // Files come after the built-in operators (or the family's members).
        let first_file = operators.len() - self.operator_files.len();
        let place = |k: usize| {
            if k >= first_file {
                format!("{field}.operator_files[{}]", k - first_file)
            } else if self.population.as_ref().is_some_and(|p| p.family.is_none()) {
                format!("{field}.builtin_operators[{k}]")
            } else {
                format!("{field}.scenario")
            }
        };
        for (k, (name, _)) in operators.iter().enumerate() {
            if let Err(e) = check_file_name("operator", name) {
                return Err(invalid(place(k), e.to_string()));
            }
            let holder = operators[..k].iter().position(|(n, _)| n == name);
            let problem = match holder {
                _ if name == RANDOM_OPERATOR => {
                    format!("operator name `{name}` is reserved: it draws an operator per trial")
                }
                Some(j) if j < first_file => {
                    format!("operator name `{name}` is taken by a built-in operator")
                }
                Some(j) => format!(
                    "operator name `{name}` is taken by `operator_files[{}]`",
                    j - first_file
                ),
                None => continue,
            };
            return Err(invalid(place(k), problem));
        }
        if let Some(population) = &self.population
            && let Err((k, problem)) = instance_members(&population.name, &operators)
        {
            let place = if population.family.is_some() {
                format!("{field}.population")
            } else {
                place(k)
            };
            return Err(invalid(place, problem));
        }
        Ok((operators, trial_contexts))
    }

    /// Refuses an experiment or mission plan (at `field`) of which an operator that may
    /// judge cannot reach the trustworthy threshold within `commands` (its count, the
    /// field naming it, and what would follow): a trial or an episode ends when a
    /// behavior reaches it, so every one would be cut off.
    pub(crate) fn check_reachable<C: Catalog>(
        &self,
        catalog: &C,
        operators: &[(String, OperatorOf<C>)],
        field: &str,
        origin: &Path,
        adapter: &AdapterConfig,
        (commands, commands_field, otherwise): (u64, &str, &str),
    ) -> Result<(), SuiteError> {
        let thresholds = adapter.thresholds;
        let trustworthy = thresholds.trustworthy;
        if let Some((name, completed)) = self.judges(operators).find_map(|(name, op)| {
            catalog
                .completion_weight(op)
                .filter(|w| thresholds.verdict(w * (commands as f64)) != Verdict::Trustworthy)
                .map(|w| (name, w))
        }) {
            return Err(invalid(
                origin,
                field.to_owned(),
                format!(
                    "operator `{name}` weighs a completion {}, so {commands} commands ({commands_field}) can never reach the trustworthy threshold {}: {otherwise}",
                    shown(completed),
                    shown(trustworthy)
                ),
            ));
        }
        Ok(())
    }
}

/// Whether a population named like a benchmark instance (`dev-K`, `eval-K`: a split's
/// prefix and a hyphen) holds that instance's members: the name must be an instance
/// ([`lab::Instance`], within its split's range) and each member named `NAME-J`, as
/// `trustcbr population` writes an instance's members, so a report never labels one
/// instance's operators as another's. The first member that is not, and why.
fn instance_members<O>(name: &str, members: &[(String, O)]) -> Result<(), (usize, String)> {
    let looks_like_instance = Split::ALL
        .iter()
        .any(|split| name.starts_with(&format!("{}-", split.prefix())));
    if !looks_like_instance {
        return Ok(());
    }
    if let Err(e) = name.parse::<Instance>() {
        return Err((
            0,
            format!(
                "population `{name}` is named as a benchmark instance but is none: {e}; give the population another name"
            ),
        ));
    }
    let prefix = format!("{name}-");
    let stray = members.iter().position(|(member, _)| {
        member
            .strip_prefix(&prefix)
            .is_none_or(|j| j.is_empty() || !j.bytes().all(|b| b.is_ascii_digit()))
    });
    match stray {
        None => Ok(()),
        Some(k) => Err((
            k,
            format!(
                "member `{}` is not one of instance `{name}`'s members (named `{name}-J`, as `trustcbr population` writes them), so the report would label it `{name}`: list that instance's operator files, or give the population another name",
                members[k].0
            ),
        )),
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

    /// A folder holding `night.ron` and `owl.ron`, two movement operators, and a suite
    /// `suite.ron` of `experiments` beside them.
    fn beside_two_operators(experiments: &str) -> (tempfile::TempDir, std::path::PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        for name in ["night", "owl"] {
            std::fs::write(
                dir.path().join(format!("{name}.ron")),
                format!("(name: \"{name}\", t_complete: 20.0, p_deadline: 0.5, p_collision: 0.5)"),
            )
            .unwrap();
        }
        let config = dir.path().join("suite.ron");
        std::fs::write(
            &config,
            format!("(seed: 1, trials: 5,\n experiments: [{experiments}])"),
        )
        .unwrap();
        (dir, config)
    }

    #[test]
    fn an_experiment_may_leave_its_operator_out_beside_operator_files_or_a_population() {
        // One file: its operator judges every trial, as if named.
        let (_dir, config) =
            beside_two_operators("(scenario: \"movement\", operator_files: [\"night.ron\"])");
        let suite = SuiteConfig::load(&UgvCatalog, &config).unwrap();
        let (_named_dir, named) = beside_two_operators(
            "(scenario: \"movement\", operator: \"night\", operator_files: [\"night.ron\"])",
        );
        assert_eq!(suite, SuiteConfig::load(&UgvCatalog, &named).unwrap());
        assert_eq!(suite.experiments[0].name(), "movement/night");
        // The config a report echoes names it, and reads back as the same config.
        let echoed = suite.to_ron();
        assert!(echoed.contains("operator: \"night\""), "{echoed}");
        assert_eq!(
            SuiteConfig::from_ron(&UgvCatalog, &echoed, &config).unwrap(),
            suite
        );
        // Several files, or a population: a draw per trial, as `random` written.
        for (experiment, name) in [
            (
                "(scenario: \"movement\", operator_files: [\"night.ron\", \"owl.ron\"])",
                "movement/random",
            ),
            (
                "(scenario: \"movement\", population: Some((name: \"pair\")), operator_files: [\"night.ron\", \"owl.ron\"])",
                "movement/pair",
            ),
            (
                "(scenario: \"movement\", population: Some((name: \"one\")), operator_files: [\"night.ron\"])",
                "movement/one",
            ),
            (
                "(scenario: \"movement\", population: Some((name: \"fam\", family: Some((conflict: 0.5, size: 2, seed: 1)))))",
                "movement/fam",
            ),
        ] {
            let (_dir, config) = beside_two_operators(experiment);
            let suite = SuiteConfig::load(&UgvCatalog, &config).unwrap();
            let spec = &suite.experiments[0];
            assert_eq!(
                (spec.operator.as_str(), spec.name().as_str()),
                (RANDOM_OPERATOR, name)
            );
            let written = std::fs::read_to_string(&config).unwrap().replace(
                "(scenario: \"movement\",",
                "(scenario: \"movement\", operator: \"random\",",
            );
            assert_eq!(
                SuiteConfig::from_ron(&UgvCatalog, &written, &config).unwrap(),
                suite
            );
        }
        // The same from JSON (a Python dict).
        let (_dir, config) = beside_two_operators("");
        let json = r#"{"seed": 1, "trials": 5, "experiments": [{"scenario": "movement", "operator_files": ["night.ron"]}]}"#;
        let suite = SuiteConfig::from_json(&UgvCatalog, json, &config).unwrap();
        assert_eq!(suite.experiments[0].operator, "night");
    }

    #[test]
    fn an_experiment_with_no_operator_and_nothing_to_choose_it_by_says_what_to_write() {
        let refused = |experiment: &str| {
            let (_dir, config) = beside_two_operators(experiment);
            SuiteConfig::load(&UgvCatalog, &config)
                .unwrap_err()
                .to_string()
                .replace(&config.display().to_string(), "suite.ron")
        };
        assert_eq!(
            refused("(scenario: \"movement\", operator: \"balanced\"), (scenario: \"patrol\")"),
            "suite.ron: experiments[1].operator: is left out, and the experiment has no `operator_files` or `population` to choose it by: write `operator: \"NAME\"` with NAME one of patrol's built-in operators (speed-focused, detection-focused), `operator: \"random\"` to draw one of them per trial, or `operator_files: [\"FILE.ron\"]` to run an operator of your own on every trial"
        );
        // An empty name is not a name left out.
        assert_eq!(
            refused("(scenario: \"movement\", operator: \"\", operator_files: [\"night.ron\"])"),
            "suite.ron:2:51: `operator` is empty: name an operator of the experiment (a built-in operator of its scenario, or an operator file's `name`), write `operator: \"random\"`, or leave `operator` out beside `operator_files` or a `population`\n2 |  experiments: [(scenario: \"movement\", operator: \"\", operator_files: [\"night.ron\"])])\n  |                                                   ^"
        );
        // A file that cannot be read is reported as before.
        let err = refused("(scenario: \"movement\", operator_files: [\"absent.ron\"])");
        assert!(err.contains("absent.ron"), "{err}");
        // A config built by hand that leaves it out beside one file.
        let (_dir, config) =
            beside_two_operators("(scenario: \"movement\", operator_files: [\"night.ron\"])");
        let mut suite = SuiteConfig::load(&UgvCatalog, &config).unwrap();
        suite.experiments[0].operator.clear();
        let err = suite
            .validate(&UgvCatalog, &config)
            .unwrap_err()
            .to_string();
        let err = err.replace(&config.display().to_string(), "x.ron");
        assert!(err.starts_with("x.ron: experiments[0].operator: is left out: write `operator: \"NAME\"` with NAME one of the experiment's operators (speed-focused, safety-focused, balanced, night), or `operator: \"random\"`"), "{err}");
    }

    #[test]
    fn a_mission_plan_draws_its_operators_and_may_write_no_other() {
        use crate::mission_suite::MissionSuiteConfig;
        let plan = |operators: &str| {
            let (dir, config) = beside_two_operators("");
            let text = format!(
                "(seed: 1, arms: [\"uniform\"], missions: [(name: \"m\", operators: {operators}, count: 1, commands: 100, changes: (every: 30.0, takeover: 0.5))])"
            );
            std::fs::write(&config, text).unwrap();
            let read = MissionSuiteConfig::load(&UgvCatalog, &config);
            drop(dir);
            read
        };
        let suite = plan("(scenario: \"movement\", population: Some((name: \"pair\")), operator_files: [\"night.ron\", \"owl.ron\"])").unwrap();
        // Left out, it is written as configs always wrote it.
        let written = ron::to_string(&suite.missions[0].operators).unwrap();
        assert!(written.contains("operator:\"random\""), "{written}");
        assert!(plan("(scenario: \"movement\", operator_files: [\"night.ron\"])").is_ok());
        let err =
            plan("(scenario: \"movement\", operator: \"night\", operator_files: [\"night.ron\"])")
                .unwrap_err()
                .to_string();
        assert!(
            err.contains(":1:") && err.contains("a mission draws its operators from the plan's operators (the scenario's, its files', or its population's): write `operator: \"random\"` or leave it out, not `night`"),
            "{err}"
        );
        // What only experiments simulate cannot be written, each refused with what to write.
        for (field, says) in [
            (
                "contexts: Some((cycle: [{}]))",
                "write the plan's `context_switches",
            ),
            (
                "goal_changes: Some((per_hour: 1.0))",
                "goal changes are simulated in experiment suites",
            ),
            (
                "stated: Some((said: 1.0))",
                "what operators state up front is simulated in experiment suites",
            ),
        ] {
            let err = plan(&format!("(scenario: \"movement\", {field})"))
                .unwrap_err()
                .to_string();
            assert!(err.contains(says), "{field}: {err}");
        }
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
