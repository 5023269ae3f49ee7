//! Parsing one protocol line into a typed [`Request`].
//!
//! A line is a JSON object. An outcome report carries an `outcome` field; every other
//! request names itself in a `request` field. Any request may carry an `id` (a JSON
//! scalar) that the reply echoes as it was sent, byte for byte (a number is never read
//! into a double and written back). Unknown fields, wrong types, unknown names
//! and unusable numbers are refused with an error naming the field and what it allows.
//! An outcome report says what the robot knows: how the command ended, its weight and
//! duration, what the robot perceived (`observed`: names the served domain declares as
//! observations), when the operator gave one, its stated reason (`stated`: a cause the
//! domain declares) and, when the robot assesses itself, its confidence that the command
//! went as it should (`confidence`, in `[0, 1]`); an interruption may say instead of a
//! reason that the operator's goals changed (`goal_change: true`), which counts against
//! nothing (trust::goal_change). The operator's true reason is never sent:
//! the retired `cause` field is refused with the spelling to use.
//! A key given twice in an object (at any depth) is refused rather than last-wins, and a
//! UTF-8 byte-order mark before the object is skipped. Parsing never looks at the
//! adapter: it only says what was asked.

use cbr_core::Statement;
use serde::Deserialize;
use serde::de::{self, DeserializeOwned, MapAccess, SeqAccess, Visitor};
use serde_json::value::RawValue;
use serde_json::{Map, Value};
use std::fmt;
use trust::estimate::OutcomeError;
use trust::{
    Cause, DeclaredCause, Observations, Outcome, OutcomeKind, UndeclaredCause, find_declared,
};

/// How a `begin` request names the first behavior.
#[derive(Clone, Debug, PartialEq)]
pub enum BehaviorSpec {
    /// `"speed=3.5,padding=0.4"`.
    Text(String),
    /// `{"speed": 3.5, "padding": 0.4}`: component name and value (a number or a label),
    /// the value given as text.
    Values(Vec<(String, String)>),
}

/// The context a request names: each variable with its value, as given (checked against
/// the domain's context space by the session).
pub type ContextSettings = Vec<(String, String)>;

/// One request of the protocol.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Request {
    /// Start an episode, with the given behavior or one the server draws, in the context
    /// given (the robot's context so far when none is).
    Begin {
        /// The first behavior; `None`: the server draws one.
        behavior: Option<BehaviorSpec>,
        /// The context the robot is in from now on; `None`: unchanged.
        context: Option<ContextSettings>,
        /// What the operator states up front, each name as given (checked against the
        /// domain's statements by the session); empty: nothing.
        preferences: Vec<Statement>,
    },
    /// The robot's context from now on (between episodes).
    Context(ContextSettings),
    /// The outcome of the last command.
    Outcome(Outcome),
    /// The adapter's current state.
    State,
    /// The case base.
    Cases,
    /// End the episode under way without retaining a case.
    Abandon,
    /// The behavior space and the adapter configuration.
    Config,
    /// The explanation of the episode so far.
    Explain,
    /// Take the safer behavior the last overtrust alert offered (mission mode).
    AcceptOffer,
}

/// The requests named by a `request` field, with the fields each allows besides it.
const NAMED: &[(&str, &[&str])] = &[
    ("begin", &["behavior", "context", "preferences"]),
    ("context", &["context"]),
    ("state", &[]),
    ("cases", &[]),
    ("abandon", &[]),
    ("config", &[]),
    ("explain", &[]),
    ("accept_offer", &[]),
];

/// The fields of an outcome report.
const OUTCOME_FIELDS: &[&str] = &[
    "outcome",
    "weight",
    "duration_s",
    "observed",
    "stated",
    "confidence",
    "goal_change",
];

/// Why a line is not a valid request.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum RequestError {
    /// The line is not JSON.
    #[error("malformed JSON: {0}")]
    Json(String),
    /// An object gives a key twice (the message names it and its place).
    #[error("{0}; give each field once")]
    RepeatedField(String),
    /// The line is JSON but not an object.
    #[error("a request must be a JSON object, got {0}")]
    NotAnObject(&'static str),
    /// Neither `request` nor `outcome` is present.
    #[error(
        "a request needs a `request` field (one of begin, context, state, cases, abandon, config, explain, accept_offer) or, for an outcome report, an `outcome` field"
    )]
    NoKind,
    /// The `request` field names no request.
    #[error(
        "field `request`: unknown request `{0}` (one of begin, context, state, cases, abandon, config, explain, accept_offer; outcome reports have an `outcome` field instead)"
    )]
    UnknownRequest(String),
    /// A field the request does not have.
    #[error("unknown field `{field}` in {what} (allowed: {allowed})")]
    UnknownField {
        /// The field given.
        field: String,
        /// The kind of request.
        what: String,
        /// The fields it allows.
        allowed: String,
    },
    /// A required field is absent.
    #[error("missing field `{0}`")]
    Missing(&'static str),
    /// A field holds the wrong type or an unknown name.
    #[error("field `{field}`: {message}")]
    Field {
        /// The field.
        field: String,
        /// What is wrong with it.
        message: String,
    },
    /// The outcome's stated reason is not one the domain declares (the message lists them).
    #[error("field `stated`: {0}")]
    UndeclaredCause(UndeclaredCause),
    /// An observation the domain does not declare.
    #[error("field `observed`: observation `{name}` is not declared (declared: {declared})")]
    UndeclaredObservation {
        /// The name given.
        name: String,
        /// The declared observations, comma-separated (`none` when there are none).
        declared: String,
    },
    /// The retired `cause` field of an older controller.
    #[error(
        "field `cause` is retired: the robot is not told the operator's true reason; send `stated` for a reason the operator gave (or leave it out) and `observed` for what the robot perceived (see `serve --help`)"
    )]
    RetiredCause,
    /// The outcome's numbers are unusable (negative weight or duration, a confidence
    /// outside `[0, 1]`; shown in the message, so not chained as a source).
    #[error("invalid outcome: {0}")]
    Outcome(OutcomeError),
}

impl From<OutcomeError> for RequestError {
    fn from(reason: OutcomeError) -> Self {
        Self::Outcome(reason)
    }
}

/// One request line: the request, and the `id` the controller gave it (echoed in the
/// reply).
#[derive(Clone, Debug, PartialEq)]
pub struct Envelope {
    /// The optional `id` field: any JSON scalar (string, number, boolean, null).
    pub id: Option<RequestId>,
    /// The request, or why the line is not one.
    pub request: Result<Request, RequestError>,
}

/// A request's `id` as the controller wrote it: the JSON text of a scalar, kept verbatim
/// so the reply echoes it byte for byte (`18446744073709551616` and `0.1000000000000000055`
/// come back as sent, not as the nearest double).
#[derive(Clone, Debug)]
pub struct RequestId(Box<RawValue>);

impl RequestId {
    /// The id's JSON text, as sent (without the whitespace around it).
    pub fn as_json(&self) -> &str {
        self.0.get()
    }
}

impl PartialEq for RequestId {
    fn eq(&self, other: &Self) -> bool {
        self.as_json() == other.as_json()
    }
}

impl serde::Serialize for RequestId {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.0.serialize(serializer)
    }
}

/// What a served domain lets an outcome report name: its declared causes (for a stated
/// reason) and observations.
#[derive(Clone, Copy, Debug)]
pub struct Vocabulary<'a> {
    /// The causes a stated reason may name.
    pub causes: &'a [DeclaredCause],
    /// The observations `observed` may name, in the domain's order (bit `i`: the `i`-th).
    pub observations: &'a [Cause],
}

/// Parses one line (without its newline; a leading UTF-8 byte-order mark is skipped),
/// with its `id`, for a domain whose outcome reports may name `vocabulary`. A key given
/// twice is refused.
pub fn parse_line(line: &[u8], vocabulary: Vocabulary<'_>) -> Envelope {
    let line = line
        .strip_prefix(files::input::BYTE_ORDER_MARK.as_bytes())
        .unwrap_or(line);
    let (map, id) = match serde_json::from_slice::<Line>(line) {
        Ok(Line::Object(map, id)) => (map, id),
        Ok(Line::Other(kind)) => {
            return Envelope {
                id: None,
                request: Err(RequestError::NotAnObject(kind)),
            };
        }
        Err(e) => {
            return Envelope {
                id: None,
                request: Err(json_error(line, &e)),
            };
        }
    };
    let kind = id
        .as_ref()
        .and_then(|id| match id.as_json().as_bytes().first() {
            Some(b'[') => Some("an array"),
            Some(b'{') => Some("an object"),
            _ => None,
        });
    match kind {
        Some(kind) => Envelope {
            id: None,
            request: Err(RequestError::Field {
                field: "id".to_owned(),
                message: format!("expected a string, a number, a boolean or null, got {kind}"),
            }),
        },
        None => Envelope {
            id,
            request: parse_object(map, vocabulary),
        },
    }
}

/// Parses one line (without its newline) for a domain that declares `causes`; an `id`
/// field is allowed and ignored.
pub fn parse_request(line: &[u8], vocabulary: Vocabulary<'_>) -> Result<Request, RequestError> {
    parse_line(line, vocabulary).request
}

fn parse_object(
    map: Map<String, Value>,
    vocabulary: Vocabulary<'_>,
) -> Result<Request, RequestError> {
    if map.contains_key("request") {
        parse_named(map)
    } else if map.contains_key("outcome") {
        parse_outcome(map, vocabulary)
    } else {
        Err(RequestError::NoKind)
    }
}

fn parse_named(map: Map<String, Value>) -> Result<Request, RequestError> {
    let mut fields = Fields(map);
    let name: String = fields.require("request")?;
    let Some(&(name, allowed)) = NAMED.iter().find(|(n, _)| *n == name) else {
        return Err(RequestError::UnknownRequest(name));
    };
    fields.only(allowed, &format!("a `{name}` request"))?;
    Ok(match name {
        "begin" => Request::Begin {
            behavior: fields.take_behavior()?,
            context: fields.take_context()?,
            preferences: fields.take_preferences()?,
        },
        "context" => Request::Context(
            fields
                .take_context()?
                .ok_or(RequestError::Missing("context"))?,
        ),
        "state" => Request::State,
        "cases" => Request::Cases,
        "abandon" => Request::Abandon,
        "explain" => Request::Explain,
        "accept_offer" => Request::AcceptOffer,
        _ => Request::Config,
    })
}

fn parse_outcome(
    map: Map<String, Value>,
    vocabulary: Vocabulary<'_>,
) -> Result<Request, RequestError> {
    if map.contains_key("cause") {
        return Err(RequestError::RetiredCause);
    }
    let mut fields = Fields(map);
    fields.only(OUTCOME_FIELDS, "an outcome report")?;
    let kind = fields.require::<OutcomeKind>("outcome")?;
    let weight = fields.require("weight")?;
    let duration_s = fields.require("duration_s")?;
    let stated = fields.take::<Option<Cause>>("stated")?.flatten();
    let confidence = fields.take::<Option<f64>>("confidence")?.flatten();
    let goal_change = fields.take::<bool>("goal_change")?.unwrap_or(false);
    if let Some(cause) = stated {
        find_declared(vocabulary.causes, cause).map_err(RequestError::UndeclaredCause)?;
    }
    let mut observed = Observations::NONE;
    for name in fields.take::<Vec<String>>("observed")?.unwrap_or_default() {
        let index = vocabulary
            .observations
            .iter()
            .position(|o| o.as_str() == name)
            .ok_or_else(|| RequestError::UndeclaredObservation {
                name: name.clone(),
                declared: if vocabulary.observations.is_empty() {
                    "none".to_owned()
                } else {
                    vocabulary
                        .observations
                        .iter()
                        .map(Cause::as_str)
                        .collect::<Vec<_>>()
                        .join(", ")
                },
            })?;
        observed = observed.with(index);
    }
    let outcome = Outcome::new(kind, weight, duration_s)
        .observing(observed)
        .stating(stated)
        .assessing(confidence)
        .saying_goal_change(goal_change);
    outcome.validate()?;
    Ok(Request::Outcome(outcome))
}

/// The fields of one request object, taken one by one.
struct Fields(Map<String, Value>);

impl Fields {
    /// Refuses any field outside `allowed` (the `request` field is always allowed).
    fn only(&self, allowed: &[&str], what: &str) -> Result<(), RequestError> {
        match self
            .0
            .keys()
            .find(|k| !allowed.contains(&k.as_str()) && k.as_str() != "request")
        {
            Some(field) => Err(RequestError::UnknownField {
                field: field.clone(),
                what: what.to_owned(),
                allowed: if allowed.is_empty() {
                    "none".to_owned()
                } else {
                    allowed.join(", ")
                },
            }),
            None => Ok(()),
        }
    }

    fn take<T: DeserializeOwned>(
        &mut self,
        field: &'static str,
    ) -> Result<Option<T>, RequestError> {
        self.0
            .remove(field)
            .map(|v| {
                serde_json::from_value(v).map_err(|e| RequestError::Field {
                    field: field.to_owned(),
                    message: e.to_string(),
                })
            })
            .transpose()
    }

    fn require<T: DeserializeOwned>(&mut self, field: &'static str) -> Result<T, RequestError> {
        self.take(field)?.ok_or(RequestError::Missing(field))
    }

    /// The `context` field, an object of variable names and their values (labels).
    fn take_context(&mut self) -> Result<Option<ContextSettings>, RequestError> {
        let bad = |field: String, got: &Value| RequestError::Field {
            field,
            message: format!("expected a label, got {}", json_type(got)),
        };
        match self.0.remove("context") {
            None | Some(Value::Null) => Ok(None),
            Some(Value::Object(values)) => values
                .into_iter()
                .map(|(name, value)| match value {
                    Value::String(s) => Ok((name, s)),
                    other => Err(bad(format!("context.{name}"), &other)),
                })
                .collect::<Result<_, _>>()
                .map(Some),
            Some(other) => Err(RequestError::Field {
                field: "context".to_owned(),
                message: format!(
                    "expected an object such as {{\"cargo\": \"hazardous\"}}, got {}",
                    json_type(&other)
                ),
            }),
        }
    }

    /// The `preferences` field, an object of statement names and whether the operator
    /// minds each (`{"hurry": true, "avoid-bumps": false}`).
    fn take_preferences(&mut self) -> Result<Vec<Statement>, RequestError> {
        match self.0.remove("preferences") {
            None | Some(Value::Null) => Ok(Vec::new()),
            Some(Value::Object(values)) => values
                .into_iter()
                .map(|(name, value)| match value {
                    Value::Bool(minds) => Ok(Statement { name, minds }),
                    other => Err(RequestError::Field {
                        field: format!("preferences.{name}"),
                        message: format!(
                            "expected true (the operator minds it) or false, got {}",
                            json_type(&other)
                        ),
                    }),
                })
                .collect(),
            Some(other) => Err(RequestError::Field {
                field: "preferences".to_owned(),
                message: format!(
                    "expected an object such as {{\"hurry\": true, \"avoid-bumps\": false}}, got {}",
                    json_type(&other)
                ),
            }),
        }
    }

    fn take_behavior(&mut self) -> Result<Option<BehaviorSpec>, RequestError> {
        let bad = |field: String, got: &Value| RequestError::Field {
            field,
            message: format!("expected a number or a label, got {}", json_type(got)),
        };
        match self.0.remove("behavior") {
            None | Some(Value::Null) => Ok(None),
            Some(Value::String(text)) => Ok(Some(BehaviorSpec::Text(text))),
            Some(Value::Object(values)) => values
                .into_iter()
                .map(|(name, value)| match value {
                    Value::Number(n) => Ok((name, n.to_string())),
                    Value::String(s) => Ok((name, s)),
                    other => Err(bad(format!("behavior.{name}"), &other)),
                })
                .collect::<Result<_, _>>()
                .map(|values| Some(BehaviorSpec::Values(values))),
            Some(other) => Err(RequestError::Field {
                field: "behavior".to_owned(),
                message: format!(
                    "expected an object such as {{\"speed\": 3.5, \"padding\": 0.4}} or a string such as \"speed=3.5,padding=0.4\", got {}",
                    json_type(&other)
                ),
            }),
        }
    }
}

/// A whole request line: an object, with its `id` kept as the JSON text sent and its
/// other fields read as [`UniqueKeys`] reads them (a key given twice is refused); or what
/// else the line holds.
enum Line {
    Object(Map<String, Value>, Option<RequestId>),
    Other(&'static str),
}

impl<'de> Deserialize<'de> for Line {
    fn deserialize<D: de::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(LineVisitor)
    }
}

struct LineVisitor;

impl<'de> Visitor<'de> for LineVisitor {
    type Value = Line;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a JSON object")
    }

    fn visit_bool<E>(self, _: bool) -> Result<Line, E> {
        Ok(Line::Other("a boolean"))
    }

    fn visit_i64<E>(self, _: i64) -> Result<Line, E> {
        Ok(Line::Other("a number"))
    }

    fn visit_u64<E>(self, _: u64) -> Result<Line, E> {
        Ok(Line::Other("a number"))
    }

    fn visit_f64<E>(self, _: f64) -> Result<Line, E> {
        Ok(Line::Other("a number"))
    }

    fn visit_str<E>(self, _: &str) -> Result<Line, E> {
        Ok(Line::Other("a string"))
    }

    fn visit_unit<E>(self) -> Result<Line, E> {
        Ok(Line::Other("null"))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Line, A::Error> {
        UniqueKeysVisitor
            .visit_seq(seq)
            .map(|_| Line::Other("an array"))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut access: A) -> Result<Line, A::Error> {
        let mut map = Map::new();
        let mut id: Option<RequestId> = None;
        while let Some(key) = access.next_key::<String>()? {
            if map.contains_key(&key) || (key == "id" && id.is_some()) {
                return Err(de::Error::custom(format_args!(
                    "field `{key}` is given twice"
                )));
            }
            if key == "id" {
                id = Some(RequestId(access.next_value()?));
            } else {
                let UniqueKeys(value) = access.next_value()?;
                map.insert(key, value);
            }
        }
        Ok(Line::Object(map, id))
    }
}

/// A JSON value whose objects, at every depth, give each key once.
struct UniqueKeys(Value);

impl<'de> Deserialize<'de> for UniqueKeys {
    fn deserialize<D: de::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer
            .deserialize_any(UniqueKeysVisitor)
            .map(UniqueKeys)
    }
}

struct UniqueKeysVisitor;

impl<'de> Visitor<'de> for UniqueKeysVisitor {
    type Value = Value;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a JSON value")
    }

    fn visit_bool<E>(self, v: bool) -> Result<Value, E> {
        Ok(Value::Bool(v))
    }

    fn visit_i64<E>(self, v: i64) -> Result<Value, E> {
        Ok(Value::from(v))
    }

    fn visit_u64<E>(self, v: u64) -> Result<Value, E> {
        Ok(Value::from(v))
    }

    fn visit_f64<E>(self, v: f64) -> Result<Value, E> {
        Ok(Value::from(v))
    }

    fn visit_str<E>(self, v: &str) -> Result<Value, E> {
        Ok(Value::String(v.to_owned()))
    }

    fn visit_string<E>(self, v: String) -> Result<Value, E> {
        Ok(Value::String(v))
    }

    fn visit_unit<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        let mut items = Vec::new();
        while let Some(UniqueKeys(item)) = seq.next_element()? {
            items.push(item);
        }
        Ok(Value::Array(items))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut access: A) -> Result<Value, A::Error> {
        let mut map = Map::new();
        while let Some(key) = access.next_key::<String>()? {
            if map.contains_key(&key) {
                return Err(de::Error::custom(format_args!(
                    "field `{key}` is given twice"
                )));
            }
            let UniqueKeys(value) = access.next_value()?;
            map.insert(key, value);
        }
        Ok(Value::Object(map))
    }
}

fn json_error(line: &[u8], error: &serde_json::Error) -> RequestError {
    if error.classify() == serde_json::error::Category::Data {
        // The only data error a `UniqueKeys` parse raises is a repeated key.
        return RequestError::RepeatedField(error.to_string());
    }
    let mut message = error.to_string();
    // Python's json.dumps writes NaN and Infinity, which JSON does not have.
    let text = String::from_utf8_lossy(line);
    if ["NaN", "Infinity"].iter().any(|w| text.contains(w)) {
        message.push_str(" (JSON has no NaN or Infinity: send finite numbers)");
    }
    RequestError::Json(message)
}

fn json_type(value: &Value) -> &'static str {
    match value {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The causes of the domain these tests serve.
    const CAUSES: [DeclaredCause; 2] = [
        DeclaredCause::new(Cause::from_static("too-slow")),
        DeclaredCause::new(Cause::from_static("dropped-item")),
    ];

    /// What the robot of these tests perceives.
    const OBSERVATIONS: [Cause; 2] = [Cause::from_static("bump"), Cause::from_static("late")];

    const VOCABULARY: Vocabulary<'static> = Vocabulary {
        causes: &CAUSES,
        observations: &OBSERVATIONS,
    };

    /// A domain that declares nothing.
    const NOTHING: Vocabulary<'static> = Vocabulary {
        causes: &[],
        observations: &[],
    };

    fn parse_request(line: &[u8]) -> Result<Request, RequestError> {
        super::parse_request(line, VOCABULARY)
    }

    fn parse_line(line: &[u8]) -> Envelope {
        super::parse_line(line, VOCABULARY)
    }

    fn err(line: &str) -> String {
        parse_request(line.as_bytes()).unwrap_err().to_string()
    }

    fn id(line: &[u8]) -> Option<String> {
        parse_line(line).id.map(|id| id.as_json().to_owned())
    }

    #[test]
    fn number_ids_are_kept_as_sent_whatever_their_size() {
        for sent in [
            "18446744073709551615",
            "18446744073709551616",
            "-92233720368547758080",
            "123456789012345678901234567890",
            "2.5",
            "0.1000000000000000055511151231257827",
            "1e400",
            "-0",
            "1E+2",
        ] {
            let line = format!(r#"{{"request":"state","id": {sent} }}"#);
            let e = parse_line(line.as_bytes());
            assert_eq!(e.request, Ok(Request::State), "{sent}");
            assert_eq!(
                e.id.map(|id| id.as_json().to_owned()),
                Some(sent.to_owned())
            );
        }
    }

    #[test]
    fn an_outcome_says_what_the_robot_knows() {
        let r = parse_request(
            br#"{"outcome": "interrupted", "weight": 1.0, "duration_s": 10.0, "observed": ["late", "bump"], "stated": "too-slow"}"#,
        )
        .unwrap();
        assert_eq!(
            r,
            Request::Outcome(
                Outcome::interrupted(1.0, 10.0)
                    .observing(Observations::NONE.with(0).with(1))
                    .stating(Some(CAUSES[0].name))
            )
        );
        let r = parse_request(
            br#"{"outcome":"completed","weight":0.5,"stated":null,"observed":[],"duration_s":3}"#,
        )
        .unwrap();
        assert_eq!(r, Request::Outcome(Outcome::completed(0.5, 3.0)));
        let r = parse_request(br#"{"outcome":"failed","weight":1,"duration_s":3}"#).unwrap();
        assert_eq!(r, Request::Outcome(Outcome::failed(1.0, 3.0)));
    }

    #[test]
    fn an_older_controller_sending_cause_is_told_what_to_send() {
        for line in [
            r#"{"outcome":"failed","weight":1,"cause":"too-slow","duration_s":1}"#,
            r#"{"outcome":"completed","weight":1,"cause":null,"duration_s":1}"#,
        ] {
            assert_eq!(
                err(line),
                "field `cause` is retired: the robot is not told the operator's true reason; send `stated` for a reason the operator gave (or leave it out) and `observed` for what the robot perceived (see `serve --help`)"
            );
        }
    }

    #[test]
    fn observations_must_be_declared_names() {
        assert_eq!(
            err(r#"{"outcome":"failed","weight":1,"duration_s":1,"observed":["smoke"]}"#),
            "field `observed`: observation `smoke` is not declared (declared: bump, late)"
        );
        assert!(
            err(r#"{"outcome":"failed","weight":1,"duration_s":1,"observed":"bump"}"#)
                .starts_with("field `observed`: invalid type: string")
        );
        assert_eq!(
            super::parse_request(
                br#"{"outcome":"failed","weight":1,"duration_s":1,"observed":["bump"]}"#,
                NOTHING
            )
            .unwrap_err()
            .to_string(),
            "field `observed`: observation `bump` is not declared (declared: none)"
        );
    }

    #[test]
    fn a_goal_change_is_said_of_an_interruption_with_no_reason() {
        let r = parse_request(
            br#"{"outcome":"interrupted","weight":1,"duration_s":2,"goal_change":true}"#,
        )
        .unwrap();
        assert_eq!(
            r,
            Request::Outcome(Outcome::interrupted(1.0, 2.0).saying_goal_change(true))
        );
        let unsaid = parse_request(
            br#"{"outcome":"interrupted","weight":1,"duration_s":2,"goal_change":false}"#,
        )
        .unwrap();
        assert_eq!(unsaid, Request::Outcome(Outcome::interrupted(1.0, 2.0)));
        assert_eq!(
            err(r#"{"outcome":"completed","weight":1,"duration_s":2,"goal_change":true}"#),
            "invalid outcome: goal_change is said only of an interruption with no stated reason (the operator stopped the robot for something other than the behavior), got outcome `completed`"
        );
        assert!(
            err(r#"{"outcome":"interrupted","weight":1,"duration_s":2,"goal_change":1}"#)
                .starts_with("field `goal_change`: invalid type: integer `1`, expected a boolean")
        );
    }

    #[test]
    fn a_self_assessed_confidence_is_a_probability() {
        let r = parse_request(
            br#"{"outcome":"completed","weight":1,"duration_s":2,"confidence":0.75}"#,
        )
        .unwrap();
        assert_eq!(
            r,
            Request::Outcome(Outcome::completed(1.0, 2.0).assessing(Some(0.75)))
        );
        for bound in ["0", "1", "null"] {
            let line =
                format!(r#"{{"outcome":"failed","weight":1,"duration_s":2,"confidence":{bound}}}"#);
            assert!(parse_request(line.as_bytes()).is_ok(), "{bound}");
        }
        assert_eq!(
            err(r#"{"outcome":"completed","weight":1,"duration_s":2,"confidence":1.5}"#),
            "invalid outcome: confidence must be a number in [0, 1], got 1.5"
        );
        assert_eq!(
            err(r#"{"outcome":"completed","weight":1,"duration_s":2,"confidence":-0.1}"#),
            "invalid outcome: confidence must be a number in [0, 1], got -0.1"
        );
        assert_eq!(
            err(r#"{"outcome":"completed","weight":1,"duration_s":2,"confidence":"high"}"#),
            "field `confidence`: invalid type: string \"high\", expected f64"
        );
    }

    #[test]
    fn named_requests() {
        assert_eq!(
            parse_request(br#"{"request":"state"}"#).unwrap(),
            Request::State
        );
        assert_eq!(
            parse_request(br#"{"request":"begin"}"#).unwrap(),
            Request::Begin {
                behavior: None,
                context: None,
                preferences: Vec::new()
            }
        );
        assert_eq!(
            parse_request(br#"{"request":"begin","behavior":{"speed":3.5,"planner":"rrt"}}"#)
                .unwrap(),
            Request::Begin {
                behavior: Some(BehaviorSpec::Values(vec![
                    ("speed".into(), "3.5".into()),
                    ("planner".into(), "rrt".into()),
                ])),
                context: None,
                preferences: Vec::new()
            }
        );
        assert_eq!(
            parse_request(br#"{"request":"begin","context":{"cargo":"hazardous"}}"#).unwrap(),
            Request::Begin {
                behavior: None,
                context: Some(vec![("cargo".into(), "hazardous".into())]),
                preferences: Vec::new()
            }
        );
        assert_eq!(
            parse_request(
                br#"{"request":"begin","preferences":{"hurry":true,"avoid-bumps":false}}"#
            )
            .unwrap(),
            Request::Begin {
                behavior: None,
                context: None,
                preferences: vec![
                    Statement::new("hurry", true),
                    Statement::new("avoid-bumps", false)
                ]
            }
        );
        assert_eq!(
            parse_request(br#"{"request":"context","context":{"situation":"emergency"}}"#).unwrap(),
            Request::Context(vec![("situation".into(), "emergency".into())])
        );
    }

    #[test]
    fn preferences_must_be_an_object_of_booleans() {
        assert_eq!(
            err(r#"{"request":"begin","preferences":["hurry"]}"#),
            r#"field `preferences`: expected an object such as {"hurry": true, "avoid-bumps": false}, got an array"#
        );
        assert_eq!(
            err(r#"{"request":"begin","preferences":{"hurry":"yes"}}"#),
            "field `preferences.hurry`: expected true (the operator minds it) or false, got a string"
        );
    }

    #[test]
    fn a_context_must_be_an_object_of_labels() {
        assert_eq!(err(r#"{"request":"context"}"#), "missing field `context`");
        assert_eq!(
            err(r#"{"request":"context","context":"hazardous"}"#),
            r#"field `context`: expected an object such as {"cargo": "hazardous"}, got a string"#
        );
        assert_eq!(
            err(r#"{"request":"begin","context":{"cargo":1}}"#),
            "field `context.cargo`: expected a label, got a number"
        );
    }

    #[test]
    fn hostile_lines_are_named() {
        assert!(err(r#"{"outcome": "interr"#).starts_with("malformed JSON: EOF while parsing"));
        assert!(err("[1,2]").contains("must be a JSON object, got an array"));
        assert!(err(r#"{"weight": 1}"#).contains("needs a `request` field"));
        assert!(err(r#"{"request": "fly"}"#).contains("unknown request `fly`"));
        assert_eq!(
            err(r#"{"outcome":"completed","weight":1,"duration_s":1,"colour":"red"}"#),
            "unknown field `colour` in an outcome report (allowed: outcome, weight, duration_s, observed, stated, confidence, goal_change)"
        );
        assert_eq!(
            err(r#"{"request":"state","verbose":true}"#),
            "unknown field `verbose` in a `state` request (allowed: none)"
        );
        assert_eq!(
            err(r#"{"outcome":"completed","weight":"heavy","duration_s":1}"#),
            "field `weight`: invalid type: string \"heavy\", expected f64"
        );
        assert_eq!(
            err(r#"{"outcome":"crashed","weight":1,"duration_s":1}"#),
            "field `outcome`: unknown variant `crashed`, expected one of `completed`, `failed`, `interrupted`"
        );
        assert_eq!(
            err(r#"{"outcome":"failed","weight":1,"stated":"gremlins","duration_s":1}"#),
            "field `stated`: cause `gremlins` is not declared (declared: too-slow, dropped-item)"
        );
        assert_eq!(
            err(r#"{"outcome":"failed","weight":1,"stated":"Gremlins!","duration_s":1}"#),
            format!(
                "field `stated`: cause `Gremlins!` has 'G' at byte 0; {}",
                trust::cause::CAUSE_RULE
            )
        );
        assert!(
            err(r#"{"outcome":"failed","weight":1,"stated":7,"duration_s":1}"#)
                .starts_with("field `stated`: invalid type: integer `7`, expected a cause name")
        );
        // No cause is declared: none is accepted, and a stated `null` still is.
        assert_eq!(
            super::parse_request(
                br#"{"outcome":"failed","weight":1,"stated":"too-slow","duration_s":1}"#,
                NOTHING
            )
            .unwrap_err()
            .to_string(),
            "field `stated`: cause `too-slow` is not declared (declared: none)"
        );
        assert!(
            super::parse_request(
                br#"{"outcome":"failed","weight":1,"stated":null,"duration_s":1}"#,
                NOTHING
            )
            .is_ok()
        );
        assert_eq!(
            err(r#"{"outcome":"failed","weight":-1,"duration_s":1}"#),
            "invalid outcome: weight must be a finite number >= 0, got -1"
        );
        assert!(
            err(r#"{"outcome":"failed","weight":NaN,"duration_s":1}"#)
                .contains("JSON has no NaN or Infinity")
        );
        assert_eq!(
            err(r#"{"outcome":"failed","weight":1}"#),
            "missing field `duration_s`"
        );
        assert!(
            err(r#"{"request":"begin","behavior":[1]}"#)
                .starts_with("field `behavior`: expected an object")
        );
        assert_eq!(
            err(r#"{"request":"begin","behavior":{"speed":true}}"#),
            "field `behavior.speed`: expected a number or a label, got a boolean"
        );
        assert!(err("\u{1F600}\u{0}").starts_with("malformed JSON"));
    }

    #[test]
    fn ids_are_scalars_taken_apart_from_the_request() {
        let e = parse_line(br#"{"request":"state","id":17}"#);
        assert_eq!(id(br#"{"request":"state","id":17}"#).as_deref(), Some("17"));
        assert_eq!(e.request, Ok(Request::State));
        let e =
            parse_line(br#"{"id":"robot-3/42","outcome":"completed","weight":1,"duration_s":2}"#);
        assert_eq!(e.id.unwrap().as_json(), r#""robot-3/42""#);
        assert_eq!(
            e.request,
            Ok(Request::Outcome(Outcome::completed(1.0, 2.0)))
        );
        let e = parse_line(br#"{"request":"state","id":[1]}"#);
        assert_eq!(e.id, None);
        assert_eq!(
            e.request.unwrap_err().to_string(),
            "field `id`: expected a string, a number, a boolean or null, got an array"
        );
        let e = parse_line(br#"{"request":"state","id":{"a":1}}"#);
        assert_eq!(e.id, None);
        assert_eq!(
            e.request.unwrap_err().to_string(),
            "field `id`: expected a string, a number, a boolean or null, got an object"
        );
        assert_eq!(
            err(r#"{"request":"state","id":1,"id":2}"#),
            "field `id` is given twice at line 1 column 30; give each field once"
        );
        let e = parse_line(br#"{"request":"fly","id":true}"#);
        assert_eq!(e.id.unwrap().as_json(), "true");
        assert!(e.request.is_err());
    }

    #[test]
    fn a_key_given_twice_is_refused_at_any_depth() {
        assert_eq!(
            err(r#"{"outcome":"completed","outcome":"failed","weight":1,"duration_s":1}"#),
            "field `outcome` is given twice at line 1 column 32; give each field once"
        );
        assert!(
            err(r#"{"request":"begin","behavior":{"speed":3.5,"speed":4,"padding":0.4}}"#)
                .starts_with("field `speed` is given twice at line 1 column")
        );
        assert!(err(r#"[{"a":1,"a":1}]"#).starts_with("field `a` is given twice"));
    }

    #[test]
    fn a_byte_order_mark_before_the_object_is_skipped() {
        assert_eq!(
            parse_request(b"\xEF\xBB\xBF{\"request\":\"state\"}").unwrap(),
            Request::State
        );
    }

    fn any_json() -> impl Strategy<Value = Value> {
        let leaf = prop_oneof![
            Just(Value::Null),
            any::<bool>().prop_map(Value::Bool),
            any::<i64>().prop_map(Value::from),
            any::<f64>().prop_map(Value::from),
            "[a-z_=,.0-9-]{0,12}".prop_map(Value::from),
        ];
        leaf.prop_recursive(3, 24, 6, |inner| {
            prop_oneof![
                prop::collection::vec(inner.clone(), 0..6).prop_map(Value::Array),
                prop::collection::vec(
                    ("(outcome|request|weight|speed|padding|[a-z]{1,3})", inner),
                    0..6
                )
                .prop_map(|pairs| Value::Object(pairs.into_iter().collect())),
            ]
        })
    }

    proptest! {
        #[test]
        fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..256)) {
            let _ = parse_request(&bytes);
        }

        /// Any JSON value (serde_json writes every key once) parses strictly to what
        /// serde_json reads, and no request built from it panics the parser.
        #[test]
        fn arbitrary_json_values_parse_alike(value in any_json()) {
            let text = value.to_string();
            let UniqueKeys(strict) = serde_json::from_str(&text).unwrap();
            prop_assert_eq!(strict, serde_json::from_str::<Value>(&text).unwrap());
            let _ = parse_request(text.as_bytes());
            let request = Value::Object(Map::from_iter([
                ("request".to_owned(), Value::from("begin")),
                ("behavior".to_owned(), value),
            ]));
            let _ = parse_request(request.to_string().as_bytes());
        }

        /// An outcome's stated reason is accepted exactly when the domain declares it; any
        /// other text is refused naming the field.
        #[test]
        fn a_stated_reason_is_accepted_exactly_when_declared(name in "too-slow|dropped-item|[a-z-]{0,12}|.{0,40}") {
            let line = serde_json::json!({
                "outcome": "failed", "weight": 1, "stated": name, "duration_s": 1
            });
            let declared = CAUSES.iter().any(|d| d.name.as_str() == name);
            match parse_request(line.to_string().as_bytes()) {
                Ok(Request::Outcome(o)) => {
                    prop_assert!(declared, "{name} accepted");
                    prop_assert_eq!(o.stated.map(|c| c.to_string()), Some(name));
                }
                Ok(other) => prop_assert!(false, "{other:?}"),
                Err(e) => {
                    prop_assert!(!declared, "{name} refused: {e}");
                    prop_assert!(e.to_string().starts_with("field `stated`: "), "{e}");
                }
            }
        }

        #[test]
        fn arbitrary_json_like_text_never_panics(text in r#"\{("(outcome|request|weight|cause|stated|observed|duration_s|behavior)":(-?[0-9.e]{1,6}|"[a-z-]{0,12}"|null|\[\]|\{\})[,}]?){0,5}"#) {
            let _ = parse_request(text.as_bytes());
        }
    }
}
