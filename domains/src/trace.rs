//! The record of one run: what happened and when, in time order. The simulation writes
//! it without knowing who watches; operator models read it and decide.
//!
//! Besides the endings (collision, stuck, missed object, label, detonation, arrival) a
//! trace records measurements the simulation has anyway and that some operators, or the
//! robot's own perception ([`crate::perception`]), care about: the closest approach to
//! each spot where people stand (occupied or not) and the robot's speed there, the run's least body
//! gap, each scan's distance and duration, and the moment the robot fell behind its own
//! plan. Writing them draws no random number; an operator that ignores them judges as if
//! they were not there.

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
    /// The robot passed closest to the spot `person` where people stand (occupied or not):
    /// the gap between its body and a person's there (m, along the planned path) and its
    /// speed there (m/s).
    PassedPerson {
        /// Index of the spot ([`crate::world::World::humans`]).
        person: usize,
        /// Whether someone stood there during the run.
        present: bool,
        /// Body-to-body gap at the closest approach (m).
        gap: f64,
        /// The robot's speed at that point (m/s).
        speed: f64,
    },
    /// The least gap between the robot's body and any obstacle or person the run came to
    /// without touching it (m), measured where its path runs close to something.
    ClosestPass {
        /// The gap (m).
        gap: f64,
        /// Where the robot's centre was.
        at: Vec2,
    },
    /// The robot finished scanning an object (written just before its label).
    Scanned {
        /// Index of the object.
        object: usize,
        /// Gap between the robot's body and the object while scanning (m).
        distance: f64,
        /// How long it scanned (s).
        duration: f64,
    },
    /// The robot's clock passed the arrival time its own plan promised (the nominal drive
    /// plus the stops it made) while it was still driving: collisions had delayed it.
    BehindPlan {
        /// The planned arrival (s), the time of this event.
        planned: f64,
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
    /// A trace of `events` (time, what), in the order given: hand-built traces for
    /// judging and perceiving.
    pub fn of(events: &[(f64, EventKind)]) -> Self {
        Self {
            events: events.iter().map(|&(t, kind)| Event { t, kind }).collect(),
        }
    }

    /// Appends an event.
    pub fn push(&mut self, t: f64, kind: EventKind) {
        self.events.push(Event { t, kind });
    }

    /// Inserts an event after every event at or before `t`, keeping the time order.
    pub fn insert_sorted(&mut self, t: f64, kind: EventKind) {
        let at = self.events.partition_point(|e| e.t <= t);
        self.events.insert(at, Event { t, kind });
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
