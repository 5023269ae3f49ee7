//! [`Session`]: the protocol's request handler over one [`TrustAdapter`].
//!
//! A session turns each request line into exactly one reply and does no I/O of its own
//! beyond saving the case base, so it can be tested without pipes or sockets. A request
//! that is refused (malformed, out of place, unusable numbers) gets an error reply and
//! leaves the adapter, the case base and the session's random stream unchanged. A case the
//! adapter retains is saved before the reply that reports it is returned; if that save
//! fails the session reports [`SessionError::Save`] and the server must stop, so that no
//! reply ever acknowledges a case that is not on disk.

use crate::domain::DomainDefinition;
use crate::reply;
use crate::request::{BehaviorSpec, Request, parse_request};
use crate::store::{CaseStore, StoreError};
use cbr_core::Behavior;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};
use trust::{ConfigError, Decision, Outcome, Source, TrustAdapter, TrustCaseBase};

/// The stream of the seed that draws initial behaviors (the adapter's search uses stream 0).
const DRAW_STREAM: u64 = 1;

/// The state of one served adapter.
pub struct Session {
    domain: String,
    adapter: TrustAdapter,
    store: CaseStore,
    draws: ChaCha8Rng,
}

/// Why a session could not start or must stop.
#[derive(Debug, thiserror::Error)]
pub enum SessionError {
    /// The adapter configuration is unusable (shown in the message, so not chained as a
    /// source).
    #[error("adapter configuration: {0}")]
    Config(ConfigError),
    /// A retained case could not be saved.
    #[error("case #{case} was retained but could not be saved, so the server stops: {reason}")]
    Save {
        /// The case.
        case: u32,
        /// Why the save failed (shown in the message, so not chained as a source).
        reason: StoreError,
    },
}

impl From<ConfigError> for SessionError {
    fn from(reason: ConfigError) -> Self {
        Self::Config(reason)
    }
}

impl Session {
    /// A session serving `domain` from the case base `cases` kept in `store`; `seed` drives
    /// the adapter's search and the server's draws of initial behaviors.
    pub fn new(
        domain: DomainDefinition,
        store: CaseStore,
        cases: TrustCaseBase,
        seed: u64,
    ) -> Result<Self, SessionError> {
        let adapter = TrustAdapter::new(domain.space, domain.adapter, cases, seed)?;
        let mut draws = ChaCha8Rng::seed_from_u64(seed);
        draws.set_stream(DRAW_STREAM);
        Ok(Self {
            domain: domain.name,
            adapter,
            store,
            draws,
        })
    }

    /// Handles one request line (without its newline) and returns the reply.
    pub fn handle_line(&mut self, line: &[u8]) -> Result<Value, SessionError> {
        match parse_request(line) {
            Ok(request) => self.handle(request),
            Err(e) => Ok(reply::error(e)),
        }
    }

    /// Handles one parsed request and returns the reply.
    pub fn handle(&mut self, request: Request) -> Result<Value, SessionError> {
        Ok(match request {
            Request::Begin(spec) => self.begin(spec.as_ref()),
            Request::Outcome(outcome) => return self.outcome(&outcome),
            Request::State => self.state(),
            Request::Cases => self.cases(),
            Request::Abandon => self.abandon(),
            Request::Config => self.config(),
        })
    }

    /// The adapter served.
    pub fn adapter(&self) -> &TrustAdapter {
        &self.adapter
    }

    fn begin(&mut self, spec: Option<&BehaviorSpec>) -> Value {
        if self.adapter.episode().is_some() {
            return reply::error(
                "an episode is already under way: report its outcomes, or end it with {\"request\": \"abandon\"}",
            );
        }
        let space = self.adapter.space().clone();
        let (initial, chosen_by) = match spec {
            None => (space.draw(&mut self.draws), "server"),
            Some(spec) => {
                let parsed = match spec {
                    BehaviorSpec::Text(text) => space.parse(text),
                    BehaviorSpec::Values(values) => space
                        .from_named_values(values.iter().map(|(n, v)| (n.as_str(), v.as_str()))),
                };
                match parsed {
                    Ok(b) => (b, "controller"),
                    Err(e) => return reply::error(format_args!("field `behavior`: {e}")),
                }
            }
        };
        match self.adapter.begin_episode(initial) {
            Ok(()) => json!({
                "ok": "begun",
                "behavior": reply::behavior(&space, &initial),
                "chosen_by": chosen_by,
            }),
            Err(e) => reply::error(e),
        }
    }

    fn outcome(&mut self, outcome: &Outcome) -> Result<Value, SessionError> {
        let Some(episode) = self.adapter.episode() else {
            return Ok(reply::error(
                "no episode is under way: start one with {\"request\": \"begin\"}",
            ));
        };
        // The elapsed time becomes a case's evaluated time; an infinite one could not be
        // loaded back, so it is refused here.
        if !(episode.estimate.elapsed_s + outcome.duration_s).is_finite() {
            return Ok(reply::error(format_args!(
                "field `duration_s`: {} s would make the behavior's total time overflow",
                outcome.duration_s
            )));
        }
        let decision = match self.adapter.record(outcome) {
            Ok(decision) => decision,
            Err(e) => return Ok(reply::error(e)),
        };
        let space = self.adapter.space().clone();
        Ok(match decision {
            Decision::Keep => {
                let episode = self.adapter.episode();
                json!({
                    "ok": "keep",
                    "behavior": episode.map(|e| reply::behavior(&space, &e.current)),
                    "trust": episode.map(|e| e.estimate.value),
                })
            }
            Decision::Switch { to, source } => switch(&space, &to, source),
            Decision::Settled(report) => {
                if let Some(case) = report.retained {
                    self.store
                        .save(self.adapter.cases())
                        .map_err(|reason| SessionError::Save {
                            case: case.0,
                            reason,
                        })?;
                }
                reply::episode_end("settled", &space, &report, self.adapter.cases().len())
            }
        })
    }

    fn state(&self) -> Value {
        let space = self.adapter.space();
        let episode = self.adapter.episode().map(|e| {
            json!({
                "behavior": reply::behavior(space, &e.current),
                "trust": e.estimate.value,
                "elapsed_s": e.estimate.elapsed_s,
                "behavior_commands": e.estimate.commands,
                "commands": e.commands,
                "evaluated": reply::evaluated(space, e.evaluated),
            })
        });
        json!({
            "ok": "state",
            "domain": self.domain,
            "episode": episode,
            "cases": self.adapter.cases().len(),
        })
    }

    fn cases(&self) -> Value {
        let space = self.adapter.space();
        let cases: Vec<Value> = self
            .adapter
            .cases()
            .iter()
            .map(|(id, case)| {
                json!({
                    "id": id.0,
                    "evaluated": reply::evaluated(space, &case.problem),
                    "solution": reply::behavior(space, &case.solution),
                })
            })
            .collect();
        json!({ "ok": "cases", "cases": cases })
    }

    fn abandon(&mut self) -> Value {
        match self.adapter.abandon_episode() {
            Some(report) => reply::episode_end(
                "abandoned",
                self.adapter.space(),
                &report,
                self.adapter.cases().len(),
            ),
            None => reply::error("no episode is under way: there is nothing to abandon"),
        }
    }

    fn config(&self) -> Value {
        json!({
            "ok": "config",
            "domain": self.domain,
            "space": self.adapter.space().as_ref(),
            "behaviors": self.adapter.space().size(),
            "adapter": self.adapter.config(),
        })
    }
}

fn switch(space: &cbr_core::BehaviorSpace, to: &Behavior, source: Source) -> Value {
    let mut reply = json!({
        "ok": "switch",
        "behavior": reply::behavior(space, to),
    });
    match source {
        Source::Search => reply["source"] = json!("search"),
        Source::Case { case, similarity } => {
            reply["source"] = json!("case");
            reply["case"] = json!(case.0);
            reply["similarity"] = json!(similarity);
        }
    }
    reply
}
