//! Every built-in searcher passes the searcher conformance kit.

use trust::SearchKind;
use trust::testing::check_searcher;

#[test]
fn every_builtin_searcher_passes_the_kit() {
    for kind in SearchKind::all() {
        check_searcher(|| kind.build());
    }
}

/// A searcher that learns across episodes without saying so: after its first episode it
/// proposes the first untried behavior in the space's order instead of a uniform draw.
struct HiddenLearner {
    episodes: u32,
    confidence: f64,
}

impl cbr_core::Searcher for HiddenLearner {
    type Evidence = trust::Evaluated;
    type Feedback = trust::Outcome;

    fn name(&self) -> &str {
        "hidden-learner"
    }

    fn propose(
        &mut self,
        space: &cbr_core::BehaviorSpace,
        evaluated: &[trust::Evaluated],
        rng: &mut dyn trust::rand::RngCore,
    ) -> cbr_core::Proposal {
        let episodes = self.episodes;
        trust::search::propose_untried(space, evaluated, rng, |tried, rng| {
            if episodes == 0 {
                trust::search::draw_untried(space, tried, 1, rng)
                    .first()
                    .copied()
            } else {
                space.iter().find(|b| !tried.contains(b))
            }
        })
    }

    fn rationale(&self, _proposed: &cbr_core::Behavior) -> cbr_core::Rationale {
        cbr_core::Rationale::Expects {
            what: "something".into(),
            confidence: Some(self.confidence),
        }
    }

    fn end_episode(&mut self, _: &[trust::Evaluated], _: Option<&cbr_core::Behavior>) {
        self.episodes += 1;
    }
}

#[test]
#[should_panic(expected = "learns_across_episodes")]
fn the_kit_catches_a_searcher_that_learns_without_saying_so() {
    check_searcher(|| {
        Box::new(HiddenLearner {
            episodes: 0,
            confidence: 0.5,
        })
    });
}

#[test]
#[should_panic(expected = "is not a probability")]
fn the_kit_checks_the_rationale() {
    check_searcher(|| {
        Box::new(HiddenLearner {
            episodes: 0,
            confidence: 1.5,
        })
    });
}
