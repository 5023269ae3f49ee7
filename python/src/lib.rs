//! `trustcbr._native`: the Rust side of the Python package `trustcbr`.
//!
//! A thin layer over the tool's own code paths: the ask/tell [`adapter`] is `serve`'s
//! [`trustcbr::service::Session`], the [`simulator`] runs a catalog's domain, and the
//! [`experiments`] run a suite through [`trustcbr::run::run_with_report`], with arms
//! written in Python ([`arms`]) entering the runner through [`trustcbr::WithArms`], the
//! door a plug-in's arms use. Data crosses as JSON text or plain Python values; the pure
//! Python package (`trustcbr/__init__.py`) gives it its shape. Every error is a
//! `trustcbr.TrustcbrError` carrying the message the command-line tool prints.

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

pub mod adapter;
pub mod arms;
pub mod convert;
pub mod experiments;
pub mod simulator;

create_exception!(
    trustcbr,
    TrustcbrError,
    PyException,
    "An error of trustcbr, with the message the command-line tool gives for it."
);

/// A `TrustcbrError` from anything displayable: `{:#}` shows an error's whole chain, as the
/// command-line tool prints it.
pub fn error(e: impl std::fmt::Display) -> PyErr {
    TrustcbrError::new_err(format!("{e:#}"))
}

/// An `anyhow` error as the command-line tool prints it (the chain, colon-separated).
pub fn anyhow_error(e: &anyhow::Error) -> PyErr {
    TrustcbrError::new_err(format!("{e:#}"))
}

/// The extension module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("TrustcbrError", m.py().get_type::<TrustcbrError>())?;
    m.add_class::<adapter::Session>()?;
    m.add_function(wrap_pyfunction!(simulator::scenarios, m)?)?;
    m.add_function(wrap_pyfunction!(simulator::operators, m)?)?;
    m.add_function(wrap_pyfunction!(simulator::space, m)?)?;
    m.add_function(wrap_pyfunction!(simulator::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(simulator::landscape, m)?)?;
    m.add_function(wrap_pyfunction!(experiments::default_suite, m)?)?;
    m.add_function(wrap_pyfunction!(experiments::builtin_arms, m)?)?;
    m.add_function(wrap_pyfunction!(experiments::run_suite, m)?)?;
    m.add_function(wrap_pyfunction!(arms::check_searcher, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
