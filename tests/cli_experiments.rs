//! End-to-end tests of `trustcbr run`, `reproduce` and `config` on small configs.

use std::path::Path;
use std::process::Command;

fn trustcbr() -> Command {
    Command::new(env!("CARGO_BIN_EXE_trustcbr"))
}

const SMALL: &str = r#"(
    seed: 7,
    trials: 4,
    experiments: [
        (scenario: movement, operator: "balanced"),
        (scenario: patrol, operator: "random"),
    ],
)"#;

/// Runs `command`, asserts that it succeeded (showing its stderr if not), returns stdout.
fn succeed(command: &mut Command) -> String {
    let output = command.output().unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8(output.stdout).unwrap()
}

fn run(config: &Path, out: &Path, threads: &str) -> String {
    succeed(
        trustcbr()
            .args([
                "run",
                config.to_str().unwrap(),
                "--threads",
                threads,
                "--out",
            ])
            .arg(out),
    )
}

#[test]
fn run_writes_a_complete_report() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("small.ron");
    std::fs::write(&config, SMALL).unwrap();
    let out = dir.path().join("report");
    let stdout = run(&config, &out, "2");
    assert!(stdout.contains("| movement | balanced | 4 |"), "{stdout}");
    assert!(stdout.contains("| patrol | random | 4 |"), "{stdout}");

    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert!(summary["elapsed_s"].as_f64().unwrap() > 0.0);
    let experiments = summary["experiments"].as_array().unwrap();
    assert_eq!(experiments.len(), 2);
    assert_eq!(experiments[1]["scenario"], "patrol");
    assert_eq!(experiments[1]["operator"], "random");
    assert_eq!(experiments[1]["trials"], 4);
    for strategy in ["random-walk", "case-based"] {
        let s = &experiments[0]["strategies"][strategy];
        assert!(s["mean"].as_f64().unwrap() >= 1.0);
        assert!(s["ci95"].as_f64().unwrap() >= 0.0);
        assert!(s["cases_acquired"].is_u64());
    }
    let p = experiments[0]["p_value"].as_f64().unwrap();
    assert!((0.0..=1.0).contains(&p));

    let trials = std::fs::read_to_string(out.join("trials.jsonl")).unwrap();
    assert_eq!(trials.lines().count(), 2 * 2 * 4);
    for line in trials.lines() {
        let t: serde_json::Value = serde_json::from_str(line).unwrap();
        let scenario = t["scenario"].as_str().unwrap();
        assert_eq!(
            t["experiment"].as_str().unwrap().split('/').next(),
            Some(scenario)
        );
        assert!(["random-walk", "case-based"].contains(&t["strategy"].as_str().unwrap()));
        assert!(t["behaviors_evaluated"].as_u64().unwrap() >= 1);
        assert!(t["runs"].as_u64().unwrap() >= 1);
        assert!(t["found_trustworthy"].is_boolean());
        let components = if scenario == "movement" { 2 } else { 4 };
        assert_eq!(t["final"].as_object().unwrap().len(), components);
        assert!(t["final"]["speed"].is_f64());
        // In the random experiment the drawn operator is named, never "random".
        assert_ne!(t["operator"], "random");
    }
    // The config used is written back and runs again.
    let used = std::fs::read_to_string(out.join("config.ron")).unwrap();
    assert!(used.contains("trials: 4"));
    for plot in [
        "curves-movement-balanced.svg",
        "finals-movement-balanced.svg",
        "curves-patrol-random.svg",
        "finals-patrol-random.svg",
    ] {
        let svg = std::fs::read_to_string(out.join(plot)).unwrap();
        assert!(svg.starts_with("<svg"), "{plot}");
    }
    assert!(out.join("table.md").is_file());
}

#[test]
fn one_and_two_threads_give_identical_trials() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("small.ron");
    std::fs::write(&config, SMALL).unwrap();
    run(&config, &dir.path().join("one"), "1");
    run(&config, &dir.path().join("two"), "2");
    let one = std::fs::read(dir.path().join("one/trials.jsonl")).unwrap();
    let two = std::fs::read(dir.path().join("two/trials.jsonl")).unwrap();
    assert!(!one.is_empty());
    assert_eq!(one, two);
}

#[test]
fn config_prints_the_embedded_paper_config_and_it_runs() {
    let text = succeed(trustcbr().arg("config"));
    assert!(text.contains("trials: 500"));
    assert_eq!(text.matches("(scenario:").count(), 7);
    // The printed config is a valid input for `run` (with fewer trials).
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("paper.ron");
    std::fs::write(&config, text.replace("trials: 500", "trials: 1")).unwrap();
    let stdout = run(&config, &dir.path().join("out"), "2");
    let trials_column: Vec<&str> = stdout
        .lines()
        .filter(|l| l.starts_with("| movement |") || l.starts_with("| patrol |"))
        .map(|l| l.split('|').nth(3).unwrap().trim())
        .collect();
    assert_eq!(trials_column, ["1"; 7], "{stdout}");
}

#[test]
fn a_bad_config_names_file_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("bad.ron");
    std::fs::write(&config, "(seed: 1,\n trials: -3, experiments: [])").unwrap();
    let output = trustcbr()
        .args(["run", config.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains(&format!("{}:2:", config.display())),
        "{stderr}"
    );
}

#[test]
fn reproduce_accepts_overrides() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("results");
    succeed(
        trustcbr()
            .args(["reproduce", "--trials", "1", "--seed", "3", "--out"])
            .arg(&out),
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["experiments"].as_array().unwrap().len(), 7);
    assert!(
        std::fs::read_to_string(out.join("config.ron"))
            .unwrap()
            .contains("seed: 3")
    );
}
