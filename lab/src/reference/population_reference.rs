//! The population reference: an agent that knows every member of a population (each
//! member's step law on every behavior, as the known-operator limit estimates it: a
//! [`Member`]) and how often each member appears, but not which member it faces. It pays
//! what an arm that had learned everything about the members would still pay for not being
//! told which one it faces: what is left between it and the known-operator limit is the
//! cost of telling members apart; what is left between an arm and it is the cost of
//! learning.
//!
//! **It is an agent, not a bound.** The exactly optimal agent for a mixture of members
//! would plan over every future observation (a partially observed decision problem far too
//! large to solve). This agent is greedy in the posterior instead:
//!
//! - it keeps a posterior over members, `w_m ∝ prior_m · Π P_m(outcome)`, updated after
//!   every command with the probability of the command's outcome (its contribution to the
//!   estimate and whether it was untrustworthy) under each member's step law for the
//!   behavior in use; a member under whose law an outcome cannot happen is ruled out;
//! - when it needs a behavior (at the start, and after each rejection) it takes, among the
//!   behaviors it has not tried, the one with the lowest `Σ_m w_m c_m(b) / Σ_m w_m p_m(b)`,
//!   `p_m(b)` being the probability that member `m` accepts behavior `b` and `c_m(b)` the
//!   metric's expected cost of its walk (1 for behaviors, the expected commands, the
//!   expected untrustworthy commands: [`WalkOutcome`]). With a single member this is the
//!   limit's optimal order ([`crate::reference::limit`]: ascending `c / p`), so with one
//!   member the agent *is* the limit's agent; with several it is the limit's rule applied to
//!   what it believes, re-planned after every rejection. Ties go to the lowest rank;
//! - each metric has its own agent (as the limit has its own order per metric), and each
//!   runs under both of the limit's protocols: its first behavior uniformly random (the
//!   paper's), or chosen by the rule from the prior.
//!
//! Facing member `m` no agent, however it chooses, can expect to pay less than `m`'s own
//! limit (behaviors are independent, so what one behavior shows tells nothing of another's
//! outcome *for a known member*): the reference is at or above the limit, up to the
//! simulation's noise.
//!
//! **How it is computed.** By simulation, stratified over members: `episodes` episodes per
//! member (each on its own seeded stream, [`Purpose::PopulationReference`], one per member
//! and episode, which every metric's agent reuses), the walks drawn from the member's step
//! laws;
//! the reference is `Σ_m prior_m · mean_m` with the standard error
//! `sqrt(Σ_m prior_m² · var_m / episodes)`. The paper protocol's first behaviors are a
//! stratified sample of the space per member (episode `i` of `n` starts at rank
//! `⌊(i + u_i) / n · N⌋`, each `u_i` uniform on its own, so every rank is as likely as in
//! the paper's draw and a small space is covered evenly; one `u` for every episode would
//! start them all a fixed stride apart, and a stride can fall in step with the ranks'
//! components, as 40 does in patrol's 16,000). Once every member but one has less than
//! [`RULED_OUT`] of the posterior, the agent follows that
//! member's optimal order (the rule's choice up to a part in a billion, without a scan of
//! the space). When no untried behavior can be accepted by any member the posterior still
//! allows, the agent would walk through every remaining behavior: the episode ends there
//! and is charged the expected cost of those walks under the member faced.

use crate::reference::limit::{Costs, SUM_TOLERANCE, Step, WalkOutcome, optimal_order};
use crate::seeds::{Purpose, stream};
use rand::Rng;
use rayon::prelude::*;
use trust::{Thresholds, Verdict};

/// The share of the posterior below which every other member counts as ruled out, and the
/// agent follows the remaining member's optimal order without scanning the space.
pub const RULED_OUT: f64 = 1e-9;

/// One member of a population as the reference knows it: how often it appears and, per
/// behavior in rank order, its walk and its step law.
#[derive(Clone, Copy, Debug)]
pub struct Member<'a> {
    /// How often it appears (any positive scale: the weights are normalized).
    pub weight: f64,
    /// Per behavior, its walk solved from its step law.
    pub walks: &'a [WalkOutcome],
    /// The distinct step laws.
    pub laws: &'a [Vec<Step>],
    /// Per behavior, which of `laws` is its step law.
    pub law_of: &'a [usize],
}

impl Member<'_> {
    /// The step law of the behavior of rank `rank`.
    fn law(&self, rank: usize) -> &[Step] {
        &self.laws[self.law_of[rank]]
    }
}

/// How the population reference is simulated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReferencePlan {
    /// The thresholds every walk runs between.
    pub thresholds: Thresholds,
    /// Episodes simulated per member, per metric and protocol.
    pub episodes: usize,
    /// The seed of the episodes' streams.
    pub seed: u64,
}

/// The population reference of a population: its mean costs, each metric's by the agent
/// for that metric, and their standard errors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PopulationReference {
    /// Under the paper's protocol: the first behavior uniformly random.
    pub paper: Costs,
    /// The standard errors of [`PopulationReference::paper`].
    pub paper_error: Costs,
    /// Free to choose the first behavior.
    pub free_first: Costs,
    /// The standard errors of [`PopulationReference::free_first`].
    pub free_first_error: Costs,
    /// Episodes simulated per member (per metric and protocol).
    pub episodes: usize,
}

/// Why the population reference could not be computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ReferenceError {
    /// No member, or a plan of fewer than two episodes per member (no standard error).
    #[error(
        "the population reference needs at least one member and two episodes per member (got {members} and {episodes})"
    )]
    TooSmall {
        /// Members given.
        members: usize,
        /// Episodes per member planned.
        episodes: usize,
    },
    /// A member's weight is not finite and positive.
    #[error("member {member}'s weight is {weight}; it must be finite and above 0")]
    Weight {
        /// The member's place.
        member: usize,
        /// Its weight.
        weight: f64,
    },
    /// Members know spaces of different sizes.
    #[error("member {member} knows {behaviors} behaviors, member 0 knows {expected}")]
    Spaces {
        /// The member's place.
        member: usize,
        /// Its behaviors.
        behaviors: usize,
        /// Member 0's.
        expected: usize,
    },
    /// The computation was asked to stop.
    #[error(transparent)]
    Interrupted(#[from] crate::Interrupted),
}

/// The metrics in [`Costs`]' order.
const METRICS: usize = 3;

/// What one metric's agent knows: per behavior and member (behavior-major, so a scan reads
/// the space in one pass), the acceptance probability and the metric's expected cost; per
/// member, its optimal order; and the rule's choice from the prior.
struct MetricView {
    accept: Vec<f64>,
    cost: Vec<f64>,
    orders: Vec<Vec<usize>>,
    from_prior: Option<usize>,
}

/// The population as the agent knows it.
struct Population<'a> {
    members: Vec<Member<'a>>,
    prior: Vec<f64>,
    behaviors: usize,
    thresholds: Thresholds,
}

/// The expected cost of a walk in each metric.
fn walk_costs(walk: &WalkOutcome) -> [f64; METRICS] {
    [1.0, walk.commands, walk.untrustworthy]
}

impl Population<'_> {
    /// What the agent for metric `metric` knows.
    fn view(&self, metric: usize) -> MetricView {
        let m = self.members.len();
        let mut accept = vec![0.0; self.behaviors * m];
        let mut cost = vec![0.0; self.behaviors * m];
        for (k, member) in self.members.iter().enumerate() {
            for (b, walk) in member.walks.iter().enumerate() {
                accept[b * m + k] = walk.accept;
                cost[b * m + k] = walk_costs(walk)[metric];
            }
        }
        let orders = self
            .members
            .iter()
            .map(|member| {
                let p: Vec<f64> = member.walks.iter().map(|w| w.accept).collect();
                let c: Vec<f64> = member.walks.iter().map(|w| walk_costs(w)[metric]).collect();
                optimal_order(&p, &c)
            })
            .collect();
        let mut view = MetricView {
            accept,
            cost,
            orders,
            from_prior: None,
        };
        view.from_prior = scan(&view, &self.prior, &vec![false; self.behaviors]);
        view
    }

    /// The behavior the agent takes next under the posterior `log_weights`, having tried
    /// `tried`; `None` when no untried behavior can be accepted by a member still possible.
    fn choose(&self, view: &MetricView, log_weights: &[f64], tried: &[bool]) -> Option<usize> {
        let top = log_weights
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        let weights: Vec<f64> = log_weights.iter().map(|lw| (lw - top).exp()).collect();
        let total: f64 = weights.iter().sum();
        let (leader, lead) =
            weights
                .iter()
                .copied()
                .enumerate()
                .fold((0, f64::NEG_INFINITY), |best, (k, w)| {
                    if w > best.1 { (k, w) } else { best }
                });
        if (total - lead) / total < RULED_OUT {
            let member = &self.members[leader];
            return view.orders[leader]
                .iter()
                .copied()
                .find(|&b| !tried[b])
                .filter(|&b| member.walks[b].accept > 0.0);
        }
        scan(view, &weights, tried)
    }

    /// One episode of the agent for `view` facing member `truth`, starting from `first`
    /// (`None`: the rule's choice from the prior): its behaviors, commands and
    /// untrustworthy commands.
    fn episode<R: Rng>(
        &self,
        view: &MetricView,
        truth: usize,
        first: Option<usize>,
        rng: &mut R,
    ) -> [f64; METRICS] {
        let facing = &self.members[truth];
        let mut log_weights: Vec<f64> = self.prior.iter().map(|w| w.ln()).collect();
        let mut tried = vec![false; self.behaviors];
        let mut spent = [0.0; METRICS];
        let mut next = first.or(view.from_prior);
        while let Some(behavior) = next {
            tried[behavior] = true;
            spent[0] += 1.0;
            let law = facing.law(behavior);
            let mut estimate = 0.0;
            let accepted = loop {
                let step = draw(law, rng);
                spent[1] += 1.0;
                spent[2] += f64::from(u8::from(step.untrustworthy));
                for (k, member) in self.members.iter().enumerate() {
                    log_weights[k] += likelihood(member.law(behavior), &step).ln();
                }
                estimate += step.delta;
                match self.thresholds.verdict(estimate) {
                    Verdict::Trustworthy => break true,
                    Verdict::Untrustworthy => break false,
                    Verdict::Undecided => {}
                }
            };
            if accepted {
                return spent;
            }
            next = self.choose(view, &log_weights, &tried);
        }
        // Nothing left that a possible member accepts: every remaining behavior would be
        // walked and rejected; charge what those walks cost the member faced.
        for (b, walk) in facing.walks.iter().enumerate() {
            if !tried[b] {
                spent[0] += 1.0;
                spent[1] += walk.commands;
                spent[2] += walk.untrustworthy;
            }
        }
        spent
    }
}

/// The untried behavior with the lowest `Σ w c / Σ w p` under `weights` (ties: the lowest
/// rank); `None` when every untried behavior has `Σ w p = 0`.
fn scan(view: &MetricView, weights: &[f64], tried: &[bool]) -> Option<usize> {
    let m = weights.len();
    let mut best: Option<(usize, f64, f64)> = None;
    for (b, _) in tried.iter().enumerate().filter(|(_, t)| !**t) {
        let (p, c) = (
            &view.accept[b * m..(b + 1) * m],
            &view.cost[b * m..(b + 1) * m],
        );
        let den: f64 = weights.iter().zip(p).map(|(w, p)| w * p).sum();
        if den <= 0.0 {
            continue;
        }
        let num: f64 = weights.iter().zip(c).map(|(w, c)| w * c).sum();
        match best {
            Some((_, best_num, best_den)) if num * best_den >= best_num * den => {}
            _ => best = Some((b, num, den)),
        }
    }
    best.map(|(b, _, _)| b)
}

/// One command's outcome drawn from a step law.
fn draw<R: Rng>(law: &[Step], rng: &mut R) -> Step {
    let total: f64 = law.iter().map(|s| s.prob).sum();
    let mut u = rng.random::<f64>() * total;
    for step in law {
        if u < step.prob {
            return *step;
        }
        u -= step.prob;
    }
    *law.iter()
        .rev()
        .find(|s| s.prob > 0.0)
        .expect("a solved step law has a step of positive probability")
}

/// The probability of `outcome` under `law`: the share of its steps with the same
/// contribution (within [`SUM_TOLERANCE`]) and the same verdict on trust.
fn likelihood(law: &[Step], outcome: &Step) -> f64 {
    law.iter()
        .filter(|s| {
            s.untrustworthy == outcome.untrustworthy
                && (s.delta - outcome.delta).abs() <= SUM_TOLERANCE
        })
        .map(|s| s.prob)
        .sum()
}

/// The mean and variance of samples (the variance with `n - 1`).
fn mean_variance(samples: &[f64]) -> (f64, f64) {
    let n = samples.len() as f64;
    let mean = samples.iter().sum::<f64>() / n;
    let variance = samples.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, variance)
}

/// The population reference of `members` under `plan`.
pub fn population_reference(
    members: &[Member<'_>],
    plan: ReferencePlan,
) -> Result<PopulationReference, ReferenceError> {
    let population = population(members, plan)?;
    let n = plan.episodes;
    let mut paper = [[0.0; 2]; METRICS];
    let mut free = [[0.0; 2]; METRICS];
    for metric in 0..METRICS {
        let view = population.view(metric);
        for (k, &weight) in population.prior.iter().enumerate() {
            let runs = (0..n)
                .into_par_iter()
                .map(|i| {
                    crate::interrupt::check()?;
                    let mut rng =
                        stream(plan.seed, k as u64, i as u64, Purpose::PopulationReference);
                    let stratum = (i as f64 + rng.random::<f64>()) / n as f64;
                    let first = ((stratum * population.behaviors as f64) as usize)
                        .min(population.behaviors - 1);
                    let random_first = population.episode(&view, k, Some(first), &mut rng);
                    let mut rng =
                        stream(plan.seed, k as u64, i as u64, Purpose::PopulationReference);
                    let chosen_first = population.episode(&view, k, None, &mut rng);
                    Ok((random_first[metric], chosen_first[metric]))
                })
                .collect::<Result<Vec<(f64, f64)>, crate::Interrupted>>()?;
            for (sums, samples) in [
                (
                    &mut paper[metric],
                    runs.iter().map(|r| r.0).collect::<Vec<_>>(),
                ),
                (&mut free[metric], runs.iter().map(|r| r.1).collect()),
            ] {
                let (mean, variance) = mean_variance(&samples);
                sums[0] += weight * mean;
                sums[1] += weight * weight * variance / n as f64;
            }
        }
    }
    let costs = |sums: &[[f64; 2]; METRICS], at: usize, f: fn(f64) -> f64| Costs {
        behaviors: f(sums[0][at]),
        commands: f(sums[1][at]),
        untrustworthy: f(sums[2][at]),
    };
    Ok(PopulationReference {
        paper: costs(&paper, 0, |x| x),
        paper_error: costs(&paper, 1, f64::sqrt),
        free_first: costs(&free, 0, |x| x),
        free_first_error: costs(&free, 1, f64::sqrt),
        episodes: n,
    })
}

/// The population of `members` with normalized weights, checked.
fn population<'a>(
    members: &[Member<'a>],
    plan: ReferencePlan,
) -> Result<Population<'a>, ReferenceError> {
    if members.is_empty() || plan.episodes < 2 {
        return Err(ReferenceError::TooSmall {
            members: members.len(),
            episodes: plan.episodes,
        });
    }
    if let Some((member, m)) = members
        .iter()
        .enumerate()
        .find(|(_, m)| !(m.weight.is_finite() && m.weight > 0.0))
    {
        return Err(ReferenceError::Weight {
            member,
            weight: m.weight,
        });
    }
    let expected = members[0].walks.len();
    if let Some((member, m)) = members
        .iter()
        .enumerate()
        .find(|(_, m)| m.walks.len() != expected || m.law_of.len() != expected)
    {
        return Err(ReferenceError::Spaces {
            member,
            behaviors: m.walks.len().min(m.law_of.len()),
            expected,
        });
    }
    let total: f64 = members.iter().map(|m| m.weight).sum();
    Ok(Population {
        members: members.to_vec(),
        prior: members.iter().map(|m| m.weight / total).collect(),
        behaviors: expected,
        thresholds: plan.thresholds,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::limit::{DEFAULT_MAX_STATES, Limit, solve_walk};

    const COMPLETES: Step = Step {
        prob: 1.0,
        delta: 1.0,
        untrustworthy: false,
    };
    const FAILS: Step = Step {
        prob: 1.0,
        delta: -1.0,
        untrustworthy: true,
    };

    /// An operator whose behavior of rank `r` has the step law `laws[r]`, with its walks
    /// solved and its limit.
    struct Known {
        laws: Vec<Vec<Step>>,
        law_of: Vec<usize>,
        walks: Vec<WalkOutcome>,
        limit: Limit,
    }

    impl Known {
        /// It as a member met `weight` times as often as a member of weight 1.
        fn weighing(&self, weight: f64) -> Member<'_> {
            Member {
                weight,
                walks: &self.walks,
                laws: &self.laws,
                law_of: &self.law_of,
            }
        }
    }

    fn member(laws: &[Vec<Step>]) -> Known {
        let walks: Vec<WalkOutcome> = laws
            .iter()
            .map(|l| solve_walk(l, Thresholds::default(), DEFAULT_MAX_STATES).unwrap())
            .collect();
        Known {
            laws: laws.to_vec(),
            law_of: (0..laws.len()).collect(),
            limit: Limit::from_outcomes(&walks).unwrap(),
            walks,
        }
    }

    fn plan(episodes: usize) -> ReferencePlan {
        ReferencePlan {
            thresholds: Thresholds::default(),
            episodes,
            seed: 7,
        }
    }

    fn assert_costs(actual: Costs, expected: [f64; 3]) {
        let got = [actual.behaviors, actual.commands, actual.untrustworthy];
        for (g, e) in got.iter().zip(expected) {
            assert!((g - e).abs() < 1e-9, "{got:?} != {expected:?}");
        }
    }

    #[test]
    fn two_members_who_trust_opposite_behaviors_are_told_apart_by_one_rejection() {
        // A completes behavior 0 always and fails behavior 1 always; B the reverse; A is
        // met three times as often. Thresholds +-5: an accepted walk is 5 completions, a
        // rejected one 5 untrustworthy commands.
        let a = member(&[vec![COMPLETES], vec![FAILS]]);
        let b = member(&[vec![FAILS], vec![COMPLETES]]);
        let reference = population_reference(&[a.weighing(3.0), b.weighing(1.0)], plan(4)).unwrap();
        // Free first: the prior makes behavior 0 the better bet for every metric (accepted
        // with 3/4; untrustworthy cost 5/4 against 15/4). Facing A: 1 behavior, 5
        // commands, 0 untrustworthy; facing B: 0 is rejected (5 failures rule A out), then
        // 1 is accepted: 2, 10, 5. In all 3/4 (1, 5, 0) + 1/4 (2, 10, 5).
        assert_costs(reference.free_first, [1.25, 6.25, 1.25]);
        assert_costs(reference.free_first_error, [0.0, 0.0, 0.0]);
        // Random first: half the episodes start at 0 (as above), half at 1: facing A, 1 is
        // rejected and 0 accepted (2, 10, 5); facing B, accepted at once (1, 5, 0), so
        // 3/4 (2, 10, 5) + 1/4 (1, 5, 0) = (1.75, 8.75, 3.75); the mean of both halves:
        assert_costs(reference.paper, [1.5, 7.5, 2.5]);
        // The limit: each member, told, takes its own behavior at once.
        assert_costs(a.limit.free_first, [1.0, 5.0, 0.0]);
    }

    #[test]
    fn a_behavior_every_member_trusts_makes_telling_them_apart_free() {
        let a = member(&[vec![COMPLETES], vec![FAILS], vec![COMPLETES]]);
        let b = member(&[vec![FAILS], vec![COMPLETES], vec![COMPLETES]]);
        let reference = population_reference(&[a.weighing(3.0), b.weighing(1.0)], plan(6)).unwrap();
        // Behavior 2 is accepted whoever is faced: the rule takes it first.
        assert_costs(reference.free_first, [1.0, 5.0, 0.0]);
        assert_costs(a.limit.free_first, [1.0, 5.0, 0.0]);
        // Random first: behaviors 0, 1 and 2 each start a third of each member's episodes
        // (episodes 0-1, 2-3, 4-5). Facing A: from 0 accepted (1, 5, 0); from 1 rejected
        // then 2 (2, 10, 5); from 2 (1, 5, 0). Facing B: from 0 (2, 10, 5); from 1 and 2
        // (1, 5, 0). Each member's mean is (4/3, 20/3, 5/3), as is the limit's.
        assert_costs(reference.paper, [4.0 / 3.0, 20.0 / 3.0, 5.0 / 3.0]);
        assert_costs(a.limit.paper, [4.0 / 3.0, 20.0 / 3.0, 5.0 / 3.0]);
    }

    /// A behavior that completes with probability `p` (+1) and else fails (-1).
    fn coin(p: f64) -> Vec<Step> {
        vec![
            Step {
                prob: p,
                delta: 1.0,
                untrustworthy: false,
            },
            Step {
                prob: 1.0 - p,
                delta: -1.0,
                untrustworthy: true,
            },
        ]
    }

    /// Whether every metric of `simulated` lies within four standard errors (and a hair)
    /// of `exact`.
    fn within(simulated: Costs, error: Costs, exact: Costs) -> bool {
        let metric = |c: Costs| [c.behaviors, c.commands, c.untrustworthy];
        metric(simulated)
            .iter()
            .zip(metric(error))
            .zip(metric(exact))
            .all(|((s, e), x)| (s - x).abs() <= 4.0 * e + 1e-9)
    }

    #[test]
    fn with_one_member_the_simulated_agent_is_the_limits_agent() {
        let laws: Vec<Vec<Step>> = [0.3, 0.55, 0.7, 0.45, 0.9, 0.6]
            .into_iter()
            .map(coin)
            .collect();
        let known = member(&laws);
        let r = population_reference(&[known.weighing(1.0)], plan(3000)).unwrap();
        assert!(within(r.paper, r.paper_error, known.limit.paper), "{r:?}");
        assert!(within(
            r.free_first,
            r.free_first_error,
            known.limit.free_first
        ));
        assert!(r.paper_error.untrustworthy > 0.0);
    }

    #[test]
    fn members_that_disagree_cost_more_than_their_limits() {
        // Each member's best behavior is another's worst: the agent pays to find out.
        let a = member(&[coin(0.95), coin(0.2), coin(0.5)]);
        let b = member(&[coin(0.2), coin(0.95), coin(0.5)]);
        let r = population_reference(&[a.weighing(1.0), b.weighing(1.0)], plan(3000)).unwrap();
        let limit = Limit::mean_of(&[a.limit, b.limit]).unwrap();
        let above = |reference: f64, error: f64, limit: f64| reference > limit + 4.0 * error;
        assert!(above(
            r.free_first.untrustworthy,
            r.free_first_error.untrustworthy,
            limit.free_first.untrustworthy
        ));
        assert!(
            r.paper.untrustworthy + 4.0 * r.paper_error.untrustworthy > limit.paper.untrustworthy
        );
    }

    #[test]
    fn a_population_it_cannot_simulate_is_refused() {
        let a = member(&[vec![COMPLETES]]);
        let b = member(&[vec![COMPLETES], vec![FAILS]]);
        assert!(matches!(
            population_reference(&[], plan(4)),
            Err(ReferenceError::TooSmall { members: 0, .. })
        ));
        assert!(matches!(
            population_reference(&[a.weighing(1.0)], plan(1)),
            Err(ReferenceError::TooSmall { episodes: 1, .. })
        ));
        assert_eq!(
            population_reference(&[a.weighing(1.0), a.weighing(0.0)], plan(4)).unwrap_err(),
            ReferenceError::Weight {
                member: 1,
                weight: 0.0
            }
        );
        let spaces =
            population_reference(&[a.weighing(1.0), b.weighing(1.0)], plan(4)).unwrap_err();
        assert_eq!(
            spaces.to_string(),
            "member 1 knows 2 behaviors, member 0 knows 1"
        );
    }
}
