//! Search strategies written in Python, as [`Searcher`]s the runner and the conformance
//! kit drive like the built-in ones.
//!
//! A Python searcher is an object with `propose(evaluated, rng)` (the episode's evaluated
//! behaviors in order, each `{"behavior": {...}, "time": s}`, and a `random.Random` seeded
//! from the trial's search stream; it returns the next behavior as a dict in real units, or
//! `None` when nothing is left to try, which keeps the behavior that resisted longest) and
//! optionally `begin_episode(initial)`, `observe(behavior, outcome)`,
//! `end_episode(evaluated, settled)`, `rationale(proposed)` (a str: how it explores; or a
//! dict `{"expects": what, "confidence": p}`: what it expects) and the attributes
//! `name` and `learns_across_episodes`. A factory builds one per chain of trials (one per
//! trial when the runner runs an arm's trials independently, as it does for built-in arms):
//! `factory(space)`, with the space as `trustcbr.space` gives it.
//!
//! Calling Python takes the interpreter lock, so a run with Python arms runs on one worker
//! thread. A searcher cannot fail in the middle of an experiment, so the first exception a
//! Python searcher raises (or a proposal that is not a behavior of the space) is kept,
//! every later proposal of every Python searcher of the run ends the episode at once
//! without calling Python, and the caller raises the kept exception when the run returns.

use crate::convert::{behavior_from_py, behavior_to_py, to_py};
use crate::error;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rand::RngCore;
use serde_json::json;
use std::borrow::Cow;
use std::sync::{Arc, Mutex};
use trustcbr::cbr_core::{Behavior, BehaviorSpace, Proposal, Rationale, Searcher};
use trustcbr::lab::Arm;
use trustcbr::service::reply;
use trustcbr::trust::named::named_space;
use trustcbr::trust::search::{TrustSearcher, longest_resisting};
use trustcbr::trust::{Cause, Evaluated, Outcome};

/// The first error a run's Python searchers raised, shared by all of them.
#[derive(Clone, Default)]
pub struct FirstError(Arc<Mutex<Option<PyErr>>>);

impl FirstError {
    /// Keeps `e` unless an error is kept already.
    fn keep(&self, e: PyErr) {
        let mut slot = self.0.lock().unwrap_or_else(|p| p.into_inner());
        if slot.is_none() {
            *slot = Some(e);
        }
    }

    /// Whether an error is kept.
    pub fn failed(&self) -> bool {
        self.0.lock().unwrap_or_else(|p| p.into_inner()).is_some()
    }

    /// The kept error, if any (taken).
    pub fn take(&self) -> Option<PyErr> {
        self.0.lock().unwrap_or_else(|p| p.into_inner()).take()
    }
}

/// A Python object driven as a search strategy, built by its factory for the space it
/// searches: at once when the space is known, else when its first episode begins.
pub struct PySearcher {
    factory: Py<PyAny>,
    object: Option<Py<PyAny>>,
    name: String,
    learns: bool,
    space: Option<Arc<BehaviorSpace>>,
    observations: Vec<Cause>,
    errors: FirstError,
}

/// The space as a Python searcher's factory is given it.
pub fn space_value(space: &BehaviorSpace) -> serde_json::Value {
    json!({ "components": named_space(space), "behaviors": space.size() })
}

impl PySearcher {
    /// A searcher the arm `name` builds with `factory(space)`, for `space` when known.
    pub fn new(
        factory: Py<PyAny>,
        name: &str,
        space: Option<&Arc<BehaviorSpace>>,
        observations: Vec<Cause>,
        errors: FirstError,
    ) -> Self {
        let mut searcher = Self {
            factory,
            object: None,
            name: name.to_owned(),
            learns: false,
            space: None,
            observations,
            errors,
        };
        if let Some(space) = space {
            searcher.build(space);
        }
        searcher
    }

    /// Builds the Python object for `space` (the error kept when the factory fails).
    fn build(&mut self, space: &Arc<BehaviorSpace>) {
        self.space = Some(space.clone());
        if self.errors.failed() {
            return;
        }
        Python::attach(|py| {
            let built = to_py(py, &space_value(space))
                .and_then(|s| self.factory.bind(py).call1((s,)))
                .and_then(|object| {
                    let learns = match object.getattr_opt("learns_across_episodes")? {
                        Some(l) if !l.is_none() => l.extract::<bool>()?,
                        _ => false,
                    };
                    Ok((object.unbind(), learns))
                });
            match built {
                Ok((object, learns)) => {
                    self.object = Some(object);
                    self.learns = learns;
                }
                Err(e) => self.errors.keep(e),
            }
        });
    }

    /// Calls the optional method `method` with `args` when the object has it.
    fn call_optional<'py>(
        &self,
        py: Python<'py>,
        method: &str,
        args: impl FnOnce(Python<'py>) -> PyResult<Vec<Bound<'py, PyAny>>>,
    ) {
        let Some(object) = self.object.as_ref().filter(|_| !self.errors.failed()) else {
            return;
        };
        let result = (|| {
            if let Some(f) = object.bind(py).getattr_opt(method)? {
                let args = pyo3::types::PyTuple::new(py, args(py)?)?;
                f.call1(args)?;
            }
            Ok(())
        })();
        if let Err(e) = result {
            self.errors.keep(e);
        }
    }

    /// What to do once a Python searcher has failed: end the episode.
    fn give_up(space: &BehaviorSpace, evaluated: &[Evaluated], rng: &mut dyn RngCore) -> Proposal {
        Proposal::Exhausted {
            keep: longest_resisting(evaluated).map_or_else(|| space.draw(rng), |e| e.behavior),
        }
    }
}

impl Searcher for PySearcher {
    type Evidence = Evaluated;
    type Feedback = Outcome;

    fn name(&self) -> &str {
        &self.name
    }

    fn learns_across_episodes(&self) -> bool {
        self.learns
    }

    fn begin_episode(&mut self, space: &BehaviorSpace, initial: &Behavior) {
        if self.object.is_none() {
            self.build(&Arc::new(space.clone()));
        }
        Python::attach(|py| {
            self.call_optional(py, "begin_episode", |py| {
                Ok(vec![behavior_to_py(py, space, initial)?])
            });
        });
    }

    fn propose(
        &mut self,
        space: &BehaviorSpace,
        evaluated: &[Evaluated],
        rng: &mut dyn RngCore,
    ) -> Proposal {
        let Some(object) = self.object.as_ref().filter(|_| !self.errors.failed()) else {
            return Self::give_up(space, evaluated, rng);
        };
        let seed = rng.next_u64();
        let proposed = Python::attach(|py| -> PyResult<Option<Behavior>> {
            let random = py.import("random")?.getattr("Random")?.call1((seed,))?;
            let list = to_py(py, &reply::evaluated(space, evaluated))?;
            let answer = object.bind(py).call_method1("propose", (list, random))?;
            if answer.is_none() {
                return Ok(None);
            }
            let behavior = behavior_from_py(space, &answer).map_err(|e| {
                error(format_args!(
                    "{}: propose returned {answer}: {e}",
                    self.name
                ))
            })?;
            Ok(Some(behavior))
        });
        match proposed {
            Ok(Some(b)) => Proposal::Next(b),
            Ok(None) => Self::give_up(space, evaluated, rng),
            Err(e) => {
                self.errors.keep(e);
                Self::give_up(space, evaluated, rng)
            }
        }
    }

    fn rationale(&self, proposed: &Behavior) -> Rationale {
        let (Some(object), Some(space)) = (self.object.as_ref(), self.space.as_deref()) else {
            return Rationale::unstated();
        };
        if self.errors.failed() {
            return Rationale::unstated();
        }
        Python::attach(|py| {
            let said = (|| -> PyResult<Option<Rationale>> {
                match object.bind(py).getattr_opt("rationale")? {
                    Some(f) => {
                        let b = behavior_to_py(py, space, proposed)?;
                        rationale_from_py(&f.call1((b,))?).map(Some)
                    }
                    None => Ok(None),
                }
            })();
            match said {
                Ok(Some(rationale)) => rationale,
                Ok(None) => Rationale::unstated(),
                Err(e) => {
                    self.errors.keep(e);
                    Rationale::unstated()
                }
            }
        })
    }

    fn observe(&mut self, behavior: &Behavior, feedback: &Outcome) {
        let Some(space) = self.space.clone() else {
            return;
        };
        Python::attach(|py| {
            self.call_optional(py, "observe", |py| {
                Ok(vec![
                    behavior_to_py(py, &space, behavior)?,
                    to_py(py, &reply::outcome(feedback, &self.observations))?,
                ])
            });
        });
    }

    fn end_episode(&mut self, evaluated: &[Evaluated], settled: Option<&Behavior>) {
        let Some(space) = self.space.clone() else {
            return;
        };
        Python::attach(|py| {
            self.call_optional(py, "end_episode", |py| {
                let settled = match settled {
                    Some(b) => behavior_to_py(py, &space, b)?,
                    None => py.None().into_bound(py),
                };
                Ok(vec![
                    to_py(py, &reply::evaluated(&space, evaluated))?,
                    settled,
                ])
            });
        });
    }
}

/// An arm of a Python factory: search only, or case reuse first (Algorithm 1, with the
/// suite's retriever) with the Python searcher as its fallback.
///
/// `observations` are the observation names of each space the arm may search (a domain's
/// declared ones), so an outcome's perceptions reach Python by name.
pub fn python_arm(
    name: String,
    factory: Arc<Py<PyAny>>,
    reuses_cases: bool,
    observations: Arc<Vec<(Arc<BehaviorSpace>, Vec<Cause>)>>,
    retriever: trustcbr::trust::RetrieverKind,
    errors: FirstError,
) -> Arm {
    let arm = name.clone();
    let searcher = move |space: &Arc<BehaviorSpace>| -> Box<TrustSearcher> {
        let named = observations
            .iter()
            .find(|(s, _)| **s == **space)
            .map(|(_, names)| names.clone())
            .unwrap_or_default();
        Box::new(PySearcher::new(
            Python::attach(|py| factory.as_ref().clone_ref(py)),
            &arm,
            Some(space),
            named,
            errors.clone(),
        ))
    };
    if reuses_cases {
        Arm::case_based(name, searcher, move |space, lambda| {
            retriever.build(space.clone(), lambda)
        })
    } else {
        Arm::search_only(name, searcher)
    }
}

/// Runs the searcher conformance kit (`trust::testing::check_searcher`: proposals in the
/// space, never an evaluated behavior while one is untried, exhaustion only when every
/// behavior was tried, the same proposals for the same seed) over searchers built by
/// `factory(space)`, on random small spaces. Raises `TrustcbrError` naming the property a
/// searcher breaks, or the searcher's own exception.
#[pyfunction]
pub fn check_searcher(py: Python<'_>, factory: Py<PyAny>) -> PyResult<()> {
    let errors = FirstError::default();
    let outcome = py.detach(|| {
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            trustcbr::trust::testing::check_searcher(|| -> Box<TrustSearcher> {
                Box::new(PySearcher::new(
                    Python::attach(|py| factory.clone_ref(py)),
                    "python",
                    None,
                    Vec::new(),
                    errors.clone(),
                ))
            })
        }))
    });
    if let Some(e) = errors.take() {
        return Err(e);
    }
    match outcome {
        Ok(()) => Ok(()),
        Err(panic) => {
            let message = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| (*s).to_owned()))
                .unwrap_or_else(|| "the searcher breaks a conformance property".to_owned());
            Err(error(message))
        }
    }
}

/// What a Python searcher's `rationale(proposed)` returned, as a [`Rationale`]: a string
/// says how it explores; a dict `{"expects": what, "confidence": p}` (the confidence a
/// probability, optional) says what it expects of the proposal.
fn rationale_from_py(said: &Bound<'_, PyAny>) -> PyResult<Rationale> {
    if let Ok(how) = said.extract::<String>() {
        return Ok(Rationale::Explores {
            how: Cow::Owned(how),
        });
    }
    let wrong = || {
        pyo3::exceptions::PyTypeError::new_err(
            "rationale(proposed) must return a str (how it explores) or a dict \
             {\"expects\": str, \"confidence\": float in [0, 1] or None}",
        )
    };
    let dict = said.cast::<PyDict>().map_err(|_| wrong())?;
    let what: String = dict
        .get_item("expects")?
        .ok_or_else(wrong)?
        .extract()
        .map_err(|_| wrong())?;
    let confidence: Option<f64> = match dict.get_item("confidence")? {
        Some(p) if !p.is_none() => Some(p.extract().map_err(|_| wrong())?),
        _ => None,
    };
    if confidence.is_some_and(|p| !(0.0..=1.0).contains(&p)) {
        return Err(wrong());
    }
    Ok(Rationale::Expects {
        what: Cow::Owned(what),
        confidence,
    })
}
