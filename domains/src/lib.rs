#![doc = include_str!("../README.md")]
#![deny(missing_docs)]

pub mod causes;
pub mod detector;
pub mod drive;
pub mod geometry;
pub mod job_context;
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
pub mod self_competence;
pub mod spaces;
pub mod statements;
pub mod trace;
pub mod ugv;
pub mod world;

pub use operator::{OperatorError, OperatorModel, UndeclaredPreference, builtin_operators};
pub use perception::perceive;
pub use render::render_run;
pub use scenario::{Scenario, UnknownScenario};
pub use trace::{Event, EventKind, Trace};
pub use ugv::{Run, Settings, UgvDomain};
pub use world::World;

/// The paper's seven experiments as a suite config (RON): the suite the `trustcbr` tool's
/// `reproduce` runs and `config` prints.
pub const PAPER_CONFIG: &str = include_str!("../experiments/paper.ron");
