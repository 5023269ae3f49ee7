//! The warehouse robot's behavior space: which gripper, which map, how fast, how hard.
//!
//! Component names are the user interface (`--behavior
//! 'gripper=suction,map=live,speed=1.5,grip_force=40'`, reports, the service protocol).
//! The whole space is built in [`warehouse_space`], the one place that constructs
//! components.

use crate::gripper::Gripper;
use crate::map::MapSource;
use std::sync::Arc;
use trustcbr::cbr_core::{BehaviorSpace, Categorical, NamedComponent, Values};

/// The gripper module (categorical: suction, parallel-jaw, soft-fingers).
pub const GRIPPER: &str = "gripper";
/// The map the planner uses (categorical: as-built, last-survey, live).
pub const MAP: &str = "map";
/// Commanded speed `{0.25, 0.5, ..., 2.5}` m/s.
pub const SPEED: &str = "speed";
/// Commanded grip force `{5, 10, ..., 100}` N.
pub const GRIP_FORCE: &str = "grip_force";

/// The space: 3 grippers x 3 maps x 10 speeds x 20 grip forces = 1,800 behaviors.
///
/// The categorical similarities say which values mean alike: the jaws and the soft
/// fingers both pinch (the grip force means a clamping force for both), a suction cup
/// pulls; the as-built plan and the last survey are both maps made before today, the live
/// map is not.
pub fn warehouse_space() -> Arc<BehaviorSpace> {
    let categorical = |name: &str, labels: Vec<&str>, similarity: Vec<Vec<f64>>| {
        let values = Values::Categorical(Categorical::new(labels).with_similarity(similarity));
        NamedComponent::new(name, "", values).expect("a valid categorical component")
    };
    let gripper = categorical(
        GRIPPER,
        Gripper::ALL.map(Gripper::label).into(),
        vec![
            vec![1.0, 0.0, 0.0],
            vec![0.0, 1.0, 0.5],
            vec![0.0, 0.5, 1.0],
        ],
    );
    let map = categorical(
        MAP,
        MapSource::ALL.map(MapSource::label).into(),
        vec![
            vec![1.0, 0.5, 0.0],
            vec![0.5, 1.0, 0.0],
            vec![0.0, 0.0, 1.0],
        ],
    );
    let speed = NamedComponent::numeric(SPEED, "m/s", 0.25, 0.25, 10).expect("a valid grid");
    let grip_force = NamedComponent::numeric(GRIP_FORCE, "N", 5.0, 5.0, 20).expect("a valid grid");
    Arc::new(BehaviorSpace::new(vec![gripper, map, speed, grip_force]).expect("a valid space"))
}
