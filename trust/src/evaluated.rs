//! Evaluated behaviors and the similarity of two sets of them, Algorithm 2
//! (docs/model.md#algorithm-2-comparing-two-searches).
//!
//! An [`Evaluated`] pair records a behavior found untrustworthy and the time `t` it took.
//! [`SetSimilarity`] compares the current episode's pairs with a case's: only pairs whose
//! behaviors are nearly identical (behavior similarity strictly above `lambda`) count, and
//! they count by how similar their times are. Between two problems
//! ([`SetSimilarity::compare_problems`]) that similarity is weighed by their contexts'
//! similarity, an exact match unless the domain declares one.

use crate::problem::TrustProblem;
use cbr_core::{Behavior, BehaviorSpace, ContextSimilarity, ContextSpace, SimilarityMeasure};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// A behavior found untrustworthy, with the task time it took to reach the threshold.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Evaluated {
    /// The behavior.
    pub behavior: Behavior,
    /// Seconds until it was judged untrustworthy (larger: resisted longer).
    pub time: f64,
}

/// The default time similarity: `1 - |t1 - t2| / max(t1, t2)`, and 1 when both are 0.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RelativeTime;

impl SimilarityMeasure<f64> for RelativeTime {
    fn similarity(&self, a: &f64, b: &f64) -> f64 {
        let larger = a.max(*b);
        if larger <= 0.0 {
            1.0
        } else {
            (1.0 - (a - b).abs() / larger).clamp(0.0, 1.0)
        }
    }
}

/// Algorithm 2: the similarity of the current episode's evaluated pairs (`e1`) to a case's
/// (`e2`), with a pluggable time similarity `T`.
#[derive(Clone, Debug)]
pub struct SetSimilarity<T = RelativeTime> {
    space: Arc<BehaviorSpace>,
    lambda: f64,
    time: T,
    context: ContextSimilarity,
}

/// A `lambda` outside `(0, 1]`.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("lambda must be in (0, 1], got {}", cbr_core::Shown(*.0))]
pub struct LambdaError(pub f64);

/// Checks that `lambda` lies in `(0, 1]`.
pub fn validate_lambda(lambda: f64) -> Result<(), LambdaError> {
    if lambda > 0.0 && lambda <= 1.0 {
        Ok(())
    } else {
        Err(LambdaError(lambda))
    }
}

/// Deserializes a `lambda` and checks it with [`validate_lambda`].
pub fn deserialize_lambda<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    let lambda = f64::deserialize(d)?;
    validate_lambda(lambda)
        .map_err(|e| serde::de::Error::custom(format_args!("field `lambda`: {e}")))?;
    Ok(lambda)
}

impl SetSimilarity<RelativeTime> {
    /// The paper's measure over `space` with threshold `lambda` and the default time
    /// similarity.
    pub fn new(space: Arc<BehaviorSpace>, lambda: f64) -> Result<Self, LambdaError> {
        Self::with_time(space, lambda, RelativeTime)
    }

    /// Algorithm 2 over `space` at `lambda`, weighing contexts as a domain declares them
    /// (`contexts`: its declared similarities, an exact match where it declares none): the
    /// measure an adapter's retriever ranks cases by, in an experiment and in `serve`.
    pub fn of_domain(
        space: Arc<BehaviorSpace>,
        lambda: f64,
        contexts: Arc<ContextSpace>,
    ) -> Result<Self, LambdaError> {
        Ok(
            Self::new(space, lambda)?
                .with_context_similarity(ContextSimilarity::Declared(contexts)),
        )
    }
}

impl<T> SetSimilarity<T> {
    /// The measure with a custom time similarity.
    pub fn with_time(space: Arc<BehaviorSpace>, lambda: f64, time: T) -> Result<Self, LambdaError> {
        validate_lambda(lambda)?;
        Ok(Self {
            space,
            lambda,
            time,
            context: ContextSimilarity::Exact,
        })
    }

    /// The same measure, weighing the contexts of two problems by `context` (an exact
    /// match by default).
    #[must_use]
    pub fn with_context_similarity(mut self, context: ContextSimilarity) -> Self {
        self.context = context;
        self
    }

    /// The behavior-similarity threshold.
    pub fn lambda(&self) -> f64 {
        self.lambda
    }

    /// The behavior space.
    pub fn space(&self) -> &Arc<BehaviorSpace> {
        &self.space
    }

    /// `E_max` for `e`: the first pair of `stored` whose behavior is most similar to
    /// `e.behavior`, with that similarity; `None` if `stored` is empty.
    pub fn closest<'a>(
        &self,
        e: &Evaluated,
        stored: &'a [Evaluated],
    ) -> Option<(&'a Evaluated, f64)> {
        let mut best: Option<(&Evaluated, f64)> = None;
        for candidate in stored {
            let s = self.space.similarity(&e.behavior, &candidate.behavior);
            if best.is_none_or(|(_, b)| s > b) {
                best = Some((candidate, s));
            }
        }
        best
    }
}

impl<T: SimilarityMeasure<f64>> SetSimilarity<T> {
    /// The time similarity of `a` and `b`.
    pub fn time_similarity(&self, a: f64, b: f64) -> f64 {
        self.time.similarity(&a, &b)
    }

    /// Algorithm 2 over two slices.
    pub fn compare(&self, e1: &[Evaluated], e2: &[Evaluated]) -> f64 {
        let mut total = 0.0;
        let mut matched = 0u32;
        for e in e1 {
            if let Some((e_max, s)) = self.closest(e, e2)
                && s > self.lambda
            {
                total += self.time.similarity(&e.time, &e_max.time);
                matched += 1;
            }
        }
        if matched == 0 {
            0.0
        } else {
            total / f64::from(matched)
        }
    }
}

impl<T: SimilarityMeasure<f64>> SetSimilarity<T> {
    /// The similarity of a query to a case's problem: Algorithm 2 over their pairs, times
    /// their contexts' similarity (exactly Algorithm 2 when both are in one context).
    pub fn compare_problems(&self, query: &TrustProblem, case: &TrustProblem) -> f64 {
        let context = self.context.similarity(&query.context, &case.context);
        if context == 0.0 {
            return 0.0;
        }
        context * self.compare(&query.evaluated, &case.evaluated)
    }
}

impl<T: SimilarityMeasure<f64>> SimilarityMeasure<TrustProblem> for SetSimilarity<T> {
    fn similarity(&self, a: &TrustProblem, b: &TrustProblem) -> f64 {
        self.compare_problems(a, b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cbr_core::NamedComponent;

    fn movement() -> Arc<BehaviorSpace> {
        Arc::new(
            BehaviorSpace::new(vec![
                NamedComponent::numeric("speed", "m/s", 0.5, 0.5, 20).unwrap(),
                NamedComponent::numeric("padding", "m", 0.1, 0.1, 20).unwrap(),
            ])
            .unwrap(),
        )
    }

    fn ev(speed: u16, padding: u16, time: f64) -> Evaluated {
        Evaluated {
            behavior: Behavior::new(&[speed, padding]),
            time,
        }
    }

    #[test]
    fn relative_time_similarity() {
        // 1 - |10 - 40| / 40 = 0.25
        assert!((RelativeTime.similarity(&10.0, &40.0) - 0.25).abs() < 1e-12);
        assert_eq!(RelativeTime.similarity(&0.0, &0.0), 1.0);
        assert_eq!(RelativeTime.similarity(&0.0, &3.0), 0.0);
    }

    #[test]
    fn hand_computed_set_similarity() {
        let sim = SetSimilarity::new(movement(), 0.95).unwrap();
        // On the 20 x 20 movement grid one index step changes one component similarity by
        // 1/19, so the behavior similarity of neighbours is (1 + 18/19) / 2 = 0.97368... > 0.95,
        // and two steps give (1 + 17/19) / 2 = 0.947... < 0.95.
        let e1 = vec![ev(3, 3, 20.0), ev(10, 10, 30.0), ev(0, 19, 50.0)];
        let e2 = vec![ev(3, 4, 40.0), ev(3, 3, 10.0), ev(10, 12, 30.0)];
        // e1[0] (3,3): closest is e2[1] (identical, sim 1): time sim 1 - 10/20 = 0.5.
        // e1[1] (10,10): closest is e2[2] at two steps, sim 0.947 <= 0.95: not counted.
        // e1[2] (0,19): nothing close: not counted.
        // Result: 0.5 / 1.
        assert!((sim.compare(&e1, &e2) - 0.5).abs() < 1e-12);
        // Reversed: e2[0] (3,4) -> e1[0] (3,3), one step: 1 - 20/40 = 0.5;
        // e2[1] (3,3) -> e1[0]: 1 - 10/20 = 0.5; e2[2] (10,12) -> e1[1] two steps: skipped.
        // (0.5 + 0.5) / 2 = 0.5.
        assert!((sim.compare(&e2, &e1) - 0.5).abs() < 1e-12);
        assert_eq!(sim.compare(&e1, &[]), 0.0);
        assert_eq!(sim.compare(&[], &e2), 0.0);
    }

    #[test]
    fn argmax_ties_go_to_the_first() {
        let sim = SetSimilarity::new(movement(), 0.95).unwrap();
        // (5,5) is one step from both (5,4) and (5,6): E_max is (5,4), time 10.
        let e1 = vec![ev(5, 5, 10.0)];
        let e2 = vec![ev(5, 4, 10.0), ev(5, 6, 20.0)];
        assert_eq!(sim.compare(&e1, &e2), 1.0);
    }

    #[test]
    fn lambda_is_checked() {
        assert!(SetSimilarity::new(movement(), 0.0).is_err());
        assert!(SetSimilarity::new(movement(), 1.5).is_err());
        assert!(SetSimilarity::new(movement(), 1.0).is_ok());
    }
}
