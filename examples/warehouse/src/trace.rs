//! What happened in one pick, in time order: what the operator watches.

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

/// The events of one pick with their times (s since the command), in time order; the
/// last ends the pick.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trace {
    /// `(time, event)` pairs.
    pub events: Vec<(f64, Event)>,
}

impl Trace {
    /// Appends an event; times never decrease.
    pub fn push(&mut self, t: f64, event: Event) {
        debug_assert!(self.events.last().is_none_or(|&(last, _)| last <= t));
        self.events.push((t, event));
    }
}
