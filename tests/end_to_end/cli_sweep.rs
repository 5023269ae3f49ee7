//! End-to-end tests of `trustcbr sweep`: a sweep over seeds and a parameter, split into
//! shards and merged into the same report byte for byte.

use crate::support;

use std::path::Path;
use support::{succeed, trustcbr};

const SUITE: &str = r#"(
    seed: 1,
    trials: 3,
    arms: ["random-walk", "case-based"],
    experiments: [(scenario: "movement", operator: "balanced")],
)"#;

const SWEEP: &str = r#"(
    suite: file("suite.ron"),
    seeds: [1, 2, 3],
    parameters: [retention([any_search, final_from_search]), time_unit([task_seconds, commands])],
)"#;

/// The report of the sweep folder `dir`: the files of its `report/` folder, by name, with
/// their bytes; it holds the report alone.
fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut found: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir.join("report"))
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            let name = e.file_name().to_string_lossy().into_owned();
            (name, std::fs::read(e.path()).unwrap())
        })
        .collect();
    found.sort();
    let names: Vec<&str> = found.iter().map(|(name, _)| name.as_str()).collect();
    assert_eq!(
        names,
        [
            "sweep-retention.svg",
            "sweep-time_unit.svg",
            "sweep.json",
            "sweep.md"
        ]
    );
    found
}

#[test]
fn shards_merge_into_the_report_of_one_run() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("suite.ron"), SUITE).unwrap();
    let sweep = dir.path().join("sweep.ron");
    std::fs::write(&sweep, SWEEP).unwrap();
    let whole = dir.path().join("whole");
    let stdout = succeed(trustcbr().arg("sweep").arg(&sweep).arg("--out").arg(&whole));
    assert!(stdout.contains("3 cells x 3 seeds"), "{stdout}");
    let md = std::fs::read_to_string(whole.join("report/sweep.md")).unwrap();
    for cell in ["base", "retention=final_from_search", "time_unit=commands"] {
        assert!(md.contains(&format!("| {cell} | case-based |")), "{md}");
    }
    // Three shards on 1 thread, then merged.
    let mut shards = Vec::new();
    for i in 1..=3 {
        let shard = dir.path().join(format!("shard-{i}"));
        succeed(
            trustcbr()
                .arg("sweep")
                .arg(&sweep)
                .args(["--shard", &format!("{i}/3"), "--threads", "1", "--out"])
                .arg(&shard),
        );
        assert!(!shard.join("report").exists(), "a shard writes no report");
        shards.push(shard);
    }
    let merged = dir.path().join("merged");
    // A missing shard is named.
    let output = trustcbr()
        .args(["sweep", "merge"])
        .arg(&sweep)
        .args(&shards[..2])
        .arg("--out")
        .arg(&merged)
        .output()
        .unwrap();
    assert!(!output.status.success());
    assert!(
        String::from_utf8_lossy(&output.stderr).contains(
            "3 of 9 runs are in none of the folders"
        ) && String::from_utf8_lossy(&output.stderr).contains(
            "runs/base/seed-3.json, runs/retention-final_from_search/seed-3.json, runs/time_unit-commands/seed-3.json; run the shards that hold them first"
        ),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    succeed(
        trustcbr()
            .args(["sweep", "merge"])
            .arg(&sweep)
            .args(&shards)
            .arg("--out")
            .arg(&merged),
    );
    assert_eq!(files(&whole), files(&merged));
}

#[test]
fn bad_shards_and_sweeps_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("suite.ron"), SUITE).unwrap();
    let sweep = dir.path().join("sweep.ron");
    std::fs::write(&sweep, SWEEP).unwrap();
    for shard in ["0/3", "4/3", "2", "a/b"] {
        let output = trustcbr()
            .arg("sweep")
            .arg(&sweep)
            .args(["--shard", shard])
            .output()
            .unwrap();
        assert!(!output.status.success(), "{shard} accepted");
    }
    std::fs::write(&sweep, SWEEP.replace("seeds: [1, 2, 3]", "seeds: []")).unwrap();
    let output = trustcbr().arg("sweep").arg(&sweep).output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        !output.status.success() && stderr.contains("seeds"),
        "{stderr}"
    );
}
