//! What happened in one pick, in time order: the events the operator watches, and what
//! the robot's own sensors and clock record ([`Reading`], [`Trace::planned_s`]), which
//! the operator does not watch and [`crate::perception`] reads.

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

/// One thing the robot's own sensors record.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Reading {
    /// The safety controller braked harder than the nominal rate for a crossing (a
    /// protective stop), whether or not the stop ended in contact.
    SafetyStop,
    /// The gripper closed on the item, squeezing it with `squeeze_n` N of two rigid pads'
    /// equivalent (the applied force over the module's spread); the item's class is rated
    /// to stand `rated_n` N (the order line names the item, the item data its class).
    Grasped {
        /// The squeeze (N).
        squeeze_n: f64,
        /// What the item's class is rated to stand (N; infinite when nothing crushes it).
        rated_n: f64,
    },
}

/// The events of one pick with their times (s since the command), in time order; the
/// last ends the pick. Beside them, the robot's own readings and its plan.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trace {
    /// `(time, event)` pairs the operator watches.
    pub events: Vec<(f64, Event)>,
    /// `(time, reading)` pairs of the robot's sensors, in time order.
    pub readings: Vec<(f64, Reading)>,
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

    /// Appends a reading of the robot's sensors; times never decrease.
    pub fn record(&mut self, t: f64, reading: Reading) {
        debug_assert!(self.readings.last().is_none_or(|&(last, _)| last <= t));
        self.readings.push((t, reading));
    }
}
