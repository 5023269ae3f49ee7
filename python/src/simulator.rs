//! The simulator: one command of a built-in domain run with a behavior, an operator (a
//! built-in name or a file, as `trustcbr landscape --operator` takes it) and a seed; and
//! operator landscapes, estimated as `trustcbr landscape` does.

use crate::convert::{behavior_from_py, to_py};
use crate::error;
use pyo3::prelude::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde_json::json;
use trustcbr::catalog::{Catalog, domain_of, find_operator, resolve_readings};
use trustcbr::lab::Domain;
use trustcbr::lab::landscape as estimates;
use trustcbr::service::reply;
use trustcbr::trust::named::named_space;
use trustcbr::{Readings, UgvCatalog};

/// The stream of a command's seed that draws the operator's stated reason (the run draws
/// from stream 0).
const FEEDBACK_STREAM: u64 = 1;

/// The readings every call here uses: the catalog's defaults.
fn default_readings(catalog: &UgvCatalog) -> PyResult<Readings> {
    resolve_readings(catalog, &Default::default()).map_err(error)
}

/// The built-in scenarios.
#[pyfunction]
pub fn scenarios() -> Vec<String> {
    UgvCatalog.scenarios()
}

/// The built-in operators of `scenario`.
#[pyfunction]
pub fn operators(scenario: &str) -> PyResult<Vec<String>> {
    let catalog = UgvCatalog;
    domain_of(&catalog, scenario).map_err(error)?;
    let readings = default_readings(&catalog)?;
    Ok(catalog
        .operators(scenario, &readings)
        .into_iter()
        .map(|(name, _)| name)
        .collect())
}

/// The behavior space of a built-in scenario (every component with its values in real
/// units), its declared causes and observations, as a dict.
#[pyfunction]
pub fn space<'py>(py: Python<'py>, scenario: &str) -> PyResult<Bound<'py, PyAny>> {
    let domain = domain_of(&UgvCatalog, scenario).map_err(error)?;
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
/// `operator` (a built-in name or an operator file), every draw from `seed`. Returns the
/// outcome as the protocol's outcome report spells it (with the reason the operator's
/// feedback channel states, if any) and the operator's true reason as `truth`, which a
/// robot is never told.
#[pyfunction]
#[pyo3(signature = (scenario, behavior, operator, seed = 0))]
pub fn simulate<'py>(
    py: Python<'py>,
    scenario: &str,
    behavior: &Bound<'py, PyAny>,
    operator: &str,
    seed: u64,
) -> PyResult<Bound<'py, PyAny>> {
    let catalog = UgvCatalog;
    let domain = domain_of(&catalog, scenario).map_err(error)?;
    let readings = default_readings(&catalog)?;
    let (_, operator) = find_operator(&catalog, scenario, operator, &readings).map_err(error)?;
    let behavior = behavior_from_py(domain.space(), behavior)?;
    let (judgement, stated) = py.detach(|| {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let judgement = domain.run(&behavior, &operator, &mut rng);
        let mut feedback = ChaCha8Rng::seed_from_u64(seed);
        feedback.set_stream(FEEDBACK_STREAM);
        let stated =
            domain
                .feedback(&operator)
                .state(judgement.truth, domain.causes(), &mut feedback);
        (judgement, stated)
    });
    let outcome = judgement.outcome.stating(stated);
    let mut value = reply::outcome(&outcome, domain.observations());
    value["truth"] = json!(judgement.truth);
    to_py(py, &value)
}

/// Estimates, for every behavior of `scenario`, the share of `runs` commands `operator`
/// lets complete (`trustcbr landscape`'s estimate, with every component fixed). Returns the
/// shares in the space's rank order (the last component fastest), the number of values of
/// each component and the components' names.
#[pyfunction]
#[pyo3(signature = (scenario, operator, runs = 100, seed = 0))]
pub fn landscape(
    py: Python<'_>,
    scenario: &str,
    operator: &str,
    runs: u32,
    seed: u64,
) -> PyResult<(Vec<f64>, Vec<usize>, Vec<String>)> {
    let catalog = UgvCatalog;
    let domain = domain_of(&catalog, scenario).map_err(error)?;
    let readings = default_readings(&catalog)?;
    let (_, operator) = find_operator(&catalog, scenario, operator, &readings).map_err(error)?;
    let every: Vec<usize> = (0..domain.space().components().len()).collect();
    let estimate = py
        .detach(|| estimates::estimate(&domain, &[&operator], &every, runs, seed, &|| {}))
        .map_err(error)?;
    let shares = estimate.cells.iter().map(|t| t.p_complete()).collect();
    let names = domain
        .space()
        .components()
        .iter()
        .map(|c| c.name.clone())
        .collect();
    Ok((shares, estimate.lengths, names))
}
