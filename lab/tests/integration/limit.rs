//! Property tests of the limit module and of the limit's law.
use lab::reference::limit::*;
use lab::reference::limit_law::{LAW_HORIZON, WalkLaw, paper_protocol_law, walk_law};
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;
use trust::Thresholds;

/// A step law on a grid of 1/12: (probability weight, contribution in twelfths, bad).
fn step_law() -> impl Strategy<Value = Vec<(u32, i32, bool)>> {
    prop::collection::vec((1u32..100, -14i32..=14, any::<bool>()), 1..5)
        .prop_filter("some step moves", |v| v.iter().any(|s| s.1 != 0))
}

fn to_steps(law: &[(u32, i32, bool)]) -> Vec<Step> {
    let total: u32 = law.iter().map(|s| s.0).sum();
    law.iter()
        .map(|&(w, d, bad)| Step {
            prob: f64::from(w) / f64::from(total),
            delta: f64::from(d) / 12.0,
            untrustworthy: bad,
        })
        .collect()
}

/// Independent dense solve on the integer grid (in twelfths).
fn dense(law: &[(u32, i32, bool)], tau12: i32) -> (f64, f64, f64) {
    let steps = to_steps(law);
    let n = (2 * tau12 - 1) as usize;
    let idx = |s: i32| (s + tau12 - 1) as usize;
    let mut a = vec![vec![0.0; n + 3]; n];
    for s in (1 - tau12)..tau12 {
        let i = idx(s);
        a[i][i] += 1.0;
        a[i][n + 1] = 1.0;
        for (st, &(_, d, bad)) in steps.iter().zip(law) {
            if bad {
                a[i][n + 2] += st.prob;
            }
            let t = s + d;
            if t >= tau12 {
                a[i][n] += st.prob;
            } else if t > -tau12 {
                a[i][idx(t)] -= st.prob;
            }
        }
    }
    // Gauss-Jordan with partial pivoting.
    for k in 0..n {
        let p = (k..n)
            .max_by(|&x, &y| a[x][k].abs().total_cmp(&a[y][k].abs()))
            .unwrap();
        a.swap(k, p);
        let piv = a[k][k];
        for v in a[k].iter_mut() {
            *v /= piv;
        }
        let pivot_row = a[k].clone();
        for (i, row) in a.iter_mut().enumerate() {
            if i != k && row[k] != 0.0 {
                let f = row[k];
                for (v, p) in row.iter_mut().zip(&pivot_row) {
                    *v -= f * p;
                }
            }
        }
    }
    let z = idx(0);
    (a[z][n], a[z][n + 1], a[z][n + 2])
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-7 * (1.0 + a.abs().max(b.abs()))
}

fn all_permutations(items: &[usize]) -> Vec<Vec<usize>> {
    if items.is_empty() {
        return vec![vec![]];
    }
    let mut out = Vec::new();
    for (i, &x) in items.iter().enumerate() {
        let mut rest = items.to_vec();
        rest.remove(i);
        for mut p in all_permutations(&rest) {
            p.insert(0, x);
            out.push(p);
        }
    }
    out
}

fn space() -> impl Strategy<Value = Vec<(f64, f64)>> {
    let p = prop_oneof![Just(0.0), Just(1.0), 0.0f64..=1.0, 0.0f64..=1.0];
    prop::collection::vec((p, 0.0f64..50.0), 1..7)
}

/// The plain convolution of two laws of counts.
fn convolve(a: &[f64], b: &[f64]) -> Vec<f64> {
    let mut sum = vec![0.0; (a.len() + b.len()).saturating_sub(1)];
    for (i, x) in a.iter().enumerate() {
        for (j, y) in b.iter().enumerate() {
            sum[i + j] += x * y;
        }
    }
    sum
}

fn add(to: &mut Vec<f64>, law: &[f64], weight: f64) {
    if to.len() < law.len() {
        to.resize(law.len(), 0.0);
    }
    for (t, x) in to.iter_mut().zip(law) {
        *t += weight * x;
    }
}

/// The paper-protocol agent's law, settled and unsettled, by brute force: for every first
/// behavior, the whole order of the rest followed to its end, one convolution at a time.
fn brute_paper_law(walks: &[(WalkOutcome, WalkLaw)]) -> (Vec<f64>, Vec<f64>) {
    let accept: Vec<f64> = walks.iter().map(|(o, _)| o.accept).collect();
    let cost: Vec<f64> = walks.iter().map(|(o, _)| o.untrustworthy).collect();
    let order = optimal_order(&accept, &cost);
    let n = walks.len() as f64;
    let (mut settled, mut unsettled) = (Vec::new(), Vec::new());
    for first in 0..walks.len() {
        let mut reach = vec![1.0];
        let rest = order.iter().copied().filter(|&b| b != first);
        for b in std::iter::once(first).chain(rest) {
            // A walk that wanders long leaves mass past the horizon (a nearly driftless
            // walk between far thresholds, 5e-14 of it in one draw; the cutoff bounds only the mass
            // still undecided where the law stops): counts never fall, so that
            // mass lands past the horizon in every sum too, and the counts within the
            // horizon, which this follows, are exact without it.
            let law = &walks[b].1;
            add(&mut settled, &convolve(&reach, &law.accepted.mass), 1.0 / n);
            reach = convolve(&reach, &law.rejected.mass);
        }
        add(&mut unsettled, &reach, 1.0 / n);
    }
    (settled, unsettled)
}

/// The limit's law on `laws` at thresholds of `tau12` / 12: each walk's law has the walk's
/// acceptance and mean, and the paper-protocol agent's law is the brute-force one and has
/// the limit's mean.
fn check_the_limits_law(laws: &[Vec<(u32, i32, bool)>], tau12: i32) -> Result<(), TestCaseError> {
    let tau = f64::from(tau12) / 12.0;
    let th = Thresholds {
        trustworthy: tau,
        untrustworthy: -tau,
    };
    let walks: Vec<(WalkOutcome, WalkLaw)> = laws
        .iter()
        .map(|law| {
            let steps = to_steps(law);
            (
                solve_walk(&steps, th, DEFAULT_MAX_STATES).unwrap(),
                walk_law(&steps, th, DEFAULT_MAX_STATES).unwrap(),
            )
        })
        .collect();
    let tight = |a: f64, b: f64| (a - b).abs() <= 1e-9 * (1.0 + a.abs().max(b.abs()));
    for (outcome, law) in &walks {
        let mean = law.accepted.moment() + law.rejected.moment();
        prop_assert!(
            tight(law.accepted.total(), outcome.accept),
            "{outcome:?} {law:?}"
        );
        prop_assert!(tight(law.accepted.total() + law.rejected.total(), 1.0));
        prop_assert!(tight(mean, outcome.untrustworthy), "{outcome:?} {mean}");
    }
    let outcomes: Vec<WalkOutcome> = walks.iter().map(|(o, _)| *o).collect();
    let limit = Limit::from_outcomes(&outcomes).unwrap().paper.untrustworthy;
    let pairs: Vec<(WalkOutcome, &WalkLaw)> = walks.iter().map(|(o, l)| (*o, l)).collect();
    let agent = paper_protocol_law(&pairs).unwrap();
    prop_assert!(tight(agent.mean(), limit), "{} vs {limit}", agent.mean());
    let (settled, unsettled) = brute_paper_law(&walks);
    // Counts past the horizon the exact law keeps as a mass and a moment only.
    for (u, brute) in settled.iter().enumerate().take(LAW_HORIZON + 1) {
        let exact = agent.settled.mass.get(u).copied().unwrap_or(0.0);
        prop_assert!(
            (exact - brute).abs() <= 1e-12,
            "settled at {u}: {exact} vs {brute}"
        );
    }
    let never: f64 = unsettled.iter().take(LAW_HORIZON + 1).sum();
    prop_assert!((agent.unsettled.within(LAW_HORIZON as u64) - never).abs() <= 1e-12);
    // Within the horizon or past it, every episode ends settled or not.
    prop_assert!(tight(agent.settled.total() + agent.unsettled.total(), 1.0));
    Ok(())
}

/// A walk that wanders long enough to leave mass (about 1e-15) past the law's horizon,
/// which the brute force once refused (a draw of the property below).
#[test]
fn a_walk_past_the_horizon_keeps_the_limits_law() {
    check_the_limits_law(&[vec![(87, 1, false), (77, -1, true)]], 28).unwrap();
}

/// A nearly driftless walk between thresholds 44 twelfths apart, which leaves about 5e-14 of
/// its mass past the horizon (a draw of the property below that the brute force once
/// refused, asking for no more than 1e-14 there).
#[test]
fn a_driftless_walk_leaves_mass_past_the_horizon_and_keeps_the_limits_law() {
    let laws = [vec![(32, -1, false), (63, 1, true), (13, -2, true)]];
    let th = Thresholds {
        trustworthy: 22.0 / 12.0,
        untrustworthy: -22.0 / 12.0,
    };
    let law = walk_law(&to_steps(&laws[0]), th, DEFAULT_MAX_STATES).unwrap();
    assert!(law.accepted.beyond + law.rejected.beyond > 1e-14);
    check_the_limits_law(&laws, 22).unwrap();
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn walk_is_sane_and_matches_a_dense_solve(law in step_law(), tau12 in 12i32..=60) {
        let steps = to_steps(&law);
        let tau = f64::from(tau12) / 12.0;
        let th = Thresholds { trustworthy: tau, untrustworthy: -tau };
        let o = solve_walk(&steps, th, DEFAULT_MAX_STATES).unwrap();
        prop_assert!((0.0..=1.0).contains(&o.accept));
        prop_assert!(o.untrustworthy >= 0.0 && o.untrustworthy <= o.commands + 1e-9);
        // The fewest commands that can absorb.
        let up = law.iter().map(|s| s.1).max().unwrap();
        let down = law.iter().map(|s| s.1).min().unwrap();
        let mut fewest = i32::MAX;
        if up > 0 { fewest = fewest.min((tau12 + up - 1) / up); }
        if down < 0 { fewest = fewest.min((tau12 - down - 1) / -down); }
        prop_assert!(o.commands >= f64::from(fewest) - 1e-9, "{o:?} fewest {fewest}");
        let (acc, cmd, bad) = dense(&law, tau12);
        prop_assert!(close(o.accept, acc), "{o:?} vs {acc}");
        prop_assert!(close(o.commands, cmd), "{o:?} vs {cmd}");
        prop_assert!(close(o.untrustworthy, bad), "{o:?} vs {bad}");
    }

    #[test]
    fn optimum_beats_every_order_and_paper_is_worse(
        space in space(),
        seeds in prop::collection::vec(any::<u64>(), 3),
    ) {
        let accept: Vec<f64> = space.iter().map(|s| s.0).collect();
        let cost: Vec<f64> = space.iter().map(|s| s.1).collect();
        let free = free_first_cost(&accept, &cost);
        let paper = paper_protocol_cost(&accept, &cost);
        prop_assert!(paper >= free - 1e-9 * (1.0 + free));
        let n = accept.len();
        // A few pseudo-random orders.
        for seed in seeds {
            let mut order: Vec<usize> = (0..n).collect();
            let mut x = seed | 1;
            for i in (1..n).rev() {
                x ^= x << 13; x ^= x >> 7; x ^= x << 17;
                order.swap(i, (x % (i as u64 + 1)) as usize);
            }
            prop_assert!(free <= order_cost(&accept, &cost, &order) + 1e-9 * (1.0 + free));
        }
        // Exhaustively: the optimum of each protocol.
        let idx: Vec<usize> = (0..n).collect();
        let best = |items: &[usize]| all_permutations(items)
            .iter()
            .map(|o| order_cost(&accept, &cost, o))
            .fold(f64::INFINITY, f64::min);
        prop_assert!(close(free, best(&idx)), "{free} vs {}", best(&idx));
        let brute_paper = (0..n).map(|b0| {
            let rest: Vec<usize> = idx.iter().copied().filter(|&b| b != b0).collect();
            let v = if rest.is_empty() { 0.0 } else { best(&rest) };
            cost[b0] + (1.0 - accept[b0]) * v
        }).sum::<f64>() / n as f64;
        prop_assert!(close(paper, brute_paper), "{paper} vs {brute_paper}");
    }

    /// The limit's law ([`check_the_limits_law`]).
    #[test]
    fn the_limits_law_has_the_limits_mean(
        laws in prop::collection::vec(step_law(), 1..6),
        tau12 in 12i32..=30,
    ) {
        check_the_limits_law(&laws, tau12)?;
    }
}
