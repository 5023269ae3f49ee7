//! Arms: the strategies an experiment compares, as data.
//!
//! An [`Arm`] is a named way of adapting: a search strategy, whether cases are reused
//! (Algorithm 1) and with which retriever, and optionally a case base to start from. The
//! runner builds every arm's parts through factories, so a user's own searcher or
//! retriever enters an experiment exactly as the built-in ones do ([`Arm::search_only`],
//! [`Arm::case_based`]). [`Arm::builtin`] names the built-in arms.

use cbr_core::BehaviorSpace;
use std::fmt;
use std::sync::Arc;
use trust::retrieval::RetrieverKind;
use trust::search::{SearchKind, TrustSearcher};
use trust::{LambdaError, RetrieverFactory, SearcherFactory};
use trust::{TrustCaseBase, TrustRetriever};

/// The built-in arms, in report order: the paper's two first.
pub const BUILTIN_ARMS: [&str; 9] = [
    "random-walk",
    "case-based",
    "uniform",
    "cause-aware",
    "model-based",
    "conditioned",
    "case-based+cause-aware",
    "case-based+model-based",
    "case-based+conditioned",
];

/// What each built-in arm does, in one line (docs/search-strategies.md tells more);
/// `None` for an arm that is not built in.
pub fn describe(name: &str) -> Option<&'static str> {
    Some(match name {
        "random-walk" => {
            "the paper's search: from the behavior that resisted longest, an untried behavior at the fewest changes; no case reuse"
        }
        "case-based" => {
            "the paper's strategy: a stored case of a similar situation first (Algorithm 1), the random walk when none fits"
        }
        "uniform" => {
            "an untried behavior uniformly at random: the baseline a learning strategy must beat"
        }
        "cause-aware" => {
            "learns from why commands failed (stated reasons, perceived events) which component values cause trouble, and avoids them"
        }
        "model-based" => {
            "a Gaussian-process model of the current operator's reactions over the behavior space picks the next behavior"
        }
        "conditioned" => {
            "remembers earlier operators' rejected and trusted behaviors, weighed by how much each resembles the current operator"
        }
        "case-based+cause-aware" => "case reuse first, the cause-aware search when no case fits",
        "case-based+model-based" => "case reuse first, the model-based search when no case fits",
        "case-based+conditioned" => "case reuse first, the conditioned search when no case fits",
        _ => return None,
    })
}

/// One strategy of an experiment.
#[derive(Clone)]
pub struct Arm {
    name: String,
    searcher: SearcherFactory,
    retriever: Option<RetrieverFactory>,
    starting_cases: Option<Arc<TrustCaseBase>>,
}

impl fmt::Debug for Arm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Arm")
            .field("name", &self.name)
            .field("reuses_cases", &self.reuses_cases())
            .field(
                "starting_cases",
                &self.starting_cases.as_ref().map(|c| c.len()),
            )
            .finish()
    }
}

/// An arm name that is not a built-in one.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown arm `{name}` (known: {})", BUILTIN_ARMS.join(", "))]
pub struct UnknownArm {
    /// The name asked for.
    pub name: String,
}

impl Arm {
    /// The search strategy alone: every adaptation comes from `searcher` (cases are still
    /// retained as docs/model.md#cases-and-retention says, and counted, but never read).
    pub fn search_only(
        name: impl Into<String>,
        searcher: impl Fn(&Arc<BehaviorSpace>) -> Box<TrustSearcher> + Send + Sync + 'static,
    ) -> Self {
        Self {
            name: name.into(),
            searcher: Arc::new(searcher),
            retriever: None,
            starting_cases: None,
        }
    }

    /// Algorithm 1 over the cases `retriever` indexes, with `searcher` as its fallback.
    pub fn case_based(
        name: impl Into<String>,
        searcher: impl Fn(&Arc<BehaviorSpace>) -> Box<TrustSearcher> + Send + Sync + 'static,
        retriever: impl Fn(&Arc<BehaviorSpace>, f64) -> Result<Box<TrustRetriever>, LambdaError>
        + Send
        + Sync
        + 'static,
    ) -> Self {
        Self {
            retriever: Some(Arc::new(retriever)),
            ..Self::search_only(name, searcher)
        }
    }

    /// The same arm starting every experiment from `cases` instead of an empty case base.
    pub fn with_starting_cases(mut self, cases: TrustCaseBase) -> Self {
        self.starting_cases = Some(Arc::new(cases));
        self
    }

    /// A built-in arm by name ([`BUILTIN_ARMS`]): `NAME` is a search strategy alone and
    /// `case-based+NAME` is Algorithm 1 with it as fallback (`case-based` falls back to
    /// the random walk, as in the paper); case-based arms use `retriever`.
    pub fn builtin(name: &str, retriever: RetrieverKind) -> Result<Self, UnknownArm> {
        let unknown = || UnknownArm {
            name: name.to_owned(),
        };
        if !BUILTIN_ARMS.contains(&name) {
            return Err(unknown());
        }
        let (reuse, search) = match name {
            "case-based" => (true, "random-walk"),
            other => match other.strip_prefix("case-based+") {
                Some(search) => (true, search),
                None => (false, other),
            },
        };
        let kind = SearchKind::ALL
            .into_iter()
            .find(|k| k.name() == search)
            .ok_or_else(unknown)?;
        let searcher = move |_: &Arc<BehaviorSpace>| kind.build();
        Ok(if reuse {
            Self::case_based(name, searcher, move |space, lambda| {
                retriever.build(space.clone(), lambda)
            })
        } else {
            Self::search_only(name, searcher)
        })
    }

    /// The arm's name in reports.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Whether the arm reuses cases (Algorithm 1).
    pub fn reuses_cases(&self) -> bool {
        self.retriever.is_some()
    }

    /// The case base the arm starts from, if any.
    pub fn starting_cases(&self) -> Option<&TrustCaseBase> {
        self.starting_cases.as_deref()
    }

    /// A fresh searcher for `space`.
    pub fn build_searcher(&self, space: &Arc<BehaviorSpace>) -> Box<TrustSearcher> {
        (self.searcher)(space)
    }

    /// The retriever for `space`: the arm's own when it reuses cases, the linear scan
    /// otherwise (it only receives the retained cases, which are never read).
    pub fn build_retriever(
        &self,
        space: &Arc<BehaviorSpace>,
        lambda: f64,
    ) -> Result<Box<TrustRetriever>, LambdaError> {
        match &self.retriever {
            Some(build) => build(space, lambda),
            None => RetrieverKind::Linear.build(space.clone(), lambda),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_builtin_name_builds_and_others_are_refused_with_the_list() {
        let space = Arc::new(
            BehaviorSpace::new(vec![
                cbr_core::NamedComponent::numeric("x", "", 0.0, 1.0, 3).unwrap(),
            ])
            .unwrap(),
        );
        for name in BUILTIN_ARMS {
            let arm = Arm::builtin(name, RetrieverKind::Linear).unwrap();
            assert_eq!(arm.name(), name);
            assert_eq!(arm.reuses_cases(), name.starts_with("case-based"));
            let searcher = arm.build_searcher(&space);
            let expected = name.strip_prefix("case-based+").unwrap_or(match name {
                "case-based" => "random-walk",
                other => other,
            });
            assert_eq!(searcher.name(), expected);
        }
        let err = Arm::builtin("case-based+random-walk", RetrieverKind::Linear).unwrap_err();
        assert!(
            err.to_string()
                .contains("known: random-walk, case-based, uniform")
        );
        assert!(Arm::builtin("annealing", RetrieverKind::Linear).is_err());
    }
}
