//! The trust crate's integration tests: each file is a module of this one test binary, so
//! that the workspace links one binary for them all instead of one per file; run one
//! file's tests with `cargo test -p trust --test integration NAME::`.

mod adapter;
mod mission;
mod retrievers;
mod searchers;
mod start;
mod vectors;
