//! Synthetic trust case bases drawn like real ones, for the benchmarks.
//!
//! Real cases come from the random walk: `E_past` is a path of one-change steps from a
//! uniformly random start, each step taken from the behavior that resisted longest, with
//! task seconds as times. The patrol simulator is not needed to get that shape: this module
//! drives the real [`TrustAdapter`] (search only, `reuse_cases: false`, the paper's
//! thresholds and patrol weights) over the patrol space against a [`SyntheticOperator`]
//! whose reactions depend on the behavior in the way the patrol task's do (slow robots
//! miss the deadline, small paddings collide, short or distant scans miss explosives, fast
//! robots pass objects unscanned). Every case is a real adapter episode; only the world is
//! made up. `docs/benchmarks.md` gives the resulting `|E_past|` distribution.

use cbr_core::{Behavior, BehaviorSpace};
use rand::{Rng, RngCore, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;
use trust::{AdapterConfig, Cause, Decision, Evaluated, Outcome, TrustAdapter, TrustCaseBase};

/// What the operator cares about (SPEC section 8's two patrol operators).
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
/// Every other outcome weighs 1/3 (SPEC section 8's default patrol weights).
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
            return Outcome::interrupted(LIGHT, Cause::Deadline, 120.0);
        }
        let collision = 0.5 * (1.0 - d / 2.0).powi(2) * v / 10.0;
        if rng.random_bool(collision * 0.05) {
            return Outcome::interrupted(LIGHT, Cause::Collision, rng.random_range(0.0..duration));
        }
        let explosives = rng.random_range(0..=3u32);
        for object in 0..6 {
            if rng.random_bool(0.15 * (v / 10.0).powi(2)) {
                return Outcome::interrupted(LIGHT, Cause::MissedObject, duration);
            }
            if object < explosives {
                if rng.random_bool((0.6 * (-s / 1.2).exp() * (0.5 + r)).min(1.0)) {
                    return Outcome::failed(HEAVY, Cause::Detonation, duration);
                }
            } else if rng.random_bool(0.2 * (-s / 2.0).exp() * r) {
                return Outcome::interrupted(LIGHT, Cause::FalseAlarm, duration);
            }
        }
        Outcome::completed(LIGHT, duration)
    }
}

/// Runs search-only episodes with operators drawn uniformly at random (the "random
/// operator" experiment) until `cases` cases are retained; returns the case base. The same
/// `seed` gives the same cases, and a smaller base is a prefix of a larger one.
pub fn case_base(space: &Arc<BehaviorSpace>, cases: usize, seed: u64) -> TrustCaseBase {
    let mut episodes = Episodes::new(space, seed);
    while episodes.adapter.cases().len() < cases {
        episodes.next();
    }
    episodes.adapter.cases().clone()
}

/// Queries as Algorithm 1 meets them: at every adaptation of `episodes` fresh episodes
/// (not in any case base of `case_base`), the evaluated pairs so far.
pub fn queries(space: &Arc<BehaviorSpace>, episodes: usize, seed: u64) -> Vec<Vec<Evaluated>> {
    let mut source = Episodes::new(space, seed ^ 0x5eed);
    (0..episodes)
        .flat_map(|_| {
            let e_past = source.next();
            (1..=e_past.len())
                .map(|n| e_past[..n].to_vec())
                .collect::<Vec<_>>()
        })
        .collect()
}

/// The search-only adapter and the random draws of its episodes.
struct Episodes<'a> {
    space: &'a Arc<BehaviorSpace>,
    adapter: TrustAdapter,
    rng: ChaCha8Rng,
}

impl<'a> Episodes<'a> {
    fn new(space: &'a Arc<BehaviorSpace>, seed: u64) -> Self {
        let config = AdapterConfig {
            reuse_cases: false,
            ..AdapterConfig::default()
        };
        let adapter = TrustAdapter::new(space.clone(), config, TrustCaseBase::new(), seed)
            .expect("the default config is valid");
        Self {
            space,
            adapter,
            rng: ChaCha8Rng::seed_from_u64(seed),
        }
    }

    /// Runs one episode to its end and returns its evaluated pairs.
    fn next(&mut self) -> Vec<Evaluated> {
        let operator = SyntheticOperator {
            focus: if self.rng.random_bool(0.5) {
                Focus::Speed
            } else {
                Focus::Detection
            },
        };
        let start = self.space.draw(&mut self.rng);
        self.adapter
            .begin_episode(start)
            .expect("no episode under way");
        let mut current = start;
        loop {
            let outcome = operator.command(self.space, &current, &mut self.rng);
            match self.adapter.record(&outcome).expect("outcomes are valid") {
                Decision::Keep => {}
                Decision::Switch { to, .. } => current = to,
                Decision::Settled(report) => return report.evaluated,
            }
        }
    }
}

/// Mean and quantiles of the `|E_past|` of a case base.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LengthStats {
    /// Mean number of evaluated pairs per case.
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

/// The `|E_past|` distribution of `base` (which must not be empty).
pub fn length_stats(base: &TrustCaseBase) -> LengthStats {
    let mut lengths: Vec<usize> = base.cases().iter().map(|c| c.problem.len()).collect();
    lengths.sort_unstable();
    let at = |q: f64| lengths[((lengths.len() - 1) as f64 * q).round() as usize];
    LengthStats {
        mean: lengths.iter().sum::<usize>() as f64 / lengths.len() as f64,
        median: at(0.5),
        p90: at(0.9),
        p99: at(0.99),
        max: lengths[lengths.len() - 1],
    }
}
