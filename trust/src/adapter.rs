//! `TrustAdapter`: the online state machine a robot embeds (and the experiment runner drives):
//! the paper's episodes.
//!
//! Report every command's outcome with [`TrustAdapter::record`]; the answer says whether to
//! keep the current behavior, switch to another, or that the episode is over (a trustworthy
//! behavior was found, or every behavior was tried). An [`Adaptation`] holds one robot's
//! episode (the evaluated pairs `E_past`) and search strategy and selects from a case memory
//! it is handed; the [`TrustAdapter`] pairs one with the memory it owns and retains a case at
//! the end of an episode (docs/model.md#cases-and-retention). Robots sharing one case
//! memory each drive their own `Adaptation`.
//!
//! This module knows nothing of missions: a robot that keeps listening after an episode
//! ends wraps an `Adaptation` or a `TrustAdapter` in [`crate::mission_mode`], which drives them
//! through the few episode-level calls made for it ([`Adaptation::account_kept`],
//! [`Adaptation::restart_account`], [`Adaptation::give_up_kept`]).

use crate::estimate::{
    Outcome, OutcomeError, OutcomeKind, ThresholdError, Thresholds, TrustEstimate, Verdict,
};
use crate::evaluated::{LambdaError, validate_lambda};
use crate::explain::{Account, Attribution, Explanation, Grounds, Next, Vocabulary};
use crate::retrieval::RetrieverKind;
use crate::search::{SearchKind, TrustSearcher};
use crate::select::{Selection, Source, select_behavior};
use crate::start::{FirstGuess, first_guess};
use crate::{Evaluated, TrustCase, TrustCaseBase, TrustMemory, TrustProblem};
use cbr_core::{Behavior, BehaviorSpace, Case, CaseId, Context, Statement};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The adapter's configuration, as a file or a request names it: its [`Parameters`] and
/// the kinds of its parts (the retriever and the search strategy); the defaults are the
/// paper's.
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
}

/// What the episode machine itself follows: every field of an [`AdapterConfig`] but the
/// kinds of its parts. An adapter built from ready-made parts ([`Adaptation::with_parts`],
/// [`TrustAdapter::with_parts`]) takes these, so no field it would not read is handed to
/// it. The defaults are the paper's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Parameters {
    /// The trust thresholds (paper: +5 / -5).
    pub thresholds: Thresholds,
    /// Algorithm 2's behavior-similarity threshold (paper: 0.95), in `(0, 1]`: what
    /// counts as the same behavior when a reused case is explained and a first behavior
    /// is guessed (the memory's retriever is built with its own).
    pub lambda: f64,
    /// Reuse cases (Algorithm 1) before searching; `false` is the search strategy alone.
    pub reuse_cases: bool,
    /// Which episodes are retained as cases (docs/model.md#open-readings).
    pub retention: Retention,
    /// The unit of an evaluated pair's time `t` (docs/model.md#open-readings).
    pub time_unit: TimeUnit,
}

impl Default for Parameters {
    fn default() -> Self {
        AdapterConfig::default().parameters()
    }
}

impl Parameters {
    /// Checks every field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.thresholds.validate()?;
        validate_lambda(self.lambda)?;
        Ok(())
    }
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
        self.parameters().validate()
    }

    /// What the episode machine follows of this config: every field but the kinds of its
    /// parts.
    pub fn parameters(&self) -> Parameters {
        let Self {
            thresholds,
            lambda,
            reuse_cases,
            retriever: _,
            search: _,
            retention,
            time_unit,
        } = *self;
        Parameters {
            thresholds,
            lambda,
            reuse_cases,
            retention,
            time_unit,
        }
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
    /// The context the episode ran in (left out of the serialized report when it is the
    /// default one).
    #[serde(default, skip_serializing_if = "Context::is_default")]
    pub context: Context,
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
    /// The episode is over.
    Settled(EpisodeReport),
}

/// Why an adapter call was refused. The adapter's state is unchanged.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum AdapterError {
    /// `record` was called with no episode under way.
    #[error("no episode is under way: begin one first")]
    NoEpisode,
    /// `begin_episode` (or [`Adaptation::give_up_kept`], or a context set) was called while
    /// one is under way.
    #[error("an episode is already under way")]
    EpisodeUnderWay,
    /// The outcome's numbers are unusable (shown in the message, so not chained as a
    /// source).
    #[error("invalid outcome: {0}")]
    Outcome(OutcomeError),
    /// The behavior does not belong to the adapter's space.
    #[error("the behavior does not belong to this behavior space")]
    ForeignBehavior,
    /// An offered behavior was taken while no settled behavior is under watch (mission
    /// mode, [`crate::MissionAdapter::accept_offer`]).
    #[error(
        "no settled behavior is under watch: an offer is taken after an overtrust alert, in mission mode"
    )]
    NotWatching,
    /// An episode was begun with two statements of the same name
    /// ([`Adaptation::begin_episode_hearing`]).
    #[error("`{name}` is stated twice: an operator states each name at most once")]
    StatedTwice {
        /// The name.
        name: String,
    },
    /// [`Adaptation::give_up_kept`] was handed an estimate above the untrustworthy
    /// threshold.
    #[error("the kept behavior's estimate {estimate} is above the untrustworthy threshold")]
    NotUntrustworthy {
        /// The estimate handed.
        estimate: f64,
    },
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
    /// The episode's context and the pairs it evaluated so far: Algorithm 1's query.
    problem: TrustProblem,
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
    /// The context the episode runs in.
    pub context: &'a Context,
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
                .evaluated
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
///
/// After an episode ends the robot keeps the behavior it settled on. A caller that goes on
/// judging that *kept* behavior (a robot on a long mission, [`crate::mission_mode`]) tells its
/// commands to [`Adaptation::account_kept`], and when the behavior has fallen to the
/// untrustworthy threshold begins the next episode from it with
/// [`Adaptation::give_up_kept`]; the paper's adapter never does either.
pub struct Adaptation {
    space: Arc<BehaviorSpace>,
    parameters: Parameters,
    searcher: Box<TrustSearcher>,
    rng: ChaCha8Rng,
    episode: Option<Episode>,
    /// The context the robot is in: every episode begun runs in it.
    context: Context,
    /// What the operator of the episode under way (or of the last one) stated up front.
    stated: Vec<Statement>,
    /// The account of the behavior in use (or kept after the last episode): the reasons
    /// of its untrustworthy commands, and what stated reasons taught across episodes.
    attribution: Attribution,
}

impl Adaptation {
    /// An adaptation over `space` with `config` (its search strategy the kind the config
    /// names); its search randomness comes from `seed`.
    pub fn new(
        space: Arc<BehaviorSpace>,
        config: AdapterConfig,
        seed: u64,
    ) -> Result<Self, ConfigError> {
        Self::with_parts(
            space,
            config.parameters(),
            config.search.build(),
            ChaCha8Rng::seed_from_u64(seed),
        )
    }

    /// An adaptation following `parameters` with a ready-made search strategy and
    /// randomness.
    pub fn with_parts(
        space: Arc<BehaviorSpace>,
        parameters: Parameters,
        searcher: Box<TrustSearcher>,
        rng: ChaCha8Rng,
    ) -> Result<Self, ConfigError> {
        parameters.validate()?;
        Ok(Self {
            space,
            parameters,
            searcher,
            rng,
            episode: None,
            context: Context::default(),
            stated: Vec::new(),
            attribution: Attribution::default(),
        })
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

    /// The context the robot is in from now on (the default one until set): episodes
    /// begun afterwards run in it, are matched with cases by it, and retain it in their
    /// case. Refused while an episode is under way, whose pairs were all evaluated in the
    /// context it began in. The searcher is told it ([`cbr_core::Searcher::enter_context`]).
    /// The caller checks `context` against its domain's [`cbr_core::ContextSpace`].
    pub fn set_context(&mut self, context: Context) -> Result<(), AdapterError> {
        if self.episode.is_some() {
            return Err(AdapterError::EpisodeUnderWay);
        }
        self.searcher.enter_context(&context);
        self.context = context;
        Ok(())
    }

    /// The context the robot is in.
    pub fn context(&self) -> &Context {
        &self.context
    }

    /// Starts an episode (a new operator, who states nothing up front) with `initial` in
    /// use, in the robot's context.
    pub fn begin_episode(&mut self, initial: Behavior) -> Result<(), AdapterError> {
        self.begin_episode_hearing(initial, Vec::new())
    }

    /// Starts an episode with `initial` in use, in the robot's context, for an operator who
    /// stated `stated` up front (in its domain's vocabulary, which the caller checks; each
    /// name at most once). The searcher hears them ([`cbr_core::Searcher::hear`]) as every
    /// episode of this operator begins (in mission mode, also when a kept behavior is
    /// given up).
    pub fn begin_episode_hearing(
        &mut self,
        initial: Behavior,
        stated: Vec<Statement>,
    ) -> Result<(), AdapterError> {
        self.check_beginning(&initial)?;
        if let Some(name) = cbr_core::statement::repeated_name(&stated) {
            return Err(AdapterError::StatedTwice {
                name: name.to_owned(),
            });
        }
        self.stated = stated;
        self.attribution.next_behavior();
        self.start_episode(initial, TrustEstimate::default(), 0);
        Ok(())
    }

    /// Refuses to begin an episode while one is under way, or from a foreign behavior.
    fn check_beginning(&self, initial: &Behavior) -> Result<(), AdapterError> {
        if self.episode.is_some() {
            return Err(AdapterError::EpisodeUnderWay);
        }
        if !self.space.contains(initial) {
            return Err(AdapterError::ForeignBehavior);
        }
        Ok(())
    }

    /// Puts `initial` in use with its estimate so far and its untrustworthy commands.
    fn start_episode(&mut self, initial: Behavior, estimate: TrustEstimate, untrustworthy: u64) {
        self.episode = Some(Episode {
            current: initial,
            estimate,
            problem: TrustProblem::in_context(self.context.clone(), Vec::new()),
            commands: u64::from(estimate.commands),
            untrustworthy,
            searched: 0,
            reused: 0,
            current_from_search: false,
            current_untrustworthy: untrustworthy,
            explanations: Vec::new(),
        });
        self.searcher.begin_episode(&self.space, &initial);
        self.searcher.hear(&self.stated);
    }

    /// What the operator of the episode under way (or of the last one) stated up front.
    pub fn stated(&self) -> &[Statement] {
        &self.stated
    }

    /// Records one command's outcome for the behavior in use and decides what to do next,
    /// selecting from `memory` when the behavior turns untrustworthy. A settled episode's
    /// report has `retained: None`: the caller retains [`Self::case_to_retain`]. A said
    /// goal change ([`Outcome::goal_change`]) counts as a command of the episode and
    /// nothing else: the estimate, the explanations' account and the search learn
    /// nothing from it, and the behavior is kept.
    pub fn record(
        &mut self,
        outcome: &Outcome,
        memory: &TrustMemory,
    ) -> Result<Decision, AdapterError> {
        self.record_passing(outcome, memory, |_| false)
    }

    /// [`Adaptation::record`], except that a behavior reaching the trustworthy threshold
    /// that `pass_over` names (asked once, with the behavior) is not settled on: it is
    /// given up as an untrustworthy one is (its evaluated pair, the next behavior from
    /// `memory`), so the episode searches on past a behavior its operator trusts (a
    /// mission preferring behaviors the robot judges competent, [`crate::mission_mode`]).
    pub fn record_passing(
        &mut self,
        outcome: &Outcome,
        memory: &TrustMemory,
        pass_over: impl FnOnce(&Behavior) -> bool,
    ) -> Result<Decision, AdapterError> {
        outcome.validate()?;
        let episode = self.episode.as_mut().ok_or(AdapterError::NoEpisode)?;
        episode.commands += 1;
        if outcome.goal_change {
            // Said not to be about the behavior: no account of it learns anything.
            return Ok(Decision::Keep);
        }
        episode.estimate.record(outcome);
        if outcome.kind != OutcomeKind::Completed {
            episode.untrustworthy += 1;
            episode.current_untrustworthy += 1;
        }
        self.attribution.record(outcome);
        self.searcher.observe(&episode.current, outcome);
        match episode.estimate.verdict(&self.parameters.thresholds) {
            Verdict::Undecided => Ok(Decision::Keep),
            Verdict::Trustworthy if pass_over(&episode.current) => Ok(self.give_up(memory)),
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
                Ok(Decision::Settled(self.finish(true)))
            }
            Verdict::Untrustworthy => Ok(self.give_up(memory)),
        }
    }

    /// Adds a command of the behavior kept after the last episode ended (no episode is
    /// under way; the robot still uses the behavior it settled on) to that behavior's
    /// account: the reasons an episode begun from it by [`Adaptation::give_up_kept`]
    /// gives for giving it up. `outcome` is assumed valid.
    pub fn account_kept(&mut self, outcome: &Outcome) {
        self.attribution.record(outcome);
    }

    /// Starts the account of the behavior in use (or kept) afresh: its untrustworthy
    /// commands so far are no longer reasons to give it up; what stated reasons taught
    /// across episodes stays.
    pub fn restart_account(&mut self) {
        self.attribution.next_behavior();
    }

    /// Begins an episode from `kept`, the behavior kept after the last episode ended,
    /// whose estimate has fallen to the untrustworthy threshold over the commands it
    /// counts (`untrustworthy` of them failed or were interrupted; its account is what
    /// [`Adaptation::account_kept`] recorded since [`Adaptation::restart_account`]), and
    /// gives it up at once as an episode gives up its behavior: its evaluated pair, then
    /// the next behavior from `memory` (a switch), or the end when every behavior has been
    /// tried.
    pub fn give_up_kept(
        &mut self,
        kept: Behavior,
        estimate: TrustEstimate,
        untrustworthy: u64,
        memory: &TrustMemory,
    ) -> Result<Decision, AdapterError> {
        self.check_beginning(&kept)?;
        if estimate.verdict(&self.parameters.thresholds) != Verdict::Untrustworthy {
            return Err(AdapterError::NotUntrustworthy {
                estimate: estimate.value,
            });
        }
        self.start_episode(kept, estimate, untrustworthy);
        Ok(self.give_up(memory))
    }

    /// The episode's behavior in use is untrustworthy: records its evaluated pair and
    /// selects the next behavior from `memory` (or ends the episode when every behavior
    /// has been tried).
    fn give_up(&mut self, memory: &TrustMemory) -> Decision {
        let episode = self.episode.as_mut().expect("an episode is under way");
        let given_up = Account {
            behavior: episode.current,
            commands: u64::from(episode.estimate.commands),
            untrustworthy: episode.current_untrustworthy,
            estimate: episode.estimate.value,
            reasons: self.attribution.reasons(),
        };
        self.attribution.next_behavior();
        episode.current_untrustworthy = 0;
        episode.problem.evaluated.push(Evaluated {
            behavior: episode.current,
            time: match self.parameters.time_unit {
                TimeUnit::TaskSeconds => episode.estimate.elapsed_s,
                TimeUnit::Commands => f64::from(episode.estimate.commands),
            },
        });
        let memory = self.parameters.reuse_cases.then_some(memory);
        let selection = select_behavior(
            &episode.problem,
            memory,
            self.searcher.as_mut(),
            &self.space,
            &mut self.rng,
        );
        let (to, source) = match selection {
            Selection::Next { behavior, source } => (behavior, source),
            Selection::Exhausted { keep } => {
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
                return Decision::Settled(self.finish(false));
            }
        };
        let grounds = match source {
            Source::Case { case, .. } => {
                episode.reused += 1;
                episode.current_from_search = false;
                Grounds::Matches {
                    matched: matched_by_case(
                        &self.space,
                        self.parameters.lambda,
                        &episode.problem.evaluated,
                        memory.and_then(|m| m.base().get(case)),
                    ),
                    given_up: u32::try_from(episode.problem.evaluated.len()).unwrap_or(u32::MAX),
                }
            }
            Source::Search => {
                episode.searched += 1;
                episode.current_from_search = true;
                Grounds::Rationale {
                    strategy: self.searcher.name().to_owned(),
                    rationale: self.searcher.rationale(&to).plain(),
                }
            }
        };
        episode.current = to;
        episode.estimate = TrustEstimate::default();
        let explanation = Explanation {
            given_up: Some(given_up),
            next: Next::Switch {
                behavior: to,
                source,
                grounds,
            },
        };
        episode.explanations.push(explanation.clone());
        Decision::Switch {
            to,
            source,
            explanation: Box::new(explanation),
        }
    }

    /// The case a finished episode retains (docs/model.md#cases-and-retention): its
    /// context and evaluated pairs, and the behavior found, when a trustworthy behavior was found and
    /// the search strategy found it, in the configured reading of "found" ([`Retention`]).
    pub fn case_to_retain(&self, report: &EpisodeReport) -> Option<TrustCase> {
        let search_found_it = match self.parameters.retention {
            Retention::AnySearch => report.searched > 0,
            Retention::FinalFromSearch => report.settled_from_search,
        };
        (report.found_trustworthy && search_found_it).then(|| Case {
            problem: TrustProblem::in_context(report.context.clone(), report.evaluated.clone()),
            solution: report.settled,
        })
    }

    /// Ends the episode under way without a trustworthy behavior and without retaining a
    /// case (the operator left). Returns the episode's report, or `None` if none was under
    /// way.
    pub fn abandon_episode(&mut self) -> Option<EpisodeReport> {
        self.episode.as_ref()?;
        Some(self.finish(false))
    }

    /// Ends the episode under way; the account of the behavior it ends on starts afresh
    /// (for the commands it may be kept for).
    fn finish(&mut self, found_trustworthy: bool) -> EpisodeReport {
        let mut episode = self.episode.take().expect("an episode is under way");
        self.attribution.next_behavior();
        // Reports may be kept by the thousand (an experiment's trials): no spare capacity.
        episode.explanations.shrink_to_fit();
        let settled = if found_trustworthy {
            Some(&episode.current)
        } else {
            None
        };
        self.searcher
            .end_episode(&episode.problem.evaluated, settled);
        let mut distinct: Vec<Behavior> = episode
            .problem
            .evaluated
            .iter()
            .map(|e| e.behavior)
            .collect();
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
            evaluated: episode.problem.evaluated,
            context: episode.problem.context,
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
            evaluated: &e.problem.evaluated,
            context: &e.problem.context,
            commands: e.commands,
            explanations: &e.explanations,
        })
    }

    /// The account of the episode's behavior in use so far: its commands, its estimate and
    /// the reasons its untrustworthy commands are attributed to (`None` with no episode
    /// under way).
    pub fn standing(&self) -> Option<Account> {
        let e = self.episode.as_ref()?;
        Some(self.account(e.current, e.estimate, e.current_untrustworthy))
    }

    /// The account of `behavior`, in use (or kept) with `estimate` over the commands it
    /// counts, `untrustworthy` of them failed or interrupted: those numbers and the
    /// reasons the account of the behavior in use attributes its untrustworthy commands to.
    pub fn account(
        &self,
        behavior: Behavior,
        estimate: TrustEstimate,
        untrustworthy: u64,
    ) -> Account {
        Account {
            behavior,
            commands: u64::from(estimate.commands),
            untrustworthy,
            estimate: estimate.value,
            reasons: self.attribution.reasons(),
        }
    }

    /// The behavior space.
    pub fn space(&self) -> &Arc<BehaviorSpace> {
        &self.space
    }

    /// The parameters it follows.
    pub fn parameters(&self) -> &Parameters {
        &self.parameters
    }
}

/// The online trust-guided adapter: one [`Adaptation`] and the case memory it owns.
pub struct TrustAdapter {
    pub(crate) adaptation: Adaptation,
    pub(crate) memory: TrustMemory,
}

impl TrustAdapter {
    /// An adapter over `space` with `config` (its retriever and search strategy the kinds
    /// the config names), starting from the case base `cases`; its search randomness
    /// comes from `seed`.
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

    /// An adapter following `parameters` from ready-made parts: a case memory (with a
    /// custom retriever), a search strategy and its randomness.
    pub fn with_parts(
        space: Arc<BehaviorSpace>,
        parameters: Parameters,
        memory: TrustMemory,
        searcher: Box<TrustSearcher>,
        rng: ChaCha8Rng,
    ) -> Result<Self, ConfigError> {
        Ok(Self {
            adaptation: Adaptation::with_parts(space, parameters, searcher, rng)?,
            memory,
        })
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

    /// The context the robot is in from now on (see [`Adaptation::set_context`]).
    pub fn set_context(&mut self, context: Context) -> Result<(), AdapterError> {
        self.adaptation.set_context(context)
    }

    /// The context the robot is in.
    pub fn context(&self) -> &Context {
        self.adaptation.context()
    }

    /// Starts an episode (a new operator) with `initial` in use, in the robot's context.
    pub fn begin_episode(&mut self, initial: Behavior) -> Result<(), AdapterError> {
        self.adaptation.begin_episode(initial)
    }

    /// Starts an episode for an operator who stated `stated` up front (see
    /// [`Adaptation::begin_episode_hearing`]).
    pub fn begin_episode_hearing(
        &mut self,
        initial: Behavior,
        stated: Vec<Statement>,
    ) -> Result<(), AdapterError> {
        self.adaptation.begin_episode_hearing(initial, stated)
    }

    /// What the operator of the episode under way (or of the last one) stated up front.
    pub fn stated(&self) -> &[Statement] {
        self.adaptation.stated()
    }

    /// Records one command's outcome for the behavior in use and decides what to do next;
    /// a settled episode retains its case (docs/model.md#cases-and-retention) before the
    /// report is returned.
    pub fn record(&mut self, outcome: &Outcome) -> Result<Decision, AdapterError> {
        let decision = self.adaptation.record(outcome, &self.memory)?;
        Ok(self.retaining(decision))
    }

    /// `decision`, with the case a settled episode retains stored in the memory and named
    /// in its report.
    pub(crate) fn retaining(&mut self, mut decision: Decision) -> Decision {
        if let Decision::Settled(report) = &mut decision {
            report.retained = self
                .adaptation
                .case_to_retain(report)
                .map(|case| self.memory.retain(case));
        }
        decision
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

    /// The account of the episode's behavior in use so far (see [`Adaptation::standing`]).
    pub fn standing(&self) -> Option<Account> {
        self.adaptation.standing()
    }

    /// The behavior space.
    pub fn space(&self) -> &Arc<BehaviorSpace> {
        self.adaptation.space()
    }

    /// The parameters it follows.
    pub fn parameters(&self) -> &Parameters {
        self.adaptation.parameters()
    }

    /// The case base (every retained case, in order).
    pub fn cases(&self) -> &TrustCaseBase {
        self.memory.base()
    }

    /// The memory's best guess of a first behavior for an operator it does not yet know
    /// in the robot's context ([`crate::start`]), `None` while no case was learned in it;
    /// behaviors more similar than the parameters' `lambda` count as the same.
    pub fn first_guess(&self) -> Option<FirstGuess> {
        first_guess(
            self.memory.base(),
            self.space(),
            self.parameters().lambda,
            self.context(),
        )
    }
}
