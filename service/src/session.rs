//! [`Session`]: the protocol's request handler for one controller.
//!
//! A session is one robot's [`Adaptation`] (its episode and search) over the server's
//! [`SharedCases`]: several sessions, one per connection, share one case memory. A session
//! turns each request line into exactly one reply and does no I/O of its own beyond the
//! case store, so it can be tested without pipes or sockets. A request that is refused
//! (malformed, out of place, unusable numbers, a case store that cannot be read) gets an
//! error reply and leaves the episode, the case base and the session's random stream
//! unchanged. Before every outcome is recorded the memory catches up with the store, so a
//! selection sees every case any process has retained. A case the episode retains is
//! stored durably before the reply that reports it is returned; if that fails the session
//! reports [`SessionError::Save`] and the server must stop, so that no reply ever
//! acknowledges a case that is not stored.
//!
//! In mission mode ([`DomainDefinition::in_mission_mode`]) the session's adaptation is
//! wrapped in a [`MissionAdaptation`]: outcomes keep coming after an episode settles; they
//! are answered for the settled behavior under watch (its estimate capped at the
//! trustworthy threshold, [`trust::watch`]), a fall of that estimate starts a new episode
//! with a switch, and an alert asks the operator to supervise ([`trust::overtrust`]);
//! `state` and `explain` report the watch, and `config` shows `"mode": "mission"` in
//! `adapter`.

use crate::domain::DomainDefinition;
use crate::reply::{self, Answer, CaseListing, Reply};
use crate::request::{BehaviorSpec, ContextSettings, Request, Vocabulary, parse_line};
use crate::shared::SharedCases;
use crate::store::{StoreError, StoreId};
use cbr_core::{Behavior, Context, ContextSpace, Statement};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};
use std::sync::Arc;
use trust::{
    Account, Adaptation, AdapterError, Cause, ConfigError, Decision, DeclaredCause, EpisodeReport,
    MissionAdaptation, MissionDecision, Outcome, Source, SwitchStart, TrustEstimate, TrustMemory,
    Watch,
};

/// How the protocol names where the behavior after a context switch comes from.
fn switch_start(from: SwitchStart) -> &'static str {
    match from {
        SwitchStart::Kept => "kept",
        SwitchStart::Resumed => "resumed",
        SwitchStart::Guessed => "guessed",
        SwitchStart::Restarted => "restarted",
    }
}

/// The stream of the seed that draws initial behaviors (the adapter's search uses stream 0).
const DRAW_STREAM: u64 = 1;

/// The state of one controller's conversation.
pub struct Session {
    domain: String,
    causes: Vec<DeclaredCause>,
    observations: Vec<Cause>,
    /// The context variables the domain declares.
    contexts: Arc<ContextSpace>,
    /// The names the domain's operators may state preferences in.
    statements: Vec<String>,
    /// The adapter served, as `config` shows it ([`DomainDefinition::served_adapter`]).
    adapter: Value,
    adapting: Adapting,
    cases: Arc<SharedCases>,
    draws: ChaCha8Rng,
    /// The safer behavior the last reply's overtrust alert offered, until the next
    /// request.
    offer: Option<Behavior>,
}

/// One controller's adapter: the paper's episodes, or mission mode around them.
#[allow(
    clippy::large_enum_variant,
    reason = "one per session, never moved in a loop: its size does not matter"
)]
enum Adapting {
    Episodes(Adaptation),
    Mission(MissionAdaptation<'static>),
}

impl Adapting {
    /// The episode machine.
    fn episodes(&self) -> &Adaptation {
        match self {
            Self::Episodes(adaptation) => adaptation,
            Self::Mission(mission) => mission.adaptation(),
        }
    }

    /// The mission wrapper, in mission mode.
    fn mission(&self) -> Option<&MissionAdaptation<'static>> {
        match self {
            Self::Episodes(_) => None,
            Self::Mission(mission) => Some(mission),
        }
    }

    fn begin_episode(
        &mut self,
        initial: Behavior,
        stated: Vec<Statement>,
    ) -> Result<(), AdapterError> {
        match self {
            Self::Episodes(adaptation) => adaptation.begin_episode_hearing(initial, stated),
            Self::Mission(mission) => mission.begin_episode_hearing(initial, stated),
        }
    }

    fn set_context(&mut self, context: Context) -> Result<(), AdapterError> {
        match self {
            Self::Episodes(adaptation) => adaptation.set_context(context),
            Self::Mission(mission) => mission.set_context(context),
        }
    }

    /// Records an outcome; the paper's episodes decide no alert.
    fn record(
        &mut self,
        outcome: &Outcome,
        memory: &TrustMemory,
    ) -> Result<MissionDecision, AdapterError> {
        match self {
            Self::Episodes(adaptation) => adaptation.record(outcome, memory).map(Into::into),
            Self::Mission(mission) => mission.record(outcome, memory),
        }
    }

    fn abandon_episode(&mut self) -> Option<EpisodeReport> {
        match self {
            Self::Episodes(adaptation) => adaptation.abandon_episode(),
            Self::Mission(mission) => mission.abandon_episode(),
        }
    }

    /// The behavior in use and its estimate: the episode's, or in mission mode the
    /// watched behavior's between episodes.
    fn in_use(&self) -> Option<(Behavior, TrustEstimate)> {
        match self {
            Self::Episodes(adaptation) => adaptation.episode().map(|e| (e.current, e.estimate)),
            Self::Mission(mission) => mission.in_use(),
        }
    }

    /// The account of the behavior in use: the episode's, or in mission mode the watched
    /// behavior's between episodes.
    fn standing(&self) -> Option<Account> {
        match self {
            Self::Episodes(adaptation) => adaptation.standing(),
            Self::Mission(mission) => mission.standing(),
        }
    }
}

/// Why a session could not start or must stop.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SessionError {
    /// The adapter configuration is unusable (shown in the message, so not chained as a
    /// source).
    #[error("adapter configuration: {0}")]
    Config(ConfigError),
    /// A retained case could not be stored (shown in the message, so not chained as a
    /// source).
    #[error("a case was retained but could not be stored, so the server stops: {0}")]
    Save(StoreError),
}

impl From<ConfigError> for SessionError {
    fn from(reason: ConfigError) -> Self {
        Self::Config(reason)
    }
}

impl Session {
    /// A session serving `domain` over the shared case memory `cases`, searching with a
    /// fresh searcher of the domain's ([`DomainDefinition::build_searcher`]: a user's, or
    /// the kind its config names); `seed` drives the search and the server's draws of
    /// initial behaviors.
    pub fn new(
        domain: DomainDefinition,
        cases: Arc<SharedCases>,
        seed: u64,
    ) -> Result<Self, SessionError> {
        let adaptation = Adaptation::with_parts(
            domain.space.clone(),
            domain.adapter.parameters(),
            domain.build_searcher(),
            ChaCha8Rng::seed_from_u64(seed),
        )?
        .with_vocabulary(domain.vocabulary());
        let adapting = if domain.mission() {
            let mut mission = MissionAdaptation::new(adaptation);
            if let Some(detector) = domain.change_detector() {
                mission = mission.detecting_changes(detector);
            }
            Adapting::Mission(match domain.competence_judge() {
                Some(judge) => mission
                    .with_competence(judge)
                    .preferring_competent(domain.competent_passes()),
                None => mission,
            })
        } else {
            Adapting::Episodes(adaptation)
        };
        let mut draws = ChaCha8Rng::seed_from_u64(seed);
        draws.set_stream(DRAW_STREAM);
        let adapter = domain.served_adapter();
        Ok(Self {
            domain: domain.name,
            causes: domain.causes,
            observations: domain.observations,
            contexts: domain.contexts,
            statements: domain.statements,
            adapter,
            adapting,
            cases,
            draws,
            offer: None,
        })
    }

    /// Handles one request line (without its newline) and returns the reply, which echoes
    /// the request's `id`.
    pub fn handle_line(&mut self, line: &[u8]) -> Result<Answer, SessionError> {
        let vocabulary = Vocabulary {
            causes: &self.causes,
            observations: &self.observations,
        };
        let envelope = parse_line(line, vocabulary);
        let reply = match envelope.request {
            Ok(request) => self.handle(request)?,
            Err(e) => Reply::Json(reply::error(e)),
        };
        Ok(reply.with_id(envelope.id))
    }

    /// Handles one parsed request and returns the reply.
    pub fn handle(&mut self, request: Request) -> Result<Reply, SessionError> {
        // An offer stands for the request right after its alert only.
        let offer = self.offer.take();
        Ok(Reply::Json(match request {
            Request::AcceptOffer => self.accept_offer(offer),
            Request::Begin {
                behavior,
                context,
                preferences,
            } => self.begin(behavior.as_ref(), context.as_ref(), preferences),
            Request::Context(settings) => self.change_context(&settings),
            Request::Outcome(outcome) => return self.outcome(&outcome).map(Reply::Json),
            Request::State => self.state(),
            Request::Cases => return Ok(self.cases()),
            Request::Abandon => self.abandon(),
            Request::Config => self.config(),
            Request::Explain => self.explain(),
        }))
    }

    /// This controller's episode machine (its episode, the space, the parameters).
    pub fn adaptation(&self) -> &Adaptation {
        self.adapting.episodes()
    }

    /// The context `settings` name, checked against the domain's context space.
    fn context(&self, settings: &ContextSettings) -> Result<Context, Value> {
        let named = settings.iter().map(|(k, v)| (k.as_str(), v.as_str()));
        self.contexts
            .context(named)
            .map_err(|e| reply::error(format_args!("field `context`: {e}")))
    }

    /// A `context` request: the robot's context from now on, between episodes; in mission
    /// mode, once a behavior is in use, a switch the robot is told mid-mission
    /// ([`MissionAdaptation::switch_context`]), answered with the behavior to use.
    fn change_context(&mut self, settings: &ContextSettings) -> Value {
        if let Adapting::Mission(mission) = &self.adapting
            && mission.in_use().is_some()
        {
            return self.switch_context(settings);
        }
        if self.adaptation().episode().is_some() {
            return reply::error(
                "an episode is under way, and its behaviors were all evaluated in the context it began in: change the context after it settles, or end it with {\"request\": \"abandon\"}",
            );
        }
        let context = match self.context(settings) {
            Ok(context) => context,
            Err(refused) => return refused,
        };
        match self.adapting.set_context(context) {
            Ok(()) => json!({"ok": "context", "context": self.adaptation().context()}),
            Err(e) => reply::error(e),
        }
    }

    /// A context switch mid-mission: the episode under way ends, and the robot goes back
    /// to what it last settled on in the new context, or carries on with the behavior in
    /// use; the reply says which (`from`: `kept`, `resumed` or `restarted`) and whether a
    /// watched behavior was given up.
    fn switch_context(&mut self, settings: &ContextSettings) -> Value {
        let context = match self.context(settings) {
            Ok(context) => context,
            Err(refused) => return refused,
        };
        let Adapting::Mission(mission) = &mut self.adapting else {
            unreachable!("called in mission mode only")
        };
        let switched = match mission.switch_context(context, None) {
            Ok(switched) => switched,
            Err(e) => return reply::error(e),
        };
        let space = self.adaptation().space().clone();
        json!({
            "ok": "context",
            "context": self.adaptation().context(),
            "behavior": reply::behavior(&space, &switched.behavior),
            "from": switch_start(switched.from),
            "gave_up_watch": switched.gave_up_watch,
        })
    }

    fn begin(
        &mut self,
        spec: Option<&BehaviorSpec>,
        context: Option<&ContextSettings>,
        preferences: Vec<Statement>,
    ) -> Value {
        if self.adaptation().episode().is_some() {
            return reply::error(
                "an episode is already under way: report its outcomes, or end it with {\"request\": \"abandon\"}",
            );
        }
        if let Some(unknown) = preferences
            .iter()
            .find(|s| !self.statements.contains(&s.name))
        {
            let declared = if self.statements.is_empty() {
                "this domain declares none".to_owned()
            } else {
                format!("declared: {}", self.statements.join(", "))
            };
            return reply::error(format_args!(
                "field `preferences`: `{}` is not a statement of this domain ({declared})",
                unknown.name
            ));
        }
        let context = match context.map(|settings| self.context(settings)).transpose() {
            Ok(context) => context,
            Err(refused) => return refused,
        };
        let space = self.adaptation().space().clone();
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
        let before = self.adaptation().context().clone();
        if let Some(context) = context
            && let Err(e) = self.adapting.set_context(context)
        {
            return reply::error(e);
        }
        let begun = self.adapting.begin_episode(initial, preferences);
        if begun.is_err() {
            // A refused request changes nothing.
            self.adapting
                .set_context(before)
                .expect("no episode is under way");
        }
        match begun {
            Ok(()) => {
                let mut begun = json!({
                    "ok": "begun",
                    "behavior": reply::behavior(&space, &initial),
                    "chosen_by": chosen_by,
                });
                reply::add_context(&mut begun, self.adaptation().context());
                let heard = self.adaptation().stated();
                if !heard.is_empty() {
                    begun["preferences"] = heard
                        .iter()
                        .map(|s| (s.name.clone(), Value::Bool(s.minds)))
                        .collect::<serde_json::Map<_, _>>()
                        .into();
                }
                begun
            }
            Err(e) => reply::error(e),
        }
    }

    fn outcome(&mut self, outcome: &Outcome) -> Result<Value, SessionError> {
        let Some((_, estimate)) = self.adapting.in_use() else {
            return Ok(reply::error(
                "no episode is under way: start one with {\"request\": \"begin\"}",
            ));
        };
        // The elapsed time becomes a case's evaluated time; an infinite one could not be
        // loaded back, so it is refused here.
        if !(estimate.elapsed_s + outcome.duration_s).is_finite() {
            return Ok(reply::error(format_args!(
                "field `duration_s`: {} s would make the behavior's total time overflow",
                outcome.duration_s
            )));
        }
        let adapting = &mut self.adapting;
        let recorded = self.cases.current(|memory, ids| {
            adapting.record(outcome, memory).map(|decision| {
                // A reused case is shown by its store id.
                let reused = match &decision {
                    MissionDecision::Episode(Decision::Switch {
                        source: Source::Case { case, .. },
                        ..
                    }) => Some(ids[case.index()]),
                    _ => None,
                };
                (decision, reused, ids.len())
            })
        });
        let (decision, reused, held) = match recorded {
            Ok(Ok(recorded)) => recorded,
            Ok(Err(e)) => return Ok(reply::error(e)),
            Err(e) => return Ok(store_unavailable(&e)),
        };
        let space = self.adaptation().space().clone();
        Ok(match decision {
            MissionDecision::Episode(Decision::Keep) => {
                let in_use = self.adapting.in_use();
                json!({
                    "ok": "keep",
                    "behavior": in_use.map(|(b, _)| reply::behavior(&space, &b)),
                    "trust": in_use.map(|(_, e)| e.value),
                })
            }
            MissionDecision::Episode(Decision::Switch {
                to,
                source,
                explanation,
            }) => {
                let mut reply = switch(&space, &to, source, reused);
                reply["explanation"] = reply::explanation(&space, &explanation, &|_| reused);
                reply
            }
            MissionDecision::Alert(alert) => reply::alert(&space, &alert),
            MissionDecision::Overtrust(alert) => {
                self.offer = alert.offer;
                reply::overtrust(&space, &alert)
            }
            MissionDecision::Episode(Decision::Settled(report)) => {
                let (retained, held) = match self.adaptation().case_to_retain(&report) {
                    Some(case) if self.cases.writable() => {
                        let (id, held) = self.cases.retain(case).map_err(SessionError::Save)?;
                        (Some(id), held)
                    }
                    _ => (None, held),
                };
                let explanation = report
                    .explanations
                    .last()
                    .map(|e| reply::explanation(&space, e, &|_| None));
                reply::episode_end("settled", &space, &report, retained, held, explanation)
            }
        })
    }

    fn state(&self) -> Value {
        let held = match self.cases.current(|memory, _| memory.base().len()) {
            Ok(held) => held,
            Err(e) => return store_unavailable(&e),
        };
        let space = self.adaptation().space();
        let episode = self.adaptation().episode().map(|e| {
            json!({
                "behavior": reply::behavior(space, &e.current),
                "trust": e.estimate.value,
                "elapsed_s": e.estimate.elapsed_s,
                "behavior_commands": e.estimate.commands,
                "commands": e.commands,
                "evaluated": reply::evaluated(space, e.evaluated),
            })
        });
        let mut reply = json!({
            "ok": "state",
            "domain": self.domain,
            "episode": episode,
        });
        reply::add_context(&mut reply, self.adaptation().context());
        if let Some(mission) = self.adapting.mission() {
            reply["watching"] = json!(mission.watching().map(|w| {
                let mut watching = json!({
                    "behavior": reply::behavior(space, &w.behavior),
                    "trust": w.estimate.value,
                    "commands": w.commands,
                    "own_record": mission.own_record().value(),
                });
                self.add_calibration(&mut watching, mission, w);
                watching
            }));
        }
        reply["cases"] = json!(held);
        reply
    }

    fn cases(&self) -> Reply {
        match self.cases.current(|memory, _| memory.base().len()) {
            Ok(count) => Reply::Cases(CaseListing {
                cases: self.cases.clone(),
                space: self.adaptation().space().clone(),
                count,
            }),
            Err(e) => Reply::Json(store_unavailable(&e)),
        }
    }

    /// Takes `offer`, the safer behavior the reply before offered: the watch moves to it.
    fn accept_offer(&mut self, offer: Option<Behavior>) -> Value {
        let (Some(offer), Adapting::Mission(mission)) = (offer, &mut self.adapting) else {
            return reply::error(
                "no offer to accept: the request right after an `overtrust` reply with an `offer` takes it",
            );
        };
        match mission.accept_offer(offer) {
            Ok(()) => json!({
                "ok": "accepted",
                "behavior": reply::behavior(self.adapting.episodes().space(), &offer),
            }),
            Err(e) => reply::error(e),
        }
    }

    fn abandon(&mut self) -> Value {
        let held = match self.cases.current(|memory, _| memory.base().len()) {
            Ok(held) => held,
            Err(e) => return store_unavailable(&e),
        };
        if let Some(watch) = self.adapting.mission().and_then(|m| m.watching().copied()) {
            // Mission mode: the operator left while a settled behavior was watched.
            self.adapting.abandon_episode();
            return json!({
                "ok": "abandoned",
                "behavior": reply::behavior(self.adaptation().space(), &watch.behavior),
                "commands": watch.commands,
                "cases": held,
            });
        }
        match self.adapting.abandon_episode() {
            Some(report) => reply::episode_end(
                "abandoned",
                self.adaptation().space(),
                &report,
                None,
                held,
                None,
            ),
            None => reply::error("no episode is under way: there is nothing to abandon"),
        }
    }

    /// The explanation of the episode so far: the account of the behavior in use and the
    /// explanation of every switch, reused cases named by their store ids; in mission mode
    /// also the account of the behavior watched between episodes.
    fn explain(&self) -> Value {
        let space = self.adaptation().space();
        let standing = self.adapting.standing();
        let episode = match (self.adaptation().episode(), &standing) {
            (Some(episode), Some(standing)) => {
                let switches = self.cases.current(|_, ids| {
                    episode
                        .explanations
                        .iter()
                        .map(|e| {
                            reply::explanation(space, e, &|case| ids.get(case.index()).copied())
                        })
                        .collect::<Vec<Value>>()
                });
                let switches = match switches {
                    Ok(switches) => switches,
                    Err(e) => return store_unavailable(&e),
                };
                json!({
                    "current": reply::account(space, standing),
                    "commands": episode.commands,
                    "switches": switches,
                })
            }
            _ => Value::Null,
        };
        let mut reply = json!({ "ok": "explanation", "episode": episode });
        if let Some(mission) = self.adapting.mission() {
            // The account `standing` gives is the watched behavior's between episodes.
            let watching = mission.watching().zip(standing);
            reply["watching"] = json!(watching.map(|(w, standing)| {
                let mut watching = json!({
                    "current": reply::account(space, &standing),
                    "commands": w.commands,
                    "own_record": mission.own_record().value(),
                });
                self.add_calibration(&mut watching, mission, w);
                watching
            }));
        }
        reply
    }

    /// Adds to a `watching` object the calibration of the watched behavior, when the robot
    /// judges its own competence.
    fn add_calibration(
        &self,
        watching: &mut Value,
        mission: &MissionAdaptation<'_>,
        watch: &Watch,
    ) {
        if let Some(judge) = mission.competence_judge() {
            watching["calibration"] = reply::calibration(
                judge,
                watch.behavior,
                watch.estimate.value,
                &self.adaptation().parameters().thresholds,
            );
        }
    }

    fn config(&self) -> Value {
        let mut config = json!({
            "ok": "config",
            "domain": self.domain,
            "causes": self.causes,
            "observations": self.observations,
            "space": self.adaptation().space().as_ref(),
            "behaviors": self.adaptation().space().size(),
            "adapter": self.adapter,
            "strategy": self.adaptation().strategy(),
        });
        if !self.contexts.is_empty() {
            config["contexts"] = json!(self.contexts.as_ref());
        }
        if !self.statements.is_empty() {
            config["statements"] = json!(self.statements);
        }
        config
    }
}

fn store_unavailable(e: &StoreError) -> Value {
    reply::error(format_args!("the case base cannot be read: {e}"))
}

fn switch(
    space: &cbr_core::BehaviorSpace,
    to: &Behavior,
    source: Source,
    reused: Option<StoreId>,
) -> Value {
    let mut reply = json!({
        "ok": "switch",
        "behavior": reply::behavior(space, to),
    });
    match source {
        Source::Search => reply["source"] = json!("search"),
        Source::Case { similarity, .. } => {
            reply["source"] = json!("case");
            reply["case"] = json!(reused);
            reply["similarity"] = json!(similarity);
        }
    }
    reply
}
