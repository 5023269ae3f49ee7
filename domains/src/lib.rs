//! Built-in domain plug-ins for the trust machinery: the paper's movement and patrol
//! scenarios over a 2-D UGV world, with operator models as data.
//!
//! A run is simulated into a time-ordered [`Trace`] (collisions, objects missed or
//! labelled, detonations, arrival or a stuck robot); an [`OperatorModel`], loaded from
//! RON, reads the trace and decides the [`trust::Outcome`]. The world and the robot are
//! documented, with the reasons for every number, in `docs/simulation.md`.

pub mod detector;
pub mod drive;
pub mod geometry;
pub mod operator;
pub mod patrol;
pub mod planner;
pub mod profile;
pub mod render;
pub mod scenario;
pub mod spaces;
pub mod suite;
pub mod sweep;
pub mod trace;
pub mod ugv;
pub mod world;

pub use operator::{OperatorError, OperatorModel, Weights, builtin_operators, find_operator};
pub use render::render_run;
pub use scenario::{Scenario, UnknownScenario};
pub use suite::{
    StartingCases, SuiteConfig, run_suite, save_case_bases, suite_best_arms, suite_table,
    write_suite_report,
};
pub use trace::{Event, EventKind, Trace};
pub use ugv::{Run, Settings, UgvDomain};
pub use world::World;
