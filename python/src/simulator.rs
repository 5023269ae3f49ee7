//! The simulator: one command of a catalog's domain run with a behavior, an operator (a
//! built-in name or a file, as `trustcbr landscape --operator` takes it) and a seed; and
//! operator landscapes, estimated as `trustcbr landscape` does (its limit on runs, its
//! progress, stopped by Ctrl-C).

use crate::calls::{Counts, Watch, run_watched};
use crate::convert::{behavior_from_py, to_py};
use crate::error;
use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use serde_json::json;
use trustcbr::Readings;
use trustcbr::catalog::{Catalog, domain_of, find_operator, resolve_readings};
use trustcbr::lab::reference::landscape as estimates;
use trustcbr::lab::{Domain, LandscapeError, Simulation};
use trustcbr::limits::RUNS_PER_BEHAVIOR;
use trustcbr::simulate::command_json;
use trustcbr::trust::named::named_space;

/// The readings every call here uses: the catalog's defaults.
fn default_readings<C: Catalog>(catalog: &C) -> PyResult<Readings> {
    resolve_readings(catalog, &Default::default()).map_err(error)
}

/// The built-in operators of `scenario`.
pub fn operators<C: Catalog>(catalog: &C, scenario: &str) -> PyResult<Vec<String>> {
    domain_of(catalog, scenario).map_err(error)?;
    let readings = default_readings(catalog)?;
    Ok(catalog
        .operators(scenario, &readings)
        .into_iter()
        .map(|(name, _)| name)
        .collect())
}

/// The behavior space of a scenario (every component with its values in real units), its
/// declared causes and observations, as a dict.
pub fn space<'py, C: Catalog>(
    py: Python<'py>,
    catalog: &C,
    scenario: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let domain = domain_of(catalog, scenario).map_err(error)?;
    let value = json!({
        "scenario": scenario,
        "components": named_space(domain.space()),
        "behaviors": domain.space().size(),
        "causes": domain.causes(),
        "observations": domain.observations(),
    });
    to_py(py, &value)
}

/// Runs one command of `scenario` with `behavior` (a dict in real units) in front of
/// `operator` (a built-in name or an operator file), every draw from `seed`: the first
/// command of `trustcbr simulate --seed SEED`. Returns the outcome as the protocol's
/// outcome report spells it (with the reason the operator's feedback channel states, if
/// any) and the operator's true reason as `truth`, which a robot is never told.
pub fn simulate<'py, C: Catalog>(
    py: Python<'py>,
    catalog: &C,
    scenario: &str,
    behavior: &Bound<'py, PyAny>,
    operator: &str,
    seed: u64,
) -> PyResult<Bound<'py, PyAny>> {
    let domain = domain_of(catalog, scenario).map_err(error)?;
    let readings = default_readings(catalog)?;
    let (_, operator) = find_operator(catalog, scenario, operator, &readings).map_err(error)?;
    let behavior = behavior_from_py(domain.space(), behavior)?;
    let command = Simulation::new(&domain, behavior, &operator, 1.0, seed)
        .map_err(error)?
        .next()
        .expect("a simulation never ends")
        .map_err(error)?;
    to_py(py, &command_json(&domain, &command))
}

/// Estimates, for every behavior of `scenario`, the share of `runs` commands `operator`
/// lets complete (`trustcbr landscape`'s estimate, with every component fixed, and its
/// limit on runs), reporting progress to `progress(done, total, elapsed_s, then)`.
/// Returns the shares in the space's rank order (the last component fastest), the number
/// of values of each component and the components' names.
pub fn landscape<C: Catalog>(
    py: Python<'_>,
    catalog: &C,
    scenario: &str,
    operator: &str,
    runs: u64,
    seed: u64,
    progress: Option<Py<PyAny>>,
) -> PyResult<(Vec<f64>, Vec<usize>, Vec<String>)> {
    RUNS_PER_BEHAVIOR.check("runs", runs).map_err(error)?;
    let runs = u32::try_from(runs).expect("checked to fit");
    let domain = domain_of(catalog, scenario).map_err(error)?;
    let readings = default_readings(catalog)?;
    let (_, operator) = find_operator(catalog, scenario, operator, &readings).map_err(error)?;
    let every: Vec<usize> = (0..domain.space().components().len()).collect();
    let watch = Watch {
        callback: progress,
        counts: Counts::of(domain.space().size()),
    };
    let counts = watch.counts.clone();
    let estimate = run_watched(py, &watch, |_| {
        estimates::estimate(&domain, &[&operator], &every, runs, seed, &|| counts.tick())
    })?
    .map_err(|e| match e {
        LandscapeError::Interrupted(_) => {
            PyKeyboardInterrupt::new_err("stopped: the landscape was not finished")
        }
        e => error(e),
    })?;
    let shares = estimate.cells.iter().map(|t| t.p_complete()).collect();
    let names = domain
        .space()
        .components()
        .iter()
        .map(|c| c.name.clone())
        .collect();
    Ok((shares, estimate.lengths, names))
}
