//! Every built-in retriever passes the retriever conformance kit
//! ([`trust::testing::check_retriever`]), and a config names each.

use cbr_core::{Behavior, BehaviorSpace, ContextSpace, ContextVariable, NamedComponent, Retriever};
use std::sync::Arc;
use trust::testing::check_retriever;
use trust::{AdapterConfig, Evaluated, RetrieverKind, SetSimilarity, TrustProblem};

#[test]
fn every_builtin_retriever_passes_the_kit() {
    for kind in RetrieverKind::ALL {
        check_retriever(|measure| kind.build_measure(measure));
    }
}

#[test]
fn a_config_names_its_retriever() {
    for (text, kind) in [
        ("(retriever: linear)", RetrieverKind::Linear),
        ("(retriever: inverted_index)", RetrieverKind::InvertedIndex),
        ("(retriever: parallel_scan)", RetrieverKind::ParallelScan),
    ] {
        let config: AdapterConfig = ron::from_str(text).unwrap();
        assert_eq!(config.retriever, kind, "{text}");
        assert_eq!(config.lambda, AdapterConfig::default().lambda);
    }
}

/// A user's retriever with a subtle bug: it scans the cases newest first and keeps the
/// first of equally similar ones, so ties go to the largest id.
struct NewestFirst(trust::SetSimilarity);

impl cbr_core::Retriever<TrustProblem, cbr_core::Behavior> for NewestFirst {
    fn name(&self) -> &str {
        "newest-first"
    }

    fn retain(&mut self, _id: cbr_core::CaseId, _case: &trust::TrustCase) {}

    fn retrieve(
        &self,
        base: &trust::TrustCaseBase,
        query: &TrustProblem,
        exclude: cbr_core::Exclusion<'_, TrustProblem, cbr_core::Behavior>,
    ) -> Option<cbr_core::Retrieved> {
        let mut best: Option<cbr_core::Retrieved> = None;
        for (id, case) in base.iter().collect::<Vec<_>>().into_iter().rev() {
            let similarity = self.0.compare_problems(query, &case.problem);
            if !exclude(case) && similarity > 0.0 && best.is_none_or(|b| similarity > b.similarity)
            {
                best = Some(cbr_core::Retrieved { id, similarity });
            }
        }
        best
    }
}

#[test]
#[should_panic(expected = "retriever check failed")]
fn a_retriever_that_breaks_ties_otherwise_fails_the_kit() {
    check_retriever(|measure| Box::new(NewestFirst(measure)));
}

/// A user's retriever that forgets the contexts: Algorithm 2 over the pairs alone.
struct ContextBlind(trust::SetSimilarity);

impl Retriever<TrustProblem, Behavior> for ContextBlind {
    fn name(&self) -> &str {
        "context-blind"
    }

    fn retain(&mut self, _id: cbr_core::CaseId, _case: &trust::TrustCase) {}

    fn retrieve(
        &self,
        base: &trust::TrustCaseBase,
        query: &TrustProblem,
        exclude: cbr_core::Exclusion<'_, TrustProblem, Behavior>,
    ) -> Option<cbr_core::Retrieved> {
        let mut best: Option<cbr_core::Retrieved> = None;
        for (id, case) in base.iter() {
            let similarity = self.0.compare(&query.evaluated, &case.problem.evaluated);
            if !exclude(case) && similarity > best.map_or(0.0, |b| b.similarity) {
                best = Some(cbr_core::Retrieved { id, similarity });
            }
        }
        best
    }
}

#[test]
#[should_panic(expected = "retriever check failed")]
fn a_retriever_that_ignores_contexts_fails_the_kit() {
    check_retriever(|measure| Box::new(ContextBlind(measure)));
}

/// With a similarity the domain declares between its contexts (the situations half
/// alike, cargo matched exactly), a case from a half-alike context scores half, one from
/// a context matched exactly nothing (every kind returns the linear scan's answer by such
/// a measure: the kit checks it).
#[test]
fn a_declared_context_similarity_weighs_a_case_by_its_context() {
    let mut situation = ContextVariable::new("situation", &["routine", "emergency"]);
    situation.similarity = Some(vec![vec![1.0, 0.5], vec![0.5, 1.0]]);
    let contexts = Arc::new(
        ContextSpace::new(vec![
            ContextVariable::new("cargo", &["normal", "hazardous"]),
            situation,
        ])
        .unwrap(),
    );
    let all = [
        contexts.context([]).unwrap(),
        contexts.context([("cargo", "hazardous")]).unwrap(),
        contexts.context([("situation", "emergency")]).unwrap(),
    ];
    let space = Arc::new(
        BehaviorSpace::new(vec![
            NamedComponent::numeric("a", "", 0.0, 1.0, 8).unwrap(),
            NamedComponent::numeric("b", "", 0.0, 1.0, 8).unwrap(),
        ])
        .unwrap(),
    );
    let measure = || SetSimilarity::of_domain(space.clone(), 0.95, contexts.clone()).unwrap();
    // By hand: the same pairs in a half-alike context score half.
    let pairs = vec![Evaluated {
        behavior: Behavior::new(&[3, 3]),
        time: 10.0,
    }];
    let routine = TrustProblem::in_context(all[0].clone(), pairs.clone());
    let emergency = TrustProblem::in_context(all[2].clone(), pairs.clone());
    let hazardous = TrustProblem::in_context(all[1].clone(), pairs);
    assert_eq!(measure().compare_problems(&routine, &routine), 1.0);
    assert_eq!(measure().compare_problems(&routine, &emergency), 0.5);
    assert_eq!(measure().compare_problems(&routine, &hazardous), 0.0);
}
