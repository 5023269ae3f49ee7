//! The ask/tell adapter: `serve`'s [`Session`](ServedSession) over the same domain names,
//! case stores and arms as `trustcbr serve --domain D --cases C [--arm A] [--seed N]
//! [--mission]`, driven one request at a time, or serving a strategy written in Python
//! (the factory `trustcbr.run` takes). A request is a protocol line (`docs/protocol.md`)
//! and its reply a JSON object; an error reply becomes a `TrustcbrError` with the reply's
//! message, and leaves the episode, the case base and the random stream unchanged, as in
//! the protocol.
//!
//! An adapter belongs to the thread that made it: a call from another thread raises
//! `TrustcbrError` saying so, and the adapter may be dropped on any thread.

use crate::arms::{FirstError, PythonArmSpec, python_arm};
use crate::calls::Caller;
use crate::{anyhow_error, error};
use pyo3::prelude::*;
use std::sync::{Arc, Mutex};
use std::thread::{self, ThreadId};
use trustcbr::Catalog;
use trustcbr::WithArms;
use trustcbr::served::{
    Spelling, check_preference, judging_competence, served_domain, serving_arm,
};
use trustcbr::service::{Location, Session as ServedSession, SharedCases};

/// One controller's adapter over a case base (`trustcbr serve` for one controller).
#[pyclass(module = "trustcbr._native")]
pub struct Session {
    session: Mutex<ServedSession>,
    owner: ThreadId,
    location: String,
    writable: bool,
    /// The first exception of a Python strategy, raised by the request it happened in.
    errors: FirstError,
}

/// Whether a session runs a mission (`serve --mission`) and, on one, the standard its
/// robot holds its own competence to (`serve --competence`).
#[derive(Clone, Copy, Debug, Default)]
pub struct MissionMode {
    /// Outcomes keep coming after an episode settles.
    pub mission: bool,
    /// The most each part of the robot's competence may fall short per command.
    pub competence: Option<f64>,
    /// A change detector beside the thresholds (`serve --detect-changes`).
    pub detect_changes: bool,
}

impl Session {
    /// Opens the case base `cases` (an SQLite file, created when absent; a `postgres://`
    /// URL; or a read-only `.ron` file) for `domain` (a scenario of `catalog` or a RON
    /// domain file), searching as the domain's config says, as the arm `arm` does, or as
    /// the Python `strategy` (`(name, factory, reuses_cases)`) does; in mission `mode`,
    /// outcomes keep coming after an episode settles (`serve --mission`), and with a
    /// competence standard the robot judges its own competence (`serve --competence`).
    pub fn open<C: Catalog + Clone>(
        catalog: &C,
        domain: &str,
        cases: &str,
        seed: u64,
        arm: Option<&str>,
        strategy: Option<(String, Py<PyAny>, bool)>,
        mode: MissionMode,
    ) -> PyResult<Self> {
        let mut definition = served_domain(catalog, domain).map_err(error)?;
        let errors = FirstError::default();
        match (arm, strategy) {
            (Some(_), Some(_)) => {
                return Err(error("serve a built-in arm or a Python strategy, not both"));
            }
            (Some(name), None) => {
                definition = serving_arm(catalog, definition, name, Spelling::Python)
                    .map_err(|e| anyhow_error(&e))?;
            }
            (None, Some((name, factory, reuses))) => {
                let served = name.clone();
                let observations = Arc::new(vec![(
                    definition.space.clone(),
                    definition.observations.clone(),
                )]);
                let spec = PythonArmSpec {
                    name,
                    factory: Arc::new(factory),
                    reuses_cases: reuses,
                    label: Arc::from("strategy"),
                };
                let (caller, kept) = (Caller::Here, errors.clone());
                let with = WithArms {
                    inner: catalog.clone(),
                    arms: vec![Arc::new(move |retriever| {
                        python_arm(
                            &spec,
                            observations.clone(),
                            retriever,
                            kept.clone(),
                            caller.clone(),
                        )
                    })],
                };
                definition = serving_arm(&with, definition, &served, Spelling::Python)
                    .map_err(|e| anyhow_error(&e))?;
            }
            (None, None) => {
                definition = serving_arm(
                    catalog,
                    definition,
                    trustcbr::lab::RECOMMENDED_ARM,
                    Spelling::Python,
                )
                .map_err(|e| anyhow_error(&e))?;
            }
        }
        if mode.mission {
            definition = definition.in_mission_mode();
        }
        if mode.detect_changes {
            if !mode.mission {
                return Err(error(
                    "detect_changes: a change detector watches a settled behavior in mission mode: pass mission=True",
                ));
            }
            definition = definition.detecting_changes(trustcbr::trust::ChangeDetector::default());
        }
        if let Some(at_most) = mode.competence {
            if !mode.mission {
                return Err(error(
                    "competence: the robot judges its own competence in mission mode: pass mission=True",
                ));
            }
            definition = judging_competence(catalog, definition, at_most, Spelling::Python)
                .map_err(|e| anyhow_error(&e))?;
        }
        check_preference(&definition, Spelling::Python).map_err(|e| anyhow_error(&e))?;
        let shared = SharedCases::open(&definition, &Location::parse(cases)).map_err(error)?;
        let (location, writable) = (shared.location().to_owned(), shared.writable());
        let session = ServedSession::new(definition, Arc::new(shared), seed).map_err(error)?;
        if let Some(e) = errors.take() {
            return Err(e);
        }
        Ok(Self {
            session: Mutex::new(session),
            owner: thread::current().id(),
            location,
            writable,
            errors,
        })
    }

    /// Refuses a call from a thread other than the one that made the adapter.
    fn on_its_thread(&self) -> PyResult<()> {
        if thread::current().id() == self.owner {
            Ok(())
        } else {
            Err(error(
                "this Adapter belongs to the thread that made it and was used from another: make one adapter per thread (they may share a SQLite or PostgreSQL case base)",
            ))
        }
    }
}

#[pymethods]
impl Session {
    /// Handles one protocol request (a JSON object as text) and returns the reply's JSON
    /// text; an error reply raises `TrustcbrError` with its message, and an exception of
    /// a Python strategy is raised as it is.
    fn request(&self, line: &str) -> PyResult<String> {
        self.on_its_thread()?;
        let mut session = self.session.lock().unwrap_or_else(|p| p.into_inner());
        let reply = session.handle_line(line.as_bytes()).map_err(error)?;
        if let Some(e) = self.errors.take() {
            return Err(e);
        }
        let value = reply.into_value();
        if let Some(message) = value.get("error").and_then(|m| m.as_str()) {
            return Err(error(message));
        }
        Ok(value.to_string())
    }

    /// Where the cases are kept, as the server shows it.
    #[getter]
    fn location(&self) -> PyResult<&str> {
        self.on_its_thread()?;
        Ok(&self.location)
    }

    /// Whether retained cases are stored (a `.ron` case file is read-only).
    #[getter]
    fn writable(&self) -> PyResult<bool> {
        self.on_its_thread()?;
        Ok(self.writable)
    }
}
