//! The domain to serve: a behavior space, the causes outcomes may carry, the adapter
//! configuration and the parts it is built from.
//!
//! Either a domain the tool's catalog builds (for `trustcbr`, `movement` and `patrol`: the
//! paper's spaces and the UGV causes, with the paper's adapter defaults) or a RON file
//! declaring a space and its causes, and optionally the adapter config, without writing
//! Rust:
//!
//! ```ron
//! (
//!     space: (components: [
//!         (name: "speed", unit: "m/s", values: Numeric(min: 0.5, step: 0.5, count: 20)),
//!         (name: "planner", values: Categorical(labels: ["astar", "rrt"])),
//!     ]),
//!     causes: [(name: "too-slow"), (name: "dropped-item", default_weight: 1.0)],
//!     adapter: (thresholds: (trustworthy: 3.0, untrustworthy: -3.0), lambda: 0.95),
//! )
//! ```
//!
//! A file may also declare the robot's context variables (`contexts: [(name: "cargo",
//! values: ["normal", "hazardous"])]`, the first value the default, with an optional
//! `similarity` table per variable): `begin` and `context` requests then name a context
//! among them, and cases are matched by it ([`cbr_core::context`]); none by default. And
//! the names an operator may state preferences in up front (`statements: ["hurry",
//! "avoid-bumps"]`): a `begin` request's `preferences` may then say of each whether the
//! operator minds it ([`cbr_core::statement`]); none by default.
//!
//! `causes` is required: the outcome reports of `serve` may carry exactly these causes
//! (an empty list: outcomes carry none). A declared default weight is informational
//! here, since every outcome report states its weight. Every field is checked while it is
//! read, so an error names the file, the line:column of the offending value, and the
//! field, and shows the line.
//!
//! The adapter's search strategy and retriever are built through the definition
//! ([`DomainDefinition::build_searcher`], [`DomainDefinition::memory`]): from the kinds
//! the adapter config names, or from a user's own factories
//! ([`DomainDefinition::with_searcher`], [`DomainDefinition::with_retriever`]), so every
//! session of a server gets a fresh searcher of the same making:
//!
//! ```
//! use service::DomainDefinition;
//! use std::path::Path;
//! let file = r#"(
//!     space: (components: [(name: "speed", unit: "m/s", values: Numeric(min: 0.5, step: 0.5, count: 4))]),
//!     causes: [(name: "too-slow")],
//! )"#;
//! let domain = DomainDefinition::from_ron(file, Path::new("robot.ron"))
//!     .unwrap()
//!     .with_searcher(|_space| Box::new(trust::search::Uniform::new()))
//!     .with_retriever(|measure| trust::RetrieverKind::InvertedIndex.build_measure(measure));
//! assert_eq!(domain.build_searcher().name(), "uniform");
//! ```

use cbr_core::{BehaviorSpace, ContextSpace};
use files::{FileError, RonError, parse_ron, read_text};
use serde::Deserialize;
use std::fmt;
use std::path::Path;
use std::sync::Arc;
use trust::ChangeDetector;
use trust::search::SearchKind;
use trust::search::TrustSearcher;
use trust::{
    AdapterConfig, Cause, ConfigError, DeclaredCause, Hint, Observations, Retention, RetrieverKind,
    SetSimilarity, Thresholds, TimeUnit, TrustCaseBase, TrustMemory, TrustRetriever, find_declared,
};
use trust::{
    CompetenceJudge, CompetencePart, CompetenceRecord, CompetenceStandard, Predictor,
    RetrieverFactory, SearcherFactory,
};

/// How a mission session's robot judges its own competence ([`trust::competence`]): the
/// parts it judges, what its models predict of a behavior, and the standard it holds itself
/// to.
#[derive(Clone)]
struct JudgedCompetence {
    /// An empty record of the parts over the domain's observations.
    record: CompetenceRecord,
    predict: Predictor<'static>,
    standard: CompetenceStandard,
}

/// A domain ready to serve.
#[derive(Clone)]
pub struct DomainDefinition {
    /// How the domain was named (a scenario name or the file path).
    pub name: String,
    /// The behavior space.
    pub space: Arc<BehaviorSpace>,
    /// The causes an outcome report's stated reason may name.
    pub causes: Vec<DeclaredCause>,
    /// What the robot perceives: the names an outcome report's `observed` may list, in
    /// the order of their bits (empty unless declared).
    pub observations: Vec<Cause>,
    /// Which observations hint at which causes, for explanations (none unless declared).
    pub hints: Vec<Hint>,
    /// The context variables a request may set (none unless declared).
    pub contexts: Arc<ContextSpace>,
    /// The names a `begin` request's `preferences` may state (none unless declared).
    pub statements: Vec<String>,
    /// The adapter configuration (the paper's defaults unless the file sets it).
    pub adapter: AdapterConfig,
    /// Whether sessions keep listening after an episode settles (mission mode:
    /// [`DomainDefinition::in_mission_mode`]).
    mission: bool,
    /// How the robot judges its own competence in mission mode; `None`: it does not.
    competence: Option<JudgedCompetence>,
    /// Trusted behaviors an episode passes over for being surely not competent.
    competent_passes: u32,
    /// The change detector of mission sessions; `None`: the thresholds alone.
    change_detector: Option<ChangeDetector>,
    /// A user's search strategy; `None`: the kind `adapter.search` names.
    searcher: Option<SearcherFactory>,
    /// A user's retriever; `None`: the kind `adapter.retriever` names.
    retriever: Option<RetrieverFactory>,
}

impl fmt::Debug for DomainDefinition {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("DomainDefinition")
            .field("name", &self.name)
            .field("space", &self.space)
            .field("causes", &self.causes)
            .field("observations", &self.observations)
            .field("hints", &self.hints)
            .field("contexts", &self.contexts)
            .field("statements", &self.statements)
            .field("adapter", &self.adapter)
            .field("mission", &self.mission)
            .field("judges_competence", &self.competence.is_some())
            .field("competent_passes", &self.competent_passes)
            .field("change_detector", &self.change_detector)
            .field("own_searcher", &self.searcher.is_some())
            .field("own_retriever", &self.retriever.is_some())
            .finish()
    }
}

/// The layout of a domain file.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DomainFile {
    space: BehaviorSpace,
    #[serde(deserialize_with = "distinct_causes")]
    causes: Vec<DeclaredCause>,
    #[serde(default, deserialize_with = "distinct_observations")]
    observations: Vec<Cause>,
    #[serde(default)]
    hints: Vec<Hint>,
    #[serde(default, deserialize_with = "contexts_named_as_causes")]
    contexts: ContextSpace,
    #[serde(default, deserialize_with = "distinct_statements")]
    statements: Vec<String>,
    #[serde(default)]
    adapter: AdapterSection,
}

/// A domain file's `adapter`: the fields of an [`AdapterConfig`], and `mode`, which is
/// deprecated: `mode: mission` serves the domain in mission mode, as `serve --mission`
/// does (docs/protocol.md#mission-mode); `episode` is the default.
#[derive(Deserialize)]
#[serde(deny_unknown_fields, default)]
struct AdapterSection {
    thresholds: Thresholds,
    #[serde(deserialize_with = "trust::evaluated::deserialize_lambda")]
    lambda: f64,
    reuse_cases: bool,
    retriever: RetrieverKind,
    search: SearchKind,
    retention: Retention,
    time_unit: TimeUnit,
    mode: Mode,
}

/// The deprecated `mode` of a domain file's `adapter`.
#[derive(Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
enum Mode {
    /// The paper's episodes.
    #[default]
    Episode,
    /// Mission mode.
    Mission,
}

impl Default for AdapterSection {
    fn default() -> Self {
        let AdapterConfig {
            thresholds,
            lambda,
            reuse_cases,
            retriever,
            search,
            retention,
            time_unit,
        } = AdapterConfig::default();
        Self {
            thresholds,
            lambda,
            reuse_cases,
            retriever,
            search,
            retention,
            time_unit,
            mode: Mode::Episode,
        }
    }
}

impl AdapterSection {
    /// The adapter config, and whether the file asks for mission mode.
    fn split(self) -> (AdapterConfig, bool) {
        let Self {
            thresholds,
            lambda,
            reuse_cases,
            retriever,
            search,
            retention,
            time_unit,
            mode,
        } = self;
        let config = AdapterConfig {
            thresholds,
            lambda,
            reuse_cases,
            retriever,
            search,
            retention,
            time_unit,
        };
        (config, mode == Mode::Mission)
    }
}

/// The declared observations, each once, at most [`Observations::CAPACITY`].
fn distinct_observations<'de, D: serde::Deserializer<'de>>(
    deserializer: D,
) -> Result<Vec<Cause>, D::Error> {
    let observations = Vec::<Cause>::deserialize(deserializer)?;
    if observations.len() > Observations::CAPACITY {
        return Err(serde::de::Error::custom(format_args!(
            "field `observations`: at most {} observations, got {}",
            Observations::CAPACITY,
            observations.len()
        )));
    }
    for (i, name) in observations.iter().enumerate() {
        if observations[..i].contains(name) {
            return Err(serde::de::Error::custom(format_args!(
                "field `observations`: observation `{name}` is declared twice"
            )));
        }
    }
    Ok(observations)
}

/// The statement names, each once and not empty.
fn distinct_statements<'de, D: serde::Deserializer<'de>>(
    deserializer: D,
) -> Result<Vec<String>, D::Error> {
    let statements = Vec::<String>::deserialize(deserializer)?;
    for (i, name) in statements.iter().enumerate() {
        named_as_causes("field `statements`: statement", name)?;
        if statements[..i].contains(name) {
            return Err(serde::de::Error::custom(format_args!(
                "field `statements`: statement `{name}` is declared twice"
            )));
        }
    }
    Ok(statements)
}

/// The context variables, their names and their values each named as causes are
/// ([`trust::cause::CAUSE_RULE`]): they become words of requests, reports and file names.
fn contexts_named_as_causes<'de, D: serde::Deserializer<'de>>(
    deserializer: D,
) -> Result<ContextSpace, D::Error> {
    let contexts = ContextSpace::deserialize(deserializer)?;
    for variable in contexts.variables() {
        named_as_causes("field `contexts`: context variable", &variable.name)?;
        let value = format!("field `contexts`: a value of `{}`", variable.name);
        for name in &variable.values {
            named_as_causes(&value, name)?;
        }
    }
    Ok(contexts)
}

/// Whether `name` (`what` says what it names) follows the naming rule of causes.
fn named_as_causes<E: serde::de::Error>(what: &str, name: &str) -> Result<(), E> {
    match Cause::new(name) {
        Ok(_) => Ok(()),
        Err(_) => Err(E::custom(format_args!(
            "{what} `{}` breaks the naming rule of causes: {}",
            name.escape_debug(),
            trust::cause::CAUSE_RULE
        ))),
    }
}

/// The declared causes, each once.
fn distinct_causes<'de, D: serde::Deserializer<'de>>(
    deserializer: D,
) -> Result<Vec<DeclaredCause>, D::Error> {
    let causes = Vec::<DeclaredCause>::deserialize(deserializer)?;
    for (i, declared) in causes.iter().enumerate() {
        if causes[..i].iter().any(|d| d.name == declared.name) {
            return Err(serde::de::Error::custom(format_args!(
                "field `causes`: cause `{}` is declared twice",
                declared.name
            )));
        }
    }
    Ok(causes)
}

/// Why a domain could not be loaded.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DomainError {
    /// The name is neither a built-in domain nor an existing file.
    #[error("`{name}` is neither a built-in domain ({known}) nor an existing file")]
    Unknown {
        /// The name given.
        name: String,
        /// The built-in domains, comma-separated.
        known: String,
    },
    /// The file could not be read.
    #[error(transparent)]
    Io(#[from] FileError),
    /// The file is not a valid domain.
    #[error(transparent)]
    Parse(#[from] RonError),
    /// A hint names an undeclared observation or cause.
    #[error("{0}")]
    Hint(String),
    /// The robot's competence cannot be judged as asked.
    #[error("{0}")]
    Competence(String),
}

impl DomainDefinition {
    /// A domain named `name` over `space` whose outcomes may carry `causes`, served with
    /// `adapter` (its search strategy and retriever are the kinds it names).
    pub fn new(
        name: impl Into<String>,
        space: Arc<BehaviorSpace>,
        causes: Vec<DeclaredCause>,
        adapter: AdapterConfig,
    ) -> Self {
        Self {
            name: name.into(),
            space,
            causes,
            observations: Vec::new(),
            hints: Vec::new(),
            contexts: Arc::new(ContextSpace::NONE),
            statements: Vec::new(),
            adapter,
            mission: false,
            competence: None,
            competent_passes: 0,
            change_detector: None,
            searcher: None,
            retriever: None,
        }
    }

    /// The same domain whose robot perceives `observations` (names an outcome report's
    /// `observed` may list; bit `i` is the `i`-th).
    #[must_use]
    pub fn with_observations(self, observations: Vec<Cause>) -> Self {
        Self {
            observations,
            ..self
        }
    }

    /// The same domain whose robot knows the context variables of `contexts`.
    #[must_use]
    pub fn with_contexts(self, contexts: ContextSpace) -> Self {
        Self {
            contexts: Arc::new(contexts),
            ..self
        }
    }

    /// The same domain whose operators may state preferences in `statements` up front.
    #[must_use]
    pub fn with_statements(self, statements: Vec<String>) -> Self {
        Self { statements, ..self }
    }

    /// The same domain served in mission mode ([`trust::mission_mode`]): outcomes keep coming
    /// after an episode settles (`serve --mission`, docs/protocol.md#mission-mode).
    #[must_use]
    pub fn in_mission_mode(mut self) -> Self {
        self.mission = true;
        self
    }

    /// Whether the domain is served in mission mode.
    pub fn mission(&self) -> bool {
        self.mission
    }

    /// The same domain whose robot judges its own competence in mission mode
    /// ([`trust::competence`], `serve --mission --competence`): it records every command
    /// for `parts` (each seen part one of the domain's observations: call
    /// [`DomainDefinition::with_observations`] first), `predict` tells what its models
    /// expect of a behavior, and a session raises an `overtrust` alert once per settled
    /// behavior its operator trusts while it is surely short of `standard`. Refused: no
    /// part, a seen part that is not an observation, a bound that is not a chance.
    pub fn judging_competence(
        self,
        parts: Vec<CompetencePart>,
        predict: Predictor<'static>,
        standard: CompetenceStandard,
    ) -> Result<Self, DomainError> {
        if parts.is_empty() {
            return Err(DomainError::Competence(format!(
                "domain `{}` declares no competence part, so its robot cannot judge its own competence",
                self.name
            )));
        }
        standard
            .validate()
            .map_err(|e| DomainError::Competence(e.to_string()))?;
        let record = CompetenceRecord::new(&parts, &self.observations)
            .map_err(|e| DomainError::Competence(e.to_string()))?;
        Ok(Self {
            competence: Some(JudgedCompetence {
                record,
                predict,
                standard,
            }),
            ..self
        })
    }

    /// Whether the robot judges its own competence ([`DomainDefinition::judging_competence`]).
    pub fn judges_competence(&self) -> bool {
        self.competence.is_some()
    }

    /// The same domain whose mission sessions prefer behaviors the robot judges competent
    /// (`serve --arm NAME+competent`): an episode passes over up to `passes` behaviors its
    /// operator trusts while the robot is sure they fall short, and searches on
    /// ([`trust::MissionAdaptation::preferring_competent`]). It takes effect where the
    /// robot judges its competence, in mission mode.
    #[must_use]
    pub fn preferring_competent(self, passes: u32) -> Self {
        Self {
            competent_passes: passes,
            ..self
        }
    }

    /// The same domain whose mission sessions watch a settled behavior with `detector`
    /// beside the thresholds (`serve --mission --detect-changes`,
    /// [`trust::MissionAdaptation::detecting_changes`]). It takes effect in mission mode.
    #[must_use]
    pub fn detecting_changes(self, detector: ChangeDetector) -> Self {
        Self {
            change_detector: Some(detector),
            ..self
        }
    }

    /// The change detector of mission sessions ([`DomainDefinition::detecting_changes`]).
    pub fn change_detector(&self) -> Option<ChangeDetector> {
        self.change_detector
    }

    /// Trusted behaviors an episode passes over ([`DomainDefinition::preferring_competent`]).
    pub fn competent_passes(&self) -> u32 {
        self.competent_passes
    }

    /// A fresh judge of the robot's competence for one session, if it judges it.
    pub fn competence_judge(&self) -> Option<CompetenceJudge<'static>> {
        self.competence
            .as_ref()
            .map(|c| CompetenceJudge::new(c.record.clone(), c.predict.clone(), c.standard.clone()))
    }

    /// The same domain whose explanations read `hints` (each names a declared observation
    /// and a declared cause; see [`trust::explain`]).
    pub fn with_hints(self, hints: Vec<Hint>) -> Result<Self, DomainError> {
        for hint in &hints {
            if !self.observations.contains(&hint.observation) {
                return Err(DomainError::Hint(format!(
                    "hint observation `{}` is not a declared observation (declared: {})",
                    hint.observation,
                    trust::cause::list_causes(&self.observations)
                )));
            }
            find_declared(&self.causes, hint.suggests)
                .map_err(|e| DomainError::Hint(format!("hint of `{}`: {e}", hint.observation)))?;
        }
        Ok(Self { hints, ..self })
    }

    /// The vocabulary an adapter explains itself in: the causes, observations and hints.
    pub fn vocabulary(&self) -> trust::Vocabulary {
        trust::Vocabulary {
            causes: self.causes.iter().map(|d| d.name).collect(),
            observations: self.observations.clone(),
            hints: self.hints.clone(),
        }
    }

    /// Resolves a built-in domain's name (`builtin` finds it; `known` lists them for the
    /// error), or else a path to a RON domain file.
    pub fn resolve(
        name: &str,
        known: &[String],
        builtin: impl FnOnce(&str) -> Option<Self>,
    ) -> Result<Self, DomainError> {
        if let Some(domain) = builtin(name) {
            return Ok(domain);
        }
        if !Path::new(name).exists() {
            return Err(DomainError::Unknown {
                name: name.to_owned(),
                known: known.join(", "),
            });
        }
        Self::load(Path::new(name))
    }

    /// The same domain searching with a user's strategy, built afresh for every session.
    pub fn with_searcher(
        mut self,
        searcher: impl Fn(&Arc<BehaviorSpace>) -> Box<TrustSearcher> + Send + Sync + 'static,
    ) -> Self {
        self.searcher = Some(Arc::new(searcher));
        self
    }

    /// The same domain retrieving cases with a user's retriever, ranking cases by the
    /// measure it is given (Algorithm 2 over the space at the adapter's `lambda`, weighing
    /// contexts as the domain declares: [`trust::SetSimilarity::of_domain`]).
    pub fn with_retriever(
        mut self,
        retriever: impl Fn(SetSimilarity) -> Box<TrustRetriever> + Send + Sync + 'static,
    ) -> Self {
        self.retriever = Some(Arc::new(retriever));
        self
    }

    /// The adapter served, as the `config` reply shows it: the adapter config, without
    /// the kinds a user's own searcher or retriever (an arm's, or a plug-in's) replace
    /// (they would be a claim about something not in use), and `"mode": "mission"` in
    /// mission mode.
    pub(crate) fn served_adapter(&self) -> serde_json::Value {
        let mut adapter = serde_json::json!(self.adapter);
        if let Some(fields) = adapter.as_object_mut() {
            if self.searcher.is_some() {
                fields.remove("search");
            }
            if self.retriever.is_some() {
                fields.remove("retriever");
            }
            if self.mission() {
                fields.insert("mode".into(), serde_json::json!("mission"));
            }
        }
        adapter
    }

    /// A fresh search strategy: the user's, or the kind the adapter config names.
    pub fn build_searcher(&self) -> Box<TrustSearcher> {
        match &self.searcher {
            Some(build) => build(&self.space),
            None => self.adapter.search.build(),
        }
    }

    /// A case memory over `cases` with the user's retriever or the kind the adapter config
    /// names, either ranking cases by Algorithm 2 weighing contexts by the domain's
    /// declared similarities.
    pub fn memory(&self, cases: TrustCaseBase) -> Result<TrustMemory, ConfigError> {
        let measure = SetSimilarity::of_domain(
            self.space.clone(),
            self.adapter.lambda,
            self.contexts.clone(),
        )?;
        let retriever = match &self.retriever {
            Some(build) => build(measure),
            None => self.adapter.retriever.build_measure(measure),
        };
        Ok(TrustMemory::new(cases, retriever))
    }

    /// Reads and checks a RON domain file.
    pub fn load(path: &Path) -> Result<Self, DomainError> {
        let text = read_text(path)?;
        Self::from_ron(&text, path)
    }

    /// Parses a domain from RON text; `origin` names the source in errors.
    pub fn from_ron(text: &str, origin: &Path) -> Result<Self, DomainError> {
        let file: DomainFile = parse_ron(text, origin)?;
        let (adapter, mission) = file.adapter.split();
        let domain = Self::new(
            origin.display().to_string(),
            Arc::new(file.space),
            file.causes,
            adapter,
        );
        let domain = if mission {
            domain.in_mission_mode()
        } else {
            domain
        };
        domain
            .with_observations(file.observations)
            .with_contexts(file.contexts)
            .with_statements(file.statements)
            .with_hints(file.hints)
            .map_err(|e| match e {
                DomainError::Hint(reason) => {
                    DomainError::Hint(format!("{}: field `hints`: {reason}", origin.display()))
                }
                other => other,
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const GOOD: &str = r#"(
    space: (components: [
        (name: "speed", unit: "m/s", values: Numeric(min: 0.5, step: 0.5, count: 20)),
        (name: "planner", values: Categorical(labels: ["astar", "rrt"])),
    ]),
    causes: [(name: "too-slow"), (name: "dropped-item", default_weight: 2.0)],
    adapter: (thresholds: (trustworthy: 3.0, untrustworthy: -3.0), lambda: 0.9),
)"#;

    /// The error for `GOOD` with `from` replaced by `to`: `(line, column, message, shown)`,
    /// after checking that the error as shown starts with `robot.ron:line:column: message`.
    fn error_after(from: &str, to: &str) -> (usize, usize, String, String) {
        assert!(GOOD.contains(from), "{from}");
        let text = GOOD.replacen(from, to, 1);
        let error = DomainDefinition::from_ron(&text, Path::new("robot.ron")).unwrap_err();
        let shown = error.to_string();
        let DomainError::Parse(RonError {
            line,
            column,
            message,
            ..
        }) = error
        else {
            panic!("expected a parse error, got {shown}");
        };
        assert!(
            shown.starts_with(&format!("robot.ron:{line}:{column}: {message}\n")),
            "{shown}"
        );
        (line, column, message, shown)
    }

    #[test]
    fn a_good_file_loads() {
        let d = DomainDefinition::from_ron(GOOD, Path::new("robot.ron")).unwrap();
        assert_eq!(d.space.size(), 40);
        assert_eq!(d.adapter.thresholds.trustworthy, 3.0);
        assert_eq!(d.adapter.lambda, 0.9);
        assert_eq!(
            d.causes,
            [
                DeclaredCause::new(trust::Cause::from_static("too-slow")),
                DeclaredCause::with_default_weight(trust::Cause::from_static("dropped-item"), 2.0)
                    .unwrap()
            ]
        );
        // The adapter section is optional: the paper's defaults.
        let without = GOOD.replace(
            "adapter: (thresholds: (trustworthy: 3.0, untrustworthy: -3.0), lambda: 0.9),",
            "",
        );
        let d = DomainDefinition::from_ron(&without, Path::new("robot.ron")).unwrap();
        assert_eq!(d.adapter, AdapterConfig::default());
    }

    #[test]
    fn statements_are_declared_once_each_and_named_as_causes() {
        let with = |names: &str| {
            GOOD.replacen(
                "adapter: (",
                &format!("statements: [{names}],\n    adapter: ("),
                1,
            )
        };
        let d = DomainDefinition::from_ron(
            &with(r#""hurry", "handle-gently""#),
            Path::new("robot.ron"),
        )
        .unwrap();
        assert_eq!(d.statements, ["hurry", "handle-gently"]);
        assert!(
            DomainDefinition::from_ron(GOOD, Path::new("robot.ron"))
                .unwrap()
                .statements
                .is_empty()
        );
        for (names, expected) in [
            (
                r#""hurry", "hurry""#,
                "field `statements`: statement `hurry` is declared twice",
            ),
            (
                r#"" ""#,
                "field `statements`: statement ` ` breaks the naming rule of causes: a cause is 1 to 32 bytes",
            ),
            (
                r#""Hurry Up!""#,
                "field `statements`: statement `Hurry Up!` breaks the naming rule of causes",
            ),
        ] {
            let error = DomainDefinition::from_ron(&with(names), Path::new("robot.ron"))
                .unwrap_err()
                .to_string();
            assert!(error.starts_with("robot.ron:"), "{error}");
            assert!(error.contains(expected), "{error}");
        }
    }

    #[test]
    fn causes_are_required_named_by_the_rule_and_declared_once() {
        let without = GOOD.replace(
            r#"causes: [(name: "too-slow"), (name: "dropped-item", default_weight: 2.0)],"#,
            "",
        );
        let err = DomainDefinition::from_ron(&without, Path::new("robot.ron"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("missing field `causes`"), "{err}");
        let empty = GOOD.replace(
            r#"(name: "too-slow"), (name: "dropped-item", default_weight: 2.0)"#,
            "",
        );
        let d = DomainDefinition::from_ron(&empty, Path::new("robot.ron")).unwrap();
        assert!(d.causes.is_empty());
        let (line, _, message, _) = error_after(r#""too-slow""#, r#""too slow""#);
        assert_eq!(line, 6);
        assert!(
            message.contains("cause `too slow` has ' ' at byte 3"),
            "{message}"
        );
        let (line, _, message, _) = error_after(r#""dropped-item""#, r#""too-slow""#);
        assert_eq!(line, 6);
        assert!(
            message.contains("field `causes`: cause `too-slow` is declared twice"),
            "{message}"
        );
        let (_, _, message, _) = error_after("default_weight: 2.0", "default_weight: -2.0");
        assert!(
            message.contains("`default_weight` must be a finite number >= 0, got -2"),
            "{message}"
        );
        let (_, _, message, _) = error_after("(name: \"too-slow\")", "(name: \"too-slow\", w: 1)");
        assert!(message.contains("w"), "{message}");
    }

    #[test]
    fn a_users_parts_are_built_through_the_definition() {
        let d = DomainDefinition::from_ron(GOOD, Path::new("robot.ron")).unwrap();
        assert_eq!(d.build_searcher().name(), "random-walk");
        assert_eq!(
            d.memory(TrustCaseBase::new()).unwrap().retriever_name(),
            "linear"
        );
        let d = d
            .with_searcher(|_| Box::new(trust::search::CauseAware::new()))
            .with_retriever(|measure| trust::RetrieverKind::ParallelScan.build_measure(measure));
        assert_eq!(d.build_searcher().name(), "cause-aware");
        assert_eq!(
            d.memory(TrustCaseBase::new()).unwrap().retriever_name(),
            "parallel_scan"
        );
        assert!(format!("{d:?}").contains("own_searcher: true"));
    }

    #[test]
    fn syntax_error_gives_file_line_column_and_excerpt() {
        let (line, column, _, shown) = error_after("step: 0.5", "step 0.5");
        assert_eq!(line, 3);
        assert!(column > 1);
        assert!(
            shown.starts_with(&format!("robot.ron:3:{column}: ")),
            "{shown}"
        );
        assert!(shown.contains("3 |         (name: \"speed\""), "{shown}");
    }

    #[test]
    fn unknown_field_is_named_where_it_is() {
        let (line, _, message, _) = error_after("unit: \"m/s\"", "unit: \"m/s\", colour: \"red\"");
        assert_eq!(line, 3);
        assert!(message.contains("colour"), "{message}");
        let (line, _, message, _) = error_after("lambda: 0.9", "lambda: 0.9, tau: 1");
        assert_eq!(line, 7);
        assert!(message.contains("tau"), "{message}");
    }

    #[test]
    fn negative_step_is_named_at_its_value() {
        let (line, column, message, _) = error_after("step: 0.5", "step: -0.5");
        assert_eq!(
            message,
            "field `step` must be a finite number > 0, got -0.5"
        );
        let text = GOOD.lines().nth(2).unwrap();
        // The column points just past the value.
        assert_eq!(line, 3);
        assert_eq!(
            column,
            text.find("step: 0.5").unwrap() + "step: -0.5".len() + 1
        );
    }

    #[test]
    fn lambda_outside_the_unit_interval_is_named() {
        for bad in ["0.0", "1.5", "-0.2"] {
            let (line, _, message, _) = error_after("lambda: 0.9", &format!("lambda: {bad}"));
            assert_eq!(line, 7);
            assert!(
                message.starts_with("field `lambda`: lambda must be in (0, 1]"),
                "{message}"
            );
        }
    }

    #[test]
    fn reversed_thresholds_are_named() {
        let (line, _, message, _) = error_after(
            "trustworthy: 3.0, untrustworthy: -3.0",
            "trustworthy: -3.0, untrustworthy: 3.0",
        );
        assert_eq!(line, 7);
        assert!(
            message.contains("untrustworthy < 0 < trustworthy"),
            "{message}"
        );
    }

    #[test]
    fn empty_components_are_named() {
        let (line, _, message, _) = error_after("count: 20", "count: 0");
        assert_eq!(line, 3);
        assert!(
            message.starts_with("field `count` must be at least 1"),
            "{message}"
        );
        let (line, _, message, _) = error_after(r#"labels: ["astar", "rrt"]"#, "labels: []");
        assert_eq!(line, 4);
        assert!(
            message.starts_with("field `labels` must name at least one value"),
            "{message}"
        );
        let (_, _, message, _) =
            error_after(r#"labels: ["astar", "rrt"]"#, r#"labels: ["rrt", "rrt"]"#);
        assert!(message.contains("label `rrt` appears twice"), "{message}");
    }

    #[test]
    fn a_grid_that_overflows_is_refused_at_load() {
        let (_, _, message, _) = error_after(
            "min: 0.5, step: 0.5, count: 20",
            "min: 1e308, step: 1e308, count: 20",
        );
        assert!(
            message.starts_with("component `speed`: the grid overflows: `min` 1e308"),
            "{message}"
        );
    }

    /// Every RON block of `docs/protocol.md` is a domain file that loads as written.
    #[test]
    fn the_documented_domain_file_loads() {
        let doc = include_str!("../../docs/protocol.md");
        let blocks: Vec<&str> = doc
            .split("```ron\n")
            .skip(1)
            .map(|rest| rest.split("```").next().unwrap())
            .collect();
        assert_eq!(blocks.len(), 1);
        let d = DomainDefinition::from_ron(blocks[0], Path::new("protocol.md")).unwrap();
        assert_eq!(d.adapter.retriever, trust::RetrieverKind::InvertedIndex);
        assert_eq!(d.space.size(), 8 * 10 * 3);
        let shift = d.contexts.context([("shift", "night")]).unwrap();
        assert_eq!(d.contexts.similarity(&shift, &Default::default()), 0.5);
    }

    /// The built-in movement domain.
    fn movement() -> DomainDefinition {
        let scenario = domains::Scenario::Movement;
        DomainDefinition::new(
            "movement",
            scenario.space(),
            scenario.causes().to_vec(),
            AdapterConfig::default(),
        )
    }

    /// Resolves `name` with `movement` as the only built-in domain.
    fn resolve(name: &str) -> Result<DomainDefinition, DomainError> {
        DomainDefinition::resolve(name, &["movement".to_owned()], |n| {
            (n == "movement").then(movement)
        })
    }

    #[test]
    fn builtin_names_and_missing_files() {
        assert_eq!(resolve("movement").unwrap().space.size(), 400);
        let err = resolve("/nonexistent/robot.ron").unwrap_err();
        assert_eq!(
            err.to_string(),
            "`/nonexistent/robot.ron` is neither a built-in domain (movement) nor an existing file"
        );
        let dir = tempfile::tempdir().unwrap();
        let err = resolve(dir.path().to_str().unwrap()).unwrap_err();
        assert!(matches!(err, DomainError::Io(_)), "{err}");
    }

    proptest! {
        #[test]
        fn arbitrary_text_never_panics(text in any::<String>()) {
            let _ = DomainDefinition::from_ron(&text, Path::new("x.ron"));
        }

        #[test]
        fn arbitrary_files_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..256)) {
            let dir = tempfile::tempdir().unwrap();
            let path = dir.path().join("x.ron");
            std::fs::write(&path, &bytes).unwrap();
            let _ = DomainDefinition::load(&path);
        }

        #[test]
        fn mangled_good_files_never_panic(cut in 0..GOOD.len(), insert in "[(),:\\[\\]a-z0-9. -]{0,4}") {
            let mut text = GOOD.to_owned();
            let cut = (0..=cut).rev().find(|&i| text.is_char_boundary(i)).unwrap_or(0);
            text.insert_str(cut, &insert);
            let _ = DomainDefinition::from_ron(&text, Path::new("x.ron"));
        }
    }
}
