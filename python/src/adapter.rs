//! The ask/tell adapter: `serve`'s [`Session`] over the same domain names, case stores and
//! arms as `trustcbr serve --domain D --cases C [--arm A] [--seed N] [--mission]`, driven
//! one request at a time. A request is a protocol line (`docs/protocol.md`) and its reply a JSON object;
//! an error reply becomes a `TrustcbrError` with the reply's message, and leaves the
//! episode, the case base and the random stream unchanged, as in the protocol.

use crate::{anyhow_error, error};
use pyo3::prelude::*;
use std::sync::Arc;
use trustcbr::UgvCatalog;
use trustcbr::served::{served_domain, serving_arm};
use trustcbr::service::{Location, Session as ServedSession, SharedCases};

/// One controller's adapter over a case base (`trustcbr serve` for one controller).
#[pyclass(module = "trustcbr._native", unsendable)]
pub struct Session {
    session: ServedSession,
    location: String,
    writable: bool,
}

#[pymethods]
impl Session {
    /// Opens the case base `cases` (an SQLite file, created when absent; a `postgres://`
    /// URL; or a read-only `.ron` file) for `domain` (a built-in scenario or a RON domain
    /// file), searching as the domain's config says or as the arm `arm` does; with
    /// `mission`, outcomes keep coming after an episode settles (`serve --mission`).
    #[new]
    #[pyo3(signature = (domain, cases, seed = 0, arm = None, mission = false))]
    fn new(
        domain: &str,
        cases: &str,
        seed: u64,
        arm: Option<&str>,
        mission: bool,
    ) -> PyResult<Self> {
        let catalog = UgvCatalog;
        let mut definition = served_domain(&catalog, domain).map_err(error)?;
        if let Some(name) = arm {
            definition = serving_arm(&catalog, definition, name).map_err(|e| anyhow_error(&e))?;
        }
        if mission {
            definition = definition.in_mission_mode();
        }
        let shared = SharedCases::open(&definition, &Location::parse(cases)).map_err(error)?;
        let (location, writable) = (shared.location().to_owned(), shared.writable());
        let session = ServedSession::new(definition, Arc::new(shared), seed).map_err(error)?;
        Ok(Self {
            session,
            location,
            writable,
        })
    }

    /// Handles one protocol request (a JSON object as text) and returns the reply's JSON
    /// text; an error reply raises `TrustcbrError` with its message.
    fn request(&mut self, line: &str) -> PyResult<String> {
        let reply = self.session.handle_line(line.as_bytes()).map_err(error)?;
        let value = reply.into_value();
        if let Some(message) = value.get("error").and_then(|m| m.as_str()) {
            return Err(error(message));
        }
        Ok(value.to_string())
    }

    /// Where the cases are kept, as the server shows it.
    #[getter]
    fn location(&self) -> &str {
        &self.location
    }

    /// Whether retained cases are stored (a `.ron` case file is read-only).
    #[getter]
    fn writable(&self) -> bool {
        self.writable
    }
}
