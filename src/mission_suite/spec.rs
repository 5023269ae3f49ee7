//! A mission plan as a suite writes it: only the fields a mission can use, so that what a
//! mission cannot do cannot be written. Who operates is [`MissionOperators`] (an
//! experiment's operators without what only experiments simulate: contexts in turn, goal
//! changes, statements up front, each refused where it is written with what to write
//! instead); the competence section holds what the robot's alerts offer
//! ([`CompetenceSpec::offer_safer`]).

use crate::suite::{ExperimentSpec, Population, RANDOM_OPERATOR, contexts_written};
use cbr_core::ContextSpace;
use lab::FeedbackChannel;
use lab::mission::{Changes, Complacency, ContextSwitches};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::num::NonZeroU32;
use std::path::PathBuf;
use trust::{Cause, CompetenceStandard};

/// One mission plan.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MissionSpec {
    /// Its name in the report.
    pub name: String,
    /// Who operates: a scenario and its population ([`MissionOperators`]).
    pub operators: MissionOperators,
    /// Missions per arm.
    pub count: NonZeroU32,
    /// Commands per mission.
    pub commands: NonZeroU32,
    /// When the operator changes.
    pub changes: Changes,
    /// When the robot's context switches, and the robot is told
    /// (`Some((among: [{}, {"cargo": "hazardous"}], every: 100.0))`); absent: every
    /// mission in the default context.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub context_switches: Option<ContextSwitchesSpec>,
    /// How operators grow complacent; absent: they stay attentive.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub complacency: Option<Complacency>,
    /// The standard the robot holds its own competence to, and what its overtrust alerts
    /// offer (`Some((at_most: 0.1))`: at most one command in ten falling short in any
    /// part); absent: it does not judge it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub competence: Option<CompetenceSpec>,
}

/// A plan's context switches as a suite writes them ([`ContextSwitches`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContextSwitchesSpec {
    /// The contexts a mission may be in, each its variables and values (`{}`: the default
    /// context); at least two, each variable once.
    #[serde(deserialize_with = "cbr_core::unique_keys::each_variable_once_in_each")]
    pub among: Vec<BTreeMap<String, String>>,
    /// Mean commands between switches.
    pub every: f64,
}

impl ContextSwitchesSpec {
    /// The switches, each context checked against `space` (the domain's context
    /// variables); an error names the field under the plan (`context_switches.among[1]`).
    pub fn switches(&self, space: &ContextSpace) -> Result<ContextSwitches, (String, String)> {
        let among = contexts_written(&self.among, space, "context_switches.among")?;
        let switches = ContextSwitches {
            among,
            every: self.every,
        };
        switches
            .validate()
            .map_err(|e| ("context_switches".to_owned(), e))?;
        Ok(switches)
    }
}

/// Who operates a mission plan: a scenario and its operators (the scenario's built-in ones
/// and `operator_files`, or a `population`), each mission drawing its operators from them,
/// and optionally how they explain themselves. Written as an experiment's operators are;
/// `operator` may only be `"random"` (or left out: a mission always draws).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MissionOperators {
    /// The scenario, by the catalog's name for it.
    #[serde(deserialize_with = "crate::suite::config::deserialize_scenario")]
    pub scenario: String,
    /// Always drawn: written `operator: "random"` (which configs written before mission
    /// plans had their own operators carry), read only to refuse another name.
    #[serde(
        default,
        rename = "operator",
        serialize_with = "write_drawn",
        deserialize_with = "read_drawn"
    )]
    drawn: (),
    /// Extra operator files (RON), relative to the config file; they join the scenario's
    /// built-in operators.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub operator_files: Vec<PathBuf>,
    /// A population's members among the scenario's built-in operators, by name, before
    /// those of `operator_files` (only with a `population` listed by hand).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub builtin_operators: Vec<String>,
    /// The operators are a population instead of the scenario's ([`ExperimentSpec::population`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub population: Option<Population>,
    /// How every operator explains itself, overriding each operator's own channel.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub feedback: Option<FeedbackChannel>,
    /// Refused: an experiment's contexts in turn.
    #[serde(default, skip_serializing, deserialize_with = "refuse_contexts")]
    contexts: (),
    /// Refused: an experiment's goal changes.
    #[serde(default, skip_serializing, deserialize_with = "refuse_goal_changes")]
    goal_changes: (),
    /// Refused: an experiment's statements up front.
    #[serde(default, skip_serializing, deserialize_with = "refuse_stated")]
    stated: (),
}

impl MissionOperators {
    /// The operators of `scenario`: its built-in ones, none added, no population.
    pub fn of_scenario(scenario: impl Into<String>) -> Self {
        Self {
            scenario: scenario.into(),
            drawn: (),
            operator_files: Vec::new(),
            builtin_operators: Vec::new(),
            population: None,
            feedback: None,
            contexts: (),
            goal_changes: (),
            stated: (),
        }
    }

    /// The same operators as an experiment's, drawn per trial: what the checks and the
    /// reading of operators both kinds of suite share take.
    pub fn as_experiment(&self) -> ExperimentSpec {
        ExperimentSpec {
            scenario: self.scenario.clone(),
            operator: RANDOM_OPERATOR.to_owned(),
            operator_files: self.operator_files.clone(),
            builtin_operators: self.builtin_operators.clone(),
            population: self.population.clone(),
            feedback: self.feedback,
            goal_changes: None,
            contexts: None,
            stated: None,
        }
    }
}

fn write_drawn<S: serde::Serializer>(_: &(), s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(RANDOM_OPERATOR)
}

fn read_drawn<'de, D: serde::Deserializer<'de>>(d: D) -> Result<(), D::Error> {
    let name = String::deserialize(d)?;
    if name == RANDOM_OPERATOR {
        Ok(())
    } else {
        Err(serde::de::Error::custom(format!(
            "a mission draws its operators from the plan's operators (the scenario's, its files', or its population's): write `operator: \"{RANDOM_OPERATOR}\"` or leave it out, not `{name}`"
        )))
    }
}

/// Refuses a field an experiment's operators have and a mission's do not, with `why`.
fn refused<'de, D: serde::Deserializer<'de>>(d: D, why: &str) -> Result<(), D::Error> {
    serde::de::IgnoredAny::deserialize(d)?;
    Err(serde::de::Error::custom(why))
}

fn refuse_contexts<'de, D: serde::Deserializer<'de>>(d: D) -> Result<(), D::Error> {
    refused(
        d,
        "`contexts`: an experiment's trials take contexts in turn; a mission's context switches at random times: write the plan's `context_switches: Some((among: [...], every: N))` instead (docs/missions.md#context-switches)",
    )
}

fn refuse_goal_changes<'de, D: serde::Deserializer<'de>>(d: D) -> Result<(), D::Error> {
    refused(
        d,
        "`goal_changes`: goal changes are simulated in experiment suites, not yet in missions: leave `goal_changes` out of a mission plan (docs/missions.md)",
    )
}

fn refuse_stated<'de, D: serde::Deserializer<'de>>(d: D) -> Result<(), D::Error> {
    refused(
        d,
        "`stated`: what operators state up front is simulated in experiment suites, not yet in missions: leave `stated` out of a mission plan (docs/missions.md)",
    )
}

/// A plan's competence section: the standard the robot holds its own competence to
/// ([`CompetenceStandard`]), and whether an answered overtrust alert offers a safer behavior.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CompetenceSpec {
    /// The most any part may fall short per command, in `[0, 1]`.
    pub at_most: f64,
    /// Parts held to another bound than `at_most`, by name.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub parts: Vec<(Cause, f64)>,
    /// Whether an answered overtrust alert offers a safer behavior, which the operator
    /// takes when it trusts it too; absent: false, the operator only looks afresh.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub offer_safer: bool,
}

impl CompetenceSpec {
    /// The standard alone.
    pub fn standard(&self) -> CompetenceStandard {
        CompetenceStandard {
            at_most: self.at_most,
            parts: self.parts.clone(),
        }
    }
}
