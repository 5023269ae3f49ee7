//! Mission mode through the request handler: outcomes after `settled` are answered for the
//! watched behavior, its fall re-adapts, a new operator or `abandon` ends the watch, an
//! alert asks for supervision, and the paper's episode mode is unchanged.

use serde_json::{Value, json};
use service::{DomainDefinition, Location, Session, SharedCases};
use std::path::Path;
use std::sync::Arc;

/// The movement domain at the paper's thresholds (+5 / -5), in mission mode or not.
fn movement(mission: bool) -> DomainDefinition {
    let domain = DomainDefinition::new(
        "movement",
        domains::Scenario::Movement.space(),
        domains::Scenario::Movement.causes().to_vec(),
        trust::AdapterConfig::default(),
    )
    .with_observations(domains::perception::MOVEMENT.to_vec());
    if mission {
        domain.in_mission_mode()
    } else {
        domain
    }
}

fn session(dir: &Path, domain: DomainDefinition) -> Session {
    let location = Location::Sqlite(dir.join("cases.db"));
    let cases = Arc::new(SharedCases::open(&domain, &location).unwrap());
    Session::new(domain, cases, 5).unwrap()
}

fn ask(s: &mut Session, line: &str) -> Value {
    s.handle_line(line.as_bytes()).unwrap().into_value()
}

fn ok(s: &mut Session, line: &str) -> Value {
    let reply = ask(s, line);
    assert!(reply.get("ok").is_some(), "{line} -> {reply}");
    reply
}

const BEGIN: &str = r#"{"request":"begin","behavior":{"speed":3.5,"padding":0.4}}"#;
const DONE: &str = r#"{"outcome":"completed","weight":1.0,"duration_s":2.0}"#;
const STOPPED: &str = r#"{"outcome":"interrupted","weight":1.0,"duration_s":2.0}"#;
/// A command during which the robot felt a collision, interrupted or let pass.
const BUMP_STOPPED: &str =
    r#"{"outcome":"interrupted","weight":1.0,"duration_s":2.0,"observed":["collision"]}"#;
const BUMP_PASSED: &str =
    r#"{"outcome":"completed","weight":1.0,"duration_s":2.0,"observed":["collision"]}"#;

fn behavior() -> Value {
    json!({"speed": 3.5, "padding": 0.4})
}

/// Begins at speed 3.5, padding 0.4 and settles there after five completions.
fn settle(s: &mut Session) {
    ok(s, BEGIN);
    for _ in 0..4 {
        assert_eq!(ok(s, DONE)["ok"], "keep");
    }
    assert_eq!(ok(s, DONE)["ok"], "settled");
}

#[test]
fn the_paper_s_episode_mode_stops_listening_and_reports_no_watch() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = session(dir.path(), movement(false));
    settle(&mut s);
    assert_eq!(
        ask(&mut s, DONE),
        json!({"error": "no episode is under way: start one with {\"request\": \"begin\"}"})
    );
    let state = ok(&mut s, r#"{"request":"state"}"#);
    assert_eq!(state.get("watching"), None);
    assert_eq!(
        ok(&mut s, r#"{"request":"explain"}"#),
        json!({"ok": "explanation", "episode": null})
    );
    assert_eq!(
        ok(&mut s, r#"{"request":"config"}"#)["adapter"].get("mode"),
        None
    );
}

#[test]
fn after_settling_outcomes_are_answered_for_the_watched_behavior_until_it_falls() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = session(dir.path(), movement(true));
    assert_eq!(
        ok(&mut s, r#"{"request":"config"}"#)["adapter"]["mode"],
        "mission"
    );
    assert_eq!(
        ok(&mut s, r#"{"request":"state"}"#)["watching"],
        Value::Null
    );
    settle(&mut s);
    // Completions keep the behavior at the cap: nothing is banked.
    for _ in 0..3 {
        assert_eq!(
            ok(&mut s, DONE),
            json!({"ok": "keep", "behavior": behavior(), "trust": 5.0})
        );
    }
    // Commands without a signal say nothing of a lapse: the own record stays at 0.
    let state = ok(&mut s, r#"{"request":"state"}"#);
    assert_eq!(state["episode"], Value::Null);
    assert_eq!(
        state["watching"],
        json!({"behavior": behavior(), "trust": 5.0, "commands": 3, "own_record": 0.0})
    );
    // Nine interruptions: +5 down to -4, kept.
    for i in 1..=9 {
        let kept = ok(&mut s, STOPPED);
        assert_eq!(
            kept,
            json!({"ok": "keep", "behavior": behavior(), "trust": 5.0 - f64::from(i)})
        );
    }
    let explained = ok(&mut s, r#"{"request":"explain"}"#);
    assert_eq!(explained["episode"], Value::Null);
    let watching = &explained["watching"];
    assert_eq!(watching["commands"], 12);
    assert_eq!(watching["current"]["behavior"], behavior());
    assert_eq!(
        (
            &watching["current"]["commands"],
            &watching["current"]["untrustworthy"],
            &watching["current"]["trust"]
        ),
        (&json!(9), &json!(9), &json!(-4.0))
    );
    // The tenth: -5, given up; a new episode starts from it.
    let switched = ok(&mut s, STOPPED);
    assert_eq!(switched["ok"], "switch");
    assert_ne!(switched["behavior"], behavior());
    let given_up = &switched["explanation"]["given_up"];
    assert_eq!(given_up["behavior"], behavior());
    assert_eq!(
        (&given_up["commands"], &given_up["trust"]),
        (&json!(10), &json!(-5.0))
    );
    let state = ok(&mut s, r#"{"request":"state"}"#);
    assert_eq!(state["watching"], Value::Null);
    assert_eq!(state["episode"]["behavior"], switched["behavior"]);
    let explained = ok(&mut s, r#"{"request":"explain"}"#);
    assert_eq!(explained["watching"], Value::Null);
    assert_eq!(explained["episode"]["switches"][0], switched["explanation"]);
    // The evaluated time: the ten commands it took to fall from trusted.
    assert_eq!(
        state["episode"]["evaluated"],
        json!([{"behavior": behavior(), "time": 20.0}])
    );
    // The re-adaptation settles as any episode does; the search found it, so its case is
    // retained.
    for _ in 0..4 {
        ok(&mut s, DONE);
    }
    let settled = ok(&mut s, DONE);
    assert_eq!(settled["ok"], "settled");
    assert_eq!(settled["retained"], 1);
    assert_eq!(ok(&mut s, DONE)["trust"], 5.0);
}

#[test]
fn a_new_operator_or_abandon_ends_the_watch() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = session(dir.path(), movement(true));
    settle(&mut s);
    ok(&mut s, DONE);
    let begun = ok(
        &mut s,
        r#"{"request":"begin","behavior":{"speed":1.0,"padding":0.2}}"#,
    );
    assert_eq!(begun["behavior"], json!({"speed": 1.0, "padding": 0.2}));
    let state = ok(&mut s, r#"{"request":"state"}"#);
    assert_eq!(state["watching"], Value::Null);
    assert_eq!(state["episode"]["commands"], 0);
    // During the new episode, begin is refused as ever.
    assert!(
        ask(&mut s, BEGIN)["error"]
            .as_str()
            .unwrap()
            .starts_with("an episode is already under way")
    );
    ok(&mut s, r#"{"request":"abandon"}"#);
    settle(&mut s);
    ok(&mut s, STOPPED);
    assert_eq!(
        ok(&mut s, r#"{"request":"abandon","id":4}"#),
        json!({"ok": "abandoned", "behavior": behavior(), "commands": 1, "cases": 0, "id": 4})
    );
    assert_eq!(
        ask(&mut s, DONE)["error"],
        "no episode is under way: start one with {\"request\": \"begin\"}"
    );
    assert!(
        ask(&mut s, r#"{"request":"abandon"}"#)["error"]
            .as_str()
            .unwrap()
            .starts_with("no episode is under way")
    );
}

#[test]
fn a_refused_outcome_during_the_watch_changes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = session(dir.path(), movement(true));
    settle(&mut s);
    // Below the cap (where the watch's time restarts), a weightless failure of a huge
    // duration: the watched behavior's time is near the largest number, so the same again
    // would overflow it.
    ok(&mut s, STOPPED);
    let huge = r#"{"outcome":"failed","weight":0.0,"duration_s":1.7e308}"#;
    ok(&mut s, huge);
    let before = (
        ok(&mut s, r#"{"request":"explain"}"#),
        ok(&mut s, r#"{"request":"state"}"#),
    );
    assert_eq!(
        ask(
            &mut s,
            r#"{"outcome":"completed","weight":1.0,"duration_s":2.0,"confidence":1.01}"#
        ),
        json!({"error": "invalid outcome: confidence must be a number in [0, 1], got 1.01"})
    );
    let refused = ask(&mut s, huge)["error"].as_str().unwrap().to_owned();
    assert!(
        refused.starts_with("field `duration_s`: ")
            && refused.ends_with(" s would make the behavior's total time overflow"),
        "{refused}"
    );
    let after = (
        ok(&mut s, r#"{"request":"explain"}"#),
        ok(&mut s, r#"{"request":"state"}"#),
    );
    assert_eq!(after, before);
}

#[test]
fn an_alert_when_the_operator_lets_pass_what_it_reacted_to() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = session(dir.path(), movement(true));
    ok(&mut s, BEGIN);
    // While deciding, the operator interrupted all three bumps and let the eight
    // completions pass: a bump's own reaction rate is 45/49 (trust/tests/integration/mission.rs), so
    // a bump it lets pass adds ln 6.625 to the evidence of a lapse.
    for _ in 0..3 {
        assert_eq!(ok(&mut s, BUMP_STOPPED)["ok"], "keep");
    }
    // Eight completions: -3 + 8 = +5, settled.
    for _ in 0..7 {
        ok(&mut s, DONE);
    }
    assert_eq!(ok(&mut s, DONE)["ok"], "settled");
    // Bumps let pass: the operator's estimate stays at +5; the third takes the evidence
    // past ln 100.
    for _ in 0..2 {
        assert_eq!(ok(&mut s, BUMP_PASSED)["ok"], "keep");
    }
    let alert = ok(&mut s, BUMP_PASSED);
    assert_eq!(alert["ok"], "alert");
    assert_eq!(alert["behavior"], behavior());
    assert_eq!(alert["trust"], 5.0);
    assert!((alert["own_record"].as_f64().unwrap() - 3.0 * 6.625f64.ln()).abs() < 1e-9);
    assert_eq!(
        (&alert["commands"], &alert["unacknowledged"]),
        (&json!(3), &json!(3))
    );
    assert_eq!(
        alert["sentence"],
        "Please supervise speed=3.5 m/s, padding=0.4 m: the operator's trust is +5.00, but 3 of the last 3 commands showed signs operators stop the robot for when attentive, and were let pass (the robot's own record makes a lapse of attention 291 times likelier than attention)."
    );
    // The own record starts again; the behavior is still watched.
    let state = ok(&mut s, r#"{"request":"state"}"#);
    assert_eq!(state["watching"]["own_record"], 0.0);
    assert_eq!(state["watching"]["commands"], 3);
    assert_eq!(ok(&mut s, BUMP_PASSED)["ok"], "keep");
}

#[test]
fn a_domain_file_may_ask_for_mission_mode() {
    let text = r#"(
    space: (components: [(name: "speed", unit: "m/s", values: Numeric(min: 0.5, step: 0.5, count: 4))]),
    causes: [],
    adapter: (thresholds: (trustworthy: 1.0, untrustworthy: -1.0), mode: mission),
)"#;
    let domain = DomainDefinition::from_ron(text, Path::new("d.ron")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut s = session(dir.path(), domain);
    ok(&mut s, r#"{"request":"begin","behavior":{"speed":1.0}}"#);
    assert_eq!(ok(&mut s, DONE)["ok"], "settled");
    assert_eq!(
        ok(&mut s, DONE),
        json!({"ok": "keep", "behavior": {"speed": 1.0}, "trust": 1.0})
    );
}

/// A context switch told mid-mission: the watched behavior stays watched where nothing
/// was settled on in the new context; back in a context, the robot begins again from what
/// it settled on there; mid-episode the episode begins again from the behavior in use.
#[test]
fn a_context_switch_mid_mission_goes_back_to_what_was_settled_on_there() {
    let dir = tempfile::tempdir().unwrap();
    let domain = movement(true).with_contexts(domains::job_context::contexts().clone());
    let mut s = session(dir.path(), domain);
    settle(&mut s);
    let hazardous = r#"{"request":"context","context":{"cargo":"hazardous"}}"#;
    assert_eq!(
        ok(&mut s, hazardous),
        json!({"ok": "context", "context": {"cargo": "hazardous"}, "behavior": behavior(),
               "from": "kept", "gave_up_watch": false})
    );
    assert_eq!(
        ok(&mut s, r#"{"request":"state"}"#)["watching"]["behavior"],
        behavior()
    );
    // The operator minds it with hazardous cargo: it falls and another settles.
    let switched = loop {
        let reply = ok(&mut s, STOPPED);
        if reply["ok"] == "switch" {
            break reply["behavior"].clone();
        }
    };
    let settled = loop {
        if ok(&mut s, DONE)["ok"] == "settled" {
            break ok(&mut s, r#"{"request":"state"}"#)["watching"]["behavior"].clone();
        }
    };
    assert_eq!(settled, switched);
    // Back to normal cargo: an episode from the behavior settled on there.
    let normal = r#"{"request":"context","context":{"cargo":"normal"}}"#;
    assert_eq!(
        ok(&mut s, normal),
        json!({"ok": "context", "context": {}, "behavior": behavior(),
               "from": "resumed", "gave_up_watch": true})
    );
    let state = ok(&mut s, r#"{"request":"state"}"#);
    assert_eq!(
        (&state["episode"]["behavior"], &state["watching"]),
        (&behavior(), &Value::Null)
    );
    // Mid-episode, to an emergency never met: the episode begins again from the behavior
    // in use.
    ok(&mut s, DONE);
    let emergency = r#"{"request":"context","context":{"situation":"emergency"}}"#;
    let reply = ok(&mut s, emergency);
    assert_eq!(
        (&reply["from"], &reply["behavior"]),
        (&json!("restarted"), &behavior())
    );
    assert_eq!(
        ok(&mut s, r#"{"request":"state"}"#)["episode"]["trust"],
        0.0
    );
    // A context the domain does not declare is refused and changes nothing.
    let before = ok(&mut s, r#"{"request":"state"}"#);
    let refused = ask(
        &mut s,
        r#"{"request":"context","context":{"weather":"rain"}}"#,
    );
    assert!(
        refused["error"]
            .as_str()
            .unwrap()
            .contains("unknown context variable")
    );
    assert_eq!(ok(&mut s, r#"{"request":"state"}"#), before);
}
