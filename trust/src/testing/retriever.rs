//! The retriever conformance kit: [`check_retriever`].
//!
//! Every retriever must return exactly the linear scan's answer: the same case, a
//! bit-identical similarity, ties to the smallest id. The kit checks it on random case
//! bases, queries and exclusions, with cases retained before and between queries, cases
//! and queries in several contexts, matched exactly or by a declared similarity; on case
//! bases shaped like real episodes; and through an adapter, whose decisions must be the
//! same as with the linear scan.

use crate::{
    AdapterConfig, Cause, Decision, Evaluated, Outcome, SetSimilarity, TrustAdapter, TrustCase,
    TrustCaseBase, TrustMemory, TrustProblem, TrustRetriever,
};
use cbr_core::testing::{SpaceShape, behavior_spaces};
use cbr_core::{
    Behavior, BehaviorSpace, Case, CaseId, Context, ContextSimilarity, ContextSpace,
    ContextVariable, LinearRetriever, NamedComponent,
};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed, TestRunner};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;

/// What builds the retriever under test, ranking cases by a measure.
type Build<'a> = dyn Fn(SetSimilarity) -> Box<TrustRetriever> + 'a;

/// The scripted operator's one cause.
const TOO_SLOW: Cause = Cause::from_static("too-slow");

/// The context variables of a robot that knows its cargo and situation; the situations
/// declared half alike, the cargo matched exactly.
fn context_space() -> ContextSpace {
    let mut situation = ContextVariable::new("situation", &["routine", "emergency"]);
    situation.similarity = Some(vec![vec![1.0, 0.5], vec![0.5, 1.0]]);
    ContextSpace::new(vec![
        ContextVariable::new("cargo", &["normal", "hazardous"]),
        situation,
    ])
    .expect("a valid declaration")
}

/// Context number `k` of three (0: the default one).
fn context(k: u8) -> Context {
    let space = context_space();
    let settings: &[(&str, &str)] = match k % 3 {
        0 => &[],
        1 => &[("cargo", "hazardous")],
        _ => &[("situation", "emergency")],
    };
    space
        .context(settings.iter().copied())
        .expect("declared values")
}

/// Algorithm 2 over `space` at `lambda`, weighing contexts exactly or, when `declared`,
/// by [`context_space`]'s declared similarities.
fn measure(space: &Arc<BehaviorSpace>, lambda: f64, declared: bool) -> SetSimilarity {
    let measure = SetSimilarity::new(space.clone(), lambda).expect("a valid lambda");
    if declared {
        measure.with_context_similarity(ContextSimilarity::Declared(Arc::new(context_space())))
    } else {
        measure
    }
}

/// The reference: the linear scan.
fn linear(measure: SetSimilarity) -> Box<TrustRetriever> {
    Box::new(LinearRetriever::new(measure))
}

/// Checks that retrievers made by `build` (ranking cases by the measure it is given:
/// Algorithm 2 at some `lambda`, weighing contexts as a domain declares) return the linear
/// scan's answer by the same measure bit for bit (same case, same similarity, ties to the
/// smallest id):
/// - on 400 random scenarios (fixed seed): numeric and categorical components (plain and
///   with similarity tables), unequal and zero weights, `lambda` from 0.01 to 1, case
///   bases with duplicate behaviors and tied times, queries with and without exclusions
///   (Algorithm 1's own and arbitrary ones), and cases retained between queries, so the
///   retriever is told of cases incrementally; cases and queries in three contexts,
///   matched exactly or by a declared similarity (a retriever weighs contexts through its
///   measure, [`crate::SetSimilarity::compare_problems`]);
/// - on 1,000 episode-shaped cases over a patrol-like space (60 queries), a quarter of
///   them learned in another context, the contexts matched exactly and declared alike;
/// - through a [`TrustAdapter`]: 150 scripted episodes, the robot's context changing
///   every 40, make the same decisions as with the linear scan.
///
/// # Panics
/// With the failing case (proptest's minimal one) when an answer differs.
pub fn check_retriever(build: impl Fn(SetSimilarity) -> Box<TrustRetriever>) {
    let mut runner = TestRunner::new(Config {
        cases: 400,
        rng_seed: RngSeed::Fixed(0x7275_7374),
        failure_persistence: None,
        ..Config::default()
    });
    let reference = linear;
    let result = runner.run(&scenario(), |s| {
        prop_assert_eq!(answers(&s, &build), answers(&s, &reference));
        Ok(())
    });
    if let Err(e) = result {
        panic!("retriever check failed: {e}");
    }
    for declared in [false, true] {
        episode_shaped_case_bases_get_the_linear_answer(&build, declared);
    }
    let decisions = scripted_run(&build);
    let reused = decisions.iter().filter(|d| d.contains("Case")).count();
    assert!(reused > 20, "the script exercises reuse ({reused} reuses)");
    assert_eq!(
        decisions,
        scripted_run(&reference),
        "an adapter decides otherwise than with the linear scan"
    );
}

/// A similarity compared bit for bit, shown as its value (and its bits, which tell two
/// values that print alike apart).
#[derive(Clone, Copy)]
struct Exact(f64);

impl PartialEq for Exact {
    fn eq(&self, other: &Exact) -> bool {
        self.0.to_bits() == other.0.to_bits()
    }
}

impl std::fmt::Debug for Exact {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:?} (bits {:#018x})", self.0, self.0.to_bits())
    }
}

/// A retrieval answer, its similarity compared bit for bit.
type Answer = Option<(CaseId, Exact)>;

fn answer(
    memory: &TrustMemory,
    query: &TrustProblem,
    exclude: &dyn Fn(&TrustCase) -> bool,
) -> Answer {
    memory
        .retrieve(query, exclude)
        .map(|r| (r.id, Exact(r.similarity)))
}

/// Numeric grids, plain and tabled categorical components, unequal and zero weights.
fn space() -> impl Strategy<Value = Arc<BehaviorSpace>> {
    behavior_spaces(SpaceShape {
        values: 1..=25,
        ..SpaceShape::mixed()
    })
    .prop_map(Arc::new)
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

/// A case as (problem pairs, solution rank seed, context number).
type ScenarioCase = (Vec<(u64, f64)>, u64, u8);

#[derive(Clone, Debug)]
struct Scenario {
    space: Arc<BehaviorSpace>,
    lambda: f64,
    /// Whether the contexts are weighed by a declared similarity (else exactly).
    declared: bool,
    cases: Vec<ScenarioCase>,
    /// How many cases the memory starts with; the rest are retained between queries.
    initial: usize,
    /// Queries as (problem, context number).
    queries: Vec<(Vec<(u64, f64)>, u8)>,
    /// Excluded solution ranks (besides Algorithm 1's own exclusion, tried separately).
    excluded: Vec<u64>,
}

fn scenario() -> impl Strategy<Value = Scenario> {
    (
        space(),
        prop_oneof![Just(0.95), Just(1.0), Just(0.5), 0.01f64..1.0],
        any::<bool>(),
        prop::collection::vec(
            (pairs(6), prop_oneof![0u64..8, any::<u64>()], contexts()),
            0..40,
        ),
        any::<prop::sample::Index>(),
        prop::collection::vec((pairs(6), contexts()), 1..5),
        prop::collection::vec(0u64..8, 0..3),
    )
        .prop_map(
            |(space, lambda, declared, cases, initial, queries, excluded)| Scenario {
                initial: initial.index(cases.len() + 1),
                space,
                lambda,
                declared,
                cases,
                queries,
                excluded,
            },
        )
}

/// Context numbers, the default one most often.
fn contexts() -> impl Strategy<Value = u8> {
    prop_oneof![2 => Just(0u8), 1 => 0u8..3]
}

fn case(space: &BehaviorSpace, (problem, solution, k): &(Vec<(u64, f64)>, u64, u8)) -> TrustCase {
    Case {
        problem: TrustProblem::in_context(context(*k), evaluated(space, problem)),
        solution: space.unrank(solution % space.size()),
    }
}

/// Runs the scenario with retrievers made by `build`, returning every answer in order.
fn answers(s: &Scenario, build: &Build<'_>) -> Vec<Answer> {
    let mut base = TrustCaseBase::new();
    for c in &s.cases[..s.initial] {
        base.push(case(&s.space, c));
    }
    let mut memory = TrustMemory::new(base, build(measure(&s.space, s.lambda, s.declared)));
    let excluded: Vec<Behavior> = s
        .excluded
        .iter()
        .map(|r| s.space.unrank(r % s.space.size()))
        .collect();
    let mut pending = s.cases[s.initial..].iter();
    let mut out = Vec::new();
    loop {
        for (q, k) in &s.queries {
            let query = TrustProblem::in_context(context(*k), evaluated(&s.space, q));
            out.push(answer(&memory, &query, &|_| false));
            out.push(answer(&memory, &query, &|c| excluded.contains(&c.solution)));
            // Algorithm 1's exclusion: final behaviors already evaluated in the episode.
            out.push(answer(&memory, &query, &|c| {
                query.evaluated.iter().any(|e| e.behavior == c.solution)
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

/// 20 x 20 x 10 x 4 like the patrol space (trust does not depend on the domains crate).
fn patrol_like() -> Arc<BehaviorSpace> {
    Arc::new(
        BehaviorSpace::new(
            [20u16, 20, 10, 4]
                .iter()
                .enumerate()
                .map(|(k, &n)| NamedComponent::numeric(&format!("c{k}"), "", 0.0, 1.0, n).unwrap())
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

/// 1,000 cases shaped like random-walk episodes over a patrol-like space, a quarter of
/// them learned in an emergency (half alike when `declared`), 60 queries of the same shape
/// (every fourth in an emergency), Algorithm 1's exclusion: the reference's answer every time, the contexts
/// weighed exactly or, when `declared`, by a declared similarity.
fn episode_shaped_case_bases_get_the_linear_answer(build: &Build<'_>, declared: bool) {
    let space = patrol_like();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut base = TrustCaseBase::new();
    for _ in 0..1_000 {
        let len = rng.random_range(1..30);
        let k = 2 * u8::from(rng.random_range(0..4) == 0);
        base.push(Case {
            problem: TrustProblem::in_context(context(k), path(&space, len, &mut rng)),
            solution: space.draw(&mut rng),
        });
    }
    let reference = TrustMemory::new(base.clone(), linear(measure(&space, 0.95, declared)));
    let memory = TrustMemory::new(base, build(measure(&space, 0.95, declared)));
    let mut reused = 0;
    for q in 0..60 {
        let len = rng.random_range(1..30);
        let query = TrustProblem::in_context(
            context(2 * u8::from(q % 4 == 3)),
            path(&space, len, &mut rng),
        );
        let exclude = |c: &TrustCase| query.evaluated.iter().any(|e| e.behavior == c.solution);
        let expected = answer(&reference, &query, &exclude);
        reused += usize::from(expected.is_some());
        assert_eq!(
            answer(&memory, &query, &exclude),
            expected,
            "{} on an episode-shaped case base: {query:?}",
            memory.retriever_name()
        );
    }
    assert!(reused > 30, "the queries exercise reuse ({reused} of 60)");
}

/// A synthetic operator: each behavior completes commands with a probability that grows
/// with its first component, so episodes search, retain and reuse. Returns every
/// decision of an adapter whose memory uses retrievers made by `build`.
fn scripted_run(build: &Build<'_>) -> Vec<String> {
    let space = Arc::new(
        BehaviorSpace::new(vec![
            NamedComponent::numeric("a", "", 0.0, 1.0, 20).unwrap(),
            NamedComponent::numeric("b", "", 0.0, 1.0, 20).unwrap(),
        ])
        .unwrap(),
    );
    let config = AdapterConfig::default();
    let memory = TrustMemory::new(
        TrustCaseBase::new(),
        build(measure(&space, config.lambda, false)),
    );
    let mut adapter = TrustAdapter::with_parts(
        space.clone(),
        config.parameters(),
        memory,
        config.search.build(),
        ChaCha8Rng::seed_from_u64(5),
    )
    .expect("the paper's parameters");
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let mut decisions = Vec::new();
    for episode in 0..150u8 {
        if episode % 40 == 0 {
            adapter.set_context(context(episode / 40)).unwrap();
        }
        adapter.begin_episode(space.draw(&mut rng)).unwrap();
        loop {
            let current = adapter.episode().unwrap().current;
            let p = f64::from(current.get(0)) / 19.0;
            let duration = f64::from(rng.random_range(1u32..20));
            let outcome = if rng.random_bool(p) {
                Outcome::completed(1.0, duration)
            } else {
                Outcome::interrupted(1.0, duration).stating(Some(TOO_SLOW))
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
