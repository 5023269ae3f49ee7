//! Driving an adapter through simulated commands: the steps a trial
//! ([`crate::experiment::runner`]) and a mission ([`crate::mission`]) share.
//!
//! Both start from a first behavior and then run command after command. The *first
//! behavior* is the random one drawn on the setup stream, or, for an arm that starts from
//! the case memory's guess ([`Initial::Learned`]) once the memory holds a case, that guess;
//! the random behavior is drawn either way, so arms stay paired ([`first_behavior`]). A
//! *command* ([`Drive::command`]) is the simulated command of [`crate::experiment::simulate`] (run by
//! the domain in front of the operator at its attention, its truth checked to be a cause
//! the domain declares, a reason stated through the plan's feedback channel or the
//! operator's own), and the adapter records the outcome. The streams of the runs and
//! of the stated reasons, and the adapter's search stream, are the trial's or mission's
//! ([`Drive::new`]).
//!
//! A command also holds the arm's searcher to its contract (what
//! `trust::testing::check_searcher` checks): the behavior a decision puts in use must be of
//! the space, and one the search proposes must not have been evaluated in the episode
//! already (it would be judged again, and the episode could run to its last command). A
//! breach stops the plan with [`PlanError::Searcher`], naming the arm and the behavior.

use crate::experiment::arm::Initial;
use crate::experiment::goal_change::GoalChangesOn;
use crate::experiment::plan::PlanError;
use crate::experiment::simulate::{self, Attention, Conditions, SimulatedCommand};
use crate::seeds::{Purpose, stream, stream_seed};
use crate::{Domain, FeedbackChannel, Judgement};
use cbr_core::Behavior;
use rand_chacha::ChaCha8Rng;
use trust::{
    AdapterError, Decision, EpisodeView, MissionAdapter, MissionDecision, Outcome, Source,
    TrustAdapter,
};

/// An adapter a drive records outcomes with: the paper's episodes, or a mission around them.
pub(crate) trait Records {
    /// What it decides after an outcome.
    type Decision;

    /// Records one command's outcome.
    fn record(&mut self, outcome: &Outcome) -> Result<Self::Decision, AdapterError>;

    /// Restarts the search randomness from `seed`.
    fn reseed(&mut self, seed: u64);

    /// The episode under way, if any.
    fn episode(&self) -> Option<EpisodeView<'_>>;

    /// The episode machine's decision inside `decision`, if it is one.
    fn episode_decision(decision: &Self::Decision) -> Option<&Decision>;
}

impl Records for TrustAdapter {
    type Decision = Decision;

    fn record(&mut self, outcome: &Outcome) -> Result<Decision, AdapterError> {
        TrustAdapter::record(self, outcome)
    }

    fn reseed(&mut self, seed: u64) {
        TrustAdapter::reseed(self, seed);
    }

    fn episode(&self) -> Option<EpisodeView<'_>> {
        TrustAdapter::episode(self)
    }

    fn episode_decision(decision: &Decision) -> Option<&Decision> {
        Some(decision)
    }
}

impl Records for MissionAdapter<'_> {
    type Decision = MissionDecision;

    fn record(&mut self, outcome: &Outcome) -> Result<MissionDecision, AdapterError> {
        MissionAdapter::<TrustAdapter>::record(self, outcome)
    }

    fn reseed(&mut self, seed: u64) {
        MissionAdapter::<TrustAdapter>::reseed(self, seed);
    }

    fn episode(&self) -> Option<EpisodeView<'_>> {
        self.adapter().episode()
    }

    fn episode_decision(decision: &MissionDecision) -> Option<&Decision> {
        match decision {
            MissionDecision::Episode(decision) => Some(decision),
            MissionDecision::Alert(_) | MissionDecision::Overtrust(_) => None,
        }
    }
}

/// The behavior an episode starts with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Start {
    /// The behavior.
    pub(crate) behavior: Behavior,
    /// Whether it is the case memory's guess rather than the random draw.
    pub(crate) learned: bool,
}

/// The first behavior of an episode of an arm that starts as `initial` says: `drawn`, the
/// unit's random behavior (drawn whatever the arm, so arms stay paired), or with
/// [`Initial::Learned`] the guess of `adapter`'s memory when it holds a case.
pub(crate) fn first_behavior(initial: Initial, adapter: &TrustAdapter, drawn: Behavior) -> Start {
    let guess = match initial {
        Initial::Random => None,
        Initial::Learned => adapter.first_guess(),
    };
    match guess {
        Some(guess) => Start {
            behavior: guess.behavior,
            learned: true,
        },
        None => Start {
            behavior: drawn,
            learned: false,
        },
    }
}

/// One command as it went: the domain's judgement, what the adapter was told, and what
/// it decided.
pub(crate) struct Command<T> {
    /// The judgement (the outcome before any reason was stated, and the truth).
    pub(crate) judgement: Judgement,
    /// The outcome the adapter recorded, with the reason the operator stated.
    pub(crate) outcome: Outcome,
    /// The adapter's decision.
    pub(crate) decision: T,
}

/// The commands of one trial or mission: its streams, and the plan's feedback channel.
pub(crate) struct Drive<'a, D: Domain> {
    /// The plan's name, for errors.
    plan: &'a str,
    /// The arm's name, for errors.
    arm: &'a str,
    domain: &'a D,
    /// The channel every operator of the plan explains itself through (`None`: each its
    /// own).
    feedback: Option<FeedbackChannel>,
    /// How often the operators' goals change, with the domain as one that models them
    /// (`None`: never).
    goal_changes: Option<GoalChangesOn<'a, D::Operator>>,
    /// The simulated runs.
    runs: ChaCha8Rng,
    /// The operators' stated reasons.
    stated: ChaCha8Rng,
    /// The moments of the goal changes (drawn only with `goal_changes`).
    goal_change_moments: ChaCha8Rng,
}

impl<'a, D: Domain> Drive<'a, D> {
    /// The commands of unit `unit` (a trial, a mission) of the arm named `arm` in the plan
    /// named `plan`, at `index` in its suite, over `domain`, under the master `seed`;
    /// `adapter`'s search restarts from the unit's search stream.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        plan: &'a str,
        arm: &'a str,
        domain: &'a D,
        feedback: Option<FeedbackChannel>,
        goal_changes: Option<GoalChangesOn<'a, D::Operator>>,
        seed: u64,
        index: u64,
        unit: u64,
        adapter: &mut impl Records,
    ) -> Self {
        adapter.reseed(stream_seed(seed, index, unit, Purpose::Search));
        Self {
            plan,
            arm,
            domain,
            feedback,
            goal_changes,
            runs: stream(seed, index, unit, Purpose::Runs),
            stated: stream(seed, index, unit, Purpose::Feedback),
            goal_change_moments: stream(seed, index, unit, Purpose::GoalChange),
        }
    }

    /// Runs one command with `behavior` in front of `operator` and records it with
    /// `adapter`: an attentive operator's ([`Domain::run`]) when `attention` is `None`, else
    /// one at that attention ([`crate::Attentive::run_attending`]); with goal changes, the
    /// moment of the next is drawn first and the domain runs the command up to it
    /// ([`crate::GoalChanging::run_redirected`]). A truth the domain does not declare stops
    /// the plan, and so does a decision that breaks the searcher's contract
    /// ([`Drive::check_contract`]).
    pub(crate) fn command<A: Records>(
        &mut self,
        adapter: &mut A,
        behavior: &Behavior,
        operator: &D::Operator,
        attention: Option<Attention<'_, D::Operator>>,
    ) -> Result<Command<A::Decision>, PlanError> {
        let channel = self
            .feedback
            .unwrap_or_else(|| self.domain.feedback(operator));
        let goal_change_at = self.goal_changes.map(|changes| {
            let at_s = changes.setting.next_at(&mut self.goal_change_moments);
            (at_s, changes.capability)
        });
        let SimulatedCommand { judgement, outcome } = simulate::command(
            self.domain,
            behavior,
            operator,
            Conditions {
                attention,
                goal_change_at,
            },
            channel,
            &mut self.runs,
            &mut self.stated,
        )
        .map_err(|refused| refused.in_plan(self.plan, self.domain.name()))?;
        let decision = adapter
            .record(&outcome)
            .expect("domains report valid outcomes");
        self.check_contract(adapter, &decision)?;
        Ok(Command {
            judgement,
            outcome,
            decision,
        })
    }

    /// Refuses a decision that puts in use a behavior outside the space, or switches to
    /// one the search proposed that the episode has already evaluated.
    fn check_contract<A: Records>(
        &self,
        adapter: &A,
        decision: &A::Decision,
    ) -> Result<(), PlanError> {
        let (behavior, searched) = match A::episode_decision(decision) {
            Some(Decision::Switch { to, source, .. }) => (*to, *source == Source::Search),
            Some(Decision::Settled(report)) => (report.settled, false),
            Some(Decision::Keep) | None => return Ok(()),
        };
        let space = self.domain.space();
        let breach = |problem: &'static str, shown: String| PlanError::Searcher {
            plan: self.plan.to_owned(),
            arm: self.arm.to_owned(),
            behavior: shown,
            problem,
        };
        if !space.contains(&behavior) {
            return Err(breach(
                "is outside the behavior space",
                format!("the value indices {:?}", behavior.indices()),
            ));
        }
        let repeated = searched
            && adapter
                .episode()
                .is_some_and(|e| e.evaluated.iter().any(|x| x.behavior == behavior));
        if repeated {
            return Err(breach(
                "the episode has already evaluated",
                space.display(&behavior).to_string(),
            ));
        }
        Ok(())
    }
}
