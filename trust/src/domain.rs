//! The plug-in contract between a task domain and the trust machinery.
//!
//! A domain has a behavior space, declares the causes of failure its outcomes may carry,
//! and can run one command with a behavior in front of an operator, returning the
//! command's [`Outcome`]. The experiment runner needs nothing else, so a new robot or task
//! plugs in by implementing this trait.

use crate::{DeclaredCause, Outcome};
use cbr_core::{Behavior, BehaviorSpace};
use rand::RngCore;
use std::sync::Arc;

/// A task domain: a behavior space and a way to run one command.
pub trait Domain: Send + Sync {
    /// The operator model that judges a run (e.g. preferences loaded from RON).
    type Operator: Send + Sync;

    /// The domain's name (e.g. `movement`).
    fn name(&self) -> &str;

    /// The behaviors the robot can adopt.
    fn space(&self) -> &Arc<BehaviorSpace>;

    /// The causes an outcome of [`Domain::run`] may carry (the experiment runner refuses
    /// any other, naming the domain, the cause and these).
    fn causes(&self) -> &[DeclaredCause];

    /// Runs one command with `behavior` under `operator`, drawing all randomness from
    /// `rng`, and returns how it ended.
    fn run(&self, behavior: &Behavior, operator: &Self::Operator, rng: &mut dyn RngCore)
    -> Outcome;
}
