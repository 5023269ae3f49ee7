//! Mission suites: RON files that `trustcbr run` runs like experiment suites, but whose
//! `missions` are long runs of commands with operator changes and complacency
//! ([`lab::mission`], docs/missions.md).
//!
//! A mission suite names its seed, the adapter parameters and arms as an experiment suite
//! does, and a list of mission plans ([`MissionSpec`]). A plan's `operators` are its own
//! ([`MissionOperators`]: a scenario and its operator files or population, without what
//! only experiments simulate); `count` missions of `commands` commands each; `changes`
//! and, optionally, `context_switches` (announced switches of the robot's context),
//! `complacency` (only over a domain that models its operators' attention,
//! [`lab::Attentive`]) and `competence` ([`CompetenceSpec`], with whether
//! alerts offer a safer behavior). The report folder holds `missions.md`, `summary.json`
//! (the summaries), `missions.jsonl`, `provenance.json`, a timeline figure per plan, and
//! the config with copies of its operator files, so it reruns by itself.

use crate::catalog::{Catalog, OperatorOf, domain_of, resolve_readings};
use crate::limits::{EXPERIMENTS, MISSION_COMMANDS, MISSIONS, TRUTH_RUNS};
use crate::suite::{
    SuiteError, arm_named, arm_names, check_adapter, check_arms, check_distinct,
    copy_operator_files, invalid, over, relocate_operator_files,
};
use files::name::check_label;
use files::write_file_in;
use files::{FileError, parse_ron, read_text};
use lab::Domain;
use lab::contract::capability::Needing;
use lab::mission::figure::mission_figure;
use lab::mission::report::{missions_json, missions_jsonl, missions_markdown};
use lab::mission::{
    CompetenceOn, ComplacencyOn, MissionPlan, MissionResult, check_competence, run_missions,
};
use lab::reference::known_operator::LimitSettings;
use lab::report::plot::svg;
use lab::report::{Provenance, file_stems};
use lab::{Arm, ArmName, PREFERS_COMPETENT, check_attention};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use trust::AdapterConfig;

mod spec;

pub use spec::{CompetenceSpec, ContextSwitchesSpec, MissionOperators, MissionSpec};

/// A mission suite.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MissionSuiteConfig {
    /// Master seed of every random stream.
    pub seed: u64,
    /// The adapter parameters every arm shares (the mode is always mission).
    #[serde(default, serialize_with = "crate::suite::config::write_suite_adapter")]
    pub adapter: AdapterConfig,
    /// The domain's readings, by name, each once.
    #[serde(
        default,
        skip_serializing_if = "BTreeMap::is_empty",
        deserialize_with = "cbr_core::unique_keys::each_once"
    )]
    pub readings: BTreeMap<String, String>,
    /// The arms, by name, written as an experiment suite writes them (a name, or
    /// `(name: NAME, initial: learned)`); default: the recommended arm
    /// ([`lab::RECOMMENDED_ARM`]) alone.
    #[serde(default = "recommended_arm", deserialize_with = "arm_names")]
    pub arms: Vec<ArmName>,
    /// A change detector beside the paper's thresholds for every arm
    /// (`change_detector: Some((commands_per_false_alarm: 8000.0))`, docs/missions.md, "A change
    /// detector"); absent: the thresholds alone.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub change_detector: Option<trust::ChangeDetector>,
    /// The mission plans, in report order.
    pub missions: Vec<MissionSpec>,
}

/// A mission suite's arms when it lists none: the recommended arm alone.
fn recommended_arm() -> Vec<ArmName> {
    vec![ArmName::new(
        lab::RECOMMENDED_ARM,
        lab::NameOptions::default(),
    )]
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

    /// Checks every field against `catalog`, with the rules experiment suites follow
    /// for what both have (arms, adapter parameters, populations and operators, names
    /// given once), refuses a plan with `complacency` over a domain that does not model
    /// attention ([`check_attention`]), and bounds the suite's cost before it runs: its
    /// plans, its missions (each record is kept for the report) and its commands, counting
    /// the runs that tell whether each expected change needed an adaptation
    /// ([`TRUTH_RUNS`] each).
    pub fn validate<C: Catalog>(&self, catalog: &C, origin: &Path) -> Result<(), SuiteError> {
        let invalid = |field: String, message: String| invalid(origin, field, message);
        let over = |error| over(origin, error);
        EXPERIMENTS
            .check("missions", self.missions.len() as u64)
            .map_err(over)?;
        check_arms(catalog, &self.arms, self.adapter.retriever, origin)?;
        if let Some(Err(reason)) = self.change_detector.map(|d| d.validate()) {
            return Err(invalid("change_detector".into(), reason.to_string()));
        }
        if !self.missions.iter().any(|m| m.context_switches.is_some())
            && let Some(i) = self.arms.iter().position(|a| a.options().context_blind)
        {
            return Err(invalid(
                format!("arms[{i}]"),
                format!(
                    "`{}` is blind to the robot's context, and no plan here has `context_switches`: every mission runs in the default context, where the arm is its sighted twin; give a plan `context_switches` or drop the arm's +context-blind",
                    self.arms[i]
                ),
            ));
        }
        if let Some(i) = self
            .arms
            .iter()
            .position(|a| a.options().ignores_statements)
        {
            return Err(invalid(
                format!("arms[{i}]"),
                format!(
                    "`{}` ignores what operators state up front, and a mission's operators state nothing (statements are an experiment's `stated`): drop the arm's +ignores-statements",
                    self.arms[i]
                ),
            ));
        }
        check_adapter(&self.adapter, origin)?;
        for (k, spec) in self.missions.iter().enumerate() {
            check_label("plan", &spec.name)
                .map_err(|e| invalid(format!("missions[{k}].name"), e.to_string()))?;
        }
        let names: Vec<String> = self.missions.iter().map(|m| m.name.clone()).collect();
        check_distinct("missions", "plan", &names, origin)?;
        let readings = resolve_readings(catalog, &self.readings)
            .map_err(|e| invalid("readings".into(), e.to_string()))?;
        let (mut commands, mut missions) = (0u64, 0u64);
        for (k, spec) in self.missions.iter().enumerate() {
            let field = |name: &str| format!("missions[{k}].{name}");
            spec.changes
                .validate()
                .map_err(|e| invalid(field("changes"), e))?;
            if spec.competence.is_none()
                && let Some(arm) = self.arms.iter().find(|a| a.options().prefers_competent)
            {
                return Err(invalid(
                    field("competence"),
                    format!(
                        "the arm `{arm}` prefers behaviors the robot judges competent, and this plan judges nothing: set a standard (`competence: Some((at_most: 0.1))`) or drop the arm's {PREFERS_COMPETENT}"
                    ),
                ));
            }
            if let Some(model) = spec.complacency {
                model
                    .validate()
                    .map_err(|e| invalid(field("complacency"), e))?;
            }
            let experiment = spec.operators.as_experiment();
            let (operators, _) =
                experiment.check(catalog, &field("operators"), origin, &readings)?;
            if spec.complacency.is_some()
                || spec.competence.is_some()
                || spec.context_switches.is_some()
            {
                let domain = domain_of(catalog, &spec.operators.scenario)
                    .map_err(|e| invalid(field("operators.scenario"), e.to_string()))?;
                if let Some(switches) = &spec.context_switches {
                    switches
                        .switches(domain.contexts())
                        .map_err(|(name, e)| invalid(field(&name), e))?;
                }
                capabilities(spec, &domain).map_err(|(name, e)| invalid(field(name), e))?;
            }
            experiment.check_reachable(
                catalog,
                &operators,
                &format!("missions[{k}]"),
                origin,
                &self.adapter,
                (
                    u64::from(spec.commands.get()),
                    "commands",
                    "no episode of a mission could settle",
                ),
            )?;
            let chains = self.arms.len() as u64 * if spec.complacency.is_some() { 2 } else { 1 };
            let plan_missions = chains * u64::from(spec.count.get());
            missions = missions.saturating_add(plan_missions);
            commands = commands.saturating_add(
                plan_missions.saturating_mul(spec.commands_with_truth_runs(operators.len())),
            );
        }
        MISSIONS
            .check_total(
                "missions",
                missions,
                " in all (arms x missions, twice for complacency plans)".into(),
            )
            .map_err(over)?;
        MISSION_COMMANDS
            .check_total(
                "missions",
                commands,
                format!(
                    " in all (arms x missions x (commands + {TRUTH_RUNS} truth runs per expected change), twice for complacency plans)"
                ),
            )
            .map_err(over)?;
        Ok(())
    }
}

impl MissionSpec {
    /// The commands one mission of the plan simulates, over a population of `members`:
    /// its own, and [`TRUTH_RUNS`] for each change expected (one every `changes.every`
    /// commands on average, none with one member, and one every `context_switches.every`).
    fn commands_with_truth_runs(&self, members: usize) -> u64 {
        let commands = u64::from(self.commands.get());
        let operator_changes = if members < 2 {
            0.0
        } else {
            commands as f64 / self.changes.every
        };
        let switches = self
            .context_switches
            .as_ref()
            .map_or(0.0, |s| commands as f64 / s.every);
        // At least one command apart, as the schedules draw them.
        let changes = ((operator_changes + switches).ceil() as u64).min(commands);
        commands.saturating_add(changes.saturating_mul(u64::from(TRUTH_RUNS)))
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
        .map(|spec| {
            spec.operators
                .as_experiment()
                .operators(catalog, origin, &readings)
        })
        .collect::<Result<_, _>>()?;
    let switches = config
        .missions
        .iter()
        .zip(&domains)
        .enumerate()
        .map(|(k, (spec, domain))| {
            spec.context_switches
                .as_ref()
                .map(|s| s.switches(domain.contexts()))
                .transpose()
                .map_err(|(name, e)| invalid(origin, format!("missions[{k}].{name}"), e))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let plans = config
        .missions
        .iter()
        .zip(&domains)
        .zip(&operators)
        .zip(switches)
        .enumerate()
        .map(|(k, (((spec, domain), operators), contexts))| {
            let (complacency, competence) = capabilities(spec, domain)
                .map_err(|(name, e)| invalid(origin, format!("missions[{k}].{name}"), e))?;
            Ok(MissionPlan {
                name: spec.name.clone(),
                domain,
                operators,
                missions: spec.count.get(),
                commands: spec.commands.get(),
                changes: spec.changes,
                contexts,
                complacency,
                competence,
                offer_safer: spec.competence.as_ref().is_some_and(|c| c.offer_safer),
                adapter: config.adapter.clone(),
                arms: arms.clone(),
                feedback: spec.operators.feedback,
                truth_runs: TRUTH_RUNS,
                limit: LimitSettings::default(),
                change_detector: config.change_detector,
            })
        })
        .collect::<Result<Vec<MissionPlan<'_, C::Domain>>, SuiteError>>()?;
    Ok(run_missions(&plans, config.seed, progress)?)
}

/// A plan's complacency and competence standard, each with the domain as the capability
/// it needs.
type Capabilities<'d, O> = (Option<ComplacencyOn<'d, O>>, Option<CompetenceOn<'d, O>>);

/// The settings of plan `spec` that need a capability of its domain, each with `domain`
/// as that capability: complacency needs attention ([`check_attention`]), a competence
/// standard a robot that judges itself ([`check_competence`]). Refused with the field
/// that needs what the domain lacks, and why.
fn capabilities<'d, D: Domain>(
    spec: &MissionSpec,
    domain: &'d D,
) -> Result<Capabilities<'d, D::Operator>, (&'static str, String)> {
    let complacency = spec
        .complacency
        .map(|model| {
            let attentive = check_attention(domain).map_err(|e| ("complacency", e.to_string()))?;
            Ok(Needing {
                setting: model,
                capability: attentive,
            })
        })
        .transpose()?;
    let competence = spec
        .competence
        .as_ref()
        .map(|spec| {
            let standard = spec.standard();
            let judging =
                check_competence(domain, &standard).map_err(|e| ("competence", e.to_string()))?;
            Ok(Needing {
                setting: standard,
                capability: judging,
            })
        })
        .transpose()?;
    Ok((complacency, competence))
}

/// Writes the report of a mission suite into `dir`: the tables, the data, a timeline per
/// plan (the first arm's first mission, alerts answered where operators grow
/// complacent), the config and `provenance.json` (what wrote it, as an experiment
/// report's `summary.json` records it). The report reruns by itself: every operator file the
/// config names (relative to `origin`) is copied into `DIR/operators/`, and the
/// `config.ron` written names those copies. Returns the files written.
pub fn write_mission_report(
    dir: &Path,
    config: &MissionSuiteConfig,
    origin: &Path,
    results: &[MissionResult],
    provenance: &Provenance,
) -> Result<Vec<PathBuf>, SuiteError> {
    let report = |e: FileError| SuiteError::Report(e.into());
    let mut portable = config.clone();
    let copies = relocate_operator_files(
        portable
            .missions
            .iter_mut()
            .map(|spec| &mut spec.operators.operator_files),
        origin,
    );
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
            "provenance.json",
            &format!(
                "{:#}\n",
                serde_json::to_value(provenance).expect("a provenance serializes")
            ),
        )
        .map_err(report)?,
        write_file_in(
            dir,
            "config.ron",
            &ron::ser::to_string_pretty(&portable, ron::ser::PrettyConfig::default())
                .expect("a mission suite serializes"),
        )
        .map_err(report)?,
    ];
    let stems = file_stems(results.iter().map(|r| r.name.clone()));
    for (result, stem) in results.iter().zip(stems) {
        let Some(arm) = result
            .arms
            .iter()
            .find(|a| a.answers_alerts == result.complacency)
        else {
            continue;
        };
        let name = format!("mission-{stem}.svg");
        let path = dir.join(&name);
        let figure = svg(&path, (1100, 480), |area| {
            mission_figure(area, &result.name, arm, &config.adapter.thresholds)
        })
        .map_err(|e| SuiteError::Report(e.into()))?;
        written.push(write_file_in(dir, &name, &figure).map_err(report)?);
    }
    written.extend(copy_operator_files(dir, &copies)?);
    Ok(written)
}
