//! `trustcbr serve --mission` as a process: outcomes after `settled` are answered for the
//! watched behavior, ten net interruptions re-adapt, a new operator's `begin` ends the
//! watch, an operator who lets pass what it reacted to raises an `alert`, a robot that
//! judges its own competence (`--competence`) raises an `overtrust` once for a trusted
//! behavior it is surely short with, and a bad `confidence` is refused; without `--mission` the paper's episodes are unchanged.

use serde_json::{Value, json};
use std::io::Write;
use std::process::Stdio;

use crate::support;

const BEGIN: &str = r#"{"request": "begin", "behavior": {"speed": 3.5, "padding": 0.4}}"#;
const DONE: &str = r#"{"outcome": "completed", "weight": 1.0, "duration_s": 2.0}"#;
const STOPPED: &str = r#"{"outcome": "interrupted", "weight": 1.0, "duration_s": 2.0}"#;
const STATE: &str = r#"{"request": "state"}"#;

/// Serves the movement domain (`--mission` when asked) over a fresh case base, sends
/// `lines` on stdin and returns one reply per line.
fn exchange(mission: bool, lines: &[&str]) -> Vec<Value> {
    exchange_with(if mission { &["--mission"] } else { &[] }, lines)
}

/// Serves the movement domain with the options `extra` over a fresh case base, sends
/// `lines` on stdin and returns one reply per line.
fn exchange_with(extra: &[&str], lines: &[&str]) -> Vec<Value> {
    let dir = tempfile::tempdir().unwrap();
    let mut command = support::trustcbr();
    command
        .args(["serve", "--domain", "movement", "--seed", "3", "--cases"])
        .arg(dir.path().join("cases.db"))
        .args(extra);
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
    // reaction rate is then 45/49: trust/tests/integration/mission.rs); each bump let pass adds
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

#[test]
fn a_robot_judging_its_competence_says_overtrust_once_for_a_trusted_behavior_that_bumps() {
    let bumped =
        r#"{"outcome": "completed", "weight": 1.0, "duration_s": 2.0, "observed": ["collision"]}"#;
    // Five completions settle the behavior; every one bumped something.
    let lines: Vec<&str> = [BEGIN]
        .into_iter()
        .chain(repeat(bumped, 8))
        .chain([STATE])
        .collect();
    let replies = exchange_with(&["--mission", "--competence", "0.1"], &lines);
    assert_eq!(replies[5]["ok"], "settled");
    // The first watched command: 6 collisions in 6 commands, surely above 1 in 10.
    let overtrust = &replies[6];
    assert_eq!(overtrust["ok"], "overtrust", "{overtrust}");
    assert_eq!(overtrust["behavior"], behavior());
    assert_eq!(overtrust["trust"], 5.0);
    assert_eq!(overtrust["short"], json!(["collision"]));
    assert_eq!(overtrust["competence"]["commands"], 6);
    let collision = &overtrust["competence"]["parts"][0];
    assert_eq!(
        (&collision["name"], &collision["perceived"]),
        (&json!("collision"), &json!(6))
    );
    let sentence = overtrust["sentence"].as_str().unwrap();
    // Its estimate: 6 of 6, shrunk towards every behavior's record (6.5 / 7) with the
    // weight of 4 commands: (6 + 4 x 6.5 / 7) / 10 = 0.97.
    assert!(sentence.contains("collision 0.97"), "{sentence}");
    // Once per settled behavior: then kept as before.
    assert_eq!(
        (&replies[7]["ok"], &replies[8]["ok"]),
        (&json!("keep"), &json!("keep"))
    );
    // `state` sets the operator's trust beside the robot's judgement.
    let calibration = &replies[9]["watching"]["calibration"];
    assert_eq!(
        (&calibration["verdict"], &calibration["short"]),
        (&json!("overtrust"), &json!(["collision"]))
    );
    assert_eq!(calibration["competence"]["commands"], 8);
    // Without --competence the same mission only keeps, and judges nothing.
    let blind = exchange(true, &lines);
    assert!(blind[6..9].iter().all(|r| r["ok"] == "keep"), "{blind:?}");
    assert!(blind[9]["watching"].get("calibration").is_none());
}

#[test]
fn competence_needs_a_mission_a_chance_and_a_scenario() {
    let refused = |args: &[&str]| {
        let dir = tempfile::tempdir().unwrap();
        let output = support::trustcbr()
            .args(["serve", "--cases"])
            .arg(dir.path().join("cases.db"))
            .args(args)
            .stdin(Stdio::null())
            .output()
            .unwrap();
        assert!(!output.status.success());
        assert!(
            !dir.path().join("cases.db").exists(),
            "a refused command creates no case base"
        );
        String::from_utf8_lossy(&output.stderr).into_owned()
    };
    let no_mission = refused(&["--domain", "movement", "--competence", "0.1"]);
    assert!(no_mission.contains("--mission"), "{no_mission}");
    let not_a_chance = refused(&["--domain", "movement", "--mission", "--competence", "1.5"]);
    assert!(
        not_a_chance.contains("--competence: the competence standard of `at_most` is 1.5; it must be a chance in [0, 1]"),
        "{not_a_chance}"
    );
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("robot.ron");
    std::fs::write(
        &file,
        r#"(space: (components: [(name: "speed", values: Numeric(min: 0.5, step: 0.5, count: 4))]), causes: [])"#,
    )
    .unwrap();
    let not_a_scenario = refused(&[
        "--domain",
        file.to_str().unwrap(),
        "--mission",
        "--competence",
        "0.1",
    ]);
    assert!(
        not_a_scenario.contains("is not a scenario of trustcbr"),
        "{not_a_scenario}"
    );
}

#[test]
fn an_arm_preferring_competent_behaviors_passes_over_a_trusted_one_the_robot_is_sure_of() {
    let bumped =
        r#"{"outcome": "completed", "weight": 1.0, "duration_s": 2.0, "observed": ["collision"]}"#;
    let lines: Vec<&str> = [BEGIN].into_iter().chain(repeat(bumped, 5)).collect();
    let replies = exchange_with(
        &[
            "--mission",
            "--competence",
            "0.1",
            "--arm",
            "uniform+competent",
        ],
        &lines,
    );
    // Trusted after five completions, every one a bump: passed over, the search goes on.
    let passed = &replies[5];
    assert_eq!(passed["ok"], "switch", "{passed}");
    assert_ne!(passed["behavior"], behavior());
    assert_eq!(passed["explanation"]["given_up"]["trust"], 5.0);
    // Without a standard the preference would do nothing: refused before anything opens.
    let dir = tempfile::tempdir().unwrap();
    let output = support::trustcbr()
        .args(["serve", "--domain", "movement", "--mission", "--arm"])
        .arg("uniform+competent")
        .arg("--cases")
        .arg(dir.path().join("cases.db"))
        .stdin(Stdio::null())
        .output()
        .unwrap();
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("add --mission --competence AT_MOST"),
        "{stderr}"
    );
    assert!(!dir.path().join("cases.db").exists());
}

#[test]
fn an_overtrust_alert_offers_a_behavior_operators_trusted_before_and_the_operator_may_take_it() {
    let bumped =
        r#"{"outcome": "completed", "weight": 1.0, "duration_s": 2.0, "observed": ["collision"]}"#;
    const ACCEPT: &str = r#"{"request": "accept_offer"}"#;
    // An operator gives up the first behavior, trusts the one the search proposes (a case
    // is retained: the search found it) and runs it cleanly for 40 more commands; then
    // another operator trusts a behavior that bumps every time.
    let lines: Vec<&str> = [ACCEPT, BEGIN]
        .into_iter()
        .chain(repeat(STOPPED, 5))
        .chain(repeat(DONE, 45))
        .chain([r#"{"request": "abandon"}"#, BEGIN])
        .chain(repeat(bumped, 6))
        .chain([ACCEPT, STATE, DONE, ACCEPT])
        .collect();
    let replies = exchange_with(&["--mission", "--competence", "0.1"], &lines);
    assert!(
        replies[0]["error"]
            .as_str()
            .unwrap()
            .starts_with("no offer to accept"),
        "{}",
        replies[0]
    );
    assert_eq!(replies[6]["ok"], "switch");
    let trusted = replies[6]["behavior"].clone();
    assert_eq!(replies[11]["ok"], "settled");
    assert_eq!(replies[11]["retained"], 1);
    // The second operator settles on the bumping behavior: the alert offers the first
    // operator's, which the robot ran 45 times without a bump.
    let b = 53;
    assert_eq!(replies[b + 5]["ok"], "settled");
    let overtrust = &replies[b + 6];
    assert_eq!(overtrust["ok"], "overtrust", "{overtrust}");
    assert_eq!(overtrust["offer"], trusted);
    let sentence = overtrust["sentence"].as_str().unwrap();
    assert!(
        sentence.contains("which the robot judges competent"),
        "{sentence}"
    );
    // Taken: the watch moves to it, at the trustworthy threshold.
    assert_eq!(
        replies[b + 7],
        json!({"ok": "accepted", "behavior": trusted})
    );
    let watching = &replies[b + 8]["watching"];
    assert_eq!(
        (
            &watching["behavior"],
            &watching["trust"],
            &watching["commands"]
        ),
        (&trusted, &json!(5.0), &json!(0))
    );
    // An offer stands for the request right after its alert only.
    assert_eq!(replies[b + 9]["ok"], "keep");
    assert!(
        replies[b + 10]["error"]
            .as_str()
            .unwrap()
            .starts_with("no offer to accept")
    );
}

/// Told the context it is already in, a mission's episode goes on as it was: trust and
/// commands kept, no new episode (it restarted the episode).
#[test]
fn a_context_request_naming_the_current_context_changes_nothing() {
    let same = r#"{"request": "context", "context": {}}"#;
    let hazardous = r#"{"request": "context", "context": {"cargo": "hazardous"}}"#;
    let lines = [
        BEGIN, DONE, DONE, STATE, same, STATE, DONE, hazardous, hazardous,
    ];
    let r = exchange(true, &lines);
    assert_eq!(r[4]["ok"], "context");
    assert_eq!(r[4]["from"], "kept", "{}", r[4]);
    assert_eq!(r[4]["gave_up_watch"], false);
    assert_eq!(r[4]["behavior"], behavior());
    // The episode's state before and after is the same: two commands, trust +2.
    assert_eq!(r[3], r[5], "{} then {}", r[3], r[5]);
    // The third completion goes on from there (trust 3 of the threshold 5).
    assert_eq!(r[6]["trust"], 3.0, "{}", r[6]);
    // A switch to another context does begin again there; told it twice, the second
    // changes nothing.
    assert_ne!(r[7]["from"], "kept", "{}", r[7]);
    assert_eq!(r[8]["from"], "kept", "{}", r[8]);
}

/// Switching back to a context does not resume a behavior the same operator gave up
/// there: settled on in the default context, it is resumed on the way back from
/// hazardous cargo; once it has fallen in the default context, the next switch back
/// carries on with the behavior in use instead (issue 52, item 11).
#[test]
fn a_switch_back_never_resumes_a_behavior_given_up_in_that_context() {
    let default = r#"{"request": "context", "context": {}}"#;
    let hazardous = r#"{"request": "context", "context": {"cargo": "hazardous"}}"#;
    let lines: Vec<&str> = [BEGIN]
        .into_iter()
        .chain(repeat(DONE, 5)) // 1..=5: settled in the default context
        .chain([hazardous]) // 6: kept, now watched with hazardous cargo
        .chain(repeat(STOPPED, 10)) // 7..=16: it falls there, the tenth switches
        .chain(repeat(DONE, 5)) // 17..=21: settled with hazardous cargo
        .chain([default]) // 22: back, resumed
        .chain(repeat(DONE, 5)) // 23..=27: settled again
        .chain(repeat(STOPPED, 10)) // 28..=37: it falls in the default context too
        .chain([hazardous, default, STATE]) // 38, 39, 40
        .collect();
    let r = exchange(true, &lines);
    assert_eq!(r[5]["ok"], "settled");
    assert_eq!(r[6]["from"], "kept", "{}", r[6]);
    assert_eq!(r[16]["ok"], "switch", "{}", r[16]);
    let there = r[16]["behavior"].clone();
    assert_eq!(r[21]["ok"], "settled", "{}", r[21]);
    assert_eq!(r[21]["behavior"], there);
    assert_eq!(r[22]["from"], "resumed", "{}", r[22]);
    assert_eq!(r[22]["behavior"], behavior());
    assert_eq!(r[22]["gave_up_watch"], true);
    assert_eq!(r[27]["ok"], "settled", "{}", r[27]);
    assert_eq!(r[37]["ok"], "switch", "{}", r[37]);
    assert_eq!(r[37]["explanation"]["given_up"]["behavior"], behavior());
    assert_eq!(r[38]["from"], "resumed", "{}", r[38]);
    assert_eq!(r[38]["behavior"], there);
    // Back in the default context: the behavior given up there is not resumed; the
    // episode under way begins again from the behavior in use.
    assert_eq!(r[39]["from"], "restarted", "{}", r[39]);
    assert_eq!(r[39]["behavior"], there);
    assert_eq!(r[40]["episode"]["behavior"], there, "{}", r[40]);
    assert_eq!(r[40]["episode"]["commands"], 0, "{}", r[40]);
}

#[test]
fn a_change_detector_gives_a_long_trusted_behavior_up_sooner_and_needs_mission_mode() {
    // Settled after five completions and trusted for a hundred more: the record bounds its
    // rate of untrustworthy commands at 1 - 0.05^(1/105) = 0.028 (bounded afresh at 104
    // commands), so an interruption adds ln(0.5 / 0.028) = 2.88 and the fourth in a row
    // passes ln(8000) = 8.99, where the paper's watch needs ten.
    let lines: Vec<&str> = [BEGIN]
        .into_iter()
        .chain(repeat(DONE, 105))
        .chain(repeat(STOPPED, 4))
        .collect();
    let detecting = exchange_with(&["--mission", "--detect-changes"], &lines);
    assert_eq!(detecting[5]["ok"], "settled");
    assert!(detecting[106..109].iter().all(|r| r["ok"] == "keep"));
    assert_eq!(detecting[109]["ok"], "switch", "{}", detecting[109]);
    assert_eq!(
        detecting[109]["explanation"]["given_up"]["untrustworthy"],
        4
    );
    let plain = exchange(true, &lines);
    assert_eq!(plain[109]["ok"], "keep");
    // The detector watches a settled behavior: refused without mission mode.
    let dir = tempfile::tempdir().unwrap();
    let refused = support::refused(
        support::trustcbr()
            .args([
                "serve",
                "--domain",
                "movement",
                "--detect-changes",
                "--cases",
            ])
            .arg(dir.path().join("cases.db")),
    );
    assert!(refused.contains("--mission"), "{refused}");
    assert!(!dir.path().join("cases.db").exists());
}
