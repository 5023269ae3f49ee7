//! The retrieval comparison as a library: a retriever, built-in or a user's, joins the
//! `retrieval/<name>/<cases>` (one query) and `retrieval-build/<name>/<cases>` (telling a
//! fresh retriever of every case) criterion groups over the same synthetic workload as
//! every other: Algorithm 1's query (with its exclusion of final behaviors already
//! evaluated) over synthetic patrol case bases of 100 to 100,000 cases ([`Workload`],
//! from [`crate::case_base`] and [`crate::queries`]). `benches/benches/retrieval.rs`
//! registers the built-in retrievers through [`bench_retriever`]; a user's crate does the
//! same from its own bench target (with `benches`, `criterion` and `trust` as
//! dev-dependencies and `harness = false`):
//!
//! ```no_run
//! use criterion::{Criterion, criterion_group, criterion_main};
//! use trust::{SetSimilarity, TrustRetriever};
//!
//! fn retrieval(c: &mut Criterion) {
//!     let workload = benches::retrieval::Workload::patrol();
//!     // The user's own index (here the reference scan stands in for it).
//!     benches::retrieval::bench_retriever(c, &workload, "my-index", |measure: SetSimilarity| {
//!         Box::new(cbr_core::LinearRetriever::new(measure)) as Box<TrustRetriever>
//!     });
//! }
//!
//! criterion_group!(benches, retrieval);
//! criterion_main!(benches);
//! ```
//!
//! Criterion then keeps the results beside the built-ins' (`target/criterion/retrieval/`),
//! and `trust::testing::check_retriever` checks the same retriever returns their answers.

use cbr_core::{BehaviorSpace, Retrieved};
use criterion::{BatchSize, BenchmarkId, Criterion, SamplingMode};
use std::hint::black_box;
use std::sync::Arc;
use std::time::Instant;
use trust::{SetSimilarity, TrustCase, TrustCaseBase, TrustMemory, TrustProblem, TrustRetriever};

/// The case-base sizes compared.
pub const SIZES: [usize; 4] = [100, 1_000, 10_000, 100_000];
/// Algorithm 2's threshold (the paper's).
pub const LAMBDA: f64 = 0.95;
/// The seed of the synthetic cases and queries.
pub const SEED: u64 = 2014;
/// Queries in the workload; each iteration takes the next.
pub const QUERIES: usize = 300;
/// Queries every retriever answers for the mean printed to stderr.
pub const SAME: usize = 40;

/// The synthetic patrol workload: the largest case base (smaller ones are its prefixes)
/// and the queries.
pub struct Workload {
    /// The patrol space.
    pub space: Arc<BehaviorSpace>,
    cases: TrustCaseBase,
    /// The query `E_past`s, drawn like the cases from another stream.
    pub queries: Vec<TrustProblem>,
}

impl Workload {
    /// [`SIZES`]' largest number of synthetic patrol cases and [`QUERIES`] queries from
    /// [`SEED`]. Prints the real and achieved `|E_past|` distributions to stderr and stops
    /// if the synthetic mean is 3% or more off the real one.
    ///
    /// # Panics
    /// When the synthetic mean is that far off.
    pub fn patrol() -> Self {
        let space = domains::spaces::patrol_space();
        let largest = SIZES[SIZES.len() - 1];
        let cases = crate::case_base(&space, largest, SEED);
        let queries = crate::queries(&space, QUERIES, SEED);
        let real = crate::LengthStats::of(crate::patrol_case_lengths());
        let made = crate::LengthStats::of(cases.cases().iter().map(|c| c.problem.evaluated.len()));
        let asked = crate::LengthStats::of(queries.iter().map(|q| q.evaluated.len()));
        eprintln!("|E_past| of the real patrol cases: {real}");
        eprintln!("|E_past| over {largest} synthetic cases: {made}");
        eprintln!("|E_past| of the {QUERIES} queries: {asked}");
        let same = crate::LengthStats::of(queries[..SAME].iter().map(|q| q.evaluated.len()));
        eprintln!("|E_past| of the first {SAME} queries: {same}");
        let off = (made.mean - real.mean).abs() / real.mean;
        assert!(
            off < 0.03,
            "the synthetic mean is {:.1}% off the real one",
            100.0 * off
        );
        Self {
            space,
            cases,
            queries,
        }
    }

    /// The first `n` cases.
    pub fn cases(&self, n: usize) -> TrustCaseBase {
        let mut out = TrustCaseBase::new();
        for case in &self.cases.cases()[..n] {
            out.push(case.clone());
        }
        out
    }
}

/// Algorithm 1's query: the case most similar to `q` among those whose final behavior `q`
/// has not evaluated.
pub fn query(memory: &TrustMemory, q: &TrustProblem) -> Option<Retrieved> {
    let exclude = |c: &TrustCase| q.evaluated.iter().any(|e| e.behavior == c.solution);
    black_box(memory.retrieve(black_box(q), &exclude))
}

/// Benchmarks the retriever `build` makes (ranking cases by the measure it is given,
/// Algorithm 2 at [`LAMBDA`], like a `trust::RetrieverFactory`), named `name`, over every
/// size of [`SIZES`]:
/// `retrieval/<name>/<cases>` (one query; the workload cycles through its queries) and
/// `retrieval-build/<name>/<cases>`. Prints to stderr its mean time over the first
/// [`SAME`] queries (criterion's median mixes query lengths differently for fast and slow
/// retrievers; this mean is over the same queries for all).
pub fn bench_retriever(
    c: &mut Criterion,
    workload: &Workload,
    name: &str,
    build: impl Fn(SetSimilarity) -> Box<TrustRetriever>,
) {
    let retriever = || {
        build(
            SetSimilarity::new(workload.space.clone(), LAMBDA)
                .expect("the paper's lambda is valid"),
        )
    };
    let mut group = c.benchmark_group("retrieval");
    group.sampling_mode(SamplingMode::Flat);
    for &n in &SIZES {
        let memory = TrustMemory::new(workload.cases(n), retriever());
        // The 100,000-case scans take a good fraction of a second per query.
        group.sample_size(if n >= 100_000 { 10 } else { 30 });
        let mut next = 0;
        group.bench_function(BenchmarkId::new(name, n), |b| {
            b.iter(|| {
                next += 1;
                query(
                    &memory,
                    &workload.queries[(next - 1) % workload.queries.len()],
                )
            })
        });
        let start = Instant::now();
        for q in &workload.queries[..SAME] {
            query(&memory, q);
        }
        eprintln!(
            "{name} over {n} cases: {:.4} ms per query, mean over the first {SAME} queries",
            start.elapsed().as_secs_f64() * 1e3 / SAME as f64
        );
    }
    group.finish();

    let mut group = c.benchmark_group("retrieval-build");
    group.sample_size(10);
    for &n in &SIZES {
        let base = workload.cases(n);
        group.bench_function(BenchmarkId::new(name, n), |b| {
            b.iter_batched(
                || base.clone(),
                |base| TrustMemory::new(base, retriever()),
                BatchSize::LargeInput,
            )
        });
    }
    group.finish();
}
