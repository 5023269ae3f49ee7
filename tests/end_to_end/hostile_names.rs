//! End-to-end: a key written twice in any RON map is refused by name, where serde would
//! keep the last silently (an experiment's context `cycle`, a suite's `readings`, an
//! operator file's `when`, a RON case file's context), and a domain file's context
//! variables, their values and its statement names follow the naming rule of causes.
//! A population named as a benchmark instance must hold that instance's members. Each
//! refusal leaves nothing behind.

use crate::support;

use std::path::Path;
use support::{refused, run_suite, trustcbr};

/// A movement operator who wants no bumps with hazardous cargo (its `when` as given).
fn operator(when: &str) -> String {
    format!(
        r#"(
    name: "carrier",
    t_complete: 15.0,
    p_deadline: 0.95,
    p_collision: 0.05,
    contexts: [(when: {when}, p_collision: Some(0.95))],
)"#
    )
}

/// A small suite over the carrier, with `extra` fields of the suite and `experiment`
/// fields of its one experiment.
fn suite(extra: &str, experiment: &str) -> String {
    format!(
        r#"(
    seed: 7,
    trials: 4,
    landscape_runs: 0,
    limit: (runs: 20, budget: 0, candidates: 0, candidate_runs: 0),
    arms: ["case-based"],{extra}
    experiments: [
        (scenario: "movement", operator: "carrier", operator_files: ["carrier.ron"]{experiment}),
    ],
)"#
    )
}

/// Runs `text` beside the carrier whose `when` is `when`, which must be refused; returns
/// the message, after checking no report was written.
fn refused_suite(dir: &Path, when: &str, text: &str) -> String {
    std::fs::write(dir.join("carrier.ron"), operator(when)).unwrap();
    let stderr = refused(&mut run_suite(dir, text));
    assert!(!dir.join("out").exists(), "{stderr}");
    stderr
}

#[test]
fn a_context_variable_written_twice_in_a_cycle_or_an_operator_file_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let hazardous = r#"{"cargo": "hazardous"}"#;
    let stderr = refused_suite(
        dir.path(),
        hazardous,
        &suite(
            "",
            r#", contexts: Some((cycle: [{}, {"cargo": "hazardous", "cargo": "normal"}]))"#,
        ),
    );
    assert!(
        stderr.contains("context variable `cargo` is given twice; give each variable once"),
        "{stderr}"
    );
    assert!(stderr.contains("suite.ron:"), "{stderr}");

    let stderr = refused_suite(
        dir.path(),
        r#"{"cargo": "hazardous", "cargo": "normal"}"#,
        &suite("", ""),
    );
    assert!(
        stderr.contains("carrier.ron:")
            && stderr.contains("context variable `cargo` is given twice; give each variable once"),
        "{stderr}"
    );
}

#[test]
fn a_reading_written_twice_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let stderr = refused_suite(
        dir.path(),
        r#"{"cargo": "hazardous"}"#,
        &suite(
            r#"
    readings: {"patrol_weights": "as_written", "patrol_weights": "three_and_one"},"#,
            "",
        ),
    );
    assert!(
        stderr.contains("`patrol_weights` is given twice; give each key once"),
        "{stderr}"
    );
}

#[test]
fn a_case_file_whose_context_writes_a_variable_twice_is_refused_and_left_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cases.ron");
    let text = r#"(cases: [(problem: (context: {"cargo": "hazardous", "cargo": "normal"}, evaluated: [(behavior: [3, 4], time: 12.0)]), solution: [1, 2])])"#;
    std::fs::write(&path, text).unwrap();
    let stderr = refused(trustcbr().args(["cases", "info"]).arg(&path));
    assert!(
        stderr.contains("context variable `cargo` is given twice; give each variable once"),
        "{stderr}"
    );
    assert_eq!(std::fs::read_to_string(&path).unwrap(), text);
}

/// `serve` of a domain file whose extra fields are `fields`, refused before any case base
/// exists; returns the message.
fn refused_domain(fields: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let domain = dir.path().join("robot.ron");
    let text = format!(
        r#"(
    space: (components: [(name: "speed", unit: "m/s", values: Numeric(min: 1.0, step: 1.0, count: 5))]),
    causes: [(name: "collision")],
    {fields}
)"#
    );
    std::fs::write(&domain, text).unwrap();
    let cases = dir.path().join("cases.db");
    let stderr = refused(
        trustcbr()
            .args(["serve", "--domain"])
            .arg(&domain)
            .arg("--cases")
            .arg(&cases)
            .stdin(std::process::Stdio::null()),
    );
    assert!(!cases.exists(), "{stderr}");
    stderr
}

#[test]
fn a_domain_file_s_context_and_statement_names_follow_the_rule_of_causes() {
    let stderr =
        refused_domain(r#"contexts: [(name: "Shift Var/../x", values: ["day", "night"])],"#);
    assert!(
        stderr.contains("field `contexts`: context variable `Shift Var/../x` breaks the naming rule of causes: a cause is 1 to 32 bytes of lower-case kebab-case"),
        "{stderr}"
    );
    let stderr = refused_domain(r#"contexts: [(name: "shift", values: ["day", "night\nshift"])],"#);
    assert!(
        stderr.contains(
            r"field `contexts`: a value of `shift` `night\nshift` breaks the naming rule of causes"
        ),
        "{stderr}"
    );
    let stderr = refused_domain(r#"statements: ["hurry", "Hurry Up!"],"#);
    assert!(
        stderr
            .contains("field `statements`: statement `Hurry Up!` breaks the naming rule of causes"),
        "{stderr}"
    );
}

/// A suite whose one experiment's population `name` lists `members` (movement operator
/// files written beside it, each named as given).
fn population_suite(dir: &Path, name: &str, members: &[&str]) -> String {
    let mut files = Vec::new();
    for member in members {
        let file = format!("{member}.ron");
        let text =
            format!(r#"(name: "{member}", t_complete: 15.0, p_deadline: 0.5, p_collision: 0.5)"#);
        std::fs::write(dir.join(&file), text).unwrap();
        files.push(format!("{file:?}"));
    }
    format!(
        r#"(
    seed: 7,
    trials: 4,
    landscape_runs: 0,
    limit: (runs: 20, budget: 0, candidates: 0, candidate_runs: 0),
    arms: ["case-based"],
    experiments: [
        (scenario: "movement", operator: "random", population: Some((name: "{name}")),
         operator_files: [{}]),
    ],
)"#,
        files.join(", ")
    )
}

#[test]
fn a_population_named_as_a_benchmark_instance_holds_that_instance_s_members() {
    let dir = tempfile::tempdir().unwrap();
    let text = population_suite(dir.path(), "dev-0", &["dev-1-0", "dev-1-1"]);
    let stderr = refused(&mut run_suite(dir.path(), &text));
    assert!(
        stderr.contains("experiments[0].operator_files[0]: member `dev-1-0` is not one of instance `dev-0`'s members"),
        "{stderr}"
    );
    let text = population_suite(dir.path(), "eval-99999999", &["eval-99999999-0"]);
    let stderr = refused(&mut run_suite(dir.path(), &text));
    assert!(
        stderr.contains("population `eval-99999999` is named as a benchmark instance but is none: instance `eval-99999999` does not exist"),
        "{stderr}"
    );
    assert!(!dir.path().join("out").exists());
    // The instance's own members, and a population of another name, run.
    for (name, members) in [
        ("dev-1", ["dev-1-0", "dev-1-1"]),
        ("mine", ["dev-1-0", "dev-1-1"]),
    ] {
        let text = population_suite(dir.path(), name, &members);
        support::succeed(&mut run_suite(dir.path(), &text));
    }
}
