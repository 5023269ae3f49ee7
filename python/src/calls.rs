//! Python called from the runner's threads, and a run that Ctrl-C stops.
//!
//! A long call ([`run_watched`]: a suite, a landscape) runs its Rust work on a thread of
//! its own while the Python thread that made the call waits for requests: every call into
//! Python the work needs (a Python arm's method) is sent to that thread and executed there,
//! as if the arm ran in the caller's own loop. So a Python arm that sleeps or loops is
//! interrupted by Ctrl-C the way any Python code is, and between requests, at least every
//! [`WATCH_EVERY`], the waiting thread looks for a pending signal (Ctrl-C) and reports
//! progress. A `KeyboardInterrupt`, from either, asks the work to stop
//! ([`trustcbr::lab::interrupt`]), which it does at its next trial, mission or landscape
//! cell; the call then raises the `KeyboardInterrupt` and writes nothing.
//!
//! Calls made outside such a run (the adapter's strategy, the conformance kit) are made on
//! the current thread ([`Caller::Here`]).

use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError, Sender};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use trustcbr::lab::interrupt;

/// How often the waiting thread looks for Ctrl-C and reports progress.
pub const WATCH_EVERY: Duration = Duration::from_millis(100);

/// A call into Python, run on the thread that waits.
type Job = Box<dyn FnOnce(Python<'_>) + Send>;

/// Where a call into Python runs.
#[derive(Clone)]
pub enum Caller {
    /// On the current thread, attached to the interpreter.
    Here,
    /// On the Python thread that waits for a run ([`run_watched`]).
    Waiting(Sender<Option<Job>>),
}

impl Caller {
    /// Runs `call` with the interpreter, where this caller says, and returns its result. A
    /// `KeyboardInterrupt` it raises asks the run under way to stop.
    pub fn call<T: Send + 'static>(
        &self,
        call: impl FnOnce(Python<'_>) -> PyResult<T> + Send + 'static,
    ) -> PyResult<T> {
        let watched = |py: Python<'_>| {
            let result = call(py);
            if let Err(e) = &result
                && e.is_instance_of::<PyKeyboardInterrupt>(py)
            {
                interrupt::request();
            }
            result
        };
        match self {
            Caller::Here => Python::attach(watched),
            Caller::Waiting(jobs) => {
                let (reply, answer) = mpsc::channel();
                let job: Job = Box::new(move |py| {
                    let _ = reply.send(watched(py));
                });
                if jobs.send(Some(job)).is_err() {
                    return Err(crate::error("the Python thread of this run has gone"));
                }
                answer
                    .recv()
                    .unwrap_or_else(|_| Err(crate::error("the Python thread of this run has gone")))
            }
        }
    }
}

/// How far a run has got, as its work reports it (from any thread) and its progress
/// callback reads it.
#[derive(Default)]
pub struct Counts {
    /// Units done.
    pub done: AtomicU64,
    /// Units in all.
    pub total: AtomicU64,
    /// What is under way once every unit is done (e.g. the report's estimates).
    pub then: Mutex<Option<&'static str>>,
}

impl Counts {
    /// Counts of `total` units, none done.
    pub fn of(total: u64) -> Arc<Self> {
        let counts = Self::default();
        counts.total.store(total, Ordering::Relaxed);
        Arc::new(counts)
    }

    /// One more unit done.
    pub fn tick(&self) {
        self.done.fetch_add(1, Ordering::Relaxed);
    }
}

/// A progress callback and what it reports: `callback(done, total, elapsed_s, then)`.
pub struct Watch {
    /// The callback, if any.
    pub callback: Option<Py<PyAny>>,
    /// The counts it reads.
    pub counts: Arc<Counts>,
}

impl Watch {
    /// Calls the callback with the counts now (and `elapsed`).
    fn report(&self, py: Python<'_>, elapsed: Duration) -> PyResult<()> {
        let Some(callback) = &self.callback else {
            return Ok(());
        };
        let then = *self.counts.then.lock().unwrap_or_else(|p| p.into_inner());
        callback.call1(
            py,
            (
                self.counts.done.load(Ordering::Relaxed),
                self.counts.total.load(Ordering::Relaxed),
                elapsed.as_secs_f64(),
                then,
            ),
        )?;
        Ok(())
    }
}

/// Runs `work` on a thread of its own while this Python thread executes the calls into
/// Python it sends ([`Caller::Waiting`]), looks for Ctrl-C and reports `watch`'s progress
/// (once at the start, at least every [`WATCH_EVERY`], once at the end). Returns the
/// work's result, or the `KeyboardInterrupt` (or the progress callback's exception) that
/// stopped it; the work is asked to stop and is waited for, so nothing runs on after the
/// call returns.
pub fn run_watched<T: Send>(
    py: Python<'_>,
    watch: &Watch,
    work: impl FnOnce(Caller) -> T + Send,
) -> PyResult<T> {
    interrupt::clear();
    let started = Instant::now();
    let (sender, jobs) = mpsc::channel::<Option<Job>>();
    let mut stopped: Option<PyErr> = None;
    let stop = |e: PyErr, stopped: &mut Option<PyErr>| {
        interrupt::request();
        stopped.get_or_insert(e);
    };
    watch.report(py, Duration::ZERO)?;
    let result = std::thread::scope(|scope| {
        let done = sender.clone();
        let worker = scope.spawn(move || {
            let result = work(Caller::Waiting(sender));
            let _ = done.send(None);
            result
        });
        let mut jobs = Some(jobs);
        let mut watched = Instant::now();
        loop {
            let receiver = jobs
                .take()
                .expect("the receiver is put back after each wait");
            let (next, receiver) =
                py.detach(move || (receiver.recv_timeout(WATCH_EVERY), receiver));
            jobs = Some(receiver);
            match next {
                Ok(Some(job)) => job(py),
                Ok(None) | Err(RecvTimeoutError::Disconnected) => break,
                Err(RecvTimeoutError::Timeout) => {}
            }
            if watched.elapsed() >= WATCH_EVERY {
                watched = Instant::now();
                if let Err(e) = py.check_signals() {
                    stop(e, &mut stopped);
                }
                if stopped.is_none()
                    && let Err(e) = watch.report(py, started.elapsed())
                {
                    stop(e, &mut stopped);
                }
            }
        }
        match worker.join() {
            Ok(result) => result,
            Err(panic) => std::panic::resume_unwind(panic),
        }
    });
    if let Some(e) = stopped {
        return Err(e);
    }
    watch.report(py, started.elapsed())?;
    Ok(result)
}
