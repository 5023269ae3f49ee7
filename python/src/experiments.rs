//! Experiments: a suite (a RON file, RON text or a dict) run as `trustcbr run` runs it,
//! an experiment suite ([`trustcbr::run::run_with_report`]) or a mission suite
//! ([`trustcbr::run::run_missions_with_report`]), with the report folder when asked for,
//! and arms written in Python added to the catalog's through [`WithArms`]; a report
//! folder's config read back; and one trial of a report replayed (`trustcbr explain`).
//! Returns the report's records, summary and tables as text.

use crate::arms::{FirstError, python_arm};
use crate::calls::{Caller, Counts, Watch, run_watched};
use crate::{anyhow_error, error};
use pyo3::prelude::*;
use std::num::{NonZeroU32, NonZeroUsize};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use trustcbr::catalog::domain_of;
use trustcbr::cbr_core::BehaviorSpace;
use trustcbr::lab::{Arm, Domain, NameOptions};
use trustcbr::limits::{LANDSCAPE_RUNS, THREADS, TRIALS};
use trustcbr::mission_suite::{MissionSuiteConfig, is_mission_suite};
use trustcbr::run::{
    RunSettings, missions_per_plan, run_missions_with_report, run_with_report_checked,
};
use trustcbr::suite::{
    EMBEDDED_ORIGIN, StartingCases, SuiteConfig, suite_table, trace_report_trial,
};
use trustcbr::trust::{Cause, RetrieverKind};
use trustcbr::{AddedArm, Catalog, WithArms};

/// One registered search strategy as Python sees it (`trustcbr.strategies()`).
#[derive(IntoPyObject)]
pub struct StrategyRow {
    name: &'static str,
    description: &'static str,
    case_based: Option<&'static str>,
    learns_across_episodes: bool,
}

/// The strategies' registry (`trust::search::strategies`), the paper's first.
pub fn strategies() -> Vec<StrategyRow> {
    trustcbr::trust::search::strategies()
        .iter()
        .map(|s| StrategyRow {
            name: s.name,
            description: s.description,
            case_based: s.with_cases.map(|w| w.name),
            learns_across_episodes: s.learns_across_episodes(),
        })
        .collect()
}

/// The built-in arms' names and the catalog's own, in report order.
pub fn builtin_arms<C: Catalog>(catalog: &C) -> Vec<String> {
    let mut names: Vec<String> = trustcbr::lab::builtin_arm_names()
        .into_iter()
        .map(str::to_owned)
        .collect();
    for arm in catalog.arms(RetrieverKind::default()) {
        if !names.iter().any(|n| n == arm.name()) {
            names.push(arm.name().to_owned());
        }
    }
    names
}

/// What `trustcbr.run` asks for (a dict, read by key): the suite in one of its forms
/// (`kind` is `file`, with `origin` the path; `ron` or `json`, with `text`, operator files
/// relative to `origin`; or `embedded`), `run`'s overrides, the Python arms as `(name,
/// factory, reuses_cases)`, and the progress callback.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub struct RunRequest {
    kind: String,
    text: String,
    origin: PathBuf,
    out: Option<PathBuf>,
    trials: Option<u64>,
    seed: Option<u64>,
    landscape_runs: Option<u64>,
    arms: Option<Vec<String>>,
    threads: Option<u64>,
    python_arms: Vec<(String, Py<PyAny>, bool)>,
    save_cases: Option<PathBuf>,
    cases: Option<PathBuf>,
    progress: Option<Py<PyAny>>,
}

/// What a run returns (a dict): `kind` (`experiments` or `missions`), the records as
/// JSON lines (`trials.jsonl` or `missions.jsonl`), `summary.json`, the full table
/// (`table.md` or `missions.md`), the paper's two-arm table (experiments only) and the
/// config that ran, as JSON.
#[derive(IntoPyObject)]
pub struct RunOutput {
    kind: &'static str,
    records: String,
    summary: String,
    table: String,
    paper_table: String,
    config: String,
}

/// The observation names of every scenario's space, so an outcome's perceptions reach a
/// Python searcher by name.
type Observations = Arc<Vec<(Arc<BehaviorSpace>, Vec<Cause>)>>;

fn observations_of<C: Catalog>(catalog: &C) -> Observations {
    Arc::new(
        catalog
            .scenarios()
            .iter()
            .filter_map(|scenario| domain_of(catalog, scenario).ok())
            .map(|d| (d.space().clone(), d.observations().to_vec()))
            .collect(),
    )
}

/// A Python arm as the Python layer gives it: its name, its factory, whether it reuses
/// cases.
type PythonArmSpec = (String, Arc<Py<PyAny>>, bool);

/// The Python arms of a request, their factories shared.
fn python_arm_specs(arms: Vec<(String, Py<PyAny>, bool)>) -> Vec<PythonArmSpec> {
    arms.into_iter()
        .map(|(name, factory, reuses)| (name, Arc::new(factory), reuses))
        .collect()
}

/// The catalog with the Python arms added (built for the suite's retriever when the suite
/// asks the catalog for its arms).
fn with_python_arms<C: Catalog + Clone>(
    catalog: &C,
    python_arms: &[PythonArmSpec],
    errors: &FirstError,
    caller: &crate::calls::Caller,
) -> WithArms<C> {
    let observations = observations_of(catalog);
    let added: Vec<AddedArm> = python_arms
        .iter()
        .map(|(name, factory, reuses)| -> AddedArm {
            let (name, reuses) = (name.clone(), *reuses);
            let (factory, observations, errors, caller) = (
                factory.clone(),
                observations.clone(),
                errors.clone(),
                caller.clone(),
            );
            Arc::new(move |retriever| -> Arm {
                python_arm(
                    name.clone(),
                    factory.clone(),
                    reuses,
                    observations.clone(),
                    retriever,
                    errors.clone(),
                    caller.clone(),
                )
            })
        })
        .collect();
    WithArms {
        inner: catalog.clone(),
        arms: added,
    }
}

/// Refuses a Python arm named like one of the catalog's (it would hide it under the same
/// label) or left out of the arms run (it would silently not run).
fn check_python_arm_names<C: Catalog>(
    catalog: &C,
    names: &[String],
    arms_run: &[String],
) -> PyResult<()> {
    let builtin = builtin_arms(catalog);
    for name in names {
        if builtin.contains(name) {
            return Err(error(format_args!(
                "python_arms: `{name}` is the name of a built-in arm; give the Python arm a name of its own"
            )));
        }
        if !arms_run
            .iter()
            .any(|a| NameOptions::of_name(a).is_ok_and(|(base, _)| base == name.as_str()))
        {
            return Err(error(format_args!(
                "python_arms: `{name}` is not among the arms run ({}); name it in `arms` to run it",
                arms_run.join(", ")
            )));
        }
    }
    Ok(())
}

/// The suite's text and origin, and whether it is a mission suite.
fn suite_text(kind: &str, text: &str, origin: &Path) -> PyResult<(String, PathBuf, bool)> {
    let (text, origin) = match kind {
        "file" => (
            trustcbr::files::read_text(origin).map_err(error)?,
            origin.to_owned(),
        ),
        "ron" | "json" => (text.to_owned(), origin.to_owned()),
        "embedded" => (String::new(), PathBuf::from(EMBEDDED_ORIGIN)),
        other => return Err(error(format_args!("unknown suite form `{other}`"))),
    };
    let missions = match kind {
        "json" => serde_json::from_str::<serde_json::Value>(&text)
            .ok()
            .is_some_and(|v| v.get("missions").is_some()),
        "embedded" => false,
        _ => is_mission_suite(&text),
    };
    Ok((text, origin, missions))
}

/// An experiment suite in one of its forms, checked against `catalog`.
fn experiment_suite<C: Catalog>(
    catalog: &C,
    kind: &str,
    text: &str,
    origin: &Path,
) -> PyResult<SuiteConfig> {
    match kind {
        "json" => SuiteConfig::from_json(catalog, text, origin),
        "embedded" => SuiteConfig::embedded(catalog),
        _ => SuiteConfig::from_ron(catalog, text, origin),
    }
    .map_err(error)
}

/// A mission suite in one of its forms, parsed (checked when it runs).
fn mission_suite(kind: &str, text: &str, origin: &Path) -> PyResult<MissionSuiteConfig> {
    if kind == "json" {
        serde_json::from_str(text).map_err(|e| error(format_args!("{}: {e}", origin.display())))
    } else {
        trustcbr::files::parse_ron(text, origin).map_err(error)
    }
}

/// Removes the folder `dir` when a failed or stopped run created it and left it empty.
fn remove_if_created(dir: Option<&Path>, existed: bool) {
    if let Some(dir) = dir
        && !existed
    {
        let _ = std::fs::remove_dir(dir);
    }
}

/// Runs a suite as `trustcbr run` does ([`RunRequest`], [`RunOutput`]). With a Python arm
/// the run is on one worker thread; Ctrl-C stops it and writes nothing.
pub fn run_suite<C: Catalog + Clone>(
    py: Python<'_>,
    catalog: &C,
    request: RunRequest,
) -> PyResult<RunOutput> {
    let (text, origin, missions) = suite_text(&request.kind, &request.text, &request.origin)?;
    if let Some(threads) = request.threads {
        THREADS.check("threads", threads).map_err(error)?;
    }
    let python = !request.python_arms.is_empty();
    let threads = if python {
        NonZeroUsize::new(1)
    } else {
        request
            .threads
            .and_then(|n| NonZeroUsize::new(usize::try_from(n).ok()?))
    };
    let names: Vec<String> = request.python_arms.iter().map(|a| a.0.clone()).collect();
    let python_arms = python_arm_specs(request.python_arms);
    let errors = FirstError::default();
    // The suite is read against the catalog with the Python arms (it names them).
    let reading = with_python_arms(catalog, &python_arms, &errors, &Caller::Here);
    let out_existed = request.out.as_ref().is_some_and(|d| d.exists());
    let cases_existed = request.save_cases.as_ref().is_some_and(|d| d.exists());
    let output = if missions {
        let experiments_only = [
            ("trials", request.trials.is_some()),
            ("landscape_runs", request.landscape_runs.is_some()),
            ("cases", request.cases.is_some()),
            ("save_cases", request.save_cases.is_some()),
        ];
        if let Some((option, _)) = experiments_only.iter().find(|(_, given)| *given) {
            return Err(error(format_args!(
                "{option} applies to experiment suites; {} is a mission suite (its plans set `count` and `commands`)",
                origin.display()
            )));
        }
        let mut config = mission_suite(&request.kind, &text, &origin)?;
        if let Some(seed) = request.seed {
            config.seed = seed;
        }
        if let Some(arms) = request.arms {
            config.arms = arms;
        }
        check_python_arm_names(catalog, &names, &config.arms)?;
        let watch = Watch {
            callback: request.progress,
            counts: Counts::of(missions_per_plan(&config).iter().map(|(_, n)| n).sum()),
        };
        let counts = watch.counts.clone();
        let out = request.out.clone();
        let ran = run_watched(py, &watch, |caller| {
            let catalog = with_python_arms(catalog, &python_arms, &errors, &caller);
            run_missions_with_report(
                &catalog,
                config,
                &origin,
                out.as_deref(),
                threads,
                &|_| counts.tick(),
                &|| stop_before_writing(&errors),
            )
        });
        let ran = finish(ran, &errors, &request.out, out_existed)?;
        RunOutput {
            kind: "missions",
            records: ran.missions_jsonl(),
            summary: ran.summary().to_string(),
            table: ran.table_md(),
            paper_table: String::new(),
            config: serde_json::to_string(&ran.config).map_err(error)?,
        }
    } else {
        let mut config = experiment_suite(&reading, &request.kind, &text, &origin)?;
        if let Some(trials) = request.trials {
            TRIALS.check("trials", trials).map_err(error)?;
            config.trials = u32::try_from(trials)
                .ok()
                .and_then(NonZeroU32::new)
                .expect("checked to be 1 to the most trials");
        }
        if let Some(seed) = request.seed {
            config.seed = seed;
        }
        if let Some(runs) = request.landscape_runs {
            LANDSCAPE_RUNS
                .check("landscape_runs", runs)
                .map_err(error)?;
            config.landscape_runs = u32::try_from(runs).expect("checked to fit");
        }
        if let Some(arms) = request.arms {
            config.arms = arms;
        }
        check_python_arm_names(catalog, &names, &config.arms)?;
        let settings = RunSettings {
            out: request.out.clone(),
            starting: request.cases.map(|dir| StartingCases { dir }),
            save_cases: request.save_cases.clone(),
            threads,
            command_line: vec!["python".into(), "trustcbr.run".into()],
        };
        let per_experiment = config.arms.len() as u64 * u64::from(config.trials.get());
        let watch = Watch {
            callback: request.progress,
            counts: Counts::of(per_experiment * config.experiments.len() as u64),
        };
        let counts = watch.counts.clone();
        let ran = run_watched(py, &watch, |caller| {
            let catalog = with_python_arms(catalog, &python_arms, &errors, &caller);
            let tick = || {
                counts.tick();
                if counts.done.load(std::sync::atomic::Ordering::Relaxed)
                    >= counts.total.load(std::sync::atomic::Ordering::Relaxed)
                {
                    *counts.then.lock().unwrap_or_else(|p| p.into_inner()) =
                        Some("finishing the report's landscapes and limits");
                }
            };
            run_with_report_checked(&catalog, config, &origin, &settings, &|_| tick(), &|| {
                stop_before_writing(&errors)
            })
        });
        remove_if_created(request.save_cases.as_deref(), cases_existed);
        let ran = finish(ran, &errors, &request.out, out_existed)?;
        RunOutput {
            kind: "experiments",
            records: ran.trials_jsonl(),
            summary: ran.summary().to_string(),
            table: ran.table_md(),
            paper_table: suite_table(&ran.config, &ran.results),
            config: serde_json::to_string(&ran.config).map_err(error)?,
        }
    };
    Ok(output)
}

/// A Python arm's exception, or Ctrl-C, stops a run before any report or case base is
/// written.
fn stop_before_writing(errors: &FirstError) -> anyhow::Result<()> {
    if errors.failed() {
        anyhow::bail!("a Python arm raised an exception")
    }
    trustcbr::lab::interrupt::check()?;
    Ok(())
}

/// The result of a watched run: the Python arm's exception first, then the run's error
/// (a stop as `KeyboardInterrupt`); a report folder a failed run created is removed.
fn finish<T>(
    ran: PyResult<anyhow::Result<T>>,
    errors: &FirstError,
    out: &Option<PathBuf>,
    out_existed: bool,
) -> PyResult<T> {
    let failed = |e| {
        remove_if_created(out.as_deref(), out_existed);
        e
    };
    let ran = ran.map_err(failed)?;
    if let Some(e) = errors.take() {
        return Err(failed(e));
    }
    ran.map_err(|e| failed(anyhow_error(&e)))
}

/// A suite's config read back as JSON, without running it: a report folder's
/// `config.ron` (kind `file`) or a suite's text, an experiment or a mission suite. Arms
/// the catalog does not know (arms written in Python) are kept as written.
pub fn read_config<C: Catalog>(
    catalog: &C,
    kind: &str,
    text: &str,
    origin: &str,
) -> PyResult<String> {
    let (text, origin, missions) = suite_text(kind, text, Path::new(origin))?;
    if missions {
        let config = mission_suite(kind, &text, &origin)?;
        return serde_json::to_string(&config).map_err(error);
    }
    let mut config: SuiteConfig = if kind == "json" {
        serde_json::from_str(&text).map_err(error)?
    } else {
        trustcbr::files::parse_ron(&text, &origin).map_err(error)?
    };
    // An experiment's operator left out beside one file is named, as a run names it.
    config.choose_left_out_operators(catalog, &origin);
    serde_json::to_string(&config).map_err(error)
}

/// Replays one trial of a report folder (`trustcbr explain`); arms written in Python are
/// replayed when their factories are given in `python_arms`. Returns the story and the
/// trial's record as JSON.
pub fn explain<C: Catalog + Clone>(
    catalog: &C,
    report: &str,
    experiment: &str,
    arm: &str,
    trial: u32,
    cases: Option<&str>,
    python_arms: Vec<(String, Py<PyAny>, bool)>,
) -> PyResult<(String, String, Vec<String>)> {
    let errors = FirstError::default();
    let catalog = with_python_arms(
        catalog,
        &python_arm_specs(python_arms),
        &errors,
        &Caller::Here,
    );
    let starting = cases.map(|dir| StartingCases { dir: dir.into() });
    if let Some(dir) = &starting
        && !dir.dir.is_dir()
    {
        return Err(error(format_args!(
            "cases {}: no such folder",
            dir.dir.display()
        )));
    }
    let traced = trace_report_trial(
        &catalog,
        Path::new(report),
        starting.as_ref(),
        experiment,
        arm,
        trial,
    );
    if let Some(e) = errors.take() {
        return Err(e);
    }
    let replayed = traced.map_err(error)?;
    let record = serde_json::to_string(&replayed.timeline.record).map_err(error)?;
    let story = trustcbr::lab::report::timeline::story(&replayed.timeline, &replayed.space);
    Ok((story, record, replayed.warnings))
}
