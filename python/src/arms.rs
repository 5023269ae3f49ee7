//! Search strategies written in Python, as [`Searcher`]s the runner and the conformance
//! kit drive like the built-in ones.
//!
//! A Python searcher is an object with `propose(evaluated, rng)` (the episode's evaluated
//! behaviors in order, each `{"behavior": {...}, "time": s}`, and a `random.Random` seeded
//! from the trial's search stream; it returns the next behavior as a dict in real units, or
//! `None` when nothing is left to try, which keeps the behavior that resisted longest) and
//! optionally `begin_episode(initial)`, `hear(stated)` (what the episode's operator
//! stated up front, a list of `{"name": ..., "minds": bool}`), `observe(behavior, outcome)`,
//! `end_episode(evaluated, settled)`, `rationale(proposed)` (a str: how it explores; or a
//! dict `{"expects": what, "confidence": p}`: what it expects) and the attributes
//! `name` and `learns_across_episodes`. A factory builds one per chain of trials (one per
//! trial when the runner runs an arm's trials independently, as it does for built-in arms):
//! `factory(space)`, with the space as `trustcbr.space` gives it.
//!
//! Every call into Python goes through a [`Caller`]: during a run, to the Python thread
//! that waits for it (so Ctrl-C interrupts a searcher as it would any Python code), and
//! a run with Python arms runs on one worker thread. A searcher cannot fail in the middle
//! of an experiment, so the first exception a Python searcher raises (or a proposal that
//! is not a behavior of the space) is kept, every later proposal of every Python searcher
//! of the run ends the episode at once without calling Python, and the caller raises the
//! kept exception when the run returns.

use crate::calls::Caller;
use crate::convert::{behavior_from_py, component_names, to_py};
use crate::error;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use rand::RngCore;
use serde_json::{Value, json};
use std::borrow::Cow;
use std::sync::{Arc, Mutex};
use trustcbr::cbr_core::{
    Behavior, BehaviorSpace, Context, Proposal, Rationale, Searcher, Statement,
};
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
    factory: Arc<Py<PyAny>>,
    object: Option<Arc<Py<PyAny>>>,
    name: String,
    /// Where the user gave the factory, as its errors name it (`python_arms['mine']`,
    /// `strategy`, `factory`).
    label: Arc<str>,
    learns: bool,
    space: Option<Arc<BehaviorSpace>>,
    observations: Vec<Cause>,
    /// A context the robot was told before the object was built, told it once built.
    untold_context: Option<Context>,
    errors: FirstError,
    caller: Caller,
}

/// The space as a Python searcher's factory is given it.
pub fn space_value(space: &BehaviorSpace) -> Value {
    json!({ "components": named_space(space), "behaviors": space.size() })
}

/// `e` with a note saying where it was raised (Python 3.11's `add_note`; on an older
/// Python, `e` as it is).
fn noted(py: Python<'_>, e: PyErr, note: String) -> PyErr {
    if let Ok(add_note) = e.value(py).getattr("add_note") {
        let _ = add_note.call1((note,));
    }
    e
}

impl PySearcher {
    /// A searcher the arm `name` builds with `factory(space)`, for `space` when known,
    /// calling Python through `caller`; `label` is where the user gave the factory, as
    /// errors name it.
    pub fn new(
        factory: Arc<Py<PyAny>>,
        (name, label): (&str, Arc<str>),
        space: Option<&Arc<BehaviorSpace>>,
        observations: Vec<Cause>,
        errors: FirstError,
        caller: Caller,
    ) -> Self {
        let mut searcher = Self {
            factory,
            object: None,
            name: name.to_owned(),
            label,
            learns: false,
            space: None,
            observations,
            untold_context: None,
            errors,
            caller,
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
        let (factory, described) = (self.factory.clone(), space_value(space));
        let (label, components) = (self.label.clone(), component_names(space));
        let built = self.caller.call(move |py| {
            let object = factory
                .bind(py)
                .call1((to_py(py, &described)?,))
                .map_err(|e| {
                    let failed = error(format_args!(
                        "{label}: the factory raised {} when called with the space ({components}): a factory takes the space and returns a searcher (a class whose __init__(self, space) it is, or a function of the space)",
                        e.value(py)
                            .repr()
                            .map_or_else(|_| "an exception".to_owned(), |r| r.to_string())
                    ));
                    failed.set_cause(py, Some(e));
                    failed
                })?;
            if object.getattr_opt("propose")?.is_none() {
                return Err(error(format_args!(
                    "{label}: the factory returned {}, which has no propose(evaluated, rng): a factory returns a searcher",
                    object
                        .repr()
                        .map_or_else(|_| "an object".to_owned(), |r| r.to_string())
                )));
            }
            let learns = match object.getattr_opt("learns_across_episodes")? {
                Some(l) if !l.is_none() => l.extract::<bool>()?,
                _ => false,
            };
            Ok((Arc::new(object.unbind()), learns))
        });
        match built {
            Ok((object, learns)) => {
                self.object = Some(object);
                self.learns = learns;
            }
            Err(e) => self.errors.keep(e),
        }
    }

    /// The Python object, unless a searcher of the run has failed.
    fn live(&self) -> Option<Arc<Py<PyAny>>> {
        self.object.clone().filter(|_| !self.errors.failed())
    }

    /// Calls the optional method `method` with the JSON `args` when the object has it.
    fn call_optional(&self, method: &'static str, args: Vec<Value>) {
        let Some(object) = self.live() else {
            return;
        };
        let label = self.label.clone();
        let called = self.caller.call(move |py| {
            if let Some(f) = object.bind(py).getattr_opt(method)? {
                let args = args
                    .iter()
                    .map(|a| to_py(py, a))
                    .collect::<PyResult<Vec<_>>>()?;
                f.call1(PyTuple::new(py, args)?)
                    .map_err(|e| noted(py, e, format!("raised by {method}() of {label}")))?;
            }
            Ok(())
        });
        if let Err(e) = called {
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

    fn enter_context(&mut self, context: &Context) {
        if self.object.is_none() {
            self.untold_context = Some(context.clone());
        } else {
            self.call_optional("enter_context", vec![json!(context)]);
        }
    }

    fn begin_episode(&mut self, space: &BehaviorSpace, initial: &Behavior) {
        if self.object.is_none() {
            self.build(&Arc::new(space.clone()));
            if let Some(context) = self.untold_context.take() {
                self.call_optional("enter_context", vec![json!(context)]);
            }
        }
        self.call_optional("begin_episode", vec![reply::behavior(space, initial)]);
    }

    fn hear(&mut self, stated: &[Statement]) {
        self.call_optional("hear", vec![json!(stated)]);
    }

    fn propose(
        &mut self,
        space: &BehaviorSpace,
        evaluated: &[Evaluated],
        rng: &mut dyn RngCore,
    ) -> Proposal {
        let Some(object) = self.live() else {
            return Self::give_up(space, evaluated, rng);
        };
        let seed = rng.next_u64();
        let (list, label) = (reply::evaluated(space, evaluated), self.label.clone());
        let searched = Arc::new(space.clone());
        let proposed = self.caller.call(move |py| -> PyResult<Option<Behavior>> {
            let random = py.import("random")?.getattr("Random")?.call1((seed,))?;
            let answer = object
                .bind(py)
                .call_method1("propose", (to_py(py, &list)?, random))
                .map_err(|e| noted(py, e, format!("raised by propose() of {label}")))?;
            if answer.is_none() {
                return Ok(None);
            }
            let behavior = behavior_from_py(&searched, &answer)
                .map_err(|e| error(format_args!("{label}: propose returned {answer}: {e}")))?;
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
        let (Some(object), Some(space)) = (self.live(), self.space.as_deref()) else {
            return Rationale::unstated();
        };
        let (behavior, label) = (reply::behavior(space, proposed), self.label.clone());
        let said = self.caller.call(move |py| -> PyResult<Option<Rationale>> {
            match object.bind(py).getattr_opt("rationale")? {
                Some(f) => rationale_from_py(&f.call1((to_py(py, &behavior)?,))?)
                    .map(Some)
                    .map_err(|e| noted(py, e, format!("raised by rationale() of {label}"))),
                None => Ok(None),
            }
        });
        match said {
            Ok(Some(rationale)) => rationale,
            Ok(None) => Rationale::unstated(),
            Err(e) => {
                self.errors.keep(e);
                Rationale::unstated()
            }
        }
    }

    fn doubts(
        &mut self,
        space: &BehaviorSpace,
        evaluated: &[Evaluated],
        behavior: &Behavior,
    ) -> bool {
        let Some(object) = self.live() else {
            return false;
        };
        let (list, candidate) = (
            reply::evaluated(space, evaluated),
            reply::behavior(space, behavior),
        );
        let label = self.label.clone();
        let doubted = self.caller.call(move |py| -> PyResult<bool> {
            match object.bind(py).getattr_opt("doubts")? {
                Some(f) => f
                    .call1((to_py(py, &list)?, to_py(py, &candidate)?))
                    .and_then(|answer| answer.is_truthy())
                    .map_err(|e| noted(py, e, format!("raised by doubts() of {label}"))),
                None => Ok(false),
            }
        });
        doubted.unwrap_or_else(|e| {
            self.errors.keep(e);
            false
        })
    }

    fn observe(&mut self, behavior: &Behavior, feedback: &Outcome) {
        let Some(space) = self.space.clone() else {
            return;
        };
        self.call_optional(
            "observe",
            vec![
                reply::behavior(&space, behavior),
                reply::outcome(feedback, &self.observations),
            ],
        );
    }

    fn end_episode(&mut self, evaluated: &[Evaluated], settled: Option<&Behavior>) {
        let Some(space) = self.space.clone() else {
            return;
        };
        let settled = settled.map_or(Value::Null, |b| reply::behavior(&space, b));
        self.call_optional(
            "end_episode",
            vec![reply::evaluated(&space, evaluated), settled],
        );
    }
}

/// A Python arm as the Python layer gives it: its name, its factory, whether it reuses
/// cases, and where the user gave it, as errors name it (`python_arms['mine']`,
/// `strategy`).
#[derive(Clone)]
pub struct PythonArmSpec {
    /// The arm's name in the reports.
    pub name: String,
    /// `factory(space)` builds its searcher.
    pub factory: Arc<Py<PyAny>>,
    /// Whether it reuses cases first.
    pub reuses_cases: bool,
    /// Where the user gave it.
    pub label: Arc<str>,
}

/// An arm of a Python factory: search only, or case reuse first (Algorithm 1, with the
/// suite's retriever) with the Python searcher as its fallback.
///
/// `observations` are the observation names of each space the arm may search (a domain's
/// declared ones), so an outcome's perceptions reach Python by name.
pub fn python_arm(
    spec: &PythonArmSpec,
    observations: Arc<Vec<(Arc<BehaviorSpace>, Vec<Cause>)>>,
    retriever: trustcbr::trust::RetrieverKind,
    errors: FirstError,
    caller: Caller,
) -> Arm {
    let (name, reuses_cases) = (spec.name.clone(), spec.reuses_cases);
    let (arm, label, factory) = (name.clone(), spec.label.clone(), spec.factory.clone());
    let searcher = move |space: &Arc<BehaviorSpace>| -> Box<TrustSearcher> {
        let named = observations
            .iter()
            .find(|(s, _)| **s == **space)
            .map(|(_, names)| names.clone())
            .unwrap_or_default();
        Box::new(PySearcher::new(
            factory.clone(),
            (&arm, label.clone()),
            Some(space),
            named,
            errors.clone(),
            caller.clone(),
        ))
    };
    if reuses_cases {
        Arm::case_based_over(name, searcher, retriever)
    } else {
        Arm::search_only(name, searcher)
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
