//! `TrustAdapter`: the online state machine a robot embeds (and the experiment runner drives).
//!
//! Report every command's outcome with [`TrustAdapter::record`]; the answer says whether to
//! keep the current behavior, switch to another, or that the episode is over (a trustworthy
//! behavior was found, or every behavior was tried). In mission mode ([`Mode::Mission`],
//! docs/missions.md) outcomes keep coming after the episode is over: the settled behavior
//! stays under watch ([`crate::watch`]), a fall of its estimate to the untrustworthy
//! threshold starts a new episode with a switch, and an [`Alert`] asks the operator to
//! supervise when its trust is high while the robot's own record is not
//! ([`crate::overtrust`]). An [`Adaptation`] holds one robot's
//! episode (the evaluated pairs `E_past`) and search strategy and selects from a case memory
//! it is handed; the [`TrustAdapter`] pairs one with the memory it owns and retains a case at
//! the end of an episode (docs/model.md#cases-and-retention). Robots sharing one case
//! memory each drive their own `Adaptation`.

use crate::estimate::{
    Outcome, OutcomeError, OutcomeKind, ThresholdError, Thresholds, TrustEstimate, Verdict,
};
use crate::evaluated::{LambdaError, validate_lambda};
use crate::explain::{Attribution, Explanation, GivenUp, Next, Vocabulary};
use crate::overtrust::{Alert, OwnRecord};
use crate::retrieval::RetrieverKind;
use crate::search::{SearchKind, TrustSearcher};
use crate::select::{Selection, select_behavior};
use crate::start::{FirstGuess, first_guess};
use crate::watch::{Mode, Watch};
use crate::{Evaluated, TrustCase, TrustCaseBase, TrustMemory};
use cbr_core::{Behavior, BehaviorSpace, Case, CaseId, Proposal};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The adapter's parameters; the defaults are the paper's.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AdapterConfig {
    /// The trust thresholds (paper: +5 / -5).
    pub thresholds: Thresholds,
    /// Algorithm 2's behavior-similarity threshold (paper: 0.95), in `(0, 1]`; checked
    /// when deserialized, so a parser reports the position of a bad value.
    #[serde(deserialize_with = "crate::evaluated::deserialize_lambda")]
    pub lambda: f64,
    /// Reuse cases (Algorithm 1) before searching; `false` is the search strategy alone.
    pub reuse_cases: bool,
    /// The retriever that answers Algorithm 1's queries.
    pub retriever: RetrieverKind,
    /// The search strategy.
    pub search: SearchKind,
    /// Which episodes are retained as cases (docs/model.md#open-readings).
    pub retention: Retention,
    /// The unit of an evaluated pair's time `t` (docs/model.md#open-readings).
    pub time_unit: TimeUnit,
    /// Whether the adapter stops at the first trustworthy behavior (`episode`, the paper's)
    /// or keeps watching it (`mission`, docs/missions.md).
    #[serde(skip_serializing_if = "Mode::is_episode")]
    pub mode: Mode,
}

/// Which successful episodes are retained as cases. The paper glosses its own
/// rule as "the agent could not find a solution by only using the case base"; the two
/// readings differ when a search step is followed by a successful reuse.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum Retention {
    /// Any adaptation of the episode came from the search strategy (the default: broader
    /// problem coverage, many cases whose solution is already stored).
    #[default]
    AnySearch,
    /// The final, trustworthy behavior itself came from the search strategy (few cases).
    FinalFromSearch,
}

/// What the time `t` of an evaluated pair counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum TimeUnit {
    /// Task seconds summed over the commands run with the behavior (the default).
    #[default]
    TaskSeconds,
    /// The number of commands run with the behavior.
    Commands,
}

impl Default for AdapterConfig {
    fn default() -> Self {
        Self {
            thresholds: Thresholds::default(),
            lambda: 0.95,
            reuse_cases: true,
            retriever: RetrieverKind::default(),
            search: SearchKind::default(),
            retention: Retention::default(),
            time_unit: TimeUnit::default(),
            mode: Mode::default(),
        }
    }
}

/// An adapter configuration that cannot be used. The reason is part of the message, so
/// it is not chained as a source too (or it would be shown twice).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ConfigError {
    /// Bad thresholds.
    #[error("thresholds: {0}")]
    Thresholds(ThresholdError),
    /// Bad lambda.
    #[error("lambda: {0}")]
    Lambda(LambdaError),
}

impl From<ThresholdError> for ConfigError {
    fn from(reason: ThresholdError) -> Self {
        Self::Thresholds(reason)
    }
}

impl From<LambdaError> for ConfigError {
    fn from(reason: LambdaError) -> Self {
        Self::Lambda(reason)
    }
}

impl AdapterConfig {
    /// Checks every field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.thresholds.validate()?;
        validate_lambda(self.lambda)?;
        Ok(())
    }

    /// The case memory this config's retriever keeps over `cases` in `space`.
    pub fn memory(
        &self,
        space: Arc<BehaviorSpace>,
        cases: TrustCaseBase,
    ) -> Result<TrustMemory, ConfigError> {
        let retriever = self.retriever.build(space, self.lambda)?;
        Ok(TrustMemory::new(cases, retriever))
    }
}

/// Where a new behavior came from.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "source")]
pub enum Source {
    /// Reused from a case (Algorithm 1).
    Case {
        /// The case reused.
        case: CaseId,
        /// Its similarity to the episode.
        similarity: f64,
    },
    /// Proposed by the search strategy.
    Search,
}

/// How an episode ended.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EpisodeReport {
    /// The behavior the robot settles on.
    pub settled: Behavior,
    /// Whether it was found trustworthy (otherwise every behavior was tried).
    pub found_trustworthy: bool,
    /// Distinct behaviors evaluated, the final one counted.
    pub behaviors_evaluated: u64,
    /// Commands recorded in the episode.
    pub commands: u64,
    /// Commands that failed or were interrupted (what the operator endured).
    pub untrustworthy: u64,
    /// Adaptations that came from the search strategy.
    pub searched: u32,
    /// Adaptations that reused a case.
    pub reused: u32,
    /// Whether the behavior settled on came from the search strategy.
    pub settled_from_search: bool,
    /// The case retained at the end of the episode, if any.
    pub retained: Option<CaseId>,
    /// The evaluated pairs `E_past`, in order.
    pub evaluated: Vec<Evaluated>,
    /// The explanation of every switch of the episode, in order, and last the one of its
    /// end.
    pub explanations: Vec<Explanation>,
}

/// What the robot should do after a recorded outcome.
#[derive(Clone, Debug, PartialEq)]
pub enum Decision {
    /// Keep the current behavior and go on.
    Keep,
    /// The current behavior is untrustworthy: use `to` from now on.
    Switch {
        /// The next behavior.
        to: Behavior,
        /// Where it came from.
        source: Source,
        /// Why the behavior was given up and why this one (boxed: a switch is rare next
        /// to the commands kept).
        explanation: Box<Explanation>,
    },
    /// The episode is over. In mission mode the settled behavior stays under watch and
    /// outcomes keep coming.
    Settled(EpisodeReport),
    /// Mission mode: keep the behavior, and ask the operator to supervise it: its trust is
    /// high while the robot's own record says the behavior is not earning it.
    Alert(Alert),
}

/// Why an adapter call was refused. The adapter's state is unchanged.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum AdapterError {
    /// `record` was called with no episode under way (and, in mission mode, no settled
    /// behavior under watch).
    #[error("no episode is under way: begin one first")]
    NoEpisode,
    /// `begin_episode` was called while one is under way.
    #[error("an episode is already under way")]
    EpisodeUnderWay,
    /// The outcome's numbers are unusable (shown in the message, so not chained as a
    /// source).
    #[error("invalid outcome: {0}")]
    Outcome(OutcomeError),
    /// The behavior does not belong to the adapter's space.
    #[error("the behavior does not belong to this behavior space")]
    ForeignBehavior,
}

impl From<OutcomeError> for AdapterError {
    fn from(reason: OutcomeError) -> Self {
        Self::Outcome(reason)
    }
}

#[derive(Clone, Debug)]
struct Episode {
    current: Behavior,
    estimate: TrustEstimate,
    evaluated: Vec<Evaluated>,
    commands: u64,
    untrustworthy: u64,
    searched: u32,
    reused: u32,
    /// Whether the behavior in use came from the search strategy.
    current_from_search: bool,
    /// Commands of the behavior in use that failed or were interrupted.
    current_untrustworthy: u64,
    /// The explanations of the episode's decisions so far.
    explanations: Vec<Explanation>,
}

/// A read-only view of the episode under way.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EpisodeView<'a> {
    /// The behavior in use.
    pub current: Behavior,
    /// Its trust estimate so far.
    pub estimate: TrustEstimate,
    /// The pairs evaluated so far.
    pub evaluated: &'a [Evaluated],
    /// Commands recorded in the episode.
    pub commands: u64,
    /// The explanations of the episode's switches so far.
    pub explanations: &'a [Explanation],
}

/// How many of the behaviors given up in an episode (`evaluated`) `case` matches: a
/// behavior of its problem is more similar to them than `lambda` (what Algorithm 2 pairs).
fn matched_by_case(
    space: &BehaviorSpace,
    lambda: f64,
    evaluated: &[Evaluated],
    case: Option<&TrustCase>,
) -> u32 {
    let Some(case) = case else { return 0 };
    let matched = evaluated
        .iter()
        .filter(|e| {
            case.problem
                .iter()
                .any(|p| space.similarity(&e.behavior, &p.behavior) > lambda)
        })
        .count();
    u32::try_from(matched).unwrap_or(u32::MAX)
}

/// One robot's half of the adapter: the episode under way, the search strategy and its
/// randomness. The case memory it selects from is passed to [`Adaptation::record`], so
/// several adaptations (several robots) can share one memory; the caller retains the case
/// [`Adaptation::case_to_retain`] names, in its memory, after the episode ends.
pub struct Adaptation {
    space: Arc<BehaviorSpace>,
    config: AdapterConfig,
    searcher: Box<TrustSearcher>,
    rng: ChaCha8Rng,
    episode: Option<Episode>,
    attribution: Attribution,
    /// Mission mode: the settled behavior under watch, between episodes.
    watch: Option<Watch>,
    /// Mission mode: the robot's own record of the watched behavior.
    own_record: OwnRecord,
}

impl Adaptation {
    /// An adaptation over `space` with `config`; its search randomness comes from `seed`.
    pub fn new(
        space: Arc<BehaviorSpace>,
        config: AdapterConfig,
        seed: u64,
    ) -> Result<Self, ConfigError> {
        config.validate()?;
        let searcher = config.search.build();
        Ok(Self::with_parts(
            space,
            config,
            searcher,
            ChaCha8Rng::seed_from_u64(seed),
        ))
    }

    /// An adaptation from a ready-made search strategy.
    pub fn with_parts(
        space: Arc<BehaviorSpace>,
        config: AdapterConfig,
        searcher: Box<TrustSearcher>,
        rng: ChaCha8Rng,
    ) -> Self {
        Self {
            space,
            config,
            searcher,
            rng,
            episode: None,
            attribution: Attribution::default(),
            watch: None,
            own_record: OwnRecord::default(),
        }
    }

    /// The same adaptation, explaining itself in `vocabulary`'s terms (the domain's
    /// causes, observations and hints; without one, explanations name only stated
    /// reasons).
    #[must_use]
    pub fn with_vocabulary(mut self, vocabulary: Vocabulary) -> Self {
        self.attribution = Attribution::new(vocabulary);
        self
    }

    /// Restarts the search randomness from `seed`.
    pub fn reseed(&mut self, seed: u64) {
        self.rng = ChaCha8Rng::seed_from_u64(seed);
    }

    /// Starts an episode (a new operator, a new mission) with `initial` in use; in mission
    /// mode this ends the watch of a settled behavior, and what the robot learned of how
    /// its operator reacts is forgotten.
    pub fn begin_episode(&mut self, initial: Behavior) -> Result<(), AdapterError> {
        if self.episode.is_some() {
            return Err(AdapterError::EpisodeUnderWay);
        }
        if !self.space.contains(&initial) {
            return Err(AdapterError::ForeignBehavior);
        }
        self.watch = None;
        self.own_record.forget_operator();
        self.attribution.next_behavior();
        self.start_episode(initial, TrustEstimate::default(), 0);
        Ok(())
    }

    /// Puts `initial` in use with its estimate so far and its untrustworthy commands.
    fn start_episode(&mut self, initial: Behavior, estimate: TrustEstimate, untrustworthy: u64) {
        self.episode = Some(Episode {
            current: initial,
            estimate,
            evaluated: Vec::new(),
            commands: u64::from(estimate.commands),
            untrustworthy,
            searched: 0,
            reused: 0,
            current_from_search: false,
            current_untrustworthy: untrustworthy,
            explanations: Vec::new(),
        });
        self.searcher.begin_episode(&self.space, &initial);
    }

    /// Records one command's outcome for the behavior in use and decides what to do next,
    /// selecting from `memory` when the behavior turns untrustworthy. A settled episode's
    /// report has `retained: None`: the caller retains [`Self::case_to_retain`].
    pub fn record(
        &mut self,
        outcome: &Outcome,
        memory: &TrustMemory,
    ) -> Result<Decision, AdapterError> {
        outcome.validate()?;
        if self.episode.is_none() && self.watch.is_some() {
            return Ok(self.watched(outcome, memory));
        }
        let episode = self.episode.as_mut().ok_or(AdapterError::NoEpisode)?;
        if self.config.mode == Mode::Mission {
            self.own_record.learn(outcome);
        }
        episode.estimate.record(outcome);
        episode.commands += 1;
        if outcome.kind != OutcomeKind::Completed {
            episode.untrustworthy += 1;
            episode.current_untrustworthy += 1;
        }
        self.attribution.record(outcome);
        self.searcher.observe(&episode.current, outcome);
        match episode.estimate.verdict(&self.config.thresholds) {
            Verdict::Undecided => Ok(Decision::Keep),
            Verdict::Trustworthy => {
                episode.explanations.push(Explanation {
                    given_up: None,
                    next: Next::Kept {
                        behavior: episode.current,
                        trustworthy: true,
                        commands: u64::from(episode.estimate.commands),
                        estimate: episode.estimate.value,
                    },
                });
                Ok(self.settle(true))
            }
            Verdict::Untrustworthy => Ok(self.give_up(memory)),
        }
    }

    /// Mission mode: one command of the settled behavior under watch. Its estimate falling
    /// to the untrustworthy threshold starts a new episode from it and gives it up; the
    /// robot's own record falling there while the estimate is above 0 raises an alert.
    fn watched(&mut self, outcome: &Outcome, memory: &TrustMemory) -> Decision {
        let thresholds = self.config.thresholds;
        let watch = self.watch.as_mut().expect("a behavior is under watch");
        self.attribution.record(outcome);
        if watch.record(outcome, &thresholds) {
            // Back at the cap: the account of its untrustworthy commands starts again.
            self.attribution.next_behavior();
        }
        self.own_record.record(outcome);
        let watch = *watch;
        if watch.fallen(&thresholds) {
            self.watch = None;
            self.start_episode(watch.behavior, watch.estimate, watch.untrustworthy);
            return self.give_up(memory);
        }
        match self.own_record.alert(watch.behavior, watch.estimate.value) {
            Some(alert) => {
                self.own_record.restart();
                Decision::Alert(alert)
            }
            None => Decision::Keep,
        }
    }

    /// The episode's behavior in use is untrustworthy: records its evaluated pair and
    /// selects the next behavior from `memory` (or ends the episode when every behavior
    /// has been tried).
    fn give_up(&mut self, memory: &TrustMemory) -> Decision {
        let episode = self.episode.as_mut().expect("an episode is under way");
        let given_up = GivenUp {
            behavior: episode.current,
            commands: u64::from(episode.estimate.commands),
            untrustworthy: episode.current_untrustworthy,
            estimate: episode.estimate.value,
            reasons: self.attribution.reasons(),
        };
        self.attribution.next_behavior();
        episode.current_untrustworthy = 0;
        episode.evaluated.push(Evaluated {
            behavior: episode.current,
            time: match self.config.time_unit {
                TimeUnit::TaskSeconds => episode.estimate.elapsed_s,
                TimeUnit::Commands => f64::from(episode.estimate.commands),
            },
        });
        let memory = self.config.reuse_cases.then_some(memory);
        let selection = select_behavior(
            &episode.evaluated,
            memory,
            self.searcher.as_mut(),
            &self.space,
            &mut self.rng,
        );
        let (to, source, next) = match selection {
            Selection::Reuse {
                case,
                similarity,
                behavior,
            } => {
                episode.reused += 1;
                episode.current_from_search = false;
                let next = Next::Case {
                    behavior,
                    case,
                    similarity,
                    matched: matched_by_case(
                        &self.space,
                        self.config.lambda,
                        &episode.evaluated,
                        memory.and_then(|m| m.base().get(case)),
                    ),
                    given_up: u32::try_from(episode.evaluated.len()).unwrap_or(u32::MAX),
                };
                (behavior, Source::Case { case, similarity }, next)
            }
            Selection::Search(Proposal::Next(behavior)) => {
                episode.searched += 1;
                episode.current_from_search = true;
                let next = Next::Search {
                    behavior,
                    strategy: self.searcher.name().to_owned(),
                    rationale: self.searcher.rationale(&behavior),
                };
                (behavior, Source::Search, next)
            }
            Selection::Search(Proposal::Exhausted { keep }) => {
                episode.current = keep;
                episode.explanations.push(Explanation {
                    given_up: Some(given_up),
                    next: Next::Kept {
                        behavior: keep,
                        trustworthy: false,
                        commands: episode.commands,
                        estimate: episode.estimate.value,
                    },
                });
                return self.settle(false);
            }
        };
        episode.current = to;
        episode.estimate = TrustEstimate::default();
        let explanation = Explanation {
            given_up: Some(given_up),
            next,
        };
        episode.explanations.push(explanation.clone());
        Decision::Switch {
            to,
            source,
            explanation: Box::new(explanation),
        }
    }

    /// Ends the episode under way (`found`: with a trustworthy behavior); in mission mode
    /// the behavior settled on goes under watch.
    fn settle(&mut self, found: bool) -> Decision {
        let value = self.episode.as_ref().map_or(0.0, |e| e.estimate.value);
        let report = self.finish(found);
        if self.config.mode == Mode::Mission {
            self.watch = Some(Watch::new(
                report.settled,
                value,
                found,
                &self.config.thresholds,
            ));
            self.own_record.restart();
            self.attribution.next_behavior();
        }
        Decision::Settled(report)
    }

    /// The case a finished episode retains (docs/model.md#cases-and-retention): its
    /// evaluated pairs and the behavior found, when a trustworthy behavior was found and
    /// the search strategy found it, in the configured reading of "found" ([`Retention`]).
    pub fn case_to_retain(&self, report: &EpisodeReport) -> Option<TrustCase> {
        let search_found_it = match self.config.retention {
            Retention::AnySearch => report.searched > 0,
            Retention::FinalFromSearch => report.settled_from_search,
        };
        (report.found_trustworthy && search_found_it).then(|| Case {
            problem: report.evaluated.clone(),
            solution: report.settled,
        })
    }

    /// Ends the episode under way without a trustworthy behavior and without retaining a
    /// case (the operator left), and in mission mode the watch of a settled behavior.
    /// Returns the episode's report, or `None` if none was under way.
    pub fn abandon_episode(&mut self) -> Option<EpisodeReport> {
        self.watch = None;
        self.episode.as_ref()?;
        Some(self.finish(false))
    }

    fn finish(&mut self, found_trustworthy: bool) -> EpisodeReport {
        let mut episode = self.episode.take().expect("an episode is under way");
        // Reports may be kept by the thousand (an experiment's trials): no spare capacity.
        episode.explanations.shrink_to_fit();
        let settled = if found_trustworthy {
            Some(&episode.current)
        } else {
            None
        };
        self.searcher.end_episode(&episode.evaluated, settled);
        let mut distinct: Vec<Behavior> = episode.evaluated.iter().map(|e| e.behavior).collect();
        if found_trustworthy {
            distinct.push(episode.current);
        }
        distinct.sort_unstable();
        distinct.dedup();
        EpisodeReport {
            settled: episode.current,
            found_trustworthy,
            behaviors_evaluated: distinct.len() as u64,
            commands: episode.commands,
            untrustworthy: episode.untrustworthy,
            searched: episode.searched,
            reused: episode.reused,
            settled_from_search: episode.current_from_search,
            retained: None,
            evaluated: episode.evaluated,
            explanations: episode.explanations,
        }
    }

    /// Whether the search strategy carries knowledge from one episode into the next.
    pub fn learns_across_episodes(&self) -> bool {
        self.searcher.learns_across_episodes()
    }

    /// The search strategy's name.
    pub fn strategy(&self) -> &str {
        self.searcher.name()
    }

    /// The episode under way, if any.
    pub fn episode(&self) -> Option<EpisodeView<'_>> {
        self.episode.as_ref().map(|e| EpisodeView {
            current: e.current,
            estimate: e.estimate,
            evaluated: &e.evaluated,
            commands: e.commands,
            explanations: &e.explanations,
        })
    }

    /// The account of the behavior in use so far: its commands, its estimate and the
    /// reasons its untrustworthy commands are attributed to (`None` with no episode under
    /// way).
    pub fn standing(&self) -> Option<GivenUp> {
        let (behavior, estimate, untrustworthy) = self.current()?;
        Some(GivenUp {
            behavior,
            commands: u64::from(estimate.commands),
            untrustworthy,
            estimate: estimate.value,
            reasons: self.attribution.reasons(),
        })
    }

    /// The behavior in use, its estimate and its untrustworthy commands: the episode's,
    /// or in mission mode the watched behavior's between episodes.
    fn current(&self) -> Option<(Behavior, TrustEstimate, u64)> {
        match (&self.episode, &self.watch) {
            (Some(e), _) => Some((e.current, e.estimate, e.current_untrustworthy)),
            (None, Some(w)) => Some((w.behavior, w.estimate, w.untrustworthy)),
            (None, None) => None,
        }
    }

    /// The behavior in use and its estimate: the episode's, or in mission mode the
    /// watched behavior's between episodes (`None` when neither).
    pub fn in_use(&self) -> Option<(Behavior, TrustEstimate)> {
        self.current()
            .map(|(behavior, estimate, _)| (behavior, estimate))
    }

    /// Mission mode: the settled behavior under watch between episodes, if any.
    pub fn watching(&self) -> Option<&Watch> {
        self.watch.as_ref()
    }

    /// Mission mode: the robot's own record of the watched behavior ([`crate::overtrust`]).
    pub fn own_record(&self) -> &OwnRecord {
        &self.own_record
    }

    /// The behavior space.
    pub fn space(&self) -> &Arc<BehaviorSpace> {
        &self.space
    }

    /// The configuration.
    pub fn config(&self) -> &AdapterConfig {
        &self.config
    }
}

/// The online trust-guided adapter: one [`Adaptation`] and the case memory it owns.
pub struct TrustAdapter {
    adaptation: Adaptation,
    memory: TrustMemory,
}

impl TrustAdapter {
    /// An adapter over `space` with `config`, starting from the case base `cases`; its
    /// search randomness comes from `seed`.
    pub fn new(
        space: Arc<BehaviorSpace>,
        config: AdapterConfig,
        cases: TrustCaseBase,
        seed: u64,
    ) -> Result<Self, ConfigError> {
        let memory = config.memory(space.clone(), cases)?;
        let adaptation = Adaptation::new(space, config, seed)?;
        Ok(Self { adaptation, memory })
    }

    /// An adapter from ready-made parts (a custom retriever or search strategy). The
    /// config's `retriever` and `search` fields are then informational only.
    pub fn with_parts(
        space: Arc<BehaviorSpace>,
        config: AdapterConfig,
        memory: TrustMemory,
        searcher: Box<TrustSearcher>,
        rng: ChaCha8Rng,
    ) -> Self {
        Self {
            adaptation: Adaptation::with_parts(space, config, searcher, rng),
            memory,
        }
    }

    /// Restarts the search randomness from `seed` (the experiment runner gives every
    /// trial its own stream).
    pub fn reseed(&mut self, seed: u64) {
        self.adaptation.reseed(seed);
    }

    /// The same adapter, explaining itself in `vocabulary`'s terms (see
    /// [`Adaptation::with_vocabulary`]).
    #[must_use]
    pub fn with_vocabulary(mut self, vocabulary: Vocabulary) -> Self {
        self.adaptation = self.adaptation.with_vocabulary(vocabulary);
        self
    }

    /// Starts an episode (a new operator, a new mission) with `initial` in use.
    pub fn begin_episode(&mut self, initial: Behavior) -> Result<(), AdapterError> {
        self.adaptation.begin_episode(initial)
    }

    /// Records one command's outcome for the behavior in use and decides what to do next;
    /// a settled episode retains its case (docs/model.md#cases-and-retention) before the
    /// report is returned.
    pub fn record(&mut self, outcome: &Outcome) -> Result<Decision, AdapterError> {
        let mut decision = self.adaptation.record(outcome, &self.memory)?;
        if let Decision::Settled(report) = &mut decision {
            report.retained = self
                .adaptation
                .case_to_retain(report)
                .map(|case| self.memory.retain(case));
        }
        Ok(decision)
    }

    /// Ends the episode under way without a trustworthy behavior and without retaining a
    /// case (the operator left). Returns its report, or `None` if none was under way.
    pub fn abandon_episode(&mut self) -> Option<EpisodeReport> {
        self.adaptation.abandon_episode()
    }

    /// Whether the search strategy carries knowledge from one episode into the next.
    pub fn learns_across_episodes(&self) -> bool {
        self.adaptation.learns_across_episodes()
    }

    /// The episode under way, if any.
    pub fn episode(&self) -> Option<EpisodeView<'_>> {
        self.adaptation.episode()
    }

    /// The account of the behavior in use so far (see [`Adaptation::standing`]).
    pub fn standing(&self) -> Option<GivenUp> {
        self.adaptation.standing()
    }

    /// The behavior in use and its estimate (see [`Adaptation::in_use`]).
    pub fn in_use(&self) -> Option<(Behavior, TrustEstimate)> {
        self.adaptation.in_use()
    }

    /// Mission mode: the settled behavior under watch between episodes, if any.
    pub fn watching(&self) -> Option<&Watch> {
        self.adaptation.watching()
    }

    /// Mission mode: the robot's own record of the watched behavior.
    pub fn own_record(&self) -> &OwnRecord {
        self.adaptation.own_record()
    }

    /// The behavior space.
    pub fn space(&self) -> &Arc<BehaviorSpace> {
        self.adaptation.space()
    }

    /// The configuration.
    pub fn config(&self) -> &AdapterConfig {
        self.adaptation.config()
    }

    /// The case base (every retained case, in order).
    pub fn cases(&self) -> &TrustCaseBase {
        self.memory.base()
    }

    /// The memory's best guess of a first behavior for an operator it does not yet know
    /// ([`crate::start`]), `None` while the case base is empty; behaviors more similar
    /// than the config's `lambda` count as the same.
    pub fn first_guess(&self) -> Option<FirstGuess> {
        first_guess(self.memory.base(), self.space(), self.config().lambda)
    }
}
