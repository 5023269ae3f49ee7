//! What a mission is whatever the robot does ([`Course`]): its first operator and context,
//! its random first behavior and its scheduled changes, drawn from streams named by
//! [`StreamName`]; and the population as it judges in each context ([`Judges`]). Arms and
//! the oracle run the same courses.

use crate::Domain;
use crate::mission::plan::{ContextSwitches, MissionPlan};
use crate::mission::record::{ChangeKind, ChangeRecord};
use crate::seeds::{Purpose, stream};
use cbr_core::Behavior;
use rand::{Rng, RngCore};

/// A change scheduled for a mission: when, what, and the operator and context after it.
pub(crate) struct Scheduled {
    /// The command at which it happens.
    pub(crate) at: u32,
    /// What changes.
    pub(crate) kind: ChangeKind,
    /// The operator after it (its place in the population).
    pub(crate) operator: usize,
    /// The context after it (its place in [`ContextSwitches::among`]; 0 without switches).
    pub(crate) context: usize,
    /// A context switch back to a context the mission was in before.
    pub(crate) back: bool,
}

/// What a mission is whatever the robot does, drawn from its setup stream (and, with
/// context switches, a stream of their own): its first operator and context, its random
/// first behavior and its changes, the same for every arm and the oracle.
pub(crate) struct Course {
    /// The first operator (its place in the population).
    pub(crate) first: usize,
    /// The first context (its place in [`ContextSwitches::among`]; 0 without switches).
    pub(crate) first_context: usize,
    /// The random first behavior (drawn whatever the arm, so arms stay paired).
    pub(crate) drawn: Behavior,
    /// The changes, in order (an operator change before a context switch at the same
    /// command).
    pub(crate) scheduled: Vec<Scheduled>,
}

impl Course {
    /// The course of the mission `named` of `plan`.
    pub(crate) fn of<D: Domain>(plan: &MissionPlan<'_, D>, named: StreamName) -> Self {
        let mission = u64::from(named.mission);
        let mut setup = stream(named.seed, named.plan, mission, Purpose::Setup);
        let first = setup.random_range(0..plan.operators.len());
        let drawn = plan.domain.space().draw(&mut setup);
        let mut scheduled = schedule(plan, first, &mut setup);
        let mut first_context = 0;
        if let Some(switches) = &plan.contexts {
            let mut rng = stream(named.seed, named.plan, mission, Purpose::ContextSwitch);
            let switched;
            (first_context, switched) = switch_contexts(switches, plan.commands, &mut rng);
            scheduled.extend(switched);
            // At a command with both, the operator change comes first.
            scheduled.sort_by_key(|s| (s.at, s.kind == ChangeKind::Context));
            let (mut operator, mut context) = (first, first_context);
            for change in &mut scheduled {
                if change.kind == ChangeKind::Context {
                    change.operator = operator;
                    context = change.context;
                } else {
                    change.context = context;
                    operator = change.operator;
                }
            }
        }
        Self {
            first,
            first_context,
            drawn,
            scheduled,
        }
    }
}

/// The mission's changes after its `first` operator, the same for every arm.
fn schedule<D: Domain>(
    plan: &MissionPlan<'_, D>,
    first: usize,
    setup: &mut dyn RngCore,
) -> Vec<Scheduled> {
    let n = plan.operators.len();
    let mut changes = Vec::new();
    let (mut at, mut operator) = (0.0f64, first);
    loop {
        at += gap(plan.changes.every, setup);
        if at >= f64::from(plan.commands) || n < 2 {
            break;
        }
        let kind = if setup.random::<f64>() < plan.changes.takeover {
            ChangeKind::Takeover
        } else {
            ChangeKind::Shift
        };
        operator = another(n, operator, setup);
        changes.push(Scheduled {
            at: at as u32,
            kind,
            operator,
            context: 0,
            back: false,
        });
    }
    changes
}

/// The commands to the next change: an exponential gap of mean `every`, rounded up, at
/// least one.
fn gap(every: f64, rng: &mut dyn RngCore) -> f64 {
    let u: f64 = rng.random();
    (-every * (1.0 - u).ln()).ceil().max(1.0)
}

/// One of `0..n` other than `current`, uniformly (`n` at least 2).
fn another(n: usize, current: usize, rng: &mut dyn RngCore) -> usize {
    let next = rng.random_range(0..n - 1);
    if next >= current { next + 1 } else { next }
}

/// A mission's first context and its switches (their operator left for the caller), from
/// the mission's own stream of them.
fn switch_contexts(
    switches: &ContextSwitches,
    commands: u32,
    rng: &mut dyn RngCore,
) -> (usize, Vec<Scheduled>) {
    let n = switches.among.len();
    let first = rng.random_range(0..n);
    let mut seen = vec![false; n];
    seen[first] = true;
    let (mut at, mut context) = (0.0f64, first);
    let mut switched = Vec::new();
    loop {
        at += gap(switches.every, rng);
        if at >= f64::from(commands) {
            break;
        }
        context = another(n, context, rng);
        switched.push(Scheduled {
            at: at as u32,
            kind: ChangeKind::Context,
            operator: 0,
            context,
            back: seen[context],
        });
        seen[context] = true;
    }
    (first, switched)
}

/// Every member of a plan's population as it judges in each context of the plan's
/// switches (the member itself in a domain whose operators judge every context alike).
pub(crate) struct Judges<'p, D: Domain> {
    operators: &'p [(String, D::Operator)],
    /// Per context (in [`ContextSwitches::among`]'s order), per member, the member there
    /// when it judges differently from its own file; empty without switches.
    in_context: Vec<Vec<Option<D::Operator>>>,
}

impl<'p, D: Domain> Judges<'p, D> {
    /// The judges of `plan`.
    pub(crate) fn of(plan: &MissionPlan<'p, D>) -> Self {
        let in_context = plan.contexts.as_ref().map_or_else(Vec::new, |switches| {
            switches
                .among
                .iter()
                .map(|context| {
                    plan.operators
                        .iter()
                        .map(|(_, operator)| plan.domain.operator_in_context(operator, context))
                        .collect()
                })
                .collect()
        });
        Self {
            operators: plan.operators,
            in_context,
        }
    }

    /// Member `member` as it judges in context `context`.
    pub(crate) fn judge(&self, member: usize, context: usize) -> &D::Operator {
        self.in_context
            .get(context)
            .and_then(|members| members[member].as_ref())
            .unwrap_or(&self.operators[member].1)
    }
}

/// What names a mission's random streams: the master seed, its plan's place in the suite
/// and its number.
#[derive(Clone, Copy)]
pub(crate) struct StreamName {
    /// The master seed.
    pub(crate) seed: u64,
    /// The plan's place in the suite.
    pub(crate) plan: u64,
    /// The mission's number.
    pub(crate) mission: u32,
}

/// Records `change` in a mission's `changes` (nothing counted yet) and returns its place,
/// the change the robot is now waiting to settle after, as the arms and the oracle
/// ([`crate::mission::oracle`]) record them.
pub(crate) fn begin_change(
    changes: &mut Vec<ChangeRecord>,
    change: &Scheduled,
    needed: bool,
) -> usize {
    changes.push(ChangeRecord {
        at: change.at,
        kind: change.kind,
        needed,
        trusted_again: None,
        untrustworthy: 0,
        back: change.back,
        start: None,
        noticed: None,
    });
    changes.len() - 1
}

/// Counts an untrustworthy command into a mission's `total` and into the change it came
/// after while the robot had not yet settled again (`waiting`), as the arms and the oracle
/// ([`crate::mission::oracle`]) count them.
pub(crate) fn count_untrustworthy(
    total: &mut u32,
    changes: &mut [ChangeRecord],
    waiting: Option<usize>,
) {
    *total += 1;
    if let Some(k) = waiting {
        changes[k].untrustworthy += 1;
    }
}
