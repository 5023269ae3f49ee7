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

use super::propose_untried;
use super::registry::{Look, Marker, Strategy, WithCases};
use super::untried::draw_untried;
use crate::{Evaluated, Outcome};
use cbr_core::{Behavior, BehaviorSpace, Proposal, Rationale, Searcher};
use faer::linalg::solvers::Llt;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::prelude::*;
use faer::{Mat, Side};
use rand::RngCore;
use rand_distr::{Distribution, StandardNormal};
use std::collections::{HashMap, HashSet};

/// Untried behaviors drawn uniformly and scored per proposal.
pub const MODEL_POOL: usize = 128;

/// Observed behaviors whose untried neighbours join the pool (the best by mean outcome).
const LOCAL_CENTRES: usize = 3;

/// The kernel sharpnesses among which the marginal likelihood chooses.
pub const SHARPNESS_CHOICES: [f64; 4] = [1.0, 2.0, 4.0, 8.0];

/// Noise variance of one observation, in units of the largest weight seen (an outcome
/// is `+-1` around a mean in `[-1, 1]`, so its variance is at most 1).
const NOISE_VARIANCE: f64 = 1.0;

/// Added to the kernel's diagonal when it is not positive definite, growing tenfold.
const JITTER: f64 = 1e-9;

/// Added to the posterior covariance's diagonal before drawing from it (it is singular
/// where candidates coincide in kernel terms), growing tenfold when not enough.
const POSTERIOR_JITTER: f64 = 1e-8;

/// One observed behavior: commands seen and the sum of their signed weights.
#[derive(Clone, Copy, Debug)]
struct Observed {
    behavior: Behavior,
    commands: f64,
    sum: f64,
}

/// Strength of the population mean in each per-value mean, in commands (shrinkage).
const PRIOR_COMMANDS: f64 = 20.0;

/// Mean signed outcome by component value over the earlier episodes: the surrogate's
/// prior mean, a main-effects model `mu + sum_k (mu_k(v_k) - mu)`, each per-value mean
/// shrunk towards the overall mean `mu`.
#[derive(Clone, Debug, Default)]
struct PopulationMeans {
    commands: f64,
    sum: f64,
    /// `by_value[k][v]`: (commands, sum of signed outcomes) with component `k` at `v`.
    by_value: Vec<Vec<(f64, f64)>>,
}

impl PopulationMeans {
    fn add(&mut self, o: &Observed) {
        self.commands += o.commands;
        self.sum += o.sum;
        if self.by_value.len() < o.behavior.len() {
            self.by_value.resize(o.behavior.len(), Vec::new());
        }
        for (k, &v) in o.behavior.indices().iter().enumerate() {
            let values = &mut self.by_value[k];
            let v = usize::from(v);
            if values.len() <= v {
                values.resize(v + 1, (0.0, 0.0));
            }
            values[v].0 += o.commands;
            values[v].1 += o.sum;
        }
    }

    /// The prior mean signed outcome at `behavior` (0 before any episode has ended).
    fn mean(&self, behavior: &Behavior) -> f64 {
        if self.commands == 0.0 {
            return 0.0;
        }
        let overall = self.sum / self.commands;
        overall
            + behavior
                .indices()
                .iter()
                .enumerate()
                .map(|(k, &v)| {
                    let (n, sum) = self
                        .by_value
                        .get(k)
                        .and_then(|values| values.get(usize::from(v)))
                        .copied()
                        .unwrap_or((0.0, 0.0));
                    (sum + PRIOR_COMMANDS * overall) / (n + PRIOR_COMMANDS) - overall
                })
                .sum::<f64>()
    }
}

/// The model-based searcher.
#[derive(Clone, Debug, Default)]
pub struct ModelBased {
    observed: Vec<Observed>,
    index: HashMap<Behavior, usize>,
    population: PopulationMeans,
    largest_weight: f64,
}

/// The model-based search as the tool offers it, alone and after case reuse.
pub const STRATEGY: Strategy = Strategy {
    name: "model-based",
    description: "a Gaussian-process model of the current operator's reactions over the behavior space picks the next behavior",
    look: Look {
        colour: [0, 158, 115],
        marker: Marker::TriangleDown,
    },
    with_cases: Some(WithCases {
        name: "case-based+model-based",
        description: "case reuse first, the model-based search when no case fits",
        look: Look {
            colour: [120, 120, 120],
            marker: Marker::Star,
        },
    }),
    build: || Box::new(ModelBased::new()),
};

impl ModelBased {
    /// A model-based searcher.
    pub fn new() -> Self {
        Self::default()
    }

    /// Ends the episode's surrogate; its observations join the population means.
    fn close_episode(&mut self) {
        for o in &self.observed {
            self.population.add(o);
        }
        self.observed.clear();
        self.index.clear();
    }

    /// The prior mean at `behavior`, in units of the largest weight seen, in `[-1, 1]`.
    fn prior_mean(&self, behavior: &Behavior) -> f64 {
        (self.population.mean(behavior) / self.largest_weight).clamp(-1.0, 1.0)
    }

    /// The untried behavior to try: the best of one joint posterior draw over the
    /// candidates; the first candidate while there is nothing to fit. `None` when every
    /// behavior has been tried.
    fn choose(
        &self,
        space: &BehaviorSpace,
        tried: &HashSet<Behavior>,
        rng: &mut dyn RngCore,
    ) -> Option<Behavior> {
        let candidates = self.candidates(space, tried, rng);
        let &first = candidates.first()?;
        if self.observed.is_empty() || self.largest_weight <= 0.0 {
            return Some(first);
        }
        let residuals: Vec<f64> = self
            .observed
            .iter()
            .map(|o| o.sum / o.commands / self.largest_weight - self.prior_mean(&o.behavior))
            .collect();
        let best_fit = SHARPNESS_CHOICES
            .iter()
            .filter_map(|&p| fit(space, &self.observed, &residuals, p))
            .fold(None, |best: Option<Fit>, f| match best {
                Some(b) if b.log_likelihood >= f.log_likelihood => Some(b),
                _ => Some(f),
            });
        let Some(surrogate) = best_fit else {
            return Some(first);
        };
        let prior_means: Vec<f64> = candidates.iter().map(|c| self.prior_mean(c)).collect();
        let Some(scores) = surrogate.sample(&self.observed, &candidates, &prior_means, rng) else {
            return Some(first);
        };
        let best = scores
            .iter()
            .enumerate()
            .fold(0, |best, (j, &s)| if s > scores[best] { j } else { best });
        Some(candidates[best])
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

/// Fits the surrogate's deviation from the prior mean: `residuals[i]` is observation
/// `i`'s mean outcome (in units of the largest weight) minus the prior mean there.
fn fit(
    space: &BehaviorSpace,
    observed: &[Observed],
    residuals: &[f64],
    sharpness: f64,
) -> Option<Fit> {
    let kernels = KernelTables::new(space, sharpness);
    let n = observed.len();
    let y = Mat::from_fn(n, 1, |i, _| residuals[i]);
    let covariance = Mat::from_fn(n, n, |i, j| {
        let k = kernels.kernel(&observed[i].behavior, &observed[j].behavior);
        if i == j {
            k + NOISE_VARIANCE / observed[i].commands
        } else {
            k
        }
    });
    let llt = factor_with_jitter(&covariance, JITTER)?;
    let alpha = llt.solve(&y);
    let lower = llt.L().to_owned();
    let fit_term: f64 = (0..n).map(|i| y[(i, 0)] * alpha[(i, 0)]).sum();
    let log_det: f64 = (0..n).map(|i| lower[(i, i)].ln()).sum();
    Some(Fit {
        kernels,
        lower,
        alpha,
        log_likelihood: -0.5 * fit_term - log_det,
    })
}

/// The Cholesky factorisation of `matrix + jitter I`, the jitter starting at `first` and
/// growing tenfold (eight tries) while the matrix is not positive definite.
fn factor_with_jitter(matrix: &Mat<f64>, first: f64) -> Option<Llt<f64>> {
    let n = matrix.nrows();
    let mut jitter = first;
    for _ in 0..8 {
        let jittered = Mat::from_fn(n, n, |i, j| {
            matrix[(i, j)] + if i == j { jitter } else { 0.0 }
        });
        if let Ok(llt) = jittered.llt(Side::Lower) {
            return Some(llt);
        }
        jitter *= 10.0;
    }
    None
}

impl Fit {
    /// The posterior of the surrogate's deviation from the prior mean at `candidates`:
    /// its mean `K*^T alpha` and covariance `K** - K*^T K^-1 K*`.
    fn posterior(&self, observed: &[Observed], candidates: &[Behavior]) -> (Vec<f64>, Mat<f64>) {
        let (n, c) = (observed.len(), candidates.len());
        let mut cross = Mat::from_fn(n, c, |i, j| {
            self.kernels.kernel(&observed[i].behavior, &candidates[j])
        });
        let means = cross.transpose() * &self.alpha;
        solve_lower_triangular_in_place(self.lower.as_ref(), cross.as_mut(), Par::Seq);
        let prior = Mat::from_fn(c, c, |i, j| {
            self.kernels.kernel(&candidates[i], &candidates[j])
        });
        let covariance = prior - cross.transpose() * &cross;
        ((0..c).map(|j| means[(j, 0)]).collect(), covariance)
    }

    /// One joint draw of the surrogate at every candidate (Thompson sampling): the prior
    /// mean plus a draw of the posterior deviation, through the Cholesky factor of its
    /// covariance. `None` if that covariance cannot be factored even with jitter.
    fn sample(
        &self,
        observed: &[Observed],
        candidates: &[Behavior],
        prior_means: &[f64],
        rng: &mut dyn RngCore,
    ) -> Option<Vec<f64>> {
        let (means, covariance) = self.posterior(observed, candidates);
        let c = candidates.len();
        let normals: Vec<f64> = (0..c).map(|_| StandardNormal.sample(&mut *rng)).collect();
        let llt = factor_with_jitter(&covariance, POSTERIOR_JITTER)?;
        let factor = llt.L();
        Some(
            (0..c)
                .map(|j| {
                    prior_means[j]
                        + means[j]
                        + (0..=j).map(|k| factor[(j, k)] * normals[k]).sum::<f64>()
                })
                .collect(),
        )
    }
}

impl Searcher for ModelBased {
    type Evidence = Evaluated;
    type Feedback = Outcome;

    fn name(&self) -> &str {
        STRATEGY.name
    }

    // It proposes from the episode's own outcomes alone: told a context or statements, it
    // proposes the same.
    fn reads_context(&self) -> bool {
        false
    }

    fn hears_statements(&self) -> bool {
        false
    }

    fn learns_across_episodes(&self) -> bool {
        true
    }

    fn begin_episode(&mut self, _space: &BehaviorSpace, _initial: &Behavior) {
        self.close_episode();
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
        propose_untried(space, evaluated, rng, |tried, rng| {
            self.choose(space, tried, rng)
        })
    }

    fn rationale(&self, _proposed: &Behavior) -> Rationale {
        if self.observed.is_empty() || self.largest_weight <= 0.0 {
            return Rationale::Explores {
                how: "no outcome weighed yet: an untried behavior drawn uniformly".into(),
            };
        }
        let commands: f64 = self.observed.iter().map(|o| o.commands).sum();
        Rationale::Expects {
            what: format!(
                "a better reaction, by a model of this operator fit to {commands} commands"
            )
            .into(),
            confidence: None,
        }
    }

    fn end_episode(&mut self, _evaluated: &[Evaluated], _settled: Option<&Behavior>) {
        self.close_episode();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::search::grid;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn line(n: u16) -> BehaviorSpace {
        grid(&[n])
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
        // K = 1 + 1 (noise) = 2, alpha = -0.5. At x = 1: k = 0.75, mean = -0.375,
        // variance = 1 - 0.75^2 / 2 = 0.71875. At x = 4 the kernel is 0: mean 0,
        // variance 1, and the covariance of x = 1 and x = 4 is 0.25 - 0.75 * 0 / 2 = 0.25.
        let space = line(5);
        let observed = [Observed {
            behavior: Behavior::new(&[0]),
            commands: 1.0,
            sum: -1.0,
        }];
        let f = fit(&space, &observed, &[-1.0], 1.0).unwrap();
        assert!((f.alpha[(0, 0)] + 0.5).abs() < 1e-9);
        let (means, covariance) =
            f.posterior(&observed, &[Behavior::new(&[1]), Behavior::new(&[4])]);
        assert!((means[0] + 0.375).abs() < 1e-9);
        assert!(means[1].abs() < 1e-12);
        assert!((covariance[(0, 0)] - 0.71875).abs() < 1e-9);
        assert!((covariance[(1, 1)] - 1.0).abs() < 1e-9);
        assert!((covariance[(0, 1)] - 0.25).abs() < 1e-9);
    }

    #[test]
    fn the_prior_mean_is_learned_from_earlier_episodes() {
        // Earlier episodes: 10 completions at x = 3 and 10 failures at x = 0, weight 1.
        // Overall mean 0; at x = 3 the shrunk mean is (10 + 20 * 0) / (10 + 20) = 1/3,
        // at x = 0 it is -1/3, and at an unseen value the overall mean, 0.
        let mut searcher = ModelBased::new();
        let (good, bad) = (Behavior::new(&[3]), Behavior::new(&[0]));
        for _ in 0..10 {
            searcher.observe(&good, &Outcome::completed(1.0, 1.0));
            searcher.observe(&bad, &Outcome::failed(1.0, 1.0));
        }
        // Nothing is known before the episode ends.
        assert_eq!(searcher.prior_mean(&good), 0.0);
        searcher.end_episode(&[], None);
        assert!((searcher.prior_mean(&good) - 1.0 / 3.0).abs() < 1e-12);
        assert!((searcher.prior_mean(&bad) + 1.0 / 3.0).abs() < 1e-12);
        assert_eq!(searcher.prior_mean(&Behavior::new(&[2])), 0.0);
    }

    #[test]
    fn leaves_a_region_the_operator_dislikes_for_one_it_tolerates() {
        // On a line of 40, failures at 0..=3 and mostly completions at 30: the draws
        // land near 30, not near 0.
        let space = line(40);
        let mut searcher = ModelBased::new();
        let mut evaluated = Vec::new();
        for x in 0..4u16 {
            let b = Behavior::new(&[x]);
            for _ in 0..5 {
                searcher.observe(&b, &Outcome::failed(1.0, 1.0));
            }
            evaluated.push(Evaluated {
                behavior: b,
                time: 5.0,
            });
        }
        let promising = Behavior::new(&[30]);
        for k in 0..12 {
            let o = if k % 4 == 0 {
                Outcome::failed(1.0, 1.0)
            } else {
                Outcome::completed(1.0, 1.0)
            };
            searcher.observe(&promising, &o);
        }
        evaluated.push(Evaluated {
            behavior: promising,
            time: 12.0,
        });
        let mut near = 0;
        for seed in 0..100 {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            match searcher.propose(&space, &evaluated, &mut rng) {
                Proposal::Next(b) => {
                    assert!(b.get(0) > 6, "{b:?} is next to the failures");
                    near += usize::from((24..=36).contains(&b.get(0)));
                }
                other => panic!("unexpected {other:?}"),
            }
        }
        // Uniform draws would land there 12 times in 35 (34%).
        assert!(
            near >= 45,
            "only {near} of 100 draws near the promising behavior"
        );
    }
}
