//! `WarehouseDomain`: one pick (shelf to packing station) behind the `lab::Domain`
//! contract.
//!
//! A pick draws the item and how far its shelf is, drives out (people may cross), finds
//! the slot or not (the map), grasps (the gripper and its force), drives back carrying
//! the item (braking for crossings may shake it loose) and sets it down. The result is a
//! [`Trace`]; the operator turns it into a `Judgement`, at the attention a mission gives
//! it (`Attentive::run_attending`; `run` is attention 1), which carries what the robot perceived
//! ([`perception`]). Every draw comes from the generator passed in, in a fixed order, so
//! a seed gives one pick.

use crate::gripper::{Grasp, Gripper};
use crate::items::{ITEM_MIX, draw_item};
use crate::map::MapSource;
use crate::motion::{NOMINAL_ACCEL, drive_leg, leg_time};
use crate::operator::WarehouseOperator;
use crate::perception;
use crate::space::{GRIP_FORCE, GRIPPER, MAP, SPEED, warehouse_space};
use crate::trace::{Event, GraspReading, Trace};
use rand::{Rng, RngCore};
use std::convert::Infallible;
use std::ops::ControlFlow;
use std::sync::Arc;
use trustcbr::cbr_core::{Behavior, BehaviorSpace};
use trustcbr::lab::{Attentive, Domain, Judgement};
use trustcbr::rand;
use trustcbr::trust::{Cause, DeclaredCause, Hint};

/// The scenario's name.
pub const PICKING: &str = "picking";

/// How far the shelf is from the packing station along the aisles (m): uniform between
/// these (a 40 m deep picking zone, the nearest aisle 10 m from the station).
pub const SHELF_DISTANCE_M: (f64, f64) = (10.0, 40.0);

/// Time to scan the slot's label before grasping (s).
pub const LABEL_SCAN_S: f64 = 1.0;

/// A behavior's settings in their own terms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// The gripper module.
    pub gripper: Gripper,
    /// The planner's map.
    pub map: MapSource,
    /// Commanded speed (m/s).
    pub speed: f64,
    /// Commanded grip force (N).
    pub grip_force: f64,
}

/// The warehouse picking task.
pub struct WarehouseDomain {
    space: Arc<BehaviorSpace>,
    /// Component index of gripper, map, speed, grip force.
    components: [usize; 4],
}

impl Default for WarehouseDomain {
    fn default() -> Self {
        Self::new()
    }
}

impl WarehouseDomain {
    /// The picking task over [`warehouse_space`].
    pub fn new() -> Self {
        let space = warehouse_space();
        let components = [GRIPPER, MAP, SPEED, GRIP_FORCE]
            .map(|name| space.component_index(name).expect("the space has it"));
        Self { space, components }
    }

    /// The behavior's settings.
    pub fn settings(&self, behavior: &Behavior) -> Settings {
        let [gripper, map, speed, grip_force] = self.components;
        let numeric = |k: usize| self.space.components()[k].numeric_value(behavior.get(k));
        Settings {
            gripper: Gripper::ALL[usize::from(behavior.get(gripper))],
            map: MapSource::ALL[usize::from(behavior.get(map))],
            speed: numeric(speed),
            grip_force: numeric(grip_force),
        }
    }

    /// One pick judged by `operator` at `attention` (1: the paper's attentive operator,
    /// [`WarehouseOperator::judge`]), with what the robot perceived until it ended.
    fn pick(
        &self,
        behavior: &Behavior,
        operator: &WarehouseOperator,
        attention: f64,
        rng: &mut dyn RngCore,
    ) -> Judgement {
        let trace = self.simulate(self.settings(behavior), rng);
        let judgement = operator.judge_attending(&trace, attention, rng);
        let observed = perception::perceive(&trace, judgement.outcome.duration_s);
        judgement.observing(observed)
    }

    /// Simulates one pick with `settings`, drawing all randomness from `rng`.
    pub fn simulate(&self, settings: Settings, rng: &mut dyn RngCore) -> Trace {
        let mut trace = Trace::default();
        let speed = settings.map.driving_speed(settings.speed);
        let item = draw_item(rng);
        let (near, far) = SHELF_DISTANCE_M;
        let distance = near + (far - near) * rng.random::<f64>();
        // Summed as the pick's time is below, so a pick without a stop ends on its plan.
        let leg = leg_time(distance, speed);
        trace.planned_s = leg
            + LABEL_SCAN_S
            + settings.gripper.grasp_time()
            + (leg + settings.gripper.release_time());
        let mut t = 0.0;
        let ControlFlow::Continue(outbound) = drive_leg(distance, speed, rng, |at, stop| {
            if stop.decel > NOMINAL_ACCEL {
                trace.safety_stops.push(t + at);
            }
            if stop.collided {
                trace.push(t + at, Event::Collision);
            }
            ControlFlow::<Infallible>::Continue(())
        });
        t += outbound;
        t += LABEL_SCAN_S;
        if rng.random::<f64>() < settings.map.misplaced_share() {
            trace.push(t, Event::ItemNotFound);
            return trace;
        }
        t += settings.gripper.grasp_time();
        let grasp = Grasp::new(settings.gripper, settings.grip_force, &item, rng);
        trace.grasp = Some(GraspReading {
            t,
            squeeze_n: grasp.squeeze_n,
            rated_n: ITEM_MIX[item.class].rated_squeeze_n(),
        });
        // Lifting off and pulling away at the nominal acceleration.
        if grasp.slips(NOMINAL_ACCEL) {
            trace.push(t, Event::DroppedItem);
            return trace;
        }
        let back = drive_leg(distance, speed, rng, |at, stop| {
            if stop.decel > NOMINAL_ACCEL {
                trace.safety_stops.push(t + at);
            }
            if stop.collided {
                trace.push(t + at, Event::Collision);
            }
            if grasp.slips(stop.decel) {
                trace.push(t + at, Event::DroppedItem);
                return ControlFlow::Break(());
            }
            ControlFlow::Continue(())
        });
        let ControlFlow::Continue(duration) = back else {
            return trace;
        };
        t += duration + settings.gripper.release_time();
        trace.push(
            t,
            Event::Delivered {
                crushed: grasp.crushed,
            },
        );
        trace
    }
}

impl Domain for WarehouseDomain {
    type Operator = WarehouseOperator;

    fn name(&self) -> &str {
        PICKING
    }

    fn space(&self) -> &Arc<BehaviorSpace> {
        &self.space
    }

    fn causes(&self) -> &[DeclaredCause] {
        &crate::cause::DECLARED
    }

    fn observations(&self) -> &[Cause] {
        &perception::OBSERVATIONS
    }

    fn hints(&self) -> &[Hint] {
        &perception::HINTS
    }

    fn run(
        &self,
        behavior: &Behavior,
        operator: &WarehouseOperator,
        rng: &mut dyn RngCore,
    ) -> Judgement {
        self.pick(behavior, operator, 1.0, rng)
    }

    fn attentive(&self) -> Option<&dyn Attentive<Operator = WarehouseOperator>> {
        Some(self)
    }
}

impl Attentive for WarehouseDomain {
    fn run_attending(
        &self,
        behavior: &Behavior,
        operator: &WarehouseOperator,
        attention: f64,
        rng: &mut dyn RngCore,
    ) -> Judgement {
        self.pick(behavior, operator, attention, rng)
    }
}
