//! The Gymnasium environment's inner loop, natively: an episode is one operator of a
//! catalog's scenario; a step runs one behavior's commands in front of it through the
//! laboratory's simulated command ([`Simulation`]: the operator's attention and its
//! feedback channel apply, as in every experiment and mission), each recorded in the
//! library's trust estimate ([`TrustEstimate`], the paper's thresholds), until the estimate
//! reaches a threshold or `max_commands` pass. The
//! Python `trustcbr.gym.TrustEnv` checks actions, builds observations and owns the
//! episode's bookkeeping; this is what makes a step cost microseconds.
//!
//! An environment belongs to the thread that made it, as an adapter does.

use crate::error;
use pyo3::prelude::*;
use rand::{RngCore, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::Mutex;
use std::thread::{self, ThreadId};
use trustcbr::Catalog;
use trustcbr::catalog::{OperatorOf, domain_of, find_operator, resolve_readings};
use trustcbr::cbr_core::Behavior;
use trustcbr::lab::{Domain, SimulatedCommand, Simulation, check_attention};
use trustcbr::trust::{OutcomeKind, Thresholds, TrustEstimate, Verdict};

/// What one step did: the commands in each outcome kind (completed, failed,
/// interrupted), how many perceived each declared observation, how many the operator
/// stated a reason for, the estimate at the end, and how the behavior ended (`trusted`,
/// `given-up` or `undecided`).
#[derive(IntoPyObject)]
pub struct StepResult {
    kinds: [u32; 3],
    observed: Vec<u32>,
    stated: u32,
    trust: f64,
    end: &'static str,
}

/// Episodes of one scenario, whatever its domain type.
trait Stepper: Send {
    /// Starts an episode with the operator `name`, drawing every run from `seed`.
    fn reset(&mut self, name: &str, seed: u64) -> PyResult<()>;
    /// Runs the behavior of value indices `action` until a verdict or `max_commands`.
    fn step(&mut self, action: &[u16]) -> PyResult<StepResult>;
    /// One run of the behavior `action` under the episode's operator, drawn as SVG (when
    /// the catalog draws its scenario's runs).
    fn render(&self, action: &[u16], seed: u64) -> Option<String>;
}

struct DomainEpisodes<C: Catalog> {
    catalog: C,
    scenario: String,
    domain: C::Domain,
    operators: Vec<(String, OperatorOf<C>)>,
    operator: Option<usize>,
    rng: ChaCha8Rng,
    max_commands: u32,
    /// The operators' attention, in `[0, 1]` (1: the paper's attentive operator).
    attention: f64,
    thresholds: Thresholds,
}

impl<C: Catalog + Send> Stepper for DomainEpisodes<C>
where
    C::Domain: Send,
{
    fn reset(&mut self, name: &str, seed: u64) -> PyResult<()> {
        let index = match self.operators.iter().position(|(n, _)| n == name) {
            Some(i) => i,
            None => {
                let readings =
                    resolve_readings(&self.catalog, &Default::default()).map_err(error)?;
                let found =
                    find_operator(&self.catalog, &self.scenario, name, &readings).map_err(error)?;
                self.operators.push(found);
                self.operators.len() - 1
            }
        };
        self.operator = Some(index);
        self.rng = ChaCha8Rng::seed_from_u64(seed);
        Ok(())
    }

    fn step(&mut self, action: &[u16]) -> PyResult<StepResult> {
        let operator = match self.operator {
            Some(i) => &self.operators[i].1,
            None => return Err(error("call reset() before step()")),
        };
        let behavior = Behavior::new(action);
        // Each step's commands come from a stream of their own, drawn from the episode's.
        let seed = self.rng.next_u64();
        let simulation = Simulation::new(&self.domain, behavior, operator, self.attention, seed)
            .map_err(error)?;
        let mut estimate = TrustEstimate::default();
        let mut kinds = [0u32; 3];
        let mut observed = vec![0u32; self.domain.observations().len()];
        let mut stated = 0;
        let mut end = "undecided";
        for command in simulation.take(self.max_commands as usize) {
            let SimulatedCommand { outcome, .. } = command.map_err(error)?;
            kinds[match outcome.kind {
                OutcomeKind::Completed => 0,
                OutcomeKind::Failed => 1,
                OutcomeKind::Interrupted => 2,
            }] += 1;
            for i in outcome.observed.indices() {
                if let Some(count) = observed.get_mut(i) {
                    *count += 1;
                }
            }
            stated += u32::from(outcome.stated.is_some());
            estimate.record(&outcome);
            match estimate.verdict(&self.thresholds) {
                Verdict::Trustworthy => {
                    end = "trusted";
                    break;
                }
                Verdict::Untrustworthy => {
                    end = "given-up";
                    break;
                }
                Verdict::Undecided => {}
            }
        }
        Ok(StepResult {
            kinds,
            observed,
            stated,
            trust: estimate.value,
            end,
        })
    }

    fn render(&self, action: &[u16], seed: u64) -> Option<String> {
        let operator = &self.operators[self.operator?].1;
        self.catalog
            .render(&self.domain, &Behavior::new(action), operator, seed)
    }
}

/// A scenario's episodes, stepped natively (`trustcbr.gym.TrustEnv`'s inner loop).
#[pyclass(module = "trustcbr._native")]
pub struct Episodes {
    stepper: Mutex<Box<dyn Stepper>>,
    owner: ThreadId,
}

impl Episodes {
    /// Episodes of `scenario` of `catalog` among `operators` (built-in names or operator
    /// files, each loaded now so an unknown one is refused here), each behavior given at
    /// most `max_commands` commands, the operators at `attention` (in `[0, 1]`; below 1
    /// only on a domain that models attention, refused here otherwise).
    pub fn new<C: Catalog + Clone + Send + 'static>(
        catalog: &C,
        scenario: &str,
        operators: Vec<String>,
        max_commands: u32,
        attention: f64,
    ) -> PyResult<Self>
    where
        C::Domain: Send + 'static,
    {
        let domain = domain_of(catalog, scenario).map_err(error)?;
        let readings = resolve_readings(catalog, &Default::default()).map_err(error)?;
        let operators = operators
            .iter()
            .map(|name| find_operator(catalog, scenario, name, &readings).map_err(error))
            .collect::<PyResult<Vec<_>>>()?;
        if !(0.0..=1.0).contains(&attention) {
            return Err(error(format!(
                "attention: a share from 0 to 1 (1: the paper's attentive operator), got {attention}"
            )));
        }
        if attention < 1.0 {
            check_attention(&domain).map_err(|reason| error(format!("attention: {reason}")))?;
        }
        let stepper = DomainEpisodes {
            catalog: catalog.clone(),
            scenario: scenario.to_owned(),
            domain,
            operators,
            operator: None,
            rng: ChaCha8Rng::seed_from_u64(0),
            max_commands,
            attention,
            thresholds: Thresholds::default(),
        };
        Ok(Self {
            stepper: Mutex::new(Box::new(stepper)),
            owner: thread::current().id(),
        })
    }

    fn stepper(&self) -> PyResult<std::sync::MutexGuard<'_, Box<dyn Stepper>>> {
        if thread::current().id() != self.owner {
            return Err(error(
                "this environment belongs to the thread that made it and was used from another: make one environment per thread",
            ));
        }
        Ok(self.stepper.lock().unwrap_or_else(|p| p.into_inner()))
    }
}

#[pymethods]
impl Episodes {
    /// Starts an episode with the operator `name` (one of the environment's, or any
    /// built-in name or operator file), every run drawn from `seed`.
    fn reset(&self, name: &str, seed: u64) -> PyResult<()> {
        self.stepper()?.reset(name, seed)
    }

    /// Runs the behavior of value indices `action` (checked by the caller).
    fn step(&self, action: Vec<u16>) -> PyResult<StepResult> {
        self.stepper()?.step(&action)
    }

    /// One run of the behavior `action` drawn as SVG, or `None` when the catalog draws
    /// no pictures of the scenario's runs.
    fn render(&self, action: Vec<u16>, seed: u64) -> PyResult<Option<String>> {
        Ok(self.stepper()?.render(&action, seed))
    }
}

/// An SVG drawing as pixels: `(width, height, RGBA bytes row by row)`, text in the
/// system's fonts (left out when it has none).
pub fn rasterize<'py>(
    py: Python<'py>,
    svg: &str,
) -> PyResult<(u32, u32, Bound<'py, pyo3::types::PyBytes>)> {
    let mut options = resvg::usvg::Options::default();
    let fonts = options.fontdb_mut();
    fonts.load_system_fonts();
    // The drawings ask for `sans-serif`: the first sans face found stands for it.
    let sans = fonts
        .faces()
        .flat_map(|face| face.families.iter().map(|(name, _)| name.clone()))
        .find(|name| name.contains("Sans") && !name.contains("Mono"));
    if let Some(family) = sans {
        fonts.set_sans_serif_family(family.clone());
        options.font_family = family;
    }
    let tree = resvg::usvg::Tree::from_str(svg, &options).map_err(error)?;
    let size = tree.size().to_int_size();
    let mut pixmap = resvg::tiny_skia::Pixmap::new(size.width(), size.height())
        .ok_or_else(|| error("the drawing has no area"))?;
    pixmap.fill(resvg::tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::default(),
        &mut pixmap.as_mut(),
    );
    let pixels = pyo3::types::PyBytes::new(py, pixmap.data());
    Ok((size.width(), size.height(), pixels))
}
