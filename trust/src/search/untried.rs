//! The behaviors an episode has not tried yet: the evaluated set, uniform draws from its
//! complement, and the best of such a draw by a searcher's own cost.
//!
//! Every informed searcher scores candidates drawn here, so each of them explores the
//! whole space and never proposes a behavior the episode has already evaluated.

use crate::Evaluated;
use cbr_core::{Behavior, BehaviorSpace};
use rand::{Rng, RngCore};
use std::collections::HashSet;

/// The distinct behaviors of an episode's evidence.
pub fn evaluated_set(evaluated: &[Evaluated]) -> HashSet<Behavior> {
    evaluated.iter().map(|e| e.behavior).collect()
}

/// Up to `count` distinct behaviors not in `tried`, drawn uniformly at random without
/// replacement (all of them, in a random order, when fewer remain). Empty only when every
/// behavior has been tried.
pub fn draw_untried(
    space: &BehaviorSpace,
    tried: &HashSet<Behavior>,
    count: usize,
    rng: &mut dyn RngCore,
) -> Vec<Behavior> {
    let size = space.size();
    let untried = size.saturating_sub(tried.len() as u64);
    if untried == 0 || count == 0 {
        return Vec::new();
    }
    // Rejection sampling is cheap while most of the space is untried and the request is a
    // small part of it; otherwise enumerate the complement and shuffle a prefix of it.
    if u128::from(untried) * 3 >= u128::from(size) * 2 && (count as u128) * 4 <= u128::from(untried)
    {
        let mut chosen = Vec::with_capacity(count);
        let mut seen = HashSet::with_capacity(count);
        while chosen.len() < count {
            let b = space.draw(rng);
            if !tried.contains(&b) && seen.insert(b) {
                chosen.push(b);
            }
        }
        return chosen;
    }
    let mut pool: Vec<Behavior> = space.iter().filter(|b| !tried.contains(b)).collect();
    let take = count.min(pool.len());
    for i in 0..take {
        let j = rng.random_range(i..pool.len());
        pool.swap(i, j);
    }
    pool.truncate(take);
    pool
}

/// The behavior of `candidates` with the lowest `cost` (the first of equal costs), or
/// `None` when there is none: how a searcher picks among candidates it scores. A searcher
/// that maximizes a score (a sampled chance of completing, say) passes its negation.
///
/// ```
/// use cbr_core::Behavior;
/// use trust::search::cheapest;
///
/// let pool = [Behavior::new(&[0]), Behavior::new(&[1]), Behavior::new(&[2])];
/// let cost = |b: &Behavior| (f64::from(b.get(0)) - 1.0).abs();
/// assert_eq!(cheapest(pool, cost), Some(Behavior::new(&[1])));
/// // Equal costs: the first is kept.
/// assert_eq!(cheapest(pool, |_| 0.0), Some(Behavior::new(&[0])));
/// assert_eq!(cheapest([], cost), None);
/// ```
pub fn cheapest(
    candidates: impl IntoIterator<Item = Behavior>,
    mut cost: impl FnMut(&Behavior) -> f64,
) -> Option<Behavior> {
    candidates
        .into_iter()
        .map(|b| (cost(&b), b))
        .fold(None, |best: Option<(f64, Behavior)>, (c, b)| match best {
            Some((lowest, _)) if lowest <= c => best,
            _ => Some((c, b)),
        })
        .map(|(_, b)| b)
}

/// The cheapest by `cost` ([`cheapest`]) of up to `count` untried behaviors drawn
/// uniformly ([`draw_untried`]); `None` only when every behavior has been tried. The
/// usual body of a scoring searcher's proposal, inside [`super::propose_untried`]:
///
/// ```
/// use cbr_core::{Behavior, BehaviorSpace, NamedComponent};
/// use rand::SeedableRng;
/// use rand_chacha::ChaCha8Rng;
/// use std::collections::HashSet;
/// use trust::search::best_untried;
///
/// let speed = NamedComponent::numeric("speed", "m/s", 1.0, 5.0, 5).unwrap();
/// let space = BehaviorSpace::new(vec![speed]).unwrap();
/// let tried: HashSet<Behavior> = [Behavior::new(&[0])].into();
/// let mut rng = ChaCha8Rng::seed_from_u64(1);
/// // All four untried behaviors drawn: the slowest of them is the cheapest.
/// let slowest = best_untried(&space, &tried, 10, &mut rng, |b| f64::from(b.get(0)));
/// assert_eq!(slowest, Some(Behavior::new(&[1])));
/// ```
pub fn best_untried(
    space: &BehaviorSpace,
    tried: &HashSet<Behavior>,
    count: usize,
    rng: &mut dyn RngCore,
    cost: impl FnMut(&Behavior) -> f64,
) -> Option<Behavior> {
    cheapest(draw_untried(space, tried, count, rng), cost)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::search::grid;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn draws_distinct_untried_behaviors_by_both_methods() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let big = grid(&[40, 40]);
        let tried: HashSet<Behavior> = [Behavior::new(&[0, 0])].into();
        // 1,599 untried, 10 wanted: rejection sampling.
        let drawn = draw_untried(&big, &tried, 10, &mut rng);
        assert_eq!(drawn.len(), 10);
        assert_eq!(drawn.iter().collect::<HashSet<_>>().len(), 10);
        assert!(drawn.iter().all(|b| !tried.contains(b)));
        // 3 x 3 with 7 tried: two remain, both returned whatever is asked.
        let small = grid(&[3, 3]);
        let tried: HashSet<Behavior> = small.iter().take(7).collect();
        let drawn = draw_untried(&small, &tried, 5, &mut rng);
        let rest: HashSet<Behavior> = small.iter().skip(7).collect();
        assert_eq!(drawn.into_iter().collect::<HashSet<_>>(), rest);
        let all: HashSet<Behavior> = small.iter().collect();
        assert!(draw_untried(&small, &all, 5, &mut rng).is_empty());
    }
}
