//! The paper's algorithms: Algorithm 2 (set similarity) on episode-sized sets and
//! Algorithm 1 (selectBehavior) over a case base of 1,000 synthetic patrol cases, all drawn
//! by the `benches` generator.
#![allow(missing_docs)] // criterion's macros generate undocumented items

use cbr_core::{BehaviorSpace, CaseMemory, LinearRetriever};
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use std::sync::Arc;
use trust::search::RandomWalk;
use trust::{SetSimilarity, select_behavior};

fn set_similarity(c: &mut Criterion) {
    let space = domains::spaces::patrol_space();
    let measure = SetSimilarity::new(space.clone(), 0.95).unwrap();
    let mut episodes = benches::Episodes::new(&space, 1);
    let mut group = c.benchmark_group("algorithm2");
    for len in [4usize, 16, 64] {
        let e1 = episodes.case_of_length(len).problem.evaluated;
        let e2 = episodes.case_of_length(len).problem.evaluated;
        group.bench_with_input(BenchmarkId::new("set_similarity", len), &len, |b, _| {
            b.iter(|| measure.compare(black_box(&e1), black_box(&e2)))
        });
    }
    group.finish();
}

fn select(c: &mut Criterion) {
    let space: Arc<BehaviorSpace> = domains::spaces::patrol_space();
    let base = benches::case_base(&space, 1_000, 2);
    // A fresh E_past (seed 3, not in the base) of 16 pairs, about the real mean length.
    let e_past = benches::Episodes::new(&space, 3).case_of_length(16).problem;
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let measure = SetSimilarity::new(space.clone(), 0.95).unwrap();
    let memory = CaseMemory::new(base, Box::new(LinearRetriever::new(measure)));
    let mut walk = RandomWalk::new();
    c.bench_function("algorithm1/select_behavior/1000", |b| {
        b.iter(|| {
            select_behavior(
                black_box(&e_past),
                Some(&memory),
                &mut walk,
                &space,
                &mut rng,
            )
        })
    });
}

criterion_group!(benches, set_similarity, select);
criterion_main!(benches);
