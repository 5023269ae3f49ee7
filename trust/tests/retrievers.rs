//! The retriever conformance suite: every [`RetrieverKind`] must return exactly the linear
//! scan's answer (same case, bit-identical similarity, ties to the smallest id) on random
//! case bases, queries and exclusions, with cases retained before and between queries; and
//! an adapter must make the same decisions whichever retriever it is configured with.

use cbr_core::{Behavior, BehaviorSpace, Case, CaseId, Component, Values};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;
use trust::{
    AdapterConfig, Cause, Decision, Evaluated, Outcome, RetrieverKind, TrustAdapter, TrustCase,
    TrustCaseBase, TrustMemory,
};

/// A retrieval answer with its similarity as bits, so equality means bit-identical.
type Answer = Option<(CaseId, u64)>;

fn answer(
    memory: &TrustMemory,
    query: &Vec<Evaluated>,
    exclude: &dyn Fn(&TrustCase) -> bool,
) -> Answer {
    memory
        .retrieve(query, exclude)
        .map(|r| (r.id, r.similarity.to_bits()))
}

/// Numeric grids, plain and tabled categorical components, unequal and zero weights.
fn space() -> impl Strategy<Value = Arc<BehaviorSpace>> {
    let component = (0u8..4, 1u16..26, prop::collection::vec(0.0f64..=1.0, 16));
    (
        prop::collection::vec(component, 1..4),
        prop::collection::vec(prop_oneof![Just(1.0), Just(0.0), 0.1f64..3.0], 3),
    )
        .prop_map(|(specs, weights)| {
            let components: Vec<Component> = specs
                .into_iter()
                .enumerate()
                .map(|(k, (kind, n, table))| {
                    let name = format!("c{k}");
                    let labels = |n: usize| (0..n).map(|i| format!("v{i}")).collect::<Vec<_>>();
                    match kind {
                        0 | 1 => Component::numeric(&name, "", 0.0, 0.5, n).unwrap(),
                        2 => Component {
                            name,
                            unit: String::new(),
                            values: Values::Categorical {
                                labels: labels(usize::from(n % 4 + 1)),
                                similarity: None,
                            },
                        },
                        _ => {
                            let n = usize::from(n % 4 + 1);
                            let t = (0..n)
                                .map(|i| {
                                    (0..n)
                                        .map(|j| {
                                            if i == j {
                                                1.0
                                            } else {
                                                table[i.min(j) * 4 + i.max(j)]
                                            }
                                        })
                                        .collect()
                                })
                                .collect();
                            Component {
                                name,
                                unit: String::new(),
                                values: Values::Categorical {
                                    labels: labels(n),
                                    similarity: Some(t),
                                },
                            }
                        }
                    }
                })
                .collect();
            let mut w = weights[..components.len()].to_vec();
            if w.iter().all(|&x| x == 0.0) {
                w[0] = 1.0;
            }
            Arc::new(BehaviorSpace::with_weights(components, Some(w)).unwrap())
        })
}

/// Times drawn from a few values (equal times, zero times: ties) or at random.
fn time() -> impl Strategy<Value = f64> {
    prop_oneof![Just(0.0), Just(10.0), Just(20.0), 0.0f64..60.0]
}

/// Pairs as (behavior rank seed, time); ranks are reduced modulo the space size, and a
/// small range of seeds makes duplicate behaviors common.
fn pairs(max: usize) -> impl Strategy<Value = Vec<(u64, f64)>> {
    prop::collection::vec((prop_oneof![0u64..8, any::<u64>()], time()), 0..max)
}

fn evaluated(space: &BehaviorSpace, pairs: &[(u64, f64)]) -> Vec<Evaluated> {
    pairs
        .iter()
        .map(|&(r, time)| Evaluated {
            behavior: space.unrank(r % space.size()),
            time,
        })
        .collect()
}

#[derive(Clone, Debug)]
struct Scenario {
    space: Arc<BehaviorSpace>,
    lambda: f64,
    /// Cases as (problem, solution rank seed).
    cases: Vec<(Vec<(u64, f64)>, u64)>,
    /// How many cases the memory starts with; the rest are retained between queries.
    initial: usize,
    queries: Vec<Vec<(u64, f64)>>,
    /// Excluded solution ranks (besides Algorithm 1's own exclusion, tried separately).
    excluded: Vec<u64>,
}

fn scenario() -> impl Strategy<Value = Scenario> {
    (
        space(),
        prop_oneof![Just(0.95), Just(1.0), Just(0.5), 0.01f64..1.0],
        prop::collection::vec((pairs(6), prop_oneof![0u64..8, any::<u64>()]), 0..40),
        any::<prop::sample::Index>(),
        prop::collection::vec(pairs(6), 1..5),
        prop::collection::vec(0u64..8, 0..3),
    )
        .prop_map(
            |(space, lambda, cases, initial, queries, excluded)| Scenario {
                initial: initial.index(cases.len() + 1),
                space,
                lambda,
                cases,
                queries,
                excluded,
            },
        )
}

fn case(space: &BehaviorSpace, (problem, solution): &(Vec<(u64, f64)>, u64)) -> TrustCase {
    Case {
        problem: evaluated(space, problem),
        solution: space.unrank(solution % space.size()),
    }
}

/// Runs the scenario with `kind`, returning every answer in order.
fn answers(s: &Scenario, kind: RetrieverKind) -> Vec<Answer> {
    let mut base = TrustCaseBase::new();
    for c in &s.cases[..s.initial] {
        base.push(case(&s.space, c));
    }
    let mut memory = TrustMemory::new(base, kind.build(s.space.clone(), s.lambda).unwrap());
    let excluded: Vec<Behavior> = s
        .excluded
        .iter()
        .map(|r| s.space.unrank(r % s.space.size()))
        .collect();
    let mut pending = s.cases[s.initial..].iter();
    let mut out = Vec::new();
    loop {
        for q in &s.queries {
            let query = evaluated(&s.space, q);
            out.push(answer(&memory, &query, &|_| false));
            out.push(answer(&memory, &query, &|c| excluded.contains(&c.solution)));
            // Algorithm 1's exclusion: final behaviors already evaluated in the episode.
            out.push(answer(&memory, &query, &|c| {
                query.iter().any(|e| e.behavior == c.solution)
            }));
        }
        // Retain a few more cases, then ask again.
        let mut retained = false;
        for c in pending.by_ref().take(7) {
            memory.retain(case(&s.space, c));
            retained = true;
        }
        if !retained {
            return out;
        }
    }
}

proptest! {
    #![proptest_config(Config {
        cases: 400,
        rng_seed: RngSeed::Fixed(0x7275_7374),
        failure_persistence: None,
        ..Config::default()
    })]

    #[test]
    fn every_retriever_returns_the_linear_answer(s in scenario()) {
        let reference = answers(&s, RetrieverKind::Linear);
        for kind in RetrieverKind::ALL {
            prop_assert_eq!(&answers(&s, kind), &reference, "{:?}", kind);
        }
    }
}

/// 20 x 20 x 10 x 4 like the patrol space (trust does not depend on the domains crate).
fn patrol_like() -> Arc<BehaviorSpace> {
    Arc::new(
        BehaviorSpace::new(
            [20u16, 20, 10, 4]
                .iter()
                .enumerate()
                .map(|(k, &n)| Component::numeric(&format!("c{k}"), "", 0.0, 1.0, n).unwrap())
                .collect(),
        )
        .unwrap(),
    )
}

/// A path of one-change steps with task-second times, as a random-walk episode leaves.
fn path(space: &BehaviorSpace, len: usize, rng: &mut ChaCha8Rng) -> Vec<Evaluated> {
    let mut current = space.draw(rng);
    let mut path = Vec::with_capacity(len);
    for _ in 0..len {
        path.push(Evaluated {
            behavior: current,
            // Whole seconds: equal times, hence tied similarities, are common.
            time: f64::from(rng.random_range(0u32..60)),
        });
        let neighbours: Vec<Behavior> = space.neighbours(&current).collect();
        current = neighbours[rng.random_range(0..neighbours.len())];
    }
    path
}

#[test]
fn episode_shaped_case_bases_get_the_linear_answer() {
    let space = patrol_like();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut base = TrustCaseBase::new();
    for _ in 0..1_000 {
        let len = rng.random_range(1..30);
        base.push(Case {
            problem: path(&space, len, &mut rng),
            solution: space.draw(&mut rng),
        });
    }
    let memories: Vec<TrustMemory> = RetrieverKind::ALL
        .iter()
        .map(|kind| TrustMemory::new(base.clone(), kind.build(space.clone(), 0.95).unwrap()))
        .collect();
    let mut reused = 0;
    for _ in 0..60 {
        let len = rng.random_range(1..30);
        let query = path(&space, len, &mut rng);
        let exclude = |c: &TrustCase| query.iter().any(|e| e.behavior == c.solution);
        let reference = answer(&memories[0], &query, &exclude);
        reused += usize::from(reference.is_some());
        for memory in &memories[1..] {
            assert_eq!(
                answer(memory, &query, &exclude),
                reference,
                "{}",
                memory.retriever_name()
            );
        }
    }
    assert!(reused > 30, "the queries exercise reuse ({reused} of 60)");
}

/// A synthetic operator: each behavior completes commands with a probability that grows
/// with its first component, so episodes search, retain and reuse.
fn scripted_run(kind: RetrieverKind) -> Vec<String> {
    let space = Arc::new(
        BehaviorSpace::new(vec![
            Component::numeric("a", "", 0.0, 1.0, 20).unwrap(),
            Component::numeric("b", "", 0.0, 1.0, 20).unwrap(),
        ])
        .unwrap(),
    );
    let config = AdapterConfig {
        retriever: kind,
        ..AdapterConfig::default()
    };
    let mut adapter = TrustAdapter::new(space.clone(), config, TrustCaseBase::new(), 5).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let mut decisions = Vec::new();
    for _ in 0..150 {
        adapter.begin_episode(space.draw(&mut rng)).unwrap();
        loop {
            let current = adapter.episode().unwrap().current;
            let p = f64::from(current.get(0)) / 19.0;
            let duration = f64::from(rng.random_range(1u32..20));
            let outcome = if rng.random_bool(p) {
                Outcome::completed(1.0, duration)
            } else {
                Outcome::interrupted(1.0, Cause::from_static("too-slow"), duration)
            };
            let decision = adapter.record(&outcome).unwrap();
            let settled = matches!(decision, Decision::Settled(_));
            decisions.push(format!("{decision:?}"));
            if settled {
                break;
            }
        }
    }
    decisions
}

#[test]
fn an_adapter_decides_alike_with_every_retriever() {
    let reference = scripted_run(RetrieverKind::Linear);
    let reused = reference.iter().filter(|d| d.contains("Case")).count();
    assert!(reused > 20, "the script exercises reuse ({reused} reuses)");
    for kind in RetrieverKind::ALL {
        assert_eq!(scripted_run(kind), reference, "{kind:?}");
    }
}

#[test]
fn a_config_names_its_retriever() {
    for (text, kind) in [
        ("(retriever: linear)", RetrieverKind::Linear),
        ("(retriever: inverted_index)", RetrieverKind::InvertedIndex),
        ("(retriever: parallel_scan)", RetrieverKind::ParallelScan),
    ] {
        let config: AdapterConfig = ron::from_str(text).unwrap();
        assert_eq!(config.retriever, kind, "{text}");
        assert_eq!(config.lambda, AdapterConfig::default().lambda);
    }
}
