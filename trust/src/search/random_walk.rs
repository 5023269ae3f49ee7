//! The paper's search strategy, `modifyBehavior` (docs/model.md#the-random-walk).
//!
//! From `E_max` (the evaluated behavior that resisted the longest), move to a behavior at
//! the minimum number of changes that has not been evaluated in this episode, chosen
//! uniformly among all such behaviors. When every behavior has been evaluated, stop and keep
//! `E_max`'s behavior.

use super::longest_resisting;
use super::registry::{Look, Marker, Strategy, WithCases};
use crate::{Evaluated, Outcome};
use cbr_core::{Behavior, BehaviorSpace, Proposal, Rationale, Searcher};
use rand::{Rng, RngCore};
use std::collections::HashSet;

/// The random walk without repetition.
#[derive(Clone, Debug, Default)]
pub struct RandomWalk {
    /// Distinct behaviors of the evaluated prefix seen so far in this episode, so each call
    /// only looks at the pairs added since the last one.
    seen: HashSet<Behavior>,
    seen_prefix: usize,
    first: Option<Behavior>,
}

/// The paper's random walk as the tool offers it, alone and after case reuse (the paper's
/// case-based strategy).
pub const STRATEGY: Strategy = Strategy {
    name: "random-walk",
    description: "the paper's search: from the behavior that resisted longest, an untried behavior at the fewest changes; no case reuse",
    look: Look {
        colour: [213, 94, 0],
        marker: Marker::Circle,
    },
    with_cases: Some(WithCases {
        name: "case-based",
        description: "the paper's strategy: a stored case of a similar situation first (Algorithm 1), the random walk when none fits",
        look: Look {
            colour: [0, 114, 178],
            marker: Marker::Square,
        },
    }),
    build: || Box::new(RandomWalk::new()),
};

impl RandomWalk {
    /// A new random walk.
    pub fn new() -> Self {
        Self::default()
    }

    /// Every unevaluated behavior at the minimum number of changes from `from`, in
    /// enumeration order; empty when every behavior has been evaluated.
    pub fn candidates(
        space: &BehaviorSpace,
        from: &Behavior,
        evaluated: &HashSet<Behavior>,
    ) -> Vec<Behavior> {
        let mut found = Vec::new();
        for changes in 1..=space.max_changes() {
            space.for_each_at_changes(from, changes, &mut |b| {
                if !evaluated.contains(&b) {
                    found.push(b);
                }
            });
            if !found.is_empty() {
                break;
            }
        }
        found
    }

    fn sync(&mut self, evaluated: &[Evaluated]) {
        // Within an episode the evidence only grows; a slice that is shorter or starts or
        // ends its old prefix differently belongs to another episode.
        let extends = self.seen_prefix <= evaluated.len()
            && self.seen_prefix > 0
            && self.first == Some(evaluated[0].behavior)
            && self
                .seen
                .contains(&evaluated[self.seen_prefix - 1].behavior);
        if !extends {
            self.seen.clear();
            self.seen_prefix = 0;
        }
        self.seen
            .extend(evaluated[self.seen_prefix..].iter().map(|e| e.behavior));
        self.seen_prefix = evaluated.len();
        self.first = evaluated.first().map(|e| e.behavior);
    }
}

impl Searcher for RandomWalk {
    type Evidence = Evaluated;
    type Feedback = Outcome;

    fn name(&self) -> &str {
        STRATEGY.name
    }

    // It proposes from the episode's evidence alone: told a context or statements, it
    // proposes the same.
    fn reads_context(&self) -> bool {
        false
    }

    fn hears_statements(&self) -> bool {
        false
    }

    fn propose(
        &mut self,
        space: &BehaviorSpace,
        evaluated: &[Evaluated],
        rng: &mut dyn RngCore,
    ) -> Proposal {
        let Some(e_max) = longest_resisting(evaluated) else {
            return Proposal::Next(space.draw(rng));
        };
        self.sync(evaluated);
        if self.seen.len() as u64 >= space.size() {
            return Proposal::Exhausted {
                keep: e_max.behavior,
            };
        }
        let candidates = Self::candidates(space, &e_max.behavior, &self.seen);
        match candidates.len() {
            0 => Proposal::Exhausted {
                keep: e_max.behavior,
            },
            n => Proposal::Next(candidates[rng.random_range(0..n)]),
        }
    }

    fn rationale(&self, _proposed: &Behavior) -> Rationale {
        Rationale::Explores {
            how: "one random step from the behavior that resisted longest".into(),
        }
    }

    fn end_episode(&mut self, _evaluated: &[Evaluated], _settled: Option<&Behavior>) {
        self.seen.clear();
        self.seen_prefix = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::search::grid;
    use proptest::prelude::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn ev(indices: &[u16], time: f64) -> Evaluated {
        Evaluated {
            behavior: Behavior::new(indices),
            time,
        }
    }

    #[test]
    fn walks_from_the_longest_resisting_behavior() {
        let space = grid(&[5, 5]);
        // E_max is (2,2) with t = 30. Its neighbours (1,2), (3,2), (2,1), (2,3): (2,1) and
        // (2,3) are evaluated, so the candidates are (1,2) and (3,2).
        let evaluated = vec![
            ev(&[0, 0], 10.0),
            ev(&[2, 2], 30.0),
            ev(&[2, 1], 5.0),
            ev(&[2, 3], 30.0),
        ];
        let mut seen = HashSet::new();
        for seed in 0..50 {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            match RandomWalk::new().propose(&space, &evaluated, &mut rng) {
                Proposal::Next(b) => {
                    assert!(b == Behavior::new(&[1, 2]) || b == Behavior::new(&[3, 2]));
                    seen.insert(b);
                }
                other => panic!("unexpected {other:?}"),
            }
        }
        assert_eq!(seen.len(), 2, "both candidates are drawn");
    }

    #[test]
    fn goes_further_when_the_neighbourhood_is_exhausted() {
        let space = grid(&[3, 3]);
        // Everything within one change of (0,0) is evaluated; the two-change shell is
        // (2,0), (1,1), (0,2).
        let evaluated = [ev(&[0, 0], 9.0), ev(&[1, 0], 1.0), ev(&[0, 1], 1.0)];
        let c = RandomWalk::candidates(
            &space,
            &Behavior::new(&[0, 0]),
            &evaluated.iter().map(|e| e.behavior).collect(),
        );
        assert_eq!(
            c,
            vec![
                Behavior::new(&[0, 2]),
                Behavior::new(&[1, 1]),
                Behavior::new(&[2, 0])
            ]
        );
    }

    #[test]
    fn exhausted_space_keeps_e_max() {
        let space = grid(&[2]);
        let evaluated = vec![ev(&[0], 3.0), ev(&[1], 7.0)];
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        assert_eq!(
            RandomWalk::new().propose(&space, &evaluated, &mut rng),
            Proposal::Exhausted {
                keep: Behavior::new(&[1])
            }
        );
    }

    proptest! {
        #[test]
        fn returns_an_unevaluated_behavior_at_minimum_changes(
            sizes in prop::collection::vec(1u16..5, 1..4),
            picks in prop::collection::vec((any::<u64>(), 0.0f64..100.0), 1..20),
            seed in any::<u64>(),
        ) {
            let space = grid(&sizes);
            let evaluated: Vec<Evaluated> = picks
                .iter()
                .map(|&(r, t)| Evaluated { behavior: space.unrank(r % space.size()), time: t })
                .collect();
            let set: HashSet<Behavior> = evaluated.iter().map(|e| e.behavior).collect();
            let e_max = longest_resisting(&evaluated).unwrap().behavior;
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            match RandomWalk::new().propose(&space, &evaluated, &mut rng) {
                Proposal::Next(b) => {
                    prop_assert!(!set.contains(&b));
                    let d = space.changes(&e_max, &b);
                    let min = space
                        .iter()
                        .filter(|x| !set.contains(x))
                        .map(|x| space.changes(&e_max, &x))
                        .min()
                        .unwrap();
                    prop_assert_eq!(d, min);
                }
                Proposal::Exhausted { keep } => {
                    prop_assert_eq!(set.len() as u64, space.size());
                    prop_assert_eq!(keep, e_max);
                }
            }
        }

        #[test]
        fn visits_every_behavior_once_before_stopping(
            sizes in prop::collection::vec(1u16..4, 1..4),
            seed in any::<u64>(),
        ) {
            let space = grid(&sizes);
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let mut walk = RandomWalk::new();
            let mut evaluated = vec![Evaluated { behavior: space.draw(&mut rng), time: rng.random_range(0.0..10.0) }];
            while let Proposal::Next(b) = walk.propose(&space, &evaluated, &mut rng) {
                prop_assert!(evaluated.iter().all(|e| e.behavior != b));
                evaluated.push(Evaluated { behavior: b, time: rng.random_range(0.0..10.0) });
            }
            prop_assert_eq!(evaluated.len() as u64, space.size());
        }
    }
}
