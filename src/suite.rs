//! The experiment suite over a catalog's domains.
//!
//! A suite config (RON) names experiments by scenario and operator, the arms to compare,
//! the trials, seed, adapter parameters and the domain's readings; [`run_suite`] turns it
//! into [`ExperimentPlan`]s for the generic runner in `lab`, over the
//! domains a [`Catalog`] builds, and [`write_suite_report`] writes the report folder. The
//! catalog embeds the suite `reproduce` runs ([`Catalog::default_suite`]). Each
//! experiment's learned case bases can be saved ([`save_case_bases`]) and an arm can start
//! from them ([`StartingCases`]).

use crate::catalog::{
    Catalog, CatalogError, Family, OperatorOf, Readings, UnknownScenario, domain_of,
    resolve_readings,
};
use cbr_core::BehaviorSpace;
use files::{FileError, RonError, parse_ron, read_text, write_file_in};
use lab::known_operator::{
    ExperimentLimit, KnownLimitError, KnownOperator, LimitSettings, known_operator,
};
use lab::landscape::Landscape;
use lab::report::{
    FINALS_LANDSCAPE_RUNS, Provenance, ReportEntry, ReportError, file_stems, finals_landscapes,
    write_report,
};
use lab::seeds::{Purpose, stream_seed};
use lab::timeline::{Timeline, sample_trial};
use lab::{
    Arm, BUILTIN_ARMS, ExperimentPlan, ExperimentResult, Initial, LEARNED_START, OperatorChoice,
    PlanError, TracedCommand, TrialRecord, TrialSettings, run_experiments, trace_trial,
};
use lab::{Domain, FeedbackChannel};
use serde::{Deserialize, Serialize};
use service::StoreError;
use service::store::ron_file::CaseBaseError;
use service::store::{self, Identity, Location, ron_file};
use std::collections::BTreeMap;
use std::num::NonZeroU32;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;
use trust::{ConfigError, Retention, RetrieverKind, Thresholds, TimeUnit, TrustCaseBase};

/// The operator name that draws an operator per trial.
pub const RANDOM_OPERATOR: &str = "random";

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

/// How errors name the catalog's embedded suite.
pub const EMBEDDED_ORIGIN: &str = "<embedded suite>";

/// A set of experiments to run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SuiteConfig {
    /// Master seed of every random stream.
    pub seed: u64,
    /// Trials per experiment and arm.
    pub trials: NonZeroU32,
    /// Commands after which a trial is abandoned (a guard against endless trials).
    #[serde(default = "default_max_commands")]
    pub max_commands: u64,
    /// The adapter parameters every arm shares.
    #[serde(default)]
    pub adapter: SuiteAdapter,
    /// The domain's readings, by name ([`Catalog::readings`]; each left out keeps its
    /// default), e.g. `{"patrol_weights": "three_and_one"}`.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub readings: BTreeMap<String, String>,
    /// The arms to compare, by name: built-in ([`BUILTIN_ARMS`]) or the catalog's own
    /// ([`Catalog::arms`]), each optionally followed by [`LEARNED_START`] (it starts each
    /// episode from the case memory's guess); default: every built-in arm. A config may
    /// also write an arm as `(name: "case-based", initial: learned)` (`initial`: `random`,
    /// the default, or `learned`), which is read as the name `case-based+learned-start`.
    #[serde(default = "default_arms", deserialize_with = "arm_names")]
    pub arms: Vec<String>,
    /// The arm the report tests every other arm against (p-values), one of `arms`;
    /// default ([`SuiteConfig::reference`]): `case-based` when it runs, else the first arm.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        serialize_with = "plain_name",
        deserialize_with = "some_name"
    )]
    pub reference: Option<String>,
    /// The experiments, in report order.
    pub experiments: Vec<ExperimentSpec>,
    /// Runs per cell of the operator landscapes the report draws the final behaviors over
    /// (0: no landscape).
    #[serde(default = "default_landscape_runs")]
    pub landscape_runs: u32,
    /// How the report estimates each experiment's known-operator limit (`runs: 0`: none).
    #[serde(default)]
    pub limit: LimitSettings,
}

/// An optional name written as a plain string (`reference: "case-based"`, not
/// `Some("case-based")`).
fn plain_name<S: serde::Serializer>(name: &Option<String>, s: S) -> Result<S::Ok, S::Error> {
    name.as_deref().unwrap_or_default().serialize(s)
}

/// Reads what [`plain_name`] writes.
fn some_name<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<String>, D::Error> {
    String::deserialize(d).map(Some)
}

/// Reads the arms of a suite: each a name, or `(name: NAME, initial: random | learned)`
/// read as the name of the arm it stands for ([`Initial::of_name`]).
fn arm_names<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Vec<String>, D::Error> {
    struct ArmName(String);
    impl<'de> Deserialize<'de> for ArmName {
        fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            d.deserialize_any(ArmVisitor).map(ArmName)
        }
    }
    struct ArmVisitor;
    impl<'de> serde::de::Visitor<'de> for ArmVisitor {
        type Value = String;
        fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str("an arm's name as a string, or `(name: \"case-based\", initial: learned)`")
        }
        fn visit_str<E: serde::de::Error>(self, name: &str) -> Result<String, E> {
            Ok(name.to_owned())
        }
        fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<String, A::Error> {
            use serde::de::Error;
            /// The fields of an arm's options (read as identifiers, as RON writes them).
            #[derive(Deserialize)]
            #[serde(field_identifier, rename_all = "snake_case")]
            enum Field {
                Name,
                Initial,
            }
            let (mut name, mut initial) = (None::<String>, None::<Initial>);
            while let Some(key) = map.next_key::<Field>()? {
                match key {
                    Field::Name if name.is_none() => name = Some(map.next_value()?),
                    Field::Initial if initial.is_none() => {
                        // The parser's message lists the allowed values.
                        initial = Some(
                            map.next_value()
                                .map_err(|e| A::Error::custom(format!("field `initial`: {e}")))?,
                        );
                    }
                    Field::Name => return Err(A::Error::duplicate_field("name")),
                    Field::Initial => return Err(A::Error::duplicate_field("initial")),
                }
            }
            let name = name.ok_or_else(|| A::Error::missing_field("name"))?;
            if Initial::of_name(&name).1 == Initial::Learned {
                return Err(A::Error::custom(format!(
                    "field `name`: `{name}` already names how its episodes start; write the arm `{}` and set `initial`",
                    Initial::of_name(&name).0
                )));
            }
            Ok(match initial.unwrap_or_default() {
                Initial::Random => name,
                Initial::Learned => name + LEARNED_START,
            })
        }
    }
    Vec::<ArmName>::deserialize(d).map(|arms| arms.into_iter().map(|a| a.0).collect())
}

fn default_landscape_runs() -> u32 {
    FINALS_LANDSCAPE_RUNS
}

fn default_max_commands() -> u64 {
    1_000_000
}

fn default_arms() -> Vec<String> {
    BUILTIN_ARMS.iter().map(|&a| a.to_owned()).collect()
}

/// The adapter parameters of a suite. Whether cases are reused and which search runs are
/// the arms' business, so they are not here.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SuiteAdapter {
    /// The trust thresholds (paper: +5 / -5).
    pub thresholds: Thresholds,
    /// Algorithm 2's behavior-similarity threshold (paper: 0.95), in `(0, 1]`.
    #[serde(deserialize_with = "trust::evaluated::deserialize_lambda")]
    pub lambda: f64,
    /// The retriever of the arms that reuse cases (every kind gives the same answers).
    pub retriever: RetrieverKind,
    /// Which episodes are retained as cases (docs/model.md#cases-and-retention):
    /// `any_search` (default) or `final_from_search`.
    pub retention: Retention,
    /// The unit of an evaluated pair's time (docs/model.md#the-trust-estimate):
    /// `task_seconds` (default) or `commands`.
    pub time_unit: TimeUnit,
}

impl Default for SuiteAdapter {
    fn default() -> Self {
        let paper = trust::AdapterConfig::default();
        Self {
            thresholds: paper.thresholds,
            lambda: paper.lambda,
            retriever: paper.retriever,
            retention: paper.retention,
            time_unit: paper.time_unit,
        }
    }
}

impl SuiteAdapter {
    /// The parameters every arm shares.
    pub fn settings(&self) -> TrialSettings {
        TrialSettings {
            thresholds: self.thresholds,
            lambda: self.lambda,
            retention: self.retention,
            time_unit: self.time_unit,
        }
    }
}

/// One experiment: a scenario and who operates the robot.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExperimentSpec {
    /// The scenario, by the catalog's name for it (a RON string: `"movement"`).
    #[serde(deserialize_with = "deserialize_scenario")]
    pub scenario: String,
    /// An operator's name, or `random` to draw one per trial.
    pub operator: String,
    /// Extra operator files (RON), relative to the config file; they join the scenario's
    /// built-in operators.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub operator_files: Vec<PathBuf>,
    /// The experiment's operators are a population instead of the scenario's: its
    /// `operator_files` alone, listed by hand, or members drawn from the catalog's
    /// parametric family ([`Catalog::family`]); `operator` must then be `random` (a member
    /// judges each trial).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub population: Option<Population>,
    /// How every operator of the experiment explains itself (`(explains: 0.3, wrong:
    /// 0.1)`), overriding each operator's own channel; absent: the operators' own (the
    /// paper's silent operator unless an operator file says otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub feedback: Option<FeedbackChannel>,
}

/// A population of operators an experiment draws from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Population {
    /// Its name in reports: the experiment is called `SCENARIO/NAME`.
    pub name: String,
    /// Members drawn from the catalog's family (`operator_files` must then be empty);
    /// absent: the members are the experiment's `operator_files`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub family: Option<Family>,
}

/// A scenario name: a string. A bare identifier (`scenario: movement`, as configs spelled
/// it before scenarios were the catalog's) is refused with the spelling to use.
fn deserialize_scenario<'de, D: serde::Deserializer<'de>>(d: D) -> Result<String, D::Error> {
    struct Name;
    impl serde::de::Visitor<'_> for Name {
        type Value = String;
        fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str("a scenario name as a string, e.g. `scenario: \"movement\"`")
        }
        fn visit_str<E: serde::de::Error>(self, name: &str) -> Result<String, E> {
            Ok(name.to_owned())
        }
        fn visit_unit<E: serde::de::Error>(self) -> Result<String, E> {
            Err(E::custom(
                "a scenario name is a string: write `scenario: \"movement\"`, not `scenario: movement`",
            ))
        }
    }
    d.deserialize_any(Name)
}

/// Why a suite cannot be run.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SuiteError {
    /// The config file could not be read.
    #[error(transparent)]
    Io(#[from] FileError),
    /// The config is not valid RON for a suite.
    #[error(transparent)]
    Parse(#[from] RonError),
    /// A value is out of range.
    #[error("{path}: {field}: {message}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// The field, e.g. `experiments[2].operator`.
        field: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// An operator file is invalid.
    #[error(transparent)]
    Operator(#[from] CatalogError),
    /// The adapter parameters are invalid.
    #[error("adapter: {0}")]
    Adapter(ConfigError),
    /// The experiments cannot be run as planned.
    #[error(transparent)]
    Plan(#[from] PlanError),
    /// A case base could not be saved.
    #[error(transparent)]
    Cases(#[from] CaseBaseError),
    /// A saved case base cannot be read, or was learned in another behavior space.
    #[error(transparent)]
    SavedCases(Box<StoreError>),
    /// The report could not be written.
    #[error(transparent)]
    Report(#[from] ReportError),
}

// Boxed: a store's error is large, and every result of a suite carries this type.
impl From<StoreError> for SuiteError {
    fn from(error: StoreError) -> Self {
        Self::SavedCases(Box::new(error))
    }
}

// By hand rather than `#[from]`, which would also expose the reason as the error's
// source and have it printed twice in a chain.
impl From<ConfigError> for SuiteError {
    fn from(reason: ConfigError) -> Self {
        SuiteError::Adapter(reason)
    }
}

impl SuiteConfig {
    /// The arm the report tests the others against: the configured `reference`, else
    /// `case-based` when it runs, else the first arm.
    pub fn reference(&self) -> &str {
        self.reference
            .as_deref()
            .or_else(|| {
                self.arms
                    .iter()
                    .find(|a| *a == "case-based")
                    .map(String::as_str)
            })
            .or_else(|| self.arms.first().map(String::as_str))
            .unwrap_or_default()
    }

    /// The suite the catalog embeds ([`Catalog::default_suite`], what `reproduce` runs).
    pub fn embedded<C: Catalog>(catalog: &C) -> Result<Self, SuiteError> {
        Self::from_ron(catalog, catalog.default_suite(), Path::new(EMBEDDED_ORIGIN))
    }

    /// Reads and checks a suite config file against `catalog`.
    pub fn load<C: Catalog>(catalog: &C, path: &Path) -> Result<Self, SuiteError> {
        let text = read_text(path)?;
        Self::from_ron(catalog, &text, path)
    }

    /// Parses and checks a suite config; `origin` names the source in errors.
    pub fn from_ron<C: Catalog>(
        catalog: &C,
        text: &str,
        origin: &Path,
    ) -> Result<Self, SuiteError> {
        let config: Self = parse_ron(text, origin)?;
        config.validate(catalog, origin)?;
        Ok(config)
    }

    /// Parses and checks a suite config given as JSON (the same fields as the RON file: a
    /// Python dict); `origin` names the source in errors and anchors operator files.
    pub fn from_json<C: Catalog>(
        catalog: &C,
        text: &str,
        origin: &Path,
    ) -> Result<Self, SuiteError> {
        let config: Self = serde_json::from_str(text)
            .map_err(|e| invalid(origin, "config".into(), e.to_string()))?;
        config.validate(catalog, origin)?;
        Ok(config)
    }

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
        self.adapter
            .thresholds
            .validate()
            .map_err(ConfigError::from)?;
        trust::evaluated::validate_lambda(self.adapter.lambda).map_err(ConfigError::from)?;
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
            let trustworthy = self.adapter.thresholds.trustworthy;
            if let Some((name, completed)) = spec.judges(&operators).find_map(|(name, op)| {
                catalog
                    .completion_weight(op)
                    .filter(|w| w * (self.max_commands as f64) < trustworthy)
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

    /// The config as RON, as written to a report's `config.ron`.
    pub fn to_ron(&self) -> String {
        ron::ser::to_string_pretty(self, ron::ser::PrettyConfig::default())
            .expect("plain data serializes")
    }
}

impl ExperimentSpec {
    /// The report name, e.g. `movement/speed-focused` (`movement/speed-focused/f0.3w0.1`
    /// with a feedback channel of its own, `movement/rung-2` for a population).
    pub fn name(&self) -> String {
        match (&self.population, self.feedback) {
            (Some(population), _) => format!("{}/{}", self.scenario, population.name),
            (None, None) => format!("{}/{}", self.scenario, self.operator),
            // The same operator may be run with several channels: each is its own
            // experiment, named by its channel (`/f0.3w0.1`: explains 30%, 10% wrongly).
            (None, Some(channel)) if channel.wrong > 0.0 => format!(
                "{}/{}/f{}w{}",
                self.scenario, self.operator, channel.explains, channel.wrong
            ),
            (None, Some(channel)) => {
                format!("{}/{}/f{}", self.scenario, self.operator, channel.explains)
            }
        }
    }

    /// The operators among `operators` that judge this experiment's trials: the one it
    /// names, or all of them for `random`.
    pub fn judges<'a, O>(
        &'a self,
        operators: &'a [(String, O)],
    ) -> impl Iterator<Item = &'a (String, O)> + 'a {
        operators
            .iter()
            .filter(|(name, _)| self.operator == RANDOM_OPERATOR || *name == self.operator)
    }

    /// The experiment's operators, as `readings` read them: the catalog's built-in ones of
    /// the scenario, then those of `operator_files` (relative to the directory of
    /// `origin`); for a population, its members alone.
    pub fn operators<C: Catalog>(
        &self,
        catalog: &C,
        origin: &Path,
        readings: &Readings,
    ) -> Result<Vec<(String, OperatorOf<C>)>, SuiteError> {
        let base = origin.parent().unwrap_or(Path::new("."));
        let mut operators = match &self.population {
            None => catalog.operators(&self.scenario, readings),
            Some(Population {
                family: Some(family),
                ..
            }) => catalog.family(&self.scenario, family, readings)?,
            Some(_) => Vec::new(),
        };
        for file in &self.operator_files {
            operators.push(catalog.load_operator(&self.scenario, &base.join(file), readings)?);
        }
        Ok(operators)
    }
}

/// A suite's results, ready for reporting.
pub struct SuiteResults {
    /// One result per experiment, in config order.
    pub results: Vec<ExperimentResult>,
    /// The behavior space of each experiment, in config order.
    pub spaces: Vec<Arc<BehaviorSpace>>,
    /// A sample trial of each experiment traced command by command
    /// ([`lab::timeline::sample_trial`]), in config order.
    pub timelines: Vec<Option<Timeline>>,
}

/// Case bases saved by an earlier run ([`save_case_bases`]): `DIR/EXPERIMENT/ARM.ron`, the
/// experiment's name made a file name ([`file_stems`]). An arm that reads cases (it reuses
/// them, or starts from their guess: [`Arm::reads_cases`]) starts from its file when there
/// is one, and from an empty case base otherwise.
#[derive(Clone, Debug)]
pub struct StartingCases {
    /// The folder.
    pub dir: PathBuf,
}

impl StartingCases {
    /// The saved case base of `arm` in the experiment `stem` of `scenario`, if there is
    /// one: refused when it records another behavior space or a case does not fit `space`.
    /// A file that records no space (saved by an earlier version) is read as `space`'s.
    fn load(
        &self,
        stem: &str,
        arm: &str,
        scenario: &str,
        space: &BehaviorSpace,
    ) -> Result<Option<TrustCaseBase>, SuiteError> {
        let path = self.dir.join(stem).join(format!("{arm}.ron"));
        if !path.exists() {
            return Ok(None);
        }
        let identity = Identity {
            domain: scenario.to_owned(),
            space: space.clone(),
        };
        let mut store = store::open(&Location::Ron(path), &identity)?;
        let location = store.location();
        let mut cases = TrustCaseBase::new();
        store.read_after(None, &mut |stored| {
            store::check_case(&location, &stored, space)?;
            cases.push(stored.case);
            Ok(())
        })?;
        Ok(Some(cases))
    }
}

/// The arm `name`: the catalog's own arm of that name, or else a built-in one, either
/// followed by [`LEARNED_START`] ([`Arm::learned_start`]); the error lists every name
/// known.
pub fn arm_named<C: Catalog>(
    catalog: &C,
    name: &str,
    retriever: RetrieverKind,
) -> Result<Arm, String> {
    let own = catalog.arms(retriever);
    let (base, initial) = Initial::of_name(name);
    let arm = match own.iter().find(|a| a.name() == base) {
        Some(arm) => arm.clone(),
        None => Arm::builtin(base, retriever).map_err(|_| {
            let known: Vec<&str> = BUILTIN_ARMS
                .iter()
                .copied()
                .chain(own.iter().map(Arm::name))
                .collect();
            format!(
                "unknown arm `{name}` (known: {}; each also as NAME{LEARNED_START})",
                known.join(", ")
            )
        })?,
    };
    Ok(match initial {
        Initial::Random => arm,
        Initial::Learned => arm.learned_start(),
    })
}

/// A [`SuiteError::Invalid`] of `field` in the file `origin`.
pub(crate) fn invalid(origin: &Path, field: String, message: String) -> SuiteError {
    SuiteError::Invalid {
        path: origin.to_owned(),
        field,
        message,
    }
}

/// What a suite's experiments need from the catalog: one domain per scenario (built once,
/// so its caches serve every experiment of that scenario) and each experiment's operators,
/// as the suite's readings read them.
struct Parts<C: Catalog> {
    domains: Vec<C::Domain>,
    /// The index in `domains` of each experiment's domain.
    domain_index: Vec<usize>,
    /// Each experiment's operators.
    operators: Vec<Vec<(String, OperatorOf<C>)>>,
}

impl<C: Catalog> Parts<C> {
    fn of(catalog: &C, config: &SuiteConfig, origin: &Path) -> Result<Self, SuiteError> {
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
    fn domain(&self, k: usize) -> &C::Domain {
        &self.domains[self.domain_index[k]]
    }
}

/// Runs every experiment of `config` (operator files relative to `origin`) over the
/// domains of `catalog` on the current rayon pool, arms that reuse cases starting from
/// `starting` when given; `progress(experiment)` is called after every trial. No trial is
/// traced (see [`run_suite_with_report`]).
pub fn run_suite<C: Catalog>(
    catalog: &C,
    config: &SuiteConfig,
    origin: &Path,
    starting: Option<&StartingCases>,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<SuiteResults, SuiteError> {
    let parts = Parts::of(catalog, config, origin)?;
    run_parts(&parts, catalog, config, origin, starting, progress, false)
}

/// [`run_suite`] and [`ReportEstimates`] together, over one domain per scenario: the
/// report's landscapes and limits depend on the config alone, so they are estimated on the
/// current rayon pool while the experiments run, filling the cores the experiments'
/// ordered chains leave idle, and the domains' caches (plans) serve both. A sample trial
/// of each experiment is traced for the report's timelines. Returns the results, the
/// experiments' own run time (s) and the estimates.
pub fn run_suite_with_report<C: Catalog>(
    catalog: &C,
    config: &SuiteConfig,
    origin: &Path,
    starting: Option<&StartingCases>,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<(SuiteResults, f64, ReportEstimates), SuiteError> {
    let parts = Parts::of(catalog, config, origin)?;
    let (run, estimates) = rayon::join(
        || {
            let started = Instant::now();
            let results = run_parts(&parts, catalog, config, origin, starting, progress, true);
            (results, started.elapsed().as_secs_f64())
        },
        || estimate_parts(&parts, config, origin),
    );
    Ok((run.0?, run.1, estimates?))
}

/// The experiments of `config` over `parts`, with a sample trial of each traced when
/// `trace` (for a report).
fn run_parts<C: Catalog>(
    parts: &Parts<C>,
    catalog: &C,
    config: &SuiteConfig,
    origin: &Path,
    starting: Option<&StartingCases>,
    progress: &(dyn Fn(usize) + Sync),
    trace: bool,
) -> Result<SuiteResults, SuiteError> {
    let plans = plans(parts, catalog, config, origin, starting)?;
    let results = run_experiments(&plans, config.seed, progress)?;
    let timelines = plans
        .iter()
        .zip(&results)
        .map(|(plan, result)| {
            // The trial as it ran: the sample arm traced its first trials.
            sample_trial(result).filter(|_| trace).map(|(arm, trial)| {
                let ran = &result.arms[arm];
                timeline_of(
                    plan,
                    config,
                    arm,
                    ran.trials[trial as usize].clone(),
                    ran.traced[trial as usize].clone(),
                )
            })
        })
        .collect();
    let spaces = (0..config.experiments.len())
        .map(|k| parts.domain(k).space().clone())
        .collect();
    Ok(SuiteResults {
        results,
        spaces,
        timelines,
    })
}

/// Replays trial `trial` of arm `arm` of experiment `k` ([`trace_trial`]).
fn timeline<D: Domain>(
    plan: &ExperimentPlan<'_, D>,
    config: &SuiteConfig,
    k: usize,
    arm: usize,
    trial: u32,
) -> Result<Timeline, PlanError> {
    let (record, commands) = trace_trial(plan, k as u64, arm, trial, config.seed)?;
    Ok(timeline_of(plan, config, arm, record, commands))
}

/// The timeline of a traced trial of arm `arm`.
fn timeline_of<D: Domain>(
    plan: &ExperimentPlan<'_, D>,
    config: &SuiteConfig,
    arm: usize,
    record: TrialRecord,
    commands: Vec<TracedCommand>,
) -> Timeline {
    Timeline {
        experiment: plan.name.clone(),
        arm: plan.arms[arm].name().to_owned(),
        arm_index: arm,
        record,
        commands,
        thresholds: config.adapter.thresholds,
        observations: plan.domain.observations().to_vec(),
    }
}

/// Why a trial cannot be told ([`trace_suite_trial`]).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TraceError {
    /// The suite cannot be run.
    #[error(transparent)]
    Suite(#[from] SuiteError),
    /// No experiment has that name.
    #[error("no experiment is named `{name}` (the config's: {known})")]
    Experiment {
        /// The name given.
        name: String,
        /// The experiments' names.
        known: String,
    },
    /// The experiment has no arm of that name.
    #[error("experiment `{experiment}` has no arm `{name}` (its arms: {known})")]
    Arm {
        /// The experiment.
        experiment: String,
        /// The name given.
        name: String,
        /// The arms.
        known: String,
    },
    /// The trial is beyond the experiment's.
    #[error("experiment `{experiment}` ran trials 0 to {last}, not {trial}")]
    Trial {
        /// The experiment.
        experiment: String,
        /// The trial given.
        trial: u32,
        /// The last trial.
        last: u32,
    },
}

/// Replays one trial of a suite (experiment and arm by name), exactly as the suite ran it,
/// and returns its timeline with the experiment's behavior space.
pub fn trace_suite_trial<C: Catalog>(
    catalog: &C,
    config: &SuiteConfig,
    origin: &Path,
    starting: Option<&StartingCases>,
    experiment: &str,
    arm: &str,
    trial: u32,
) -> Result<(Timeline, Arc<BehaviorSpace>), TraceError> {
    let parts = Parts::of(catalog, config, origin)?;
    let plans = plans(&parts, catalog, config, origin, starting)?;
    let k = plans
        .iter()
        .position(|p| p.name == experiment)
        .ok_or_else(|| TraceError::Experiment {
            name: experiment.to_owned(),
            known: plans
                .iter()
                .map(|p| p.name.as_str())
                .collect::<Vec<_>>()
                .join(", "),
        })?;
    let plan = &plans[k];
    let a = plan
        .arms
        .iter()
        .position(|a| a.name() == arm)
        .ok_or_else(|| TraceError::Arm {
            experiment: experiment.to_owned(),
            name: arm.to_owned(),
            known: plan
                .arms
                .iter()
                .map(Arm::name)
                .collect::<Vec<_>>()
                .join(", "),
        })?;
    if trial >= plan.trials {
        return Err(TraceError::Trial {
            experiment: experiment.to_owned(),
            trial,
            last: plan.trials - 1,
        });
    }
    let timeline = timeline(plan, config, k, a, trial).map_err(SuiteError::from)?;
    Ok((timeline, parts.domain(k).space().clone()))
}

/// The experiment plans of `config` over `parts`, arms that reuse cases starting from
/// `starting` when given.
fn plans<'p, C: Catalog>(
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
                Some(s) if arm.reads_cases() => {
                    s.load(stem, arm.name(), &spec.scenario, domain.space())?
                }
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
        plans.push(ExperimentPlan {
            name: spec.name(),
            domain,
            operators,
            choice,
            trials: config.trials.get(),
            settings: config.adapter.settings(),
            arms: plan_arms,
            max_commands: config.max_commands,
            feedback: spec.feedback,
        });
    }
    Ok(plans)
}

/// Saves the case base each case-reading arm ([`Arm::reads_cases`]) ended every
/// experiment with, as
/// `DIR/EXPERIMENT/ARM.ron` (what [`StartingCases`] reads), each file naming its scenario
/// and behavior space as `trustcbr cases export` writes them, so that `cases info`,
/// `cases import` and `serve` read it as it is. Returns the files written.
pub fn save_case_bases(
    dir: &Path,
    config: &SuiteConfig,
    results: &SuiteResults,
) -> Result<Vec<PathBuf>, SuiteError> {
    let stems = file_stems(config.experiments.iter().map(|s| s.name()));
    let mut written = Vec::new();
    let experiments = results.results.iter().zip(&results.spaces);
    for (((result, space), stem), spec) in experiments.zip(&stems).zip(&config.experiments) {
        let folder = dir.join(stem);
        let identity = Identity {
            domain: spec.scenario.clone(),
            space: (**space).clone(),
        };
        for arm in &result.arms {
            let Some(cases) = &arm.final_cases else {
                continue;
            };
            std::fs::create_dir_all(&folder).map_err(|reason| FileError {
                path: folder.clone(),
                reason,
            })?;
            let path = folder.join(format!("{}.ron", arm.name));
            ron_file::save(&path, &identity, cases.cases())?;
            written.push(path);
        }
    }
    Ok(written)
}

/// The report entries of a suite's results, with the landscapes of each experiment when
/// given.
fn entries<'a>(
    config: &'a SuiteConfig,
    results: &'a SuiteResults,
    landscapes: &'a [Vec<Landscape>],
    limits: &'a [Option<ExperimentLimit>],
) -> Vec<ReportEntry<'a>> {
    config
        .experiments
        .iter()
        .zip(&results.results)
        .zip(&results.spaces)
        .enumerate()
        .map(|(k, ((spec, result), space))| ReportEntry {
            timeline: results.timelines.get(k).and_then(Option::as_ref),
            landscapes: landscapes.get(k).map_or(&[], Vec::as_slice),
            limit: limits.get(k).and_then(Option::as_ref),
            result,
            scenario: &spec.scenario,
            operator: spec
                .population
                .as_ref()
                .map_or(&spec.operator, |population| &population.name),
            space,
            reference: config.reference(),
            seed: config.seed,
        })
        .collect()
}

/// The report entries of a suite's results with its report's estimates: what the report's
/// tables, `summary.json` and `trials.jsonl` are made from.
pub fn report_entries<'a>(
    config: &'a SuiteConfig,
    results: &'a SuiteResults,
    estimates: &'a ReportEstimates,
) -> Vec<ReportEntry<'a>> {
    entries(config, results, &estimates.landscapes, &estimates.limits)
}

/// The results table in Markdown.
pub fn suite_table(config: &SuiteConfig, results: &SuiteResults) -> String {
    lab::report::table(&entries(config, results, &[], &[]))
}

/// One line per experiment: the arm that needed the fewest behaviors, against the first.
pub fn suite_best_arms(config: &SuiteConfig, results: &SuiteResults) -> String {
    lab::report::best_arms(&entries(config, results, &[], &[]))
}

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

/// What a suite's report estimates beside the experiments' results, from the config alone:
/// the landscapes behind each experiment's final behaviors and its known-operator limit
/// ([`run_suite_with_report`]). Independent of the results, so it is computed while the
/// experiments run.
pub struct ReportEstimates {
    /// Per experiment, its landscapes (empty when `landscape_runs` is 0).
    landscapes: Vec<Vec<Landscape>>,
    /// Per experiment, its limit (none when the limit's `runs` is 0).
    limits: Vec<Option<ExperimentLimit>>,
}

/// Estimates, on the current rayon pool, the landscape of each experiment's operators
/// behind its final behaviors and each experiment's known-operator limit (once per scenario
/// and operator), over `parts`.
fn estimate_parts<C: Catalog>(
    parts: &Parts<C>,
    config: &SuiteConfig,
    origin: &Path,
) -> Result<ReportEstimates, SuiteError> {
    let mut landscapes = Vec::with_capacity(config.experiments.len());
    let mut limits = Vec::with_capacity(config.experiments.len());
    let mut operator_limits = OperatorLimits::default();
    for (k, spec) in config.experiments.iter().enumerate() {
        let fail = |reason: String| invalid(origin, format!("experiments[{k}]"), reason);
        let judges: Vec<&(String, OperatorOf<C>)> = spec.judges(&parts.operators[k]).collect();
        if config.landscape_runs > 0 {
            let operators: Vec<&OperatorOf<C>> = judges.iter().map(|(_, op)| op).collect();
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
            let known: Vec<&KnownOperator> = of_each
                .iter()
                .map(|&i| &operator_limits.known[i].1)
                .collect();
            limits.push(Some(
                ExperimentLimit::of(&known).map_err(|e| fail(e.to_string()))?,
            ));
        }
    }
    Ok(ReportEstimates { landscapes, limits })
}

/// Writes the report folder for a suite run, with its [`ReportEstimates`]: the landscapes
/// behind each experiment's final behaviors and each experiment's known-operator limit. The
/// report reruns by itself: every operator file the config names (relative to `origin`)
/// is copied into `DIR/operators/`, and the `config.ron` written names those copies.
pub fn write_suite_report(
    dir: &Path,
    config: &SuiteConfig,
    origin: &Path,
    results: &SuiteResults,
    estimates: &ReportEstimates,
    elapsed_s: f64,
    provenance: &Provenance,
) -> Result<Vec<PathBuf>, SuiteError> {
    let (portable, copies) = config.with_operator_files_in("operators", origin);
    let mut written = write_report(
        dir,
        &entries(config, results, &estimates.landscapes, &estimates.limits),
        &portable.to_ron(),
        elapsed_s,
        provenance,
    )?;
    for (source, copy) in copies {
        written.push(write_file_in(dir, copy, &read_text(&source)?)?);
    }
    Ok(written)
}

impl SuiteConfig {
    /// This config with every operator file moved into `folder` (relative names, one
    /// copy per distinct file), and the (source, copy) pairs to copy: sources resolved
    /// against `origin`'s directory.
    fn with_operator_files_in(
        &self,
        folder: &str,
        origin: &Path,
    ) -> (Self, Vec<(PathBuf, PathBuf)>) {
        let base = origin.parent().unwrap_or(Path::new("."));
        let mut sources: Vec<PathBuf> = Vec::new();
        for spec in &self.experiments {
            for file in &spec.operator_files {
                let source = base.join(file);
                if !sources.contains(&source) {
                    sources.push(source);
                }
            }
        }
        let stems = file_stems(sources.iter().map(|p| {
            p.file_stem()
                .map_or_else(String::new, |s| s.to_string_lossy().into_owned())
        }));
        let copies: Vec<(PathBuf, PathBuf)> = sources
            .into_iter()
            .zip(stems)
            .map(|(source, stem)| (source, Path::new(folder).join(format!("{stem}.ron"))))
            .collect();
        let mut portable = self.clone();
        for spec in &mut portable.experiments {
            for file in &mut spec.operator_files {
                let source = base.join(&*file);
                *file = copies
                    .iter()
                    .find(|(s, _)| *s == source)
                    .expect("every file was collected")
                    .1
                    .clone();
            }
        }
        (portable, copies)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::UgvCatalog;
    use crate::ugv::{PATROL_WEIGHTS, THREE_AND_ONE};

    #[test]
    fn the_paper_config_has_the_seven_experiments() {
        let config = SuiteConfig::embedded(&UgvCatalog).unwrap();
        assert_eq!(config.trials.get(), 500);
        let names: Vec<String> = config
            .experiments
            .iter()
            .map(ExperimentSpec::name)
            .collect();
        assert_eq!(
            names,
            [
                "movement/speed-focused",
                "movement/safety-focused",
                "movement/balanced",
                "movement/random",
                "patrol/speed-focused",
                "patrol/detection-focused",
                "patrol/random",
            ]
        );
        assert_eq!(
            config.adapter,
            SuiteAdapter {
                retriever: RetrieverKind::InvertedIndex,
                ..SuiteAdapter::default()
            }
        );
        assert_eq!(config.arms, BUILTIN_ARMS);
    }

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
    fn the_patrol_weight_reading_is_a_config_value() {
        let spec = ExperimentSpec {
            scenario: "patrol".into(),
            operator: RANDOM_OPERATOR.into(),
            operator_files: Vec::new(),
            population: None,
            feedback: None,
        };
        let origin = Path::new("x.ron");
        let as_written = resolve_readings(&UgvCatalog, &BTreeMap::new()).unwrap();
        let chosen = BTreeMap::from([(PATROL_WEIGHTS.to_owned(), THREE_AND_ONE.to_owned())]);
        let three = resolve_readings(&UgvCatalog, &chosen).unwrap();
        let w = &spec.operators(&UgvCatalog, origin, &as_written).unwrap()[0]
            .1
            .weights;
        let t = &spec.operators(&UgvCatalog, origin, &three).unwrap()[0]
            .1
            .weights;
        assert!((w.completed - 1.0 / 3.0).abs() < 1e-15);
        assert!((t.completed - 1.0).abs() < 1e-15);
        assert!((t.of(domains::causes::COLLISION) - 1.0).abs() < 1e-15);
        assert!((t.of(domains::causes::DETONATION) - 3.0).abs() < 1e-15);
        // Movement operators are not patrol operators: unchanged.
        let movement = ExperimentSpec {
            scenario: "movement".into(),
            ..spec
        };
        let m = movement.operators(&UgvCatalog, origin, &three).unwrap();
        assert_eq!(m[0].1.weights.completed, 1.0);
        let config = SuiteConfig::from_ron(
            &UgvCatalog,
            "(seed: 1, trials: 5, readings: {\"patrol_weights\": \"three_and_one\"}, adapter: (retention: final_from_search, time_unit: commands), experiments: [(scenario: \"patrol\", operator: \"random\")])",
            origin,
        )
        .unwrap();
        assert_eq!(config.readings, chosen);
        assert_eq!(config.adapter.retention, Retention::FinalFromSearch);
        assert_eq!(config.adapter.time_unit, TimeUnit::Commands);
        // A reading or value the catalog does not declare is named with what is allowed.
        for (readings, wanted) in [
            (
                "{\"weights\": \"x\"}",
                "unknown reading `weights` (known: patrol_weights)",
            ),
            (
                "{\"patrol_weights\": \"double\"}",
                "has no value `double` (allowed: as_written, three_and_one)",
            ),
        ] {
            let err = SuiteConfig::from_ron(
                &UgvCatalog,
                &format!("(seed: 1, trials: 5, readings: {readings}, experiments: [(scenario: \"patrol\", operator: \"random\")])"),
                origin,
            )
            .unwrap_err()
            .to_string();
            assert!(err.contains("readings") && err.contains(wanted), "{err}");
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

    #[test]
    fn the_config_round_trips() {
        let config = SuiteConfig::embedded(&UgvCatalog).unwrap();
        let back =
            SuiteConfig::from_ron(&UgvCatalog, &config.to_ron(), Path::new("x.ron")).unwrap();
        assert_eq!(back, config);
    }

    /// The UGV catalog with one arm of its own: uniform search under another name.
    struct WithOwnArm;

    impl Catalog for WithOwnArm {
        type Domain = domains::UgvDomain;
        fn tool(&self) -> crate::ToolInfo {
            crate::tool_info!()
        }
        fn scenarios(&self) -> Vec<String> {
            UgvCatalog.scenarios()
        }
        fn domain(&self, scenario: &str) -> Option<Self::Domain> {
            UgvCatalog.domain(scenario)
        }
        fn operators(
            &self,
            scenario: &str,
            readings: &Readings,
        ) -> Vec<(String, OperatorOf<Self>)> {
            UgvCatalog.operators(scenario, readings)
        }
        fn load_operator(
            &self,
            scenario: &str,
            path: &Path,
            readings: &Readings,
        ) -> Result<(String, OperatorOf<Self>), CatalogError> {
            UgvCatalog.load_operator(scenario, path, readings)
        }
        fn arms(&self, _: RetrieverKind) -> Vec<Arm> {
            vec![Arm::search_only("mine", |_| {
                trust::SearchKind::Uniform.build()
            })]
        }
        fn default_suite(&self) -> &str {
            UgvCatalog.default_suite()
        }
    }

    #[test]
    fn a_catalog_s_own_arms_are_named_like_built_in_ones() {
        let origin = Path::new("own.ron");
        let config = SuiteConfig::from_ron(
            &WithOwnArm,
            "(seed: 1, trials: 3, arms: [\"random-walk\", \"mine\"], experiments: [(scenario: \"movement\", operator: \"balanced\")])",
            origin,
        )
        .unwrap();
        let results = run_suite(&WithOwnArm, &config, origin, None, &|_| ()).unwrap();
        let names: Vec<&str> = results.results[0]
            .arms
            .iter()
            .map(|a| a.name.as_str())
            .collect();
        assert_eq!(names, ["random-walk", "mine"]);
        let err = SuiteConfig::from_ron(
            &WithOwnArm,
            "(seed: 1, trials: 3, arms: [\"yours\"], experiments: [(scenario: \"movement\", operator: \"balanced\")])",
            origin,
        )
        .unwrap_err()
        .to_string();
        assert!(
            err.contains("arms[0]")
                && err.contains("unknown arm `yours`")
                && err.ends_with(
                    "case-based+model-based, case-based+conditioned, mine; each also as NAME+learned-start)"
                ),
            "{err}"
        );
    }

    #[test]
    fn the_learned_start_suite_pairs_each_arm_with_its_learned_start() {
        let file =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("domains/experiments/learned-start.ron");
        let suite = SuiteConfig::load(&UgvCatalog, &file).unwrap();
        assert_eq!(suite.experiments.len(), 7 + 2 * 5);
        for pair in suite.arms.chunks(2) {
            assert_eq!(pair[1], format!("{}+learned-start", pair[0]));
        }
    }

    #[test]
    fn an_arm_may_start_from_the_memory_s_guess() {
        let origin = Path::new("learned.ron");
        let parse = |arms: &str| {
            SuiteConfig::from_ron(
                &WithOwnArm,
                &format!(
                    "(seed: 1, trials: 4, arms: {arms}, experiments: [(scenario: \"movement\", operator: \"random\")])"
                ),
                origin,
            )
        };
        // Plain names are read as they always were; an arm's options are read as the
        // name of the arm they make, for a built-in arm or the catalog's own.
        let config = parse(
            "[\"case-based\", (name: \"case-based\", initial: learned), (name: \"uniform\", initial: random), (name: \"mine\", initial: learned), \"conditioned+learned-start\"]",
        )
        .unwrap();
        assert_eq!(
            config.arms,
            [
                "case-based",
                "case-based+learned-start",
                "uniform",
                "mine+learned-start",
                "conditioned+learned-start"
            ]
        );
        let back = SuiteConfig::from_ron(&WithOwnArm, &config.to_ron(), origin).unwrap();
        assert_eq!(back, config);
        let json = SuiteConfig::from_json(
            &WithOwnArm,
            r#"{"seed": 1, "trials": 4, "arms": ["uniform", {"name": "uniform", "initial": "learned"}], "experiments": [{"scenario": "movement", "operator": "random"}]}"#,
            origin,
        )
        .unwrap();
        assert_eq!(json.arms, ["uniform", "uniform+learned-start"]);
        // A bad value is refused where it stands, with the allowed ones.
        let err = parse("[\"uniform\",\n  (name: \"case-based\", initial: fast)]")
            .unwrap_err()
            .to_string();
        assert!(
            err.starts_with("learned.ron:2:")
                && err.contains("field `initial`")
                && err.contains("`random`")
                && err.contains("`learned`"),
            "{err}"
        );
        for (arms, expected) in [
            (
                "[(name: \"case-based+learned-start\", initial: learned)]",
                "write the arm `case-based` and set `initial`",
            ),
            ("[(name: \"case-based\", start: learned)]", "start"),
            ("[(initial: learned)]", "missing field `name`"),
            ("[(name: \"x\", name: \"y\")]", "duplicate field `name`"),
            ("[3]", "an arm's name as a string"),
            (
                "[\"case-based+learned-start\", (name: \"case-based\", initial: learned)]",
                "arms[1]: `case-based+learned-start` is listed twice",
            ),
            (
                "[(name: \"annealing\", initial: learned)]",
                "unknown arm `annealing+learned-start`",
            ),
        ] {
            let err = parse(arms).unwrap_err().to_string();
            assert!(err.contains(expected), "{arms}: {err}");
        }

        // Every name works where arm names do: the run, the reference, a replayed trial,
        // saved case bases read back.
        let config = parse(
            "[\"case-based\", (name: \"case-based\", initial: learned), (name: \"mine\", initial: learned)], reference: \"case-based+learned-start\"",
        )
        .unwrap();
        assert_eq!(config.reference(), "case-based+learned-start");
        let results = run_suite(&WithOwnArm, &config, origin, None, &|_| ()).unwrap();
        let result = &results.results[0];
        let names: Vec<&str> = result.arms.iter().map(|a| a.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "case-based",
                "case-based+learned-start",
                "mine+learned-start"
            ]
        );
        for arm in &result.arms {
            // Trial 0 of every arm starts from the same random behavior.
            assert_eq!(arm.trials[0].initial, result.arms[0].trials[0].initial);
            assert!(!arm.trials[0].learned_start);
        }
        let learned = &result.arms[1];
        let replayed = trace_suite_trial(
            &WithOwnArm,
            &config,
            origin,
            None,
            &result.name,
            "case-based+learned-start",
            3,
        )
        .unwrap()
        .0;
        assert_eq!(replayed.record, learned.trials[3]);
        let dir = tempfile::tempdir().unwrap();
        let written = save_case_bases(dir.path(), &config, &results).unwrap();
        // Every arm reads cases: the plain one reuses them, the others start from them.
        assert_eq!(written.len(), 3);
        assert!(written[2].ends_with("movement-random/mine+learned-start.ron"));
        let starting = StartingCases {
            dir: dir.path().to_owned(),
        };
        let again = run_suite(&WithOwnArm, &config, origin, Some(&starting), &|_| ()).unwrap();
        let mine = &again.results[0].arms[2];
        assert_eq!(
            mine.starting_cases,
            result.arms[2].final_cases.as_ref().unwrap().len()
        );
        if mine.starting_cases > 0 {
            assert!(mine.trials[0].learned_start);
        }
    }
}
