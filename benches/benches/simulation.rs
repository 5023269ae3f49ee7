//! One simulated run per task, judged by an operator: the unit of work of every
//! experiment. Plans are cached per (padding, people present), so the caches are warmed
//! first and the figures are for the steady state an experiment runs in.
#![allow(missing_docs)] // criterion's macros generate undocumented items

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use domains::{Scenario, UgvDomain, builtin_operators};
use lab::Domain;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;

fn one_run(c: &mut Criterion) {
    let mut group = c.benchmark_group("simulation/run");
    for (scenario, text) in [
        (Scenario::Movement, "speed=5,padding=0.5"),
        (
            Scenario::Patrol,
            "speed=3,padding=0.5,scan_time=2.5,scan_distance=0.5",
        ),
    ] {
        let domain = UgvDomain::new(scenario);
        let operator = &builtin_operators(scenario)[0];
        let space = domain.space().clone();
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        // Warm every plan: all paddings, enough runs to meet every set of people.
        for _ in 0..20_000 {
            domain.run(&space.draw(&mut rng), operator, &mut rng);
        }
        let fixed = space.parse(text).unwrap();
        group.bench_function(BenchmarkId::new(scenario.as_str(), "fixed"), |b| {
            b.iter(|| black_box(domain.run(&fixed, operator, &mut rng)))
        });
        group.bench_function(BenchmarkId::new(scenario.as_str(), "random"), |b| {
            b.iter(|| {
                let behavior = space.draw(&mut rng);
                black_box(domain.run(&behavior, operator, &mut rng))
            })
        });
    }
    group.finish();
}

criterion_group!(benches, one_run);
criterion_main!(benches);
