//! `trustcbr._native`: the Rust side of the Python package `trustcbr`, and the library a
//! plug-in's own Python module is built from.
//!
//! A thin layer over the tool's own code paths, generic over the [`Catalog`] it serves:
//! the ask/tell [`adapter`] is `serve`'s [`trustcbr::service::Session`], the
//! [`simulator`] runs a catalog's domain, the [`experiments`] run a suite through
//! [`trustcbr::run`], arms written in Python ([`arms`]) enter the runner through
//! [`trustcbr::WithArms`] (the door a plug-in's arms use), the conformance kit checks them
//! ([`conformance`]), and the Gymnasium environment steps a domain natively ([`gym`]).
//! Long calls run beside a Python thread that executes the Python they need and stops
//! them on Ctrl-C ([`calls`]). Data crosses as JSON text or plain Python values; the pure
//! Python package (`trustcbr/__init__.py`) gives it its shape. Every error is a
//! `trustcbr.TrustcbrError` carrying the message the command-line tool prints.
//!
//! [`catalog_module!`] makes the extension module of any catalog: `trustcbr._native` is
//! `catalog_module!(_native, UgvCatalog)` plus the exception; a plug-in's crate makes its
//! own (`examples/warehouse/python`) and hands the module to the Python API's `catalog=`.

use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use trustcbr::lab::interrupt;

pub use pyo3;
pub use trustcbr;
pub use trustcbr::Catalog;

pub mod adapter;
pub mod arms;
pub mod calls;
pub mod conformance;
pub mod convert;
pub mod experiments;
pub mod gym;
pub mod simulator;

pyo3::import_exception!(trustcbr._errors, TrustcbrError);

/// A `TrustcbrError` from anything displayable: `{:#}` shows an error's whole chain, as the
/// command-line tool prints it.
pub fn error(e: impl std::fmt::Display) -> PyErr {
    TrustcbrError::new_err(format!("{e:#}"))
}

/// An `anyhow` error as the command-line tool prints it (the chain, colon-separated), or
/// `KeyboardInterrupt` when it is a stop that Ctrl-C requested.
pub fn anyhow_error(e: &anyhow::Error) -> PyErr {
    if interrupt::requested() {
        return PyKeyboardInterrupt::new_err("stopped: nothing was written");
    }
    TrustcbrError::new_err(format!("{e:#}"))
}

/// The extension module of a catalog: `catalog_module!(NAME, CATALOG)` defines the Python
/// module `NAME` (build it as a `cdylib` named `NAME`, e.g. with maturin) whose functions
/// serve the catalog value `CATALOG`, as `trustcbr._native` serves the UGV catalog. The
/// crate that invokes it depends on `pyo3` (the version this crate uses) and
/// `trustcbr-python`. Hand the module to the Python API: `trustcbr.run(...,
/// catalog=module)`, `trustcbr.Adapter(..., catalog=module)`.
#[macro_export]
macro_rules! catalog_module {
    ($name:ident, $catalog:expr) => {
        #[pyo3::pymodule]
        mod $name {
            use $crate::pyo3::prelude::*;

            #[pymodule_export]
            use $crate::adapter::Session;
            #[pymodule_export]
            use $crate::experiments::Report;
            #[pymodule_export]
            use $crate::gym::Episodes;

            #[pymodule_init]
            fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
                m.add("__version__", env!("CARGO_PKG_VERSION"))?;
                m.add("tool", $crate::trustcbr::Catalog::tool(&$catalog).name)?;
                m.add("RECOMMENDED_ARM", $crate::trustcbr::lab::RECOMMENDED_ARM)?;
                Ok(())
            }

            #[pyfunction]
            fn scenarios() -> Vec<String> {
                $crate::trustcbr::Catalog::scenarios(&$catalog)
            }

            #[pyfunction]
            fn operators(scenario: &str) -> PyResult<Vec<String>> {
                $crate::simulator::operators(&$catalog, scenario)
            }

            #[pyfunction]
            fn space<'py>(py: Python<'py>, scenario: &str) -> PyResult<Bound<'py, PyAny>> {
                $crate::simulator::space(py, &$catalog, scenario)
            }

            #[pyfunction]
            fn simulate<'py>(
                py: Python<'py>,
                scenario: &str,
                behavior: &Bound<'py, PyAny>,
                operator: &str,
                seed: u64,
            ) -> PyResult<Bound<'py, PyAny>> {
                $crate::simulator::simulate(py, &$catalog, scenario, behavior, operator, seed)
            }

            #[pyfunction]
            fn landscape(
                py: Python<'_>,
                scenario: &str,
                operator: &str,
                runs: u64,
                seed: u64,
                progress: Option<Py<PyAny>>,
            ) -> PyResult<(Vec<f64>, Vec<usize>, Vec<String>)> {
                $crate::simulator::landscape(
                    py, &$catalog, scenario, operator, runs, seed, progress,
                )
            }

            #[pyfunction]
            fn default_suite() -> String {
                $crate::trustcbr::Catalog::default_suite(&$catalog).to_owned()
            }

            #[pyfunction]
            fn strategies() -> Vec<$crate::experiments::StrategyRow> {
                $crate::experiments::strategies()
            }

            #[pyfunction]
            fn builtin_arms() -> Vec<String> {
                $crate::experiments::builtin_arms(&$catalog)
            }

            #[pyfunction]
            fn run_suite(
                py: Python<'_>,
                request: $crate::experiments::RunRequest,
            ) -> PyResult<$crate::experiments::RunOutput> {
                $crate::experiments::run_suite(py, &$catalog, request)
            }

            #[pyfunction]
            fn read_config(kind: &str, text: &str, origin: &str) -> PyResult<String> {
                $crate::experiments::read_config(&$catalog, kind, text, origin)
            }

            #[pyfunction]
            fn explain(
                report: &str,
                experiment: &str,
                arm: &str,
                trial: u32,
                cases: Option<&str>,
                python_arms: Vec<(String, Py<PyAny>, bool)>,
            ) -> PyResult<(String, String, Vec<String>)> {
                $crate::experiments::explain(
                    &$catalog,
                    report,
                    experiment,
                    arm,
                    trial,
                    cases,
                    python_arms,
                )
            }

            #[pyfunction]
            fn check_searcher<'py>(
                py: Python<'py>,
                factory: Py<PyAny>,
                scenario: Option<&str>,
            ) -> PyResult<Option<Bound<'py, PyAny>>> {
                $crate::conformance::check_searcher(py, &$catalog, factory, scenario)
            }

            #[pyfunction]
            #[allow(clippy::too_many_arguments)]
            fn session(
                domain: &str,
                cases: &str,
                seed: u64,
                arm: Option<&str>,
                strategy: Option<(String, Py<PyAny>, bool)>,
                mission: bool,
                competence: Option<f64>,
                detect_changes: bool,
            ) -> PyResult<Session> {
                let mode = $crate::adapter::MissionMode {
                    mission,
                    competence,
                    detect_changes,
                };
                Session::open(&$catalog, domain, cases, seed, arm, strategy, mode)
            }

            #[pyfunction]
            fn rasterize<'py>(
                py: Python<'py>,
                svg: &str,
            ) -> PyResult<(u32, u32, Bound<'py, pyo3::types::PyBytes>)> {
                $crate::gym::rasterize(py, svg)
            }

            #[pyfunction]
            fn episodes(
                scenario: &str,
                operators: Vec<String>,
                max_commands: u32,
                attention: f64,
            ) -> PyResult<Episodes> {
                Episodes::new(&$catalog, scenario, operators, max_commands, attention)
            }
        }
    };
}

catalog_module!(_native, trustcbr::UgvCatalog);
