//! What the robot itself perceives of a pick: its own sensors and clock, up to the moment
//! the command ended. This is not why the operator reacted (that is the judgement's truth,
//! kept for evaluation); it is what a strategy may relate an untrustworthy pick to.
//!
//! The robot perceives ([`OBSERVATIONS`], in bit order; the reasons: the crate's README,
//! "What the robot perceives"):
//! - `safety-stop`: its safety controller braked harder than the nominal rate for a
//!   crossing (a protective stop). The controller reports the stop, not how close the
//!   person came, and the robot has no bumper: a stop that ended in contact looks the same;
//! - `item-not-found`: its label scan read another item's label: the cause itself,
//!   perceived, so it bears the cause's name;
//! - `firm-grip`: its gripper squeezed the item harder than the item's class is rated to
//!   stand ([`ItemClass::rated_squeeze_n`](crate::items::ItemClass::rated_squeeze_n)): it
//!   knows its own force and which item it picks, not how much this one stands;
//! - `dropped-item`: the gripper's vacuum pressure or jaw travel told it the item left
//!   the grasp: the cause itself, perceived;
//! - `behind-plan`: its clock passed the end its own plan promised ([`Trace::planned_s`]:
//!   no stops); this is its own expectation, not the operator's allowance, which it is not
//!   told.
//!
//! It never perceives whether a stop touched the person who crossed, whether a squeezed
//! item was damaged (the packer sees that), or the operator's deadline.

use crate::cause::WarehouseCause;
use crate::trace::{Event, Trace};
use trustcbr::trust::{Cause, Hint, Observations};

/// The safety controller made a protective stop for a crossing.
pub const SAFETY_STOP: Cause = Cause::from_static("safety-stop");
/// The gripper squeezed the item harder than its class is rated to stand.
pub const FIRM_GRIP: Cause = Cause::from_static("firm-grip");
/// The robot's clock passed the end of its own plan.
pub const BEHIND_PLAN: Cause = Cause::from_static("behind-plan");

/// What the robot perceives, in bit order ([`trustcbr::lab::Domain::observations`]).
pub const OBSERVATIONS: [Cause; 5] = [
    SAFETY_STOP,
    WarehouseCause::ItemNotFound.to_trust(),
    FIRM_GRIP,
    WarehouseCause::DroppedItem.to_trust(),
    BEHIND_PLAN,
];

/// What the robot's designer knows an observation hints at, for the explanations'
/// inferences (`trust::explain`): each is the robot's own view of an operator's reason it
/// cannot perceive.
/// - `safety-stop` hints at `collision`: every collision ends a protective stop (the
///   brake could not stop the robot short), and the robot cannot tell which stops touched;
/// - `firm-grip` hints at `crushed-item`: no item is crushed by a grip that is not firm
///   (every item stands its class's rating), and whether this one was is the packer's to
///   see;
/// - `behind-plan` hints at `too-slow`: the operator's allowance is not told to the robot,
///   but a pick later than its own plan is the pick most likely to exceed it.
pub const HINTS: [Hint; 3] = [
    Hint {
        observation: SAFETY_STOP,
        suggests: WarehouseCause::Collision.to_trust(),
    },
    Hint {
        observation: FIRM_GRIP,
        suggests: WarehouseCause::CrushedItem.to_trust(),
    },
    Hint {
        observation: BEHIND_PLAN,
        suggests: WarehouseCause::TooSlow.to_trust(),
    },
];

/// What the robot perceived of the pick in `trace` up to time `until` (s), the moment the
/// command ended (the judgement's duration).
pub fn perceive(trace: &Trace, until: f64) -> Observations {
    let stops = trace.safety_stops.iter().map(|&t| (t, SAFETY_STOP));
    let firm = trace
        .grasp
        .filter(|g| g.squeeze_n > g.rated_n)
        .map(|g| (g.t, FIRM_GRIP));
    let events = trace.events.iter().filter_map(|&(t, event)| match event {
        Event::ItemNotFound => Some((t, WarehouseCause::ItemNotFound.to_trust())),
        Event::DroppedItem => Some((t, WarehouseCause::DroppedItem.to_trust())),
        // Whether a stop touched, and whether the item arrived whole, it does not know.
        Event::Collision | Event::Delivered { .. } => None,
    });
    // Behind its plan from the first instant past it: a pick without a stop ends exactly
    // on its plan, and is not late.
    let late = (trace.planned_s.next_up(), BEHIND_PLAN);
    let timed = stops.chain(firm).chain(events).chain([late]);
    Observations::named_until(&OBSERVATIONS, until, timed)
}
