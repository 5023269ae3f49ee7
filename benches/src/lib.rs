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
//! - **Times.** The time of each pair is the task time one of the paper's two patrol
//!   operators (speed- or detection-focused, drawn per case) takes to reach a verdict on the
//!   behavior under the paper's thresholds, each command the patrol domain's own run
//!   through the lab's driver ([`verdict_time`]). A real episode ends at the first
//!   trustworthy verdict; a synthetic case must go on to `L` pairs, so a behavior this
//!   operator would trust counts with the time its verdict took and the walk continues.
//!
//! Queries are drawn the same way from another seed. `docs/benchmarks.md` gives the
//! achieved statistics and how to measure the real lengths again.
//!
//! [`retrieval`] puts any retriever, a user's included, into the retrieval comparison
//! over these cases.

#![deny(missing_docs)]

pub mod retrieval;

use cbr_core::{Behavior, BehaviorSpace, Case};
use domains::{OperatorModel, Scenario, UgvDomain, builtin_operators};
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Deserialize;
use std::fmt;
use trust::search::RandomWalk;
use trust::{
    Evaluated, Selection, Thresholds, TrustCase, TrustCaseBase, TrustEstimate, TrustProblem,
    Verdict, select_behavior,
};

/// The task seconds `operator` takes to reach a verdict, either one, on `behavior` of the
/// patrol `domain` under the paper's thresholds: the time of an evaluated pair. Every
/// command is the lab's simulated command ([`lab::Simulation`], the driver every trial
/// goes through), its draws from `seed`.
pub fn verdict_time(
    domain: &UgvDomain,
    operator: &OperatorModel,
    behavior: &Behavior,
    seed: u64,
) -> f64 {
    let thresholds = Thresholds::default();
    let mut estimate = TrustEstimate::default();
    let commands = lab::Simulation::new(domain, *behavior, operator, 1.0, seed)
        .expect("a patrol behavior at full attention");
    for command in commands {
        let command = command.expect("the patrol domain declares every cause it reports");
        estimate.record(&command.outcome);
        if estimate.verdict(&thresholds) != Verdict::Undecided {
            break;
        }
    }
    estimate.elapsed_s
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
    domain: UgvDomain,
    /// The paper's two patrol operators, speed- then detection-focused.
    operators: [OperatorModel; 2],
    rng: ChaCha8Rng,
    deck: Vec<usize>,
    dealt: usize,
}

impl<'a> Episodes<'a> {
    /// Cases over `space` (the patrol space, which the patrol domain runs) drawn from
    /// `seed`.
    pub fn new(space: &'a BehaviorSpace, seed: u64) -> Self {
        let deck = patrol_case_lengths();
        let domain = UgvDomain::new(Scenario::Patrol);
        assert_eq!(
            lab::Domain::space(&domain).as_ref(),
            space,
            "synthetic cases are patrol episodes: give the patrol space"
        );
        let [speed, detection, ..] = &builtin_operators(Scenario::Patrol)[..] else {
            unreachable!("the paper's two patrol operators are built in")
        };
        Self {
            space,
            domain,
            operators: [speed.clone(), detection.clone()],
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
        let operator = &self.operators[usize::from(self.rng.random_bool(0.5))];
        let mut walk = RandomWalk::new();
        let mut e_past = TrustProblem::new(Vec::with_capacity(len));
        let mut current = self.space.draw(&mut self.rng);
        loop {
            let time = verdict_time(&self.domain, operator, &current, self.rng.random());
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
    fn a_pair_s_time_is_the_driver_s_commands_until_a_verdict() {
        let domain = UgvDomain::new(Scenario::Patrol);
        let operator = &builtin_operators(Scenario::Patrol)[0];
        let behavior = lab::Domain::space(&domain).draw(&mut ChaCha8Rng::seed_from_u64(5));
        let time = verdict_time(&domain, operator, &behavior, 11);
        // The same commands, drawn by the lab's simulation from the same seed, summed by
        // hand until the paper's estimate leaves "undecided".
        let mut estimate = TrustEstimate::default();
        let mut summed = 0.0;
        for command in lab::Simulation::new(&domain, behavior, operator, 1.0, 11).unwrap() {
            let outcome = command.unwrap().outcome;
            summed += outcome.duration_s;
            estimate.record(&outcome);
            if estimate.verdict(&Thresholds::default()) != Verdict::Undecided {
                break;
            }
        }
        assert!(time > 0.0);
        assert!((time - summed).abs() < 1e-9, "{time} vs {summed}");
        assert_eq!(verdict_time(&domain, operator, &behavior, 11), time);
    }

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
