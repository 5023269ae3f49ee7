//! What a report is made of ([`ReportEntry`]: one experiment's results with what
//! describes them), where it came from ([`Provenance`]), and why writing it can fail
//! ([`ReportError`]).

use crate::experiment::record::ExperimentResult;
use crate::reference::known_operator::ExperimentLimit;
use crate::reference::landscape::Landscape;
use crate::report::plot::PlotError;
use crate::report::timeline::Timeline;
use cbr_core::BehaviorSpace;
use files::FileError;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// One experiment's results with what the report needs to describe them.
pub struct ReportEntry<'a> {
    /// The results.
    pub result: &'a ExperimentResult,
    /// The scenario (domain) name, e.g. `movement`.
    pub scenario: &'a str,
    /// The configured operator: a name, `random`, or the name of a population.
    pub operator: &'a str,
    /// The behavior space, to show behaviors in real units.
    pub space: &'a BehaviorSpace,
    /// The operator's landscapes the final behaviors are drawn over, one per pair of
    /// [`component_pairs`](crate::report::component_pairs) ([`finals_landscapes`](crate::report::finals_landscapes)); empty to draw them on white.
    pub landscapes: &'a [Landscape],
    /// The known-operator limit of the experiment ([`crate::reference::known_operator`]), when
    /// computed.
    pub limit: Option<&'a ExperimentLimit>,
    /// A sample trial traced command by command ([`crate::report::timeline`]), when traced.
    pub timeline: Option<&'a Timeline>,
    /// The arm every other arm is tested against (p-values) and measured against (effect
    /// sizes); when it is not among the arms, no arm is.
    pub reference: &'a str,
    /// The master seed of the experiments, from which the effect sizes' bootstrap
    /// streams derive ([`crate::seeds::Purpose::Bootstrap`]).
    pub seed: u64,
}

/// Why the report could not be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReportError {
    /// A file or folder could not be written.
    #[error(transparent)]
    Io(#[from] FileError),
    /// A plot could not be drawn.
    #[error(transparent)]
    Plot(#[from] PlotError),
}

/// Where the report came from: the tool, its version and commit, the command line, and
/// what a replay of its trials must find unchanged.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Provenance {
    /// The program that wrote the report.
    pub tool: String,
    /// Its version.
    pub version: String,
    /// The source commit it was built from, when known.
    pub git_commit: Option<String>,
    /// The command line, program first.
    pub command_line: Vec<String>,
    /// What `explain` checks before it replays a trial of the report (absent in reports
    /// of earlier versions).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub replay: Option<Replay>,
}

/// What a faithful replay of a report's trials needs unchanged, besides the tool and its
/// version: the config it ran, and the cases each arm started from, by content hash.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Replay {
    /// The content hash of the report's `config.ron`, as written.
    pub config: String,
    /// The content hash of the cases each arm started from (a run given saved case bases),
    /// by experiment, then arm; an arm that started from none is not listed.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub starting_cases: BTreeMap<String, BTreeMap<String, String>>,
}
