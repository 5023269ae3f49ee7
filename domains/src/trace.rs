//! The record of one run: what happened and when, in time order. The simulation writes
//! it without knowing who watches; operator models read it and decide.

use crate::geometry::Vec2;

/// Something that happened during a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EventKind {
    /// The robot touched an obstacle at `at`.
    Collision {
        /// Where the robot's centre was.
        at: Vec2,
    },
    /// The robot found no path that keeps its padding and gave up.
    Stuck,
    /// The robot drove past a suspicious object without noticing it.
    MissedObject {
        /// Index of the object.
        object: usize,
    },
    /// The robot scanned an object and labelled it.
    Labelled {
        /// Index of the object.
        object: usize,
        /// Whether it really is explosive.
        explosive: bool,
        /// Whether the robot labelled it explosive.
        labelled_explosive: bool,
    },
    /// An explosive the robot labelled harmless went off.
    Detonation {
        /// Index of the object.
        object: usize,
    },
    /// The robot reached its goal at `at` (not exactly the planned goal).
    Arrived {
        /// Where the robot's centre stopped.
        at: Vec2,
    },
}

/// An event and its time since the command was given (s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Event {
    /// Seconds since the start of the run.
    pub t: f64,
    /// What happened.
    pub kind: EventKind,
}

/// The events of one run in time order; the last is `Arrived` or `Stuck`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trace {
    /// Events, earliest first.
    pub events: Vec<Event>,
}

impl Trace {
    /// Appends an event.
    pub fn push(&mut self, t: f64, kind: EventKind) {
        self.events.push(Event { t, kind });
    }

    /// Puts the events in time order (stable: simultaneous events keep their order).
    pub fn sort(&mut self) {
        self.events.sort_by(|a, b| a.t.total_cmp(&b.t));
    }

    /// Number of collisions.
    pub fn collisions(&self) -> usize {
        self.events
            .iter()
            .filter(|e| matches!(e.kind, EventKind::Collision { .. }))
            .count()
    }
}
