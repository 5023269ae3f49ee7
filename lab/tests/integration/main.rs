//! The lab crate's integration tests: each file is a module of this one test binary, so
//! that the workspace links one binary for them all instead of one per file; run one
//! file's tests with `cargo test -p lab --test integration NAME::`.

mod declared_contexts;
mod experiment;
mod goal_changes;
mod limit;
mod limit_bounds_arms;
mod mission_contexts;
mod missions;
mod perception;
