//! Retrieval indices on the same workload: Algorithm 1's query (with its exclusion of final
//! behaviors already evaluated) over synthetic patrol case bases of 100 to 100,000 cases
//! (`benches::case_base`, lengths following the real patrol cases), for every
//! `RetrieverKind`.
//!
//! - `retrieval/<retriever>/<cases>`: one query (the workload cycles through 300 query
//!   `E_past`s drawn like the cases, `benches::queries`);
//! - `retrieval-build/<retriever>/<cases>`: telling a fresh retriever of every case
//!   (these two registered by `benches::retrieval::bench_retriever`, the function a
//!   user's retriever goes through too);
//! - `retrieval-lambda/<retriever>/<lambda>`: 10,000 cases under lower `lambda`s;
//! - on stderr: the real and the achieved `|E_past|` distributions (the run stops if the
//!   synthetic mean is 3% or more off the real one), the index's heap bytes per case, and
//!   each retriever's mean time over the same 40 queries.
#![allow(missing_docs)] // criterion's macros generate undocumented items

use benches::retrieval::{LAMBDA, QUERIES, SEED, SIZES, Workload, bench_retriever, query};
use criterion::{BenchmarkId, Criterion, SamplingMode, criterion_group, criterion_main};
use trust::{InvertedIndex, RetrieverKind, SetSimilarity, TrustMemory};

fn retrieval(c: &mut Criterion) {
    let workload = Workload::patrol();
    for &n in &SIZES {
        let measure = SetSimilarity::new(workload.space.clone(), LAMBDA).unwrap();
        let mut index = InvertedIndex::new(measure);
        for (id, case) in workload.cases(n).iter() {
            cbr_core::Retriever::retain(&mut index, id, case);
        }
        eprintln!(
            "inverted_index over {n} cases: {:.0} heap bytes per case",
            index.heap_bytes() as f64 / n as f64
        );
    }
    for kind in RetrieverKind::ALL {
        let name = kind
            .build(workload.space.clone(), LAMBDA)
            .unwrap()
            .name()
            .to_owned();
        bench_retriever(c, &workload, &name, |measure| kind.build_measure(measure));
    }
}

/// Where the index stops paying: the same 10,000 cases and queries under lower `lambda`s,
/// whose neighbourhoods are larger.
fn lambda_sweep(c: &mut Criterion) {
    let space = domains::spaces::patrol_space();
    let base = benches::case_base(&space, 10_000, SEED);
    let queries = benches::queries(&space, QUERIES, SEED);
    let mut group = c.benchmark_group("retrieval-lambda");
    group.sampling_mode(SamplingMode::Flat);
    group.sample_size(10);
    for lambda in [0.95, 0.9, 0.8, 0.6] {
        for kind in RetrieverKind::ALL {
            let memory = TrustMemory::new(base.clone(), kind.build(space.clone(), lambda).unwrap());
            let mut next = 0;
            group.bench_function(BenchmarkId::new(memory.retriever_name(), lambda), |b| {
                b.iter(|| {
                    next += 1;
                    query(&memory, &queries[(next - 1) % queries.len()])
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, retrieval, lambda_sweep);
criterion_main!(benches);
