//! Experiments: a suite (a RON file, RON text or a dict) run as `trustcbr run` runs it,
//! an experiment suite ([`trustcbr::run::run_with_report`]) or a mission suite
//! ([`trustcbr::run::run_missions_with_report`]), with the report folder when asked for,
//! and arms written in Python added to the catalog's through [`WithArms`]; a report
//! folder's config read back; and one trial of a report replayed (`trustcbr explain`).
//! Returns the report's records, summary and tables as text.

use crate::arms::{FirstError, PythonArmSpec, python_arm};
use crate::calls::{Caller, Counts, Watch, run_watched};
use crate::{anyhow_error, error};
use pyo3::prelude::*;
use std::num::{NonZeroU32, NonZeroUsize};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use trustcbr::catalog::domain_of;
use trustcbr::cbr_core::BehaviorSpace;
use trustcbr::config_file::from_json;
use trustcbr::lab::{Arm, ArmName, Domain};
use trustcbr::limits::{Bound, LANDSCAPE_RUNS, MISSION_COMMANDS, MISSIONS, THREADS, TRIALS};
use trustcbr::mission_suite::{MissionSuiteConfig, is_mission_suite};
use trustcbr::run::{
    MissionSettings, MissionsRan, Ran, RunSettings, missions_per_plan, run_missions_with_report,
    run_with_report_checked,
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
/// (`kind` is `file`, with `origin` the path; `ron` or `json`, with `text` and `origin` its
/// name, operator files relative to `base`, else to the working directory; or
/// `embedded`), the kind of suite the caller runs (`expect`: `experiments` for `run`,
/// `missions` for `run_missions`), `run`'s overrides (a mission suite's `count` and `commands` for every
/// plan), the Python arms as `(name, factory, reuses_cases)`, and the progress callback.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub struct RunRequest {
    kind: String,
    text: String,
    origin: PathBuf,
    base: Option<PathBuf>,
    expect: String,
    out: Option<PathBuf>,
    trials: Option<u64>,
    count: Option<u64>,
    commands: Option<u64>,
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
/// (`table.md` or `missions.md`), the paper's two-arm table (experiments only), the
/// config that ran, as JSON, what wrote the report (`provenance.json`, missions only: an
/// experiment's `summary.json` holds its own), and the run itself, to write its report
/// folder later.
#[derive(IntoPyObject)]
pub struct RunOutput {
    kind: &'static str,
    records: String,
    summary: String,
    table: String,
    paper_table: String,
    config: String,
    provenance: String,
    report: Report,
}

/// A finished run, kept to write its report folder on demand (`Results.save`): byte for
/// byte the folder `out=` writes, from the same results, run time and provenance.
#[pyclass(module = "trustcbr._native", frozen)]
pub struct Report(Mutex<Finished>);

/// What a [`Report`] keeps: an experiment suite's run or a mission suite's.
enum Finished {
    Experiments(Box<Ran>),
    Missions(Box<MissionsRan>),
}

#[pymethods]
impl Report {
    /// Writes the report folder `out` (replacing an earlier report there, as a run does);
    /// returns the files written.
    fn save(&self, py: Python<'_>, out: PathBuf) -> PyResult<Vec<PathBuf>> {
        let finished = self.0.lock().unwrap_or_else(|p| p.into_inner());
        py.detach(|| match &*finished {
            Finished::Experiments(ran) => ran.write_report(&out),
            Finished::Missions(ran) => ran.write_report(&out),
        })
        .map_err(|e| error(format_args!("{e:#}")))
    }
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

/// The Python arms of a request (`python_arms`), their factories shared.
fn python_arm_specs(arms: Vec<(String, Py<PyAny>, bool)>) -> Vec<PythonArmSpec> {
    arms.into_iter()
        .map(|(name, factory, reuses_cases)| PythonArmSpec {
            label: Arc::from(format!("python_arms['{name}']")),
            name,
            factory: Arc::new(factory),
            reuses_cases,
        })
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
        .map(|spec| -> AddedArm {
            let (spec, observations, errors, caller) = (
                spec.clone(),
                observations.clone(),
                errors.clone(),
                caller.clone(),
            );
            Arc::new(move |retriever| -> Arm {
                python_arm(
                    &spec,
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

/// What a report from Python records as its command line.
fn python_command_line() -> Vec<String> {
    vec!["python".into(), "trustcbr.run".into()]
}

/// The arms a run was given (`arms=`), each read once, or the first that is no arm's
/// name, said with its place.
fn read_arms(arms: Vec<String>) -> PyResult<Vec<ArmName>> {
    arms.iter()
        .enumerate()
        .map(|(i, name)| ArmName::parse(name).map_err(|e| error(format_args!("arms[{i}]: {e}"))))
        .collect()
}

/// Refuses a Python arm named like one of the catalog's (it would hide it under the same
/// label) or left out of the arms run (it would silently not run).
fn check_python_arm_names<C: Catalog>(
    catalog: &C,
    names: &[String],
    arms_run: &[ArmName],
) -> PyResult<()> {
    let builtin = builtin_arms(catalog);
    for name in names {
        if builtin.contains(name) {
            return Err(error(format_args!(
                "python_arms: `{name}` is the name of a built-in arm; give the Python arm a name of its own"
            )));
        }
        if !arms_run.iter().any(|a| a.base() == name.as_str()) {
            return Err(error(format_args!(
                "python_arms: `{name}` is not among the arms run ({}); name it in `arms` to run it",
                ArmName::join(arms_run, ", ")
            )));
        }
    }
    Ok(())
}

/// The suite's text and origin, and whether it is a mission suite. A suite given as text
/// or a dict is named `origin` in `base` (its operator files are read from there), or in
/// the working directory.
fn suite_text(
    kind: &str,
    text: &str,
    origin: &Path,
    base: Option<&Path>,
) -> PyResult<(String, PathBuf, bool)> {
    let (text, origin) = match kind {
        "file" => (
            trustcbr::files::read_text(origin).map_err(error)?,
            origin.to_owned(),
        ),
        "ron" | "json" => (
            text.to_owned(),
            base.map_or_else(|| origin.to_owned(), |base| base.join(origin)),
        ),
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

/// A suite in one of its forms, parsed as `T` and not checked: a dict's error names the
/// field by its path.
fn parsed<T: serde::de::DeserializeOwned>(kind: &str, text: &str, origin: &Path) -> PyResult<T> {
    if kind == "json" {
        from_json(text, origin).map_err(error)
    } else {
        trustcbr::files::parse_ron(text, origin).map_err(error)
    }
}

/// Refuses an operator file of a suite given as text or a dict (`kind` `ron` or `json`)
/// that is not there, saying where it was looked for: in `base`, or the working
/// directory when `base` is not given. `files` are each file's field and path.
fn check_operator_files<'a>(
    kind: &str,
    base: Option<&Path>,
    files: impl Iterator<Item = (String, &'a Path)>,
) -> PyResult<()> {
    if !matches!(kind, "ron" | "json") {
        return Ok(());
    }
    let folder = base.unwrap_or(Path::new(""));
    for (field, file) in files {
        if !folder.join(file).is_file() {
            let looked = match base {
                Some(base) => format!("in base={}", base.display()),
                None => format!(
                    "in the working directory ({}), as no base= was given",
                    std::env::current_dir()
                        .map_or_else(|_| ".".into(), |d| d.display().to_string())
                ),
            };
            let form = if kind == "ron" { "text" } else { "a dict" };
            return Err(error(format_args!(
                "{field}: no operator file `{}` {looked}: a suite given as {form} reads its operator files relative to base=, the folder they are in",
                file.display()
            )));
        }
    }
    Ok(())
}

/// Every plan of a mission suite with `count` missions and `commands` commands each, when
/// given, checked as the suite's own (1 to the most missions and commands of a suite; its
/// totals are checked when it runs).
fn resize_plans(
    config: &mut MissionSuiteConfig,
    count: Option<u64>,
    commands: Option<u64>,
) -> PyResult<()> {
    let count = count.map(|n| within(&MISSIONS, "count", n)).transpose()?;
    let commands = commands
        .map(|n| within(&MISSION_COMMANDS, "commands", n))
        .transpose()?;
    for plan in &mut config.missions {
        plan.count = count.unwrap_or(plan.count);
        plan.commands = commands.unwrap_or(plan.commands);
    }
    Ok(())
}

/// `value` of the option `option` checked against `limit` (each of these is 1 to at most
/// `u32::MAX`), as the count a config holds.
fn within(limit: &Bound, option: &str, value: u64) -> PyResult<NonZeroU32> {
    limit.check(option, value).map_err(error)?;
    Ok(u32::try_from(value)
        .ok()
        .and_then(NonZeroU32::new)
        .expect("checked to be 1 to the limit's most"))
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
    let base = request.base.as_deref();
    let (text, origin, missions) = suite_text(&request.kind, &request.text, &request.origin, base)?;
    match (request.expect.as_str(), missions) {
        ("experiments", true) => {
            return Err(error(format_args!(
                "{}: a mission suite (it lists `missions`): run it with trustcbr.run_missions(), which returns MissionResults",
                origin.display()
            )));
        }
        ("missions", false) => {
            return Err(error(format_args!(
                "{}: an experiment suite (it lists no `missions`): run it with trustcbr.run(), which returns Results",
                origin.display()
            )));
        }
        _ => {}
    }
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
        let mut config: MissionSuiteConfig = parsed(&request.kind, &text, &origin)?;
        check_operator_files(
            &request.kind,
            base,
            config.missions.iter().enumerate().flat_map(|(k, plan)| {
                plan.operators
                    .operator_files
                    .iter()
                    .enumerate()
                    .map(move |(i, f)| {
                        (
                            format!("missions[{k}].operators.operator_files[{i}]"),
                            f.as_path(),
                        )
                    })
            }),
        )?;
        resize_plans(&mut config, request.count, request.commands)?;
        if let Some(seed) = request.seed {
            config.seed = seed;
        }
        if let Some(arms) = request.arms {
            config.arms = read_arms(arms)?;
        }
        check_python_arm_names(catalog, &names, &config.arms)?;
        let watch = Watch {
            callback: request.progress,
            counts: Counts::of(missions_per_plan(&config).iter().map(|(_, n)| n).sum()),
        };
        let counts = watch.counts.clone();
        let settings = MissionSettings {
            out: request.out.clone(),
            threads,
            command_line: python_command_line(),
        };
        let ran = run_watched(py, &watch, |caller| {
            let catalog = with_python_arms(catalog, &python_arms, &errors, &caller);
            run_missions_with_report(
                &catalog,
                config,
                &origin,
                &settings,
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
            provenance: serde_json::to_string(&ran.provenance).map_err(error)?,
            report: Report(Mutex::new(Finished::Missions(Box::new(ran)))),
        }
    } else {
        if request.kind != "embedded" {
            let written: SuiteConfig = parsed(&request.kind, &text, &origin)?;
            check_operator_files(
                &request.kind,
                base,
                written
                    .experiments
                    .iter()
                    .enumerate()
                    .flat_map(|(k, spec)| {
                        spec.operator_files.iter().enumerate().map(move |(i, f)| {
                            (format!("experiments[{k}].operator_files[{i}]"), f.as_path())
                        })
                    }),
            )?;
        }
        if let Some(dir) = &request.cases
            && !dir.is_dir()
        {
            return Err(error(format_args!(
                "cases: no folder {} (give the folder a run's save_cases= wrote)",
                dir.display()
            )));
        }
        let mut config = experiment_suite(&reading, &request.kind, &text, &origin)?;
        if let Some(trials) = request.trials {
            config.trials = within(&TRIALS, "trials", trials)?;
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
            config.arms = read_arms(arms)?;
        }
        check_python_arm_names(catalog, &names, &config.arms)?;
        let settings = RunSettings {
            out: request.out.clone(),
            starting: request.cases.map(|dir| StartingCases { dir }),
            save_cases: request.save_cases.clone(),
            threads,
            command_line: python_command_line(),
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
            provenance: String::new(),
            report: Report(Mutex::new(Finished::Experiments(Box::new(ran)))),
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
    let (text, origin, missions) = suite_text(kind, text, Path::new(origin), None)?;
    if missions {
        let config: MissionSuiteConfig = parsed(kind, &text, &origin)?;
        return serde_json::to_string(&config).map_err(error);
    }
    let mut config: SuiteConfig = parsed(kind, &text, &origin)?;
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
