//! The reference vectors of `tests/data/paper-algorithms.json` (computed independently from
//! the specification) against this crate's Algorithms 1 (through every retriever) and 2 and
//! random walk.

use cbr_core::{Behavior, BehaviorSpace, Case, CaseBase, CaseMemory, NamedComponent};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Deserialize;
use std::collections::HashSet;
use std::sync::Arc;
use trust::search::{RandomWalk, longest_resisting};
use trust::{
    Evaluated, RetrieverKind, Selection, SetSimilarity, Source, TrustProblem, select_behavior,
};

#[derive(Deserialize)]
struct Vectors {
    set_similarity: Vec<SetSimilarityVector>,
    select_behavior: Vec<SelectVector>,
    random_walk: Vec<WalkVector>,
}

#[derive(Deserialize)]
struct ComponentSpec {
    name: String,
    min: f64,
    step: f64,
    size: u16,
}

#[derive(Deserialize)]
struct Pair {
    behavior: Vec<f64>,
    t: f64,
}

#[derive(Deserialize)]
struct SetSimilarityVector {
    space: Vec<ComponentSpec>,
    e1: Vec<Pair>,
    e2: Vec<Pair>,
    sim: f64,
}

#[derive(Deserialize)]
struct StoredCase {
    e_past: Vec<Pair>,
    #[serde(rename = "final")]
    final_behavior: Vec<f64>,
}

#[derive(Deserialize)]
struct SelectVector {
    space: Vec<ComponentSpec>,
    e_past: Vec<Pair>,
    case_base: Vec<StoredCase>,
    similarities: Vec<Option<f64>>,
    selected_case: Option<usize>,
}

#[derive(Deserialize)]
struct WalkVector {
    space: Vec<ComponentSpec>,
    evaluated: Vec<Pair>,
    e_max: Vec<f64>,
    min_changes: Option<u32>,
    candidates: Vec<Vec<f64>>,
}

fn load() -> Vectors {
    let text = include_str!("../data/paper-algorithms.json");
    serde_json::from_str(text).expect("the vectors parse")
}

fn space(specs: &[ComponentSpec]) -> Arc<BehaviorSpace> {
    Arc::new(
        BehaviorSpace::new(
            specs
                .iter()
                .map(|c| NamedComponent::numeric(&c.name, "", c.min, c.step, c.size).unwrap())
                .collect(),
        )
        .unwrap(),
    )
}

fn behavior(space: &BehaviorSpace, values: &[f64]) -> Behavior {
    let indices: Vec<u16> = space
        .components()
        .iter()
        .zip(values)
        .map(|(c, &v)| {
            c.index_of_numeric(v)
                .expect("vector values lie on the grid")
        })
        .collect();
    Behavior::new(&indices)
}

fn pairs(space: &BehaviorSpace, pairs: &[Pair]) -> Vec<Evaluated> {
    pairs
        .iter()
        .map(|p| Evaluated {
            behavior: behavior(space, &p.behavior),
            time: p.t,
        })
        .collect()
}

#[test]
fn algorithm_2_matches_every_vector() {
    let vectors = load();
    assert!(!vectors.set_similarity.is_empty());
    for (i, v) in vectors.set_similarity.iter().enumerate() {
        let space = space(&v.space);
        let measure = SetSimilarity::new(space.clone(), 0.95).unwrap();
        let got = measure.compare(&pairs(&space, &v.e1), &pairs(&space, &v.e2));
        assert!(
            (got - v.sim).abs() < 1e-9,
            "set_similarity[{i}]: got {got}, expected {}",
            v.sim
        );
    }
}

#[test]
fn algorithm_1_matches_every_vector() {
    let vectors = load();
    assert!(!vectors.select_behavior.is_empty());
    for (i, v) in vectors.select_behavior.iter().enumerate() {
        let space = space(&v.space);
        let measure = SetSimilarity::new(space.clone(), 0.95).unwrap();
        let e_past = pairs(&space, &v.e_past);
        let mut base: CaseBase<TrustProblem, _> = CaseBase::new();
        for case in &v.case_base {
            base.push(Case {
                problem: pairs(&space, &case.e_past).into(),
                solution: behavior(&space, &case.final_behavior),
            });
        }
        // Per-case similarities and exclusions.
        for (k, (case, expected)) in base.cases().iter().zip(&v.similarities).enumerate() {
            let excluded = e_past.iter().any(|e| e.behavior == case.solution);
            match expected {
                None => assert!(excluded, "select_behavior[{i}] case {k} should be excluded"),
                Some(s) => {
                    assert!(
                        !excluded,
                        "select_behavior[{i}] case {k} should not be excluded"
                    );
                    let got = measure.compare(&e_past, &case.problem.evaluated);
                    assert!(
                        (got - s).abs() < 1e-9,
                        "select_behavior[{i}] case {k}: {got} vs {s}"
                    );
                }
            }
        }
        // Every retriever a config can name gives the same selection.
        for kind in RetrieverKind::ALL {
            let retriever = kind.build(space.clone(), 0.95).unwrap();
            let memory = CaseMemory::new(base.clone(), retriever);
            let mut walk = RandomWalk::new();
            let mut rng = ChaCha8Rng::seed_from_u64(i as u64);
            let query = TrustProblem::new(e_past.clone());
            let selection = select_behavior(&query, Some(&memory), &mut walk, &space, &mut rng);
            match (selection, v.selected_case) {
                (
                    Selection::Next {
                        behavior,
                        source: Source::Case { case, .. },
                    },
                    Some(expected),
                ) => {
                    assert_eq!(case.index(), expected, "select_behavior[{i}] {kind:?}");
                    assert_eq!(behavior, memory.base().cases()[expected].solution);
                }
                (
                    Selection::Next {
                        source: Source::Search,
                        ..
                    }
                    | Selection::Exhausted { .. },
                    None,
                ) => {}
                (got, expected) => {
                    panic!("select_behavior[{i}] {kind:?}: got {got:?}, expected case {expected:?}")
                }
            }
        }
    }
}

#[test]
fn random_walk_matches_every_vector() {
    let vectors = load();
    assert!(!vectors.random_walk.is_empty());
    for (i, v) in vectors.random_walk.iter().enumerate() {
        let space = space(&v.space);
        let evaluated = pairs(&space, &v.evaluated);
        let e_max = behavior(&space, &v.e_max);
        assert_eq!(
            longest_resisting(&evaluated).unwrap().behavior,
            e_max,
            "random_walk[{i}] e_max"
        );
        let expected: HashSet<Behavior> =
            v.candidates.iter().map(|c| behavior(&space, c)).collect();
        let set: HashSet<Behavior> = evaluated.iter().map(|e| e.behavior).collect();
        let candidates: HashSet<Behavior> = RandomWalk::candidates(&space, &e_max, &set)
            .into_iter()
            .collect();
        assert_eq!(candidates, expected, "random_walk[{i}] candidates");
        if let Some(d) = v.min_changes {
            assert!(candidates.iter().all(|c| space.changes(&e_max, c) == d));
        }
        // Over many seeds the walk returns each candidate, and nothing else.
        let mut drawn = HashSet::new();
        for seed in 0..(40 * expected.len().max(1) as u64) {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            match cbr_core::Searcher::propose(&mut RandomWalk::new(), &space, &evaluated, &mut rng)
            {
                cbr_core::Proposal::Next(b) => {
                    assert!(expected.contains(&b), "random_walk[{i}] drew {b:?}");
                    drawn.insert(b);
                }
                cbr_core::Proposal::Exhausted { keep } => {
                    assert!(v.min_changes.is_none(), "random_walk[{i}] stopped early");
                    assert_eq!(keep, e_max);
                }
            }
        }
        assert_eq!(drawn, expected, "random_walk[{i}] draws every candidate");
    }
}
