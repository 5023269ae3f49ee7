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
//!
//! The files: the configuration (`config.rs`), what an episode decides and reports
//! (`episode.rs`), one robot's [`Adaptation`] (`adaptation.rs`) and, here, the
//! [`TrustAdapter`] that owns its memory.

use crate::estimate::Outcome;
use crate::explain::{Account, Vocabulary};
use crate::search::TrustSearcher;
use crate::start::{FirstGuess, first_guess};
use crate::{TrustCaseBase, TrustMemory};
use cbr_core::{Behavior, BehaviorSpace, Context, Statement};
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;

mod adaptation;
mod config;
mod episode;

pub use adaptation::Adaptation;
pub use config::{AdapterConfig, ConfigError, Parameters, Retention, TimeUnit};
pub use episode::{AdapterError, Decision, EpisodeReport, EpisodeView};

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
