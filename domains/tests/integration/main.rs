//! The domains crate's integration tests: each file is a module of this one test binary, so
//! that the workspace links one binary for them all instead of one per file; run one
//! file's tests with `cargo test -p domains --test integration NAME::`.

mod conformance;
mod fingerprint;
mod ugv;
