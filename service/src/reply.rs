//! Writing the session's answers: one JSON object each, with an `ok` field naming what it
//! is or an `error` field saying what went wrong, and behaviors in real units.
//!
//! A [`Reply`] is either a JSON value or the case listing, which is written case by case
//! as it is copied from the shared memory, so a listing never holds the case base twice.
//! An [`Answer`] is a reply with the request's `id`, written as the controller sent it.

use crate::request::RequestId;
use crate::shared::SharedCases;
use crate::store::StoreId;
use cbr_core::{Behavior, BehaviorSpace, CaseId, Context};
use serde::ser::{SerializeMap, Serializer};
use serde_json::{Map, Value, json};
use std::io::{self, Write};
use std::sync::Arc;
use trust::named::named_behavior;
use trust::{
    Account, Alert, Cause, CompetenceAlert, CompetenceJudge, EpisodeReport, Evaluated, Explanation,
    Grounds, Next, Outcome, Source, Thresholds, calibrate,
};

/// How many cases a listing copies from the shared memory at a time.
const LISTING_CHUNK: usize = 256;

/// One reply, ready to be written as one line.
pub enum Reply {
    /// A JSON object.
    Json(Value),
    /// `{"ok": "cases", "cases": [...]}`, streamed.
    Cases(CaseListing),
}

/// The cases held when a `cases` request was handled, to be streamed.
pub struct CaseListing {
    /// The memory the cases are copied from.
    pub cases: Arc<SharedCases>,
    /// The behavior space, to show behaviors in real units.
    pub space: Arc<BehaviorSpace>,
    /// How many cases to list (those held when the request was handled).
    pub count: usize,
}

/// A reply with the request's `id` (when one was given), echoed as the controller wrote it.
pub struct Answer {
    /// The reply.
    pub reply: Reply,
    /// The request's `id`.
    pub id: Option<RequestId>,
}

impl Reply {
    /// The reply with the request's `id` (when one was given).
    pub fn with_id(self, id: Option<RequestId>) -> Answer {
        Answer { reply: self, id }
    }

    /// Writes the reply and its newline.
    pub fn write_line(&self, out: &mut dyn Write) -> io::Result<()> {
        self.write(None, out)?;
        out.write_all(b"\n")
    }

    /// Writes the reply; an object gets `id`'s text as its `id` field (in place of one it
    /// has, or last).
    fn write(&self, id: Option<&RequestId>, out: &mut dyn Write) -> io::Result<()> {
        match (self, id) {
            (Reply::Json(Value::Object(map)), Some(id)) => {
                write_with_id(map, id, out)?;
            }
            (Reply::Json(value), _) => serde_json::to_writer(&mut *out, value)?,
            (Reply::Cases(listing), id) => listing.write(id, out)?,
        }
        Ok(())
    }
}

impl Answer {
    /// Writes the answer and its newline.
    pub fn write_line(&self, out: &mut dyn Write) -> io::Result<()> {
        self.reply.write(self.id.as_ref(), out)?;
        out.write_all(b"\n")
    }

    /// The answer as one JSON value (for callers in the same process, and tests; a number
    /// `id` is then read as `serde_json` reads numbers).
    pub fn into_value(self) -> Value {
        let mut bytes = Vec::new();
        self.reply
            .write(self.id.as_ref(), &mut bytes)
            .expect("writing to memory");
        serde_json::from_slice(&bytes).expect("a reply is JSON")
    }
}

/// Writes the object `map` with `id` as its `id` field, where `map` has one, or last.
fn write_with_id(map: &Map<String, Value>, id: &RequestId, out: &mut dyn Write) -> io::Result<()> {
    let mut serializer = serde_json::Serializer::new(out);
    let has_id = map.contains_key("id");
    let mut object = serializer.serialize_map(Some(map.len() + usize::from(!has_id)))?;
    for (key, value) in map {
        if key == "id" {
            object.serialize_entry(key, id)?;
        } else {
            object.serialize_entry(key, value)?;
        }
    }
    if !has_id {
        object.serialize_entry("id", id)?;
    }
    object.end()?;
    Ok(())
}

impl CaseListing {
    fn write(&self, id: Option<&RequestId>, out: &mut dyn Write) -> io::Result<()> {
        out.write_all(br#"{"ok":"cases","cases":["#)?;
        let mut written = 0;
        while written < self.count {
            let chunk = self
                .cases
                .copy_range(written, LISTING_CHUNK.min(self.count - written));
            if chunk.is_empty() {
                break;
            }
            for (id, case) in &chunk {
                if written > 0 {
                    out.write_all(b",")?;
                }
                let mut entry = json!({
                    "id": id,
                    "evaluated": evaluated(&self.space, &case.problem.evaluated),
                    "solution": behavior(&self.space, &case.solution),
                });
                add_context(&mut entry, &case.problem.context);
                serde_json::to_writer(&mut *out, &entry)?;
                written += 1;
            }
        }
        out.write_all(b"]")?;
        if let Some(id) = id {
            out.write_all(br#","id":"#)?;
            out.write_all(id.as_json().as_bytes())?;
        }
        out.write_all(b"}")
    }
}

/// `reply` with the robot's `context` under `"context"`, unless it is the default one
/// (replies in the default context are as they were before contexts).
pub fn add_context(reply: &mut Value, context: &Context) {
    if !context.is_default() {
        reply["context"] = json!(context);
    }
}

/// An error reply: `{"error": message}`.
pub fn error(message: impl std::fmt::Display) -> Value {
    json!({ "error": message.to_string() })
}

/// A behavior in real units: `{"speed": 3.5, "padding": 0.4}`; categorical components give
/// their label.
pub fn behavior(space: &BehaviorSpace, behavior: &Behavior) -> Value {
    Value::Object(named_behavior(space, behavior))
}

/// An outcome as the protocol's outcome report spells it (what a controller sends, and so
/// what it may send back): `{"outcome": "interrupted", "weight": 1.0, "duration_s": 10.0,
/// "observed": ["collision"], "stated": null}`, the observations by the names the domain
/// declares (`observations`, bit `i` the `i`-th), and `confidence` when the robot assessed
/// itself.
pub fn outcome(outcome: &Outcome, observations: &[Cause]) -> Value {
    let observed: Vec<&str> = outcome
        .observed
        .indices()
        .filter_map(|i| observations.get(i).map(Cause::as_str))
        .collect();
    let mut report = json!({
        "outcome": outcome.kind,
        "weight": outcome.weight,
        "duration_s": outcome.duration_s,
        "observed": observed,
        "stated": outcome.stated,
    });
    if let Some(confidence) = outcome.confidence {
        report["confidence"] = json!(confidence);
    }
    report
}

/// Evaluated pairs: `[{"behavior": {...}, "time": 12.5}, ...]`.
pub fn evaluated(space: &BehaviorSpace, pairs: &[Evaluated]) -> Value {
    pairs
        .iter()
        .map(|e| json!({ "behavior": behavior(space, &e.behavior), "time": e.time }))
        .collect()
}

/// The account of a behavior (given up, or in use): its commands, its trust estimate and
/// the reasons attributed to its untrustworthy commands, each with its evidence.
pub fn account(space: &BehaviorSpace, account: &Account) -> Value {
    json!({
        "behavior": behavior(space, &account.behavior),
        "commands": account.commands,
        "untrustworthy": account.untrustworthy,
        "trust": account.estimate,
        "reasons": account.reasons.iter().map(|r| json!({
            "cause": r.cause,
            "weight": r.weight,
            "stated": r.stated,
            "perceived": r.perceived,
            "inferred": r.inferred,
        })).collect::<Vec<_>>(),
    })
}

/// An explanation in real units, with its plain sentence: `given_up` (an [`account`]),
/// `next` (`source` `case` with the case's store id, its similarity and the behaviors it
/// matched; `search` with the strategy and its rationale; or `kept`) and `sentence`.
/// `case_id` gives a reused case's store id.
pub fn explanation(
    space: &BehaviorSpace,
    explanation: &Explanation,
    case_id: &dyn Fn(CaseId) -> Option<StoreId>,
) -> Value {
    let next = match &explanation.next {
        Next::Switch {
            behavior: b,
            source,
            grounds,
        } => {
            let mut next = json!({
                "source": match source {
                    Source::Case { .. } => "case",
                    Source::Search => "search",
                },
                "behavior": behavior(space, b),
            });
            if let Source::Case { case, similarity } = source {
                next["case"] = json!(case_id(*case));
                next["similarity"] = json!(similarity);
            }
            match grounds {
                Grounds::Matches { matched, given_up } => {
                    next["matched"] = json!(matched);
                    next["given_up"] = json!(given_up);
                }
                Grounds::Rationale {
                    strategy,
                    rationale,
                } => {
                    next["strategy"] = json!(strategy);
                    next["rationale"] = json!(rationale);
                }
            }
            next
        }
        Next::Kept {
            behavior: b,
            trustworthy,
            commands,
            estimate,
        } => json!({
            "source": "kept",
            "behavior": behavior(space, b),
            "trustworthy": trustworthy,
            "commands": commands,
            "trust": estimate,
        }),
    };
    let sentence = explanation.sentence_naming_cases(space, &|case| {
        case_id(case).map_or_else(|| "(unknown)".to_owned(), |id| id.to_string())
    });
    json!({
        "given_up": explanation.given_up.as_ref().map(|g| account(space, g)),
        "next": next,
        "sentence": sentence,
    })
}

/// An alert (mission mode): the behavior kept, the operator's estimate of it (`trust`), the
/// robot's own record of it (`own_record`), the commands that record covers and how many of
/// them had a signal the operator let pass (`unacknowledged`), and a `sentence` asking the
/// operator to supervise, for its screen.
pub fn alert(space: &BehaviorSpace, alert: &Alert) -> Value {
    let sentence = format!(
        "Please supervise {}: the operator's trust is {:+.2}, but {} of the last {} commands \
         showed signs operators stop the robot for when attentive, and were let pass (the \
         robot's own record makes a lapse of attention {:.0} times likelier than attention).",
        space.display(&alert.behavior),
        alert.estimate,
        alert.unacknowledged,
        alert.commands,
        alert.own_record.exp(),
    );
    json!({
        "ok": "alert",
        "behavior": behavior(space, &alert.behavior),
        "trust": alert.estimate,
        "own_record": alert.own_record,
        "commands": alert.commands,
        "unacknowledged": alert.unacknowledged,
        "sentence": sentence,
    })
}

/// The calibration of the watched `behavior` (mission mode with a competence standard):
/// the operator's `estimate` beside the robot's judgement of its own competence, as
/// `{"verdict": "calibrated" | "overtrust" | "undertrust", "short": [...], "competence":
/// {...}}` (`short`, for overtrust, the parts above the standard by the robot's best
/// estimate).
pub fn calibration(
    judge: &CompetenceJudge<'_>,
    behavior: Behavior,
    estimate: f64,
    thresholds: &Thresholds,
) -> Value {
    let competence = judge.competence(behavior);
    let mut reply = json!(calibrate(
        estimate,
        thresholds,
        &competence,
        judge.standard()
    ));
    reply["competence"] = json!({
        "commands": competence.commands,
        "parts": competence.parts,
    });
    reply
}

/// An overtrust alert (mission mode with a competence standard): the behavior kept, the
/// operator's estimate of it (`trust`), the parts of the robot's own assessment above the
/// standard (`short`), the assessment itself (`competence`: the commands behind it and
/// each part's estimated chance per command, the model's prediction and the commands the
/// robot perceived it in), the safer behavior it offers (`offer`: one an operator trusted
/// before that the robot judges competent, taken with `{"request": "accept_offer"}`; `null`
/// when it knows none), and a `sentence` asking the operator to choose, for its screen.
pub fn overtrust(space: &BehaviorSpace, alert: &CompetenceAlert) -> Value {
    let short: Vec<String> = alert
        .competence
        .parts
        .iter()
        .filter(|p| alert.short.contains(&p.name))
        .map(|p| format!("{} {:.2}", p.name, p.rate.unwrap_or(f64::NAN)))
        .collect();
    let choices = match &alert.offer {
        Some(offer) => format!(
            "Keep it, supervise it, or take {}, which the robot judges competent.",
            space.display(offer)
        ),
        None => "Keep it, supervise it, or ask for a safer behavior.".to_owned(),
    };
    let sentence = format!(
        "Please choose: the operator trusts {} (trust {:+.2}), but the robot judges it short of \
         its standard, per command: {}. {choices}",
        space.display(&alert.behavior),
        alert.estimate,
        short.join(", "),
    );
    json!({
        "ok": "overtrust",
        "behavior": behavior(space, &alert.behavior),
        "trust": alert.estimate,
        "short": alert.short,
        "competence": {
            "commands": alert.competence.commands,
            "parts": alert.competence.parts,
        },
        "offer": alert.offer.map(|offer| behavior(space, &offer)),
        "sentence": sentence,
    })
}

/// The summary of a finished episode, under the `ok` name `kind`: `retained` is the store
/// id of the case it retained, `cases` the number of cases held, `explanation` why it
/// ended (an [`explanation`], for a settled episode).
pub fn episode_end(
    kind: &str,
    space: &BehaviorSpace,
    report: &EpisodeReport,
    retained: Option<StoreId>,
    cases: usize,
    explanation: Option<Value>,
) -> Value {
    json!({
        "explanation": explanation,
        "ok": kind,
        "behavior": behavior(space, &report.settled),
        "trustworthy": report.found_trustworthy,
        "behaviors_evaluated": report.behaviors_evaluated,
        "commands": report.commands,
        "searched": report.searched,
        "reused": report.reused,
        "retained": retained,
        "cases": cases,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use cbr_core::NamedComponent;

    #[test]
    fn an_outcome_is_written_as_the_report_that_reads_back_to_it() {
        let (bump, late) = (Cause::from_static("bump"), Cause::from_static("late"));
        let declared = [trust::DeclaredCause {
            name: late,
            default_weight: None,
        }];
        let observations = [bump, late];
        let outcome = Outcome::interrupted(0.5, 12.0)
            .observing(trust::Observations::NONE.with(1))
            .stating(Some(late));
        let value = super::outcome(&outcome, &observations);
        assert_eq!(
            value.to_string(),
            r#"{"outcome":"interrupted","weight":0.5,"duration_s":12.0,"observed":["late"],"stated":"late"}"#
        );
        let vocabulary = crate::request::Vocabulary {
            causes: &declared,
            observations: &observations,
        };
        let parsed = crate::request::parse_line(value.to_string().as_bytes(), vocabulary);
        assert_eq!(parsed.request, Ok(crate::Request::Outcome(outcome)));
    }

    #[test]
    fn a_self_assessment_is_written_only_when_the_robot_made_one() {
        let assessed = Outcome::completed(1.0, 2.0).assessing(Some(0.25));
        assert_eq!(
            super::outcome(&assessed, &[]).to_string(),
            r#"{"outcome":"completed","weight":1.0,"duration_s":2.0,"observed":[],"stated":null,"confidence":0.25}"#
        );
        let parsed = crate::request::parse_line(
            super::outcome(&assessed, &[]).to_string().as_bytes(),
            crate::request::Vocabulary {
                causes: &[],
                observations: &[],
            },
        );
        assert_eq!(parsed.request, Ok(crate::Request::Outcome(assessed)));
    }

    #[test]
    fn an_alert_asks_for_supervision_in_real_units() {
        let space = BehaviorSpace::new(vec![
            NamedComponent::numeric("speed", "m/s", 0.5, 0.5, 20).unwrap(),
            NamedComponent::numeric("padding", "m", 0.1, 0.1, 20).unwrap(),
        ])
        .unwrap();
        let raised = Alert {
            behavior: Behavior::new(&[6, 3]),
            estimate: 5.0,
            own_record: 100f64.ln(),
            commands: 9,
            unacknowledged: 4,
        };
        assert_eq!(
            alert(&space, &raised).to_string(),
            r#"{"ok":"alert","behavior":{"speed":3.5,"padding":0.4},"trust":5.0,"own_record":4.605170185988092,"commands":9,"unacknowledged":4,"sentence":"Please supervise speed=3.5 m/s, padding=0.4 m: the operator's trust is +5.00, but 4 of the last 9 commands showed signs operators stop the robot for when attentive, and were let pass (the robot's own record makes a lapse of attention 100 times likelier than attention)."}"#
        );
    }

    #[test]
    fn behaviors_are_written_in_real_units() {
        let space = BehaviorSpace::new(vec![
            NamedComponent::numeric("padding", "m", 0.1, 0.1, 20).unwrap(),
            NamedComponent::categorical("planner", &["astar", "rrt"]).unwrap(),
        ])
        .unwrap();
        let b = Behavior::new(&[2, 1]);
        assert_eq!(
            behavior(&space, &b).to_string(),
            r#"{"padding":0.3,"planner":"rrt"}"#
        );
    }
}
