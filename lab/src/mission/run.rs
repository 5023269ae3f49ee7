//! Missions: long runs of commands in which the operator changes without the robot being
//! told, and operators may grow complacent (docs/missions.md).
//!
//! A *mission* is `commands` commands from one population. It starts with a member drawn
//! at random and the arm's first behavior (the paper's random one, or the case memory's
//! guess for an arm that starts from it, drawn as a trial's first behavior is); at random
//! times (exponential gaps of mean [`Changes::every`](crate::mission::Changes::every) commands) the operator changes:
//! another operator *takes over* (a new person, who starts without trust in the robot) or
//! the same operator's preferences *shift* to another member's (the context changed; its
//! trust in the robot carries over). With [`ContextSwitches`](crate::mission::ContextSwitches) the robot's context (its
//! cargo, the situation it was sent into) also switches at random times, and the robot is
//! *told* (it knows what it carries): the operator then judges as it does in the new
//! context ([`Domain::operator_in_context`]). The robot runs in mission mode
//! ([`trust::MissionAdapter`]) and is told only outcomes; its commands are driven as a
//! trial's are (the private `driver` module: the first behavior and each command).
//!
//! With a [`Complacency`](crate::mission::Complacency) model the operator's attention falls as its own trust in the
//! robot builds: each arm then runs twice on the same streams, once ignoring the robot's
//! alerts and once answering them (the operator is asked to supervise and looks afresh:
//! its trust restarts from nothing and its attention is whole again), so the harm done
//! with and without alerts is paired mission by mission.
//!
//! The missions of one arm form a chain (the case base carries from one to the next);
//! chains run in parallel. Every draw comes from a stream named by (seed, mission plan,
//! mission, purpose), the same for every arm.
use crate::contract::capability::Needing;
use crate::experiment::arm::{Arm, Initial};
use crate::experiment::driver::{Command, Drive, first_behavior};
use crate::experiment::plan::{PlanError, fresh_adapter};
use crate::experiment::simulate::Attention;
use crate::mission::course::{
    Course, Judges, Scheduled, StreamName, begin_change, count_untrustworthy,
};
use crate::mission::oracle::run_oracles;
use crate::mission::plan::{COMPLACENT_BELOW, MissionPlan, RECOVERED_AT};
use crate::mission::record::{
    CalibrationRecord, ChangeKind, Mark, MissionArmResult, MissionRecord, MissionResult,
    MissionStep, MissionTrace, OnsetRecord,
};
use crate::reference::competence_truth::{true_competence, true_rates};
use crate::seeds::{Purpose, stream};
use crate::{Domain, Judgement};
use cbr_core::Behavior;
use rand::RngCore;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::collections::HashMap;
use trust::{
    Calibration, CompetenceAlert, Decision, MissionAdapter, MissionDecision, Outcome, OutcomeKind,
    OwnRecord, Thresholds, Verdict,
};

/// The truth of the behaviors' competence on one chain of a plan with a standard, each
/// behavior's learned once from the plan's truth runs on a stream of its own (so every
/// chain finds the same truth).
struct CompetenceTruth<'p, 'a, D: Domain> {
    plan: &'p MissionPlan<'a, D>,
    /// The seed and the plan's place, naming the streams.
    seed: u64,
    index: u64,
    known: HashMap<Behavior, bool>,
}

impl<'p, 'a, D: Domain> CompetenceTruth<'p, 'a, D> {
    /// Whether `behavior` is truly competent under the plan's standard.
    fn competent(&mut self, behavior: Behavior) -> bool {
        let plan = self.plan;
        let (seed, index) = (self.seed, self.index);
        *self.known.entry(behavior).or_insert_with(|| {
            let Needing {
                setting: standard,
                capability: judging,
            } = plan.competence.as_ref().expect("a plan with a standard");
            let mut rng = stream(
                seed,
                index,
                plan.domain.space().rank(&behavior),
                Purpose::CompetenceTruth,
            );
            let rates = true_rates(*judging, &behavior, plan.truth_runs, &mut rng);
            standard.met_by(&true_competence(
                judging.competence_parts(),
                behavior,
                &rates,
            ))
        })
    }
}

/// Runs every plan: each (plan, arm, whether alerts are answered) is a chain of missions,
/// chains in parallel on the current rayon pool, and the plan's oracle runs the same
/// missions ([`crate::mission::oracle::MissionOracle`]). Every plan is checked first
/// ([`MissionPlan::validate`]): a refused plan stops the run before any mission.
pub fn run_missions<D: Domain>(
    plans: &[MissionPlan<'_, D>],
    seed: u64,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Vec<MissionResult>, PlanError> {
    for plan in plans {
        plan.validate()?;
    }
    let oracles = run_oracles(plans, seed)?;
    let chains: Vec<(usize, usize, bool)> = plans
        .iter()
        .enumerate()
        .flat_map(|(p, plan)| {
            let answers: &[bool] = if plan.complacency.is_some() {
                &[false, true]
            } else {
                &[false]
            };
            (0..plan.arms.len()).flat_map(move |a| answers.iter().map(move |&y| (p, a, y)))
        })
        .collect();
    let mut ran = chains
        .par_iter()
        .map(|&(p, a, answers)| run_chain(&plans[p], p as u64, a, answers, seed, &|| progress(p)))
        .collect::<Result<Vec<_>, PlanError>>()?
        .into_iter();
    Ok(plans
        .iter()
        .zip(oracles)
        .map(|(plan, oracle)| {
            let per_arm = if plan.complacency.is_some() { 2 } else { 1 };
            MissionResult {
                name: plan.name.clone(),
                complacency: plan.complacency.is_some(),
                context_switches: plan.contexts.is_some(),
                arms: ran.by_ref().take(plan.arms.len() * per_arm).collect(),
                oracle,
            }
        })
        .collect())
}

/// How many commands of a mission run between two looks at [`crate::interrupt`].
const INTERRUPT_EVERY: u32 = 4096;

fn run_chain<D: Domain>(
    plan: &MissionPlan<'_, D>,
    index: u64,
    arm_index: usize,
    answers_alerts: bool,
    seed: u64,
    progress: &(dyn Fn() + Sync),
) -> Result<MissionArmResult, PlanError> {
    let arm = &plan.arms[arm_index];
    let adapter =
        fresh_adapter(plan.domain, &plan.adapter, arm).map_err(|reason| PlanError::Config {
            plan: plan.name.clone(),
            reason,
        })?;
    let mut adapter = MissionAdapter::new(adapter);
    if let Some(detector) = plan.change_detector {
        adapter = adapter.detecting_changes(detector);
    }
    if let Some(judge) = plan.judge() {
        adapter = adapter
            .with_competence(judge)
            .preferring_competent(arm.competent_passes());
    }
    let mut truth = CompetenceTruth {
        plan,
        seed,
        index,
        known: HashMap::new(),
    };
    let mut missions = Vec::with_capacity(plan.missions as usize);
    let mut traced = MissionTrace::of(plan.commands);
    for mission in 0..plan.missions {
        crate::interrupt::check()?;
        let trace = (mission == 0).then_some(&mut traced);
        let named = StreamName {
            seed,
            plan: index,
            mission,
        };
        missions.push(run_mission(
            plan,
            arm,
            &mut adapter,
            named,
            answers_alerts,
            &mut truth,
            trace,
        )?);
        progress();
    }
    Ok(MissionArmResult {
        arm: arm.arm_name().clone(),
        answers_alerts,
        missions,
        traced,
    })
}

/// Whether `behavior` is trustworthy for `operator`: its mean weighted outcome over the
/// plan's truth runs is above 0 (the expected estimate climbs).
fn trustworthy<D: Domain>(
    plan: &MissionPlan<'_, D>,
    behavior: &Behavior,
    operator: &D::Operator,
    rng: &mut dyn RngCore,
) -> bool {
    let sum: f64 = (0..plan.truth_runs)
        .map(|_| {
            plan.domain
                .run(behavior, operator, rng)
                .outcome
                .contribution()
        })
        .sum();
    sum > 0.0
}

/// The operator's own state in a mission: its trust in the robot and whether it is
/// complacent.
struct OperatorState {
    /// Its trust in the robot, in `[0, 1]`.
    felt: f64,
    /// The onset under way, if the operator is complacent.
    onset: Option<usize>,
}

impl OperatorState {
    /// An operator whose trust in the robot starts from nothing, attentive: a new one, or
    /// one asked by an alert to look afresh.
    fn fresh() -> Self {
        Self {
            felt: 0.0,
            onset: None,
        }
    }
}

/// One mission of `arm` on `plan`, its course named by `named`: a command at a time, the
/// course's changes applied as they come ([`MissionRun::apply`]), the operator's attention
/// followed ([`MissionRun::attend`]), the watched behavior's calibration counted
/// ([`MissionRun::calibrate`]), the command driven and what it did recorded
/// ([`MissionRun::observe`]), then the robot's decision followed ([`MissionRun::decided`]).
fn run_mission<D: Domain>(
    plan: &MissionPlan<'_, D>,
    arm: &Arm,
    adapter: &mut MissionAdapter<'_>,
    named: StreamName,
    answers_alerts: bool,
    truth: &mut CompetenceTruth<'_, '_, D>,
    mut trace: Option<&mut MissionTrace>,
) -> Result<MissionRecord, PlanError> {
    let course = Course::of(plan, named);
    let mut run = MissionRun::begin(plan, arm, adapter, named, answers_alerts, &course);
    let mut drive = Drive::new(
        &plan.name,
        arm.name(),
        plan.domain,
        plan.feedback,
        None,
        named.seed,
        named.plan,
        u64::from(named.mission),
        adapter,
    );
    adapter
        .begin_episode(run.behavior)
        .expect("no episode is under way and the behavior is drawn from the space");
    let mut upcoming = course.scheduled.iter().peekable();
    for c in 0..plan.commands {
        // A long mission stops within a few milliseconds of a request, not at its end.
        if c % INTERRUPT_EVERY == 0 {
            crate::interrupt::check()?;
        }
        let mut marks = Vec::new();
        while let Some(change) = upcoming.next_if(|s| s.at == c) {
            run.apply(c, change, adapter, &mut marks);
        }
        let attention = run.attend(c, &mut marks);
        let was_watching = adapter.watching().is_some();
        run.calibrate(adapter, truth);
        let judge = run.judges.judge(run.operator, run.context);
        let Command {
            judgement,
            outcome,
            decision,
        } = drive.command(adapter, &run.behavior, judge, attention)?;
        run.observe(&judgement, &outcome);
        run.decided(c, decision, was_watching, adapter, truth, &mut marks);
        if let Some(trace) = trace.as_deref_mut() {
            let estimate = adapter.in_use().map_or(0.0, |(_, e)| e.value);
            trace.record(
                c,
                MissionStep {
                    estimate,
                    low: estimate,
                    high: estimate,
                    own_record: adapter.watching().map(|_| adapter.own_record().value()),
                    untrustworthy: outcome.is_untrustworthy(),
                    marks,
                },
            );
        }
    }
    adapter.abandon_episode();
    Ok(run.record)
}

/// A mission under way: what it has recorded, who judges in which context, and where the
/// robot stands.
struct MissionRun<'r, 'a, D: Domain> {
    plan: &'r MissionPlan<'a, D>,
    arm: &'r Arm,
    named: StreamName,
    /// Whether the robot is told its context (the plan switches contexts and the arm is
    /// not blind to them).
    told: bool,
    answers_alerts: bool,
    judges: Judges<'r, D>,
    thresholds: Thresholds,
    record: MissionRecord,
    /// The operator and the context in force (their places in the population and in the
    /// switches).
    operator: usize,
    context: usize,
    state: OperatorState,
    /// The behavior in use.
    behavior: Behavior,
    /// The last change, while the robot has not settled since.
    waiting: Option<usize>,
    /// Whether any change happened since the behavior in use settled.
    changed_since_settled: bool,
}

impl<'r, 'a: 'r, D: Domain> MissionRun<'r, 'a, D> {
    /// The mission at its start: told its first context (when it is told contexts), its
    /// first behavior chosen as a trial's is, nothing recorded yet.
    fn begin(
        plan: &'r MissionPlan<'a, D>,
        arm: &'r Arm,
        adapter: &mut MissionAdapter<'_>,
        named: StreamName,
        answers_alerts: bool,
        course: &Course,
    ) -> Self {
        let told = plan.contexts.is_some() && !arm.is_context_blind();
        if told {
            adapter
                .set_context(plan.context(course.first_context))
                .expect("no episode is under way between missions");
        }
        let judges = Judges::of(plan);
        let start = first_behavior(arm.initial(), adapter.adapter(), course.drawn);
        let record = MissionRecord {
            mission: named.mission,
            learned_start: start.learned.then_some(start.behavior),
            context: plan.context(course.first_context),
            changes: Vec::new(),
            readaptations: 0,
            false_alarms: 0,
            alerts: Vec::new(),
            onsets: Vec::new(),
            failures: 0,
            overlooked: 0,
            untrustworthy: 0,
            calibration: plan
                .competence
                .as_ref()
                .map(|_| CalibrationRecord::default()),
        };
        Self {
            plan,
            arm,
            named,
            told,
            answers_alerts,
            judges,
            thresholds: adapter.adapter().parameters().thresholds,
            record,
            operator: course.first,
            context: course.first_context,
            state: OperatorState::fresh(),
            behavior: start.behavior,
            waiting: None,
            changed_since_settled: false,
        }
    }

    /// A stream of this mission's, for `purpose`, numbered `k` within it.
    fn stream(&self, k: u64, purpose: Purpose) -> ChaCha8Rng {
        let StreamName {
            seed,
            plan,
            mission,
        } = self.named;
        stream(seed, plan, u64::from(mission) << 16 | k, purpose)
    }

    /// The scheduled `change`, at command `c`: the new operator or context takes over, the
    /// change is recorded (with whether the behavior in use is trustworthy for who judges
    /// now), and a robot told its context switches it.
    fn apply(
        &mut self,
        c: u32,
        change: &Scheduled,
        adapter: &mut MissionAdapter<'_>,
        marks: &mut Vec<Mark>,
    ) {
        (self.operator, self.context) = (change.operator, change.context);
        if change.kind == ChangeKind::Takeover {
            self.state = OperatorState::fresh();
        }
        let mut truth = self.stream(self.record.changes.len() as u64, Purpose::Truth);
        let judge = self.judges.judge(self.operator, self.context);
        let needed = !trustworthy(self.plan, &self.behavior, judge, &mut truth);
        let k = begin_change(&mut self.record.changes, change, needed);
        self.waiting = Some(k);
        self.changed_since_settled = true;
        marks.push(Mark::Change(change.kind));
        if change.kind == ChangeKind::Context && self.told {
            let switched = adapter
                .switch_context(
                    self.plan.context(self.context),
                    self.arm.initial() == Initial::Learned,
                )
                .expect("a mission always has an episode or a watch, in a declared context");
            self.record.changes[k].start = Some(switched.from);
            if switched.behavior != self.behavior {
                self.record.changes[k].notice(c);
            }
            if switched.gave_up_watch {
                self.record.readaptations += 1;
                marks.push(Mark::Readaptation);
            } else if switched.behavior != self.behavior {
                marks.push(Mark::Switch);
            }
            self.behavior = switched.behavior;
        }
    }

    /// The operator's attention for command `c` (`None`: the paper's attentive operator),
    /// recording a complacency onset when it falls below [`COMPLACENT_BELOW`] and ending
    /// it when it is back at [`RECOVERED_AT`].
    fn attend(&mut self, c: u32, marks: &mut Vec<Mark>) -> Option<Attention<'a, D::Operator>> {
        let attention = self
            .plan
            .complacency
            .map(|complacent| complacent.attention(self.state.felt));
        let level = attention.map_or(1.0, |(level, _)| level);
        if level < COMPLACENT_BELOW && self.state.onset.is_none() {
            self.state.onset = Some(self.record.onsets.len());
            self.record.onsets.push(OnsetRecord {
                at: c,
                detected_after: None,
                perceivable: 0,
            });
            marks.push(Mark::Onset);
        } else if level >= RECOVERED_AT {
            self.state.onset = None;
        }
        attention
    }

    /// The command of a watched behavior, on a plan with a competence standard: trusted
    /// or not, truly competent or not, and what the robot judges of it, as the command is
    /// given.
    fn calibrate(&mut self, adapter: &MissionAdapter<'_>, truth: &mut CompetenceTruth<'_, '_, D>) {
        let (Some(calibration), Some(watch), Some(robot)) = (
            self.record.calibration.as_mut(),
            adapter.watching(),
            adapter.competence_judge(),
        ) else {
            return;
        };
        let trusted = self.thresholds.verdict(watch.estimate.value) == Verdict::Trustworthy;
        let competent = truth.competent(watch.behavior);
        let judged = matches!(
            robot.calibration(watch.behavior, watch.estimate.value, &self.thresholds),
            Calibration::Overtrust { .. }
        );
        let overtrusted = trusted && !competent;
        calibration.watched += 1;
        calibration.competent += u32::from(competent);
        calibration.overtrusted += u32::from(overtrusted);
        calibration.judged += u32::from(judged);
        calibration.both += u32::from(overtrusted && judged);
    }

    /// What the command did: a failure, a problem overlooked (perceivable by the robot or
    /// not), an untrustworthy command counted against the change it follows, and the
    /// operator's trust in the robot after it.
    fn observe(&mut self, judgement: &Judgement, outcome: &Outcome) {
        let record = &mut self.record;
        record.failures += u32::from(outcome.kind == OutcomeKind::Failed);
        record.overlooked += u32::from(judgement.overlooked.is_some());
        if let Some(k) = self.state.onset {
            let onset = &mut record.onsets[k];
            if judgement.overlooked.is_some()
                && OwnRecord::has_signal(outcome)
                && onset.detected_after.is_none()
            {
                onset.perceivable += 1;
            }
        }
        if outcome.is_untrustworthy() {
            count_untrustworthy(&mut record.untrustworthy, &mut record.changes, self.waiting);
        }
        if let Some(c) = self.plan.complacency {
            self.state.felt = c.setting.felt_after(self.state.felt, outcome);
        }
    }

    /// The robot's decision after command `c`: an alert (answered or not), an overtrust
    /// alert ([`MissionRun::overtrusted`]), a switch (a readaptation when it gave up a
    /// watched behavior, a false alarm when nothing changed since it settled) or a settled
    /// episode.
    fn decided(
        &mut self,
        c: u32,
        decision: MissionDecision,
        was_watching: bool,
        adapter: &mut MissionAdapter<'_>,
        truth: &mut CompetenceTruth<'_, '_, D>,
        marks: &mut Vec<Mark>,
    ) {
        match decision {
            MissionDecision::Episode(Decision::Keep) => {}
            MissionDecision::Alert(_) => {
                self.record.alerts.push(c);
                marks.push(Mark::Alert);
                if let Some(k) = self.state.onset {
                    let onset = &mut self.record.onsets[k];
                    onset.detected_after.get_or_insert(c - onset.at);
                }
                if self.answers_alerts {
                    // Asked to supervise, the operator looks afresh.
                    self.state = OperatorState::fresh();
                }
            }
            MissionDecision::Overtrust(alert) => {
                marks.push(Mark::Alert);
                self.overtrusted(c, &alert, adapter, truth);
            }
            MissionDecision::Episode(Decision::Switch { to, .. }) => {
                if let Some(k) = self.waiting {
                    self.record.changes[k].notice(c + 1);
                }
                if was_watching {
                    self.record.readaptations += 1;
                    self.record.false_alarms += u32::from(!self.changed_since_settled);
                    marks.push(Mark::Readaptation);
                } else {
                    marks.push(Mark::Switch);
                }
                self.behavior = to;
            }
            MissionDecision::Episode(Decision::Settled(report)) => {
                self.behavior = report.settled;
                self.changed_since_settled = false;
                if report.found_trustworthy
                    && let Some(k) = self.waiting.take()
                {
                    self.record.changes[k].trusted_again = Some(c + 1 - self.record.changes[k].at);
                }
                marks.push(Mark::Settled);
            }
        }
    }

    /// An overtrust alert at command `c`: recorded with whether the behavior is truly
    /// competent; an operator who answers alerts looks afresh, and on a plan that offers
    /// the safer behavior, takes the offer when it trusts it too.
    fn overtrusted(
        &mut self,
        c: u32,
        alert: &CompetenceAlert,
        adapter: &mut MissionAdapter<'_>,
        truth: &mut CompetenceTruth<'_, '_, D>,
    ) {
        let competent = truth.competent(alert.behavior);
        let offered = {
            let calibration = self
                .record
                .calibration
                .as_mut()
                .expect("only a plan with a standard judges competence");
            calibration.alerts.push((c, competent));
            calibration.offered
        };
        if !self.answers_alerts {
            return;
        }
        // Asked to choose, the operator looks afresh at the behavior.
        self.state = OperatorState::fresh();
        let Some(offer) = alert.offer.filter(|_| self.plan.offer_safer) else {
            return;
        };
        // Offered a safer behavior, it takes it if it trusts it too.
        let mut judged = self.stream(u64::from(offered), Purpose::Offer);
        let calibration = self.record.calibration.as_mut().expect("checked above");
        calibration.offered += 1;
        let judge = self.judges.judge(self.operator, self.context);
        if trustworthy(self.plan, &offer, judge, &mut judged) {
            calibration.taken += 1;
            adapter
                .accept_offer(offer)
                .expect("an alert came from a watched behavior of the space");
            self.behavior = offer;
        }
    }
}
