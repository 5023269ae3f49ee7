//! What a report records so that `trustcbr explain` replays its trials faithfully, and
//! the check `explain` makes before it does.
//!
//! `explain` replays a trial from the report's `config.ron`, from the saved case bases it
//! is given, with the running tool: the story is the trial that ran only if all three are
//! what the run had. A report's `summary.json` records them ([`lab::report::Replay`] in its
//! provenance, beside the tool and version): the content hash of `config.ron` as written,
//! and of the cases each arm started from. [`check_replay`] refuses, naming what differs;
//! a report of an earlier version, which records none of it, is replayed with a warning.

use super::plan::Parts;
use super::saved_cases::saved_file;
use super::{StartingCases, SuiteConfig, SuiteError, arm_named};
use crate::catalog::Catalog;
use crate::config_file::content_hash;
use lab::report::{Replay, file_stems};
use lab::{ArmName, Domain};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use trust::TrustCaseBase;

/// Why a report's trial cannot be replayed as it ran.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReplayError {
    /// The suite cannot be run.
    #[error(transparent)]
    Suite(#[from] SuiteError),
    /// `summary.json` cannot be read as a report's.
    #[error("{}: {reason}", path.display())]
    Summary {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// Another tool or version wrote the report.
    #[error(
        "{report}: written by {wrote}, and this is {running}: its trials may not replay as they ran; run the report again with this version (`{tool} run {report}/config.ron`)"
    )]
    Version {
        /// The report folder.
        report: String,
        /// The tool and version that wrote it.
        wrote: String,
        /// The tool and version running.
        running: String,
        /// The running tool's name.
        tool: String,
    },
    /// `config.ron` was changed after the run.
    #[error(
        "{}: differs from the config the report ran (content hash {now}, the run's {ran}): explain replays from this file, so its story would not be the trial of trials.jsonl; restore the file, or run it again",
        path.display()
    )]
    Config {
        /// The config file.
        path: PathBuf,
        /// Its hash now.
        now: String,
        /// The hash the run recorded.
        ran: String,
    },
    /// The cases the arm would start from are not those it started from.
    #[error("experiment `{experiment}`, arm `{arm}`: {problem}")]
    Cases {
        /// The experiment.
        experiment: String,
        /// The arm.
        arm: String,
        /// What differs, and what to give.
        problem: String,
    },
}

/// The content hash of the cases a case base holds (their JSON form, so a file's layout
/// does not count).
fn cases_hash(cases: &TrustCaseBase) -> String {
    content_hash(
        serde_json::to_string(cases.cases())
            .expect("cases serialize")
            .as_bytes(),
    )
}

/// What a report of `config` (read from `origin`), run from `starting`, records for a
/// replay: the hash of `config_ron` (its `config.ron` as written) and of the cases each
/// case-reading arm of each experiment started from.
pub(crate) fn report_replay<C: Catalog>(
    catalog: &C,
    config: &SuiteConfig,
    origin: &Path,
    config_ron: &str,
    starting: Option<&StartingCases>,
) -> Result<Replay, SuiteError> {
    let mut starting_cases = BTreeMap::new();
    if let Some(starting) = starting {
        let parts = Parts::of(catalog, config, origin)?;
        let stems = file_stems(config.experiments.iter().map(|s| s.name()));
        for (k, (spec, stem)) in config.experiments.iter().zip(&stems).enumerate() {
            let domain = parts.domain(k);
            let mut arms = BTreeMap::new();
            for arm in &config.arms {
                if reads_cases(catalog, config, arm)
                    && let Some(cases) = starting.load(
                        stem,
                        arm.as_str(),
                        &spec.scenario,
                        domain.space(),
                        domain.contexts(),
                    )?
                {
                    arms.insert(arm.to_string(), cases_hash(&cases));
                }
            }
            if !arms.is_empty() {
                starting_cases.insert(spec.name(), arms);
            }
        }
    }
    Ok(Replay {
        config: content_hash(config_ron.as_bytes()),
        starting_cases,
    })
}

/// Checks, before `explain` replays a trial of arm `arm` in experiment `experiment` of the
/// report in `report`, that what the replay uses is what the run had: the tool and
/// version, `config.ron` (its text `config_text`, read as `config`), and the cases the arm
/// starts from in `starting`. Refuses with what differs; returns warnings for a report that
/// records nothing to check.
#[allow(clippy::too_many_arguments)]
pub fn check_replay<C: Catalog>(
    catalog: &C,
    report: &Path,
    config: &SuiteConfig,
    config_text: &str,
    starting: Option<&StartingCases>,
    experiment: &str,
    arm: &str,
) -> Result<Vec<String>, ReplayError> {
    let summary_path = report.join("summary.json");
    let unchecked = |what: &str| {
        vec![format!(
            "{}: {what}, so nothing shows that config.ron and the case bases are what the run had (a report of an earlier version?); the story is replayed from them as they are now",
            summary_path.display()
        )]
    };
    if !summary_path.is_file() {
        return Ok(unchecked("there is no summary.json"));
    }
    let summary_error = |reason: String| ReplayError::Summary {
        path: summary_path.clone(),
        reason,
    };
    let text = files::read_text_at_most(&summary_path, files::MAX_CASE_BASE_BYTES)
        .map_err(SuiteError::from)?;
    let summary: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| summary_error(e.to_string()))?;
    let provenance = &summary["provenance"];
    let running = catalog.tool();
    let wrote = (provenance["tool"].as_str(), provenance["version"].as_str());
    if let (Some(tool), Some(version)) = wrote
        && (tool != running.name || version != running.version)
    {
        return Err(ReplayError::Version {
            report: report.display().to_string(),
            wrote: format!("{tool} {version}"),
            running: format!("{} {}", running.name, running.version),
            tool: running.name,
        });
    }
    let replay: Replay = match provenance.get("replay") {
        None => return Ok(unchecked("its provenance records no `replay`")),
        Some(value) => serde_json::from_value(value.clone())
            .map_err(|e| summary_error(format!("provenance.replay: {e}")))?,
    };
    let now = content_hash(config_text.as_bytes());
    if now != replay.config {
        return Err(ReplayError::Config {
            path: report.join("config.ron"),
            now,
            ran: replay.config,
        });
    }
    let ran = replay
        .starting_cases
        .get(experiment)
        .and_then(|arms| arms.get(arm));
    let given = starting_hash(catalog, config, report, starting, experiment, arm)?;
    let cases_error = |problem: String| ReplayError::Cases {
        experiment: experiment.to_owned(),
        arm: arm.to_owned(),
        problem,
    };
    match (ran, given) {
        (None, None) => Ok(Vec::new()),
        (Some(ran), Some((_, now))) if *ran == now => Ok(Vec::new()),
        (Some(_), None) => Err(cases_error(
            "the run started it from saved case bases (`--cases`), and none is given: give the folder the run was given, with --cases".into(),
        )),
        (None, Some((file, _))) => Err(cases_error(format!(
            "the run started it with no case base, and --cases gives {}: explain it without --cases (or with a folder that holds no case base for it)",
            file.display()
        ))),
        (Some(ran), Some((file, now))) => Err(cases_error(format!(
            "{} holds other cases than the run started it from (content hash {now}, the run's {ran}): give the folder the run was given",
            file.display()
        ))),
    }
}

/// The file and content hash of the cases `arm` of `experiment` would start from in
/// `starting`, if any.
fn starting_hash<C: Catalog>(
    catalog: &C,
    config: &SuiteConfig,
    report: &Path,
    starting: Option<&StartingCases>,
    experiment: &str,
    arm: &str,
) -> Result<Option<(PathBuf, String)>, SuiteError> {
    let Some(starting) = starting else {
        return Ok(None);
    };
    let Some(arm) = config.arms.iter().find(|a| *a == arm) else {
        return Ok(None);
    };
    if !reads_cases(catalog, config, arm) {
        return Ok(None);
    }
    let stems = file_stems(config.experiments.iter().map(|s| s.name()));
    let Some(k) = config
        .experiments
        .iter()
        .position(|s| s.name() == experiment)
    else {
        return Ok(None);
    };
    let origin = report.join("config.ron");
    let parts = Parts::of(catalog, config, &origin)?;
    let spec = &config.experiments[k];
    let domain = parts.domain(k);
    let file = saved_file(&starting.dir, &stems[k], arm.as_str())?;
    Ok(starting
        .load(
            &stems[k],
            arm.as_str(),
            &spec.scenario,
            domain.space(),
            domain.contexts(),
        )?
        .map(|cases| (file, cases_hash(&cases))))
}

/// Whether the arm named `arm` of `config` reads cases, so starts from saved ones when a
/// run is given them (an unknown name reads none: the replay refuses it anyway).
fn reads_cases<C: Catalog>(catalog: &C, config: &SuiteConfig, arm: &ArmName) -> bool {
    arm_named(catalog, arm, config.adapter.retriever).is_ok_and(|a| a.reads_cases())
}
