//! `trustcbr serve --mission` as a process: outcomes after `settled` are answered for the
//! watched behavior, ten net interruptions re-adapt, a new operator's `begin` ends the
//! watch, an operator who lets pass what it reacted to raises an `alert`, and a bad
//! `confidence` is refused; without `--mission` the paper's episodes are unchanged.

use serde_json::{Value, json};
use std::io::Write;
use std::process::Stdio;

mod support;

const BEGIN: &str = r#"{"request": "begin", "behavior": {"speed": 3.5, "padding": 0.4}}"#;
const DONE: &str = r#"{"outcome": "completed", "weight": 1.0, "duration_s": 2.0}"#;
const STOPPED: &str = r#"{"outcome": "interrupted", "weight": 1.0, "duration_s": 2.0}"#;
const STATE: &str = r#"{"request": "state"}"#;

/// Serves the movement domain (`--mission` when asked) over a fresh case base, sends
/// `lines` on stdin and returns one reply per line.
fn exchange(mission: bool, lines: &[&str]) -> Vec<Value> {
    let dir = tempfile::tempdir().unwrap();
    let mut command = support::trustcbr();
    command
        .args(["serve", "--domain", "movement", "--seed", "3", "--cases"])
        .arg(dir.path().join("cases.db"));
    if mission {
        command.arg("--mission");
    }
    let mut child = command
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut input = lines.join("\n");
    input.push('\n');
    child
        .stdin
        .take()
        .unwrap()
        .write_all(input.as_bytes())
        .unwrap();
    let output = child.wait_with_output().unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let replies: Vec<Value> = output
        .stdout
        .split(|&b| b == b'\n')
        .filter(|l| !l.is_empty())
        .map(|l| serde_json::from_slice(l).unwrap())
        .collect();
    assert_eq!(replies.len(), lines.len(), "one reply per line");
    replies
}

fn repeat(line: &'static str, n: usize) -> impl Iterator<Item = &'static str> {
    std::iter::repeat_n(line, n)
}

fn behavior() -> Value {
    json!({"speed": 3.5, "padding": 0.4})
}

#[test]
fn without_mission_an_outcome_after_settled_is_refused_as_before() {
    let lines: Vec<&str> = [BEGIN].into_iter().chain(repeat(DONE, 6)).collect();
    let replies = exchange(false, &lines);
    assert_eq!(replies[5]["ok"], "settled");
    assert_eq!(
        replies[6],
        json!({"error": "no episode is under way: start one with {\"request\": \"begin\"}"})
    );
}

#[test]
fn a_mission_is_answered_after_settled_readapts_and_ends_at_a_new_operator() {
    let new_operator = r#"{"request": "begin", "behavior": {"speed": 1.0, "padding": 0.2}}"#;
    let lines: Vec<&str> = [BEGIN]
        .into_iter()
        .chain(repeat(DONE, 5)) // 1..=5: settled at the fifth
        .chain(repeat(DONE, 2)) // 6, 7: kept at the cap
        .chain(repeat(STOPPED, 10)) // 8..=17: the tenth gives it up
        .chain([STATE, BEGIN]) // 18, 19: an episode is under way again
        .chain(repeat(DONE, 6)) // 20..=25: settled, then watched
        .chain([new_operator, STATE]) // 26, 27
        .collect();
    let r = exchange(true, &lines);
    assert_eq!(r[5]["ok"], "settled");
    for kept in &r[6..8] {
        assert_eq!(
            *kept,
            json!({"ok": "keep", "behavior": behavior(), "trust": 5.0})
        );
    }
    for (i, kept) in r[8..17].iter().enumerate() {
        assert_eq!(kept["ok"], "keep");
        assert_eq!(kept["trust"], 4.0 - i as f64);
    }
    let switched = &r[17];
    assert_eq!(switched["ok"], "switch", "{switched}");
    assert_ne!(switched["behavior"], behavior());
    assert_eq!(switched["explanation"]["given_up"]["behavior"], behavior());
    assert_eq!(switched["explanation"]["given_up"]["untrustworthy"], 10);
    assert_eq!(r[18]["watching"], Value::Null);
    assert_eq!(
        r[18]["episode"]["evaluated"],
        json!([{"behavior": behavior(), "time": 20.0}])
    );
    assert!(
        r[19]["error"]
            .as_str()
            .unwrap()
            .starts_with("an episode is already under way")
    );
    assert_eq!(r[24]["ok"], "settled");
    assert_eq!(r[24]["behavior"], switched["behavior"]);
    assert_eq!(r[24]["retained"], 1, "the search found it");
    assert_eq!(
        r[25],
        json!({"ok": "keep", "behavior": switched["behavior"], "trust": 5.0})
    );
    assert_eq!(r[26]["ok"], "begun");
    assert_eq!(r[27]["watching"], Value::Null);
    assert_eq!(
        r[27]["episode"]["behavior"],
        json!({"speed": 1.0, "padding": 0.2})
    );
}

#[test]
fn an_operator_who_lets_pass_what_it_reacted_to_gets_an_alert() {
    let bump_stopped = r#"{"outcome": "interrupted", "weight": 1.0, "duration_s": 2.0, "observed": ["collision"]}"#;
    let bump_passed =
        r#"{"outcome": "completed", "weight": 1.0, "duration_s": 2.0, "observed": ["collision"]}"#;
    // Three bumps interrupted while deciding, eight completions settle at +5 (a bump's own
    // reaction rate is then 45/49: trust/tests/mission.rs); each bump let pass adds
    // ln 6.625 to the evidence of a lapse, and the third passes ln 100.
    let lines: Vec<&str> = [BEGIN]
        .into_iter()
        .chain(repeat(bump_stopped, 3))
        .chain(repeat(DONE, 8))
        .chain(repeat(bump_passed, 3))
        .chain([STATE])
        .collect();
    let r = exchange(true, &lines);
    assert_eq!(r[11]["ok"], "settled");
    assert!(r[12..14].iter().all(|k| k["ok"] == "keep"));
    let alert = &r[14];
    assert_eq!(alert["ok"], "alert", "{alert}");
    assert_eq!(alert["behavior"], behavior());
    assert_eq!(alert["trust"], 5.0);
    assert!((alert["own_record"].as_f64().unwrap() - 3.0 * 6.625f64.ln()).abs() < 1e-9);
    assert_eq!(
        (&alert["commands"], &alert["unacknowledged"]),
        (&json!(3), &json!(3))
    );
    assert!(
        alert["sentence"]
            .as_str()
            .unwrap()
            .starts_with("Please supervise speed=3.5 m/s, padding=0.4 m: ")
    );
    assert_eq!(r[15]["watching"]["own_record"], 0.0);
    assert_eq!(r[15]["watching"]["trust"], 5.0);
}

#[test]
fn a_confidence_outside_zero_to_one_is_refused_naming_the_field() {
    let lines = [
        BEGIN,
        r#"{"outcome": "completed", "weight": 1.0, "duration_s": 2.0, "confidence": 1.5}"#,
        r#"{"outcome": "completed", "weight": 1.0, "duration_s": 2.0, "confidence": "sure"}"#,
        STATE,
        r#"{"outcome": "completed", "weight": 1.0, "duration_s": 2.0, "confidence": 0.95}"#,
    ];
    let r = exchange(true, &lines);
    assert_eq!(
        r[1],
        json!({"error": "invalid outcome: confidence must be a number in [0, 1], got 1.5"})
    );
    assert_eq!(
        r[2],
        json!({"error": "field `confidence`: invalid type: string \"sure\", expected f64"})
    );
    assert_eq!(r[3]["episode"]["behavior_commands"], 0, "nothing recorded");
    assert_eq!(r[4]["ok"], "keep");
}
