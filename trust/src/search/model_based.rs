//! Model-based search: a Gaussian-process surrogate of how the current operator judges
//! each behavior, fit to the episode's command outcomes, and the untried behavior most
//! likely to be judged well.
//!
//! Every command is an observation at its behavior: `+w` completed, `-w` failed or
//! interrupted (the outcome's signed contribution to the trust estimate). Observations of
//! one behavior are pooled into their mean, with noise shrinking as their number grows.
//! The surrogate's prior has mean 0 (no opinion) and a kernel built from the space's own
//! component similarities: `k(a, b) = prod_k s_k(a_k, b_k)^(p * m * w_k)`, with `s_k` the
//! component similarity, `w_k` the normalised component weight, `m` the number of
//! components and `p` a sharpness. A numeric component's similarity is a triangle
//! `1 - |a - b| / range`, whose powers of at least one are positive definite on a line,
//! and a categorical one is an identity kernel, so with equal weights the product kernel
//! is positive definite; a small jitter covers user similarity tables that are not. The
//! sharpness is chosen per proposal among [`SHARPNESS_CHOICES`] by the marginal
//! likelihood of the episode's observations (the data say how smooth the operator is).
//!
//! A proposal scores no more than it must: a pool of untried behaviors drawn uniformly
//! ([`MODEL_POOL`]) plus the untried neighbours of the best observed behaviors, ranked by
//! the probability that the operator's mean reaction there is positive, `Phi(mu / sigma)`
//! (ranked through `mu / sigma`). Far from every observation that is one half, near bad
//! behaviors less, near promising ones more, so the search leaves regions the operator
//! dislikes and closes in on the ones it tolerates. The linear algebra (Cholesky
//! factorisation and triangular solves) is faer's, run sequentially so results do not
//! depend on threads.

use super::longest_resisting;
use super::untried::{draw_untried, evaluated_set};
use crate::{Evaluated, Outcome};
use cbr_core::{Behavior, BehaviorSpace, Proposal, Searcher};
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::prelude::*;
use faer::{Mat, Side};
use rand::RngCore;
use std::collections::{HashMap, HashSet};

/// Untried behaviors drawn uniformly and scored per proposal.
pub const MODEL_POOL: usize = 256;

/// Observed behaviors whose untried neighbours join the pool (the best by mean outcome).
const LOCAL_CENTRES: usize = 3;

/// The kernel sharpnesses among which the marginal likelihood chooses.
pub const SHARPNESS_CHOICES: [f64; 4] = [1.0, 2.0, 4.0, 8.0];

/// Noise variance of one observation, in units of the largest weight seen (an outcome
/// is `+-1` around a mean in `[-1, 1]`, so its variance is at most 1).
const NOISE_VARIANCE: f64 = 1.0;

/// Added to the kernel's diagonal when it is not positive definite, growing tenfold.
const JITTER: f64 = 1e-9;

/// One observed behavior: commands seen and the sum of their signed weights.
#[derive(Clone, Copy, Debug)]
struct Observed {
    behavior: Behavior,
    commands: f64,
    sum: f64,
}

/// The model-based searcher.
#[derive(Clone, Debug, Default)]
pub struct ModelBased {
    observed: Vec<Observed>,
    index: HashMap<Behavior, usize>,
    largest_weight: f64,
}

impl ModelBased {
    /// A model-based searcher.
    pub fn new() -> Self {
        Self::default()
    }

    fn forget(&mut self) {
        self.observed.clear();
        self.index.clear();
        self.largest_weight = 0.0;
    }

    /// The untried candidates: a uniform pool plus the untried neighbours of the best
    /// observed behaviors.
    fn candidates(
        &self,
        space: &BehaviorSpace,
        tried: &HashSet<Behavior>,
        rng: &mut dyn RngCore,
    ) -> Vec<Behavior> {
        let mut pool = draw_untried(space, tried, MODEL_POOL, rng);
        let mut best: Vec<&Observed> = self.observed.iter().collect();
        best.sort_by(|a, b| (b.sum / b.commands).total_cmp(&(a.sum / a.commands)));
        let mut seen: HashSet<Behavior> = pool.iter().copied().collect();
        for centre in best.into_iter().take(LOCAL_CENTRES) {
            for n in space.neighbours(&centre.behavior) {
                if !tried.contains(&n) && seen.insert(n) {
                    pool.push(n);
                }
            }
        }
        pool
    }
}

/// Per-component kernel factors `s_k(u, v)^(p * m * w_k)`, row-major per component.
struct KernelTables {
    tables: Vec<(usize, Vec<f64>)>,
}

impl KernelTables {
    fn new(space: &BehaviorSpace, sharpness: f64) -> Self {
        let m = space.components().len() as f64;
        let weight_sum: f64 = space.weights().iter().sum();
        let tables = space
            .components()
            .iter()
            .zip(space.weights())
            .map(|(c, w)| {
                let n = c.len();
                let exponent = sharpness * m * w / weight_sum;
                let mut t = vec![0.0; n * n];
                for u in 0..n {
                    for v in 0..n {
                        t[u * n + v] = c.similarity(u as u16, v as u16).powf(exponent);
                    }
                }
                (n, t)
            })
            .collect();
        Self { tables }
    }

    fn kernel(&self, a: &Behavior, b: &Behavior) -> f64 {
        self.tables
            .iter()
            .zip(a.indices().iter().zip(b.indices()))
            .map(|((n, t), (&u, &v))| t[usize::from(u) * n + usize::from(v)])
            .product()
    }
}

/// A surrogate fit to the observations under one kernel.
struct Fit {
    kernels: KernelTables,
    /// The Cholesky factor of the observations' covariance.
    lower: Mat<f64>,
    /// `K^-1 y`.
    alpha: Mat<f64>,
    log_likelihood: f64,
}

fn fit(space: &BehaviorSpace, observed: &[Observed], scale: f64, sharpness: f64) -> Option<Fit> {
    let kernels = KernelTables::new(space, sharpness);
    let n = observed.len();
    let y = Mat::from_fn(n, 1, |i, _| observed[i].sum / observed[i].commands / scale);
    let mut jitter = JITTER;
    for _ in 0..8 {
        let covariance = Mat::from_fn(n, n, |i, j| {
            let k = kernels.kernel(&observed[i].behavior, &observed[j].behavior);
            if i == j {
                k + NOISE_VARIANCE / observed[i].commands + jitter
            } else {
                k
            }
        });
        if let Ok(llt) = covariance.llt(Side::Lower) {
            let alpha = llt.solve(&y);
            let lower = llt.L().to_owned();
            let fit_term: f64 = (0..n).map(|i| y[(i, 0)] * alpha[(i, 0)]).sum();
            let log_det: f64 = (0..n).map(|i| lower[(i, i)].ln()).sum();
            return Some(Fit {
                kernels,
                lower,
                alpha,
                log_likelihood: -0.5 * fit_term - log_det,
            });
        }
        jitter *= 10.0;
    }
    None
}

impl Fit {
    /// `mu / sigma` of the surrogate at every candidate.
    fn scores(&self, observed: &[Observed], candidates: &[Behavior]) -> Vec<f64> {
        let n = observed.len();
        let mut cross = Mat::from_fn(n, candidates.len(), |i, j| {
            self.kernels.kernel(&observed[i].behavior, &candidates[j])
        });
        let means: Vec<f64> = (0..candidates.len())
            .map(|j| (0..n).map(|i| cross[(i, j)] * self.alpha[(i, 0)]).sum())
            .collect();
        solve_lower_triangular_in_place(self.lower.as_ref(), cross.as_mut(), Par::Seq);
        candidates
            .iter()
            .enumerate()
            .map(|(j, c)| {
                let explained: f64 = (0..n).map(|i| cross[(i, j)].powi(2)).sum();
                let variance = (self.kernels.kernel(c, c) - explained).max(1e-12);
                means[j] / variance.sqrt()
            })
            .collect()
    }
}

impl Searcher for ModelBased {
    type Evidence = Evaluated;
    type Feedback = Outcome;

    fn name(&self) -> &str {
        "model-based"
    }

    fn begin_episode(&mut self, _space: &BehaviorSpace, _initial: &Behavior) {
        self.forget();
    }

    fn observe(&mut self, behavior: &Behavior, outcome: &Outcome) {
        let i = *self.index.entry(*behavior).or_insert_with(|| {
            self.observed.push(Observed {
                behavior: *behavior,
                commands: 0.0,
                sum: 0.0,
            });
            self.observed.len() - 1
        });
        let o = &mut self.observed[i];
        o.commands += 1.0;
        o.sum += outcome.kind.sign() * outcome.weight;
        self.largest_weight = self.largest_weight.max(outcome.weight);
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
        let candidates = self.candidates(space, &evaluated_set(evaluated), rng);
        let Some(&first) = candidates.first() else {
            return Proposal::Exhausted {
                keep: e_max.behavior,
            };
        };
        if self.observed.is_empty() || self.largest_weight <= 0.0 {
            return Proposal::Next(first);
        }
        let best_fit = SHARPNESS_CHOICES
            .iter()
            .filter_map(|&p| fit(space, &self.observed, self.largest_weight, p))
            .fold(None, |best: Option<Fit>, f| match best {
                Some(b) if b.log_likelihood >= f.log_likelihood => Some(b),
                _ => Some(f),
            });
        let Some(surrogate) = best_fit else {
            return Proposal::Next(first);
        };
        let scores = surrogate.scores(&self.observed, &candidates);
        let best = scores
            .iter()
            .enumerate()
            .fold(0, |best, (j, &s)| if s > scores[best] { j } else { best });
        Proposal::Next(candidates[best])
    }

    fn end_episode(&mut self, _evaluated: &[Evaluated], _settled: Option<&Behavior>) {
        self.forget();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cbr_core::Component;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn line(n: u16) -> BehaviorSpace {
        BehaviorSpace::new(vec![Component::numeric("x", "", 0.0, 1.0, n).unwrap()]).unwrap()
    }

    #[test]
    fn kernel_by_hand() {
        // One component of 5 values (similarity 1 - |u - v| / 4) at sharpness 2:
        // k(0, 1) = 0.75^2 = 0.5625, k(0, 4) = 0, k(2, 2) = 1.
        let space = line(5);
        let k = KernelTables::new(&space, 2.0);
        let b = |i| Behavior::new(&[i]);
        assert!((k.kernel(&b(0), &b(1)) - 0.5625).abs() < 1e-12);
        assert_eq!(k.kernel(&b(0), &b(4)), 0.0);
        assert_eq!(k.kernel(&b(2), &b(2)), 1.0);
    }

    #[test]
    fn posterior_by_hand() {
        // One observation y = -1 (one failure) at x = 0 on a line of 5, sharpness 1:
        // K = 1 + 1 (noise) = 2, alpha = -0.5. At x = 1: k = 0.75, mu = -0.375,
        // variance = 1 - 0.75^2 / 2 = 0.71875, score = -0.375 / 0.847791 = -0.442326.
        let space = line(5);
        let observed = [Observed {
            behavior: Behavior::new(&[0]),
            commands: 1.0,
            sum: -1.0,
        }];
        let f = fit(&space, &observed, 1.0, 1.0).unwrap();
        assert!((f.alpha[(0, 0)] + 0.5).abs() < 1e-9);
        let scores = f.scores(&observed, &[Behavior::new(&[1]), Behavior::new(&[4])]);
        assert!((scores[0] + 0.442326).abs() < 1e-6, "{}", scores[0]);
        // At x = 4 the kernel is 0: no opinion.
        assert!(scores[1].abs() < 1e-12);
    }

    #[test]
    fn leaves_a_region_the_operator_dislikes_for_one_it_tolerates() {
        // On a line of 40, failures at 0..=3 and mixed outcomes at 30: the best untried
        // candidate lies near 30, not near 0.
        let space = line(40);
        let mut searcher = ModelBased::new();
        let mut evaluated = Vec::new();
        for x in 0..4u16 {
            let b = Behavior::new(&[x]);
            for _ in 0..5 {
                searcher.observe(&b, &Outcome::failed(1.0, crate::Cause::Deadline, 1.0));
            }
            evaluated.push(Evaluated {
                behavior: b,
                time: 5.0,
            });
        }
        let promising = Behavior::new(&[30]);
        for k in 0..12 {
            let o = if k % 3 == 0 {
                Outcome::failed(1.0, crate::Cause::Deadline, 1.0)
            } else {
                Outcome::completed(1.0, 1.0)
            };
            searcher.observe(&promising, &o);
        }
        evaluated.push(Evaluated {
            behavior: promising,
            time: 12.0,
        });
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        match searcher.propose(&space, &evaluated, &mut rng) {
            Proposal::Next(b) => assert!((26..=34).contains(&b.get(0)), "{b:?}"),
            other => panic!("unexpected {other:?}"),
        }
    }
}
