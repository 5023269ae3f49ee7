//! Experiments: a suite (a RON file, RON text or a dict) run as `trustcbr run` runs it
//! ([`trustcbr::run::run_with_report`]), with the report folder when asked for, and arms
//! written in Python added to the catalog's through [`WithArms`]. Returns the report's
//! `trials.jsonl`, `summary.json` and the results table, as text.

use crate::arms::{FirstError, python_arm};
use crate::{anyhow_error, error};
use pyo3::prelude::*;
use std::num::{NonZeroU32, NonZeroUsize};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use trustcbr::catalog::{Catalog, domain_of};
use trustcbr::lab::BUILTIN_ARMS;
use trustcbr::lab::Domain;
use trustcbr::run::{RunSettings, run_with_report_checked};
use trustcbr::limits::TRIALS;
use trustcbr::suite::{EMBEDDED_ORIGIN, StartingCases, SuiteConfig, suite_table};
use trustcbr::{AddedArm, UgvCatalog, WithArms};

/// The embedded suite (the paper's seven experiments) as RON text, as `trustcbr config`
/// prints it.
#[pyfunction]
pub fn default_suite() -> String {
    UgvCatalog.default_suite().to_owned()
}

/// The built-in arms' names, in report order.
#[pyfunction]
pub fn builtin_arms() -> Vec<&'static str> {
    BUILTIN_ARMS.to_vec()
}

/// A suite in one of its three forms.
fn load_suite<C: Catalog>(
    catalog: &C,
    kind: &str,
    text: &str,
    origin: &Path,
) -> PyResult<SuiteConfig> {
    let loaded = match kind {
        "file" => SuiteConfig::load(catalog, origin),
        "ron" => SuiteConfig::from_ron(catalog, text, origin),
        "json" => SuiteConfig::from_json(catalog, text, origin),
        "embedded" => SuiteConfig::embedded(catalog),
        other => return Err(error(format_args!("unknown suite form `{other}`"))),
    };
    loaded.map_err(error)
}

/// Runs a suite and returns `(trials_jsonl, summary_json, table_md, config_json)`.
///
/// `kind` is `file` (`origin` is the path), `ron` or `json` (`text`, operator files
/// relative to `origin`) or `embedded`. `trials`, `seed`, `landscape_runs` and `arms`
/// override the config as `run`'s options do; `python_arms` are `(name, factory,
/// reuses_cases)` triples, named in `arms` like any other; with any of them the run is on
/// one worker thread. `out` writes the report folder as `trustcbr run --out` does.
#[pyfunction]
#[pyo3(signature = (kind, text, origin, *, out = None, trials = None, seed = None,
    landscape_runs = None, arms = None, threads = None, python_arms = Vec::new(),
    save_cases = None, cases = None))]
#[allow(clippy::too_many_arguments)]
pub fn run_suite(
    py: Python<'_>,
    kind: &str,
    text: &str,
    origin: PathBuf,
    out: Option<PathBuf>,
    trials: Option<u32>,
    seed: Option<u64>,
    landscape_runs: Option<u32>,
    arms: Option<Vec<String>>,
    threads: Option<usize>,
    python_arms: Vec<(String, Py<PyAny>, bool)>,
    save_cases: Option<PathBuf>,
    cases: Option<PathBuf>,
) -> PyResult<(String, String, String, String)> {
    let origin = if kind == "embedded" {
        PathBuf::from(EMBEDDED_ORIGIN)
    } else {
        origin
    };
    let errors = FirstError::default();
    let python = !python_arms.is_empty();
    let observations: Arc<Vec<_>> = Arc::new(
        UgvCatalog
            .scenarios()
            .iter()
            .filter_map(|scenario| domain_of(&UgvCatalog, scenario).ok())
            .map(|d| (d.space().clone(), d.observations().to_vec()))
            .collect(),
    );
    // Built for the suite's retriever when the suite asks the catalog for its arms.
    let added: Vec<AddedArm> = python_arms
        .into_iter()
        .map(|(name, factory, reuses)| -> AddedArm {
            let (factory, observations, errors) =
                (Arc::new(factory), observations.clone(), errors.clone());
            Arc::new(move |retriever| {
                python_arm(
                    name.clone(),
                    factory.clone(),
                    reuses,
                    observations.clone(),
                    retriever,
                    errors.clone(),
                )
            })
        })
        .collect();
    let catalog = WithArms {
        inner: UgvCatalog,
        arms: added,
    };
    let mut config = load_suite(&catalog, kind, text, &origin)?;
    if let Some(trials) = trials {
        TRIALS.check("trials", u64::from(trials)).map_err(error)?;
        config.trials = NonZeroU32::new(trials).expect("checked to be at least 1");
    }
    if let Some(seed) = seed {
        config.seed = seed;
    }
    if let Some(runs) = landscape_runs {
        config.landscape_runs = runs;
    }
    if let Some(arms) = arms {
        config.arms = arms;
    }
    let threads = match threads {
        Some(0) => return Err(error("threads: a number of worker threads from 1 to 256")),
        _ if python => NonZeroUsize::new(1),
        Some(n) => NonZeroUsize::new(n),
        None => None,
    };
    let settings = RunSettings {
        out,
        starting: cases.map(|dir| StartingCases { dir }),
        save_cases,
        threads,
        command_line: vec!["python".into(), "trustcbr.run".into()],
    };
    // A Python arm's exception stops the run before any report or case base is written.
    let failed = || {
        if errors.failed() {
            anyhow::bail!("a Python arm raised an exception")
        }
        Ok(())
    };
    let ran = py
        .detach(|| run_with_report_checked(&catalog, config, &origin, &settings, &|_| {}, &failed));
    if let Some(e) = errors.take() {
        return Err(e);
    }
    let ran = ran.map_err(|e| anyhow_error(&e))?;
    let config_json = serde_json::to_string(&ran.config).map_err(error)?;
    Ok((
        ran.trials_jsonl(),
        ran.summary().to_string(),
        suite_table(&ran.config, &ran.results),
        config_json,
    ))
}
