//! Goal changes through the binary: an experiment suite with them writes their table and
//! figures, said and unsaid; configs that cannot mean anything are refused, leaving
//! nothing behind; `serve` counts a said goal change against nothing.

use crate::support;

use std::io::Write;
use std::process::Stdio;
use support::{one_mission_suite, refused, run_suite, succeed, trustcbr};

/// Movement, the paper's operators drawn per trial, goal changes every two minutes on
/// average (a sixth of the 20 s commands cut), unsaid and said.
const SUITE: &str = r#"(
    seed: 7,
    trials: 30,
    landscape_runs: 0,
    limit: (runs: 20, budget: 0, candidates: 0, candidate_runs: 0),
    arms: ["uniform", "case-based"],
    experiments: [
        (scenario: "movement", operator: "random"),
        (scenario: "movement", operator: "random", goal_changes: Some((per_hour: 30.0))),
        (scenario: "movement", operator: "random", goal_changes: Some((per_hour: 30.0)), feedback: Some((goal_changes: 1.0))),
    ],
)"#;

#[test]
fn a_suite_with_goal_changes_reports_them_per_arm() {
    let dir = tempfile::tempdir().unwrap();
    let stdout = succeed(&mut run_suite(dir.path(), SUITE));
    assert!(stdout.contains("movement/random/g30s1"), "{stdout}");
    let out = dir.path().join("out");
    let table = std::fs::read_to_string(out.join("table.md")).unwrap();
    assert!(table.contains("## Goal changes: interruptions not about the behavior"));
    assert!(
        table.contains("| movement/random | uniform | none |"),
        "{table}"
    );
    assert!(
        table.contains("| movement/random/g30s1 | case-based | "),
        "{table}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let experiments = summary["experiments"].as_array().unwrap();
    let names: Vec<&str> = experiments
        .iter()
        .map(|e| e["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "movement/random",
            "movement/random/g30",
            "movement/random/g30s1"
        ]
    );
    // Without goal changes: no record, but behaviors given up though trusted are counted.
    let absent = &experiments[0]["strategies"]["uniform"]["goal_changes"];
    assert!(absent["record"].is_null());
    assert!(absent["given_up_though_trusted"]["mean"].as_f64().unwrap() >= 0.0);
    for (k, said) in [(1, false), (2, true)] {
        for arm in ["uniform", "case-based"] {
            let g = &experiments[k]["strategies"][arm]["goal_changes"];
            let record = &g["record"];
            let happened = record["happened"].as_u64().unwrap();
            assert!(happened > 0, "{arm}: {g}");
            assert_eq!(
                record["said"].as_u64().unwrap(),
                if said { happened } else { 0 }
            );
            if said {
                assert!(g["guess_recall"].is_null());
            } else {
                let recall = g["guess_recall"].as_f64().unwrap();
                assert!((0.0..=1.0).contains(&recall));
            }
        }
    }
    // Every trial line carries its record where the experiment has goal changes.
    let lines = std::fs::read_to_string(out.join("trials.jsonl")).unwrap();
    for line in lines.lines() {
        let trial: serde_json::Value = serde_json::from_str(line).unwrap();
        let expected = trial["experiment"] != "movement/random";
        assert_eq!(trial.get("goal_changes").is_some(), expected, "{line}");
    }
}

#[test]
fn goal_changes_that_cannot_mean_anything_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let said_but_none = SUITE.replace(
        r#"(scenario: "movement", operator: "random"),"#,
        r#"(scenario: "movement", operator: "random", feedback: Some((goal_changes: 0.5))),"#,
    );
    let stderr = refused(&mut run_suite(dir.path(), &said_but_none));
    assert!(
        stderr.contains("experiments[0].feedback.goal_changes: the operators would say goal changes, but none happen"),
        "{stderr}"
    );
    let zero = SUITE.replace("per_hour: 30.0", "per_hour: 0.0");
    let stderr = refused(&mut run_suite(dir.path(), &zero));
    assert!(
        stderr.contains("goal_changes `per_hour` must be a number in (0, 3600]"),
        "{stderr}"
    );
    let loud = SUITE.replace("goal_changes: 1.0", "goal_changes: 1.5");
    let stderr = refused(&mut run_suite(dir.path(), &loud));
    assert!(
        stderr.contains("feedback `goal_changes` must be a probability in [0, 1], got 1.5"),
        "{stderr}"
    );
    let mission = one_mission_suite(
        r#"(scenario: "movement", operator: "random", goal_changes: Some((per_hour: 1.0)))"#,
    );
    let stderr = refused(&mut run_suite(dir.path(), &mission));
    assert!(
        stderr.contains(
            "`goal_changes`: goal changes are simulated in experiment suites, not yet in missions"
        ),
        "{stderr}"
    );
    assert!(!dir.path().join("out").exists());
}

#[test]
fn serve_counts_a_said_goal_change_against_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mut server = trustcbr()
        .args(["serve", "--domain", "movement", "--seed", "7", "--cases"])
        .arg(dir.path().join("cases.db"))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let lines = [
        r#"{"request":"begin"}"#,
        r#"{"outcome":"interrupted","weight":1.0,"duration_s":9.0,"observed":["behind-plan"]}"#,
        r#"{"outcome":"interrupted","weight":1.0,"duration_s":4.0,"goal_change":true}"#,
        r#"{"outcome":"completed","weight":1.0,"duration_s":4.0,"goal_change":true}"#,
        r#"{"request":"state"}"#,
    ];
    let mut stdin = server.stdin.take().unwrap();
    for line in lines {
        writeln!(stdin, "{line}").unwrap();
    }
    drop(stdin);
    let output = server.wait_with_output().unwrap();
    let replies: Vec<serde_json::Value> = String::from_utf8(output.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(replies[1]["trust"], -1.0);
    assert_eq!(replies[2]["ok"], "keep");
    assert_eq!(replies[2]["trust"], -1.0);
    assert!(
        replies[3]["error"]
            .as_str()
            .unwrap()
            .contains("goal_change is said only of an interruption"),
        "{}",
        replies[3]
    );
    let episode = &replies[4]["episode"];
    assert_eq!(episode["trust"], -1.0);
    assert_eq!(
        (
            episode["commands"].as_u64(),
            episode["behavior_commands"].as_u64()
        ),
        (Some(2), Some(1))
    );
}
