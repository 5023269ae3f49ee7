//! The searcher conformance kit over a Python factory: `trust::testing`'s rules, checked
//! on random small spaces or on a scenario's own space (for a strategy that reads its
//! components by name), and the rule broken returned with its case in Python terms for
//! the Python layer to raise as one exception with the rule's advice.

use crate::arms::{FirstError, PySearcher};
use crate::calls::Caller;
use crate::convert::to_py;
use crate::error;
use pyo3::prelude::*;
use serde_json::{Value, json};
use std::sync::Arc;
use trustcbr::Catalog;
use trustcbr::catalog::domain_of;
use trustcbr::cbr_core::{BehaviorSpace, Proposal};
use trustcbr::lab::Domain;
use trustcbr::service::reply;
use trustcbr::trust::named::named_space;
use trustcbr::trust::search::TrustSearcher;
use trustcbr::trust::testing::{SearcherFailure, searcher_conformance};

/// A proposal in Python terms: a behavior dict, or `None` for "every behavior was tried"
/// (with the behavior kept).
fn proposal_value(space: &BehaviorSpace, proposal: &Proposal) -> Value {
    match proposal {
        Proposal::Next(b) => json!({ "returned": reply::behavior(space, b) }),
        Proposal::Exhausted { keep } => {
            json!({ "returned": null, "keeps": reply::behavior(space, keep) })
        }
    }
}

/// The failure in Python terms: the rule's name, the kit's message, the space (as a
/// factory is given it), the evaluated behaviors and the failing proposal, and the seed.
fn failure_value(failure: &SearcherFailure) -> Value {
    let space = &failure.space;
    json!({
        "rule": failure.rule.name(),
        "message": failure.message,
        "space": { "components": named_space(space), "behaviors": space.size() },
        "evaluated": reply::evaluated(space, &failure.evaluated),
        "proposal": failure.proposal.as_ref().map(|p| proposal_value(space, p)),
        "seed": failure.seed,
    })
}

/// Runs the searcher conformance kit over searchers built by `factory(space)`, on random
/// small spaces, or on the space of the catalog's `scenario` when given. Returns `None`
/// when every rule holds, else the rule broken with its case as a dict; raises the
/// searcher's own exception when it raised one.
pub fn check_searcher<'py, C: Catalog>(
    py: Python<'py>,
    catalog: &C,
    factory: Py<PyAny>,
    scenario: Option<&str>,
) -> PyResult<Option<Bound<'py, PyAny>>> {
    let (space, observations) = match scenario {
        Some(name) => {
            let domain = domain_of(catalog, name).map_err(error)?;
            (
                Some(Arc::clone(domain.space())),
                domain.observations().to_vec(),
            )
        }
        None => (None, Vec::new()),
    };
    let errors = FirstError::default();
    let factory = Arc::new(factory);
    let build = || -> Box<TrustSearcher> {
        Box::new(PySearcher::new(
            factory.clone(),
            ("python", Arc::from("factory")),
            None,
            observations.clone(),
            errors.clone(),
            Caller::Here,
        ))
    };
    let checked = py.detach(|| searcher_conformance(space.as_deref(), &build));
    if let Some(e) = errors.take() {
        return Err(e);
    }
    match checked {
        Ok(()) => Ok(None),
        Err(failure) => to_py(py, &failure_value(&failure)).map(Some),
    }
}
