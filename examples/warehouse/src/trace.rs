//! What happened in one pick, in time order: the events the operator watches, and what
//! the robot's own sensors and clock record (its protective stops, its grasp, its plan),
//! which the operator does not watch and [`crate::perception`] reads.

/// One thing the operator can see happen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Event {
    /// The robot hit someone or something crossing its path (it stops and goes on).
    Collision,
    /// The slot held another item: the map misplaced it. The pick ends.
    ItemNotFound,
    /// The item slipped out of the gripper. The pick ends.
    DroppedItem,
    /// The item reached the packing station; `crushed` when the gripper squeezed it
    /// beyond what it stands. The pick ends.
    Delivered {
        /// Whether the item arrived crushed.
        crushed: bool,
    },
}

/// The grasp as the gripper's own force or vacuum reading saw it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GraspReading {
    /// When the gripper closed (s since the command).
    pub t: f64,
    /// The squeeze (N) of two rigid pads' equivalent: the applied force over the module's
    /// spread.
    pub squeeze_n: f64,
    /// What the item's class is rated to stand (N; infinite when nothing crushes it): the
    /// order line names the item, the item data its class.
    pub rated_n: f64,
}

/// The events of one pick with their times (s since the command), in time order; the
/// last ends the pick. Beside them, the robot's own readings and its plan.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trace {
    /// `(time, event)` pairs the operator watches.
    pub events: Vec<(f64, Event)>,
    /// Times (s) of the safety controller's protective stops for crossings (it braked
    /// harder than the nominal rate), whether or not a stop ended in contact; in order.
    pub safety_stops: Vec<f64>,
    /// The grasp, when the robot got to grasp the item.
    pub grasp: Option<GraspReading>,
    /// When the robot's own plan has the pick end (s): both legs driven without a stop,
    /// the label scan, the grasp and the release.
    pub planned_s: f64,
}

impl Trace {
    /// Appends an event; times never decrease.
    pub fn push(&mut self, t: f64, event: Event) {
        debug_assert!(self.events.last().is_none_or(|&(last, _)| last <= t));
        self.events.push((t, event));
    }
}
