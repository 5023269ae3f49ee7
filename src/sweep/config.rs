//! A sweep as written in RON: its base suite, seeds, parameters (and how each reads,
//! labels and sets its values) and design.

use crate::suite::{SuiteConfig, arm_name_lists, some_arm_names};
use lab::ArmName;
use serde::{Deserialize, Serialize};
use std::num::NonZeroU32;
use std::path::PathBuf;
use trust::{Retention, Thresholds, TimeUnit};

/// A sweep, as written in RON.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepConfig {
    /// The suite every cell starts from: `embedded` (the catalog's embedded suite) or a
    /// RON file, relative to the sweep file.
    pub suite: SuiteSource,
    /// Trials per experiment and arm (overrides the suite's).
    #[serde(default)]
    pub trials: Option<NonZeroU32>,
    /// The arms (overrides the suite's), written as a suite writes them.
    #[serde(default, deserialize_with = "some_arm_names")]
    pub arms: Option<Vec<ArmName>>,
    /// The master seeds; every cell runs once per seed.
    pub seeds: Vec<u64>,
    /// The parameters to vary.
    pub parameters: Vec<Parameter>,
    /// How cells are formed from the parameters.
    #[serde(default)]
    pub design: Design,
}

/// Where a sweep's base suite comes from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum SuiteSource {
    /// The catalog's embedded suite (what `reproduce` runs; for the UGV catalog, the
    /// paper's seven experiments).
    Embedded,
    /// A suite config file, relative to the sweep file.
    File(PathBuf),
}

/// How a sweep's cells are formed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum Design {
    /// The base suite, then each parameter's other values one at a time, the rest as in
    /// the base.
    #[default]
    OneAtATime,
    /// Every combination of the parameters' values.
    Grid,
}

/// A parameter and the values it takes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum Parameter {
    /// Algorithm 2's threshold.
    Lambda(Vec<f64>),
    /// The trust thresholds.
    Thresholds(Vec<Thresholds>),
    /// The retention reading.
    Retention(Vec<Retention>),
    /// The unit of `t`.
    TimeUnit(Vec<TimeUnit>),
    /// A reading the catalog's domain declares, by name, and its values, e.g.
    /// `reading("patrol_weights", ["as_written", "three_and_one"])`.
    Reading(String, Vec<String>),
    /// The arms compared, each list written as a suite writes its arms.
    Arms(#[serde(deserialize_with = "arm_name_lists")] Vec<Vec<ArmName>>),
}

impl Parameter {
    /// The parameter's name in reports.
    pub fn name(&self) -> &str {
        match self {
            Parameter::Lambda(_) => "lambda",
            Parameter::Thresholds(_) => "thresholds",
            Parameter::Retention(_) => "retention",
            Parameter::TimeUnit(_) => "time_unit",
            Parameter::Reading(name, _) => name,
            Parameter::Arms(_) => "arms",
        }
    }

    pub(super) fn len(&self) -> usize {
        match self {
            Parameter::Lambda(v) => v.len(),
            Parameter::Thresholds(v) => v.len(),
            Parameter::Retention(v) => v.len(),
            Parameter::TimeUnit(v) => v.len(),
            Parameter::Reading(_, v) => v.len(),
            Parameter::Arms(v) => v.len(),
        }
    }

    /// Value `i` as labels show it, e.g. `0.9`.
    pub(super) fn value(&self, i: usize) -> String {
        match self {
            Parameter::Lambda(v) => v[i].to_string(),
            Parameter::Thresholds(v) => format!("{}/{}", v[i].trustworthy, v[i].untrustworthy),
            Parameter::Retention(v) => ron_name(&v[i]),
            Parameter::TimeUnit(v) => ron_name(&v[i]),
            Parameter::Reading(_, v) => v[i].clone(),
            Parameter::Arms(v) => ArmName::join(&v[i], "+"),
        }
    }

    /// The first value listed twice (after an equal one), if any.
    pub(super) fn repeated(&self) -> Option<usize> {
        fn first<T: PartialEq>(values: &[T]) -> Option<usize> {
            (1..values.len()).find(|&j| values[..j].contains(&values[j]))
        }
        match self {
            Parameter::Lambda(v) => first(v),
            Parameter::Thresholds(v) => first(v),
            Parameter::Retention(v) => first(v),
            Parameter::TimeUnit(v) => first(v),
            Parameter::Reading(_, v) => first(v),
            Parameter::Arms(v) => first(v),
        }
    }

    /// Whether value `i` is the one `base` has already.
    pub(super) fn is_in(&self, i: usize, base: &SuiteConfig) -> bool {
        match self {
            Parameter::Lambda(v) => v[i] == base.adapter.lambda,
            Parameter::Thresholds(v) => v[i] == base.adapter.thresholds,
            Parameter::Retention(v) => v[i] == base.adapter.retention,
            Parameter::TimeUnit(v) => v[i] == base.adapter.time_unit,
            Parameter::Reading(name, v) => base.readings.get(name) == Some(&v[i]),
            Parameter::Arms(v) => v[i] == base.arms,
        }
    }

    /// Sets value `i` in `suite`; returns its label, e.g. `lambda=0.9`.
    pub(super) fn apply(&self, i: usize, suite: &mut SuiteConfig) -> String {
        match self {
            Parameter::Lambda(v) => suite.adapter.lambda = v[i],
            Parameter::Thresholds(v) => suite.adapter.thresholds = v[i],
            Parameter::Retention(v) => suite.adapter.retention = v[i],
            Parameter::TimeUnit(v) => suite.adapter.time_unit = v[i],
            Parameter::Reading(name, v) => {
                suite.readings.insert(name.clone(), v[i].clone());
            }
            Parameter::Arms(v) => suite.arms.clone_from(&v[i]),
        }
        format!("{}={}", self.name(), self.value(i))
    }
}

/// A unit variant's RON spelling.
fn ron_name(value: &impl Serialize) -> String {
    ron::to_string(value).expect("plain data serializes")
}
