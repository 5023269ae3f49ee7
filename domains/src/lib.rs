//! Built-in domain plug-ins for the trust machinery: the paper's movement and patrol
//! scenarios over a 2-D UGV world, with operator models as data.
//!
//! A run is simulated into a time-ordered [`Trace`] (collisions, objects missed or
//! labelled, detonations, arrival or a stuck robot); an [`OperatorModel`], loaded from
//! RON, reads the trace and decides the [`trust::Outcome`]. The world and the robot are
//! documented, with the reasons for every number, in `docs/simulation.md`.

#![deny(missing_docs)]

pub mod causes;
pub mod detector;
pub mod drive;
pub mod geometry;
pub mod map_labels;
pub mod operator;
pub mod patrol;
pub mod perception;
pub mod planner;
pub mod population;
pub mod prior;
pub mod profile;
pub mod render;
pub mod scenario;
pub mod spaces;
pub mod trace;
pub mod ugv;
pub mod world;

pub use operator::{OperatorError, OperatorModel, builtin_operators};
pub use perception::perceive;
pub use render::render_run;
pub use scenario::{Scenario, UnknownScenario};
pub use trace::{Event, EventKind, Trace};
pub use ugv::{Run, Settings, UgvDomain};
pub use world::World;

/// The paper's seven experiments as a suite config (RON): the suite the `trustcbr` tool's
/// `reproduce` runs and `config` prints.
pub const PAPER_CONFIG: &str = include_str!("../experiments/paper.ron");
