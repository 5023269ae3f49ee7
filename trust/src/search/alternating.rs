//! Alternating search: two strategies take turns proposing, and both learn from everything.
//!
//! Two searches that model the operator differently fail on different operators. On the
//! development instances of the benchmark (docs/search-strategies.md, "The benchmark"),
//! [`super::CauseAware`] never found the six trusted behaviors of patrol `dev-9`'s first
//! member in 144 episodes (every one cut off at 2,000 commands), which
//! [`super::ModelBased`]'s climb from the best observed behaviors found in every episode;
//! on `dev-4`, whose two members trust three behaviors each, it was the other way round
//! (130 episodes cut off with the model, 18 with the causes). Which model fits an operator
//! met for the first time cannot be known before its commands are seen. Taking turns bounds
//! the cost of the wrong choice: an episode that one of the two would end after `n`
//! proposals ends after at most about `2n` (it proposes on every other turn, and the other
//! one's proposals only add to the evidence), whereas committing to the wrong one may never
//! end it. Both strategies observe every outcome and every episode's end, so each learns
//! from the behaviors the other proposed.
//!
//! The turns restart with every episode, the first strategy first.

use super::pair::Pair;
use crate::{Evaluated, Outcome};
use cbr_core::{Behavior, BehaviorSpace, Context, Proposal, Rationale, Searcher, Statement};
use rand::RngCore;

/// Two searchers proposing in turn (see the module documentation).
#[derive(Clone, Debug, Default)]
pub struct Alternating<A, B> {
    pair: Pair<A, B>,
    /// Whether the next proposal is the second strategy's.
    second_next: bool,
}

impl<A, B> Alternating<A, B> {
    /// `first` and `second` taking turns, `first` first in every episode.
    pub fn new(first: A, second: B) -> Self {
        Self {
            pair: Pair::new(first, second),
            second_next: false,
        }
    }
}

impl<A, B> Searcher for Alternating<A, B>
where
    A: Searcher<Evidence = Evaluated, Feedback = Outcome>,
    B: Searcher<Evidence = Evaluated, Feedback = Outcome>,
{
    type Evidence = Evaluated;
    type Feedback = Outcome;

    fn name(&self) -> &str {
        "alternating"
    }

    fn learns_across_episodes(&self) -> bool {
        self.pair.learns_across_episodes()
    }

    fn reads_context(&self) -> bool {
        self.pair.reads_context()
    }

    fn hears_statements(&self) -> bool {
        self.pair.hears_statements()
    }

    fn enter_context(&mut self, context: &Context) {
        self.pair.enter_context(context);
    }

    fn hear(&mut self, stated: &[Statement]) {
        self.pair.hear(stated);
    }

    fn begin_episode(&mut self, space: &BehaviorSpace, initial: &Behavior) {
        self.second_next = false;
        self.pair.begin_episode(space, initial);
    }

    fn propose(
        &mut self,
        space: &BehaviorSpace,
        evaluated: &[Evaluated],
        rng: &mut dyn RngCore,
    ) -> Proposal {
        let second = self.second_next;
        self.second_next = !second;
        self.pair.propose(second, space, evaluated, rng)
    }

    fn rationale(&self, proposed: &Behavior) -> Rationale {
        self.pair.rationale(proposed)
    }

    fn observe(&mut self, behavior: &Behavior, outcome: &Outcome) {
        self.pair.observe(behavior, outcome);
    }

    fn end_episode(&mut self, evaluated: &[Evaluated], settled: Option<&Behavior>) {
        self.pair.end_episode(evaluated, settled);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::search::{Fixed, Uniform, grid};
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn they_take_turns_and_both_hear_everything() {
        let space = grid(&[10]);
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let mut both = Alternating::new(
            Fixed {
                at: 1,
                ..Fixed::default()
            },
            Fixed {
                at: 2,
                ..Fixed::default()
            },
        );
        let evidence = [Evaluated {
            behavior: Behavior::new(&[0]),
            time: 1.0,
        }];
        both.begin_episode(&space, &Behavior::new(&[0]));
        let mut proposed = Vec::new();
        for _ in 0..3 {
            let Proposal::Next(b) = both.propose(&space, &evidence, &mut rng) else {
                panic!("a fixed searcher always proposes");
            };
            // The rationale is the proposer's.
            let Rationale::Explores { how } = both.rationale(&b) else {
                panic!("fixed searchers explore");
            };
            assert_eq!(how, format!("always {}", b.get(0)));
            proposed.push(b.get(0));
        }
        assert_eq!(proposed, [1, 2, 1]);
        both.observe(&Behavior::new(&[1]), &Outcome::completed(1.0, 1.0));
        both.end_episode(&evidence, None);
        assert_eq!(
            (both.pair.first.observed, both.pair.second.observed),
            (1, 1)
        );
        assert_eq!((both.pair.first.ended, both.pair.second.ended), (1, 1));
        // A new episode starts with the first again.
        both.begin_episode(&space, &Behavior::new(&[0]));
        assert_eq!(
            both.propose(&space, &evidence, &mut rng),
            Proposal::Next(Behavior::new(&[1]))
        );
        // Neither fixed searcher learns across episodes; with a learner, the pair does.
        assert!(!both.learns_across_episodes());
        let learner = Alternating::new(Uniform::new(), crate::search::CauseAware::new());
        assert!(learner.learns_across_episodes());
    }
}
