//! A suite config as written (RON, or JSON from Python): its fields and their defaults,
//! how arms and scenarios are read, reading and parsing a file, and what an experiment
//! names (its report name, its operators).

use super::{SuiteError, invalid};
use crate::catalog::{Catalog, Family, OperatorOf, Readings, resolve_readings};
use crate::limits::CONTEXT_CYCLE;
use cbr_core::{Context, ContextSpace};
use files::{parse_ron, read_text};
use lab::contract::stating::Stating;
use lab::reference::known_operator::LimitSettings;
use lab::report::FINALS_LANDSCAPE_RUNS;
use lab::{ArmName, Initial, NameOptions};
use lab::{FeedbackChannel, GoalChanges, TrialContexts};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::num::NonZeroU32;
use std::path::{Path, PathBuf};
use trust::{AdapterConfig, SearchKind};

/// The operator name that draws an operator per trial.
pub const RANDOM_OPERATOR: &str = "random";

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
    /// The adapter every arm starts from: thresholds, `lambda`, the retriever of the arms
    /// that reuse cases, retention and unit of time; case reuse and the search strategy
    /// are each arm's (a suite that sets them is refused).
    #[serde(default, serialize_with = "write_suite_adapter")]
    pub adapter: AdapterConfig,
    /// The domain's readings, by name ([`Catalog::readings`]; each left out keeps its
    /// default), e.g. `{"patrol_weights": "three_and_one"}`, each once.
    #[serde(
        default,
        skip_serializing_if = "BTreeMap::is_empty",
        deserialize_with = "cbr_core::unique_keys::each_once"
    )]
    pub readings: BTreeMap<String, String>,
    /// The arms to compare, by name: built-in ([`lab::builtin_arms`]) or the catalog's own
    /// ([`Catalog::arms`]), each optionally followed by [`lab::LEARNED_START`] (it starts each
    /// episode from the case memory's guess); default: every built-in arm. A config may
    /// also write an arm as `(name: "case-based", initial: learned)` (`initial`: `random`,
    /// the default, or `learned`), which is read as the name `case-based+learned-start`
    /// (`case-based+learned-start+competent` for `(name: "case-based+competent", ...)`).
    #[serde(default = "default_arms", deserialize_with = "arm_names")]
    pub arms: Vec<ArmName>,
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
    #[serde(deserialize_with = "experiments_read")]
    pub experiments: Vec<ExperimentSpec>,
    /// Runs per cell of the operator landscapes the report draws the final behaviors over
    /// (0: no landscape).
    #[serde(default = "default_landscape_runs")]
    pub landscape_runs: u32,
    /// How the report estimates each experiment's known-operator limit (`runs: 0`: none).
    #[serde(default)]
    pub limit: LimitSettings,
    /// Whether the suite is a benchmark: its population experiments are instances of their
    /// scenarios, and the report aggregates every arm over each scenario's populations
    /// against their limits ([`lab::population::benchmark`]). Left out of a config that is not (every
    /// other config and report reads and writes as before).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub benchmark: bool,
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
/// read as the name of the arm it stands for (`NAME+learned-start` for `learned`), each
/// read once into an [`ArmName`] (suffixes written twice or out of order are refused
/// here, where the file says them). Mission suites and sweeps read their arms with it too.
pub(crate) fn arm_names<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Vec<ArmName>, D::Error> {
    Vec::<WrittenArm>::deserialize(d).map(|arms| arms.into_iter().map(|a| a.0).collect())
}

/// [`arm_names`] of an optional list (a sweep's `arms`).
pub(crate) fn some_arm_names<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<Option<Vec<ArmName>>, D::Error> {
    Option::<Vec<WrittenArm>>::deserialize(d)
        .map(|arms| arms.map(|arms| arms.into_iter().map(|a| a.0).collect()))
}

/// [`arm_names`] of each list of a list (a sweep's `arms([...])` parameter).
pub(crate) fn arm_name_lists<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<Vec<Vec<ArmName>>, D::Error> {
    Vec::<Vec<WrittenArm>>::deserialize(d).map(|lists| {
        lists
            .into_iter()
            .map(|arms| arms.into_iter().map(|a| a.0).collect())
            .collect()
    })
}

/// One arm as a suite writes it, read.
struct WrittenArm(ArmName);

impl<'de> Deserialize<'de> for WrittenArm {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(ArmVisitor).map(WrittenArm)
    }
}

struct ArmVisitor;

impl<'de> serde::de::Visitor<'de> for ArmVisitor {
    type Value = ArmName;
    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("an arm's name as a string, or `(name: \"case-based\", initial: learned)`")
    }
    fn visit_str<E: serde::de::Error>(self, name: &str) -> Result<ArmName, E> {
        ArmName::parse(name).map_err(E::custom)
    }
    fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<ArmName, A::Error> {
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
        let read =
            ArmName::parse(&name).map_err(|e| A::Error::custom(format!("field `name`: {e}")))?;
        let options = read.options();
        if options.initial == Initial::Learned {
            let unstarted = read.with_options(NameOptions {
                initial: Initial::Random,
                ..options
            });
            return Err(A::Error::custom(format!(
                "field `name`: `{name}` already names how its episodes start; write the arm `{unstarted}` and set `initial`"
            )));
        }
        Ok(read.with_options(NameOptions {
            initial: initial.unwrap_or_default(),
            ..options
        }))
    }
}

fn default_landscape_runs() -> u32 {
    FINALS_LANDSCAPE_RUNS
}

fn default_max_commands() -> u64 {
    1_000_000
}

fn default_arms() -> Vec<ArmName> {
    lab::builtin_arms()
        .iter()
        .map(|arm| ArmName::new(arm.name, NameOptions::default()))
        .collect()
}

/// Writes a suite's `adapter` without `reuse_cases` and `search`, which the arms choose
/// ([`check_arms_choose`] refuses them in a suite).
pub(crate) fn write_suite_adapter<S: serde::Serializer>(
    adapter: &AdapterConfig,
    serializer: S,
) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeStruct;
    let AdapterConfig {
        thresholds,
        lambda,
        reuse_cases: _,
        retriever,
        search: _,
        retention,
        time_unit,
    } = *adapter;
    let mut out = serializer.serialize_struct("AdapterConfig", 5)?;
    out.serialize_field("thresholds", &thresholds)?;
    out.serialize_field("lambda", &lambda)?;
    out.serialize_field("retriever", &retriever)?;
    out.serialize_field("retention", &retention)?;
    out.serialize_field("time_unit", &time_unit)?;
    out.end()
}

/// Refuses a suite `adapter` that chooses what each arm chooses: whether cases are reused
/// and the search strategy.
pub(crate) fn check_arms_choose(adapter: &AdapterConfig, origin: &Path) -> Result<(), SuiteError> {
    if !adapter.reuse_cases {
        return Err(invalid(
            origin,
            "adapter.reuse_cases".into(),
            "whether cases are reused is each arm's choice (`case-based` reuses them, `random-walk` does not): remove it and list the arms in `arms`".into(),
        ));
    }
    if adapter.search != SearchKind::default() {
        return Err(invalid(
            origin,
            "adapter.search".into(),
            "the search strategy is each arm's choice (`uniform`, `cause-aware`, ...): remove it and list the arms in `arms`".into(),
        ));
    }
    Ok(())
}

/// One experiment: a scenario and who operates the robot.
///
/// Read through [`SuiteConfig::from_ron`], [`SuiteConfig::from_json`] or
/// [`SuiteConfig::load`], an experiment always names its operator: one it leaves out is
/// chosen there (see [`ExperimentSpec::operator`]), and the report's `config.ron` writes it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExperimentSpec {
    /// The scenario, by the catalog's name for it (a RON string: `"movement"`).
    #[serde(deserialize_with = "deserialize_scenario")]
    pub scenario: String,
    /// Who judges the trials: one of the experiment's operators by name (a built-in
    /// operator of the scenario, or the `name` of one of its `operator_files`), or
    /// [`RANDOM_OPERATOR`] (`random`) to draw one of them per trial.
    ///
    /// A config may leave it out when the experiment says who operates otherwise:
    /// - with a `population`, it is `random` (the only value a population takes);
    /// - with exactly one operator file (and no population), it is that file's operator
    ///   (its `name`), which judges every trial, exactly as with that name written;
    /// - with several operator files (and no population), it is `random`: each trial draws
    ///   one of all the experiment's operators, the scenario's built-in ones and the
    ///   files' (for a draw among the files alone, make them a `population`).
    ///
    /// An experiment with neither an `operator`, nor `operator_files`, nor a `population`
    /// is refused, naming what to write. Every config that writes `operator` reads as it
    /// always did. The `random` cases are filled in as the config is parsed, the one-file
    /// case as it is read against the catalog (which reads the file's name): empty until
    /// then, and an empty `operator` is written out of a config.
    #[serde(
        default,
        skip_serializing_if = "String::is_empty",
        deserialize_with = "deserialize_operator"
    )]
    pub operator: String,
    /// Extra operator files (RON), relative to the config file; they join the scenario's
    /// built-in operators.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub operator_files: Vec<PathBuf>,
    /// A population's members among the scenario's built-in operators
    /// ([`Catalog::operators`]), by name, before those of `operator_files`: a population
    /// a config needs no file for (a catalog's embedded suite). Only with a `population`
    /// listed by hand.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub builtin_operators: Vec<String>,
    /// The experiment's operators are a population instead of the scenario's: listed by
    /// hand (`builtin_operators`, then `operator_files`), or members drawn from the
    /// catalog's parametric family ([`Catalog::family`]); `operator` must then be `random`
    /// or left out (a member judges each trial).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub population: Option<Population>,
    /// How every operator of the experiment explains itself (`(explains: 0.3, wrong:
    /// 0.1)`), overriding each operator's own channel; absent: the operators' own (the
    /// paper's silent operator unless an operator file says otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub feedback: Option<FeedbackChannel>,
    /// How often the operators' goals change (`(per_hour: 1.0)`): commands interrupted
    /// for reasons that are not the behavior's (lab::experiment::goal_change); absent: never, the
    /// paper's assumption. Whether an operator says so is its channel's
    /// (`feedback: (goal_changes: 1.0)`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub goal_changes: Option<GoalChanges>,
    /// The contexts the trials run in, in turn (`(cycle: [{}, {"cargo": "hazardous"}])`;
    /// docs/simulation.md#context; the robot is told them unless its arm is
    /// `NAME+context-blind`); absent: every trial in the default context.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contexts: Option<ContextsSpec>,
    /// What the operators state up front (`(said: 1.0, wrong: 0.3)`: each true statement
    /// said with chance `said`, the wrong way round with chance `wrong`; lab::contract::stating,
    /// docs/simulation.md#stated-preferences); absent: nothing, as the paper's operators.
    /// Named in the experiment's name (`/s1w0.3`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stated: Option<Stating>,
}

/// Reads a suite's experiments, each with the `operator` it leaves out chosen where that
/// needs no catalog ([`ExperimentSpec::random_when_left_out`]).
fn experiments_read<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<Vec<ExperimentSpec>, D::Error> {
    let mut experiments = Vec::<ExperimentSpec>::deserialize(d)?;
    experiments
        .iter_mut()
        .for_each(ExperimentSpec::random_when_left_out);
    Ok(experiments)
}

/// An experiment's `operator` as written: a name, never empty (an empty name would read as
/// one left out).
fn deserialize_operator<'de, D: serde::Deserializer<'de>>(d: D) -> Result<String, D::Error> {
    let name = String::deserialize(d)?;
    if name.is_empty() {
        return Err(serde::de::Error::custom(format!(
            "`operator` is empty: name an operator of the experiment (a built-in operator of its scenario, or an operator file's `name`), write `operator: \"{RANDOM_OPERATOR}\"`, or leave `operator` out beside `operator_files` or a `population`"
        )));
    }
    Ok(name)
}

/// The contexts an experiment's trials run in ([`lab::TrialContexts`]), as a suite writes
/// them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContextsSpec {
    /// Trial `k` runs in context `k` modulo the cycle's length: each context its
    /// variables and values (`{}`: the default context), each variable once.
    #[serde(deserialize_with = "cbr_core::unique_keys::each_variable_once_in_each")]
    pub cycle: Vec<BTreeMap<String, String>>,
    /// Retired (read only to say so): whether the robot is told the context is its arm's
    /// (`NAME+context-blind`), so that a blind arm runs on the same trials as its sighted
    /// twin.
    #[serde(default, skip_serializing)]
    pub told: Retired,
}

/// A field that is read only to refuse it with what replaced it: present (whatever its
/// value) or not.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Retired(bool);

impl Retired {
    /// Whether the field was written.
    pub fn is_written(self) -> bool {
        self.0
    }
}

impl<'de> Deserialize<'de> for Retired {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        serde::de::IgnoredAny::deserialize(d).map(|_| Retired(true))
    }
}

impl ContextsSpec {
    /// The trials' contexts, each checked against `space` (the domain's context
    /// variables), at most [`CONTEXT_CYCLE`] of them (counted before any is read), each
    /// listed once; an error names the field under the experiment (`contexts.cycle[1]`).
    ///
    /// A context listed twice is refused rather than merged: merging would change which
    /// context a trial runs in, and a repeated context only repeats the report's work on
    /// it (every operator in every context of the cycle is taken apart).
    pub fn trial_contexts(&self, space: &ContextSpace) -> Result<TrialContexts, (String, String)> {
        if self.told.is_written() {
            return Err((
                "contexts.told".to_owned(),
                "is retired: whether the robot is told its context is its arm's; run the arm `NAME+context-blind` beside `NAME`, on the same trials".to_owned(),
            ));
        }
        CONTEXT_CYCLE
            .check_total(
                "contexts.cycle",
                self.cycle.len() as u64,
                " in the cycle".to_owned(),
            )
            .map_err(|e| (e.field().to_owned(), e.problem()))?;
        let cycle = contexts_written(&self.cycle, space, "contexts.cycle")?;
        let mut first_at = BTreeMap::new();
        for (i, context) in cycle.iter().enumerate() {
            if let Some(j) = first_at.insert(context, i) {
                return Err((
                    format!("contexts.cycle[{i}]"),
                    format!(
                        "the context `{context}` is listed already, at contexts.cycle[{j}]; list each context once (trials take them in turn)"
                    ),
                ));
            }
        }
        TrialContexts::new(cycle).ok_or_else(|| {
            (
                "contexts.cycle".to_owned(),
                "needs at least one context (`{}` is the default one)".to_owned(),
            )
        })
    }
}

/// The contexts a suite writes under `field` (each its variables and values), each checked
/// against `space`; an error names the field and the place (`contexts.cycle[1]`).
pub(crate) fn contexts_written(
    written: &[BTreeMap<String, String>],
    space: &ContextSpace,
    field: &str,
) -> Result<Vec<Context>, (String, String)> {
    written
        .iter()
        .enumerate()
        .map(|(i, settings)| {
            let named = settings.iter().map(|(k, v)| (k.as_str(), v.as_str()));
            space
                .context(named)
                .map_err(|e| (format!("{field}[{i}]"), e.to_string()))
        })
        .collect()
}

/// A population of operators an experiment draws from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Population {
    /// Its name in reports: the experiment is called `SCENARIO/NAME`.
    pub name: String,
    /// Members drawn from the catalog's family (`builtin_operators` and `operator_files`
    /// must then be empty); absent: the members are the experiment's `builtin_operators`
    /// and `operator_files`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub family: Option<Family>,
}

/// A scenario name: a string. A bare identifier (`scenario: movement`, as configs spelled
/// it before scenarios were the catalog's) is refused with the spelling to use.
pub(crate) fn deserialize_scenario<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<String, D::Error> {
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

/// The fields of an experiment ([`ExperimentSpec`]), which a suite refuses at its top level
/// with a word on where they belong.
const EXPERIMENT_FIELDS: [&str; 8] = [
    "scenario",
    "operator",
    "operator_files",
    "builtin_operators",
    "population",
    "feedback",
    "goal_changes",
    "contexts",
];

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
                    .map(ArmName::as_str)
            })
            .or_else(|| self.arms.first().map(ArmName::as_str))
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

    /// Parses and checks a suite config; `origin` names the source in errors. An
    /// experiment's `operator` left out is chosen here ([`ExperimentSpec::operator`]).
    pub fn from_ron<C: Catalog>(
        catalog: &C,
        text: &str,
        origin: &Path,
    ) -> Result<Self, SuiteError> {
        let mut config = Self::parse(text, origin)?;
        config.choose_left_out_operators(catalog, origin);
        config.validate(catalog, origin)?;
        Ok(config)
    }

    /// Chooses the operator of each experiment that leaves it out beside exactly one
    /// operator file: that file's operator (its file relative to the directory of
    /// `origin`; [`ExperimentSpec::operator`]); the other choices were made as the config
    /// was parsed. [`SuiteConfig::from_ron`], [`SuiteConfig::from_json`] and
    /// [`SuiteConfig::load`] call it; a config parsed otherwise may. A file that cannot be
    /// read, or readings that are not the catalog's, leave it out, for
    /// [`SuiteConfig::validate`] to report.
    pub fn choose_left_out_operators<C: Catalog>(&mut self, catalog: &C, origin: &Path) {
        if let Ok(readings) = resolve_readings(catalog, &self.readings) {
            for spec in &mut self.experiments {
                spec.operator_of_its_file(catalog, origin, &readings);
            }
        }
    }

    /// Parses a suite config as written, unchecked (a mission suite refused by name, not
    /// as a field `SuiteConfig` lacks); `origin` names the source in errors.
    pub(super) fn parse(text: &str, origin: &Path) -> Result<Self, SuiteError> {
        if crate::mission_suite::is_mission_suite(text) {
            return Err(mission_suite_here(origin));
        }
        parse_ron(text, origin).map_err(|mut e| {
            if let Some(field) = EXPERIMENT_FIELDS
                .iter()
                .find(|f| {
                    let unexpected = format!("Unexpected field named `{f}` in `SuiteConfig`");
                    e.message.starts_with(&unexpected)
                })
            {
                e.message.push_str(&format!(
                    "; `{field}` belongs to an experiment: `experiments: [(scenario: ..., {field}: ...)]`"
                ));
            }
            SuiteError::from(e)
        })
    }

    /// Parses and checks a suite config given as JSON (the same fields as the RON file: a
    /// Python dict); `origin` names the source in errors and anchors operator files.
    pub fn from_json<C: Catalog>(
        catalog: &C,
        text: &str,
        origin: &Path,
    ) -> Result<Self, SuiteError> {
        if let Ok(serde_json::Value::Object(fields)) = serde_json::from_str(text)
            && fields.contains_key("missions")
        {
            return Err(mission_suite_here(origin));
        }
        let mut config: Self = crate::config_file::from_json(text, origin)?;
        config.choose_left_out_operators(catalog, origin);
        config.validate(catalog, origin)?;
        Ok(config)
    }

    /// The config as RON, as written to a report's `config.ron`.
    pub fn to_ron(&self) -> String {
        ron::ser::to_string_pretty(self, ron::ser::PrettyConfig::default())
            .expect("plain data serializes")
    }
}

/// A mission suite given where an experiment suite is needed.
fn mission_suite_here(origin: &Path) -> SuiteError {
    invalid(
        origin,
        "missions".into(),
        "this is a mission suite (it lists `missions`), not an experiment suite: `trustcbr run` runs it and writes its report; `explain`, `sweep` and the options of experiments (trials, landscapes, case bases) apply to experiment suites".into(),
    )
}

impl ExperimentSpec {
    /// The contexts its trials run in, when it has `contexts`
    /// ([`ContextsSpec::trial_contexts`], checked against `space`); an error names the
    /// field under the experiment (`contexts.cycle[1]`).
    pub(crate) fn trial_contexts(
        &self,
        space: &ContextSpace,
    ) -> Result<Option<TrialContexts>, (String, String)> {
        self.contexts
            .as_ref()
            .map(|c| c.trial_contexts(space))
            .transpose()
    }

    /// The report name, e.g. `movement/speed-focused` (`movement/speed-focused/f0.3w0.1`
    /// with a feedback channel of its own, `movement/rung-2` for a population; with goal
    /// changes, `/g1` at one an hour, `/g1s0.5` when half of them are said; in contexts,
    /// `/contexts`).
    pub fn name(&self) -> String {
        let name = self.name_without_contexts();
        // The same operators may state with several shares: each is its own experiment.
        let name = match self.stated {
            None => name,
            Some(s) if s.wrong > 0.0 => format!("{name}/s{}w{}", s.said, s.wrong),
            Some(s) => format!("{name}/s{}", s.said),
        };
        match &self.contexts {
            None => name,
            Some(_) => format!("{name}/contexts"),
        }
    }

    /// [`ExperimentSpec::name`] before the statements' and the contexts' parts.
    fn name_without_contexts(&self) -> String {
        let says_goal_changes = self.feedback.map_or(0.0, |c| c.goal_changes);
        let base = match (&self.population, self.feedback) {
            (Some(population), _) => format!("{}/{}", self.scenario, population.name),
            (None, None) => format!("{}/{}", self.scenario, self.operator),
            // The same operator may be run with several channels: each is its own
            // experiment, named by its channel (`/f0.3w0.1`: explains 30%, 10% wrongly).
            (None, Some(channel)) if channel.wrong > 0.0 => format!(
                "{}/{}/f{}w{}",
                self.scenario, self.operator, channel.explains, channel.wrong
            ),
            // A channel that only says goal changes is named by them.
            (None, Some(channel)) if channel.explains <= 0.0 && says_goal_changes > 0.0 => {
                format!("{}/{}", self.scenario, self.operator)
            }
            (None, Some(channel)) => {
                format!("{}/{}/f{}", self.scenario, self.operator, channel.explains)
            }
        };
        match self.goal_changes {
            None => base,
            Some(changes) if says_goal_changes > 0.0 => {
                format!("{base}/g{}s{says_goal_changes}", changes.per_hour)
            }
            Some(changes) => format!("{base}/g{}", changes.per_hour),
        }
    }

    /// Chooses the `operator` the experiment leaves out where that needs no catalog:
    /// `random` with a population or several operator files ([`ExperimentSpec::operator`]).
    pub(crate) fn random_when_left_out(&mut self) {
        if self.operator.is_empty() && (self.population.is_some() || self.operator_files.len() > 1)
        {
            self.operator = RANDOM_OPERATOR.to_owned();
        }
    }

    /// Chooses the `operator` the experiment leaves out beside exactly one operator file
    /// (and no population): that file's operator, read as `readings` read it (relative to
    /// the directory of `origin`). A file that cannot be read leaves it out, for
    /// [`SuiteConfig::validate`] to report the file's error.
    fn operator_of_its_file<C: Catalog>(
        &mut self,
        catalog: &C,
        origin: &Path,
        readings: &Readings,
    ) {
        if let ([file], None, true) = (
            self.operator_files.as_slice(),
            &self.population,
            self.operator.is_empty(),
        ) && catalog.domain(&self.scenario).is_some()
        {
            let base = origin.parent().unwrap_or(Path::new("."));
            if let Ok((name, _)) = catalog.load_operator(&self.scenario, &base.join(file), readings)
            {
                self.operator = name;
            }
        }
    }

    /// Why an experiment that leaves `operator` out cannot run (it has no operator files
    /// and no population to choose it by), and what to write: a name among the scenario's
    /// `builtins`, `random`, or an operator file.
    pub(crate) fn operator_left_out(&self, builtins: &[String]) -> String {
        let own = "`operator_files: [\"FILE.ron\"]` to run an operator of your own on every trial";
        let choose = "is left out, and the experiment has no `operator_files` or `population` to choose it by";
        if builtins.is_empty() {
            format!(
                "{choose}: write {own} ({} has no built-in operators)",
                self.scenario
            )
        } else {
            format!(
                "{choose}: write `operator: \"NAME\"` with NAME one of {}'s built-in operators ({}), `operator: \"{RANDOM_OPERATOR}\"` to draw one of them per trial, or {own}",
                self.scenario,
                builtins.join(", ")
            )
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
    /// `origin`); for a population, its members alone (drawn from the family, or the
    /// built-in operators it names, then its operator files).
    pub fn operators<C: Catalog>(
        &self,
        catalog: &C,
        origin: &Path,
        readings: &Readings,
    ) -> Result<Vec<(String, OperatorOf<C>)>, SuiteError> {
        let base = origin.parent().unwrap_or(Path::new("."));
        let builtins = catalog.operators(&self.scenario, readings);
        let mut operators = match &self.population {
            None => builtins,
            Some(Population {
                family: Some(family),
                ..
            }) => catalog.family(&self.scenario, family, readings)?,
            Some(_) => self.builtin_members(builtins).map_err(|(k, problem)| {
                invalid(origin, format!("builtin_operators[{k}]"), problem)
            })?,
        };
        for file in &self.operator_files {
            operators.push(catalog.load_operator(&self.scenario, &base.join(file), readings)?);
        }
        Ok(operators)
    }

    /// The scenario's built-in operators `builtin_operators` names, taken out of
    /// `builtins` (all of them) in the order named; else the place of the first name that
    /// is unknown or named twice, and why, with the known names.
    pub(crate) fn builtin_members<O>(
        &self,
        mut builtins: Vec<(String, O)>,
    ) -> Result<Vec<(String, O)>, (usize, String)> {
        let known: Vec<String> = builtins.iter().map(|(name, _)| name.clone()).collect();
        let mut members = Vec::with_capacity(self.builtin_operators.len());
        for (k, name) in self.builtin_operators.iter().enumerate() {
            match builtins.iter().position(|(n, _)| n == name) {
                Some(i) => members.push(builtins.swap_remove(i)),
                None if self.builtin_operators[..k].contains(name) => {
                    return Err((k, format!("`{name}` is named twice")));
                }
                None => {
                    return Err((
                        k,
                        format!(
                            "unknown operator `{name}` for {} (known: {})",
                            self.scenario,
                            known.join(", ")
                        ),
                    ));
                }
            }
        }
        Ok(members)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_arm_preferring_competent_behaviors_may_start_from_the_memory_s_guess() {
        #[derive(Deserialize)]
        struct Arms {
            #[serde(deserialize_with = "arm_names")]
            arms: Vec<ArmName>,
        }
        let read = |text: &str| ron::from_str::<Arms>(text).map(|a| a.arms);
        assert_eq!(
            read(r#"(arms: ["uniform", (name: "case-based+competent", initial: learned), (name: "uniform+competent")])"#).unwrap(),
            ["uniform", "case-based+learned-start+competent", "uniform+competent"]
        );
        let twice =
            read(r#"(arms: [(name: "case-based+learned-start+competent", initial: learned)])"#)
                .unwrap_err()
                .to_string();
        assert!(
            twice.contains("already names how its episodes start; write the arm `case-based+competent` and set `initial`"),
            "{twice}"
        );
    }
    use crate::UgvCatalog;
    use crate::catalog::resolve_readings;
    use crate::ugv::{PATROL_WEIGHTS, THREE_AND_ONE};
    use trust::{Retention, RetrieverKind, TimeUnit};

    #[test]
    fn an_experiment_s_field_at_the_top_says_where_it_belongs() {
        let err = SuiteConfig::from_ron(
            &UgvCatalog,
            "(seed: 1, operator_files: [\"night.ron\"], experiments: [])",
            Path::new("suite.ron"),
        )
        .unwrap_err()
        .to_string();
        assert!(
            err.starts_with(
                "suite.ron:1:25: Unexpected field named `operator_files` in `SuiteConfig`, expected one of `seed`, "
            ),
            "{err}"
        );
        assert!(
            err.contains(
                "instead; `operator_files` belongs to an experiment: `experiments: [(scenario: ..., operator_files: ...)]`\n1 | (seed"
            ),
            "{err}"
        );
        // A field that belongs nowhere gets ron's list alone.
        let err = SuiteConfig::from_ron(&UgvCatalog, "(sede: 1)", Path::new("suite.ron"))
            .unwrap_err()
            .to_string();
        assert!(!err.contains("belongs"), "{err}");
    }

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
            AdapterConfig {
                retriever: RetrieverKind::InvertedIndex,
                ..AdapterConfig::default()
            }
        );
        // The default `reproduce` keeps the nine arms its reports have always had; the
        // built-in arms after them (`hedged`, `case-based+hedged`) run in the benchmark and
        // ladder suites.
        assert_eq!(
            config.arms,
            [
                "random-walk",
                "case-based",
                "uniform",
                "cause-aware",
                "model-based",
                "conditioned",
                "case-based+cause-aware",
                "case-based+model-based",
                "case-based+conditioned",
            ]
        );
    }

    #[test]
    fn the_patrol_weight_reading_is_a_config_value() {
        let spec = ExperimentSpec {
            scenario: "patrol".into(),
            operator: RANDOM_OPERATOR.into(),
            operator_files: Vec::new(),
            builtin_operators: Vec::new(),
            population: None,
            feedback: None,
            goal_changes: None,
            contexts: None,
            stated: None,
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
    fn the_config_round_trips() {
        let config = SuiteConfig::embedded(&UgvCatalog).unwrap();
        let back =
            SuiteConfig::from_ron(&UgvCatalog, &config.to_ron(), Path::new("x.ron")).unwrap();
        assert_eq!(back, config);
        // A suite that is not a benchmark writes no `benchmark` (its config.ron stays as
        // it was); one that is writes it and reads it back.
        assert!(!config.benchmark && !config.to_ron().contains("benchmark"));
        let benchmark = SuiteConfig {
            benchmark: true,
            ..config
        };
        let ron = benchmark.to_ron();
        assert!(ron.contains("benchmark: true"), "{ron}");
        assert_eq!(
            SuiteConfig::from_ron(&UgvCatalog, &ron, Path::new("x.ron")).unwrap(),
            benchmark
        );
    }

    #[test]
    fn the_contexts_suite_runs_each_case_reusing_arm_beside_its_blind_twin() {
        let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("domains/experiments/contexts.ron");
        let suite = SuiteConfig::load(&UgvCatalog, &file).unwrap();
        assert!(suite.experiments.iter().all(|e| e.contexts.is_some()));
        let sighted: Vec<&ArmName> = suite
            .arms
            .iter()
            .filter(|a| a.base().starts_with("case-based") && !a.options().context_blind)
            .collect();
        assert_eq!(sighted.len(), 4);
        for arm in sighted {
            let twin = arm.with_options(NameOptions {
                context_blind: true,
                ..arm.options()
            });
            assert!(suite.arms.contains(&twin), "{twin}");
        }
    }

    #[test]
    fn the_learned_start_suite_pairs_each_arm_with_its_learned_start() {
        let file =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("domains/experiments/learned-start.ron");
        let suite = SuiteConfig::load(&UgvCatalog, &file).unwrap();
        assert_eq!(suite.experiments.len(), 7 + 2 * 5);
        for pair in suite.arms.chunks(2) {
            assert_eq!(pair[1].as_str(), format!("{}+learned-start", pair[0]));
        }
    }
}
