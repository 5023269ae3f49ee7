//! Every built-in retriever passes the retriever conformance kit
//! ([`trust::testing::check_retriever`]), and a config names each.

use cbr_core::{
    Behavior, BehaviorSpace, Case, ContextSimilarity, ContextSpace, ContextVariable,
    LinearRetriever, NamedComponent, Retriever,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;
use trust::testing::check_retriever;
use trust::{
    AdapterConfig, Evaluated, RetrieverKind, SetSimilarity, TrustCaseBase, TrustMemory,
    TrustProblem,
};

#[test]
fn every_builtin_retriever_passes_the_kit() {
    for kind in RetrieverKind::ALL {
        check_retriever(|space, lambda| kind.build(space.clone(), lambda));
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
    check_retriever(|space, lambda| {
        Ok(Box::new(NewestFirst(trust::SetSimilarity::new(
            space.clone(),
            lambda,
        )?)))
    });
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
    check_retriever(|space, lambda| {
        Ok(Box::new(ContextBlind(trust::SetSimilarity::new(
            space.clone(),
            lambda,
        )?)))
    });
}

/// With a similarity the domain declares between its contexts (the situations half
/// alike, cargo matched exactly), every kind built on that measure returns the linear
/// scan's answer, bit for bit, and a case from a half-alike context is found at half its
/// similarity.
#[test]
fn a_declared_context_similarity_gives_every_kind_the_linear_answer() {
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
        contexts
            .context([("situation", "emergency"), ("cargo", "hazardous")])
            .unwrap(),
    ];
    let space = Arc::new(
        BehaviorSpace::new(vec![
            NamedComponent::numeric("a", "", 0.0, 1.0, 8).unwrap(),
            NamedComponent::numeric("b", "", 0.0, 1.0, 8).unwrap(),
        ])
        .unwrap(),
    );
    let measure = || {
        SetSimilarity::new(space.clone(), 0.95)
            .unwrap()
            .with_context_similarity(ContextSimilarity::Declared(contexts.clone()))
    };
    let mut rng = ChaCha8Rng::seed_from_u64(30);
    let problem = |rng: &mut ChaCha8Rng| {
        let len = rng.random_range(1..6);
        let mut pairs = Vec::with_capacity(len);
        for _ in 0..len {
            let behavior = space.draw(rng);
            let time = f64::from(rng.random_range(0u32..30));
            pairs.push(Evaluated { behavior, time });
        }
        let context = all[rng.random_range(0..all.len())].clone();
        TrustProblem::in_context(context, pairs)
    };
    let mut base = TrustCaseBase::new();
    for _ in 0..400 {
        let problem = problem(&mut rng);
        base.push(Case {
            problem,
            solution: space.draw(&mut rng),
        });
    }
    let reference = TrustMemory::new(base.clone(), Box::new(LinearRetriever::new(measure())));
    let memories: Vec<TrustMemory> = RetrieverKind::ALL
        .iter()
        .map(|kind| TrustMemory::new(base.clone(), kind.build_measure(measure())))
        .collect();
    let answer = |m: &TrustMemory, q: &TrustProblem| {
        m.retrieve(q, &|_| false)
            .map(|r| (r.id, r.similarity.to_bits()))
    };
    let mut found = 0;
    for _ in 0..200 {
        let query = problem(&mut rng);
        let expected = answer(&reference, &query);
        found += usize::from(expected.is_some());
        for memory in &memories {
            assert_eq!(
                answer(memory, &query),
                expected,
                "{}",
                memory.retriever_name()
            );
        }
    }
    assert!(found > 100, "the queries find cases ({found} of 200)");
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
