//! A warehouse pick-and-place robot as a trust domain, written against `trustcbr`'s public
//! API only, as a user of the library would.
//!
//! Each command fetches one item from a shelf to the packing station. The robot adapts
//! four components: which gripper grasps (a module), which map the planner uses (data),
//! how fast it drives and how hard it grips. Operators (RON files) weigh throughput
//! against care. The binary is the whole `trustcbr` tool over [`WarehouseCatalog`].
//! Every modelling choice and its reason: `README.md` next to this crate.
//!
//! - [`space`]: the behavior space;
//! - [`items`]: the item mix;
//! - [`gripper`]: the grasping modules and the arithmetic of a grasp;
//! - [`map`]: the maps and what a stale one costs;
//! - [`motion`]: driving a leg, stopping for crossings;
//! - [`trace`]: what happened in a pick;
//! - [`domain`]: [`WarehouseDomain`], one pick;
//! - [`cause`]: the warehouse's causes;
//! - [`perception`]: what the robot perceives of a pick, and what that hints at;
//! - [`operator`]: the operators, as data;
//! - [`population`]: a family of operators who disagree, throughput against care;
//! - [`searcher`]: [`Troubleshooter`], the warehouse's own search strategy;
//! - [`catalog`]: [`WarehouseCatalog`], what the command-line tool offers.

pub mod catalog;
pub mod cause;
pub mod domain;
pub mod gripper;
pub mod items;
pub mod map;
pub mod motion;
pub mod operator;
pub mod perception;
pub mod population;
pub mod searcher;
pub mod space;
pub mod trace;

pub use catalog::WarehouseCatalog;
pub use cause::WarehouseCause;
pub use domain::{PICKING, Settings, WarehouseDomain};
pub use operator::{OperatorError, WarehouseOperator, builtin_operators};
pub use searcher::Troubleshooter;
