//! The paper's algorithms: Algorithm 2 (set similarity) on episode-sized sets and
//! Algorithm 1 (selectBehavior) over a case base of 1,000 synthetic patrol cases.
#![allow(missing_docs)] // criterion's macros generate undocumented items

use cbr_core::{Behavior, BehaviorSpace, Case, CaseMemory, LinearRetriever};
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use std::sync::Arc;
use trust::search::RandomWalk;
use trust::{Evaluated, SetSimilarity, TrustCaseBase, select_behavior};

/// An episode-like path: a random start and one-change steps, as the random walk makes.
fn synthetic_episode(space: &BehaviorSpace, len: usize, rng: &mut ChaCha8Rng) -> Vec<Evaluated> {
    let mut current = space.draw(rng);
    let mut path = Vec::with_capacity(len);
    for _ in 0..len {
        path.push(Evaluated {
            behavior: current,
            time: rng.random_range(5.0..300.0),
        });
        let neighbours: Vec<Behavior> = space.neighbours(&current).collect();
        current = neighbours[rng.random_range(0..neighbours.len())];
    }
    path
}

fn set_similarity(c: &mut Criterion) {
    let space = domains::spaces::patrol_space();
    let measure = SetSimilarity::new(space.clone(), 0.95).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut group = c.benchmark_group("algorithm2");
    for len in [4usize, 16, 64] {
        let e1 = synthetic_episode(&space, len, &mut rng);
        let e2 = synthetic_episode(&space, len, &mut rng);
        group.bench_with_input(BenchmarkId::new("set_similarity", len), &len, |b, _| {
            b.iter(|| measure.compare(black_box(&e1), black_box(&e2)))
        });
    }
    group.finish();
}

fn select(c: &mut Criterion) {
    let space: Arc<BehaviorSpace> = domains::spaces::patrol_space();
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let mut base = TrustCaseBase::new();
    for _ in 0..1_000 {
        let len = rng.random_range(1..=20);
        let problem = synthetic_episode(&space, len, &mut rng);
        let solution = space.draw(&mut rng);
        base.push(Case { problem, solution });
    }
    let measure = SetSimilarity::new(space.clone(), 0.95).unwrap();
    let memory = CaseMemory::new(base, Box::new(LinearRetriever::new(measure)));
    let e_past = synthetic_episode(&space, 8, &mut rng);
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
