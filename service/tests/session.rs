//! The request handler under hostile and ordinary input: every refused request gets an
//! error reply naming the problem and leaves the state unchanged.

use proptest::prelude::*;
use serde_json::{Value, json};
use service::{DomainDefinition, Location, Session, SharedCases};
use std::io::BufReader;
use std::path::Path;
use std::sync::Arc;
use trust::TrustCaseBase;

/// The movement domain with episodes that settle after one command either way
/// (thresholds +1 / -1).
fn quick_movement() -> DomainDefinition {
    let mut domain = DomainDefinition::new(
        "movement",
        domains::Scenario::Movement.space(),
        domains::Scenario::Movement.causes().to_vec(),
        trust::AdapterConfig::default(),
    )
    .with_observations(domains::perception::MOVEMENT.to_vec())
    .with_contexts(domains::job_context::contexts().clone());
    domain.adapter.thresholds.trustworthy = 1.0;
    domain.adapter.thresholds.untrustworthy = -1.0;
    domain
}

/// The case base `cases.db` in `dir`, opened as a server would.
fn open_cases(dir: &Path) -> Arc<SharedCases> {
    let location = Location::Sqlite(dir.join("cases.db"));
    Arc::new(SharedCases::open(&quick_movement(), &location).unwrap())
}

/// A quick movement session over the case base in `dir`.
fn session(dir: &Path) -> Session {
    Session::new(quick_movement(), open_cases(dir), 7).unwrap()
}

/// Every case stored in `dir`'s case base, read afresh as another process would.
fn stored(dir: &Path) -> TrustCaseBase {
    open_cases(dir)
        .current(|memory, _| memory.base().clone())
        .unwrap()
}

fn ask(s: &mut Session, line: &str) -> Value {
    s.handle_line(line.as_bytes()).unwrap().into_value()
}

fn ok(s: &mut Session, line: &str) -> Value {
    let reply = ask(s, line);
    assert!(reply.get("ok").is_some(), "{line} -> {reply}");
    reply
}

/// What a controller can observe: the state and the case base. (The server's draws are
/// checked separately: a refused `begin` must not consume one.)
fn snapshot(s: &mut Session) -> (Value, Value) {
    (
        ok(s, r#"{"request":"state"}"#),
        ok(s, r#"{"request":"cases"}"#),
    )
}

/// The replies written to `output`, one JSON value per line.
fn reply_lines(output: &[u8]) -> Vec<Value> {
    output
        .split(|&b| b == b'\n')
        .filter(|l| !l.is_empty())
        .map(|l| serde_json::from_slice(l).unwrap())
        .collect()
}

/// Serves `input` to the end and returns the replies.
fn serve_all(s: &mut Session, input: &[u8]) -> Vec<Value> {
    let mut output = Vec::new();
    service::transport::serve(s, BufReader::new(input), &mut output).unwrap();
    reply_lines(&output)
}

const INTERRUPTED: &str =
    r#"{"outcome": "interrupted", "weight": 1.0, "duration_s": 10.0, "stated": "collision"}"#;
const COMPLETED: &str = r#"{"outcome": "completed", "weight": 1.0, "duration_s": 8.0}"#;

#[test]
fn an_episode_over_the_protocol() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = session(dir.path());
    let begun = ok(
        &mut s,
        r#"{"request":"begin","behavior":{"speed":3.5,"padding":0.4}}"#,
    );
    assert_eq!(begun["behavior"], json!({"speed": 3.5, "padding": 0.4}));
    assert_eq!(begun["chosen_by"], "controller");
    // One interruption: -1 <= -1, switch by search to a behavior one change away.
    let switched = ok(&mut s, INTERRUPTED);
    assert_eq!(switched["ok"], "switch");
    assert_eq!(switched["source"], "search");
    let state = ok(&mut s, r#"{"request":"state"}"#);
    assert_eq!(state["episode"]["behavior"], switched["behavior"]);
    assert_eq!(
        state["episode"]["evaluated"][0]["behavior"],
        begun["behavior"]
    );
    assert_eq!(state["episode"]["evaluated"][0]["time"], 10.0);
    // One completion: trustworthy; searched once, so the case is retained and stored.
    assert!(stored(dir.path()).is_empty());
    let settled = ok(&mut s, COMPLETED);
    assert_eq!(settled["ok"], "settled");
    assert_eq!(settled["trustworthy"], true);
    assert_eq!(
        settled["retained"], 1,
        "the first id of an SQLite case base"
    );
    assert_eq!(settled["behaviors_evaluated"], 2);
    assert_eq!(settled["cases"], 1);
    let on_disk = stored(dir.path());
    assert_eq!(on_disk.len(), 1);
    assert_eq!(
        service::reply::behavior(s.adaptation().space(), &on_disk.cases()[0].solution),
        settled["behavior"]
    );
    let cases = ok(&mut s, r#"{"request":"cases","id":"list-1"}"#);
    assert_eq!(cases["cases"][0]["id"], 1);
    assert_eq!(cases["cases"][0]["solution"], settled["behavior"]);
    assert_eq!(cases["id"], "list-1");
    assert_eq!(ok(&mut s, r#"{"request":"state"}"#)["episode"], Value::Null);
    // The server waits for the next begin; it may draw the behavior itself.
    let begun = ok(&mut s, r#"{"request":"begin"}"#);
    assert_eq!(begun["chosen_by"], "server");
    let config = ok(&mut s, r#"{"request":"config"}"#);
    assert_eq!(config["behaviors"], 400);
    assert_eq!(
        config["causes"],
        json!([
            {"name": "deadline"},
            {"name": "collision"},
            {"name": "stuck"},
            {"name": "too-fast-near-people"},
            {"name": "too-close"}
        ])
    );
    assert_eq!(
        config["observations"],
        json!([
            "collision",
            "stuck",
            "behind-plan",
            "near-person-fast",
            "close-pass"
        ])
    );
    assert_eq!(config["adapter"]["thresholds"]["trustworthy"], 1.0);
    // Nothing of the config's is replaced: it names the kinds in use.
    assert_eq!(config["adapter"]["search"], "random_walk", "{config}");
    assert_eq!(config["strategy"], "random-walk", "{config}");
    let abandoned = ok(&mut s, r#"{"request":"abandon"}"#);
    assert_eq!(abandoned["ok"], "abandoned");
    assert_eq!(abandoned["retained"], Value::Null);
}

/// A user's searcher, written outside the library: the untried behavior of smallest rank.
struct Lowest;

impl cbr_core::Searcher for Lowest {
    type Evidence = trust::Evaluated;
    type Feedback = trust::Outcome;

    fn name(&self) -> &str {
        "lowest"
    }

    fn propose(
        &mut self,
        space: &cbr_core::BehaviorSpace,
        evaluated: &[trust::Evaluated],
        rng: &mut dyn rand::RngCore,
    ) -> cbr_core::Proposal {
        trust::search::propose_untried(space, evaluated, rng, |tried, _| {
            (0..space.size())
                .map(|r| space.unrank(r))
                .find(|b| !tried.contains(b))
        })
    }
}

#[test]
fn a_users_searcher_and_retriever_serve_through_the_definition() {
    let dir = tempfile::tempdir().unwrap();
    let domain = quick_movement()
        .with_searcher(|_| Box::new(Lowest))
        .with_retriever(|measure| trust::RetrieverKind::InvertedIndex.build_measure(measure));
    let cases = SharedCases::open(&domain, &Location::Sqlite(dir.path().join("cases.db"))).unwrap();
    let retriever = cases.current(|memory, _| memory.retriever_name().to_owned());
    assert_eq!(retriever.unwrap(), "inverted_index");
    let mut s = Session::new(domain, Arc::new(cases), 7).unwrap();
    ok(
        &mut s,
        r#"{"request":"begin","behavior":"speed=3.5,padding=0.4"}"#,
    );
    let reply = ok(
        &mut s,
        r#"{"outcome":"interrupted","weight":1,"stated":"collision","duration_s":2}"#,
    );
    assert_eq!(reply["source"], "search", "{reply}");
    let space = s.adaptation().space().clone();
    assert_eq!(s.adaptation().episode().unwrap().current, space.unrank(0));
    // The config reply names the strategy in use, and no longer the config's kinds the
    // user's parts replaced.
    let config = ok(&mut s, r#"{"request":"config"}"#);
    assert_eq!(config["strategy"], "lowest", "{config}");
    assert_eq!(config["adapter"].get("search"), None, "{config}");
    assert_eq!(config["adapter"].get("retriever"), None, "{config}");
    assert_eq!(config["adapter"]["lambda"], 0.95, "{config}");
}

#[test]
fn hostile_lines_get_named_errors_and_change_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = session(dir.path());
    ok(
        &mut s,
        r#"{"request":"begin","behavior":"speed=3.5,padding=0.4"}"#,
    );
    // A half-weight completion leaves the trust at 0.5: the episode stays open with a
    // non-trivial state for the refused requests to leave alone. Its 1e308 s leave no room
    // for another such duration.
    ok(
        &mut s,
        r#"{"outcome":"completed","weight":0.5,"duration_s":1e308}"#,
    );
    let deep = format!("{}{}", "[".repeat(100_000), "]".repeat(100_000));
    let cases: [(&str, &str); 23] = [
        (
            r#"{"outcome":"failed","weight":1,"duration_s":1,"outcome":"completed"}"#,
            "field `outcome` is given twice",
        ),
        (
            r#"{"outcome": "interrupted", "weight": 1.0, "cau"#,
            "malformed JSON",
        ),
        (
            r#"{"outcome": "interrupted" "weight": 1.0}"#,
            "malformed JSON",
        ),
        ("", "malformed JSON"),
        ("\u{0}\u{7f}garbage", "malformed JSON"),
        ("42", "must be a JSON object, got a number"),
        (
            r#"{"outcome":"completed","weight":1,"duration_s":1,"mood":"ok"}"#,
            "unknown field `mood` in an outcome report",
        ),
        (
            r#"{"request":"state","x":1}"#,
            "unknown field `x` in a `state` request",
        ),
        (
            r#"{"outcome":"completed","weight":"1","duration_s":1}"#,
            "field `weight`: invalid type: string",
        ),
        (
            r#"{"outcome":"completed","weight":1,"duration_s":[1]}"#,
            "field `duration_s`: invalid type: sequence",
        ),
        (
            r#"{"outcome":7,"weight":1,"duration_s":1}"#,
            "field `outcome`: invalid type: integer",
        ),
        (
            r#"{"outcome":"completed","weight":NaN,"duration_s":1}"#,
            "JSON has no NaN",
        ),
        (
            r#"{"outcome":"completed","weight":-0.5,"duration_s":1}"#,
            "weight must be a finite number >= 0, got -0.5",
        ),
        (
            r#"{"outcome":"failed","weight":1,"duration_s":-3}"#,
            "duration_s must be a finite number >= 0",
        ),
        (
            r#"{"outcome":"failed","weight":1e999,"duration_s":1}"#,
            "malformed JSON: number out of range",
        ),
        (
            r#"{"outcome":"failed","weight":1,"stated":"ghost","duration_s":1}"#,
            "field `stated`: cause `ghost` is not declared (declared: deadline, collision, stuck, too-fast-near-people, too-close)",
        ),
        (
            // A patrol cause, not one of the movement domain's.
            r#"{"outcome":"failed","weight":1,"stated":"detonation","duration_s":1}"#,
            "field `stated`: cause `detonation` is not declared (declared: deadline, collision, stuck, too-fast-near-people, too-close)",
        ),
        (
            r#"{"outcome":"failed","weight":1,"cause":"collision","duration_s":1}"#,
            "field `cause` is retired",
        ),
        (r#"{"request":"dance"}"#, "unknown request `dance`"),
        (r#"{"request":"begin"}"#, "an episode is already under way"),
        (r#"{"weight":1}"#, "needs a `request` field"),
        (
            r#"{"outcome":"completed","weight":0,"duration_s":1.7e308}"#,
            "total time overflow",
        ),
        (&deep, "recursion limit exceeded"),
    ];
    for (line, expected) in cases {
        let before = snapshot(&mut s);
        let reply = ask(&mut s, line);
        let error = reply["error"]
            .as_str()
            .unwrap_or_else(|| panic!("{line} -> {reply}"));
        assert!(error.contains(expected), "{line} -> {error}");
        assert_eq!(reply.as_object().unwrap().len(), 1, "{reply}");
        assert_eq!(snapshot(&mut s), before, "{line} changed the state");
    }
}

#[test]
fn bad_behaviors_and_out_of_place_requests_change_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = session(dir.path());
    let cases = [
        (INTERRUPTED, "no episode is under way"),
        (r#"{"request":"abandon"}"#, "nothing to abandon"),
        (
            r#"{"request":"begin","behavior":{"speed":3.5}}"#,
            "no value given for component `padding`",
        ),
        (
            r#"{"request":"begin","behavior":{"speed":3.5,"padding":0.4,"turbo":1}}"#,
            "unknown component `turbo` (known: speed, padding)",
        ),
        (
            r#"{"request":"begin","behavior":{"speed":30,"padding":0.4}}"#,
            "`30` is not an admissible value of `speed` (0.5 to 10 in steps of 0.5)",
        ),
        (
            r#"{"request":"begin","behavior":"speed:3.5"}"#,
            "expected `name=value",
        ),
        (
            r#"{"request":"begin","behavior":{"speed":null,"padding":0.4}}"#,
            "field `behavior.speed`",
        ),
        (
            r#"{"request":"begin","behavior":"speed=NaN,padding=0.4"}"#,
            "`NaN` is not an admissible value of `speed`",
        ),
        (
            r#"{"request":"begin","behavior":{"speed":"inf","padding":0.4}}"#,
            "`inf` is not an admissible value of `speed`",
        ),
        (
            r#"{"request":"begin","behavior":"speed=3.5,speed=4.0,padding=0.4"}"#,
            "component `speed` is given twice",
        ),
        (
            r#"{"request":"begin","behavior":{"speed":3.5,"padding":0.4,"speed":4.0}}"#,
            "field `speed` is given twice",
        ),
        (
            r#"{"request":"begin","behavior":{}}"#,
            "no value given for components `speed`, `padding`",
        ),
    ];
    for (line, expected) in cases {
        let before = snapshot(&mut s);
        let reply = ask(&mut s, line);
        let error = reply["error"]
            .as_str()
            .unwrap_or_else(|| panic!("{line} -> {reply}"));
        assert!(error.contains(expected), "{line} -> {error}");
        assert_eq!(snapshot(&mut s), before, "{line} changed the state");
    }
    // A refused begin does not consume the server's draw: a fresh session draws the same.
    let drawn = ok(&mut s, r#"{"request":"begin"}"#)["behavior"].clone();
    let dir2 = tempfile::tempdir().unwrap();
    let mut fresh = session(dir2.path());
    assert_eq!(ok(&mut fresh, r#"{"request":"begin"}"#)["behavior"], drawn);
}

#[test]
fn a_failed_save_is_reported_and_stops_the_server() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = session(dir.path());
    // After start-up the database starts refusing new cases (as a full disk would): the
    // first retention cannot be stored.
    rusqlite::Connection::open(dir.path().join("cases.db"))
        .unwrap()
        .execute_batch(
            "CREATE TRIGGER refuse BEFORE INSERT ON trustcbr_cases
             BEGIN SELECT RAISE(FAIL, 'database or disk is full'); END;",
        )
        .unwrap();
    let input = [
        r#"{"request":"begin"}"#,
        INTERRUPTED,
        COMPLETED,
        r#"{"request":"state"}"#,
    ]
    .join("\n");
    let mut output = Vec::new();
    let err = service::transport::serve(&mut s, BufReader::new(input.as_bytes()), &mut output)
        .unwrap_err();
    assert!(
        err.to_string()
            .starts_with("a case was retained but could not be stored, so the server stops"),
        "{err}"
    );
    let replies = reply_lines(&output);
    // begin, switch, then the error instead of `settled`; the `state` line is never read.
    assert_eq!(replies.len(), 3);
    assert_eq!(replies[1]["ok"], "switch");
    assert!(
        replies[2]["error"]
            .as_str()
            .unwrap()
            .contains("database or disk is full")
    );
    assert!(stored(dir.path()).is_empty());
}

#[test]
fn a_line_of_exactly_the_limit_is_accepted_with_either_terminator() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = session(dir.path());
    let mut full = b"{\"request\":\"state\"}".to_vec();
    full.resize(service::MAX_LINE_BYTES, b' ');
    let mut input = Vec::new();
    for terminator in [&b"\r\n"[..], b"\n", b""] {
        input.extend_from_slice(&full);
        input.extend_from_slice(terminator);
    }
    let replies = serve_all(&mut s, &input);
    assert_eq!(replies.len(), 3);
    for reply in replies {
        assert_eq!(reply["ok"], "state", "{reply}");
    }
}

#[test]
fn oversize_lines_are_refused_and_the_conversation_goes_on() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = session(dir.path());
    let mut input = Vec::new();
    input.extend_from_slice(b"{\"request\":\"begin\",\"behavior\":\"speed=1,padding=1\"}\n");
    input.extend_from_slice(b"{\"request\":\"state\"}\n");
    let mut huge = b"{\"outcome\":\"completed\",\"weight\":1,\"duration_s\":1,\"pad\":\"".to_vec();
    huge.resize(huge.len() + service::MAX_LINE_BYTES, b'x');
    huge.extend_from_slice(b"\"}\n");
    input.extend_from_slice(&huge);
    input.extend_from_slice(b"{\"request\":\"state\"}\n");
    let replies = serve_all(&mut s, &input);
    assert_eq!(replies.len(), 4);
    assert!(
        replies[2]["error"]
            .as_str()
            .unwrap()
            .contains("line too long")
    );
    assert!(
        replies[2]["error"]
            .as_str()
            .unwrap()
            .contains("65536 bytes")
    );
    assert_eq!(
        replies[1], replies[3],
        "the oversize line changed the state"
    );
}

/// Lines a controller might send, right or wrong.
fn any_line() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        Just(br#"{"request": "begin"}"#.to_vec()),
        Just(br#"{"request": "state"}"#.to_vec()),
        Just(br#"{"request": "abandon"}"#.to_vec()),
        Just(INTERRUPTED.as_bytes().to_vec()),
        Just(COMPLETED.as_bytes().to_vec()),
        prop::collection::vec(
            any::<u8>().prop_filter("no newline", |b| *b != b'\n'),
            0..64
        ),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Whatever arrives, every line gets exactly one reply, `ok` or `error`, and the server
    /// goes on.
    #[test]
    fn every_line_gets_one_reply(lines in prop::collection::vec(any_line(), 0..40)) {
        let dir = tempfile::tempdir().unwrap();
        let mut s = session(dir.path());
        let mut input = Vec::new();
        for line in &lines {
            input.extend_from_slice(line);
            input.push(b'\n');
        }
        let replies = serve_all(&mut s, &input);
        prop_assert_eq!(replies.len(), lines.len());
        for reply in replies {
            let object = reply.as_object().unwrap();
            prop_assert!(object.contains_key("ok") != object.contains_key("error"));
        }
    }
}

/// A JSON object of fields a request might carry, some of them given twice.
fn object_with_repeats() -> impl Strategy<Value = Vec<u8>> {
    let field = prop_oneof![
        Just(r#""request":"begin""#),
        Just(r#""request":"state""#),
        Just(r#""outcome":"completed""#),
        Just(r#""outcome":"interrupted""#),
        Just(r#""weight":1.0"#),
        Just(r#""duration_s":2.0"#),
        Just(r#""cause":"collision""#),
        Just(r#""stated":"collision""#),
        Just(r#""observed":["collision"]"#),
        Just(r#""behavior":"speed=3.5,padding=0.4""#),
        Just(r#""behavior":"speed=NaN,padding=0.4""#),
        Just(r#""behavior":{"speed":3.5,"padding":0.4,"speed":"inf"}"#),
        Just(r#""behavior":{"speed":"nan","padding":0.4}"#),
    ];
    prop::collection::vec(field, 1..6).prop_flat_map(|fields| {
        let repeat = 0..fields.len();
        (Just(fields), repeat).prop_map(|(mut fields, k)| {
            fields.push(fields[k]);
            format!("{{{}}}", fields.join(",")).into_bytes()
        })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Whatever is refused (arbitrary bytes, repeated keys, non-finite behavior values),
    /// the episode under way, the case base and the server's draws stay as they were.
    #[test]
    fn refused_lines_change_nothing(
        line in prop_oneof![
            object_with_repeats(),
            prop::collection::vec(any::<u8>(), 0..96),
            any_line(),
        ]
    ) {
        let dir = tempfile::tempdir().unwrap();
        let mut s = session(dir.path());
        ok(&mut s, r#"{"request":"begin","behavior":"speed=3.5,padding=0.4"}"#);
        ok(&mut s, r#"{"outcome":"completed","weight":0.5,"duration_s":1.0}"#);
        let before = snapshot(&mut s);
        let reply = s.handle_line(&line).unwrap().into_value();
        if reply.get("error").is_some() {
            prop_assert_eq!(snapshot(&mut s), before);
            // The server's draws are untouched: after the episode, it draws what a fresh
            // session with the same history draws.
            ok(&mut s, r#"{"request":"abandon"}"#);
            let drawn = ok(&mut s, r#"{"request":"begin"}"#)["behavior"].clone();
            let dir2 = tempfile::tempdir().unwrap();
            let mut fresh = session(dir2.path());
            ok(&mut fresh, r#"{"request":"begin","behavior":"speed=3.5,padding=0.4"}"#);
            ok(&mut fresh, r#"{"request":"abandon"}"#);
            prop_assert_eq!(ok(&mut fresh, r#"{"request":"begin"}"#)["behavior"].clone(), drawn);
        }
    }
}

#[test]
fn every_switch_and_settled_reply_explains_itself_and_explain_tells_the_episode_so_far() {
    let dir = tempfile::tempdir().unwrap();
    let mut domain = quick_movement()
        .with_hints(domains::perception::MOVEMENT_HINTS.to_vec())
        .unwrap();
    // Three interruptions to give a behavior up, five completions to trust it.
    domain.adapter.thresholds.untrustworthy = -3.0;
    domain.adapter.thresholds.trustworthy = 5.0;
    let mut s = Session::new(domain, open_cases(dir.path()), 7).unwrap();
    assert_eq!(
        ok(&mut s, r#"{"request":"explain"}"#),
        json!({"ok": "explanation", "episode": null})
    );
    ok(
        &mut s,
        r#"{"request":"begin","behavior":{"speed":3.5,"padding":0.4}}"#,
    );
    // A bump the robot perceives, a stated collision, and a run behind its plan with
    // nothing stated (a hint at the deadline).
    let bump = r#"{"outcome": "interrupted", "weight": 1.0, "duration_s": 4.0, "observed": ["collision"]}"#;
    let said =
        r#"{"outcome": "interrupted", "weight": 1.0, "duration_s": 4.0, "stated": "collision"}"#;
    let late = r#"{"outcome": "interrupted", "weight": 1.0, "duration_s": 9.0, "observed": ["behind-plan"]}"#;
    ok(&mut s, bump);
    ok(&mut s, said);
    let so_far = ok(&mut s, r#"{"request":"explain","id":3}"#);
    assert_eq!(so_far["id"], 3);
    let current = &so_far["episode"]["current"];
    assert_eq!(current["behavior"], json!({"speed": 3.5, "padding": 0.4}));
    assert_eq!(
        (current["commands"].clone(), current["trust"].clone()),
        (json!(2), json!(-2.0))
    );
    assert_eq!(
        current["reasons"],
        json!([{"cause": "collision", "weight": 2.0, "stated": 1, "perceived": 1, "inferred": 0.0}])
    );
    assert_eq!(so_far["episode"]["switches"], json!([]));
    let switched = ok(&mut s, late);
    assert_eq!(switched["ok"], "switch");
    let explanation = &switched["explanation"];
    assert_eq!(explanation["given_up"]["untrustworthy"], 3);
    assert_eq!(explanation["given_up"]["reasons"][0]["cause"], "collision");
    assert_eq!(explanation["given_up"]["reasons"][1]["cause"], "deadline");
    assert_eq!(explanation["next"]["source"], "search");
    assert_eq!(explanation["next"]["strategy"], "random-walk");
    assert_eq!(explanation["next"]["behavior"], switched["behavior"]);
    assert_eq!(explanation["next"]["rationale"]["kind"], "explores");
    let sentence = explanation["sentence"].as_str().unwrap();
    assert!(
        sentence.starts_with("Gave up speed=3.5 m/s, padding=0.4 m after 3 commands (3 untrustworthy): most likely collision (stated once; perceived once), then deadline (inferred, p = "),
        "{sentence}"
    );
    // The episode so far now holds the switch.
    let so_far = ok(&mut s, r#"{"request":"explain"}"#);
    assert_eq!(so_far["episode"]["switches"][0], *explanation);
    assert_eq!(so_far["episode"]["current"]["commands"], 0);
    // Five completions settle it: the settled reply says why.
    let mut settled = Value::Null;
    for _ in 0..5 {
        settled = ok(&mut s, COMPLETED);
    }
    assert_eq!(settled["ok"], "settled");
    assert_eq!(settled["explanation"]["given_up"], Value::Null);
    assert_eq!(settled["explanation"]["next"]["source"], "kept");
    assert_eq!(settled["explanation"]["next"]["commands"], 5);
    assert!(
        settled["explanation"]["sentence"]
            .as_str()
            .unwrap()
            .ends_with("trusted after 5 commands (estimate +5.00)."),
        "{settled}"
    );
}

#[test]
fn a_domain_file_declares_hints_by_name_and_is_refused_with_an_unknown_one() {
    let text = |hint: &str| {
        format!(
            r#"(
    space: (components: [(name: "speed", unit: "m/s", values: Numeric(min: 0.5, step: 0.5, count: 4))]),
    causes: [(name: "late")],
    observations: ["slow-progress"],
    hints: [{hint}],
)"#
        )
    };
    let good = DomainDefinition::from_ron(
        &text(r#"(observation: "slow-progress", suggests: "late")"#),
        Path::new("d.ron"),
    )
    .unwrap();
    assert_eq!(good.vocabulary().hints.len(), 1);
    let err = DomainDefinition::from_ron(
        &text(r#"(observation: "beep", suggests: "late")"#),
        Path::new("d.ron"),
    )
    .unwrap_err()
    .to_string();
    assert_eq!(
        err,
        "d.ron: field `hints`: hint observation `beep` is not a declared observation (declared: slow-progress)"
    );
    let err = DomainDefinition::from_ron(
        &text(r#"(observation: "slow-progress", suggests: "early")"#),
        Path::new("d.ron"),
    )
    .unwrap_err()
    .to_string();
    assert_eq!(
        err,
        "d.ron: field `hints`: hint of `slow-progress`: cause `early` is not declared (declared: late)"
    );
}

/// The paper's arithmetic over the protocol: with the default thresholds (+5 / -5), fifteen
/// outcomes of weight 1/3 (as a controller sends it, `0.3333333333333333`) reach a
/// threshold on the fifteenth, not the sixteenth.
#[test]
fn fifteen_weights_of_a_third_reach_a_threshold_over_the_protocol() {
    let dir = tempfile::tempdir().unwrap();
    let paper = DomainDefinition::new(
        "movement",
        domains::Scenario::Movement.space(),
        domains::Scenario::Movement.causes().to_vec(),
        trust::AdapterConfig::default(),
    );
    let cases = Arc::new(
        SharedCases::open(&paper, &Location::Sqlite(dir.path().join("cases.db"))).unwrap(),
    );
    let mut s = Session::new(paper, cases, 7).unwrap();
    let third = |kind: &str| {
        format!(r#"{{"outcome": "{kind}", "weight": 0.3333333333333333, "duration_s": 10.0}}"#)
    };
    ok(
        &mut s,
        r#"{"request":"begin","behavior":{"speed":3.5,"padding":0.4}}"#,
    );
    for _ in 0..14 {
        assert_eq!(ok(&mut s, &third("interrupted"))["ok"], "keep");
    }
    let switched = ok(&mut s, &third("interrupted"));
    assert_eq!(switched["ok"], "switch", "{switched}");
    for _ in 0..14 {
        assert_eq!(ok(&mut s, &third("completed"))["ok"], "keep");
    }
    let settled = ok(&mut s, &third("completed"));
    assert_eq!(settled["ok"], "settled", "{settled}");
    assert_eq!(settled["trustworthy"], true);
}

/// The robot's context over the protocol: a case keeps the context its episode began in,
/// an episode reuses only the cases of its own context, and a context that is not the
/// domain's, or a change in the middle of an episode, is refused and changes nothing.
#[test]
fn cases_are_learned_and_reused_in_their_context() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = session(dir.path());
    let config = ok(&mut s, r#"{"request":"config"}"#);
    assert_eq!(
        config["contexts"],
        json!([
            {"name": "cargo", "values": ["normal", "hazardous"]},
            {"name": "situation", "values": ["routine", "emergency"]}
        ])
    );
    let first = r#""behavior":{"speed":3.5,"padding":0.4}"#;
    let begun = ok(
        &mut s,
        &format!(r#"{{"request":"begin",{first},"context":{{"cargo":"hazardous"}}}}"#),
    );
    assert_eq!(begun["context"], json!({"cargo": "hazardous"}));
    // No change of context while the episode runs.
    let before = snapshot(&mut s);
    let refused = ask(
        &mut s,
        r#"{"request":"context","context":{"cargo":"normal"}}"#,
    );
    assert!(
        refused["error"]
            .as_str()
            .unwrap()
            .starts_with("an episode is under way, and its behaviors were all evaluated"),
        "{refused}"
    );
    assert_eq!(snapshot(&mut s), before);
    assert_eq!(before.0["context"], json!({"cargo": "hazardous"}));
    assert_eq!(ok(&mut s, INTERRUPTED)["source"], "search");
    assert_eq!(ok(&mut s, COMPLETED)["retained"], 1);
    let learned = stored(dir.path());
    assert_eq!(
        learned.cases()[0].problem.context.to_string(),
        "cargo=hazardous"
    );
    let cases = ok(&mut s, r#"{"request":"cases"}"#);
    assert_eq!(cases["cases"][0]["context"], json!({"cargo": "hazardous"}));

    // Back to normal cargo: the same first behavior, given up alike, finds no case.
    let changed = ok(
        &mut s,
        r#"{"request":"context","context":{"cargo":"normal"}}"#,
    );
    assert_eq!(changed, json!({"ok": "context", "context": {}}));
    assert!(
        ok(&mut s, r#"{"request":"state"}"#)
            .get("context")
            .is_none()
    );
    ok(&mut s, &format!(r#"{{"request":"begin",{first}}}"#));
    assert_eq!(ok(&mut s, INTERRUPTED)["source"], "search");
    ok(&mut s, r#"{"request":"abandon"}"#);
    // With hazardous cargo again it reuses the case learned with it.
    ok(
        &mut s,
        &format!(r#"{{"request":"begin",{first},"context":{{"cargo":"hazardous"}}}}"#),
    );
    let reused = ok(&mut s, INTERRUPTED);
    assert_eq!(reused["source"], "case", "{reused}");
    assert_eq!(reused["behavior"], cases["cases"][0]["solution"]);
    ok(&mut s, r#"{"request":"abandon"}"#);

    // A context the domain does not declare is refused, naming what it allows, and a
    // refused begin begins nothing.
    let before = snapshot(&mut s);
    let unknown = ask(
        &mut s,
        r#"{"request":"context","context":{"weather":"rain"}}"#,
    );
    assert_eq!(
        unknown["error"],
        "field `context`: unknown context variable `weather`; the domain declares: cargo, situation"
    );
    let bad_value = ask(
        &mut s,
        r#"{"request":"begin","context":{"situation":"drill"}}"#,
    );
    assert_eq!(
        bad_value["error"],
        "field `context`: context variable `situation` may be routine, emergency, not `drill`"
    );
    assert_eq!(snapshot(&mut s), before);
    assert_eq!(ok(&mut s, r#"{"request":"begin"}"#)["chosen_by"], "server");
}

/// A user's searcher that keeps what it heard at each episode's start (and proposes as
/// [`Lowest`]).
struct Hearing(Arc<std::sync::Mutex<Vec<Vec<cbr_core::Statement>>>>);

impl cbr_core::Searcher for Hearing {
    type Evidence = trust::Evaluated;
    type Feedback = trust::Outcome;

    fn name(&self) -> &str {
        "hearing"
    }

    fn hear(&mut self, stated: &[cbr_core::Statement]) {
        self.0.lock().unwrap().push(stated.to_vec());
    }

    fn propose(
        &mut self,
        space: &cbr_core::BehaviorSpace,
        evaluated: &[trust::Evaluated],
        rng: &mut dyn rand::RngCore,
    ) -> cbr_core::Proposal {
        Lowest.propose(space, evaluated, rng)
    }
}

/// What an operator states up front reaches the searcher through `begin`'s
/// `preferences`; a name the domain does not declare is refused and changes nothing.
#[test]
fn stated_preferences_reach_the_searcher_through_begin() {
    let dir = tempfile::tempdir().unwrap();
    let heard = Arc::new(std::sync::Mutex::new(Vec::new()));
    let kept = heard.clone();
    let domain = quick_movement()
        .with_statements(vec!["hurry".into(), "avoid-bumps".into()])
        .with_searcher(move |_| Box::new(Hearing(kept.clone())));
    let cases = SharedCases::open(&domain, &Location::Sqlite(dir.path().join("cases.db"))).unwrap();
    let mut s = Session::new(domain, Arc::new(cases), 7).unwrap();
    let config = ok(&mut s, r#"{"request":"config"}"#);
    assert_eq!(config["statements"], json!(["hurry", "avoid-bumps"]));
    let before = snapshot(&mut s);
    let refused = ask(
        &mut s,
        r#"{"request":"begin","preferences":{"hurry":true,"fly":false}}"#,
    );
    assert_eq!(
        refused["error"],
        "field `preferences`: `fly` is not a statement of this domain (declared: hurry, avoid-bumps)"
    );
    assert_eq!(snapshot(&mut s), before);
    assert!(heard.lock().unwrap().is_empty());
    let begun = ok(
        &mut s,
        r#"{"request":"begin","behavior":"speed=3.5,padding=0.4","preferences":{"avoid-bumps":true,"hurry":false}}"#,
    );
    assert_eq!(
        begun["preferences"],
        json!({"avoid-bumps": true, "hurry": false})
    );
    assert_eq!(
        *heard.lock().unwrap(),
        [vec![
            cbr_core::Statement::new("avoid-bumps", true),
            cbr_core::Statement::new("hurry", false)
        ]]
    );
    ok(&mut s, r#"{"request":"abandon"}"#);
    // The next operator states nothing: the searcher hears nothing.
    let begun = ok(&mut s, r#"{"request":"begin"}"#);
    assert!(begun.get("preferences").is_none(), "{begun}");
    assert_eq!(heard.lock().unwrap().last().unwrap(), &Vec::new());
}
