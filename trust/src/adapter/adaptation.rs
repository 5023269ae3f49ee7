//! [`Adaptation`]: one robot's half of the adapter, the episode under way and the search
//! strategy, selecting from a case memory it is handed.

use crate::estimate::{Outcome, OutcomeKind, TrustEstimate, Verdict};
use crate::explain::{Account, Attribution, Explanation, Grounds, Next, Vocabulary};
use crate::search::TrustSearcher;
use crate::select::{Selection, Source, select_behavior};
use crate::{Evaluated, TrustCase, TrustMemory, TrustProblem};
use cbr_core::{Behavior, BehaviorSpace, Case, Context, Statement};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;

use super::config::{AdapterConfig, ConfigError, Parameters, Retention, TimeUnit};
use super::episode::{AdapterError, Decision, EpisodeReport, EpisodeView};

/// The episode under way: the behavior in use and its estimate, the query of Algorithm 1,
/// and what the episode's report will count.
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
        self.give_up_changed(kept, estimate, untrustworthy, memory)
    }

    /// [`Adaptation::give_up_kept`] for a kept behavior whose estimate has not fallen but
    /// whose own record a change detector ([`crate::change`]) found changed: it is given
    /// up at its estimate as it stands.
    pub fn give_up_changed(
        &mut self,
        kept: Behavior,
        estimate: TrustEstimate,
        untrustworthy: u64,
        memory: &TrustMemory,
    ) -> Result<Decision, AdapterError> {
        self.check_beginning(&kept)?;
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
            current_untrustworthy: e.current_untrustworthy,
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
