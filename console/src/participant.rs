//! One participant's session, rebuilt from their stored events on every request: `serve`'s
//! own session replays the outcome reports their stops made, each replayed reply is
//! checked against the recorded one, and what the page shows next follows from the result.
//! Nothing about a participant lives in a console's memory, so a reload, a restart or
//! another console serving the same study all resume at the same place.

use crate::cases::ParticipantCases;
use crate::db::{Db, DbError, Event, NewEvent, Participant};
use crate::stage::{Ending, Stage};
use crate::study::{RateAfter, Scale, Study, mix};
use cbr_core::Behavior;
use serde_json::{Value, json};
use service::store::Identity;
use service::{DomainDefinition, Session, SessionError, SharedCases};
use std::sync::Arc;
use trust::{OutcomeKind, TrustCaseBase};

/// A study being run: the study, each condition's served domain (its arm applied), the
/// stage its runs are shown on, and its database.
pub struct Conduct {
    /// The study.
    pub study: Study,
    /// Per condition, the domain `serve` would serve with the condition's arm.
    pub conditions: Vec<DomainDefinition>,
    /// Where the runs happen.
    pub stage: Arc<dyn Stage>,
    /// Where everything is stored.
    pub db: Arc<dyn Db>,
}

/// Why a participant's request was not done.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ConductError {
    /// The request does not fit the participant's session (wrong command, phase or value):
    /// nothing was stored.
    #[error("{0}")]
    Refused(String),
    /// The database failed.
    #[error(transparent)]
    Db(#[from] DbError),
    /// The adapter could not be set up or could not store a retained case.
    #[error(transparent)]
    Session(#[from] SessionError),
    /// Replaying the participant's events gave another reply than the one recorded (the
    /// study was recorded by a build that decides otherwise).
    #[error(
        "participant {}'s event {}: the adapter now replies {}, but {} was recorded",
        .0.participant, .0.seq, .0.replayed, .0.recorded
    )]
    Diverged(Box<Divergence>),
}

/// Where a replay left the record ([`ConductError::Diverged`]).
#[derive(Debug)]
pub struct Divergence {
    /// The participant's pseudonym.
    pub participant: String,
    /// The event.
    pub seq: u64,
    /// The reply recorded.
    pub recorded: Value,
    /// The reply the replay gave.
    pub replayed: Value,
}

/// Where a participant's session stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// A run is shown (or about to be): the participant may stop it.
    Watch,
    /// The participant stopped the run; the page asks why.
    StateCause,
    /// The page asks for a trust rating.
    Rate,
    /// The session is over.
    Done,
}

impl Phase {
    /// The phase as the page's API names it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Watch => "watch",
            Self::StateCause => "state-cause",
            Self::Rate => "rate",
            Self::Done => "done",
        }
    }
}

/// The last command's end, as the page shows it.
#[derive(Clone, Debug, PartialEq)]
pub struct Closed {
    /// The command.
    pub command: u64,
    /// `completed`, `failed` or `interrupted`.
    pub outcome: String,
    /// `keep`, `switch`, `settled` or `abandoned`.
    pub decision: String,
    /// The adapter's explanation, when the reply gave one.
    pub explanation: Option<String>,
}

/// A rating owed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Due {
    /// The command after which it is asked.
    pub after_command: u64,
    /// Behaviors evaluated by then.
    pub behaviors: u32,
    /// The inverse trust estimate of the behavior just evaluated (the sum of its
    /// commands' weighted outcomes).
    pub estimate: f64,
}

/// A participant's session after replaying their events.
pub struct Replayed {
    /// The adapter, as `serve` holds it.
    pub session: Session,
    /// The behavior in use (the last one, once the session is over).
    pub behavior: Behavior,
    /// Commands closed so far; the open command's index.
    pub commands: u64,
    /// Behaviors evaluated so far (the one in use included).
    pub behaviors: u32,
    /// Whether the open command was shown, and where it was stopped.
    pub shown: bool,
    /// Where the open command was stopped, if it was.
    pub stopped_at: Option<f64>,
    /// The last closed command.
    pub last: Option<Closed>,
    /// Every rating owed, in order.
    pub due: Vec<Due>,
    /// Ratings given.
    pub rated: usize,
    /// Whether the adapter's episode is over (settled or abandoned).
    pub finished: bool,
    /// The next event's seq.
    pub next_seq: u64,
    /// The open behavior's estimate so far.
    estimate: f64,
}

impl Replayed {
    /// Takes in an event that is not a decision (decisions go through the adapter:
    /// `Conduct::close`): a run shown, a stop, a rating; the others change nothing here.
    fn note(&mut self, kind: &str, body: &Value) {
        match kind {
            "shown" => self.shown = true,
            "stop" => self.stopped_at = body["at_s"].as_f64(),
            "rating" => self.rated += 1,
            _ => {}
        }
    }

    /// Where the session stands.
    pub fn phase(&self, conduct: &Conduct, condition: usize) -> Phase {
        if self.due.len() > self.rated {
            Phase::Rate
        } else if self.finished {
            Phase::Done
        } else if self.stopped_at.is_some() && conduct.study.conditions[condition].statements {
            Phase::StateCause
        } else {
            Phase::Watch
        }
    }
}

/// The body of a participant's `enrolled` event.
pub fn enrolled_body(study: &Study, participant: &Participant) -> Value {
    json!({
        "condition": study.conditions[participant.condition].name,
        "arm": study.conditions[participant.condition].arm,
        "seed": participant.seed,
        "snapshot": participant.snapshot,
    })
}

/// How the command an outcome report closed ended (`None` when it does not say).
pub fn outcome_kind(report: &Value) -> Option<OutcomeKind> {
    serde_json::from_value(report["outcome"].clone()).ok()
}

/// What the command an outcome report closed adds to its behavior's inverse trust
/// estimate: its weight times the sign of how it ended (`OutcomeKind::sign`).
pub fn contribution(report: &Value) -> f64 {
    let sign = outcome_kind(report).map_or(-1.0, OutcomeKind::sign);
    sign * report["weight"].as_f64().unwrap_or(1.0)
}

/// The seed of the run shown as command `command` of the participant seeded `seed`.
pub fn run_seed(seed: u64, command: u64) -> u64 {
    mix(seed ^ mix(command.wrapping_add(0x5eed)))
}

/// The request that starts the participant's episode: `serve` draws the first behavior.
const BEGIN: &[u8] = br#"{"request": "begin"}"#;
/// The request that ends it when the study's limits are reached.
const ABANDON: &[u8] = br#"{"request": "abandon"}"#;

fn ask(session: &mut Session, line: &[u8]) -> Result<Value, ConductError> {
    Ok(session.handle_line(line)?.into_value())
}

impl Conduct {
    /// The participant holding `token`.
    pub fn participant(&self, token: &str) -> Result<Participant, ConductError> {
        self.db
            .participant(token)?
            .ok_or_else(|| ConductError::Refused("unknown participant token".into()))
    }

    /// A fresh adapter for `participant`, as `serve` would start it for a controller.
    fn session(&self, participant: &Participant) -> Result<Session, ConductError> {
        let domain = &self.conditions[participant.condition];
        let identity = Identity {
            domain: domain.name.clone(),
            space: (*domain.space).clone(),
        };
        let store = ParticipantCases::open(self.db.clone(), identity, participant)?;
        let memory = domain
            .memory(TrustCaseBase::new())
            .map_err(SessionError::from)?;
        let cases = SharedCases::load(
            Box::new(store),
            memory,
            domain.space.clone(),
            domain.contexts.clone(),
        )
        .map_err(SessionError::Save)?;
        Ok(Session::new(
            domain.clone(),
            Arc::new(cases),
            participant.seed,
        )?)
    }

    /// Replays `participant`'s `events`.
    pub fn replay(
        &self,
        participant: &Participant,
        events: &[Event],
    ) -> Result<Replayed, ConductError> {
        let mut session = self.session(participant)?;
        let begun = ask(&mut session, BEGIN)?;
        let behavior = current(&session).ok_or_else(|| {
            ConductError::Refused(format!("the adapter did not begin an episode: {begun}"))
        })?;
        let mut replayed = Replayed {
            session,
            behavior,
            commands: 0,
            behaviors: 1,
            shown: false,
            stopped_at: None,
            last: None,
            due: Vec::new(),
            rated: 0,
            finished: false,
            next_seq: 0,
            estimate: 0.0,
        };
        for event in events {
            replayed.next_seq = event.seq + 1;
            match event.kind.as_str() {
                "decision" => self.replay_decision(participant, &mut replayed, event)?,
                kind => replayed.note(kind, &event.body),
            }
        }
        Ok(replayed)
    }

    /// Feeds a recorded decision's outcome report (and abandon) to the adapter and checks
    /// its replies are the ones recorded.
    fn replay_decision(
        &self,
        participant: &Participant,
        replayed: &mut Replayed,
        event: &Event,
    ) -> Result<(), ConductError> {
        let report = event.body["report"].to_string();
        let reply = ask(&mut replayed.session, report.as_bytes())?;
        let check = |recorded: &Value, replayed: Value| {
            if *recorded == replayed {
                Ok(())
            } else {
                Err(ConductError::Diverged(Box::new(Divergence {
                    participant: participant.pseudonym(),
                    seq: event.seq,
                    recorded: recorded.clone(),
                    replayed,
                })))
            }
        };
        check(&event.body["reply"], reply.clone())?;
        let abandoned = match event.body.get("abandon_reply") {
            Some(recorded) if !recorded.is_null() => {
                let reply = ask(&mut replayed.session, ABANDON)?;
                check(recorded, reply.clone())?;
                Some(reply)
            }
            _ => None,
        };
        self.close(replayed, &event.body["report"], &reply, abandoned.as_ref());
        Ok(())
    }

    /// Moves `replayed` past a closed command whose report got `reply` (and `abandoned`,
    /// when the study's limits ended the episode there).
    fn close(
        &self,
        replayed: &mut Replayed,
        report: &Value,
        reply: &Value,
        abandoned: Option<&Value>,
    ) {
        let command = replayed.commands;
        let outcome = report["outcome"].as_str().unwrap_or_default().to_owned();
        replayed.estimate += contribution(report);
        replayed.commands += 1;
        replayed.shown = false;
        replayed.stopped_at = None;
        let decision = match abandoned {
            Some(_) => "abandoned",
            None => reply["ok"].as_str().unwrap_or("error"),
        }
        .to_owned();
        let explanation = reply["explanation"]["sentence"].as_str().map(str::to_owned);
        let ended_behavior = decision != "keep";
        let owes = match self.study.rating.after {
            RateAfter::EachBehavior => ended_behavior,
            RateAfter::Commands(n) => {
                replayed.commands.is_multiple_of(u64::from(n.get()))
                    || decision != "keep" && decision != "switch"
            }
        };
        if owes {
            replayed.due.push(Due {
                after_command: command,
                behaviors: replayed.behaviors,
                estimate: replayed.estimate,
            });
        }
        match decision.as_str() {
            "switch" => {
                replayed.behaviors += 1;
                replayed.estimate = 0.0;
            }
            "keep" => {}
            _ => replayed.finished = true,
        }
        if let Some(behavior) = current(&replayed.session) {
            replayed.behavior = behavior;
        }
        replayed.last = Some(Closed {
            command,
            outcome,
            decision,
            explanation,
        });
    }

    /// The state the page renders (docs/studies.md, "The page's API").
    pub fn state(&self, participant: &Participant, replayed: &Replayed) -> Value {
        let condition = &self.study.conditions[participant.condition];
        let phase = replayed.phase(self, participant.condition);
        let domain = &self.conditions[participant.condition];
        let mut state = json!({
            "participant": participant.pseudonym(),
            "condition": {
                "name": condition.name,
                "explanations": condition.explanations,
                "statements": condition.statements,
            },
            "phase": phase.name(),
            "progress": {
                "commands": replayed.commands,
                "max_commands": self.study.commands.get(),
                "behaviors": replayed.behaviors,
                "max_behaviors": self.study.behaviors.get(),
            },
            "last": replayed.last.as_ref().map(|last| json!({
                "command": last.command,
                "outcome": last.outcome,
                "decision": last.decision,
                "explanation": if condition.explanations { last.explanation.clone() } else { None },
            })),
            "rating": null,
        });
        if condition.statements {
            state["causes"] = domain
                .causes
                .iter()
                .map(|c| json!({"name": c.name.as_str(), "text": self.stage.cause_text(c.name.as_str())}))
                .collect();
        }
        match phase {
            Phase::Watch | Phase::StateCause => {
                let seed = run_seed(participant.seed, replayed.commands);
                let run = self.stage.show(&replayed.behavior, seed);
                state["command"] = json!({
                    "index": replayed.commands,
                    "behavior": domain.space.display(&replayed.behavior).to_string(),
                    "speedup": self.study.speedup.get(),
                    "stopped_at": replayed.stopped_at,
                    "run": run.picture,
                });
            }
            Phase::Rate => {
                let (min, max) = self.study.rating.scale.range();
                let scale = match self.study.rating.scale {
                    Scale::Likert(points) => json!({"kind": "likert", "points": points.get()}),
                    Scale::Slider => json!({"kind": "slider", "min": min, "max": max}),
                };
                let mut scale = scale;
                scale["low"] = json!(self.study.rating.low);
                scale["high"] = json!(self.study.rating.high);
                state["rating"] = json!({
                    "number": replayed.rated,
                    "question": self.study.rating.question,
                    "scale": scale,
                });
            }
            Phase::Done => {}
        }
        state
    }

    /// The events an action adds to `replayed`'s session, checked against it, each taken
    /// into `replayed` as it is made (as a replay would take it in); `None` when the action
    /// was already recorded (a repeated request).
    pub fn act(
        &self,
        participant: &Participant,
        replayed: &mut Replayed,
        action: &Action,
    ) -> Result<Option<Vec<NewEvent>>, ConductError> {
        let phase = replayed.phase(self, participant.condition);
        let open = replayed.commands;
        let condition = &self.study.conditions[participant.condition];
        let refuse = |what: String| Err(ConductError::Refused(what));
        match *action {
            Action::Leave => Ok(Some(vec![NewEvent {
                kind: "left",
                body: json!({}),
            }])),
            Action::Shown { command } => {
                if command < open || phase != Phase::Watch && command == open {
                    return Ok(Some(vec![NewEvent {
                        kind: "resumed",
                        body: json!({"command": command}),
                    }]));
                }
                self.check_open(phase, Phase::Watch, command, open)?;
                let kind = if replayed.shown { "resumed" } else { "shown" };
                let domain = &self.conditions[participant.condition];
                let body = json!({
                    "command": command,
                    "behavior": domain.space.display(&replayed.behavior).to_string(),
                    "run_seed": run_seed(participant.seed, command),
                });
                replayed.note(kind, &body);
                Ok(Some(vec![NewEvent { kind, body }]))
            }
            Action::Stop { command, at_s } => {
                if command < open || phase == Phase::StateCause && command == open {
                    return Ok(None);
                }
                self.check_open(phase, Phase::Watch, command, open)?;
                let seed = run_seed(participant.seed, command);
                let duration = self.stage.show(&replayed.behavior, seed).duration_s;
                if !(at_s.is_finite() && (0.0..=duration).contains(&at_s)) {
                    return refuse(format!(
                        "field `at_s`: {at_s} is not a moment of the run: allowed 0 to {duration}"
                    ));
                }
                let stop = NewEvent {
                    kind: "stop",
                    body: json!({"command": command, "at_s": at_s}),
                };
                replayed.note(stop.kind, &stop.body);
                if condition.statements {
                    Ok(Some(vec![stop]))
                } else {
                    let decision =
                        self.decide(replayed, participant, Ending::Stopped(at_s), None)?;
                    Ok(Some(vec![stop, decision]))
                }
            }
            Action::Statement { command, ref cause } => {
                if command < open {
                    return Ok(None);
                }
                self.check_open(phase, Phase::StateCause, command, open)?;
                let domain = &self.conditions[participant.condition];
                if let Some(cause) = cause
                    && !domain.causes.iter().any(|c| c.name.as_str() == cause)
                {
                    let known: Vec<&str> = domain.causes.iter().map(|c| c.name.as_str()).collect();
                    return refuse(format!(
                        "field `cause`: `{cause}` is not a cause of {}: allowed {} or null",
                        domain.name,
                        known.join(", ")
                    ));
                }
                let at_s = replayed.stopped_at.expect("a stated cause follows a stop");
                let decision = self.decide(
                    replayed,
                    participant,
                    Ending::Stopped(at_s),
                    cause.as_deref(),
                )?;
                Ok(Some(vec![
                    NewEvent {
                        kind: "statement",
                        body: json!({"command": command, "cause": cause}),
                    },
                    decision,
                ]))
            }
            Action::End { command } => {
                if command < open {
                    return Ok(None);
                }
                self.check_open(phase, Phase::Watch, command, open)?;
                let decision = self.decide(replayed, participant, Ending::RanOut, None)?;
                Ok(Some(vec![
                    NewEvent {
                        kind: "end",
                        body: json!({"command": command}),
                    },
                    decision,
                ]))
            }
            Action::Rating { number, value } => {
                if number < replayed.rated {
                    return Ok(None);
                }
                if phase != Phase::Rate || number != replayed.rated {
                    return refuse(format!(
                        "no rating {number} is asked for now (the session is at `{}`)",
                        phase.name()
                    ));
                }
                let (min, max) = self.study.rating.scale.range();
                if !(f64::from(min)..=f64::from(max)).contains(&value) || value.fract() != 0.0 {
                    return refuse(format!(
                        "field `value`: {value} is not on the scale: allowed whole numbers {min} to {max}"
                    ));
                }
                let due = replayed.due[number];
                let rating = NewEvent {
                    kind: "rating",
                    body: json!({
                        "number": number,
                        "after_command": due.after_command,
                        "behaviors": due.behaviors,
                        // A whole number (checked above), stored as one.
                        "value": value as i64,
                        "estimate": due.estimate,
                    }),
                };
                replayed.note(rating.kind, &rating.body);
                Ok(Some(vec![rating]))
            }
        }
    }

    fn check_open(
        &self,
        phase: Phase,
        wanted: Phase,
        command: u64,
        open: u64,
    ) -> Result<(), ConductError> {
        if phase != wanted {
            return Err(ConductError::Refused(format!(
                "the session is at `{}`, not `{}`",
                phase.name(),
                wanted.name()
            )));
        }
        if command != open {
            return Err(ConductError::Refused(format!(
                "field `command`: {command} is not the command shown now ({open})"
            )));
        }
        Ok(())
    }

    /// Closes the open command as `ending` says: its outcome report goes to the adapter
    /// exactly as a controller's would go to `serve`; when the study's limits are reached
    /// the episode is abandoned. Returns the `decision` event.
    fn decide(
        &self,
        replayed: &mut Replayed,
        participant: &Participant,
        ending: Ending,
        stated: Option<&str>,
    ) -> Result<NewEvent, ConductError> {
        let command = replayed.commands;
        let seed = run_seed(participant.seed, command);
        let report = self.stage.outcome(&replayed.behavior, seed, ending, stated);
        let reply = ask(&mut replayed.session, report.to_string().as_bytes())?;
        if reply.get("error").is_some() {
            return Err(ConductError::Refused(format!(
                "the adapter refused the outcome report {report}: {reply}"
            )));
        }
        let closed_all = command + 1 >= u64::from(self.study.commands.get());
        let too_many = reply["ok"] == "switch" && replayed.behaviors >= self.study.behaviors.get();
        let abandon_reply = if (closed_all || too_many)
            && matches!(reply["ok"].as_str(), Some("keep" | "switch"))
        {
            Some(ask(&mut replayed.session, ABANDON)?)
        } else {
            None
        };
        self.close(replayed, &report, &reply, abandon_reply.as_ref());
        Ok(NewEvent {
            kind: "decision",
            body: json!({
                "command": command,
                "report": report,
                "reply": reply,
                "abandon_reply": abandon_reply,
            }),
        })
    }
}

/// The behavior the adapter's episode uses now.
fn current(session: &Session) -> Option<Behavior> {
    session.adaptation().episode().map(|e| e.current)
}

/// What a participant's page asks the console to record.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// The run of `command` started playing.
    Shown {
        /// The command.
        command: u64,
    },
    /// The participant stopped the run of `command` at `at_s` (s of the run).
    Stop {
        /// The command.
        command: u64,
        /// The moment of the run.
        at_s: f64,
    },
    /// The participant said why they stopped `command` (or declined to).
    Statement {
        /// The command.
        command: u64,
        /// The cause, one of the domain's.
        cause: Option<String>,
    },
    /// The run of `command` played to its end unstopped.
    End {
        /// The command.
        command: u64,
    },
    /// The participant gave rating `number`.
    Rating {
        /// Which rating.
        number: usize,
        /// On the study's scale.
        value: f64,
    },
    /// The page was closed or left.
    Leave,
}

/// Runs `action` for the participant holding `token` and returns their state: replays
/// their events, stores what the action adds (durably, before returning), and retries
/// when another request stored an event first.
pub fn perform(
    conduct: &Conduct,
    token: &str,
    action: Option<&Action>,
    now_ms: i64,
) -> Result<Value, ConductError> {
    let participant = conduct.participant(token)?;
    for _ in 0..8 {
        let events = conduct.db.events(participant.number)?;
        let mut replayed = conduct.replay(&participant, &events)?;
        let Some(action) = action else {
            return Ok(conduct.state(&participant, &replayed));
        };
        let Some(new) = conduct.act(&participant, &mut replayed, action)? else {
            return Ok(conduct.state(&participant, &replayed));
        };
        if conduct
            .db
            .append(participant.number, replayed.next_seq, &new, now_ms)?
        {
            return Ok(conduct.state(&participant, &replayed));
        }
    }
    Err(ConductError::Refused(
        "the session is changing too fast: retry".into(),
    ))
}
