//! Experiments and their driver: an [`Arm`](arm::Arm) (a search strategy and its
//! options), the simulated command ([`simulate`]), the driver every trial and mission
//! command goes through (the private `driver`), paired trials of every arm and their
//! results ([`runner`]), the contexts trials run in ([`trial_contexts`]) and goal changes
//! ([`goal_change`]).
//!
//! Imports the [`contract`](crate::contract) and [`reference`](crate::reference) folders.

pub mod arm;
pub mod arm_name;
pub(crate) mod driver;
pub mod goal_change;
pub mod plan;
pub mod record;
pub mod runner;
pub mod simulate;
pub mod trial_contexts;
