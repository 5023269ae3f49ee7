//! `trustcbr`: the command-line tool for trust-guided behavior adaptation, as a library.
//!
//! The tool runs experiments (`reproduce`, `run`, `sweep`), simulates commands
//! (`simulate`), draws runs and landscapes (`render`, `landscape`), serves the online
//! adapter to robot controllers (`serve`) and manages case bases (`cases`) for the
//! scenarios of a [`Catalog`]. The shipped binary is
//! [`cli::main`] over `UgvCatalog` (the paper's movement and patrol scenarios); a task
//! plug-in in its own crate implements [`lab::Domain`] and [`Catalog`] and gets the whole
//! tool with `fn main() -> ExitCode { trustcbr::cli::main(MyCatalog) }`
//! (`docs/plugin-guide.md`).
//!
//! - [`catalog`]: the [`Catalog`] trait and what it names (scenarios, operators, readings);
//! - [`config_file`]: what goes wrong with a config file, shared by suites and sweeps;
//! - [`limits`]: every cap on what the tool is asked, in one table, with its checks;
//! - [`suite`]: suite configs (RON) and their runs and reports;
//! - [`sweep`]: suites over seeds and parameter values, sharded and merged;
//! - [`mission_suite`]: mission suites (long missions, operator changes, complacency) and
//!   their reports;
//! - [`run`]: a suite run with its report folder, as `run` does it;
//! - [`served`]: the domain and strategy `serve` serves;
//! - [`simulate`]: a simulated command as `simulate` prints it;
//! - [`cli`]: the command line;
//! - `console_stage`: the UGV world as a stage a person watches in a trust study (the
//!   `console` and `ugv` features; `console` is the study's server);
//! - `ugv`: the built-in catalog (the `ugv` feature; plain names here, not links, so the
//!   docs of a build without it link nothing missing).
//!
//! Cargo features, all but `testing` on by default: `ugv` (the built-in catalog and the
//! `trustcbr` binary, over the `domains` crate), `sqlite` and `postgres` (the case stores
//! of `serve --cases` and `cases`, `service`'s features of the same names), `console` (a
//! trust study served to browsers, the `console` crate), `testing` (the
//! conformance kits, and `testing`: a plug-in's tool run on a suite as a real process). A plug-in's tool depends on this crate with `default-features =
//! false` and the stores it opens; a store left out is refused when a command opens one
//! ("this tool was built without the `postgres` feature"). The plug-in guide's *Building
//! only what you need* has what each costs.

#![deny(missing_docs)]

pub mod catalog;
pub mod cli;
pub mod config_file;
#[cfg(all(feature = "console", feature = "ugv"))]
pub mod console_stage;
pub mod limits;
pub mod mission_suite;
pub mod own_files;
pub mod progress;
pub mod run;
pub mod served;
pub mod simulate;
pub mod suite;
pub mod sweep;
#[cfg(feature = "testing")]
pub mod testing;
#[cfg(feature = "ugv")]
pub mod ugv;

#[doc = include_str!("../docs/plugin-guide.md")]
pub mod plugin_guide {}

/// The top-level README's Rust examples (the tool as a library), run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;

pub use catalog::{
    AddedArm, Catalog, CatalogError, Family, FindOperatorError, OperatorFile, Reading,
    ReadingError, Readings, ToolInfo, UnknownScenario, WithArms,
};
pub use config_file::ConfigFileError;
pub use suite::{SuiteError, TraceError};
pub use sweep::SweepError;
#[cfg(feature = "ugv")]
pub use ugv::UgvCatalog;

// The crates a plug-in's code names, re-exported so a plug-in depends on one version of
// each (`trustcbr` alone; the `testing` feature turns on `trust::testing`): `rand` and
// `rand_distr` for a domain's randomness (a `rand_distr` of another version does not
// accept the `RngCore` the runner hands over), `rand_chacha` for the portable generator
// the project seeds everything with (`ChaCha8Rng`: the same draws on every platform, for
// a plug-in's own families, priors and tests), `serde` and `ron` for its files (derive
// with `#[serde(crate = "trustcbr::serde")]`), `service` to serve it by hand.
pub use cbr_core;
#[cfg(feature = "console")]
pub use console;
pub use files;
pub use lab;
pub use rand;
pub use rand_chacha;
pub use rand_distr;
pub use ron;
pub use serde;
pub use service;
pub use trust;
