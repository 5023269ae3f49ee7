//! Participants' sessions over a real SQLite file (and a real PostgreSQL server when
//! `TRUSTCBR_TEST_POSTGRES` names one): hand-computed sessions, replay after a restart,
//! repeated and misplaced requests, a fleet's pinned case base, and a record that no longer
//! replays.

use console::db::{Db, open};
use console::participant::{Action, Conduct, ConductError, perform};
use console::{Ending, ShownRun, Stage, Study};
use serde_json::{Value, json};
use service::DomainDefinition;
use std::path::Path;
use std::sync::Arc;

/// A corridor: every run lasts 10 s and arrives; a stop interrupts it.
struct Corridor;

impl Stage for Corridor {
    fn scene(&self) -> Value {
        json!({"size": [10.0, 2.0]})
    }

    fn show(&self, _: &cbr_core::Behavior, seed: u64) -> ShownRun {
        ShownRun {
            picture: json!({"duration_s": 10.0, "seed": seed}),
            duration_s: 10.0,
        }
    }

    fn outcome(
        &self,
        _: &cbr_core::Behavior,
        _: u64,
        ending: Ending,
        stated: Option<&str>,
    ) -> Value {
        match ending {
            Ending::Stopped(at) => {
                json!({"outcome": "interrupted", "weight": 1.0, "duration_s": at, "observed": [], "stated": stated})
            }
            Ending::RanOut => {
                json!({"outcome": "completed", "weight": 1.0, "duration_s": 10.0, "observed": [], "stated": null})
            }
        }
    }
}

/// Thresholds +3 / -2: two stops give a behavior up, three completions settle one.
const DOMAIN: &str = r#"(
    space: (components: [
        (name: "speed", unit: "m/s", values: Numeric(min: 1.0, step: 1.0, count: 5)),
        (name: "padding", unit: "m", values: Numeric(min: 0.2, step: 0.2, count: 5)),
    ]),
    causes: [(name: "collision"), (name: "stuck")],
    adapter: (thresholds: (trustworthy: 3.0, untrustworthy: -2.0), reuse_cases: true),
)"#;

fn study_text(cases: &str, statements: bool) -> String {
    format!(
        r#"Study(
    title: "corridor",
    domain: "corridor",
    conditions: [
        Condition(name: "a", arm: "case-based", explanations: true, statements: {statements}),
    ],
    assignment: Counterbalanced(seed: 1),
    commands: 12,
    behaviors: 4,
    rating: Rating(after: EachBehavior, scale: Likert(7), question: "How much do you trust it?", low: "no", high: "yes"),
    speedup: 10.0,
    consent: "ok",
    cases: {cases},
    seed: 3,
)"#
    )
}

fn conduct(location: &str, text: &str) -> Result<Conduct, console::DbError> {
    let study = Study::from_ron(text, Path::new("study.ron")).unwrap();
    let domain = DomainDefinition::from_ron(DOMAIN, Path::new("corridor.ron")).unwrap();
    let db = open(location, &study, text, "study.ron")?;
    Ok(Conduct {
        conditions: vec![domain],
        study,
        stage: Arc::new(Corridor),
        db: Arc::from(db),
    })
}

fn enroll(conduct: &Conduct) -> String {
    let token = console::server::new_token();
    conduct.db.enroll(&conduct.study, &token, 0).unwrap();
    token
}

fn act(conduct: &Conduct, token: &str, action: Action) -> Value {
    perform(conduct, token, Some(&action), 0).unwrap()
}

fn kinds(db: &dyn Db, participant: u64) -> Vec<String> {
    db.events(participant)
        .unwrap()
        .into_iter()
        .map(|e| e.kind)
        .collect()
}

/// Stops twice (given up at -2), rates, lets three runs end (settled at +3), rates.
fn hand_computed_session(conduct: &Conduct) -> String {
    let token = enroll(conduct);
    let state = perform(conduct, &token, None, 0).unwrap();
    assert_eq!(state["phase"], "watch");
    assert_eq!(state["participant"], "P001");
    assert_eq!(state["command"]["index"], 0);
    let first = state["command"]["behavior"].clone();
    act(conduct, &token, Action::Shown { command: 0 });
    let state = act(
        conduct,
        &token,
        Action::Stop {
            command: 0,
            at_s: 2.5,
        },
    );
    assert_eq!(state["phase"], "state-cause", "the condition asks why");
    let state = act(
        conduct,
        &token,
        Action::Statement {
            command: 0,
            cause: Some("collision".into()),
        },
    );
    assert_eq!(state["last"]["decision"], "keep");
    assert_eq!(state["last"]["outcome"], "interrupted");
    act(conduct, &token, Action::Shown { command: 1 });
    act(
        conduct,
        &token,
        Action::Stop {
            command: 1,
            at_s: 4.0,
        },
    );
    let state = act(
        conduct,
        &token,
        Action::Statement {
            command: 1,
            cause: None,
        },
    );
    assert_eq!(state["last"]["decision"], "switch");
    assert!(
        state["last"]["explanation"]
            .as_str()
            .unwrap()
            .starts_with("Gave up")
    );
    assert_eq!(state["phase"], "rate");
    assert_eq!(state["rating"]["number"], 0);
    let state = act(
        conduct,
        &token,
        Action::Rating {
            number: 0,
            value: 2.0,
        },
    );
    assert_eq!(state["phase"], "watch");
    assert_ne!(
        state["command"]["behavior"], first,
        "the switch changed the behavior"
    );
    assert_eq!(state["progress"]["behaviors"], 2);
    for command in 2..5 {
        act(conduct, &token, Action::Shown { command });
        let state = act(conduct, &token, Action::End { command });
        let expected = if command < 4 { "keep" } else { "settled" };
        assert_eq!(state["last"]["decision"], expected);
    }
    let state = act(
        conduct,
        &token,
        Action::Rating {
            number: 1,
            value: 6.0,
        },
    );
    assert_eq!(state["phase"], "done");
    assert_eq!(
        kinds(conduct.db.as_ref(), 0),
        [
            "enrolled",
            "shown",
            "stop",
            "statement",
            "decision",
            "shown",
            "stop",
            "statement",
            "decision",
            "rating",
            "shown",
            "end",
            "decision",
            "shown",
            "end",
            "decision",
            "shown",
            "end",
            "decision",
            "rating"
        ]
    );
    let ratings: Vec<Value> = conduct
        .db
        .events(0)
        .unwrap()
        .into_iter()
        .filter(|e| e.kind == "rating")
        .map(|e| json!([e.body["value"], e.body["estimate"], e.body["after_command"]]))
        .collect();
    // The estimates are the sums of the rated behaviors' outcomes: -1 -1, then +1 +1 +1.
    assert_eq!(ratings, [json!([2, -2.0, 1]), json!([6, 3.0, 4])]);
    token
}

#[test]
fn a_hand_computed_session_in_sqlite() {
    let dir = tempfile::tempdir().unwrap();
    let location = dir.path().join("study.db");
    let conduct = conduct(location.to_str().unwrap(), &study_text("EachEmpty", true)).unwrap();
    hand_computed_session(&conduct);
    let participant = &conduct.db.participants().unwrap()[0];
    let story = console::story::story(&conduct.study, participant, &conduct.db.events(0).unwrap());
    let lines: Vec<&str> = story.lines().collect();
    assert_eq!(
        lines[0],
        "study/a, arm case-based, participant P001: 5 commands, 2 untrustworthy, 2 behaviors; settled on a behavior the participant trusts, by the estimate"
    );
    assert_eq!(
        lines[3],
        "  #  outcome      at (s)  perceived  stated     estimate"
    );
    assert_eq!(
        lines[4],
        "  1  interrupted  2.5     -          collision  -1"
    );
    assert_eq!(
        lines[5],
        "  2  interrupted  4.0     -          -          -2"
    );
    assert!(lines[6].starts_with("  -> Gave up"), "{story}");
    assert_eq!(lines[7], "  rated 2 (the estimate was -2)");
    assert_eq!(lines.last(), Some(&"  rated 6 (the estimate was +3)"));
}

#[test]
fn a_restarted_console_resumes_every_participant_where_they_were() {
    let dir = tempfile::tempdir().unwrap();
    let location = dir.path().join("study.db");
    let text = study_text("EachEmpty", true);
    let first = conduct(location.to_str().unwrap(), &text).unwrap();
    let token = enroll(&first);
    act(&first, &token, Action::Shown { command: 0 });
    act(
        &first,
        &token,
        Action::Stop {
            command: 0,
            at_s: 1.0,
        },
    );
    act(
        &first,
        &token,
        Action::Statement {
            command: 0,
            cause: None,
        },
    );
    act(&first, &token, Action::Shown { command: 1 });
    let before = act(
        &first,
        &token,
        Action::Stop {
            command: 1,
            at_s: 3.0,
        },
    );
    drop(first);
    let second = conduct(location.to_str().unwrap(), &text).unwrap();
    let after = perform(&second, &token, None, 0).unwrap();
    assert_eq!(after, before);
    assert_eq!(after["phase"], "state-cause");
    assert_eq!(after["command"]["stopped_at"], 3.0);
}

#[test]
fn repeated_requests_are_recorded_once_and_misplaced_ones_not_at_all() {
    let dir = tempfile::tempdir().unwrap();
    let location = dir.path().join("study.db");
    let conduct = conduct(location.to_str().unwrap(), &study_text("EachEmpty", true)).unwrap();
    let token = enroll(&conduct);
    act(&conduct, &token, Action::Shown { command: 0 });
    act(&conduct, &token, Action::Shown { command: 0 });
    act(
        &conduct,
        &token,
        Action::Stop {
            command: 0,
            at_s: 1.0,
        },
    );
    act(
        &conduct,
        &token,
        Action::Stop {
            command: 0,
            at_s: 1.0,
        },
    );
    assert_eq!(
        kinds(conduct.db.as_ref(), 0),
        ["enrolled", "shown", "resumed", "stop"]
    );
    let refused = |action: Action, wanted: &str| {
        let before = conduct.db.events(0).unwrap();
        match perform(&conduct, &token, Some(&action), 0) {
            Err(ConductError::Refused(message)) => assert!(message.contains(wanted), "{message}"),
            other => panic!("{action:?} was not refused: {other:?}"),
        }
        assert_eq!(
            conduct.db.events(0).unwrap(),
            before,
            "a refused request stores nothing"
        );
    };
    refused(
        Action::End { command: 0 },
        "the session is at `state-cause`",
    );
    refused(
        Action::Statement {
            command: 0,
            cause: Some("boredom".into()),
        },
        "`boredom` is not a cause of corridor.ron: allowed collision, stuck or null",
    );
    refused(
        Action::Statement {
            command: 3,
            cause: None,
        },
        "field `command`: 3 is not the command shown now (0)",
    );
    refused(
        Action::Rating {
            number: 0,
            value: 3.0,
        },
        "no rating 0 is asked for now",
    );
    act(
        &conduct,
        &token,
        Action::Statement {
            command: 0,
            cause: None,
        },
    );
    refused(
        Action::Stop {
            command: 1,
            at_s: 10.5,
        },
        "field `at_s`: 10.5 is not a moment of the run: allowed 0 to 10",
    );
    refused(
        Action::Stop {
            command: 1,
            at_s: f64::NAN,
        },
        "is not a moment of the run",
    );
    assert!(matches!(
        perform(&conduct, "not-a-token", None, 0),
        Err(ConductError::Refused(m)) if m == "unknown participant token"
    ));
}

#[test]
fn a_fleet_study_pins_each_participant_to_the_cases_retained_before_they_started() {
    let dir = tempfile::tempdir().unwrap();
    let location = dir.path().join("study.db");
    let conduct = conduct(location.to_str().unwrap(), &study_text("Shared", false)).unwrap();
    // Two participants start before anyone has retained a case; a third starts after the
    // first retained one.
    let first = enroll(&conduct);
    let second = enroll(&conduct);
    // A robot retains a case when it found a behavior after giving one up: two stops,
    // a rating, three runs that end.
    let settle = |token: &str| {
        for command in 0..2 {
            act(&conduct, token, Action::Shown { command });
            act(&conduct, token, Action::Stop { command, at_s: 1.0 });
        }
        act(
            &conduct,
            token,
            Action::Rating {
                number: 0,
                value: 1.0,
            },
        );
        for command in 2..5 {
            act(&conduct, token, Action::Shown { command });
            act(&conduct, token, Action::End { command });
        }
    };
    settle(&first);
    let third = enroll(&conduct);
    settle(&second);
    settle(&third);
    let settled_cases = |number: u64| {
        conduct
            .db
            .events(number)
            .unwrap()
            .into_iter()
            .filter(|e| e.kind == "decision" && e.body["reply"]["ok"] == "settled")
            .map(|e| {
                (
                    e.body["reply"]["retained"].clone(),
                    e.body["reply"]["cases"].clone(),
                )
            })
            .collect::<Vec<_>>()
    };
    assert_eq!(settled_cases(0), [(json!(1), json!(1))]);
    assert_eq!(
        settled_cases(1),
        [(json!(2), json!(1))],
        "the second robot did not see the first's case"
    );
    assert_eq!(
        settled_cases(2),
        [(json!(3), json!(2))],
        "the third robot started with the first's case"
    );
    let snapshots: Vec<i64> = conduct
        .db
        .participants()
        .unwrap()
        .iter()
        .map(|p| p.snapshot)
        .collect();
    assert_eq!(snapshots, [0, 0, 1]);
    // Replaying the second after everyone retained gives the same decisions.
    let state = perform(&conduct, &second, None, 0).unwrap();
    assert_eq!(state["phase"], "rate");
}

#[test]
fn a_record_the_adapter_no_longer_replays_is_reported_not_served() {
    let dir = tempfile::tempdir().unwrap();
    let location = dir.path().join("study.db");
    let conduct = conduct(location.to_str().unwrap(), &study_text("EachEmpty", false)).unwrap();
    let token = enroll(&conduct);
    act(&conduct, &token, Action::Shown { command: 0 });
    act(&conduct, &token, Action::End { command: 0 });
    let sqlite = rusqlite::Connection::open(&location).unwrap();
    sqlite
        .execute(
            "UPDATE console_events SET body = json_set(body, '$.reply.trust', 7.0) WHERE kind = 'decision'",
            [],
        )
        .unwrap();
    match perform(&conduct, &token, None, 0) {
        Err(ConductError::Diverged(d)) => assert_eq!((d.participant.as_str(), d.seq), ("P001", 3)),
        other => panic!("not refused: {other:?}"),
    }
}

#[test]
fn a_database_holding_another_study_is_refused_and_left_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let location = dir.path().join("study.db");
    drop(conduct(location.to_str().unwrap(), &study_text("EachEmpty", true)).unwrap());
    let before = std::fs::read(&location).unwrap();
    let error = conduct(location.to_str().unwrap(), &study_text("Shared", true))
        .err()
        .unwrap()
        .to_string();
    assert!(
        error.contains("holds another study than study.ron"),
        "{error}"
    );
    assert_eq!(std::fs::read(&location).unwrap(), before);
    // The same study with other comments and layout is the same study.
    let relaid = format!(
        "// a comment\n{}",
        study_text("EachEmpty", true).replace("    ", "  ")
    );
    assert!(conduct(location.to_str().unwrap(), &relaid).is_ok());
}

#[cfg(feature = "postgres")]
#[test]
fn a_hand_computed_session_in_postgres() {
    let Ok(url) = std::env::var("TRUSTCBR_TEST_POSTGRES") else {
        assert!(
            std::env::var("CI").as_deref() != Ok("true"),
            "CI must run the console against PostgreSQL: set TRUSTCBR_TEST_POSTGRES (.ci/run starts a server)"
        );
        eprintln!("skipped: set TRUSTCBR_TEST_POSTGRES=postgres://... to run it");
        return;
    };
    let database = format!("trustcbr_console_{}", std::process::id());
    let mut admin = postgres::Client::connect(&url, postgres::NoTls).unwrap();
    for statement in [
        format!("DROP DATABASE IF EXISTS {database}"),
        format!("CREATE DATABASE {database}"),
    ] {
        admin.batch_execute(&statement).unwrap();
    }
    let (base, _) = url.rsplit_once('/').unwrap();
    let location = format!("{base}/{database}");
    {
        let conduct = conduct(&location, &study_text("EachEmpty", true)).unwrap();
        hand_computed_session(&conduct);
        // A second console on the same database sees the same participant.
        let other = self::conduct(&location, &study_text("EachEmpty", true)).unwrap();
        assert_eq!(other.db.participants().unwrap().len(), 1);
        assert_eq!(kinds(other.db.as_ref(), 0).len(), 20);
    }
    admin
        .batch_execute(&format!("DROP DATABASE {database} WITH (FORCE)"))
        .unwrap();
}
