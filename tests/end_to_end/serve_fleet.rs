//! Several `trustcbr serve` processes on one case base, as a fleet of robots would run
//! them: on one SQLite file, and on one PostgreSQL database (the server `.ci/run` starts;
//! the test reads its URL from `TRUSTCBR_TEST_POSTGRES`, and is skipped with a message
//! when the variable is absent, except under CI, where it fails).
//!
//! Four servers drive 200 episodes in all, concurrently. Before every episode a server
//! must already hold every case any server had acknowledged (it catches up before each
//! selection); at the end every acknowledged case is stored exactly once, and every
//! server lists the same cases in the same order as the store.

use serde_json::Value;
use service::store::{Location, StoreId};
use std::collections::BTreeMap;
use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use crate::support;

const SERVERS: usize = 4;
const EPISODES: usize = 200;

/// One server process spoken to over its stdin and stdout.
struct Server {
    log: std::path::PathBuf,
    child: Child,
    input: ChildStdin,
    output: BufReader<ChildStdout>,
}

impl Server {
    fn start(domain: &Path, cases: &str, seed: usize) -> Self {
        let log = domain.with_file_name(format!("server-{seed}.log"));
        let mut child = Command::new(env!("CARGO_BIN_EXE_trustcbr"))
            .args(["serve", "--domain"])
            .arg(domain)
            .args(["--cases", cases, "--seed", &seed.to_string()])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(std::fs::File::create(&log).unwrap())
            .spawn()
            .unwrap();
        let input = child.stdin.take().unwrap();
        let output = BufReader::new(child.stdout.take().unwrap());
        Self {
            log,
            child,
            input,
            output,
        }
    }

    fn ask(&mut self, request: &str) -> Value {
        let mut line = String::new();
        let sent = writeln!(self.input, "{request}");
        if sent.is_err() || self.output.read_line(&mut line).unwrap() == 0 {
            panic!(
                "the server exited ({sent:?}): {}",
                std::fs::read_to_string(&self.log).unwrap()
            );
        }
        let reply: Value = serde_json::from_str(&line).unwrap();
        assert!(reply.get("ok").is_some(), "{request} -> {reply}");
        reply
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        self.child.kill().ok();
        self.child.wait().ok();
    }
}

/// Runs the fleet over the case base at `cases` and checks it.
fn fleet(dir: &Path, cases: &str) {
    let domain = dir.join("quick.ron");
    std::fs::write(&domain, support::quick_domain(true)).unwrap();
    let mut servers: Vec<Server> = (0..SERVERS)
        .map(|k| Server::start(&domain, cases, k))
        .collect();
    // Retained cases acknowledged so far, by store id (solutions in real units).
    let acknowledged = Mutex::new(BTreeMap::<i64, Value>::new());
    let acknowledged_count = AtomicUsize::new(0);
    let reused = AtomicUsize::new(0);
    std::thread::scope(|scope| {
        for server in &mut servers {
            let (acknowledged, acknowledged_count, reused) =
                (&acknowledged, &acknowledged_count, &reused);
            scope.spawn(move || {
                for _ in 0..EPISODES / SERVERS {
                    let known = acknowledged_count.load(Ordering::SeqCst);
                    let held = server.ask(r#"{"request": "state"}"#)["cases"]
                        .as_u64()
                        .unwrap();
                    assert!(
                        held as usize >= known,
                        "a server holds {held} cases while {known} were acknowledged"
                    );
                    server.ask(support::EPISODE[0]);
                    let switched = server.ask(support::EPISODE[1]);
                    if switched["source"] == "case" {
                        reused.fetch_add(1, Ordering::SeqCst);
                    }
                    let settled = server.ask(support::EPISODE[2]);
                    assert_eq!(settled["ok"], "settled");
                    if let Some(id) = settled["retained"].as_i64() {
                        let mut map = acknowledged.lock().unwrap();
                        let earlier = map.insert(id, settled["behavior"].clone());
                        assert_eq!(earlier, None, "case id {id} acknowledged twice");
                        acknowledged_count.fetch_add(1, Ordering::SeqCst);
                    }
                }
            });
        }
    });
    let acknowledged = acknowledged.into_inner().unwrap();
    let definition = service::DomainDefinition::load(&domain).unwrap();
    let stored = support::stored_solutions(&Location::parse(cases), &definition.space);
    assert_eq!(
        stored, acknowledged,
        "the store holds exactly the acknowledged cases"
    );
    let ids: Vec<StoreId> = stored.keys().copied().collect();
    for server in &mut servers {
        let listed: Vec<StoreId> = server.ask(r#"{"request": "cases"}"#)["cases"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c["id"].as_i64().unwrap())
            .collect();
        assert_eq!(listed, ids, "every server holds the cases in store order");
    }
    eprintln!(
        "{SERVERS} servers, {EPISODES} episodes: {} cases retained and stored once each, {} switches reused a case",
        acknowledged.len(),
        reused.load(Ordering::SeqCst)
    );
    // Cases were both retained and reused, so the servers did select from each other's.
    assert!(
        acknowledged.len() >= SERVERS,
        "too few cases retained to share"
    );
    assert!(reused.load(Ordering::SeqCst) > 0, "no case was reused");
}

#[test]
fn four_servers_share_one_sqlite_case_base() {
    let dir = tempfile::tempdir().unwrap();
    let cases = dir.path().join("fleet.db");
    fleet(dir.path(), cases.to_str().unwrap());
}

#[test]
fn four_servers_share_one_postgres_case_base() {
    let Ok(url) = std::env::var("TRUSTCBR_TEST_POSTGRES") else {
        assert!(
            std::env::var("CI").as_deref() != Ok("true"),
            "CI must run the fleet test against PostgreSQL: set TRUSTCBR_TEST_POSTGRES (.ci/run starts a server)"
        );
        eprintln!(
            "skipped: set TRUSTCBR_TEST_POSTGRES=postgres://... (eval \"$(.ci/start-postgres)\") to run the fleet test against PostgreSQL"
        );
        return;
    };
    let database = format!("trustcbr_fleet_{}", std::process::id());
    let mut admin = postgres::Client::connect(&url, postgres::NoTls).unwrap();
    for statement in [
        format!("DROP DATABASE IF EXISTS {database}"),
        format!("CREATE DATABASE {database}"),
    ] {
        admin.batch_execute(&statement).unwrap();
    }
    let (base, _) = url.rsplit_once('/').unwrap();
    let dir = tempfile::tempdir().unwrap();
    fleet(dir.path(), &format!("{base}/{database}"));
    admin
        .batch_execute(&format!("DROP DATABASE {database} WITH (FORCE)"))
        .unwrap();
}
