//! One simulated pick judged by an operator: the unit of work of every warehouse
//! experiment, for a fixed behavior and for behaviors drawn across the space.
#![allow(missing_docs)] // criterion's macros generate undocumented items

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use trustcbr::lab::Domain;
use trustcbr::rand::SeedableRng;
use trustcbr::rand::rngs::StdRng;
use warehouse::{WarehouseDomain, builtin_operators};

fn one_pick(c: &mut Criterion) {
    let domain = WarehouseDomain::new();
    let space = domain.space().clone();
    let mut group = c.benchmark_group("warehouse/run");
    for operator in builtin_operators() {
        let mut rng = StdRng::seed_from_u64(1);
        let fixed = space
            .parse("gripper=suction,map=last-survey,speed=2,grip_force=80")
            .unwrap();
        group.bench_function(BenchmarkId::new(&operator.name, "fixed"), |b| {
            b.iter(|| black_box(domain.run(&fixed, &operator, &mut rng)))
        });
        group.bench_function(BenchmarkId::new(&operator.name, "random"), |b| {
            b.iter(|| {
                let behavior = space.draw(&mut rng);
                black_box(domain.run(&behavior, &operator, &mut rng))
            })
        });
    }
}

criterion_group!(benches, one_pick);
criterion_main!(benches);
