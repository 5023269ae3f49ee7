//! [`Troubleshooter`]: the warehouse's own search strategy. It reads what the untrustworthy
//! picks of the behavior just given up told the robot (the operator's stated reason, what
//! the robot perceived, whether the pick was interrupted or failed) and changes the
//! component that trouble implicates, as a technician would:
//! - stops for crossings (`collision` stated, `safety-stop` perceived): drive slower;
//! - a pick too slow (`too-slow`, `behind-plan`, or an interruption with no stop seen):
//!   drive faster, on the same map if it allows, else on a map that does not cap the speed;
//! - a slot not where the map put it (`item-not-found`): a fresher map, else another one;
//! - an item slipping (`dropped-item`): a firmer grip, else another gripper;
//! - an item crushed (`crushed-item`, or a failure after a `firm-grip`): a gentler grip,
//!   else another gripper.
//!
//! Among the untried behaviors such a change reaches it draws one uniformly; when the
//! picks were unexplained, or no change of the implicated components is left untried, it
//! draws uniformly among every untried behavior (as it does on a space without the
//! warehouse's components). It learns nothing across episodes: what it reads is this
//! episode's.

use crate::cause::WarehouseCause;
use crate::gripper::Gripper;
use crate::map::MapSource;
use crate::perception::{BEHIND_PLAN, FIRM_GRIP, OBSERVATIONS, SAFETY_STOP};
use crate::space::{GRIP_FORCE, GRIPPER, MAP, SPEED};
use std::collections::{HashMap, HashSet};
use trustcbr::cbr_core::{Behavior, BehaviorSpace, Proposal, Rationale, Searcher};
use trustcbr::rand::{Rng, RngCore};
use trustcbr::trust::search::{draw_untried, propose_untried};
use trustcbr::trust::{Cause, Evaluated, Outcome, OutcomeKind};

/// The searcher's name, and the arm's that searches with it alone.
pub const TROUBLESHOOTER: &str = "troubleshooter";

/// What went wrong with a pick, as the robot can tell it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Trouble {
    /// It stopped for crossings, and may have touched someone.
    Crossing,
    /// The pick took too long.
    Late,
    /// The slot was not where the map put it.
    Misplaced,
    /// The item slipped out of the gripper.
    Slipped,
    /// The item was squeezed too hard.
    Crushed,
}

impl Trouble {
    /// Every trouble; ties between troubles go to the earlier.
    pub const ALL: [Trouble; 5] = [
        Trouble::Crossing,
        Trouble::Late,
        Trouble::Misplaced,
        Trouble::Slipped,
        Trouble::Crushed,
    ];

    /// The trouble an operator's stated reason names.
    pub fn stated(cause: Cause) -> Option<Trouble> {
        let cause: WarehouseCause = cause.as_str().parse().ok()?;
        Some(match cause {
            WarehouseCause::Collision => Trouble::Crossing,
            WarehouseCause::TooSlow => Trouble::Late,
            WarehouseCause::ItemNotFound => Trouble::Misplaced,
            WarehouseCause::DroppedItem => Trouble::Slipped,
            WarehouseCause::CrushedItem => Trouble::Crushed,
        })
    }

    /// The troubles an untrustworthy `outcome` points at, each with an equal share of it:
    /// the stated reason when there is one; else a perceived drop or missing slot; else,
    /// for an interruption (the operator stops a pick for a collision, which always ends
    /// a safety stop, or for its deadline), the stops and the lateness perceived, or
    /// lateness when no stop was; for a failure (a crushed item at delivery, or a pick
    /// given up), a firm grip and the lateness perceived, or lateness when the grip was
    /// not firm.
    pub fn of(outcome: &Outcome) -> Vec<Trouble> {
        if let Some(stated) = outcome.stated.and_then(Trouble::stated) {
            return vec![stated];
        }
        let perceived = |name: Cause| outcome.observed.contains_named(&OBSERVATIONS, name);
        if perceived(WarehouseCause::DroppedItem.to_trust()) {
            return vec![Trouble::Slipped];
        }
        if perceived(WarehouseCause::ItemNotFound.to_trust()) {
            return vec![Trouble::Misplaced];
        }
        let (sign, of_sign) = match outcome.kind {
            OutcomeKind::Interrupted => (SAFETY_STOP, Trouble::Crossing),
            OutcomeKind::Failed => (FIRM_GRIP, Trouble::Crushed),
            OutcomeKind::Completed => return Vec::new(),
        };
        if !perceived(sign) {
            return vec![Trouble::Late];
        }
        let mut troubles = vec![of_sign];
        if perceived(BEHIND_PLAN) {
            troubles.push(Trouble::Late);
        }
        troubles
    }

    fn index(self) -> usize {
        Trouble::ALL
            .iter()
            .position(|&t| t == self)
            .expect("every trouble is listed")
    }

    /// What changing the implicated component should bring, for the rationale.
    fn expectation(self) -> &'static str {
        match self {
            Trouble::Crossing => "fewer hard stops and collisions at crossings: driving slower",
            Trouble::Late => "picks on time: driving faster",
            Trouble::Misplaced => "slots where the map puts them: another map",
            Trouble::Slipped => "no item slipping: a firmer grip or another gripper",
            Trouble::Crushed => "no item crushed: a gentler grip or another gripper",
        }
    }
}

/// Where the warehouse's components are in a space.
#[derive(Clone, Copy, Debug)]
struct Layout {
    gripper: usize,
    map: usize,
    speed: usize,
    grip_force: usize,
}

impl Layout {
    /// The warehouse's components in `space`, or `None` when it lacks one of them.
    fn of(space: &BehaviorSpace) -> Option<Self> {
        let layout = Self {
            gripper: space.component_index(GRIPPER)?,
            map: space.component_index(MAP)?,
            speed: space.component_index(SPEED)?,
            grip_force: space.component_index(GRIP_FORCE)?,
        };
        let components = space.components();
        // Another space's components of the same names are not the warehouse's.
        (components[layout.gripper].len() == Gripper::ALL.len()
            && components[layout.map].len() == MapSource::ALL.len())
        .then_some(layout)
    }

    fn map(&self, b: &Behavior) -> MapSource {
        MapSource::ALL[usize::from(b.get(self.map))]
    }

    /// The speed `b` drives at (m/s): its commanded speed as its map allows.
    fn driving_speed(&self, space: &BehaviorSpace, b: &Behavior) -> f64 {
        let commanded = space.components()[self.speed].numeric_value(b.get(self.speed));
        self.map(b).driving_speed(commanded)
    }

    fn grip_force(&self, space: &BehaviorSpace, b: &Behavior) -> f64 {
        space.components()[self.grip_force].numeric_value(b.get(self.grip_force))
    }
}

/// One change of the implicated components, against the behavior given up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Change {
    /// A lower commanded speed, so a lower driving speed.
    Slower,
    /// A higher commanded speed, to a higher driving speed.
    Faster,
    /// A higher driving speed on any map (the live map caps it).
    FasterOnAnyMap,
    /// A map that misplaces fewer slots.
    FresherMap,
    /// Any other map.
    OtherMap,
    /// A higher grip force.
    FirmerGrip,
    /// A lower grip force.
    GentlerGrip,
    /// Another gripper, at any force.
    OtherGripper,
}

impl Change {
    /// The changes that repair `trouble`, in order of preference.
    fn repairing(trouble: Trouble) -> &'static [Change] {
        match trouble {
            Trouble::Crossing => &[Change::Slower],
            Trouble::Late => &[Change::Faster, Change::FasterOnAnyMap],
            Trouble::Misplaced => &[Change::FresherMap, Change::OtherMap],
            Trouble::Slipped => &[Change::FirmerGrip, Change::OtherGripper],
            Trouble::Crushed => &[Change::GentlerGrip, Change::OtherGripper],
        }
    }

    /// The components the change may set.
    fn varies(self, layout: &Layout) -> Vec<usize> {
        match self {
            Change::Slower | Change::Faster => vec![layout.speed],
            Change::FasterOnAnyMap => vec![layout.speed, layout.map],
            Change::FresherMap | Change::OtherMap => vec![layout.map],
            Change::FirmerGrip | Change::GentlerGrip => vec![layout.grip_force],
            Change::OtherGripper => vec![layout.gripper, layout.grip_force],
        }
    }

    /// Whether `to` makes the change from `from`.
    fn made(self, layout: &Layout, space: &BehaviorSpace, from: &Behavior, to: &Behavior) -> bool {
        let driving = |b| layout.driving_speed(space, b);
        let force = |b| layout.grip_force(space, b);
        match self {
            Change::Slower => driving(to) < driving(from),
            Change::Faster | Change::FasterOnAnyMap => driving(to) > driving(from),
            Change::FresherMap => {
                layout.map(to).misplaced_share() < layout.map(from).misplaced_share()
            }
            Change::OtherMap => to.get(layout.map) != from.get(layout.map),
            Change::FirmerGrip => force(to) > force(from),
            Change::GentlerGrip => force(to) < force(from),
            Change::OtherGripper => to.get(layout.gripper) != from.get(layout.gripper),
        }
    }

    /// The untried behaviors that make the change from `from`, in rank order.
    fn candidates(
        self,
        layout: &Layout,
        space: &BehaviorSpace,
        from: &Behavior,
        tried: &HashSet<Behavior>,
    ) -> Vec<Behavior> {
        let mut reached = vec![*from];
        for k in self.varies(layout) {
            let values = space.components()[k].len() as u16;
            reached = reached
                .into_iter()
                .flat_map(|b| (0..values).map(move |v| b.with(k, v)))
                .collect();
        }
        reached.retain(|b| !tried.contains(b) && self.made(layout, space, from, b));
        reached
    }
}

/// The troubleshooting searcher ([module documentation](self)).
#[derive(Clone, Debug, Default)]
pub struct Troubleshooter {
    /// This episode's untrustworthy weight per behavior and trouble.
    troubles: HashMap<Behavior, [f64; Trouble::ALL.len()]>,
    /// The trouble the last proposal repairs (`None`: it explored).
    repairing: Option<Trouble>,
}

impl Troubleshooter {
    /// A troubleshooter that has read nothing yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// The trouble that weighed most on `behavior` in this episode, if any did.
    fn main_trouble(&self, behavior: &Behavior) -> Option<Trouble> {
        let weights = self.troubles.get(behavior)?;
        Trouble::ALL
            .into_iter()
            .filter(|t| weights[t.index()] > 0.0)
            .fold(None, |best: Option<Trouble>, t| match best {
                Some(b) if weights[b.index()] >= weights[t.index()] => Some(b),
                _ => Some(t),
            })
    }
}

impl Searcher for Troubleshooter {
    type Evidence = Evaluated;
    type Feedback = Outcome;

    fn name(&self) -> &str {
        TROUBLESHOOTER
    }

    fn begin_episode(&mut self, _space: &BehaviorSpace, _initial: &Behavior) {
        self.troubles.clear();
        self.repairing = None;
    }

    fn observe(&mut self, behavior: &Behavior, outcome: &Outcome) {
        if !outcome.is_untrustworthy() {
            return;
        }
        let troubles = Trouble::of(outcome);
        let share = outcome.weight / troubles.len().max(1) as f64;
        let weights = self.troubles.entry(*behavior).or_default();
        for trouble in troubles {
            weights[trouble.index()] += share;
        }
    }

    fn propose(
        &mut self,
        space: &BehaviorSpace,
        evaluated: &[Evaluated],
        rng: &mut dyn RngCore,
    ) -> Proposal {
        self.repairing = None;
        let layout = Layout::of(space);
        let given_up = evaluated.last().map(|e| e.behavior);
        let trouble = given_up.and_then(|b| self.main_trouble(&b));
        let mut repairing = None;
        let proposal = propose_untried(space, evaluated, rng, |tried, rng| {
            if let (Some(layout), Some(from), Some(trouble)) = (layout, given_up, trouble) {
                for change in Change::repairing(trouble) {
                    let candidates = change.candidates(&layout, space, &from, tried);
                    if !candidates.is_empty() {
                        repairing = Some(trouble);
                        return Some(candidates[rng.random_range(0..candidates.len())]);
                    }
                }
            }
            draw_untried(space, tried, 1, rng).pop()
        });
        self.repairing = repairing;
        proposal
    }

    fn rationale(&self, _proposed: &Behavior) -> Rationale {
        match self.repairing {
            Some(trouble) => Rationale::Expects {
                what: trouble.expectation().into(),
                confidence: None,
            },
            None => Rationale::Explores {
                how: "uniform among untried behaviors: no component implicated".into(),
            },
        }
    }
}
