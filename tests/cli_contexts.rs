//! Trials in contexts through the binary: an experiment's trials take the contexts of its
//! cycle in turn, their operator judging by the preferences it states there; a robot told
//! its context learns cases in it, one not told learns them all in the default context;
//! a context the domain does not declare is refused, leaving nothing behind.

mod support;

use std::path::Path;
use std::process::Command;
use support::{one_mission_suite, refused, succeed, trustcbr};

/// A movement operator who wants speed on a routine job and, with hazardous cargo, wants
/// no bumps and no hurry: both are satisfiable, so trials settle quickly in either context.
const OPERATOR: &str = r#"(
    name: "carrier",
    t_complete: 15.0,
    p_deadline: 0.95,
    p_collision: 0.05,
    contexts: [(when: {"cargo": "hazardous"}, p_deadline: Some(0.05), p_collision: Some(0.95))],
)"#;

fn suite(cycle: &str) -> String {
    format!(
        r#"(
    seed: 7,
    trials: 12,
    landscape_runs: 0,
    limit: (runs: 20, budget: 0, candidates: 0, candidate_runs: 0),
    arms: ["case-based"],
    experiments: [
        (scenario: "movement", operator: "random", population: Some((name: "carrier")),
         operator_files: ["carrier.ron"], contexts: Some((cycle: {cycle}))),
        (scenario: "movement", operator: "random", population: Some((name: "carrier")),
         operator_files: ["carrier.ron"], contexts: Some((cycle: {cycle}, told: false))),
    ],
)"#
    )
}

fn run(dir: &Path, text: &str) -> Command {
    std::fs::write(dir.join("carrier.ron"), OPERATOR).unwrap();
    let config = dir.join("suite.ron");
    std::fs::write(&config, text).unwrap();
    let mut command = trustcbr();
    command
        .arg("run")
        .arg(&config)
        .arg("--out")
        .arg(dir.join("out"))
        .arg("--save-cases")
        .arg(dir.join("cases"));
    command
}

/// Every file under `dir`, read as text, joined.
fn all_text(dir: &Path) -> String {
    let mut text = String::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            text.push_str(&all_text(&path));
        } else {
            text.push_str(&std::fs::read_to_string(&path).unwrap());
        }
    }
    text
}

#[test]
fn trials_take_the_contexts_in_turn_and_a_told_robot_learns_cases_in_them() {
    let dir = tempfile::tempdir().unwrap();
    let stdout = succeed(&mut run(
        dir.path(),
        &suite(r#"[{}, {"cargo": "hazardous"}]"#),
    ));
    assert!(stdout.contains("movement/carrier/contexts"), "{stdout}");
    let lines = std::fs::read_to_string(dir.path().join("out/trials.jsonl")).unwrap();
    let mut seen = [0; 2];
    for line in lines.lines() {
        let trial: serde_json::Value = serde_json::from_str(line).unwrap();
        let told = trial["experiment"] == "movement/carrier/contexts";
        if !told {
            assert_eq!(trial["experiment"], "movement/carrier/contexts-untold");
        }
        seen[usize::from(told)] += 1;
        let hazardous = trial["trial"].as_u64().unwrap() % 2 == 1;
        if hazardous {
            assert_eq!(
                trial["context"],
                serde_json::json!({"cargo": "hazardous"}),
                "{line}"
            );
            // A robot not told its context is told the default one.
            assert_eq!(trial.get("told").is_some(), !told, "{line}");
        } else {
            assert!(trial.get("context").is_none(), "{line}");
            assert!(trial.get("told").is_none(), "{line}");
        }
    }
    assert_eq!(seen, [12, 12]);
    // The told robot's cases include some learned with hazardous cargo; the other's none.
    let cases = dir.path().join("cases");
    let mut told_text = String::new();
    let mut untold_text = String::new();
    for entry in std::fs::read_dir(&cases).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let text = if path.is_dir() {
            all_text(&path)
        } else {
            std::fs::read_to_string(&path).unwrap()
        };
        if name.contains("untold") {
            untold_text.push_str(&text);
        } else {
            told_text.push_str(&text);
        }
    }
    assert!(told_text.contains("hazardous"), "{told_text}");
    assert!(!untold_text.is_empty() && !untold_text.contains("hazardous"));
}

#[test]
fn a_context_the_domain_does_not_declare_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let err = refused(&mut run(dir.path(), &suite(r#"[{}, {"cargo": "toxic"}]"#)));
    assert!(err.contains("experiments[0].contexts.cycle[1]"), "{err}");
    assert!(
        err.contains("context variable `cargo` may be normal, hazardous, not `toxic`"),
        "{err}"
    );
    assert!(!dir.path().join("out").exists());
}

#[test]
fn a_mission_plan_in_contexts_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mission = one_mission_suite(
        r#"(scenario: "movement", operator: "random", contexts: Some((cycle: [{}])))"#,
    );
    let err = refused(&mut run(dir.path(), &mission));
    assert!(
        err.contains("missions[0].operators.contexts: contexts are simulated in experiment suites, not yet in missions"),
        "{err}"
    );
    assert!(!dir.path().join("out").exists());
}
