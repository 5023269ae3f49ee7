//! Every built-in retriever passes the retriever conformance kit
//! ([`trust::testing::check_retriever`]), and a config names each.

use trust::testing::check_retriever;
use trust::{AdapterConfig, RetrieverKind};

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

impl cbr_core::Retriever<Vec<trust::Evaluated>, cbr_core::Behavior> for NewestFirst {
    fn name(&self) -> &str {
        "newest-first"
    }

    fn retain(&mut self, _id: cbr_core::CaseId, _case: &trust::TrustCase) {}

    fn retrieve(
        &self,
        base: &trust::TrustCaseBase,
        query: &Vec<trust::Evaluated>,
        exclude: cbr_core::Exclusion<'_, Vec<trust::Evaluated>, cbr_core::Behavior>,
    ) -> Option<cbr_core::Retrieved> {
        let mut best: Option<cbr_core::Retrieved> = None;
        for (id, case) in base.iter().collect::<Vec<_>>().into_iter().rev() {
            let similarity = self.0.compare(query, &case.problem);
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
