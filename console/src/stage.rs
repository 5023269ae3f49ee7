//! What a domain gives the console so a person can watch its robot: the world to draw,
//! one run of a behavior as it unfolds, and the outcome report of that run when the person
//! stopped it at a given moment (or let it end).
//!
//! A domain enters the console through [`Stage`] alone, as it enters `serve` through its
//! definition: the tool's catalog answers with a stage for each scenario it can show.

use cbr_core::Behavior;
use serde_json::Value;

/// One run of a behavior, as the page plays it and the console closes it.
#[derive(Clone, Debug, PartialEq)]
pub struct ShownRun {
    /// What the page draws (docs/studies.md, "The page's API": `duration_s`, `ends`,
    /// `path`, `present`, `objects`, `events`).
    pub picture: Value,
    /// When the run ends by itself (s of the robot's time).
    pub duration_s: f64,
}

/// How a run ended for the outcome report: stopped by the person at `at_s`, or by itself.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ending {
    /// The person stopped the robot at this moment of the run (s).
    Stopped(f64),
    /// Nobody stopped it: it ran until it arrived or failed on its own.
    RanOut,
}

/// A domain whose runs a person can watch and stop.
pub trait Stage: Send + Sync {
    /// The world the runs happen in, drawn once by the page (docs/studies.md, "The
    /// page's API": `size`, `roads`, `obstacles`, `people`, `route`, `robot_radius`).
    fn scene(&self) -> Value;

    /// The run of `behavior` drawn from `seed`: the same seed gives the same run.
    fn show(&self, behavior: &Behavior, seed: u64) -> ShownRun;

    /// The outcome report a controller would send `serve` for the run of `behavior`
    /// drawn from `seed`, ended as `ending` says, with the reason the person `stated`:
    /// `outcome`, `weight`, `duration_s` and what the robot perceived until then
    /// (`observed`), in the protocol's words (docs/protocol.md, "Outcome report").
    fn outcome(
        &self,
        behavior: &Behavior,
        seed: u64,
        ending: Ending,
        stated: Option<&str>,
    ) -> Value;

    /// The words the page uses for `cause` when it asks why the robot was stopped
    /// (default: the cause's name).
    fn cause_text(&self, cause: &str) -> String {
        cause.to_owned()
    }
}
