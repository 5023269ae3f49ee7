//! Mission mode: a robot that keeps listening after an episode settles (docs/missions.md).
//!
//! The paper's adapter ([`crate::adapter`]) stops at the first trustworthy behavior: the
//! episode is over, and the next one begins when the robot is told of a new operator. On a
//! long mission the operator's preferences may change, another operator may take over
//! unannounced, or the behavior may have been trusted by luck. A mission wraps the episode
//! machine and adds, between its episodes:
//!
//! - **the watch** of the behavior an episode settled on ([`crate::watch`]): every outcome
//!   is still answered, the estimate is capped at the trustworthy threshold, and its fall
//!   to the untrustworthy threshold begins a new episode from it, given up at once
//!   ([`Adaptation::give_up_kept`]), which goes on as any episode does (cases reused, a
//!   case retained when it settles) and whose end is watched in turn;
//! - **a change detector**, when the mission is given one
//!   ([`MissionAdapter::detecting_changes`], [`crate::change`]): a sequential test of the
//!   watched behavior's own record beside the thresholds, which gives it up as a fall
//!   does when its rate of untrustworthy commands has risen;
//! - **the robot's own record** ([`crate::overtrust`]): learned from every command of an
//!   episode, weighed over the commands of the watched behavior, and an [`Alert`] when the
//!   operator's trust is high while that record says the behavior is not earning it;
//! - **the robot's own competence**, when the mission is given a [`CompetenceJudge`]
//!   ([`crate::competence`]): every command recorded, and an [`CompetenceAlert`] once per
//!   settled behavior the operator trusts while the robot judges it not competent; and,
//!   when asked ([`MissionAdapter::preferring_competent`]), episodes that pass over a few
//!   trusted behaviors the robot is sure are not competent before settling.
//!
//! A goal change the operator says ([`crate::Outcome::goal_change`]) is kept out of all
//! of these: the behavior in use stays, and nothing learns from the command.
//!
//! Telling the robot of a new operator ([`MissionAdaptation::begin_episode`]) ends the
//! watch and forgets what it learned of how its operator reacts. Telling it that its
//! context switched ([`MissionAdapter::switch_context`]) mid-mission ends an episode under
//! way (its behaviors were evaluated in the old context) and forgets how its operator
//! reacts (that holds in the context it was learned in); the robot then goes back to the
//! behavior it last settled on, trusted, in the new context since its operator began (and
//! has not given up there since), or else to the case memory's first guess there when
//! asked, or else carries on with the
//! behavior in use ([`ContextSwitch`]). The episode machine knows
//! nothing of this: a mission drives it through its episode-level calls (an episode's
//! outcomes, the account of the behavior kept after it, the episode begun from a kept
//! behavior that fell).
//!
//! Two wrappers share this logic: [`MissionAdaptation`] around an [`Adaptation`] (the case
//! memory handed in, as `serve` shares one among its sessions) and [`MissionAdapter`]
//! around a [`TrustAdapter`] (the memory owned, as an experiment's chain does). Their
//! answers are [`MissionDecision`]s: the episode machine's decision, or an alert.

use crate::adapter::{Adaptation, AdapterError, Decision, EpisodeReport, TrustAdapter};
use crate::change::{ChangeDetector, Cusum};
use crate::competence::{CompetenceAlert, CompetenceJudge};
use crate::explain::Account;
use crate::overtrust::{Alert, OwnRecord};
use crate::start::first_guess;
use crate::watch::Watch;
use crate::{Outcome, Thresholds, TrustEstimate, TrustMemory, Verdict};
use cbr_core::{Behavior, Context, Statement};

/// What the robot should do after an outcome recorded on a mission.
#[derive(Clone, Debug, PartialEq)]
pub enum MissionDecision {
    /// The episode machine's decision: keep the behavior (in an episode, or the watched
    /// one), switch (in an episode, or from a watched behavior that fell: a new episode
    /// began), or an episode settled (its behavior is now watched).
    Episode(Decision),
    /// Keep the watched behavior, and ask the operator to supervise it: its trust is high
    /// while the robot's own record says the behavior is not earning it.
    Alert(Alert),
    /// Keep the watched behavior, and ask the operator to choose: it trusts the behavior
    /// while the robot judges it not competent ([`crate::competence`]), once per settled
    /// behavior, on a mission given a [`CompetenceJudge`].
    Overtrust(CompetenceAlert),
}

/// What the robot did when told mid-mission that its context switched
/// ([`MissionAdapter::switch_context`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ContextSwitch {
    /// The behavior in use from now on.
    pub behavior: Behavior,
    /// Where it comes from.
    pub from: SwitchStart,
    /// Whether a watched (settled) behavior was given up for it.
    pub gave_up_watch: bool,
}

/// Where the behavior in use after a context switch comes from ([`ContextSwitch`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SwitchStart {
    /// The behavior in use, as it was: the watched behavior still watched (nothing the
    /// robot knows of the new context says otherwise), or, told the context it is already
    /// in, the episode or watch under way going on unchanged.
    Kept,
    /// The behavior the robot last settled on, trusted, in the new context since its
    /// operator began, and has not given up there since: an episode begins from it.
    Resumed,
    /// The case memory's first guess for the new context ([`crate::start`]): an episode
    /// begins from it.
    Guessed,
    /// The behavior in use: the episode under way begins again in the new context.
    Restarted,
}

/// The first guess of `memory` in `adaptation`'s context, if there is a memory to guess
/// from ([`crate::start`]).
fn guess(memory: Option<&TrustMemory>, adaptation: &Adaptation) -> Option<Behavior> {
    let memory = memory?;
    let parameters = adaptation.parameters();
    first_guess(
        memory.base(),
        adaptation.space(),
        parameters.lambda,
        adaptation.context(),
    )
    .map(|g| g.behavior)
}

/// Whether the episode gave up the behavior it had in use: a switch, or its end with every
/// behavior tried (it settles on the one that held out longest, untrusted).
fn gives_up(decision: &Decision) -> bool {
    match decision {
        Decision::Keep => false,
        Decision::Switch { .. } => true,
        Decision::Settled(report) => !report.found_trustworthy,
    }
}

impl From<Decision> for MissionDecision {
    fn from(decision: Decision) -> Self {
        Self::Episode(decision)
    }
}

/// What a mission adds to an episode machine, between and across its episodes.
#[derive(Clone, Debug, Default)]
struct Mission<'p> {
    /// The behavior the last episode settled on, under watch until a new episode begins.
    watch: Option<Watch>,
    /// The robot's own record of the watched behavior.
    own_record: OwnRecord,
    /// The robot's judge of its own competence, if it was given one.
    judge: Option<CompetenceJudge<'p>>,
    /// Whether the watched behavior has had its overtrust alert.
    judged: bool,
    /// How many trusted behaviors an episode may pass over for being surely not competent
    /// (0: it settles on the first, as the paper's does).
    passes: u32,
    /// How many the episode under way has passed over.
    passed: u32,
    /// Per context, the behavior the robot last settled on, trusted, in it since its
    /// operator began; forgotten once given up there (`forget_settled`).
    settled_in: Vec<(Context, Behavior)>,
    /// The change detector, if the mission was given one.
    detector: Option<ChangeDetector>,
    /// Its test of the watched behavior.
    test: Option<Cusum>,
}

impl<'p> Mission<'p> {
    /// A new operator, who stated `stated` up front: an episode from `initial`, ending the
    /// watch.
    fn begin_episode(
        &mut self,
        adaptation: &mut Adaptation,
        initial: Behavior,
        stated: Vec<Statement>,
    ) -> Result<(), AdapterError> {
        adaptation.begin_episode_hearing(initial, stated)?;
        self.watch = None;
        self.passed = 0;
        self.own_record.forget_operator();
        self.settled_in.clear();
        Ok(())
    }

    /// The robot's context switched to `context` mid-mission (see the module docs);
    /// `guess` is the case memory's first guess in the adaptation's (new) context, if the
    /// robot starts from it. Refused with neither an episode nor a watch.
    fn switch_context(
        &mut self,
        adaptation: &mut Adaptation,
        context: Context,
        guess: impl FnOnce(&Adaptation) -> Option<Behavior>,
    ) -> Result<ContextSwitch, AdapterError> {
        let in_use = self.in_use(adaptation).ok_or(AdapterError::NoEpisode)?.0;
        if context == *adaptation.context() {
            // Told the context it is in: nothing switched, so the episode or the watch
            // goes on as it was (its estimate and commands kept).
            return Ok(ContextSwitch {
                behavior: in_use,
                from: SwitchStart::Kept,
                gave_up_watch: false,
            });
        }
        let watching = self.watch.is_some();
        adaptation.abandon_episode();
        adaptation.set_context(context)?;
        self.own_record.enter_context(adaptation.context());
        self.own_record.forget_operator();
        self.own_record.restart();
        let remembered = self
            .settled_in
            .iter()
            .find(|(c, _)| c == adaptation.context())
            .map(|&(_, b)| b);
        let (start, from) = match remembered {
            Some(b) => (Some(b), SwitchStart::Resumed),
            None => (guess(adaptation), SwitchStart::Guessed),
        };
        let (behavior, from) = match start {
            Some(b) if !(watching && b == in_use) => (b, from),
            _ if watching => {
                return Ok(ContextSwitch {
                    behavior: in_use,
                    from: SwitchStart::Kept,
                    gave_up_watch: false,
                });
            }
            _ => (in_use, SwitchStart::Restarted),
        };
        adaptation.begin_episode(behavior)?;
        self.watch = None;
        self.passed = 0;
        Ok(ContextSwitch {
            behavior,
            from,
            gave_up_watch: watching,
        })
    }

    /// Remembers `behavior` as the one last settled on, trusted, in `adaptation`'s
    /// context.
    fn remember_settled(&mut self, adaptation: &Adaptation, behavior: Behavior) {
        let context = adaptation.context();
        match self.settled_in.iter_mut().find(|(c, _)| c == context) {
            Some(entry) => entry.1 = behavior,
            None => self.settled_in.push((context.clone(), behavior)),
        }
    }

    /// Forgets `behavior` as the one last settled on in `adaptation`'s context, if it is:
    /// the robot has given it up there (its estimate fell, or an episode gave it up), so a
    /// switch back to the context must not resume it.
    fn forget_settled(&mut self, adaptation: &Adaptation, behavior: Behavior) {
        let context = adaptation.context();
        self.settled_in
            .retain(|(c, b)| !(c == context && *b == behavior));
    }

    /// One command: of the episode under way, or of the watched behavior.
    fn record(
        &mut self,
        adaptation: &mut Adaptation,
        outcome: &Outcome,
        memory: &TrustMemory,
    ) -> Result<MissionDecision, AdapterError> {
        outcome.validate()?;
        let in_use = self.in_use(adaptation).ok_or(AdapterError::NoEpisode)?.0;
        if outcome.goal_change {
            // Said not to be about the behavior: neither its estimate, its watch, its
            // account, the robot's record nor its competence learns anything from it (an
            // episode counts it as one of its commands).
            return Ok(match self.watch {
                Some(_) => Decision::Keep,
                None => adaptation.record(outcome, memory)?,
            }
            .into());
        }
        if let Some(judge) = &mut self.judge {
            judge.record(in_use, outcome);
        }
        if self.watch.is_some() {
            return Ok(self.watched(adaptation, outcome, memory));
        }
        // The record a change test starts from should this command settle the episode on
        // the behavior in use: its commands in this episode, this one included.
        let settling = adaptation
            .episode()
            .map(|e| {
                (
                    e.current,
                    u64::from(e.estimate.commands) + 1,
                    e.current_untrustworthy + u64::from(outcome.is_untrustworthy()),
                )
            })
            .ok_or(AdapterError::NoEpisode)?;
        // During an episode the operator is taken to be attentive: the record learns how
        // it reacts.
        self.own_record.learn(outcome);
        let decision = match self.judge.as_ref().filter(|_| self.passed < self.passes) {
            Some(judge) => {
                let mut passed_over = false;
                let decision = adaptation.record_passing(outcome, memory, |behavior| {
                    passed_over = !judge.surely_short(*behavior).1.is_empty();
                    passed_over
                })?;
                self.passed += u32::from(passed_over);
                decision
            }
            None => adaptation.record(outcome, memory)?,
        };
        if gives_up(&decision) {
            self.forget_settled(adaptation, in_use);
        }
        self.after(adaptation, &decision, Some(settling));
        Ok(decision.into())
    }

    /// One command of the watched behavior. Its estimate falling to the untrustworthy
    /// threshold begins a new episode from it and gives it up; the robot's own record
    /// reaching the alert while the estimate is above 0 raises an alert.
    fn watched(
        &mut self,
        adaptation: &mut Adaptation,
        outcome: &Outcome,
        memory: &TrustMemory,
    ) -> MissionDecision {
        let thresholds = adaptation.parameters().thresholds;
        let watch = self.watch.as_mut().expect("a behavior is under watch");
        adaptation.account_kept(outcome);
        if watch.record(outcome, &thresholds) {
            // Back at the cap: the account of its untrustworthy commands starts again.
            adaptation.restart_account();
        }
        self.own_record.record(outcome);
        let watch = *watch;
        let changed = self.test.as_mut().is_some_and(|test| test.record(outcome));
        if watch.fallen(&thresholds) || changed {
            self.watch = None;
            self.forget_settled(adaptation, watch.behavior);
            let decision = if watch.fallen(&thresholds) {
                adaptation.give_up_kept(watch.behavior, watch.estimate, watch.untrustworthy, memory)
            } else {
                adaptation.give_up_changed(
                    watch.behavior,
                    watch.estimate,
                    watch.untrustworthy,
                    memory,
                )
            }
            .expect("no episode runs while a behavior of the space is watched");
            self.after(adaptation, &decision, None);
            return decision.into();
        }
        if let Some(alert) = self.own_record.alert(watch.behavior, watch.estimate.value) {
            self.own_record.restart();
            return MissionDecision::Alert(alert);
        }
        match self.overtrust(watch.behavior, watch.estimate.value, &thresholds, memory) {
            Some(alert) => MissionDecision::Overtrust(alert),
            None => Decision::Keep.into(),
        }
    }

    /// The overtrust alert for the watched `behavior` at the operator's `estimate`: once
    /// per settled behavior, when the operator trusts it while the judge finds it surely
    /// not competent ([`crate::competence::CompetenceStandard::surely_short`]), offering
    /// the safest behavior of `memory`'s solutions the judge finds competent.
    fn overtrust(
        &mut self,
        behavior: Behavior,
        estimate: f64,
        thresholds: &Thresholds,
        memory: &TrustMemory,
    ) -> Option<CompetenceAlert> {
        let judge = self.judge.as_ref().filter(|_| !self.judged)?;
        if thresholds.verdict(estimate) != Verdict::Trustworthy {
            return None;
        }
        let (competence, short) = judge.surely_short(behavior);
        if short.is_empty() {
            return None;
        }
        self.judged = true;
        let offer = judge.safer_than(behavior, memory.base().cases().iter().map(|c| c.solution));
        Some(CompetenceAlert {
            behavior,
            estimate,
            competence,
            short,
            offer,
        })
    }

    /// The operator took the behavior an overtrust alert offered: it is watched from now
    /// on, as if an episode had settled on it (its estimate at the trustworthy threshold:
    /// the operator chose it), with a new account and own record.
    fn accept_offer(
        &mut self,
        adaptation: &mut Adaptation,
        offer: Behavior,
    ) -> Result<(), AdapterError> {
        if self.watch.is_none() {
            return Err(AdapterError::NotWatching);
        }
        if !adaptation.space().contains(&offer) {
            return Err(AdapterError::ForeignBehavior);
        }
        self.watch_settled(offer, true, (0, 0), adaptation);
        self.remember_settled(adaptation, offer);
        adaptation.restart_account();
        Ok(())
    }

    /// An episode that settled puts its behavior under watch, with a new own record;
    /// `settling` is the behavior the decision was made on, with its commands and
    /// untrustworthy commands in the episode (the record a change test starts from when
    /// the episode settles on it).
    fn after(
        &mut self,
        adaptation: &Adaptation,
        decision: &Decision,
        settling: Option<(Behavior, u64, u64)>,
    ) {
        if let Decision::Settled(report) = decision {
            let record = settling
                .filter(|&(b, _, _)| b == report.settled)
                .map_or((0, 0), |(_, n, f)| (n, f));
            self.watch_settled(report.settled, report.found_trustworthy, record, adaptation);
            if report.found_trustworthy {
                self.remember_settled(adaptation, report.settled);
            }
            self.passed = 0;
        }
    }

    /// Watches `behavior` as a settled one (`trustworthy`: it reached the threshold), with
    /// a new own record and its overtrust alert still to come; a change test starts from
    /// `(commands, untrustworthy)`, its record when it settled.
    fn watch_settled(
        &mut self,
        behavior: Behavior,
        trustworthy: bool,
        (commands, untrustworthy): (u64, u64),
        adaptation: &Adaptation,
    ) {
        self.watch = Some(Watch::settled(
            behavior,
            trustworthy,
            &adaptation.parameters().thresholds,
        ));
        self.test = self
            .detector
            .map(|detector| detector.watch(commands, untrustworthy));
        self.own_record.restart();
        self.judged = false;
    }

    /// The operator left: ends the episode under way (its report) or the watch.
    fn abandon(&mut self, adaptation: &mut Adaptation) -> Option<EpisodeReport> {
        self.watch = None;
        adaptation.abandon_episode()
    }

    /// The behavior in use and its estimate: the episode's, or the watched behavior's.
    fn in_use(&self, adaptation: &Adaptation) -> Option<(Behavior, TrustEstimate)> {
        match (adaptation.episode(), &self.watch) {
            (Some(e), _) => Some((e.current, e.estimate)),
            (None, Some(w)) => Some((w.behavior, w.estimate)),
            (None, None) => None,
        }
    }

    /// The account of the behavior in use: the episode's, or the watched behavior's since
    /// its estimate last stood at the cap.
    fn standing(&self, adaptation: &Adaptation) -> Option<Account> {
        match &self.watch {
            Some(w) => Some(adaptation.account(w.behavior, w.estimate, w.untrustworthy)),
            None => adaptation.standing(),
        }
    }
}

/// The episode machine a [`MissionAdapter`] wraps: an [`Adaptation`] alone (over a case
/// memory the caller hands in, [`MissionAdaptation`]) or a [`TrustAdapter`] with the memory
/// it owns.
pub trait EpisodeMachine {
    /// The episode machine itself.
    fn adaptation(&self) -> &Adaptation;
    /// The episode machine itself, to drive.
    fn adaptation_mut(&mut self) -> &mut Adaptation;
}

impl EpisodeMachine for Adaptation {
    fn adaptation(&self) -> &Adaptation {
        self
    }
    fn adaptation_mut(&mut self) -> &mut Adaptation {
        self
    }
}

impl EpisodeMachine for TrustAdapter {
    fn adaptation(&self) -> &Adaptation {
        &self.adaptation
    }
    fn adaptation_mut(&mut self) -> &mut Adaptation {
        &mut self.adaptation
    }
}

/// Mission mode around an episode machine `M`: its episodes, and the watch of a settled
/// behavior between them. Around a [`TrustAdapter`] (the default) it retains a case when
/// an episode settles, over the memory the adapter owns (an experiment's missions); around
/// an [`Adaptation`] ([`MissionAdaptation`]) it selects from a memory handed in with each
/// outcome, and the caller retains the case [`Adaptation::case_to_retain`] names
/// (`serve --mission`, where sessions share one memory).
pub struct MissionAdapter<'p, M: EpisodeMachine = TrustAdapter> {
    machine: M,
    mission: Mission<'p>,
}

/// Mission mode around an [`Adaptation`] over a memory handed in ([`MissionAdapter`]).
pub type MissionAdaptation<'p> = MissionAdapter<'p, Adaptation>;

impl<'p, M: EpisodeMachine> MissionAdapter<'p, M> {
    /// `machine` on a mission, watching nothing yet.
    pub fn new(machine: M) -> Self {
        Self {
            machine,
            mission: Mission::default(),
        }
    }

    /// The episode machine (its episode, space, parameters and strategy).
    pub fn adaptation(&self) -> &Adaptation {
        self.machine.adaptation()
    }

    /// A new operator: begins an episode with `initial` in use, ending the watch of a
    /// settled behavior; what the robot learned of how its operator reacts is forgotten.
    pub fn begin_episode(&mut self, initial: Behavior) -> Result<(), AdapterError> {
        self.begin_episode_hearing(initial, Vec::new())
    }

    /// A new operator who stated `stated` up front
    /// ([`Adaptation::begin_episode_hearing`]): as [`MissionAdapter::begin_episode`].
    pub fn begin_episode_hearing(
        &mut self,
        initial: Behavior,
        stated: Vec<Statement>,
    ) -> Result<(), AdapterError> {
        self.mission
            .begin_episode(self.machine.adaptation_mut(), initial, stated)
    }

    /// The robot's context from now on ([`Adaptation::set_context`]): a watched behavior
    /// stays in use, the episodes begun afterwards run in it, and the own record weighs
    /// signals by how operators react in it ([`OwnRecord::enter_context`]). Refused while
    /// an episode is under way.
    pub fn set_context(&mut self, context: Context) -> Result<(), AdapterError> {
        let adaptation = self.machine.adaptation_mut();
        adaptation.set_context(context)?;
        self.mission.own_record.enter_context(adaptation.context());
        Ok(())
    }

    /// Ends the episode under way (returning its report) or the watch (returning `None`).
    pub fn abandon_episode(&mut self) -> Option<EpisodeReport> {
        self.mission.abandon(self.machine.adaptation_mut())
    }

    /// The behavior in use and its estimate: the episode's, or the watched behavior's.
    pub fn in_use(&self) -> Option<(Behavior, TrustEstimate)> {
        self.mission.in_use(self.machine.adaptation())
    }

    /// The account of the behavior in use: the episode's, or the watched behavior's since
    /// its estimate last stood at the cap.
    pub fn standing(&self) -> Option<Account> {
        self.mission.standing(self.machine.adaptation())
    }

    /// The settled behavior under watch between episodes, if any.
    pub fn watching(&self) -> Option<&Watch> {
        self.mission.watch.as_ref()
    }

    /// The robot's own record of the watched behavior.
    pub fn own_record(&self) -> &OwnRecord {
        &self.mission.own_record
    }

    /// The same mission judging its own competence with `judge`: every command is
    /// recorded, and a watched behavior the operator trusts while the judge finds it not
    /// competent raises [`MissionDecision::Overtrust`] once.
    #[must_use]
    pub fn with_competence(mut self, judge: CompetenceJudge<'p>) -> Self {
        self.mission.judge = Some(judge);
        self
    }

    /// The robot's judge of its own competence, if it has one.
    pub fn competence_judge(&self) -> Option<&CompetenceJudge<'p>> {
        self.mission.judge.as_ref()
    }

    /// The same mission preferring behaviors its judge finds competent (given one with
    /// [`MissionAdapter::with_competence`]): an episode passes over up to `passes`
    /// behaviors its operator trusts while the judge is sure they fall short, searching
    /// on past each, and settles on the next trusted one whatever its competence.
    #[must_use]
    pub fn preferring_competent(mut self, passes: u32) -> Self {
        self.mission.passes = passes;
        self
    }

    /// The same mission with a change detector beside the paper's thresholds
    /// ([`crate::change`]): a watched behavior is also given up when the test of its own
    /// record finds that its rate of untrustworthy commands rose.
    #[must_use]
    pub fn detecting_changes(mut self, detector: ChangeDetector) -> Self {
        self.mission.detector = Some(detector);
        self
    }

    /// The operator took the behavior an overtrust alert offered
    /// ([`CompetenceAlert::offer`]): the watch moves to it, as if an episode had settled
    /// on it. Refused with no behavior under watch, or one outside the space.
    pub fn accept_offer(&mut self, offer: Behavior) -> Result<(), AdapterError> {
        self.mission
            .accept_offer(self.machine.adaptation_mut(), offer)
    }
}

impl MissionAdapter<'_, Adaptation> {
    /// The robot's context switched to `context` mid-mission, and it is told (see
    /// [`MissionAdapter::switch_context`]); `learned_start`: the case memory whose first
    /// guess in `context` to take when nothing was settled on there, if the robot starts
    /// from it.
    pub fn switch_context(
        &mut self,
        context: Context,
        learned_start: Option<&TrustMemory>,
    ) -> Result<ContextSwitch, AdapterError> {
        self.mission
            .switch_context(&mut self.machine, context, |a| guess(learned_start, a))
    }

    /// Records one command's outcome (of the episode under way, or of the watched
    /// behavior) and decides what to do next, selecting from `memory` when a behavior is
    /// given up. Refused only with neither an episode nor a watch, or an unusable outcome.
    pub fn record(
        &mut self,
        outcome: &Outcome,
        memory: &TrustMemory,
    ) -> Result<MissionDecision, AdapterError> {
        self.mission.record(&mut self.machine, outcome, memory)
    }
}

impl MissionAdapter<'_, TrustAdapter> {
    /// The episode machine and its memory (its episode, cases and first guess).
    pub fn adapter(&self) -> &TrustAdapter {
        &self.machine
    }

    /// Restarts the search randomness from `seed`.
    pub fn reseed(&mut self, seed: u64) {
        self.machine.reseed(seed);
    }

    /// The robot's context switched to `context` mid-mission, and it is told: an episode
    /// under way ends, what the robot learned of how its operator reacts is forgotten, and
    /// it goes back to the behavior it last settled on, trusted, in `context` since its
    /// operator began and has not given up there since (its watch fell, an episode gave it
    /// up or passed it over), or else (with `learned_start`) to the case memory's first
    /// guess in `context`, or else carries on with the behavior in use (an episode under
    /// way begins again from it; a watched one stays watched). Refused with neither an
    /// episode nor a watch.
    pub fn switch_context(
        &mut self,
        context: Context,
        learned_start: bool,
    ) -> Result<ContextSwitch, AdapterError> {
        let TrustAdapter { adaptation, memory } = &mut self.machine;
        let memory = learned_start.then_some(&*memory);
        self.mission
            .switch_context(adaptation, context, |a| guess(memory, a))
    }

    /// Records one command's outcome (as the [`MissionAdaptation`]'s own); a settled
    /// episode retains its case before the report is returned.
    pub fn record(&mut self, outcome: &Outcome) -> Result<MissionDecision, AdapterError> {
        let TrustAdapter { adaptation, memory } = &mut self.machine;
        Ok(match self.mission.record(adaptation, outcome, memory)? {
            MissionDecision::Episode(decision) => self.machine.retaining(decision).into(),
            alert @ (MissionDecision::Alert(_) | MissionDecision::Overtrust(_)) => alert,
        })
    }
}
