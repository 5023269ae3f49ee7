//! A request to stop, as a signal is: one per process, seen by every long computation of
//! this crate at its natural steps (a trial, a mission, a landscape cell), which then
//! returns [`Interrupted`] instead of going on.
//!
//! Nothing here catches a signal: a caller that does (the Python package, on Ctrl-C)
//! calls [`request`], and [`clear`]s the request before the next computation it starts.
//! The command-line tool leaves the default (Ctrl-C ends the process), so nothing
//! requests a stop there. Checking is one relaxed atomic load, so it costs nothing beside
//! a trial.

use std::sync::atomic::{AtomicBool, Ordering};

/// Whether a stop is requested.
static REQUESTED: AtomicBool = AtomicBool::new(false);

/// A computation stopped because a stop was requested ([`request`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("interrupted: a stop was requested (Ctrl-C) before the work was done")]
pub struct Interrupted;

/// Asks every computation under way to stop at its next step.
pub fn request() {
    REQUESTED.store(true, Ordering::Relaxed);
}

/// Withdraws the request, before a new computation starts.
pub fn clear() {
    REQUESTED.store(false, Ordering::Relaxed);
}

/// Whether a stop is requested.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}

/// `Err(Interrupted)` when a stop is requested.
pub fn check() -> Result<(), Interrupted> {
    if requested() {
        Err(Interrupted)
    } else {
        Ok(())
    }
}
