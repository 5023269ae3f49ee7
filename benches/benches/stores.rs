//! Case stores holding 100,000 synthetic patrol cases (`benches::case_base`), as
//! `trustcbr serve` uses them:
//!
//! - `stores/retain/<store>`: one retention acknowledged: the append transaction (durable:
//!   SQLite `synchronous=FULL`, PostgreSQL's flushed commit) and the case added to the
//!   shared memory, through `SharedCases::retain`;
//! - `stores/open/<store>`: opening the case base and loading every case into a memory
//!   with the domain's retriever (`SharedCases::open`, what `serve` does at start);
//! - `stores/list/<store>`: a `cases` reply of all 100,000 cases written to a sink,
//!   streamed case by case (the reply is never built whole in memory).
//!
//! `<store>` is `sqlite` (a file in a temporary directory) and `postgres` when
//! `TRUSTCBR_TEST_POSTGRES` names a server (a fresh database is created on it); without
//! it the PostgreSQL benchmarks are skipped with a message.
#![allow(missing_docs)] // criterion's macros generate undocumented items

use criterion::{Criterion, criterion_group, criterion_main};
use service::store::{self, Identity, Location};
use service::{DomainDefinition, Session, SharedCases};
use std::sync::Arc;
use std::time::Duration;

const CASES: usize = 100_000;
const SEED: u64 = 2014;

/// The case base at `location`, filled with `CASES` synthetic cases.
fn fill(location: &Location, domain: &DomainDefinition) {
    let identity = Identity {
        domain: domain.name.clone(),
        space: (*domain.space).clone(),
    };
    let cases = benches::case_base(&domain.space, CASES, SEED);
    let mut store = store::open(location, &identity).expect("the store opens");
    store
        .append_all(cases.cases())
        .expect("the cases are stored");
}

fn bench_store(c: &mut Criterion, name: &str, location: &Location) {
    let domain = DomainDefinition::new(
        "patrol",
        domains::Scenario::Patrol.space(),
        domains::Scenario::Patrol.causes().to_vec(),
        trust::AdapterConfig::default(),
    );
    fill(location, &domain);
    let mut group = c.benchmark_group("stores");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(10));
    group.bench_function(format!("open/{name}"), |b| {
        b.iter(|| SharedCases::open(&domain, location).expect("the base opens"));
    });
    let shared = Arc::new(SharedCases::open(&domain, location).expect("the base opens"));
    let mut session = Session::new(domain.clone(), shared.clone(), SEED).expect("a session");
    let mut meter = Meter::default();
    let before = resident_bytes();
    session
        .handle_line(br#"{"request": "cases"}"#)
        .expect("a reply")
        .write_line(&mut meter)
        .expect("the meter takes it");
    eprintln!(
        "stores/list/{name}: a {:.0} MB reply of {CASES} cases; resident memory grew by at most {:.1} MB while it was written",
        meter.bytes as f64 / 1e6,
        meter.peak.saturating_sub(before) as f64 / 1e6,
    );
    group.bench_function(format!("list/{name}"), |b| {
        b.iter(|| {
            let reply = session
                .handle_line(br#"{"request": "cases"}"#)
                .expect("a reply");
            reply
                .write_line(&mut std::io::sink())
                .expect("a sink takes it");
        });
    });
    group
        .sample_size(50)
        .measurement_time(Duration::from_secs(5));
    let mut episodes = benches::Episodes::new(&domain.space, SEED ^ 0x7e7a1);
    group.bench_function(format!("retain/{name}"), |b| {
        b.iter_batched(
            || episodes.next_case(),
            |case| shared.retain(case).expect("the case is stored"),
            criterion::BatchSize::SmallInput,
        );
    });
    group.finish();
}

/// A writer that counts what it is given and samples the resident memory as it goes.
#[derive(Default)]
struct Meter {
    bytes: u64,
    peak: u64,
    since_sample: u64,
}

impl std::io::Write for Meter {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.bytes += buf.len() as u64;
        self.since_sample += buf.len() as u64;
        if self.since_sample > 1 << 20 {
            self.since_sample = 0;
            self.peak = self.peak.max(resident_bytes());
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// This process's resident memory (`VmRSS`), in bytes.
fn resident_bytes() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok())
        .map_or(0, |kb| kb * 1024)
}

fn stores(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("a temporary directory");
    bench_store(c, "sqlite", &Location::Sqlite(dir.path().join("cases.db")));
    match std::env::var("TRUSTCBR_TEST_POSTGRES") {
        Ok(url) => {
            let database = format!("trustcbr_bench_{}", std::process::id());
            let mut admin = postgres::Client::connect(&url, postgres::NoTls).expect("connects");
            admin
                .batch_execute(&format!("CREATE DATABASE {database}"))
                .expect("creates the database");
            let (server, _) = url.rsplit_once('/').expect("a database URL");
            bench_store(
                c,
                "postgres",
                &Location::Postgres(format!("{server}/{database}")),
            );
            admin
                .batch_execute(&format!("DROP DATABASE {database} WITH (FORCE)"))
                .expect("drops the database");
        }
        Err(_) => eprintln!(
            "stores/*/postgres skipped: set TRUSTCBR_TEST_POSTGRES=postgres://... (eval \"$(.ci/start-postgres)\")"
        ),
    }
}

criterion_group!(benches, stores);
criterion_main!(benches);
