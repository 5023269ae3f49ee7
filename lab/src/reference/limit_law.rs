//! The known-operator limit's law: not only how many untrustworthy commands the agent of
//! [`crate::reference::limit`] endures on average, but how often it settles within `N` of them.
//!
//! # The law of one behavior's walk
//!
//! The walk of a behavior ([`crate::reference::limit`]) ends accepted or rejected after some number
//! `U` of untrustworthy commands. Its joint law, `P(accepted, U = u)` and `P(rejected, U =
//! u)` ([`WalkLaw`]), is computed exactly on the same absorbing chain
//! [`solve_walk`](crate::reference::limit::solve_walk) solves, with the count as an extra dimension
//! ([`walk_law`]). The probability mass is
//! propagated one *layer* at a time, layer `u` being the states visited after exactly `u`
//! untrustworthy commands: within a layer only the trustworthy steps move the walk, so the
//! expected visits `v_u` to each state solve `v_u (I - Q_c) = m_u`, `Q_c` the chain's
//! transitions by trustworthy steps and `m_u` the mass entering layer `u` (at `u = 0`, all
//! of it at the sum 0). The trustworthy steps out of `v_u` that cross a threshold end the
//! walk with `U = u`; the untrustworthy steps out of it cross a threshold with `U = u + 1`
//! or enter layer `u + 1`. `I - Q_c` is banded like `I - Q` and factored once; a layer
//! costs a banded solve. The layers stop once the mass still undecided falls below
//! [`LAW_CUTOFF`] (that mass is dropped); the counts are kept one by one up to
//! [`LAW_HORIZON`], beyond it by their mass and first moment only ([`CountLaw`]).
//!
//! # The law of the agent
//!
//! The paper-protocol agent of [`crate::reference::limit`] tries a uniformly random first behavior,
//! then the rest in the optimal order of the untrustworthy-commands metric (ascending
//! `E[U] / p`, [`optimal_order`]), never one twice, and stops at the first accepted one.
//! The walks are independent, so its total count is a sum of independent counts: with
//! `A_b` and `R_b` the accepted and rejected parts of behavior `b`'s law and `*` the
//! convolution, the law of an order `o_1, o_2, ...` is
//!
//! ```text
//! D(o_1, o_2, ...) = A_{o_1} + R_{o_1} * D(o_2, ...),   D() = "never settled" at 0
//! ```
//!
//! and the paper protocol's is `mean_{b0} [A_{b0} + R_{b0} * D(the order without b0)]`
//! ([`paper_protocol_law`]). Removing `b0` leaves the rest of the optimal order as it was,
//! so the tails are built once: the suffix laws `D(o_k, ...)` backwards; forwards, the
//! reach of `o_k` (every behavior before it rejected, `R_{o_1} * ... * R_{o_{k-1}}`) and
//! the settled part before it; and for `b0 = o_k`, `D(without o_k) = settled before o_k +
//! reach of o_k * D(o_{k+1}, ...)`. The order is
//! followed until every behavior but one could have been rejected with a probability
//! below [`SURVIVAL_CUTOFF`] (the agent then counts as never settling; the limit's means
//! stop there too), so the law's mean is the limit's `paper.untrustworthy` up to the
//! cutoffs. An agent that trusts almost nothing could try thousands of behaviors, so the
//! law follows at most [`MAX_LAW_BEHAVIORS`] of them one by one: an agent still searching
//! after that many (it has endured that many rejections) counts as not settled, beyond
//! the horizon, with the rest of the order's expected untrustworthy commands
//! ([`order_cost`]) added to its count. The mean then exceeds the limit's by at most the
//! chance of still searching times one behavior's expected count (the first behavior is
//! counted in that rest again when it lies there).
//!
//! Exact, not a Monte Carlo: the chains are small (29 states for the patrol weights) and
//! the agent's order is short (its first behaviors are accepted almost surely), so the
//! exact law costs a few milliseconds per operator, without sampling error.

use crate::reference::limit::{
    Banded, LimitError, SURVIVAL_CUTOFF, Step, Target, WalkChain, WalkOutcome, acceptance,
    optimal_order, order_cost,
};
use std::collections::HashMap;
use trust::Thresholds;

/// A walk's law stops once the mass still undecided falls below this; that mass is
/// dropped.
pub const LAW_CUTOFF: f64 = 1e-15;

/// Counts up to this are kept one by one; beyond it, by their mass and first moment only.
pub const LAW_HORIZON: usize = 5_000;

/// The most untrustworthy commands a walk's law follows ([`LimitError::LawTooLong`]).
pub const MAX_WALK_COUNT: usize = 1_000_000;

/// The most behaviors of the optimal order the agent's law follows one by one.
pub const MAX_LAW_BEHAVIORS: usize = 256;

/// A sub-probability law of a count (of untrustworthy commands): its mass at each count up
/// to [`LAW_HORIZON`], and the mass and first moment of the counts beyond it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CountLaw {
    /// The mass at counts `0, 1, ...` (none after the last count of positive mass).
    pub mass: Vec<f64>,
    /// The mass at counts beyond [`LAW_HORIZON`].
    pub beyond: f64,
    /// The sum of count times mass over the counts beyond [`LAW_HORIZON`].
    pub beyond_moment: f64,
}

impl CountLaw {
    /// All of the mass `mass` at the count `count`.
    fn point(count: usize, mass: f64) -> Self {
        let mut law = Self::default();
        law.add_at(count, mass);
        law
    }

    /// Adds `mass` at `count`.
    fn add_at(&mut self, count: usize, mass: f64) {
        if mass == 0.0 {
            return;
        }
        if count > LAW_HORIZON {
            self.beyond += mass;
            self.beyond_moment += count as f64 * mass;
            return;
        }
        if self.mass.len() <= count {
            self.mass.resize(count + 1, 0.0);
        }
        self.mass[count] += mass;
    }

    /// Its total mass.
    pub fn total(&self) -> f64 {
        self.mass_within() + self.beyond
    }

    /// Its first moment: the sum of count times mass.
    pub fn moment(&self) -> f64 {
        self.moment_within() + self.beyond_moment
    }

    /// Its mass up to the horizon.
    fn mass_within(&self) -> f64 {
        self.mass.iter().sum()
    }

    /// Its first moment up to the horizon.
    fn moment_within(&self) -> f64 {
        self.mass
            .iter()
            .enumerate()
            .map(|(u, m)| u as f64 * m)
            .sum()
    }

    /// The mass at counts up to `n` (those beyond [`LAW_HORIZON`] never counted).
    pub fn within(&self, n: u64) -> f64 {
        let end = usize::try_from(n).map_or(self.mass.len(), |n| {
            n.saturating_add(1).min(self.mass.len())
        });
        self.mass[..end].iter().sum()
    }

    /// Adds `weight` times `other`.
    fn add_scaled(&mut self, other: &Self, weight: f64) {
        if self.mass.len() < other.mass.len() {
            self.mass.resize(other.mass.len(), 0.0);
        }
        for (m, o) in self.mass.iter_mut().zip(&other.mass) {
            *m += weight * o;
        }
        self.beyond += weight * other.beyond;
        self.beyond_moment += weight * other.beyond_moment;
    }

    /// The law of the sum of independent counts of these laws. The mass and first moment
    /// beyond the horizon are exact: `E[(X + Y) 1{X beyond}] = E[X 1{X beyond}] P(Y) +
    /// P(X beyond) E[Y]`.
    fn convolve(&self, other: &Self) -> Self {
        let mut sum = Self::default();
        let (a, b) = (&self.mass, &other.mass);
        if !a.is_empty() && !b.is_empty() {
            sum.mass = vec![0.0; (a.len() + b.len() - 1).min(LAW_HORIZON + 1)];
            // Mass and moment of `b` from each count on, for the pairs that leave the horizon.
            let mut tail = vec![(0.0, 0.0); b.len() + 1];
            for j in (0..b.len()).rev() {
                tail[j] = (tail[j + 1].0 + b[j], tail[j + 1].1 + j as f64 * b[j]);
            }
            for (i, &x) in a.iter().enumerate() {
                if x == 0.0 {
                    continue;
                }
                let inside = (LAW_HORIZON + 1 - i).min(b.len());
                for (s, &y) in sum.mass[i..].iter_mut().zip(&b[..inside]) {
                    *s += x * y;
                }
                let (mass, moment) = tail[inside];
                sum.beyond += x * mass;
                sum.beyond_moment += x * (i as f64 * mass + moment);
            }
        }
        let (a_mass, a_moment) = (self.mass_within(), self.moment_within());
        sum.beyond += self.beyond * other.total() + a_mass * other.beyond;
        sum.beyond_moment += self.beyond_moment * other.total()
            + self.beyond * other.moment()
            + a_moment * other.beyond
            + a_mass * other.beyond_moment;
        while sum.mass.last() == Some(&0.0) {
            sum.mass.pop();
        }
        sum
    }
}

/// The joint law of how a behavior's walk ends and the untrustworthy commands it took.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WalkLaw {
    /// `P(accepted, U = u)`.
    pub accepted: CountLaw,
    /// `P(rejected, U = u)`.
    pub rejected: CountLaw,
}

/// The law of a behavior's walk from an estimate of 0 (see the module docs), on the chain
/// [`solve_walk`](crate::reference::limit::solve_walk) solves, with its errors, and
/// [`LimitError::LawTooLong`] if more than [`LAW_CUTOFF`] of the mass is undecided after
/// [`MAX_WALK_COUNT`] untrustworthy commands.
///
/// Cost: a banded factorisation, then a banded solve per untrustworthy command followed.
pub fn walk_law(
    steps: &[Step],
    thresholds: Thresholds,
    max_states: usize,
) -> Result<WalkLaw, LimitError> {
    let chain = WalkChain::build(steps, thresholds, max_states)?;
    let n = chain.states();
    // `(I - Q_c)^T`, `Q_c` the moves by trustworthy steps, so that each layer is a plain
    // solve; and per state, the mass a trustworthy step accepts and rejects.
    let mut matrix = Banded::zeros(n, chain.upper, chain.lower);
    let mut ends = vec![(0.0, 0.0); n];
    for (r, row) in chain.rows().enumerate() {
        matrix.add(r, r, 1.0);
        for (t, s) in row.iter().zip(&chain.steps) {
            if s.untrustworthy {
                continue;
            }
            match *t {
                Target::State(j) => matrix.add(j, r, -s.prob),
                Target::Accept => ends[r].0 += s.prob,
                Target::Reject => ends[r].1 += s.prob,
            }
        }
    }
    matrix.factor()?;
    let mut law = WalkLaw::default();
    let mut layer = vec![[0.0]; n];
    layer[chain.start][0] = 1.0;
    let mut next = vec![[0.0]; n];
    // Mass an untrustworthy step ended, accepted and rejected, at the next count.
    let mut ended_next = (0.0, 0.0);
    let mut count = 0;
    loop {
        // Expected visits to each state after exactly `count` untrustworthy commands.
        matrix.solve(&mut layer);
        let mut ended = std::mem::take(&mut ended_next);
        next.iter_mut().for_each(|m| m[0] = 0.0);
        for ((row, [visits]), (accept, reject)) in chain.rows().zip(&layer).zip(&ends) {
            if *visits == 0.0 {
                continue;
            }
            ended.0 += visits * accept;
            ended.1 += visits * reject;
            for (t, s) in row.iter().zip(&chain.steps) {
                if !s.untrustworthy {
                    continue;
                }
                match *t {
                    Target::State(j) => next[j][0] += visits * s.prob,
                    Target::Accept => ended_next.0 += visits * s.prob,
                    Target::Reject => ended_next.1 += visits * s.prob,
                }
            }
        }
        law.accepted.add_at(count, ended.0);
        law.rejected.add_at(count, ended.1);
        let undecided: f64 = next.iter().map(|m| m[0]).sum();
        if undecided < LAW_CUTOFF {
            law.accepted.add_at(count + 1, ended_next.0);
            law.rejected.add_at(count + 1, ended_next.1);
            return Ok(law);
        }
        if count == MAX_WALK_COUNT {
            return Err(LimitError::LawTooLong { count, undecided });
        }
        std::mem::swap(&mut layer, &mut next);
        count += 1;
    }
}

/// The law of the untrustworthy commands an agent endures in an episode, by whether it
/// settled on an accepted behavior.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct UntrustworthyLaw {
    /// The episodes that settled, by their untrustworthy commands.
    pub settled: CountLaw,
    /// The episodes that never settled (every behavior tried was rejected, or the agent
    /// was still searching where the law stops following it).
    pub unsettled: CountLaw,
}

impl UntrustworthyLaw {
    /// The expected untrustworthy commands, settled or not.
    pub fn mean(&self) -> f64 {
        self.settled.moment() + self.unsettled.moment()
    }

    /// The probability of settling within `n` untrustworthy commands (`n` up to
    /// [`LAW_HORIZON`]; the mass beyond it is never counted).
    pub fn settled_within(&self, n: u64) -> f64 {
        self.settled.within(n)
    }

    /// Where its curve steps up: each count of positive settled mass, with the probability
    /// of settling within it.
    pub fn steps(&self) -> Vec<(u64, f64)> {
        let mut within = 0.0;
        self.settled
            .mass
            .iter()
            .enumerate()
            .filter(|(_, m)| **m > 0.0)
            .map(|(u, m)| {
                within += m;
                (u as u64, within)
            })
            .collect()
    }

    /// The weighted mixture of `laws` (weights non-negative, not all 0, normalised here);
    /// the default law for none.
    pub fn mixture<'a>(laws: impl IntoIterator<Item = (f64, &'a UntrustworthyLaw)>) -> Self {
        let laws: Vec<(f64, &UntrustworthyLaw)> = laws.into_iter().collect();
        let total: f64 = laws.iter().map(|(weight, _)| weight).sum();
        let mut mixed = Self::default();
        if total > 0.0 {
            for (weight, law) in laws {
                mixed.add_scaled(law, weight / total);
            }
        }
        mixed
    }

    /// Adds `weight` times `other`.
    fn add_scaled(&mut self, other: &Self, weight: f64) {
        self.settled.add_scaled(&other.settled, weight);
        self.unsettled.add_scaled(&other.unsettled, weight);
    }

    /// This law after first `rejected` (a count law, every behavior so far rejected).
    fn after(&self, rejected: &CountLaw) -> Self {
        Self {
            settled: rejected.convolve(&self.settled),
            unsettled: rejected.convolve(&self.unsettled),
        }
    }
}

/// The law of the paper-protocol agent's untrustworthy commands over a space whose
/// behaviors have these walks (each behavior's outcome, from
/// [`solve_walk`](crate::reference::limit::solve_walk), and its law, from [`walk_law`]): a uniformly
/// random first behavior, then the optimal order of the rest for the untrustworthy
/// metric, the order [`Limit::from_outcomes`](crate::reference::limit::Limit::from_outcomes) uses;
/// its mean is that limit's `paper.untrustworthy` (see the module docs). Errors as
/// `from_outcomes`. Cost: about `K` convolutions of laws for the `K` behaviors followed.
pub fn paper_protocol_law(
    walks: &[(WalkOutcome, &WalkLaw)],
) -> Result<UntrustworthyLaw, LimitError> {
    let outcomes: Vec<WalkOutcome> = walks.iter().map(|(o, _)| *o).collect();
    let accept = acceptance(&outcomes)?;
    let cost: Vec<f64> = outcomes.iter().map(|o| o.untrustworthy).collect();
    let order = optimal_order(&accept, &cost);
    let law = |k: usize| walks[order[k]].1;

    // How far the order is followed: until every behavior but one could have been
    // rejected with a probability below the cutoff (so that skipping any one of them, as
    // a first behavior, leaves the rest under it too), or the cap.
    let (mut all_but_least, mut least) = (1.0, 1.0f64);
    let mut end = order.len();
    for (k, &b) in order.iter().enumerate() {
        if k == MAX_LAW_BEHAVIORS || all_but_least < SURVIVAL_CUTOFF {
            end = k;
            break;
        }
        let rejected = 1.0 - accept[b];
        all_but_least *= rejected.max(least);
        least = least.min(rejected);
    }
    // What follows the last behavior followed: never settled, after nothing more when the
    // order is spent or cut at the survival cutoff (as the limit's means are), else after
    // the rest's expected untrustworthy commands, summarised beyond the horizon.
    let after_end = if end == MAX_LAW_BEHAVIORS && end < order.len() {
        UntrustworthyLaw {
            settled: CountLaw::default(),
            unsettled: CountLaw {
                mass: Vec::new(),
                beyond: 1.0,
                beyond_moment: order_cost(&accept, &cost, &order[end..]),
            },
        }
    } else {
        UntrustworthyLaw {
            settled: CountLaw::default(),
            unsettled: CountLaw::point(0, 1.0),
        }
    };
    // suffix[k]: the law of following the order from its `k`-th behavior to `end`.
    let mut suffix = vec![after_end];
    for k in (0..end).rev() {
        let mut from_here = suffix[suffix.len() - 1].after(&law(k).rejected);
        from_here.settled.add_scaled(&law(k).accepted, 1.0);
        suffix.push(from_here);
    }
    suffix.reverse();

    let mut total = UntrustworthyLaw::default();
    // Forwards: every behavior before `k` rejected (`reach`), and settled on one of them.
    let mut reach = CountLaw::point(0, 1.0);
    let mut settled_before = CountLaw::default();
    for k in 0..end {
        let walk = law(k);
        // The first behavior is the `k`-th: the rest is the order without it.
        let reach_next = reach.convolve(&walk.rejected);
        let rest_after_reach = suffix[k + 1].after(&reach_next);
        total.settled.add_scaled(&walk.accepted, 1.0);
        total
            .settled
            .add_scaled(&walk.rejected.convolve(&settled_before), 1.0);
        total.add_scaled(&rest_after_reach, 1.0);
        settled_before.add_scaled(&reach.convolve(&walk.accepted), 1.0);
        reach = reach_next;
    }
    // A first behavior past `end`: the whole order follows. Behaviors that share a law
    // (thousands do: they share their counts) add it once, times their number, in the
    // order first met, so that the sums are the same every time.
    let mut first_met: HashMap<*const WalkLaw, usize> = HashMap::new();
    let mut shared: Vec<(&WalkLaw, f64)> = Vec::new();
    for k in end..order.len() {
        let at = *first_met.entry(law(k)).or_insert_with(|| {
            shared.push((law(k), 0.0));
            shared.len() - 1
        });
        shared[at].1 += 1.0;
    }
    let mut rejected_first = CountLaw::default();
    for (walk, times) in shared {
        total.settled.add_scaled(&walk.accepted, times);
        rejected_first.add_scaled(&walk.rejected, times);
    }
    total.add_scaled(&suffix[0].after(&rejected_first), 1.0);
    let mut mean = UntrustworthyLaw::default();
    mean.add_scaled(&total, 1.0 / order.len() as f64);
    Ok(mean)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::limit::{DEFAULT_MAX_STATES, Limit, solve_walk};

    /// Thresholds `+1` and `-2`: two transient states, the sums 0 and -1.
    const SMALL: Thresholds = Thresholds {
        trustworthy: 1.0,
        untrustworthy: -2.0,
    };

    fn step(prob: f64, delta: f64, untrustworthy: bool) -> Step {
        Step {
            prob,
            delta,
            untrustworthy,
        }
    }

    /// A behavior's outcome and law under `thresholds`.
    fn walk(steps: &[Step], thresholds: Thresholds) -> (WalkOutcome, WalkLaw) {
        (
            solve_walk(steps, thresholds, DEFAULT_MAX_STATES).unwrap(),
            walk_law(steps, thresholds, DEFAULT_MAX_STATES).unwrap(),
        )
    }

    fn assert_close(a: f64, b: f64, tolerance: f64) {
        assert!(
            (a - b).abs() <= tolerance * (1.0 + a.abs().max(b.abs())),
            "{a} vs {b}"
        );
    }

    /// A fair coin between `+1` (completed) and `-1` (untrustworthy) on [`SMALL`]: from 0,
    /// `(-1, +1)` repeated `k` times then `+1` accepts after `k` untrustworthy commands,
    /// with probability `(1/4)^k / 2`; `(-1, +1)` `k` times then `-1, -1` rejects after
    /// `k + 2`, with probability `(1/4)^(k + 1)`. Accepted with 2/3; `E[U]` = 2/9 + 7/9.
    fn coin() -> [Step; 2] {
        [step(0.5, 1.0, false), step(0.5, -1.0, true)]
    }

    #[test]
    fn a_fair_coin_by_hand() {
        let (outcome, law) = walk(&coin(), SMALL);
        for k in 0..10 {
            let quarter = 0.25f64.powi(k);
            assert_close(law.accepted.mass[k as usize], quarter / 2.0, 1e-12);
            assert_close(law.rejected.mass[k as usize + 2], quarter / 4.0, 1e-12);
        }
        assert_eq!(law.rejected.mass[..2], [0.0, 0.0]);
        assert_close(law.accepted.total(), 2.0 / 3.0, 1e-12);
        assert_close(law.accepted.moment(), 2.0 / 9.0, 1e-12);
        assert_close(law.rejected.moment(), 7.0 / 9.0, 1e-12);
        // The law's masses and mean are the walk's own.
        assert_close(law.accepted.total(), outcome.accept, 1e-12);
        assert_close(
            law.accepted.moment() + law.rejected.moment(),
            outcome.untrustworthy,
            1e-12,
        );
    }

    #[test]
    fn two_behaviors_by_hand() {
        // The coin and a behavior always completed (accepted at 0). The optimal order puts
        // the sure one first (0 / 1 < 1 / (2/3)). First behavior the sure one (1/2): settled
        // at 0. The coin (1/2): accepted by its own law, or rejected and then settled at
        // once on the sure one: settled at `u` with the coin's `A(u) + R(u)`. So settled at
        // 0 with 1/2 + 1/4 = 3/4, at 1 with 1/16, at `u >= 2` with (9/4)(1/4)^u; never
        // unsettled; mean 1/2, the limit's.
        let (coin_outcome, coin_law) = walk(&coin(), SMALL);
        let (sure_outcome, sure_law) = walk(&[step(1.0, 1.0, false)], SMALL);
        let law =
            paper_protocol_law(&[(coin_outcome, &coin_law), (sure_outcome, &sure_law)]).unwrap();
        assert_close(law.settled.mass[0], 0.75, 1e-12);
        assert_close(law.settled.mass[1], 1.0 / 16.0, 1e-12);
        for u in 2..12 {
            assert_close(law.settled.mass[u], 2.25 * 0.25f64.powi(u as i32), 1e-12);
        }
        assert!(law.unsettled.total() < 1e-15, "{:?}", law.unsettled);
        assert_close(law.settled_within(1), 13.0 / 16.0, 1e-12);
        assert_close(law.settled_within(2), 61.0 / 64.0, 1e-12);
        assert_eq!(law.steps()[..2], [(0, 0.75), (1, 13.0 / 16.0)]);
        let limit = Limit::from_outcomes(&[coin_outcome, sure_outcome]).unwrap();
        assert_close(law.mean(), 0.5, 1e-12);
        assert_close(law.mean(), limit.paper.untrustworthy, 1e-12);
    }

    #[test]
    fn an_agent_that_never_settles_keeps_its_mass() {
        // Two behaviors always rejected after 2 untrustworthy commands: every episode
        // tries both and ends unsettled at 4.
        let (outcome, never) = walk(&[step(1.0, -1.0, true)], SMALL);
        let law = paper_protocol_law(&[(outcome, &never), (outcome, &never)]).unwrap();
        assert_eq!(law.settled.total(), 0.0);
        assert_eq!(law.unsettled, CountLaw::point(4, 1.0));
        assert_eq!(law.mean(), 4.0);
        assert_eq!(law.steps(), []);
    }

    #[test]
    fn counts_beyond_the_horizon_keep_their_mass_and_mean() {
        // Half at H - 1, half at H + 10, each plus 3 (certain): H + 2 and H + 13, both
        // beyond; mass and moment exact.
        let mut a = CountLaw::point(LAW_HORIZON - 1, 0.5);
        a.add_at(LAW_HORIZON + 10, 0.5);
        assert_eq!((a.mass.len(), a.beyond), (LAW_HORIZON, 0.5));
        let sum = a.convolve(&CountLaw::point(3, 1.0));
        assert!(sum.mass.is_empty(), "{}", sum.mass.len());
        assert_eq!(sum.beyond, 1.0);
        let h = LAW_HORIZON as f64;
        assert_close(sum.beyond_moment, 0.5 * (h + 2.0) + 0.5 * (h + 13.0), 1e-15);
        assert_close(sum.moment(), a.moment() + 3.0, 1e-15);
        // Within the horizon, a plain convolution: (0.5 at 0, 0.5 at 2) + (0.5 at 0, 0.5 at
        // 1) is 1/4 at each of 0, 1, 2, 3.
        let mut b = CountLaw::point(0, 0.5);
        b.add_at(2, 0.5);
        let mut c = CountLaw::point(0, 0.5);
        c.add_at(1, 0.5);
        assert_eq!(b.convolve(&c).mass, [0.25; 4]);
        assert_eq!(b.within(1), 0.5);
        assert_eq!(b.within(u64::MAX), 1.0);
    }

    #[test]
    fn a_long_search_is_summarised_by_its_mean() {
        // 300 behaviors, each accepted at once with 1/100, else rejected after 1
        // untrustworthy command: the agent is still searching after MAX_LAW_BEHAVIORS with
        // probability 0.99^257; its mean stays the limit's within that chance times one
        // behavior's expected count.
        let steps = [step(0.01, 5.0, false), step(0.99, -5.0, true)];
        let (outcome, law) = walk(&steps, Thresholds::default());
        let walks = vec![(outcome, &law); 300];
        let agent = paper_protocol_law(&walks).unwrap();
        let outcomes: Vec<WalkOutcome> = walks.iter().map(|(o, _)| *o).collect();
        let limit = Limit::from_outcomes(&outcomes).unwrap().paper.untrustworthy;
        let searching = 0.99f64.powi(257);
        assert!(
            agent.unsettled.beyond >= searching * 0.9,
            "{:?}",
            agent.unsettled
        );
        assert!((agent.mean() - limit).abs() <= searching * outcome.untrustworthy);
        assert_close(agent.settled.total() + agent.unsettled.total(), 1.0, 1e-12);
        // Settled within 0: the first behavior accepted at once.
        assert_close(agent.settled_within(0), 0.01, 1e-12);
    }

    #[test]
    fn mixtures_weigh_their_laws() {
        let at = |u| UntrustworthyLaw {
            settled: CountLaw::point(u, 1.0),
            unsettled: CountLaw::default(),
        };
        let mixed = UntrustworthyLaw::mixture([(3.0, &at(0)), (1.0, &at(2))]);
        assert_eq!(mixed.steps(), [(0, 0.75), (2, 1.0)]);
        assert_eq!(mixed.mean(), 0.5);
        assert_eq!(UntrustworthyLaw::mixture([]), UntrustworthyLaw::default());
    }
}
