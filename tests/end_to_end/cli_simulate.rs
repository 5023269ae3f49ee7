//! End-to-end: `simulate` prints one JSON line per command, drawn one after the other from
//! the seed's stream, and an operator who minds nothing but a deadline no command can meet
//! interrupts every command at that deadline.

use crate::support;

use serde_json::{Value, json};
use std::process::Command;
use support::{succeed, trustcbr};

/// A risky movement behavior: the balanced operator interrupts some of its commands and
/// lets others complete.
const RISKY: &str = "speed=9.5,padding=0.2";

fn simulate(behavior: &str, operator: &str, extra: &[&str]) -> Command {
    let mut command = trustcbr();
    command
        .args(["simulate", "--scenario", "movement", "--operator", operator])
        .args(["--behavior", behavior])
        .args(extra);
    command
}

fn lines(stdout: &str) -> Vec<Value> {
    stdout
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

#[test]
fn the_same_seed_prints_the_same_commands_one_line_each() {
    let run = |seed: &str, count: &str| {
        succeed(&mut simulate(
            RISKY,
            "balanced",
            &["--seed", seed, "--count", count],
        ))
    };
    let forty = run("3", "40");
    assert_eq!(forty.lines().count(), 40);
    assert_eq!(run("3", "40"), forty);
    assert_ne!(run("4", "40"), forty);
    // The commands are drawn one after the other: fewer commands are the first ones.
    let five = run("3", "5");
    assert!(forty.starts_with(&five), "{five}\n{forty}");
    // The default is one command with seed 0.
    let first = succeed(&mut simulate(RISKY, "balanced", &[]));
    assert_eq!(first, run("0", "1"));
    let commands = lines(&forty);
    let kinds: Vec<&str> = commands
        .iter()
        .map(|c| c["outcome"].as_str().unwrap())
        .collect();
    assert!(kinds.contains(&"completed") && kinds.contains(&"interrupted"));
    for c in &commands {
        let keys: Vec<&str> = c.as_object().unwrap().keys().map(String::as_str).collect();
        assert_eq!(
            keys,
            [
                "outcome",
                "weight",
                "duration_s",
                "observed",
                "stated",
                "truth"
            ]
        );
        // A completion has no true reason; an interruption has one.
        assert_eq!(c["truth"].is_null(), c["outcome"] == "completed", "{c}");
    }
}

#[test]
fn an_operator_whose_deadline_no_command_meets_interrupts_every_command_at_it() {
    let dir = tempfile::tempdir().unwrap();
    let impatient = dir.path().join("impatient.ron");
    // Half a second to cross the movement map, which takes seconds even at 10 m/s; it
    // always reacts to a late command and never to a collision.
    std::fs::write(
        &impatient,
        r#"(name: "impatient", t_complete: 0.5, p_deadline: 1.0, p_collision: 0.0)"#,
    )
    .unwrap();
    let impatient = impatient.to_str().unwrap();
    let stdout = succeed(&mut simulate(
        "speed=10,padding=1",
        impatient,
        &["--count", "50", "--seed", "9"],
    ));
    let commands = lines(&stdout);
    assert_eq!(commands.len(), 50);
    for c in &commands {
        assert_eq!(
            *c,
            json!({"outcome": "interrupted", "weight": 1.0, "duration_s": 0.5, "observed": [],
                   "stated": null, "truth": "deadline"})
        );
    }
    // Without attention it reacts to nothing it minds: the deadline passes unnoticed (and
    // is named as overlooked), and the command fails when the operator's patience ends.
    let stdout = succeed(&mut simulate(
        "speed=10,padding=1",
        impatient,
        &["--count", "50", "--seed", "9", "--attention", "0"],
    ));
    for c in lines(&stdout) {
        assert_eq!(c["outcome"], "failed", "{c}");
        assert_eq!(c["overlooked"], "deadline", "{c}");
    }
}

#[test]
fn an_attention_outside_zero_to_one_a_count_of_zero_and_a_behavior_off_the_grid_are_refused() {
    for (extra, behavior, message) in [
        (
            &["--attention", "1.5"][..],
            RISKY,
            "error: --attention: attention must be a number in [0, 1] (1: the paper's attentive operator), got 1.5",
        ),
        (
            &["--count", "0"][..],
            RISKY,
            "error: invalid value '0' for '--count <COUNT>': 0 is not in 1..=1000000",
        ),
        (
            &[][..],
            "speed=99,padding=0.2",
            "error: `99` is not an admissible value of `speed` (0.5 to 10 in steps of 0.5)",
        ),
    ] {
        let output = simulate(behavior, "balanced", extra).output().unwrap();
        assert!(!output.status.success());
        assert!(output.stdout.is_empty());
        let stderr = String::from_utf8(output.stderr).unwrap();
        assert!(stderr.starts_with(message), "{stderr}");
    }
}
