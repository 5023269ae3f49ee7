//! A study's records as files: every event (`events.jsonl`), the ratings beside the
//! adapter's inverse trust estimate (`ratings.csv`), and each participant's episode in the
//! terms of a report's `trials.jsonl` (`episodes.jsonl`). Read from the database alone:
//! what was recorded, not what a replay would give.

use crate::db::{Db, DbError, Event, Participant, open_existing};
use crate::participant::{Conduct, ConductError, outcome_kind};
use crate::study::{Study, StudyError};
use serde_json::{Map, Value, json};
use std::collections::BTreeMap;
use std::path::Path;
use trust::OutcomeKind;

/// Why a study could not be exported or reported.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ExportError {
    /// The database could not be read.
    #[error(transparent)]
    Db(#[from] DbError),
    /// The study recorded in it no longer parses.
    #[error(transparent)]
    Study(#[from] StudyError),
    /// The output folder could not be written.
    #[error("{path}: {source}")]
    Write {
        /// The file.
        path: String,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// The output folder is refused (not empty, not writable, a file).
    #[error(transparent)]
    Folder(#[from] files::FolderError),
}

/// A study's database with the study it holds.
pub struct Recorded {
    /// The database.
    pub db: Box<dyn Db>,
    /// The study.
    pub study: Study,
}

impl Recorded {
    /// Opens the study database at `location` (it must exist).
    pub fn open(location: &str) -> Result<Self, ExportError> {
        let db = open_existing(location)?;
        let text = db.study_text()?;
        let study = Study::from_ron(&text, Path::new(&format!("{location} (its study)")))?;
        Ok(Self { db, study })
    }

    /// Every participant with their events.
    pub fn everyone(&self) -> Result<Vec<(Participant, Vec<Event>)>, DbError> {
        self.db
            .participants()?
            .into_iter()
            .map(|p| {
                let events = self.db.events(p.number)?;
                Ok((p, events))
            })
            .collect()
    }
}

/// One event as `events.jsonl` writes it.
pub fn event_line(participant: &Participant, event: &Event) -> Value {
    let mut line = json!({
        "participant": participant.pseudonym(),
        "seq": event.seq,
        "at_ms": event.at_ms,
        "kind": event.kind,
    });
    if let Value::Object(fields) = &event.body {
        for (k, v) in fields {
            line[k] = v.clone();
        }
    }
    line
}

/// The researcher's overview: one row per participant.
pub fn overview(conduct: &Conduct) -> Result<Value, ConductError> {
    let mut rows = Vec::new();
    for participant in conduct.db.participants()? {
        let events = conduct.db.events(participant.number)?;
        let replayed = conduct.replay(&participant, &events)?;
        rows.push(json!({
            "participant": participant.pseudonym(),
            "condition": conduct.study.conditions[participant.condition].name,
            "phase": replayed.phase(conduct, participant.condition).name(),
            "commands": replayed.commands,
            "behaviors": replayed.behaviors,
            "ratings": replayed.rated,
            "events": events.len(),
        }));
    }
    Ok(Value::Array(rows))
}

/// What one participant's events say, for exports and reports.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Summary {
    /// The condition's name.
    pub condition: String,
    /// The arm.
    pub arm: String,
    /// Commands closed.
    pub commands: u64,
    /// Commands the participant stopped.
    pub stops: u64,
    /// Commands that were not completed (stopped or failed).
    pub untrustworthy: u64,
    /// The last behavior.
    pub last: Map<String, Value>,
    /// The reply that ended the episode (`settled` or `abandoned`), if it ended.
    pub ended: Option<Value>,
    /// Switches by source: `search` and `case`.
    pub searched: u32,
    /// Switches to a reused case.
    pub reused: u32,
    /// Per switch, the reason the adapter gave and the cause the participant stated most.
    pub given_up: Vec<(Option<String>, Option<String>)>,
    /// The causes stated, counted.
    pub stated: BTreeMap<String, u32>,
    /// Each rating: (number, after command, behaviors by then, value, estimate).
    pub ratings: Vec<(u64, u64, u64, f64, f64)>,
}

/// What `participant`'s `events` say.
pub fn summarize(study: &Study, participant: &Participant, events: &[Event]) -> Summary {
    let condition = &study.conditions[participant.condition];
    let mut summary = Summary {
        condition: condition.name.clone(),
        arm: condition.arm.clone(),
        ..Summary::default()
    };
    let mut behavior_stated: BTreeMap<String, u32> = BTreeMap::new();
    for event in events {
        let body = &event.body;
        match event.kind.as_str() {
            "statement" => {
                if let Some(cause) = body["cause"].as_str() {
                    *summary.stated.entry(cause.to_owned()).or_default() += 1;
                    *behavior_stated.entry(cause.to_owned()).or_default() += 1;
                }
            }
            "stop" => summary.stops += 1,
            "rating" => summary.ratings.push((
                body["number"].as_u64().unwrap_or(0),
                body["after_command"].as_u64().unwrap_or(0),
                body["behaviors"].as_u64().unwrap_or(0),
                body["value"].as_f64().unwrap_or(f64::NAN),
                body["estimate"].as_f64().unwrap_or(f64::NAN),
            )),
            "decision" => {
                summary.commands += 1;
                if outcome_kind(&body["report"]) != Some(OutcomeKind::Completed) {
                    summary.untrustworthy += 1;
                }
                let reply = &body["reply"];
                if let Some(Value::Object(b)) = reply.get("behavior") {
                    summary.last = b.clone();
                }
                if reply["ok"] == "switch" {
                    match reply["source"].as_str() {
                        Some("case") => summary.reused += 1,
                        _ => summary.searched += 1,
                    }
                    let reason = reply["explanation"]["given_up"]["reasons"][0]["cause"]
                        .as_str()
                        .map(str::to_owned);
                    let most = behavior_stated
                        .iter()
                        .max_by_key(|(_, n)| **n)
                        .map(|(c, _)| c.clone());
                    summary.given_up.push((reason, most));
                    behavior_stated.clear();
                }
                let ended = match body.get("abandon_reply") {
                    Some(r) if !r.is_null() => Some(r.clone()),
                    _ if reply["ok"] == "settled" => Some(reply.clone()),
                    _ => None,
                };
                if ended.is_some() {
                    summary.ended = ended;
                }
            }
            _ => {}
        }
    }
    summary
}

/// The participant's episode as a line of a report's `trials.jsonl`: the condition is the
/// experiment (`study/CONDITION`), the participant is the operator, their number the trial.
/// The participant's true reasons are not known: `true_causes` holds what they stated, and
/// each given-up behavior's `truth` the cause they stated most for it.
pub fn episode_line(
    study: &Study,
    participant: &Participant,
    summary: &Summary,
    initial: &Value,
) -> Value {
    let ended = summary.ended.as_ref();
    let found = ended.is_some_and(|r| r["ok"] == "settled" && r["trustworthy"] == true);
    json!({
        "experiment": format!("study/{}", summary.condition),
        "scenario": study.domain,
        "operator": participant.pseudonym(),
        "arm": summary.arm,
        "trial": participant.number,
        "behaviors_evaluated": ended.and_then(|r| r["behaviors_evaluated"].as_u64()).unwrap_or(summary.given_up.len() as u64 + 1),
        "commands": summary.commands,
        "untrustworthy": summary.untrustworthy,
        "found_trustworthy": found,
        "final": summary.last,
        "initial": initial,
        "searched": summary.searched,
        "reused": summary.reused,
        "retained": ended.is_some_and(|r| r["retained"].is_number()),
        "truncated": ended.is_some_and(|r| r["ok"] == "abandoned"),
        "true_causes": summary.stated,
        "given_up": summary.given_up.iter().map(|(reason, truth)| json!({
            "reason": reason,
            "truth": truth,
            "right": reason.is_some() && reason == truth,
        })).collect::<Vec<_>>(),
    })
}

/// The first behavior of a participant, in the adapter's units: the behavior the first
/// decision gave up, or kept.
fn initial_behavior(events: &[Event]) -> Value {
    for event in events {
        if event.kind == "decision" {
            let reply = &event.body["reply"];
            if let Some(given_up) = reply["explanation"]["given_up"]["behavior"].as_object() {
                return Value::Object(given_up.clone());
            }
            if let Some(b) = reply["behavior"].as_object() {
                return Value::Object(b.clone());
            }
        }
    }
    Value::Object(Map::new())
}

/// Writes `events.jsonl`, `ratings.csv` and `episodes.jsonl` of the study at `location`
/// into the folder `out` (made when absent; an earlier export there is replaced).
pub fn export(location: &str, out: &Path) -> Result<usize, ExportError> {
    let recorded = Recorded::open(location)?;
    let everyone = recorded.everyone()?;
    let (low, high) = recorded.study.rating.scale.range();
    let mut events = String::new();
    let mut ratings = String::from(
        "participant,condition,number,after_command,behaviors,value,scale_min,scale_max,trust_estimate\n",
    );
    let mut episodes = String::new();
    for (participant, list) in &everyone {
        for event in list {
            events.push_str(&event_line(participant, event).to_string());
            events.push('\n');
        }
        let summary = summarize(&recorded.study, participant, list);
        for (number, after, behaviors, value, estimate) in &summary.ratings {
            ratings.push_str(&format!(
                "{},{},{number},{after},{behaviors},{value},{low},{high},{estimate}\n",
                participant.pseudonym(),
                csv_field(&summary.condition),
            ));
        }
        let initial = initial_behavior(list);
        episodes
            .push_str(&episode_line(&recorded.study, participant, &summary, &initial).to_string());
        episodes.push('\n');
    }
    write_all(
        out,
        &[
            ("events.jsonl", events),
            ("ratings.csv", ratings),
            ("episodes.jsonl", episodes),
        ],
    )?;
    Ok(everyone.len())
}

/// `text` as one CSV field (quoted when it holds a comma, a quote or a line break).
pub fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_owned()
    }
}

/// Writes each `(name, text)` into `out`, each file whole (a temporary file renamed).
pub(crate) fn write_all(out: &Path, files_: &[(&str, String)]) -> Result<(), ExportError> {
    files::output::ensure_writable_dir(out)?;
    for (name, text) in files_ {
        files::write_file_in(out, name, text).map_err(|e| ExportError::Write {
            path: out.join(name).display().to_string(),
            source: std::io::Error::other(e.to_string()),
        })?;
    }
    Ok(())
}
