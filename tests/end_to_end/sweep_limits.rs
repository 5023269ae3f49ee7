//! End-to-end: the size of the work a suite or a sweep asks for is checked before any of
//! it is built or started, against stated limits, with an error naming the size and the
//! limit; a sweep's seeds and each parameter's values are distinct, and one seed gives a
//! mean without an interval.

use crate::support;

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};
use support::{succeed, trustcbr};

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

/// Writes `suite.ron` and `sweep.ron` (holding `sweep`) into `dir`; returns the sweep's
/// path.
fn sweep_file(dir: &Path, sweep: &str) -> std::path::PathBuf {
    std::fs::write(dir.join("suite.ron"), SUITE).unwrap();
    let path = dir.join("sweep.ron");
    std::fs::write(&path, sweep).unwrap();
    path
}

/// `sweep FILE --out DIR/out` and `sweep merge FILE DIR/out --out DIR/merged`: both must
/// refuse the file with `expected`, before creating any folder.
fn both_refuse(dir: &Path, sweep: &str, expected: &str) {
    let file = sweep_file(dir, sweep);
    let out = dir.join("out");
    let merged = dir.join("merged");
    let stderr = refused(trustcbr().arg("sweep").arg(&file).arg("--out").arg(&out));
    assert!(
        stderr.contains(&format!("{}: {expected}", file.display())),
        "{stderr}"
    );
    let stderr = refused(
        trustcbr()
            .args(["sweep", "merge"])
            .arg(&file)
            .arg(&out)
            .arg("--out")
            .arg(&merged),
    );
    assert!(
        stderr.contains(&format!("{}: {expected}", file.display())),
        "{stderr}"
    );
    assert!(!out.exists() && !merged.exists());
}

#[test]
fn repeated_seeds_and_values_are_refused_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    both_refuse(
        dir.path(),
        r#"(suite: file("suite.ron"), seeds: [1, 1, 2], parameters: [])"#,
        "seeds: seed 1 is listed twice; each seed runs every cell once",
    );
    both_refuse(
        dir.path(),
        r#"(suite: file("suite.ron"), seeds: [1], parameters: [time_unit([commands]), lambda([0.8, 0.9, 0.90])])"#,
        "parameters[1]: lambda lists 0.9 twice",
    );
    both_refuse(
        dir.path(),
        r#"(suite: file("suite.ron"), seeds: [1], parameters: [arms([["random-walk"], ["uniform"], ["random-walk"]])])"#,
        "parameters[0]: arms lists random-walk twice",
    );
}

#[test]
fn a_sweep_too_large_is_refused_before_its_cells_are_built() {
    let dir = tempfile::tempdir().unwrap();
    // Five lists of 199 values: 199^5 cells, about 3.1 * 10^11, as a grid.
    let values: Vec<String> = (1..=199)
        .map(|i| format!("{}", f64::from(i) / 200.0))
        .collect();
    let list = format!("lambda([{}])", values.join(", "));
    let grid = format!(
        r#"(suite: file("suite.ron"), seeds: [1, 2], design: grid, parameters: [{list}, {list}, {list}, {list}, {list}])"#
    );
    both_refuse(
        dir.path(),
        &grid,
        "parameters: 624159201998 runs (312079600999 cells, every combination of the values, x 2 seeds); at most 10000",
    );
    // One at a time: the base and 198 values (0.9 is the base's own), x 51 seeds.
    let seeds: Vec<String> = (1..=51).map(|s| s.to_string()).collect();
    let one_at_a_time = format!(
        r#"(suite: file("suite.ron"), seeds: [{}], parameters: [{list}])"#,
        seeds.join(", ")
    );
    both_refuse(
        dir.path(),
        &one_at_a_time,
        "parameters: 10149 runs (199 cells, the base and each value it does not have, x 51 seeds); at most 10000",
    );
    // Few runs, but each of 100,000 trials x 2 arms: 10.2 million trials in all.
    let heavy = format!(
        r#"(suite: file("suite.ron"), trials: Some(100000), arms: Some(["random-walk", "uniform"]), seeds: [{}], parameters: [])"#,
        seeds.join(", ")
    );
    both_refuse(
        dir.path(),
        &heavy,
        "parameters: 10200000 trials in all (per cell: experiments x arms x trials, x 51 seeds); at most 10000000",
    );
}

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
    // The known-operator limit's estimates.
    for (limit, expected) in [
        (
            "(runs: 4294967295)",
            "limit.runs: 4294967295 runs; at most 10000",
        ),
        (
            "(budget: 18446744073709551615)",
            "limit.budget: 18446744073709551615 runs; at most 8000000",
        ),
        (
            "(candidates: 100000, candidate_runs: 100000)",
            "limit.candidates x limit.candidate_runs: 10000000000 runs; at most 8000000",
        ),
        (
            "(reference_episodes: 100001)",
            "limit.reference_episodes: must be 0 to 100000, got 100001",
        ),
        (
            "(reference_episodes: 1)",
            "limit.reference_episodes: got 1; must be 0 (no population reference) or at least 2",
        ),
    ] {
        std::fs::write(
            &landscapes,
            SUITE.replace("trials: 2,", &format!("trials: 2, limit: {limit},")),
        )
        .unwrap();
        let stderr = refused(
            trustcbr()
                .arg("run")
                .arg(&landscapes)
                .arg("--out")
                .arg(&out),
        );
        assert!(stderr.contains(expected), "{stderr}");
    }
    assert!(!out.join("summary.json").exists());
}

#[test]
fn one_seed_gives_a_mean_without_an_interval() {
    let dir = tempfile::tempdir().unwrap();
    let file = sweep_file(
        dir.path(),
        r#"(suite: file("suite.ron"), seeds: [5], parameters: [])"#,
    );
    let out = dir.path().join("out");
    succeed(trustcbr().arg("sweep").arg(&file).arg("--out").arg(&out));
    let md = std::fs::read_to_string(out.join("report/sweep.md")).unwrap();
    let row = md
        .lines()
        .find(|l| l.starts_with("| base | random-walk |"))
        .unwrap_or_else(|| panic!("{md}"));
    assert!(!row.contains('±'), "{row}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report/sweep.json")).unwrap())
            .unwrap();
    let result = &json["results"][0];
    assert!(result["behaviors_ci95"].is_null(), "{result}");
    assert!(result["commands_ci95"].is_null(), "{result}");
    assert!(
        result["behaviors_mean"].as_f64().unwrap() >= 1.0,
        "{result}"
    );
}

#[test]
fn a_stray_comma_in_arms_is_the_options_fault() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("suite.ron");
    std::fs::write(&config, SUITE).unwrap();
    let stderr = refused(
        trustcbr()
            .arg("run")
            .arg(&config)
            .args(["--arms", "random-walk,case-based,"]),
    );
    assert!(
        stderr.contains("invalid value '' for '--arms <ARMS>': an empty arm name (a stray comma?)"),
        "{stderr}"
    );
    assert!(!stderr.contains("suite.ron"), "{stderr}");
}
