//! Durability of `trustcbr serve` on an SQLite case base: the server is killed (SIGKILL)
//! at random points, many of them while retentions are being committed, and after every
//! kill the database must open and hold, exactly once, every case whose retention a reply
//! had acknowledged before the kill; a server killed while it creates a new case base
//! leaves it whole or absent.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::Value;
use service::DomainDefinition;
use service::store::{Location, StoreId};
use std::collections::BTreeMap;
use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

use crate::support;

/// Kill rounds; each restarts the server on the case base the previous round left.
const ROUNDS: usize = 50;

#[test]
fn killed_servers_never_lose_acknowledged_cases() {
    let dir = tempfile::tempdir().unwrap();
    let domain_path = dir.path().join("quick.ron");
    std::fs::write(&domain_path, support::quick_domain(false)).unwrap();
    let domain = DomainDefinition::load(&domain_path).unwrap();
    let cases_path = dir.path().join("cases.db");
    let mut rng = ChaCha8Rng::seed_from_u64(20140929);
    // The solution (in real units) of every case a reply reported retained, by store id.
    let mut acknowledged: BTreeMap<StoreId, Value> = BTreeMap::new();
    let mut kills_with_retentions_pending = 0;
    let mut unacknowledged_on_disk = 0;
    for round in 0..ROUNDS {
        let mut child = Command::new(env!("CARGO_BIN_EXE_trustcbr"))
            .args(["serve", "--domain"])
            .arg(&domain_path)
            .arg("--cases")
            .arg(&cases_path)
            .args(["--seed", &round.to_string()])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let mut input = child.stdin.take().unwrap();
        let mut output = BufReader::new(child.stdout.take().unwrap());
        let mut read_reply = || {
            let mut line = String::new();
            output.read_line(&mut line).unwrap();
            serde_json::from_str::<Value>(&line).unwrap()
        };
        // The restarted server starts from everything on disk.
        writeln!(input, r#"{{"request": "state"}}"#).unwrap();
        let on_disk = load(&cases_path, &domain).len();
        assert_eq!(read_reply()["cases"], on_disk);
        // Queue several episodes at once so the server keeps working (and committing)
        // while the replies are read, then kill it after a random number of them.
        let episodes = rng.random_range(1..=6);
        for _ in 0..episodes {
            for request in support::EPISODE {
                writeln!(input, "{request}").unwrap();
            }
        }
        input.flush().unwrap();
        let replies = rng.random_range(0..=3 * episodes);
        let mut retained_here = 0;
        for _ in 0..replies {
            let reply = read_reply();
            assert!(reply.get("ok").is_some(), "{reply}");
            if let Some(id) = reply["retained"].as_i64() {
                let earlier = acknowledged.insert(id, reply["behavior"].clone());
                assert_eq!(earlier, None, "case id {id} acknowledged twice");
                retained_here += 1;
            }
        }
        // Let the server run on for a random while (it may be anywhere: parsing, deciding,
        // writing the WAL, syncing, committing) before it dies.
        std::thread::sleep(Duration::from_micros(rng.random_range(0..3000)));
        child.kill().unwrap();
        child.wait().unwrap();
        if retained_here < episodes {
            kills_with_retentions_pending += 1;
        }
        let cases = load(&cases_path, &domain);
        for (id, solution) in &acknowledged {
            assert_eq!(
                cases.get(id),
                Some(solution),
                "round {round}: acknowledged case #{id} is not on disk as acknowledged"
            );
        }
        // A retention committed after the last reply read was never acknowledged: the
        // test adopts it, as the next server will.
        for (id, solution) in cases {
            if let std::collections::btree_map::Entry::Vacant(e) = acknowledged.entry(id) {
                e.insert(solution);
                unacknowledged_on_disk += 1;
            }
        }
    }
    eprintln!(
        "{ROUNDS} kills ({kills_with_retentions_pending} with retentions still queued), {} cases verified on disk, {unacknowledged_on_disk} of them committed but not yet acknowledged when the server died",
        acknowledged.len()
    );
    assert!(
        kills_with_retentions_pending >= ROUNDS / 2,
        "most kills must land while retentions are still due"
    );
}

/// The case base as it is on disk, by store id (solutions in real units); it must always
/// open, and a missing one is empty.
fn load(path: &Path, domain: &DomainDefinition) -> BTreeMap<StoreId, Value> {
    if !path.exists() {
        return BTreeMap::new();
    }
    support::stored_solutions(&Location::Sqlite(path.to_owned()), &domain.space)
}

/// Servers started on a new case base and killed a few milliseconds in, many of them
/// while they create it: after each, the case base is absent or whole (`cases info`
/// reads it), never a file that looks like a database and is no case base.
#[test]
fn a_server_killed_while_it_creates_its_case_base_leaves_it_whole_or_absent() {
    let dir = tempfile::tempdir().unwrap();
    let domain_path = dir.path().join("quick.ron");
    std::fs::write(&domain_path, support::quick_domain(false)).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(2026);
    let (mut whole, mut absent) = (0, 0);
    for round in 0..40 {
        let cases = dir.path().join(format!("cases-{round}.db"));
        let mut child = Command::new(env!("CARGO_BIN_EXE_trustcbr"))
            .args(["serve", "--domain"])
            .arg(&domain_path)
            .arg("--cases")
            .arg(&cases)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_micros(rng.random_range(0..20_000)));
        child.kill().unwrap();
        child.wait().unwrap();
        if !cases.exists() {
            absent += 1;
            continue;
        }
        let info = Command::new(env!("CARGO_BIN_EXE_trustcbr"))
            .args(["cases", "info"])
            .arg(&cases)
            .output()
            .unwrap();
        assert!(
            info.status.success(),
            "round {round}: {}",
            String::from_utf8_lossy(&info.stderr)
        );
        whole += 1;
    }
    eprintln!("{whole} case bases whole, {absent} absent after the kill");
}
