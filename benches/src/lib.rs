//! Synthetic trust case bases drawn like real ones, for the benchmarks.
//!
//! Two properties of real cases matter to retrieval: how many evaluated pairs a case holds
//! (`|E_past|`) and how those pairs lie in the space. This module takes the first from the
//! real patrol experiments and the second from the real search code:
//!
//! - **Length.** `data/patrol-case-lengths.json` (embedded) holds the `|E_past|` of every
//!   case the case-based strategy retained in the three patrol experiments of
//!   `trustcbr reproduce` (seed 2014, 500 trials each). Each synthetic case takes its length
//!   from that list: the lengths are dealt like cards from a shuffled deck of the list,
//!   reshuffled when empty, so every case's length follows the real distribution and any
//!   373 consecutive cases hold each real length once.
//! - **Shape.** The `E_past` of a case of length `L` is a random-walk episode cut at `L`
//!   pairs: a uniformly random patrol-space start, then Algorithm 1 without a case base
//!   ([`select_behavior`] with the paper's [`RandomWalk`]: one-change steps from the
//!   behavior that resisted longest). The case's final behavior is the walk's next
//!   proposal, so it is never in `E_past`, as in a real case.
//! - **Times.** The time of each pair is the task time a [`SyntheticOperator`] (speed- or
//!   detection-focused, drawn per case) takes to reach a verdict on the behavior under the
//!   paper's thresholds. A real episode ends at the first trustworthy verdict; a synthetic
//!   case must go on to `L` pairs, so a behavior this operator would trust counts with the
//!   time its verdict took and the walk continues.
//!
//! Queries are drawn the same way from another seed. `docs/benchmarks.md` gives the
//! achieved statistics and how to measure the real lengths again.
//!
//! [`retrieval`] puts any retriever, a user's included, into the retrieval comparison
//! over these cases.

#![deny(missing_docs)]

pub mod retrieval;

use cbr_core::{Behavior, BehaviorSpace, Case};
use rand::seq::SliceRandom;
use rand::{Rng, RngCore, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Deserialize;
use std::fmt;
use trust::search::RandomWalk;
use trust::{
    Evaluated, Outcome, Selection, Thresholds, TrustCase, TrustCaseBase, TrustEstimate,
    TrustProblem, Verdict, select_behavior,
};

/// What the operator cares about (the two patrol operators of docs/model.md#the-operators).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Focus {
    /// Interrupts late runs (`p_alpha = 0.95`).
    Speed,
    /// Tolerates late runs (`p_alpha = 0.05`); explosives and false alarms dominate.
    Detection,
}

/// A made-up patrol world and operator: one command is one patrol of a 120 m route with six
/// suspicious objects, 0 to 3 of them explosive.
///
/// With the behavior's speed `v` (m/s), padding `d` (m), scan time `s` (s) and scan
/// distance `r` (m):
/// - the run takes `120 / v + 5 s + 20 d` seconds (route, scans, detours);
/// - past the 120 s deadline the operator interrupts with probability `p_alpha`;
/// - the robot collides with probability `0.5 (1 - d / 2)^2 v / 10`, and the operator then
///   interrupts with probability `p_gamma = 0.05`;
/// - each object is passed unscanned with probability `0.15 (v / 10)^2` (interruption);
/// - each explosive is labelled harmless with probability `0.6 exp(-s / 1.2) (0.5 + r)`
///   (detonation: a failure of weight 1);
/// - each harmless object is labelled explosive with probability `0.2 exp(-s / 2) r`
///   (interruption).
///
/// Every other outcome weighs 1/3 (the default patrol weights of docs/model.md#open-readings).
#[derive(Clone, Copy, Debug)]
pub struct SyntheticOperator {
    /// What the operator watches most.
    pub focus: Focus,
}

const HEAVY: f64 = 1.0;
const LIGHT: f64 = 1.0 / 3.0;

impl SyntheticOperator {
    /// The outcome of one command performed with `behavior` (a patrol-space behavior).
    pub fn command(
        &self,
        space: &BehaviorSpace,
        behavior: &Behavior,
        rng: &mut dyn RngCore,
    ) -> Outcome {
        let value = |k: usize| space.components()[k].numeric_value(behavior.get(k));
        let (v, d, s, r) = (value(0), value(1), value(2), value(3));
        let duration = 120.0 / v + 5.0 * s + 20.0 * d;
        let p_alpha = match self.focus {
            Focus::Speed => 0.95,
            Focus::Detection => 0.05,
        };
        if duration > 120.0 && rng.random_bool(p_alpha) {
            return Outcome::interrupted(LIGHT, 120.0);
        }
        let collision = 0.5 * (1.0 - d / 2.0).powi(2) * v / 10.0;
        if rng.random_bool(collision * 0.05) {
            return Outcome::interrupted(LIGHT, rng.random_range(0.0..duration));
        }
        let explosives = rng.random_range(0..=3u32);
        for object in 0..6 {
            if rng.random_bool(0.15 * (v / 10.0).powi(2)) {
                return Outcome::interrupted(LIGHT, duration);
            }
            if object < explosives {
                if rng.random_bool((0.6 * (-s / 1.2).exp() * (0.5 + r)).min(1.0)) {
                    return Outcome::failed(HEAVY, duration);
                }
            } else if rng.random_bool(0.2 * (-s / 2.0).exp() * r) {
                return Outcome::interrupted(LIGHT, duration);
            }
        }
        Outcome::completed(LIGHT, duration)
    }

    /// The task seconds this operator takes to reach a verdict, either one, on `behavior`
    /// under the paper's thresholds: the time of an evaluated pair.
    pub fn verdict_time(
        &self,
        space: &BehaviorSpace,
        behavior: &Behavior,
        rng: &mut dyn RngCore,
    ) -> f64 {
        let thresholds = Thresholds::default();
        let mut estimate = TrustEstimate::default();
        while estimate.verdict(&thresholds) == Verdict::Undecided {
            estimate.record(&self.command(space, behavior, rng));
        }
        estimate.elapsed_s
    }
}

/// The embedded measurement (its `about` field says how it was taken).
#[derive(Deserialize)]
struct Measured {
    lengths: Vec<usize>,
}

/// The `|E_past|` of the real patrol cases (`data/patrol-case-lengths.json`), in the order
/// they were recorded.
pub fn patrol_case_lengths() -> Vec<usize> {
    let measured: Measured = serde_json::from_str(include_str!("../data/patrol-case-lengths.json"))
        .expect("the embedded lengths are valid JSON");
    measured.lengths
}

/// A seeded source of synthetic patrol cases. Lengths, operators, starts, outcomes and walk
/// steps all come from one stream, so the same seed gives the same cases.
pub struct Episodes<'a> {
    space: &'a BehaviorSpace,
    rng: ChaCha8Rng,
    deck: Vec<usize>,
    dealt: usize,
}

impl<'a> Episodes<'a> {
    /// Cases over `space` (the patrol space) drawn from `seed`.
    pub fn new(space: &'a BehaviorSpace, seed: u64) -> Self {
        let deck = patrol_case_lengths();
        Self {
            space,
            rng: ChaCha8Rng::seed_from_u64(seed),
            dealt: deck.len(),
            deck,
        }
    }

    /// The next case, its length dealt from the real distribution.
    pub fn next_case(&mut self) -> TrustCase {
        if self.dealt == self.deck.len() {
            self.deck.shuffle(&mut self.rng);
            self.dealt = 0;
        }
        let len = self.deck[self.dealt];
        self.dealt += 1;
        self.case_of_length(len)
    }

    /// A case of exactly `len >= 1` evaluated pairs: a random walk from a uniformly random
    /// start, its final behavior the walk's next proposal.
    pub fn case_of_length(&mut self, len: usize) -> TrustCase {
        assert!(len > 0, "a case holds at least one evaluated pair");
        let operator = SyntheticOperator {
            focus: if self.rng.random_bool(0.5) {
                Focus::Speed
            } else {
                Focus::Detection
            },
        };
        let mut walk = RandomWalk::new();
        let mut e_past = TrustProblem::new(Vec::with_capacity(len));
        let mut current = self.space.draw(&mut self.rng);
        loop {
            let time = operator.verdict_time(self.space, &current, &mut self.rng);
            e_past.evaluated.push(Evaluated {
                behavior: current,
                time,
            });
            match select_behavior(&e_past, None, &mut walk, self.space, &mut self.rng) {
                Selection::Next { behavior: next, .. } if e_past.evaluated.len() == len => {
                    return Case {
                        problem: e_past,
                        solution: next,
                    };
                }
                Selection::Next { behavior: next, .. } => current = next,
                other => panic!(
                    "a walk of {len} steps over {} behaviors ended early: {other:?}",
                    self.space.size()
                ),
            }
        }
    }
}

/// `cases` synthetic cases over `space` (the patrol space). The same `seed` gives the same
/// cases, and a smaller base is a prefix of a larger one.
pub fn case_base(space: &BehaviorSpace, cases: usize, seed: u64) -> TrustCaseBase {
    let mut episodes = Episodes::new(space, seed);
    let mut base = TrustCaseBase::new();
    for _ in 0..cases {
        base.push(episodes.next_case());
    }
    base
}

/// `count` query `E_past`s drawn like the cases of [`case_base`] but from another stream,
/// so none is in a case base of the same `seed`.
pub fn queries(space: &BehaviorSpace, count: usize, seed: u64) -> Vec<TrustProblem> {
    let mut episodes = Episodes::new(space, seed ^ 0x5eed);
    (0..count).map(|_| episodes.next_case().problem).collect()
}

/// Mean and quantiles of a list of `|E_past|`s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LengthStats {
    /// Mean number of evaluated pairs.
    pub mean: f64,
    /// Median.
    pub median: usize,
    /// 90th percentile.
    pub p90: usize,
    /// 99th percentile.
    pub p99: usize,
    /// Largest.
    pub max: usize,
}

impl LengthStats {
    /// The statistics of `lengths` (which must not be empty); quantile `q` is the sorted
    /// list's element at index `round((n - 1) q)`.
    pub fn of(lengths: impl IntoIterator<Item = usize>) -> Self {
        let mut lengths: Vec<usize> = lengths.into_iter().collect();
        assert!(!lengths.is_empty(), "no lengths to describe");
        lengths.sort_unstable();
        let at = |q: f64| lengths[((lengths.len() - 1) as f64 * q).round() as usize];
        Self {
            mean: lengths.iter().sum::<usize>() as f64 / lengths.len() as f64,
            median: at(0.5),
            p90: at(0.9),
            p99: at(0.99),
            max: lengths[lengths.len() - 1],
        }
    }
}

impl fmt::Display for LengthStats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "mean {:.1}, median {}, p90 {}, p99 {}, max {}",
            self.mean, self.median, self.p90, self.p99, self.max
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn lengths_follow_the_real_distribution() {
        let space = domains::spaces::patrol_space();
        let base = case_base(&space, 2_000, 7);
        let real = LengthStats::of(patrol_case_lengths());
        let made = LengthStats::of(base.cases().iter().map(|c| c.problem.evaluated.len()));
        assert_eq!(made.median, real.median);
        assert!(
            (made.mean - real.mean).abs() <= 0.1 * real.mean,
            "synthetic {made} against real {real}"
        );
    }

    #[test]
    fn cases_are_walks_without_repetition() {
        let space = domains::spaces::patrol_space();
        let mut episodes = Episodes::new(&space, 3);
        for len in [1, 2, 40] {
            let case = episodes.case_of_length(len);
            assert_eq!(case.problem.evaluated.len(), len);
            let distinct: HashSet<Behavior> =
                case.problem.evaluated.iter().map(|e| e.behavior).collect();
            assert_eq!(distinct.len(), len);
            assert!(!distinct.contains(&case.solution));
            assert!(case.problem.evaluated.iter().all(|e| e.time > 0.0));
        }
        let again = case_base(&space, 50, 3);
        assert_eq!(case_base(&space, 80, 3).cases()[..50], again.cases()[..]);
    }
}
