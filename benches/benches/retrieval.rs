//! Retrieval indices on the same workload: Algorithm 1's query (with its exclusion of final
//! behaviors already evaluated) over synthetic patrol case bases of 100 to 100,000 cases
//! (`benches::case_base`, lengths following the real patrol cases), for every
//! `RetrieverKind`.
//!
//! - `retrieval/<retriever>/<cases>`: one query (the workload cycles through 300 query
//!   `E_past`s drawn like the cases, `benches::queries`);
//! - `retrieval-build/<retriever>/<cases>`: telling a fresh retriever of every case;
//! - `retrieval-lambda/<retriever>/<lambda>`: 10,000 cases under lower `lambda`s;
//! - on stderr: the real and the achieved `|E_past|` distributions (the run stops if the
//!   synthetic mean is 3% or more off the real one), the index's heap bytes per case, and
//!   each retriever's mean time over the same 40 queries.
#![allow(missing_docs)] // criterion's macros generate undocumented items

use cbr_core::Retrieved;
use criterion::{BatchSize, BenchmarkId, Criterion, SamplingMode, criterion_group, criterion_main};
use std::hint::black_box;
use std::time::Instant;
use trust::{
    Evaluated, InvertedIndex, RetrieverKind, SetSimilarity, TrustCase, TrustCaseBase, TrustMemory,
};

const SIZES: [usize; 4] = [100, 1_000, 10_000, 100_000];
const LAMBDA: f64 = 0.95;
const SEED: u64 = 2014;
/// Queries in the workload; each iteration takes the next.
const QUERIES: usize = 300;
/// Queries every retriever answers for the mean printed to stderr.
const SAME: usize = 40;

fn prefix(base: &TrustCaseBase, n: usize) -> TrustCaseBase {
    let mut out = TrustCaseBase::new();
    for case in &base.cases()[..n] {
        out.push(case.clone());
    }
    out
}

/// Algorithm 1's query: the case most similar to `q` among those whose final behavior `q`
/// has not evaluated.
fn answer(memory: &TrustMemory, q: &Vec<Evaluated>) -> Option<Retrieved> {
    let exclude = |c: &TrustCase| q.iter().any(|e| e.behavior == c.solution);
    black_box(memory.retrieve(black_box(q), &exclude))
}

fn retrieval(c: &mut Criterion) {
    let space = domains::spaces::patrol_space();
    let largest = SIZES[SIZES.len() - 1];
    let all = benches::case_base(&space, largest, SEED);
    let queries = benches::queries(&space, QUERIES, SEED);
    let real = benches::LengthStats::of(benches::patrol_case_lengths());
    let made = benches::LengthStats::of(all.cases().iter().map(|c| c.problem.len()));
    let asked = benches::LengthStats::of(queries.iter().map(Vec::len));
    eprintln!("|E_past| of the real patrol cases: {real}");
    eprintln!("|E_past| over {largest} synthetic cases: {made}");
    eprintln!("|E_past| of the {QUERIES} queries: {asked}");
    let same = benches::LengthStats::of(queries[..SAME].iter().map(Vec::len));
    eprintln!("|E_past| of the first {SAME} queries: {same}");
    let off = (made.mean - real.mean).abs() / real.mean;
    assert!(
        off < 0.03,
        "the synthetic mean is {:.1}% off the real one",
        100.0 * off
    );

    let mut query = c.benchmark_group("retrieval");
    query.sampling_mode(SamplingMode::Flat);
    for &n in &SIZES {
        let base = prefix(&all, n);
        let measure = SetSimilarity::new(space.clone(), LAMBDA).unwrap();
        let mut index = InvertedIndex::new(measure);
        for (id, case) in base.iter() {
            cbr_core::Retriever::retain(&mut index, id, case);
        }
        eprintln!(
            "inverted_index over {n} cases: {:.0} heap bytes per case",
            index.heap_bytes() as f64 / n as f64
        );
        for kind in RetrieverKind::ALL {
            let memory = TrustMemory::new(base.clone(), kind.build(space.clone(), LAMBDA).unwrap());
            // The 100,000-case scans take a good fraction of a second per query.
            query.sample_size(if n >= 100_000 { 10 } else { 30 });
            let mut next = 0;
            query.bench_function(BenchmarkId::new(memory.retriever_name(), n), |b| {
                b.iter(|| {
                    next += 1;
                    answer(&memory, &queries[(next - 1) % queries.len()])
                })
            });
            // Criterion's median mixes query lengths differently for fast and slow
            // retrievers; this mean is over the same queries for all.
            let start = Instant::now();
            for q in &queries[..SAME] {
                answer(&memory, q);
            }
            eprintln!(
                "{} over {n} cases: {:.4} ms per query, mean over the first {SAME} queries",
                memory.retriever_name(),
                start.elapsed().as_secs_f64() * 1e3 / SAME as f64
            );
        }
    }
    query.finish();

    let mut group = c.benchmark_group("retrieval-build");
    group.sample_size(10);
    for &n in &SIZES {
        let base = prefix(&all, n);
        for kind in RetrieverKind::ALL {
            let name = kind.build(space.clone(), LAMBDA).unwrap().name().to_owned();
            group.bench_function(BenchmarkId::new(name, n), |b| {
                b.iter_batched(
                    || base.clone(),
                    |base| TrustMemory::new(base, kind.build(space.clone(), LAMBDA).unwrap()),
                    BatchSize::LargeInput,
                )
            });
        }
    }
    group.finish();
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
                    answer(&memory, &queries[(next - 1) % queries.len()])
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, retrieval, lambda_sweep);
criterion_main!(benches);
