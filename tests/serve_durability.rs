//! Durability of `trustcbr serve`: the server is killed (SIGKILL) at random points, many
//! of them during case-base saves, and after every kill the case file on disk must load
//! and hold every case whose retention a reply had acknowledged before the kill.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::Value;
use service::DomainDefinition;
use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;
use trust::TrustCaseBase;

/// Kill rounds; each restarts the server on the case file the previous round left.
const ROUNDS: usize = 50;

/// A 5 x 5 space whose episodes retain a case in three requests: `begin`, one interruption
/// (untrustworthy at -1: the search switches), one completion (trustworthy at +1). Case
/// reuse is off so that every episode searches and therefore retains.
const QUICK_DOMAIN: &str = r#"(
    space: (components: [
        (name: "speed", unit: "m/s", values: Numeric(min: 1.0, step: 1.0, count: 5)),
        (name: "padding", unit: "m", values: Numeric(min: 0.2, step: 0.2, count: 5)),
    ]),
    adapter: (thresholds: (trustworthy: 1.0, untrustworthy: -1.0), reuse_cases: false),
)"#;

const EPISODE: [&str; 3] = [
    r#"{"request": "begin"}"#,
    r#"{"outcome": "interrupted", "weight": 1.0, "cause": "collision", "duration_s": 4.0}"#,
    r#"{"outcome": "completed", "weight": 1.0, "duration_s": 6.0}"#,
];

#[test]
fn killed_servers_never_lose_or_corrupt_acknowledged_cases() {
    let dir = tempfile::tempdir().unwrap();
    let domain_path = dir.path().join("quick.ron");
    std::fs::write(&domain_path, QUICK_DOMAIN).unwrap();
    let domain = DomainDefinition::load(&domain_path).unwrap();
    let cases_path = dir.path().join("cases.ron");
    let mut rng = ChaCha8Rng::seed_from_u64(20140929);
    // The solution (in real units) of every case a reply reported retained, by id.
    let mut acknowledged: Vec<Value> = Vec::new();
    let mut kills_with_saves_pending = 0;
    let mut unacknowledged_on_disk = 0;
    let mut kills_mid_save = 0;
    let mut temporaries_seen = 0;
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
        let on_disk = load(&cases_path).len();
        assert_eq!(read_reply()["cases"], on_disk);
        // Queue several episodes at once so the server keeps working (and saving) while
        // the replies are read, then kill it after a random number of them.
        let episodes = rng.random_range(1..=6);
        for _ in 0..episodes {
            for request in EPISODE {
                writeln!(input, "{request}").unwrap();
            }
        }
        input.flush().unwrap();
        let replies = rng.random_range(0..=3 * episodes);
        let mut retained_here = 0;
        for _ in 0..replies {
            let reply = read_reply();
            assert!(reply.get("ok").is_some(), "{reply}");
            if let Some(id) = reply["retained"].as_u64() {
                assert_eq!(id as usize, acknowledged.len(), "ids are positions");
                acknowledged.push(reply["behavior"].clone());
                retained_here += 1;
            }
        }
        // Let the server run on for a random while (it may be anywhere: parsing, deciding,
        // writing the temporary file, syncing, renaming) before it dies.
        std::thread::sleep(Duration::from_micros(rng.random_range(0..3000)));
        child.kill().unwrap();
        child.wait().unwrap();
        if retained_here < episodes {
            kills_with_saves_pending += 1;
        }
        // A temporary file left beside the case file means the kill hit a save between
        // creating the temporary file and renaming it.
        let temporaries = std::fs::read_dir(dir.path())
            .unwrap()
            .filter(|e| {
                let name = e.as_ref().unwrap().file_name();
                name.to_string_lossy().starts_with(".cases.ron.tmp")
            })
            .count();
        if temporaries > temporaries_seen {
            kills_mid_save += 1;
            temporaries_seen = temporaries;
        }
        let cases = load(&cases_path);
        assert!(
            cases.len() >= acknowledged.len(),
            "round {round}: {} cases on disk, {} acknowledged",
            cases.len(),
            acknowledged.len()
        );
        for (id, solution) in acknowledged.iter().enumerate() {
            let stored = &cases.cases()[id].solution;
            assert_eq!(&service::reply::behavior(&domain.space, stored), solution);
        }
        // A save that completed after the last reply read was never acknowledged: the
        // test adopts it, as the next server will.
        unacknowledged_on_disk += cases.len() - acknowledged.len();
        for case in &cases.cases()[acknowledged.len()..] {
            acknowledged.push(service::reply::behavior(&domain.space, &case.solution));
        }
    }
    eprintln!(
        "{ROUNDS} kills ({kills_with_saves_pending} with retentions still queued, {kills_mid_save} in the middle of a save), {} cases verified on disk, {unacknowledged_on_disk} of them saved but not yet acknowledged when the server died",
        acknowledged.len()
    );
    assert!(
        kills_with_saves_pending >= ROUNDS / 2,
        "most kills must land while saves are still due"
    );
}

/// The case file as it is on disk: it must always load (a missing file is empty).
fn load(path: &Path) -> TrustCaseBase {
    if !path.exists() {
        return TrustCaseBase::new();
    }
    TrustCaseBase::load_ron(path).unwrap_or_else(|e| panic!("the case file must load: {e}"))
}
