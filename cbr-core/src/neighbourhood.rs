//! Similarity neighbourhoods: every behavior more similar to a centre than a threshold.
//!
//! With a threshold near 1 (Algorithm 2's `lambda`) the behaviors `b` with
//! `similarity(centre, b) > threshold` form a small neighbourhood, which retrieval indices
//! probe instead of scanning. The neighbourhood is derived from the component similarities
//! and weights, not from a fixed radius: a behavior's *loss* is
//! `1 - similarity = sum_k w_k (1 - s_k) / sum_k w_k`, so a depth-first walk over the
//! components keeps only partial behaviors whose accumulated loss stays below
//! `1 - threshold`. The walk's bound is widened by [`BOUND_SLACK`] so that floating-point
//! rounding can never drop a behavior, and every behavior it reaches is then checked with
//! the exact [`BehaviorSpace::similarity`]: the visited set is exactly the exact test's set.
//! Components of every kind (numeric, categorical, tabled, custom) work the same way; a
//! zero-weight component simply contributes every one of its values.

use crate::behavior::{Behavior, BehaviorSpace};

/// How far beyond `1 - threshold` the walk's loss bound reaches, so that rounding in the
/// loss sums cannot exclude a behavior the exact similarity accepts (all quantities are in
/// `[0, 1]`, where rounding errors are around `1e-16`).
pub const BOUND_SLACK: f64 = 1e-9;

impl BehaviorSpace {
    /// Calls `visit` for every behavior `b` with `self.similarity(centre, b) > threshold`,
    /// exactly those, each once (in rank order).
    pub fn for_each_more_similar(
        &self,
        centre: &Behavior,
        threshold: f64,
        visit: &mut dyn FnMut(Behavior),
    ) {
        let weight_sum: f64 = self.weights().iter().sum();
        let budget = (1.0 - threshold) + BOUND_SLACK;
        if budget <= 0.0 {
            return;
        }
        let mut walk = Walk {
            space: self,
            centre,
            threshold,
            weight_sum,
            budget,
            visit,
        };
        walk.from(0, *centre, 0.0);
    }
}

struct Walk<'a> {
    space: &'a BehaviorSpace,
    centre: &'a Behavior,
    threshold: f64,
    weight_sum: f64,
    budget: f64,
    visit: &'a mut dyn FnMut(Behavior),
}

impl Walk<'_> {
    fn from(&mut self, component: usize, partial: Behavior, loss: f64) {
        let space = self.space;
        if component == space.components().len() {
            // Well inside the bound the exact test cannot disagree (rounding is far below
            // the slack); only the thin band around the boundary needs it.
            let inside = loss < self.budget - 2.0 * BOUND_SLACK;
            if inside || space.similarity(self.centre, &partial) > self.threshold {
                (self.visit)(partial);
            }
            return;
        }
        let c = &space.components()[component];
        let share = space.weights()[component] / self.weight_sum;
        let here = self.centre.get(component);
        let added = |value: u16| share * (1.0 - c.similarity(here, value));
        let budget = self.budget;
        let fits = |value: u16| loss + added(value) < budget;
        // Numeric similarity falls with the index distance, so the values that fit form an
        // interval around `here`; other components may fit anywhere.
        let (low, high) = if c.is_numeric() {
            let mut low = here;
            while low > 0 && fits(low - 1) {
                low -= 1;
            }
            let mut high = here;
            while usize::from(high) + 1 < c.len() && fits(high + 1) {
                high += 1;
            }
            (low, high)
        } else {
            (0, c.len() as u16 - 1)
        };
        for value in low..=high {
            if fits(value) {
                self.from(
                    component + 1,
                    partial.with(component, value),
                    loss + added(value),
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::component::{Categorical, NamedComponent, Values};
    use crate::testing::{SpaceShape, behavior_spaces};
    use crate::{Behavior, BehaviorSpace};
    use proptest::prelude::*;
    use rand::SeedableRng;

    fn neighbourhood(space: &BehaviorSpace, centre: &Behavior, threshold: f64) -> Vec<Behavior> {
        let mut found = Vec::new();
        space.for_each_more_similar(centre, threshold, &mut |b| found.push(b));
        found
    }

    #[test]
    fn patrol_like_grid_at_lambda_095() {
        // 20 x 20 x 10 x 4, equal weights: one step costs 1/76, 1/76, 1/36 and 1/12 of
        // similarity. Below 0.05: up to 3 steps of speed and padding together (3/76), or one
        // step of scan time with at most one of speed or padding (1/36 + 1/76 < 0.05).
        let space = BehaviorSpace::new(vec![
            NamedComponent::numeric("speed", "", 0.5, 0.5, 20).unwrap(),
            NamedComponent::numeric("padding", "", 0.1, 0.1, 20).unwrap(),
            NamedComponent::numeric("scan_time", "", 0.5, 0.5, 10).unwrap(),
            NamedComponent::numeric("scan_distance", "", 0.25, 0.25, 4).unwrap(),
        ])
        .unwrap();
        let centre = Behavior::new(&[10, 10, 5, 2]);
        // |ds| + |dp| <= 3: 1 + 4 + 8 + 12 = 25; scan time +-1 with |ds| + |dp| <= 1: 2 x 5.
        assert_eq!(neighbourhood(&space, &centre, 0.95).len(), 35);
    }

    #[test]
    fn tabled_categorical_components_follow_the_table() {
        let planner = NamedComponent {
            name: "planner".into(),
            unit: String::new(),
            values: Values::Categorical(Categorical {
                labels: vec!["a".into(), "b".into(), "c".into()],
                similarity: Some(vec![
                    vec![1.0, 0.9, 0.0],
                    vec![0.9, 1.0, 0.5],
                    vec![0.0, 0.5, 1.0],
                ]),
            }),
        };
        let space = BehaviorSpace::new(vec![planner]).unwrap();
        let found = neighbourhood(&space, &Behavior::new(&[0]), 0.8);
        assert_eq!(found, vec![Behavior::new(&[0]), Behavior::new(&[1])]);
        // The boundary is strict: similarity 0.9 is not above 0.9.
        let found = neighbourhood(&space, &Behavior::new(&[0]), 0.9);
        assert_eq!(found, vec![Behavior::new(&[0])]);
    }

    fn mixed_space() -> impl Strategy<Value = BehaviorSpace> {
        behavior_spaces(SpaceShape {
            values: 1..=6,
            ..SpaceShape::mixed()
        })
    }

    proptest! {
        #[test]
        fn visits_exactly_the_behaviors_above_the_threshold(
            space in mixed_space(),
            seed in any::<u64>(),
            threshold in prop_oneof![0.0f64..1.0, Just(0.95), Just(0.5), Just(1.0)],
        ) {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let centre = space.draw(&mut rng);
            let expected: Vec<Behavior> = space
                .iter()
                .filter(|b| space.similarity(&centre, b) > threshold)
                .collect();
            prop_assert_eq!(neighbourhood(&space, &centre, threshold), expected);
        }
    }
}
