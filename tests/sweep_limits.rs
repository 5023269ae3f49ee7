//! End-to-end: the size of the work a suite asks for is checked before any of it is
//! started, against stated limits, with an error naming the size and the limit.

mod support;

use std::process::Command;
use std::time::{Duration, Instant};
use support::trustcbr;

/// Runs `command`, checks that it failed with an error (status 1, or 2 for a usage error)
/// rather than a panic, and quickly, and returns its stderr.
fn refused(command: &mut Command) -> String {
    let started = Instant::now();
    let output = command.output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(matches!(output.status.code(), Some(1 | 2)), "{stderr}");
    assert!(stderr.starts_with("error: "), "{stderr}");
    assert!(
        started.elapsed() < Duration::from_secs(10),
        "refused only after {:?}: {stderr}",
        started.elapsed()
    );
    stderr
}

const SUITE: &str = r#"(
    seed: 1,
    trials: 2,
    arms: ["random-walk"],
    experiments: [(scenario: "movement", operator: "balanced")],
)"#;

#[test]
fn a_suite_too_large_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let experiments = vec![r#"(scenario: "movement", operator: "balanced")"#; 1000].join(", ");
    let config = dir.path().join("huge.ron");
    std::fs::write(
        &config,
        format!(
            r#"(seed: 1, trials: 100000, arms: ["random-walk", "case-based", "uniform", "cause-aware", "model-based", "conditioned", "case-based+cause-aware"], experiments: [{experiments}])"#
        ),
    )
    .unwrap();
    let out = dir.path().join("report");
    let stderr = refused(trustcbr().arg("run").arg(&config).arg("--out").arg(&out));
    assert!(
        stderr.contains(&format!(
            "{}: trials: 700000000 trials in all (1000 experiments x 7 arms x 100000 trials); at most 250000",
            config.display()
        )),
        "{stderr}"
    );
    // The limit applies to `--trials` too.
    let small = dir.path().join("small.ron");
    std::fs::write(&small, SUITE).unwrap();
    let stderr = refused(
        trustcbr()
            .arg("run")
            .arg(&small)
            .args([
                "--trials",
                "100000",
                "--arms",
                "random-walk,uniform,cause-aware",
            ])
            .arg("--out")
            .arg(&out),
    );
    assert!(
        stderr.contains(
            "trials: 300000 trials in all (1 experiments x 3 arms x 100000 trials); at most 250000"
        ),
        "{stderr}"
    );
    // Landscape runs, on the command line and in a config.
    for args in [
        &["reproduce", "--landscape-runs", "4294967295"][..],
        &[
            "landscape",
            "--scenario",
            "movement",
            "--operator",
            "balanced",
            "--runs",
            "4294967295",
        ],
    ] {
        let stderr = refused(trustcbr().args(args));
        assert!(
            stderr.contains("4294967295 is not in") && stderr.contains("10000"),
            "{args:?}: {stderr}"
        );
    }
    let landscapes = dir.path().join("landscapes.ron");
    std::fs::write(
        &landscapes,
        SUITE.replace("trials: 2,", "trials: 2, landscape_runs: 20000,"),
    )
    .unwrap();
    let stderr = refused(
        trustcbr()
            .arg("run")
            .arg(&landscapes)
            .arg("--out")
            .arg(&out),
    );
    assert!(
        stderr.contains("landscape_runs: must be 0 to 10000, got 20000"),
        "{stderr}"
    );
    assert!(!out.join("summary.json").exists());
}
