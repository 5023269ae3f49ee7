#![doc = include_str!("../README.md")]

pub mod cases;
pub mod db;
#[cfg(feature = "postgres")]
mod db_postgres;
mod db_sqlite;
pub mod export;
pub mod participant;
pub mod report;
pub mod server;
pub mod stage;
pub mod story;
pub mod study;

pub use db::{Db, DbError};
pub use participant::{Conduct, ConductError};
pub use stage::{Ending, ShownRun, Stage};
pub use study::{Study, StudyError};
