//! Mission suites: RON files that `trustcbr run` runs like experiment suites, but whose
//! `missions` are long runs of commands with operator changes and complacency
//! ([`lab::mission`], docs/missions.md).
//!
//! A mission suite names its seed, the adapter parameters and arms as an experiment suite
//! does, and a list of mission plans. A plan's `operators` are an experiment's (a scenario
//! and its operator files or population; `operator` must be `random`); `count` missions of
//! `commands` commands each; `changes` and, optionally, `complacency`. The report folder
//! holds `missions.md`, `summary.json` (the summaries), `missions.jsonl`, a timeline figure per plan and
//! the config.

use crate::catalog::{Catalog, OperatorOf, domain_of, resolve_readings};
use crate::suite::{ExperimentSpec, RANDOM_OPERATOR, SuiteError, arm_named, invalid};
use files::write_file_in;
use files::{FileError, parse_ron, read_text};
use lab::Arm;
use lab::mission::{Changes, Complacency, MissionPlan, MissionResult, run_missions};
use lab::mission_figure::mission_figure;
use lab::mission_report::{missions_json, missions_jsonl, missions_markdown};
use lab::plot::svg;
use lab::report::file_stems;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::num::NonZeroU32;
use std::path::{Path, PathBuf};
use trust::AdapterConfig;

/// The most commands a mission suite may simulate in all (plans x arms x missions x
/// commands, doubled for complacency plans): about 20 minutes of the machine of
/// docs/results.md.
pub const MAX_MISSION_COMMANDS: u64 = 100_000_000;

/// Runs per (behavior, operator) of the truth of a change (whether the behavior in use
/// is trustworthy for the new operator): a mean weighted outcome of 0.2 is told from 0
/// with a standard error of about 0.07 at 200 runs.
pub const TRUTH_RUNS: u32 = 200;

/// A mission suite.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MissionSuiteConfig {
    /// Master seed of every random stream.
    pub seed: u64,
    /// The adapter parameters every arm shares (the mode is always mission).
    #[serde(default, serialize_with = "crate::suite::config::write_suite_adapter")]
    pub adapter: AdapterConfig,
    /// The domain's readings, by name.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub readings: BTreeMap<String, String>,
    /// The arms, by name.
    pub arms: Vec<String>,
    /// The mission plans, in report order.
    pub missions: Vec<MissionSpec>,
}

/// One mission plan.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MissionSpec {
    /// Its name in the report.
    pub name: String,
    /// Who operates: a scenario and its population (`operator: "random"`).
    pub operators: ExperimentSpec,
    /// Missions per arm.
    pub count: NonZeroU32,
    /// Commands per mission.
    pub commands: NonZeroU32,
    /// When the operator changes.
    pub changes: Changes,
    /// How operators grow complacent; absent: they stay attentive.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub complacency: Option<Complacency>,
}

/// Whether `text` is a mission suite: a RON structure with a `missions` field.
pub fn is_mission_suite(text: &str) -> bool {
    match ron::from_str::<ron::Value>(text) {
        Ok(ron::Value::Map(map)) => map
            .keys()
            .any(|k| matches!(k, ron::Value::String(s) if s == "missions")),
        _ => false,
    }
}

impl MissionSuiteConfig {
    /// Reads and checks a mission suite file.
    pub fn load<C: Catalog>(catalog: &C, path: &Path) -> Result<Self, SuiteError> {
        let text = read_text(path)?;
        let config: Self = parse_ron(&text, path)?;
        config.validate(catalog, path)?;
        Ok(config)
    }

    /// Checks every field against `catalog`.
    pub fn validate<C: Catalog>(&self, catalog: &C, origin: &Path) -> Result<(), SuiteError> {
        let invalid = |field: String, message: String| invalid(origin, field, message);
        if self.missions.is_empty() {
            return Err(invalid(
                "missions".into(),
                "at least one mission plan is needed".into(),
            ));
        }
        self.adapter.validate()?;
        crate::suite::config::check_arms_choose(&self.adapter, origin)?;
        if self.arms.is_empty() {
            return Err(invalid("arms".into(), "at least one arm is needed".into()));
        }
        for (i, name) in self.arms.iter().enumerate() {
            arm_named(catalog, name, self.adapter.retriever)
                .map_err(|e| invalid(format!("arms[{i}]"), e))?;
        }
        let mut commands: u64 = 0;
        for (k, spec) in self.missions.iter().enumerate() {
            let field = |name: &str| format!("missions[{k}].{name}");
            if spec.operators.operator != RANDOM_OPERATOR {
                return Err(invalid(
                    field("operators.operator"),
                    format!(
                        "a mission draws its operators from the population: write `operator: \"{RANDOM_OPERATOR}\"`, got `{}`",
                        spec.operators.operator
                    ),
                ));
            }
            spec.changes
                .validate()
                .map_err(|e| invalid(field("changes"), e))?;
            if let Some(model) = spec.complacency {
                model
                    .validate()
                    .map_err(|e| invalid(field("complacency"), e))?;
            }
            let doubled = if spec.complacency.is_some() { 2 } else { 1 };
            commands = commands.saturating_add(
                self.arms.len() as u64
                    * doubled
                    * u64::from(spec.count.get())
                    * u64::from(spec.commands.get()),
            );
        }
        if commands > MAX_MISSION_COMMANDS {
            return Err(invalid(
                "missions".into(),
                format!(
                    "{commands} commands in all (arms x missions x commands, twice for complacency plans); at most {MAX_MISSION_COMMANDS}"
                ),
            ));
        }
        let readings = resolve_readings(catalog, &self.readings)
            .map_err(|e| invalid("readings".into(), e.to_string()))?;
        for (k, spec) in self.missions.iter().enumerate() {
            domain_of(catalog, &spec.operators.scenario)
                .map_err(|e| invalid(format!("missions[{k}].operators.scenario"), e.to_string()))?;
            let operators = spec.operators.operators(catalog, origin, &readings)?;
            if operators.is_empty() {
                return Err(invalid(
                    format!("missions[{k}].operators"),
                    "the population has no operator".into(),
                ));
            }
        }
        Ok(())
    }
}

/// Runs every mission plan of `config` (operator files relative to `origin`) on the
/// current rayon pool; `progress(plan)` after every mission of every arm.
pub fn run_mission_suite<C: Catalog>(
    catalog: &C,
    config: &MissionSuiteConfig,
    origin: &Path,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Vec<MissionResult>, SuiteError> {
    let readings = resolve_readings(catalog, &config.readings)
        .map_err(|e| invalid(origin, "readings".into(), e.to_string()))?;
    let arms = config
        .arms
        .iter()
        .map(|name| arm_named(catalog, name, config.adapter.retriever))
        .collect::<Result<Vec<Arm>, String>>()
        .map_err(|e| invalid(origin, "arms".into(), e))?;
    let domains = config
        .missions
        .iter()
        .map(|spec| domain_of(catalog, &spec.operators.scenario))
        .collect::<Result<Vec<C::Domain>, _>>()
        .map_err(|e| invalid(origin, "missions".into(), e.to_string()))?;
    let operators: Vec<Vec<(String, OperatorOf<C>)>> = config
        .missions
        .iter()
        .map(|spec| spec.operators.operators(catalog, origin, &readings))
        .collect::<Result<_, _>>()?;
    let plans: Vec<MissionPlan<'_, C::Domain>> = config
        .missions
        .iter()
        .zip(&domains)
        .zip(&operators)
        .map(|((spec, domain), operators)| MissionPlan {
            name: spec.name.clone(),
            domain,
            operators,
            missions: spec.count.get(),
            commands: spec.commands.get(),
            changes: spec.changes,
            complacency: spec.complacency,
            adapter: config.adapter.clone(),
            arms: arms.clone(),
            feedback: spec.operators.feedback,
            truth_runs: TRUTH_RUNS,
        })
        .collect();
    Ok(run_missions(&plans, config.seed, progress)?)
}

/// Writes the report of a mission suite into `dir`: the tables, the data, a timeline per
/// plan (the first arm's first mission, alerts answered where operators grow
/// complacent) and the config. Returns the files written.
pub fn write_mission_report(
    dir: &Path,
    config: &MissionSuiteConfig,
    results: &[MissionResult],
) -> Result<Vec<PathBuf>, SuiteError> {
    let report = |e: FileError| SuiteError::Report(e.into());
    let mut written = vec![
        write_file_in(dir, "missions.md", &missions_markdown(results)).map_err(report)?,
        write_file_in(
            dir,
            "summary.json",
            &format!("{:#}\n", missions_json(results)),
        )
        .map_err(report)?,
        write_file_in(dir, "missions.jsonl", &missions_jsonl(results)).map_err(report)?,
        write_file_in(
            dir,
            "config.ron",
            &ron::ser::to_string_pretty(config, ron::ser::PrettyConfig::default())
                .expect("a mission suite serializes"),
        )
        .map_err(report)?,
    ];
    let stems = file_stems(results.iter().map(|r| r.name.clone()));
    for (result, stem) in results.iter().zip(stems) {
        let Some((index, arm)) = result
            .arms
            .iter()
            .enumerate()
            .find(|(_, a)| a.answers_alerts == result.complacency)
        else {
            continue;
        };
        let name = format!("mission-{stem}.svg");
        let path = dir.join(&name);
        let figure = svg(&path, (1100, 480), |area| {
            mission_figure(
                area,
                &result.name,
                index / if result.complacency { 2 } else { 1 },
                arm,
                &config.adapter.thresholds,
            )
        })
        .map_err(|e| SuiteError::Report(e.into()))?;
        written.push(write_file_in(dir, &name, &figure).map_err(report)?);
    }
    Ok(written)
}
