//! The known-operator limit: how few behaviors, commands and untrustworthy commands an
//! agent needs when it knows the operator's expected outcome of every behavior.
//!
//! # The walk of one behavior
//!
//! While a behavior is in use its trust estimate starts at `0` and every command adds a
//! contribution: `+w_c` for a completion, `-w_k` for a failure or interruption of kind `k`.
//! The behavior is *accepted* as soon as the estimate reaches the trustworthy threshold
//! (`>= tau_T`, e.g. `+5`) and *rejected* as soon as it reaches the untrustworthy one
//! (`<= tau_UT`, e.g. `-5`). A behavior's command outcomes are i.i.d. draws from its outcome
//! distribution (a [`Step`] law: probability, contribution, and whether the outcome is
//! untrustworthy, i.e. not a completion).
//!
//! The estimate is then an absorbing Markov chain on the *reachable sums*: every value
//! reachable from `0` by adding contributions while staying strictly between the thresholds
//! is a transient state; crossing a threshold absorbs. [`solve_walk`] enumerates these
//! states by breadth-first search (sums closer than [`SUM_TOLERANCE`] are one state, so
//! floating-point noise such as `3 * (1/3) - 1 != 0` merges; a sum has reached a threshold
//! by the adapter's own rule, [`Thresholds::verdict`]), sorts them, and solves
//! `(I - Q) x = b` for three right-hand sides, `Q` being the transient-to-transient
//! transition matrix:
//!
//! - `b_i = P(absorbed into "accepted" in one step from i)` gives `P(accept)`;
//! - `b_i = 1` gives `E[commands until absorbed]`;
//! - `b_i = P(the next command is untrustworthy)` gives `E[untrustworthy commands until
//!   absorbed]`.
//!
//! The value at state `0` is the behavior's [`WalkOutcome`]. With few distinct steps the
//! sorted `I - Q` is banded (the default patrol reading, steps `+1/3, -1/3, -1`, has 29
//! states, lower bandwidth 3 and upper bandwidth 1), so a banded Gaussian elimination costs
//! `N * kl * ku` for `N` states.
//!
//! # The limit over a behavior space
//!
//! Given each behavior's acceptance probability `p_i` and a per-behavior cost `c_i` (`1` for
//! the *behaviors* metric, the expected commands for *commands*, the expected untrustworthy
//! commands for *untrustworthy*), an agent that evaluates behaviors one after the other,
//! never re-trying one within an episode, and stops at the first accepted one pays, for an
//! order `b_1, b_2, ...`,
//!
//! ```text
//! E[cost] = sum_k c_{b_k} * prod_{j<k} (1 - p_{b_j})
//! ```
//!
//! (if every behavior is rejected the episode ends after the last). Swapping two adjacent
//! behaviors `a, b` changes the cost by `p_b c_a - p_a c_b`, so the optimal order is by
//! ascending `c / p` (behaviors with `p = 0` last; ties in any order) — the classic
//! interchange argument. Two protocols are reported ([`Limit`]):
//!
//! - **free first choice**: the whole order is optimal;
//! - **paper protocol**: the first behavior is uniformly random over the space (as in the
//!   paper's trials), then the agent continues optimally among the remaining behaviors:
//!   `E = mean_{b0} [c_{b0} + (1 - p_{b0}) V(space without b0)]`.
//!
//! Sums stop once the survival product `prod (1 - p)` falls below [`SURVIVAL_CUTOFF`].
//!
//! These are means; the law of the untrustworthy commands (how often the paper-protocol
//! agent settles within `N` of them) is [`crate::reference::limit_law`]'s, on the same chain.

use std::collections::HashMap;
use thiserror::Error;
use trust::{Thresholds, Verdict};

/// Two sums closer than this are the same state of the walk (the adapter's tolerance at the
/// thresholds, [`trust::THRESHOLD_TOLERANCE`], which decides absorption through
/// [`Thresholds::verdict`]).
pub const SUM_TOLERANCE: f64 = trust::THRESHOLD_TOLERANCE;

/// The default cap on the number of transient states of one walk.
pub const DEFAULT_MAX_STATES: usize = 20_000;

/// The largest banded matrix (`states * (kl + ku + 1)` entries) [`solve_walk`] builds.
pub const MAX_BAND_ENTRIES: usize = 16_000_000;

/// How far the step probabilities may sum away from 1.
pub const PROBABILITY_SUM_TOLERANCE: f64 = 1e-6;

/// Survival products (the probability that every behavior so far was rejected) below this
/// end the sums of [`order_cost`], [`free_first_cost`] and [`paper_protocol_cost`].
pub const SURVIVAL_CUTOFF: f64 = 1e-15;

/// Why a walk or a limit could not be computed.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum LimitError {
    /// The thresholds are not finite, or do not satisfy `tau_UT < 0 < tau_T`, or are
    /// larger in magnitude than `1e6`.
    #[error(
        "invalid thresholds: trustworthy {trustworthy}, untrustworthy {untrustworthy} (need untrustworthy < 0 < trustworthy, both finite, |tau| <= 1e6)"
    )]
    InvalidThresholds {
        /// The trustworthy threshold given.
        trustworthy: f64,
        /// The untrustworthy threshold given.
        untrustworthy: f64,
    },
    /// A step has a negative or non-finite probability or a non-finite contribution.
    #[error("invalid step {index}: probability {prob}, contribution {delta}")]
    InvalidStep {
        /// The step's position in the slice.
        index: usize,
        /// Its probability.
        prob: f64,
        /// Its contribution.
        delta: f64,
    },
    /// The step probabilities do not sum to 1 (within [`PROBABILITY_SUM_TOLERANCE`]).
    #[error("step probabilities sum to {sum}, not 1")]
    ProbabilitySum {
        /// Their sum.
        sum: f64,
    },
    /// Every step of positive probability has a zero contribution: the walk never ends.
    #[error("the walk can never be absorbed: every step of positive probability contributes 0")]
    NeverAbsorbs,
    /// More transient states are reachable than the cap allows.
    #[error("the walk has more than {max} transient states (stopped counting at {count})")]
    TooManyStates {
        /// The number of states found when enumeration stopped.
        count: usize,
        /// The cap.
        max: usize,
    },
    /// The banded matrix would exceed [`MAX_BAND_ENTRIES`] entries.
    #[error(
        "the walk's matrix is too wide: {states} states, bandwidths {lower} below and {upper} above the diagonal"
    )]
    BandTooWide {
        /// The number of transient states.
        states: usize,
        /// The lower bandwidth.
        lower: usize,
        /// The upper bandwidth.
        upper: usize,
    },
    /// Elimination met a non-positive or non-finite pivot (cannot happen for a valid chain).
    #[error("numerical failure: pivot {pivot} at state {state}")]
    Numerical {
        /// The state (in sorted order) whose pivot failed.
        state: usize,
        /// The pivot's value.
        pivot: f64,
    },
    /// Landscape counts are inconsistent (no runs, or outcomes not adding up to the runs),
    /// or a weight is negative or not finite.
    #[error("invalid counts: {reason}")]
    InvalidCounts {
        /// What is wrong.
        reason: String,
    },
    /// A limit was asked of an empty space or an empty population.
    #[error("empty space: a limit needs at least one behavior (or operator)")]
    Empty,
    /// A behavior's outcome has an acceptance probability outside `[0, 1]` or a negative or
    /// non-finite cost.
    #[error(
        "invalid outcome of behavior {index}: accept {accept}, commands {commands}, untrustworthy {untrustworthy}"
    )]
    InvalidOutcome {
        /// The behavior's position.
        index: usize,
        /// Its acceptance probability.
        accept: f64,
        /// Its expected commands.
        commands: f64,
        /// Its expected untrustworthy commands.
        untrustworthy: f64,
    },
    /// A walk's law ([`crate::reference::limit_law::walk_law`]) still had more than
    /// [`crate::reference::limit_law::LAW_CUTOFF`] of its mass undecided after
    /// [`crate::reference::limit_law::MAX_WALK_COUNT`] untrustworthy commands.
    #[error(
        "the walk's law is too long: {undecided} of its mass is still undecided after {count} untrustworthy commands"
    )]
    LawTooLong {
        /// The untrustworthy commands followed.
        count: usize,
        /// The mass still undecided.
        undecided: f64,
    },
}

/// One possible outcome of a command: its probability, its contribution to the trust
/// estimate, and whether it is untrustworthy (anything but a completion).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step {
    /// Probability of this outcome for one command.
    pub prob: f64,
    /// Contribution to the trust estimate (`+w_c` for a completion, `-w_k` otherwise).
    pub delta: f64,
    /// Whether the outcome counts as an untrustworthy command.
    pub untrustworthy: bool,
}

/// The exact outcome of one behavior's walk from an estimate of 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WalkOutcome {
    /// Probability that the behavior is accepted (reaches the trustworthy threshold).
    pub accept: f64,
    /// Expected number of commands until accepted or rejected.
    pub commands: f64,
    /// Expected number of untrustworthy commands until accepted or rejected.
    pub untrustworthy: f64,
    /// Number of transient states of the chain (diagnostic).
    pub states: usize,
}

/// Where one step from a transient state leads.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Target {
    /// The transient state of this rank (states sorted by sum).
    State(usize),
    /// The trustworthy threshold: the behavior is accepted.
    Accept,
    /// The untrustworthy threshold: the behavior is rejected.
    Reject,
}

/// Looks up the state within [`SUM_TOLERANCE`] of `sum`, if any.
fn find_state(index: &HashMap<i64, usize>, sums: &[f64], sum: f64) -> (i64, Option<usize>) {
    let key = (sum / SUM_TOLERANCE).round() as i64;
    for k in [key, key - 1, key + 1] {
        if let Some(&i) = index.get(&k)
            && (sums[i] - sum).abs() <= SUM_TOLERANCE
        {
            return (key, Some(i));
        }
    }
    (key, None)
}

/// The absorbing chain of one behavior's walk: its transient states (the reachable sums,
/// sorted, so that with few distinct steps a matrix over them is banded) and where each
/// step leads from each. [`solve_walk`] solves it for its means, [`crate::reference::limit_law`]
/// for its law.
#[derive(Debug, Clone)]
pub(crate) struct WalkChain {
    /// The steps of positive probability, contributions below [`SUM_TOLERANCE`] made 0.
    pub(crate) steps: Vec<Step>,
    /// Per state (by rank), per step of `steps`, where it leads.
    targets: Vec<Target>,
    /// The rank of the state at sum 0, where the walk starts.
    pub(crate) start: usize,
    /// How far below the diagonal a step reaches (in ranks).
    pub(crate) lower: usize,
    /// How far above the diagonal a step reaches (in ranks).
    pub(crate) upper: usize,
}

impl WalkChain {
    /// Checks the input and enumerates the chain (the errors of [`solve_walk`]).
    pub(crate) fn build(
        steps: &[Step],
        thresholds: Thresholds,
        max_states: usize,
    ) -> Result<Self, LimitError> {
        let Thresholds {
            trustworthy: hi,
            untrustworthy: lo,
        } = thresholds;
        if !(hi.is_finite()
            && lo.is_finite()
            && lo < -SUM_TOLERANCE
            && hi > SUM_TOLERANCE
            && hi <= trust::MAX_THRESHOLD
            && lo >= -trust::MAX_THRESHOLD)
        {
            return Err(LimitError::InvalidThresholds {
                trustworthy: hi,
                untrustworthy: lo,
            });
        }
        let mut sum = 0.0;
        for (index, s) in steps.iter().enumerate() {
            if !(s.prob.is_finite() && s.prob >= 0.0 && s.delta.is_finite()) {
                return Err(LimitError::InvalidStep {
                    index,
                    prob: s.prob,
                    delta: s.delta,
                });
            }
            sum += s.prob;
        }
        if (sum - 1.0).abs() > PROBABILITY_SUM_TOLERANCE {
            return Err(LimitError::ProbabilitySum { sum });
        }
        let live: Vec<Step> = steps
            .iter()
            .filter(|s| s.prob > 0.0)
            .map(|s| Step {
                delta: if s.delta.abs() < SUM_TOLERANCE {
                    0.0
                } else {
                    s.delta
                },
                ..*s
            })
            .collect();
        if live.iter().all(|s| s.delta == 0.0) {
            return Err(LimitError::NeverAbsorbs);
        }

        // Breadth-first enumeration of the transient sums. Each state keeps the sum of the
        // first (shortest) path that reached it, so float noise stays at a few ulps per step.
        let mut sums: Vec<f64> = vec![0.0];
        let mut index: HashMap<i64, usize> = HashMap::from([(0, 0)]);
        let mut found: Vec<Target> = Vec::new(); // live.len() per state, in discovery order
        let mut next = 0;
        while next < sums.len() {
            let from = sums[next];
            for s in &live {
                let to = from + s.delta;
                let target = match thresholds.verdict(to) {
                    Verdict::Trustworthy => Target::Accept,
                    Verdict::Untrustworthy => Target::Reject,
                    Verdict::Undecided => match find_state(&index, &sums, to) {
                        (_, Some(i)) => Target::State(i),
                        (key, None) => {
                            if sums.len() >= max_states {
                                return Err(LimitError::TooManyStates {
                                    count: sums.len() + 1,
                                    max: max_states,
                                });
                            }
                            sums.push(to);
                            index.insert(key, sums.len() - 1);
                            Target::State(sums.len() - 1)
                        }
                    },
                };
                found.push(target);
            }
            next += 1;
        }
        let n = sums.len();

        // Sort the states by sum: with few distinct steps, a matrix over them is banded.
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| sums[a].total_cmp(&sums[b]));
        let mut rank = vec![0; n];
        for (r, &i) in order.iter().enumerate() {
            rank[i] = r;
        }
        let mut targets = vec![Target::Reject; found.len()];
        let (mut lower, mut upper) = (0usize, 0usize);
        for (i, row) in found.chunks(live.len()).enumerate() {
            let ri = rank[i];
            for (slot, t) in targets[ri * live.len()..].iter_mut().zip(row) {
                *slot = match *t {
                    Target::State(j) => {
                        let rj = rank[j];
                        lower = lower.max(ri.saturating_sub(rj));
                        upper = upper.max(rj.saturating_sub(ri));
                        Target::State(rj)
                    }
                    other => other,
                };
            }
        }
        if n.saturating_mul(lower + upper + 1) > MAX_BAND_ENTRIES {
            return Err(LimitError::BandTooWide {
                states: n,
                lower,
                upper,
            });
        }
        Ok(Self {
            steps: live,
            targets,
            start: rank[0],
            lower,
            upper,
        })
    }

    /// The number of transient states.
    pub(crate) fn states(&self) -> usize {
        self.targets.len() / self.steps.len()
    }

    /// Per state (by rank), where each step of [`WalkChain::steps`] leads.
    pub(crate) fn rows(&self) -> std::slice::ChunksExact<'_, Target> {
        self.targets.chunks_exact(self.steps.len())
    }
}

/// A square banded matrix (entry `(i, j)` kept when `j` is at most `lower` below and
/// `upper` above `i`), factored in place into `L U` by Gaussian elimination without
/// pivoting. Every matrix factored here is a nonsingular M-matrix (`I - Q` of an absorbing
/// chain, or its transpose, or the same for a subset of the steps): elimination without
/// pivoting keeps every Schur complement an M-matrix, its pivots stay positive, it is
/// numerically stable, and it creates no fill-in outside the band.
#[derive(Debug, Clone)]
pub(crate) struct Banded {
    size: usize,
    lower: usize,
    upper: usize,
    /// Entry `(i, j)` at `i * (lower + upper + 1) + j + lower - i`.
    entries: Vec<f64>,
}

impl Banded {
    /// The zero matrix of `size` rows with these bandwidths.
    pub(crate) fn zeros(size: usize, lower: usize, upper: usize) -> Self {
        Self {
            size,
            lower,
            upper,
            entries: vec![0.0; size * (lower + upper + 1)],
        }
    }

    fn at(&self, i: usize, j: usize) -> usize {
        i * (self.lower + self.upper + 1) + j + self.lower - i
    }

    /// Adds `value` to entry `(i, j)`, which must lie within the band.
    pub(crate) fn add(&mut self, i: usize, j: usize, value: f64) {
        let at = self.at(i, j);
        self.entries[at] += value;
    }

    /// Factors the matrix into `L U` in place (`L`'s multipliers below the diagonal).
    /// Errors on a non-positive or non-finite pivot.
    pub(crate) fn factor(&mut self) -> Result<(), LimitError> {
        let n = self.size;
        for k in 0..n {
            let pivot = self.entries[self.at(k, k)];
            if !(pivot.is_finite() && pivot > 0.0) {
                return Err(LimitError::Numerical { state: k, pivot });
            }
            let last_col = (k + self.upper).min(n - 1);
            for i in (k + 1)..=(k + self.lower).min(n - 1) {
                let below = self.at(i, k);
                let factor = self.entries[below] / pivot;
                self.entries[below] = factor;
                if factor == 0.0 {
                    continue;
                }
                for j in (k + 1)..=last_col {
                    let (to, from) = (self.at(i, j), self.at(k, j));
                    self.entries[to] -= factor * self.entries[from];
                }
            }
        }
        Ok(())
    }

    /// Solves the factored system for `K` right-hand sides at once, in place.
    pub(crate) fn solve<const K: usize>(&self, rhs: &mut [[f64; K]]) {
        let n = self.size;
        for i in 0..n {
            for k in i.saturating_sub(self.lower)..i {
                let factor = self.entries[self.at(i, k)];
                if factor == 0.0 {
                    continue;
                }
                let known = rhs[k];
                for (x, p) in rhs[i].iter_mut().zip(known) {
                    *x -= factor * p;
                }
            }
        }
        for i in (0..n).rev() {
            let mut x = rhs[i];
            let last = (i + self.upper).min(n - 1);
            for (j, known) in rhs.iter().enumerate().take(last + 1).skip(i + 1) {
                let a = self.entries[self.at(i, j)];
                for (v, w) in x.iter_mut().zip(known) {
                    *v -= a * w;
                }
            }
            let pivot = self.entries[self.at(i, i)];
            rhs[i] = x.map(|v| v / pivot);
        }
    }
}

/// Solves one behavior's walk exactly: `P(accept)`, `E[commands]` and `E[untrustworthy
/// commands]` from an estimate of 0 (see the module docs).
///
/// Steps of probability 0 are ignored; contributions smaller in magnitude than
/// [`SUM_TOLERANCE`] count as 0 (a self-loop). Errors when the input is invalid, when no
/// step of positive probability moves the estimate ([`LimitError::NeverAbsorbs`]), when more
/// than `max_states` transient states are reachable ([`LimitError::TooManyStates`]; use
/// [`DEFAULT_MAX_STATES`]) or when the banded matrix would exceed [`MAX_BAND_ENTRIES`].
///
/// Cost: `O(N * s)` to enumerate `N` states with `s` steps, `O(N * kl * ku)` to solve.
pub fn solve_walk(
    steps: &[Step],
    thresholds: Thresholds,
    max_states: usize,
) -> Result<WalkOutcome, LimitError> {
    let chain = WalkChain::build(steps, thresholds, max_states)?;
    // Untrustworthy mass of one command: the same from every state.
    let bad: f64 = chain
        .steps
        .iter()
        .filter(|s| s.untrustworthy)
        .map(|s| s.prob)
        .sum();
    let n = chain.states();
    // `I - Q`, and per state the right-hand sides accept, commands, untrustworthy.
    let mut matrix = Banded::zeros(n, chain.lower, chain.upper);
    let mut rhs = vec![[0.0; 3]; n];
    for (r, row) in chain.rows().enumerate() {
        matrix.add(r, r, 1.0);
        rhs[r][1] = 1.0;
        rhs[r][2] = bad;
        for (t, s) in row.iter().zip(&chain.steps) {
            match *t {
                Target::State(j) => matrix.add(r, j, -s.prob),
                Target::Accept => rhs[r][0] += s.prob,
                Target::Reject => {}
            }
        }
    }
    // Every state is transient and can reach absorption (some step of positive probability
    // moves the estimate monotonically towards a threshold): `I - Q` is a nonsingular
    // M-matrix.
    matrix.factor()?;
    matrix.solve(&mut rhs);
    let [accept, commands, untrustworthy] = rhs[chain.start];
    Ok(WalkOutcome {
        accept: accept.clamp(0.0, 1.0),
        commands: commands.max(1.0),
        untrustworthy: untrustworthy.clamp(0.0, commands.max(1.0)),
        states: n,
    })
}

/// Builds a step law from a landscape row: `runs` commands of which `completed` completed
/// (each contributing `+completion_weight`), and the other outcomes as `(count, weight)`
/// pairs, each contributing `-weight` and counted untrustworthy. The counts must add up to
/// `runs`; weights must be finite and non-negative. Zero counts are dropped.
pub fn steps_from_counts(
    runs: u64,
    completed: u64,
    completion_weight: f64,
    others: &[(u64, f64)],
) -> Result<Vec<Step>, LimitError> {
    if runs == 0 {
        return Err(LimitError::InvalidCounts {
            reason: "no runs".to_owned(),
        });
    }
    let total = others
        .iter()
        .try_fold(completed, |acc, &(c, _)| acc.checked_add(c));
    if total != Some(runs) {
        return Err(LimitError::InvalidCounts {
            reason: format!(
                "{completed} completions and {} other outcomes do not add up to {runs} runs",
                others.iter().map(|&(c, _)| u128::from(c)).sum::<u128>()
            ),
        });
    }
    let mut weights = std::iter::once(completion_weight).chain(others.iter().map(|&(_, w)| w));
    if let Some(w) = weights.find(|w| !(w.is_finite() && *w >= 0.0)) {
        return Err(LimitError::InvalidCounts {
            reason: format!("weight {w} is not finite and non-negative"),
        });
    }
    let n = runs as f64;
    let completion = Step {
        prob: completed as f64 / n,
        delta: completion_weight,
        untrustworthy: false,
    };
    Ok(std::iter::once((completed, completion))
        .chain(others.iter().map(|&(count, weight)| {
            (
                count,
                Step {
                    prob: count as f64 / n,
                    delta: -weight,
                    untrustworthy: true,
                },
            )
        }))
        .filter(|&(count, _)| count > 0)
        .map(|(_, s)| s)
        .collect())
}

/// The three metrics of an episode: behaviors evaluated (the final one counted), commands
/// issued, untrustworthy commands endured.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Costs {
    /// Expected number of behaviors evaluated.
    pub behaviors: f64,
    /// Expected number of commands.
    pub commands: f64,
    /// Expected number of untrustworthy commands.
    pub untrustworthy: f64,
}

/// The known-operator limit of one operator over one behavior space, under both protocols.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Limit {
    /// The agent chooses every behavior, the first included, optimally.
    pub free_first: Costs,
    /// The first behavior is uniformly random (the paper's protocol); the rest are chosen
    /// optimally among the remaining behaviors.
    pub paper: Costs,
}

impl Limit {
    /// The limit of a space whose behaviors have the given walk outcomes (one per
    /// behavior). Each metric has its own optimal order (ascending `cost / p`). Errors on an
    /// empty space or on an outcome with `accept` outside `[0, 1]` (beyond `1e-9`) or a
    /// negative or non-finite cost. `O(N log N + K^2)`, `K` being the number of behaviors
    /// tried before the survival product falls below [`SURVIVAL_CUTOFF`].
    pub fn from_outcomes(outcomes: &[WalkOutcome]) -> Result<Self, LimitError> {
        let accept = acceptance(outcomes)?;
        let ones = vec![1.0; outcomes.len()];
        let commands: Vec<f64> = outcomes.iter().map(|o| o.commands).collect();
        let untrustworthy: Vec<f64> = outcomes.iter().map(|o| o.untrustworthy).collect();
        let costs = |f: fn(&[f64], &[f64]) -> f64| Costs {
            behaviors: f(&accept, &ones),
            commands: f(&accept, &commands),
            untrustworthy: f(&accept, &untrustworthy),
        };
        Ok(Self {
            free_first: costs(free_first_cost),
            paper: costs(paper_protocol_cost),
        })
    }

    /// The mean limit over a population of operators (each limit computed for one
    /// operator), e.g. the paper's "random operator" experiments. This is a lower bound for
    /// an agent that does not know which operator it faces: such an agent can at best do
    /// as well as one that knows. Errors on an empty population.
    pub fn mean_of(limits: &[Limit]) -> Result<Limit, LimitError> {
        if limits.is_empty() {
            return Err(LimitError::Empty);
        }
        let n = limits.len() as f64;
        let mean = |f: fn(&Limit) -> Costs| {
            let (b, c, u) = limits.iter().map(f).fold((0.0, 0.0, 0.0), |acc, x| {
                (
                    acc.0 + x.behaviors,
                    acc.1 + x.commands,
                    acc.2 + x.untrustworthy,
                )
            });
            Costs {
                behaviors: b / n,
                commands: c / n,
                untrustworthy: u / n,
            }
        };
        Ok(Limit {
            free_first: mean(|l| l.free_first),
            paper: mean(|l| l.paper),
        })
    }
}

/// The acceptance probabilities of `outcomes`, each clamped to `[0, 1]`. Errors on none,
/// or on an outcome with `accept` outside `[0, 1]` (beyond `1e-9`) or a negative or
/// non-finite cost.
pub(crate) fn acceptance(outcomes: &[WalkOutcome]) -> Result<Vec<f64>, LimitError> {
    if outcomes.is_empty() {
        return Err(LimitError::Empty);
    }
    outcomes
        .iter()
        .enumerate()
        .map(|(index, o)| {
            let ok = o.accept.is_finite()
                && (-1e-9..=1.0 + 1e-9).contains(&o.accept)
                && o.commands.is_finite()
                && o.commands >= 0.0
                && o.untrustworthy.is_finite()
                && o.untrustworthy >= 0.0;
            if ok {
                Ok(o.accept.clamp(0.0, 1.0))
            } else {
                Err(LimitError::InvalidOutcome {
                    index,
                    accept: o.accept,
                    commands: o.commands,
                    untrustworthy: o.untrustworthy,
                })
            }
        })
        .collect()
}

/// The optimal order of behaviors for per-behavior costs `cost` and acceptance
/// probabilities `accept` (same length): ascending `cost / accept`, behaviors with
/// `accept <= 0` last, ties in index order (any order of tied behaviors is optimal: swapping
/// adjacent behaviors `a, b` changes the expected cost by `p_b c_a - p_a c_b`).
pub fn optimal_order(accept: &[f64], cost: &[f64]) -> Vec<usize> {
    let ratio: Vec<f64> = accept
        .iter()
        .zip(cost)
        .map(|(&p, &c)| if p > 0.0 { c / p } else { f64::INFINITY })
        .collect();
    let mut order: Vec<usize> = (0..accept.len()).collect();
    order.sort_by(|&a, &b| ratio[a].total_cmp(&ratio[b]));
    order
}

/// The expected total cost of trying behaviors in `order` (indices into `accept` and
/// `cost`) until one is accepted, or all are rejected: `sum_k cost_k * prod_{j<k} (1 -
/// p_j)`, stopping once the survival product falls below [`SURVIVAL_CUTOFF`].
pub fn order_cost(accept: &[f64], cost: &[f64], order: &[usize]) -> f64 {
    order_cost_skipping(accept, cost, order, None).0
}

/// [`order_cost`] with one position of `order` skipped; also returns how many positions
/// (skipped one included) were visited.
fn order_cost_skipping(
    accept: &[f64],
    cost: &[f64],
    order: &[usize],
    skip: Option<usize>,
) -> (f64, usize) {
    let (mut total, mut survival) = (0.0, 1.0);
    for (k, &b) in order.iter().enumerate() {
        if survival < SURVIVAL_CUTOFF {
            return (total, k);
        }
        if Some(k) == skip {
            continue;
        }
        total += cost[b] * survival;
        survival *= 1.0 - accept[b];
    }
    (total, order.len())
}

/// The free-first-choice limit of one metric: the expected cost of the optimal order
/// ([`optimal_order`]).
pub fn free_first_cost(accept: &[f64], cost: &[f64]) -> f64 {
    order_cost(accept, cost, &optimal_order(accept, cost))
}

/// The paper-protocol limit of one metric: a uniformly random first behavior `b0`, then the
/// optimal order among the others: `mean_{b0} [cost_{b0} + (1 - p_{b0}) V(without b0)]`.
///
/// Removing `b0` leaves the optimal order of the rest equal to the full optimal order minus
/// `b0`, so `V(without b0) = V(all)` unless `b0` lies in the prefix that the truncated sum
/// visits; only those `K` values are recomputed (`O(N log N + K^2)`). Returns 0 for an
/// empty space.
pub fn paper_protocol_cost(accept: &[f64], cost: &[f64]) -> f64 {
    let n = accept.len();
    if n == 0 {
        return 0.0;
    }
    let order = optimal_order(accept, cost);
    let (all, visited) = order_cost_skipping(accept, cost, &order, None);
    let mut total = 0.0;
    for (k, &b) in order.iter().enumerate() {
        let rest = if k < visited {
            order_cost_skipping(accept, cost, &order, Some(k)).0
        } else {
            all
        };
        total += cost[b] + (1.0 - accept[b]) * rest;
    }
    total / n as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
    }

    fn walk(steps: &[(f64, f64, bool)]) -> WalkOutcome {
        let steps: Vec<Step> = steps
            .iter()
            .map(|&(prob, delta, untrustworthy)| Step {
                prob,
                delta,
                untrustworthy,
            })
            .collect();
        solve_walk(&steps, Thresholds::default(), DEFAULT_MAX_STATES).unwrap()
    }

    /// Gambler's ruin from 5 on {0, ..., 10}, up with probability p.
    fn ruin(p: f64) -> (f64, f64) {
        let q = 1.0 - p;
        if (p - q).abs() < 1e-12 {
            return (0.5, 25.0);
        }
        let r = q / p;
        let accept = (1.0 - r.powi(5)) / (1.0 - r.powi(10));
        let duration = 5.0 / (q - p) - 10.0 / (q - p) * accept;
        (accept, duration)
    }

    #[test]
    fn symmetric_walk_is_fair() {
        let o = walk(&[(0.5, 1.0, false), (0.5, -1.0, true)]);
        assert!(close(o.accept, 0.5, 1e-12), "{o:?}");
        assert!(close(o.commands, 25.0, 1e-12), "{o:?}");
        assert!(close(o.untrustworthy, 12.5, 1e-12), "{o:?}");
        assert_eq!(o.states, 9);
    }

    #[test]
    fn biased_walks_match_gamblers_ruin() {
        for p in [0.05, 0.3, 0.45, 0.55, 0.7, 0.9, 0.99] {
            let o = walk(&[(p, 1.0, false), (1.0 - p, -1.0, true)]);
            let (accept, duration) = ruin(p);
            assert!(close(o.accept, accept, 1e-10), "p {p}: {o:?} vs {accept}");
            assert!(close(o.commands, duration, 1e-10), "p {p}: {o:?}");
            // Wald: untrustworthy = q * E[commands] for a single failure kind.
            assert!(close(o.untrustworthy, (1.0 - p) * duration, 1e-10));
        }
    }

    #[test]
    fn certain_completion_accepts_in_five() {
        let o = walk(&[(1.0, 1.0, false), (0.0, -1.0, true)]);
        assert_eq!((o.accept, o.commands, o.untrustworthy), (1.0, 5.0, 0.0));
    }

    #[test]
    fn patrol_extremes_by_hand() {
        let third = 1.0 / 3.0;
        let o = walk(&[(1.0, third, false)]);
        assert!(close(o.accept, 1.0, 1e-12) && close(o.commands, 15.0, 1e-12));
        let o = walk(&[(1.0, -third, true)]);
        assert!(close(o.accept, 0.0, 1e-12) && close(o.untrustworthy, 15.0, 1e-12));
        let o = walk(&[(1.0, -1.0, true)]);
        assert!(close(o.commands, 5.0, 1e-12));
        let o = walk(&[(0.5, third, false), (0.3, -third, true), (0.2, -1.0, true)]);
        assert_eq!(o.states, 29);
        // Weights written with 10 digits give the same chain.
        let w = 0.333_333_333_3;
        let p = walk(&[(0.5, w, false), (0.3, -w, true), (0.2, -1.0, true)]);
        assert_eq!(p.states, 29);
        assert!(close(o.accept, p.accept, 1e-9) && close(o.commands, p.commands, 1e-9));
    }

    /// A tiny LCG (Knuth's MMIX constants) so the Monte Carlo needs no crate.
    struct Lcg(u64);
    impl Lcg {
        fn uniform(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn patrol_walk_matches_monte_carlo() {
        let third = 1.0 / 3.0;
        let law = [
            (0.62, third, false),
            (0.3, -third, true),
            (0.08, -1.0, true),
        ];
        let o = walk(&law);
        let mut rng = Lcg(42);
        let trials = 100_000;
        let (mut acc, mut cmds, mut bad) = (0.0, 0.0, 0.0);
        for _ in 0..trials {
            let mut sum = 0i32; // in thirds
            let mut n = 0;
            while sum > -15 && sum < 15 {
                let u = rng.uniform();
                n += 1;
                if u < 0.62 {
                    sum += 1;
                } else if u < 0.92 {
                    sum -= 1;
                    bad += 1.0;
                } else {
                    sum -= 3;
                    bad += 1.0;
                }
            }
            if sum >= 15 {
                acc += 1.0;
            }
            cmds += f64::from(n);
        }
        let t = f64::from(trials);
        let (acc, cmds, bad) = (acc / t, cmds / t, bad / t);
        let se = (o.accept * (1.0 - o.accept) / t).sqrt();
        assert!((acc - o.accept).abs() < 4.0 * se + 1e-3, "{acc} vs {o:?}");
        assert!(
            (cmds - o.commands).abs() < 0.02 * o.commands,
            "{cmds} vs {o:?}"
        );
        assert!(
            (bad - o.untrustworthy).abs() < 0.03 * o.untrustworthy,
            "{bad} vs {o:?}"
        );
    }

    #[test]
    fn zero_steps_and_self_loops() {
        // Half the commands do nothing: twice the commands, same acceptance.
        let o = walk(&[(0.25, 1.0, false), (0.25, -1.0, true), (0.5, 0.0, true)]);
        assert!(close(o.accept, 0.5, 1e-12) && close(o.commands, 50.0, 1e-12));
        assert!(close(o.untrustworthy, 37.5, 1e-12));
    }

    #[test]
    fn errors_are_typed() {
        let s = |prob, delta| Step {
            prob,
            delta,
            untrustworthy: true,
        };
        let th = Thresholds::default();
        assert_eq!(
            solve_walk(&[s(1.0, 0.0), s(0.0, 1.0)], th, 100),
            Err(LimitError::NeverAbsorbs)
        );
        assert!(matches!(
            solve_walk(&[s(0.5, 0.001), s(0.5, -0.001)], th, 100),
            Err(LimitError::TooManyStates {
                count: 101,
                max: 100
            })
        ));
        assert!(matches!(
            solve_walk(&[s(0.5, 1.0)], th, 100),
            Err(LimitError::ProbabilitySum { .. })
        ));
        assert!(matches!(
            solve_walk(&[s(-0.5, 1.0), s(1.5, 1.0)], th, 100),
            Err(LimitError::InvalidStep { index: 0, .. })
        ));
        let bad = Thresholds {
            trustworthy: 5.0,
            untrustworthy: 1.0,
        };
        assert!(matches!(
            solve_walk(&[s(1.0, 1.0)], bad, 100),
            Err(LimitError::InvalidThresholds { .. })
        ));
    }

    #[test]
    fn counts_become_steps() {
        let steps =
            steps_from_counts(10, 6, 1.0 / 3.0, &[(3, 1.0 / 3.0), (0, 1.0), (1, 1.0)]).unwrap();
        assert_eq!(steps.len(), 3);
        assert!(close(steps[0].prob, 0.6, 1e-15) && !steps[0].untrustworthy);
        assert!(steps[2].delta == -1.0 && steps[2].untrustworthy);
        assert!(steps_from_counts(10, 6, 1.0, &[(3, 1.0)]).is_err());
        assert!(steps_from_counts(0, 0, 1.0, &[]).is_err());
        assert!(steps_from_counts(1, 1, f64::NAN, &[]).is_err());
    }

    #[test]
    fn three_behaviors_by_hand() {
        // p = (0.5, 0.8, 0.0), commands = (10, 20, 5).
        let accept = [0.5, 0.8, 0.0];
        let cmds = [10.0, 20.0, 5.0];
        let o: Vec<WalkOutcome> = (0..3)
            .map(|i| WalkOutcome {
                accept: accept[i],
                commands: cmds[i],
                untrustworthy: cmds[i] / 2.0,
                states: 1,
            })
            .collect();
        let l = Limit::from_outcomes(&o).unwrap();
        // Behaviors: order 1, 0, 2: 1 + 0.2 + 0.2 * 0.5 = 1.3.
        assert!(close(l.free_first.behaviors, 1.3, 1e-12));
        // Commands: ratios 20, 25, inf: order 0, 1, 2: 10 + 0.5 * 20 + 0.1 * 5 = 20.5.
        assert!(close(l.free_first.commands, 20.5, 1e-12));
        assert!(close(l.free_first.untrustworthy, 10.25, 1e-12));
        // Paper, behaviors: b0 = 0: 1 + 0.5 * (1 + 0.2) = 1.6; b0 = 1: 1 + 0.2 * (1 + 0.5) =
        // 1.3; b0 = 2: 1 + 1 * (1 + 0.2) = 2.2. Mean 5.1 / 3.
        assert!(close(l.paper.behaviors, 5.1 / 3.0, 1e-12));
        // Paper, commands: b0 = 0: 10 + 0.5 * (20 + 0.2 * 5) = 20.5; b0 = 1: 20 + 0.2 * (10 +
        // 0.5 * 5) = 22.5; b0 = 2: 5 + (10 + 0.5 * 20) = 25. Mean 68 / 3.
        assert!(close(l.paper.commands, 68.0 / 3.0, 1e-12));
        assert!(close(l.paper.untrustworthy, 68.0 / 6.0, 1e-12));
        let m = Limit::mean_of(&[l, Limit::default()]).unwrap();
        assert!(close(m.paper.commands, 68.0 / 6.0, 1e-12));
        assert_eq!(Limit::mean_of(&[]), Err(LimitError::Empty));
        assert_eq!(Limit::from_outcomes(&[]), Err(LimitError::Empty));
    }

    #[test]
    fn certain_behaviors_end_the_sums() {
        // Two behaviors that are always accepted among many never accepted.
        let mut accept = vec![0.0; 1000];
        accept[10] = 1.0;
        accept[500] = 1.0;
        let ones = vec![1.0; 1000];
        assert_eq!(free_first_cost(&accept, &ones), 1.0);
        // Paper: 2/1000 of b0 end at once; else 1 + 1.
        let expect = (2.0 * 1.0 + 998.0 * 2.0) / 1000.0;
        assert!(close(paper_protocol_cost(&accept, &ones), expect, 1e-12));
        // A single one: removing it leaves nothing acceptable; the rest are all tried.
        let mut accept = vec![0.0; 4];
        accept[0] = 1.0;
        let ones = vec![1.0; 4];
        let expect = (1.0 + 3.0 * 2.0) / 4.0;
        assert!(close(paper_protocol_cost(&accept, &ones), expect, 1e-12));
    }
}
