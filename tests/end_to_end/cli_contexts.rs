//! Trials in contexts through the binary: an experiment's trials take the contexts of its
//! cycle in turn, their operator judging by the preferences it states there; an arm told
//! its context learns cases in it, its context-blind twin (on the same trials) learns them
//! all in the default context; a context the domain does not declare, a blind arm with no
//! contexts to be blind to and the retired `told` are refused, leaving nothing behind.

use crate::support;

use std::path::Path;
use std::process::Command;
use support::{one_mission_suite, refused, run_suite, succeed};

/// A movement operator who wants speed on a routine job and, with hazardous cargo, wants
/// no bumps and no hurry: both are satisfiable, so trials settle quickly in either context.
const OPERATOR: &str = r#"(
    name: "carrier",
    t_complete: 15.0,
    p_deadline: 0.95,
    p_collision: 0.05,
    contexts: [(when: {"cargo": "hazardous"}, p_deadline: Some(0.05), p_collision: Some(0.95))],
)"#;

fn suite(contexts: &str) -> String {
    format!(
        r#"(
    seed: 7,
    trials: 12,
    landscape_runs: 0,
    limit: (runs: 20, budget: 0, candidates: 0, candidate_runs: 0),
    arms: ["case-based", "case-based+context-blind"],
    experiments: [
        (scenario: "movement", operator: "random", population: Some((name: "carrier")),
         operator_files: ["carrier.ron"]{contexts}),
    ],
)"#
    )
}

/// [`suite`] with trials in the contexts of `cycle`.
fn suite_in(cycle: &str) -> String {
    suite(&format!(", contexts: Some((cycle: {cycle}))"))
}

/// [`run_suite`] beside the operator file, saving the cases.
fn run(dir: &Path, text: &str) -> Command {
    std::fs::write(dir.join("carrier.ron"), OPERATOR).unwrap();
    let mut command = run_suite(dir, text);
    command.arg("--save-cases").arg(dir.join("cases"));
    command
}

#[test]
fn trials_take_the_contexts_in_turn_and_a_told_arm_learns_cases_in_them() {
    let dir = tempfile::tempdir().unwrap();
    let stdout = succeed(&mut run(
        dir.path(),
        &suite_in(r#"[{}, {"cargo": "hazardous"}]"#),
    ));
    assert!(stdout.contains("movement/carrier/contexts"), "{stdout}");
    let lines = std::fs::read_to_string(dir.path().join("out/trials.jsonl")).unwrap();
    let mut seen = [0; 2];
    let mut operators = [Vec::new(), Vec::new()];
    for line in lines.lines() {
        let trial: serde_json::Value = serde_json::from_str(line).unwrap();
        assert_eq!(trial["experiment"], "movement/carrier/contexts");
        let told = trial["arm"] == "case-based";
        if !told {
            assert_eq!(trial["arm"], "case-based+context-blind");
        }
        seen[usize::from(told)] += 1;
        operators[usize::from(told)].push((trial["trial"].clone(), trial["operator"].clone()));
        let hazardous = trial["trial"].as_u64().unwrap() % 2 == 1;
        if hazardous {
            assert_eq!(
                trial["context"],
                serde_json::json!({"cargo": "hazardous"}),
                "{line}"
            );
            // A blind arm is told the default context.
            assert_eq!(trial.get("told").is_some(), !told, "{line}");
        } else {
            assert!(trial.get("context").is_none(), "{line}");
            assert!(trial.get("told").is_none(), "{line}");
        }
    }
    assert_eq!(seen, [12, 12]);
    // The twins are paired: the same trials.
    assert_eq!(operators[0], operators[1]);
    // The report breaks each arm down by context, against its blind twin.
    let table = std::fs::read_to_string(dir.path().join("out/table.md")).unwrap();
    assert!(table.contains("## By context"), "{table}");
    for row in [
        "| movement/carrier/contexts | case-based | all | 12 |",
        "| movement/carrier/contexts | case-based | default | 6 |",
        "| movement/carrier/contexts | case-based | cargo=hazardous | 6 |",
        "| movement/carrier/contexts | case-based+context-blind | cargo=hazardous | 6 |",
    ] {
        assert!(table.contains(row), "{row}: {table}");
    }
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("out/summary.json")).unwrap(),
    )
    .unwrap();
    let strategies = &summary["experiments"][0]["strategies"];
    let told = &strategies["case-based"]["contexts"];
    assert_eq!(told[0]["context"], serde_json::Value::Null);
    assert_eq!(
        told[2]["context"],
        serde_json::json!({"cargo": "hazardous"})
    );
    assert!(told[2]["versus_blind"]["untrustworthy_p"].is_number());
    assert!(strategies["case-based+context-blind"]["contexts"][2]["versus_blind"].is_null());
    // The told arm's cases include some learned with hazardous cargo; the other's none.
    let cases = dir.path().join("cases/movement-carrier-contexts");
    let told_text = std::fs::read_to_string(cases.join("case-based.ron")).unwrap();
    let untold_text = std::fs::read_to_string(cases.join("case-based+context-blind.ron")).unwrap();
    assert!(told_text.contains("hazardous"), "{told_text}");
    assert!(!untold_text.is_empty() && !untold_text.contains("hazardous"));
    // `explain` says the context a trial ran in, and what a blind arm was told.
    let explain = |arm: &str, trial: &str| {
        succeed(
            Command::new(env!("CARGO_BIN_EXE_trustcbr"))
                .arg("explain")
                .arg(dir.path().join("out"))
                .args(["--experiment", "movement/carrier/contexts", "--arm", arm])
                .args(["--trial", trial]),
        )
    };
    let story = explain("case-based", "1");
    assert!(
        story.lines().nth(1) == Some("in context cargo=hazardous"),
        "{story}"
    );
    let story = explain("case-based+context-blind", "1");
    assert!(
        story.contains("in context cargo=hazardous (the arm was told default: it is blind to it)"),
        "{story}"
    );
    assert!(!explain("case-based", "0").contains("in context"));
}

#[test]
fn a_context_the_domain_does_not_declare_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let err = refused(&mut run(
        dir.path(),
        &suite_in(r#"[{}, {"cargo": "toxic"}]"#),
    ));
    assert!(err.contains("experiments[0].contexts.cycle[1]"), "{err}");
    assert!(
        err.contains("context variable `cargo` may be normal, hazardous, not `toxic`"),
        "{err}"
    );
    assert!(!dir.path().join("out").exists());
}

#[test]
fn a_blind_arm_without_contexts_and_the_retired_told_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let err = refused(&mut run(dir.path(), &suite("")));
    assert!(err.contains("arms[1]"), "{err}");
    assert!(
        err.contains("`case-based+context-blind` is blind to the robot's context, and no trial here runs in a context other than the default"),
        "{err}"
    );
    // Contexts that are all the default one change nothing either.
    let err = refused(&mut run(dir.path(), &suite_in("[{}]")));
    assert!(
        err.contains("arms[1]: `case-based+context-blind` is blind to the robot's context, and no trial here runs in a context other than the default"),
        "{err}"
    );
    // A blind arm that reuses no case, of a search that ignores the context, is its twin.
    let text = suite_in(r#"[{}, {"cargo": "hazardous"}]"#).replace(
        r#"arms: ["case-based", "case-based+context-blind"]"#,
        r#"arms: ["random-walk", "random-walk+context-blind"]"#,
    );
    let err = refused(&mut run(dir.path(), &text));
    assert!(
        err.contains("arms[1]: `random-walk+context-blind` is blind to the robot's context, but it reuses no case and its search (`random-walk`) ignores the context"),
        "{err}"
    );
    assert!(!dir.path().join("out").exists());
    let err = refused(&mut run(
        dir.path(),
        &suite(r#", contexts: Some((cycle: [{}], told: false))"#),
    ));
    assert!(err.contains("experiments[0].contexts.told"), "{err}");
    assert!(
        err.contains("run the arm `NAME+context-blind` beside `NAME`"),
        "{err}"
    );
    assert!(!dir.path().join("out").exists());
}

/// An experiment's contexts in turn are not a mission's switches.
#[test]
fn a_mission_plan_with_an_experiment_s_contexts_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mission = one_mission_suite(
        r#"(scenario: "movement", operator: "random", contexts: Some((cycle: [{}])))"#,
    );
    let err = refused(&mut run(dir.path(), &mission));
    assert!(
        err.contains("suite.ron:6:92: `contexts`: an experiment's trials take contexts in turn")
            && err.contains("context_switches: Some((among: [...], every: N))"),
        "{err}"
    );
    assert!(!dir.path().join("out").exists());
}

#[test]
fn a_blind_arm_in_a_mission_suite_without_switches_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mission = one_mission_suite(r#"(scenario: "movement", operator: "random")"#)
        .replace(r#"["uniform"]"#, r#"["uniform+context-blind"]"#);
    let err = refused(&mut run(dir.path(), &mission));
    assert!(
        err.contains("arms[0]: `uniform+context-blind` is blind to the robot's context, and no plan here has `context_switches`"),
        "{err}"
    );
    assert!(!dir.path().join("out").exists());
}
