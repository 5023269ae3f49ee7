//! The catalog of domains a command-line tool offers: the one door through which a task
//! plug-in reaches `run`, `reproduce`, `sweep`, `landscape`, `render`, `serve` and the
//! report.
//!
//! A [`Catalog`] names its scenarios, builds the [`Domain`] of each, finds operators by
//! name or loads them from a file, may draw populations of operators (from a family, or
//! from a prior as operator files), declares the domain's *readings* (choices the domain
//! leaves open, which a suite config may set and a sweep may vary) and embeds the suite
//! `reproduce` runs. The shipped tool is [`crate::cli::main`] over the UGV catalog
//! (`UgvCatalog`, the `ugv` feature); a user's crate gets the same tool for its own domains with
//!
//! ```no_run
//! use std::path::Path;
//! use std::process::ExitCode;
//! use std::sync::Arc;
//! use trustcbr::cbr_core::{Behavior, BehaviorSpace, NamedComponent};
//! use trustcbr::rand::{Rng, RngCore};
//! use trustcbr::trust::{Cause, DeclaredCause};
//! use trustcbr::lab::{Domain, Judgement};
//! use trustcbr::{Catalog, CatalogError, Readings};
//!
//! /// A lamp whose brightness an operator likes or not.
//! struct Lamp(Arc<BehaviorSpace>);
//!
//! impl Domain for Lamp {
//!     type Operator = f64; // the brightness the operator wants
//!     fn name(&self) -> &str {
//!         "lamp"
//!     }
//!     fn space(&self) -> &Arc<BehaviorSpace> {
//!         &self.0
//!     }
//!     fn causes(&self) -> &[DeclaredCause] {
//!         const GLARE: DeclaredCause =
//!             DeclaredCause { name: Cause::from_static("glare"), default_weight: None };
//!         &[GLARE]
//!     }
//!     fn run(&self, b: &Behavior, wanted: &f64, rng: &mut dyn RngCore) -> Judgement {
//!         let brightness = self.0.components()[0].real_value(b.get(0));
//!         if rng.random::<f64>() < 1.0 - (brightness - wanted).abs() {
//!             Judgement::completed(1.0, 1.0)
//!         } else {
//!             Judgement::interrupted(1.0, Cause::from_static("glare"), 1.0)
//!         }
//!     }
//! }
//!
//! struct LampCatalog;
//!
//! impl Catalog for LampCatalog {
//!     type Domain = Lamp;
//!     fn tool(&self) -> trustcbr::ToolInfo {
//!         trustcbr::tool_info!()
//!     }
//!     fn scenarios(&self) -> Vec<String> {
//!         vec!["lamp".into()]
//!     }
//!     fn domain(&self, scenario: &str) -> Option<Lamp> {
//!         let level = NamedComponent::numeric("brightness", "", 0.0, 0.1, 11).ok()?;
//!         (scenario == "lamp").then(|| Lamp(Arc::new(BehaviorSpace::new(vec![level]).unwrap())))
//!     }
//!     fn operators(&self, _: &str, _: &Readings) -> Vec<(String, f64)> {
//!         vec![("dim".into(), 0.2), ("bright".into(), 0.9)]
//!     }
//!     fn load_operator(&self, _: &str, path: &Path, _: &Readings)
//!         -> Result<(String, f64), CatalogError> {
//!         Err(CatalogError { path: Some(path.into()), reason: "lamps have no operator files".into() })
//!     }
//!     fn default_suite(&self) -> &str {
//!         r#"(seed: 1, trials: 100, arms: ["random-walk", "case-based"],
//!             experiments: [(scenario: "lamp", operator: "random")])"#
//!     }
//! }
//!
//! fn main() -> ExitCode {
//!     trustcbr::cli::main(LampCatalog)
//! }
//! ```

use cbr_core::Behavior;
use lab::{Arm, Domain, Instance, SimulatedOperator};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use trust::RetrieverKind;

/// The operator type of a catalog's domain.
pub type OperatorOf<C> = <<C as Catalog>::Domain as Domain>::Operator;

/// The chosen value of every reading a catalog declares, by reading name (a suite fills in
/// each reading's default).
pub type Readings = BTreeMap<String, String>;

/// A choice the domain leaves open (e.g. how the paper's patrol weights are scaled): a
/// name, its admissible values (the first is the default) and what it means.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Reading {
    /// The name a suite config uses (`readings: {"NAME": "VALUE"}`) and a sweep varies.
    pub name: String,
    /// The admissible values; the first is the default.
    pub values: Vec<String>,
    /// One line on what the reading changes.
    pub about: String,
}

/// Who the tool is: its name and version, shown by `--help`, `--version` and written into
/// every report's provenance.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ToolInfo {
    /// The tool's name (e.g. `trustcbr`).
    pub name: String,
    /// Its version.
    pub version: String,
    /// The commit it was built from, when known.
    pub git_commit: Option<String>,
    /// One line on what it does.
    pub about: String,
}

/// The [`ToolInfo`] of the crate that invokes it: its package name, version and
/// description, and the commit in `TRUSTCBR_GIT_COMMIT` when its build script sets that
/// variable (`cargo:rustc-env=TRUSTCBR_GIT_COMMIT=...`, as this crate's `build.rs` does).
#[macro_export]
macro_rules! tool_info {
    () => {
        $crate::ToolInfo {
            name: env!("CARGO_PKG_NAME").to_owned(),
            version: env!("CARGO_PKG_VERSION").to_owned(),
            git_commit: option_env!("TRUSTCBR_GIT_COMMIT").map(str::to_owned),
            about: env!("CARGO_PKG_DESCRIPTION").to_owned(),
        }
    };
}

/// An operator that could not be loaded: why, in the catalog's own error type, and the
/// file when the reason does not name it already.
#[derive(Debug, thiserror::Error)]
#[error("{}{reason}", path.as_ref().map(|p| format!("{}: ", p.display())).unwrap_or_default())]
pub struct CatalogError {
    /// The operator file, shown before the reason when given.
    pub path: Option<PathBuf>,
    /// Why it cannot be used.
    pub reason: Box<dyn std::error::Error + Send + Sync>,
}

/// An operator file's error as a catalog's: the error names its file already.
impl<E> From<lab::contract::operator_file::OperatorFileError<E>> for CatalogError
where
    E: std::error::Error + Send + Sync + 'static,
{
    fn from(error: lab::contract::operator_file::OperatorFileError<E>) -> Self {
        Self {
            path: None,
            reason: Box::new(error),
        }
    }
}

/// How a population is drawn from a domain's family of operators ([`Catalog::family`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Family {
    /// How much the members disagree, in `[0, 1]`: 0, they share one preference; 1, they
    /// sit at the family's opposite poles.
    pub conflict: f64,
    /// How many members.
    pub size: usize,
    /// The seed they are drawn with.
    pub seed: u64,
}

/// A member of a population drawn from a catalog's prior over operators
/// ([`Catalog::prior`]), as the operator file a reader opens and [`Catalog::load_operator`]
/// reads back.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OperatorFile {
    /// The member's name, a plain file name without its extension: the file is
    /// `NAME.ron`.
    pub name: String,
    /// The file's text, saying in a comment which prior, instance and seed it comes from.
    pub text: String,
}

/// The domains a tool offers, by scenario name. See the [module documentation](self).
pub trait Catalog: Send + Sync {
    /// The domain type every scenario builds (an enum when scenarios differ in type).
    type Domain: Domain + 'static;

    /// The tool's name, version and description: [`tool_info!`](crate::tool_info) gives
    /// the calling crate's.
    fn tool(&self) -> ToolInfo;

    /// The scenario names, in the order help and errors list them.
    fn scenarios(&self) -> Vec<String>;

    /// The domain of `scenario`, or `None` when the catalog does not know it.
    fn domain(&self, scenario: &str) -> Option<Self::Domain>;

    /// The built-in operators of `scenario`, by name, as `readings` read them. This and
    /// [`Catalog::load_operator`] are only asked about a scenario for which
    /// [`Catalog::domain`] gave a domain.
    fn operators(&self, scenario: &str, readings: &Readings) -> Vec<(String, OperatorOf<Self>)>;

    /// Loads an operator of `scenario` from a file (a suite's `operator_files`, or a file
    /// given where an operator name is expected), as `readings` read it; returns its name
    /// and the operator.
    fn load_operator(
        &self,
        scenario: &str,
        path: &Path,
        readings: &Readings,
    ) -> Result<(String, OperatorOf<Self>), CatalogError>;

    /// `family.size` operators of `scenario` drawn (with `family.seed`) from the domain's
    /// parametric family of operators, whose one parameter `family.conflict` in `[0, 1]`
    /// sets how much they disagree (0: they agree), as `readings` read them; for a suite's
    /// `population: (name: ..., family: (...))`. Default: the domain has no family.
    fn family(
        &self,
        scenario: &str,
        family: &Family,
        readings: &Readings,
    ) -> Result<Vec<(String, OperatorOf<Self>)>, CatalogError> {
        let _ = (family, readings);
        Err(CatalogError {
            path: None,
            reason: format!("scenario `{scenario}` has no family of operators to draw from").into(),
        })
    }

    /// The members of `instance` of the domain's prior over operators for `scenario`, as
    /// operator files (their weights as written, before any reading): operators no one
    /// designed, for `population` to write. `screened`: only members the domain's screen
    /// admits (whatever rule it has against members no behavior satisfies); false, the
    /// draws before any screen, to see what it removes. Default: the domain has no prior.
    fn prior(
        &self,
        scenario: &str,
        instance: &Instance,
        screened: bool,
    ) -> Result<Vec<OperatorFile>, CatalogError> {
        let _ = (instance, screened);
        Err(CatalogError {
            path: None,
            reason: format!("scenario `{scenario}` has no prior over operators to draw from")
                .into(),
        })
    }

    /// The readings the domain leaves open (default: none).
    fn readings(&self) -> Vec<Reading> {
        Vec::new()
    }

    /// The weight a completion carries for `operator`, when the operator has one: a suite
    /// refuses an experiment whose operators could never reach the trustworthy threshold
    /// within its `max_commands`. By default what the operator says
    /// ([`SimulatedOperator::completion_weight`]:
    /// its `weights.completed` for an operator with the standard fields); `None` skips
    /// that check.
    fn completion_weight(&self, operator: &OperatorOf<Self>) -> Option<f64> {
        operator.completion_weight()
    }

    /// Arms of the catalog's own (a user's searcher or retriever, through
    /// [`Arm::search_only`] and [`Arm::case_based`]), which configs and `--arms` name like
    /// the built-in ones; a name here hides a built-in arm of the same name. `retriever` is
    /// the suite's choice for case-reusing arms. Default: none.
    fn arms(&self, retriever: RetrieverKind) -> Vec<Arm> {
        let _ = retriever;
        Vec::new()
    }

    /// The suite config (RON) `reproduce` runs and `config` prints.
    fn default_suite(&self) -> &str;

    /// The stage a person watches `scenario`'s runs on, for `console` (default: none, the
    /// scenario's runs cannot be shown to a person).
    #[cfg(feature = "console")]
    fn stage(&self, scenario: &str) -> Option<std::sync::Arc<dyn console::Stage>> {
        let _ = scenario;
        None
    }

    /// One run of `behavior` under `operator` drawn as SVG, for `render` (default: the
    /// domain has no picture).
    fn render(
        &self,
        domain: &Self::Domain,
        behavior: &Behavior,
        operator: &OperatorOf<Self>,
        seed: u64,
    ) -> Option<String> {
        let _ = (domain, behavior, operator, seed);
        None
    }
}

/// An arm added to a catalog, built for the suite's retriever ([`Catalog::arms`]).
pub type AddedArm = std::sync::Arc<dyn Fn(RetrieverKind) -> Arm + Send + Sync>;

/// A catalog with arms added to its own ([`Catalog::arms`]): how arms built at run time
/// (a Python object's strategy, `python/`) enter the runner through the same door as a
/// plug-in's arms; every other question goes to `inner`. An added arm hides an arm of the
/// same name.
pub struct WithArms<C> {
    /// The catalog answering everything else.
    pub inner: C,
    /// The arms added.
    pub arms: Vec<AddedArm>,
}

impl<C: Catalog> Catalog for WithArms<C> {
    type Domain = C::Domain;

    fn tool(&self) -> ToolInfo {
        self.inner.tool()
    }

    fn scenarios(&self) -> Vec<String> {
        self.inner.scenarios()
    }

    fn domain(&self, scenario: &str) -> Option<Self::Domain> {
        self.inner.domain(scenario)
    }

    fn operators(&self, scenario: &str, readings: &Readings) -> Vec<(String, OperatorOf<Self>)> {
        self.inner.operators(scenario, readings)
    }

    fn load_operator(
        &self,
        scenario: &str,
        path: &Path,
        readings: &Readings,
    ) -> Result<(String, OperatorOf<Self>), CatalogError> {
        self.inner.load_operator(scenario, path, readings)
    }

    fn family(
        &self,
        scenario: &str,
        family: &Family,
        readings: &Readings,
    ) -> Result<Vec<(String, OperatorOf<Self>)>, CatalogError> {
        self.inner.family(scenario, family, readings)
    }

    fn prior(
        &self,
        scenario: &str,
        instance: &Instance,
        screened: bool,
    ) -> Result<Vec<OperatorFile>, CatalogError> {
        self.inner.prior(scenario, instance, screened)
    }

    fn readings(&self) -> Vec<Reading> {
        self.inner.readings()
    }

    fn completion_weight(&self, operator: &OperatorOf<Self>) -> Option<f64> {
        self.inner.completion_weight(operator)
    }

    fn arms(&self, retriever: RetrieverKind) -> Vec<Arm> {
        let mut arms: Vec<Arm> = self.arms.iter().map(|build| build(retriever)).collect();
        let inner: Vec<Arm> = self
            .inner
            .arms(retriever)
            .into_iter()
            .filter(|a| !arms.iter().any(|added| added.name() == a.name()))
            .collect();
        arms.extend(inner);
        arms
    }

    fn default_suite(&self) -> &str {
        self.inner.default_suite()
    }

    fn render(
        &self,
        domain: &Self::Domain,
        behavior: &Behavior,
        operator: &OperatorOf<Self>,
        seed: u64,
    ) -> Option<String> {
        self.inner.render(domain, behavior, operator, seed)
    }

    #[cfg(feature = "console")]
    fn stage(&self, scenario: &str) -> Option<std::sync::Arc<dyn console::Stage>> {
        self.inner.stage(scenario)
    }
}

/// An operator named on the command line: a built-in name of `scenario`, or else a file.
pub fn find_operator<C: Catalog>(
    catalog: &C,
    scenario: &str,
    name: &str,
    readings: &Readings,
) -> Result<(String, OperatorOf<C>), FindOperatorError> {
    if let Some(found) = catalog
        .operators(scenario, readings)
        .into_iter()
        .find(|(n, _)| n == name)
    {
        return Ok(found);
    }
    // Any existing path is the catalog's to read, so a FIFO or a folder gets its refusal.
    if Path::new(name).exists() {
        return Ok(catalog.load_operator(scenario, Path::new(name), readings)?);
    }
    let known: Vec<String> = catalog
        .operators(scenario, readings)
        .into_iter()
        .map(|(n, _)| n)
        .collect();
    Err(FindOperatorError::Unknown {
        name: name.to_owned(),
        scenario: scenario.to_owned(),
        known: known.join(", "),
    })
}

/// A scenario named on the command line or in a config that the catalog does not know.
#[derive(Debug, thiserror::Error)]
#[error("unknown scenario `{name}` (known: {known})")]
pub struct UnknownScenario {
    /// The name given.
    pub name: String,
    /// The catalog's scenarios, comma-separated.
    pub known: String,
}

/// The domain of `scenario`, or an error listing the catalog's scenarios.
pub fn domain_of<C: Catalog>(catalog: &C, scenario: &str) -> Result<C::Domain, UnknownScenario> {
    catalog.domain(scenario).ok_or_else(|| UnknownScenario {
        name: scenario.to_owned(),
        known: catalog.scenarios().join(", "),
    })
}

/// An operator that cannot be found.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FindOperatorError {
    /// Neither a built-in operator of the scenario nor a file.
    #[error("`{name}` is neither an operator of {scenario} ({known}) nor an operator file")]
    Unknown {
        /// The name given.
        name: String,
        /// The scenario.
        scenario: String,
        /// The scenario's built-in operators, comma-separated.
        known: String,
    },
    /// The file does not hold a usable operator.
    #[error(transparent)]
    File(#[from] CatalogError),
}

/// Every reading of `catalog` with its value: `chosen` where it names one, the default
/// otherwise. Errors name the reading or value and list what is allowed.
pub fn resolve_readings<C: Catalog>(
    catalog: &C,
    chosen: &BTreeMap<String, String>,
) -> Result<Readings, ReadingError> {
    let declared = catalog.readings();
    for (name, value) in chosen {
        let Some(reading) = declared.iter().find(|r| r.name == *name) else {
            return Err(ReadingError::UnknownReading {
                name: name.clone(),
                known: if declared.is_empty() {
                    "none".into()
                } else {
                    declared
                        .iter()
                        .map(|r| r.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                },
            });
        };
        if !reading.values.contains(value) {
            return Err(ReadingError::UnknownValue {
                name: name.clone(),
                value: value.clone(),
                known: reading.values.join(", "),
            });
        }
    }
    Ok(declared
        .into_iter()
        .map(|r| {
            let value = chosen
                .get(&r.name)
                .cloned()
                .unwrap_or_else(|| r.values[0].clone());
            (r.name, value)
        })
        .collect())
}

/// A reading or value the catalog does not declare.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ReadingError {
    /// No reading of that name.
    #[error("unknown reading `{name}` (known: {known})")]
    UnknownReading {
        /// The name given.
        name: String,
        /// The declared readings.
        known: String,
    },
    /// The reading has no such value.
    #[error("reading `{name}` has no value `{value}` (allowed: {known})")]
    UnknownValue {
        /// The reading.
        name: String,
        /// The value given.
        value: String,
        /// The admissible values.
        known: String,
    },
}
