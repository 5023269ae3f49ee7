//! `trustcbr console` as a real process: a study file refused before anything is stored, a
//! participant served over HTTP, a killed console that loses nothing it acknowledged, and
//! the export and report of what was stored.

use crate::support::{Server, refused, succeed, trustcbr};
use serde_json::{Value, json};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::process::Stdio;

const PILOT: &str = include_str!("../../domains/studies/pilot.ron");

/// Starts `console` on a free loopback port and returns it with its address.
fn console(study: &Path, db: &Path) -> (Server, String) {
    let mut server = Server(
        trustcbr()
            .args(["console", "--study"])
            .arg(study)
            .arg("--db")
            .arg(db)
            .args(["--listen", "127.0.0.1:0"])
            .env("TRUSTCBR_CONSOLE_ADMIN_TOKEN", "an-admin-token-for-tests")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap(),
    );
    let mut out = BufReader::new(server.0.stdout.take().expect("stdout is piped"));
    let mut line = String::new();
    out.read_line(&mut line).unwrap();
    let addr = line
        .trim()
        .strip_prefix("listening on http://")
        .unwrap_or_else(|| panic!("not the ready line: {line:?}"))
        .to_owned();
    (server, addr)
}

/// One HTTP/1.1 request; returns the status and the body as JSON (null when empty).
fn http(
    addr: &str,
    method: &str,
    path: &str,
    token: Option<&str>,
    body: Option<Value>,
) -> (u16, Value) {
    let mut stream = TcpStream::connect(addr).unwrap();
    let body = body.map(|b| b.to_string()).unwrap_or_default();
    let auth = token
        .map(|t| format!("Authorization: Bearer {t}\r\n"))
        .unwrap_or_default();
    write!(
        stream,
        "{method} {path} HTTP/1.1\r\nHost: {addr}\r\n{auth}Content-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    )
    .unwrap();
    let mut reply = String::new();
    stream.read_to_string(&mut reply).unwrap();
    let (head, text) = reply.split_once("\r\n\r\n").unwrap();
    let status = head.split(' ').nth(1).unwrap().parse().unwrap();
    (status, serde_json::from_str(text).unwrap_or(Value::Null))
}

fn post(addr: &str, path: &str, token: &str, body: Value) -> Value {
    let (status, reply) = http(addr, "POST", path, Some(token), Some(body));
    assert_eq!(status, 200, "{path}: {reply}");
    reply
}

#[test]
fn a_bad_study_file_is_refused_before_any_table_is_made() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("study.db");
    let cases = [
        (
            "commands: 20",
            "commands: 900",
            "900 is out of range: allowed 1 to 500",
        ),
        (
            "arm: \"case-based\", explanations: false",
            "arm: \"case-bassed\", explanations: false",
            "conditions[1].arm",
        ),
        (
            "domain: \"movement\"",
            "domain: \"warehouse\"",
            "`warehouse` is not a scenario trustcbr can show a person: allowed movement, patrol",
        ),
        ("seed: 7,", "seed: 7, colour: \"red\",", "colour"),
    ];
    for (from, to, reason) in cases {
        let text = PILOT.replacen(from, to, 1);
        assert_ne!(text, PILOT, "{from}");
        // Every refusal names the file and the line of the field at fault.
        let line = text.lines().position(|l| l.contains(to)).unwrap() + 1;
        let place = format!("study.ron:{line}:");
        let study = dir.path().join("study.ron");
        std::fs::write(&study, &text).unwrap();
        let error = refused(
            trustcbr()
                .args(["console", "--study"])
                .arg(&study)
                .arg("--db")
                .arg(&db),
        );
        assert!(error.contains(&place), "{place}: {error}");
        assert!(error.contains(reason), "{error}");
        assert!(
            !db.exists(),
            "{from}: the refused study made {}",
            db.display()
        );
    }
}

#[test]
fn a_public_address_needs_the_flag_and_a_researchers_token() {
    let dir = tempfile::tempdir().unwrap();
    let study = dir.path().join("pilot.ron");
    std::fs::write(&study, PILOT).unwrap();
    let db = dir.path().join("study.db");
    let error = refused(
        trustcbr()
            .args(["console", "--study"])
            .arg(&study)
            .arg("--db")
            .arg(&db)
            .args(["--listen", "0.0.0.0:0"]),
    );
    assert!(error.contains("not a loopback address"), "{error}");
    let error = refused(
        trustcbr()
            .args(["console", "--public", "--study"])
            .arg(&study)
            .arg("--db")
            .arg(&db)
            .args(["--listen", "0.0.0.0:0"])
            .env_remove("TRUSTCBR_CONSOLE_ADMIN_TOKEN"),
    );
    assert!(error.contains("TRUSTCBR_CONSOLE_ADMIN_TOKEN"), "{error}");
    assert!(!db.exists());
}

#[test]
fn a_killed_console_loses_nothing_it_acknowledged_and_the_export_holds_it_all() {
    let dir = tempfile::tempdir().unwrap();
    let study = dir.path().join("pilot.ron");
    std::fs::write(&study, PILOT).unwrap();
    let db = dir.path().join("study.db");
    let (mut server, addr) = console(&study, &db);
    let (status, page) = http(&addr, "GET", "/api/study", None, None);
    assert_eq!(
        (status, page["title"].as_str()),
        (200, Some("Would you let this robot drive?"))
    );
    let (status, enrolled) = http(
        &addr,
        "POST",
        "/api/participants",
        None,
        Some(json!({"consent": true})),
    );
    assert_eq!(status, 201);
    let token = enrolled["token"].as_str().unwrap().to_owned();
    assert_eq!(token.len(), 32, "128 bits as hex");
    let state = post(&addr, "/api/shown", &token, json!({"command": 0}));
    assert_eq!(
        state["condition"]["name"], "explained",
        "the pilot's first block starts with it"
    );
    let run = &state["command"]["run"];
    let duration = run["duration_s"].as_f64().unwrap();
    let path = run["path"].as_array().unwrap();
    assert!(
        path.windows(2)
            .all(|p| p[0][0].as_f64() <= p[1][0].as_f64()),
        "time runs forward"
    );
    assert_eq!(path.last().unwrap()[0].as_f64(), Some(duration));
    let stopped = post(
        &addr,
        "/api/stop",
        &token,
        json!({"command": 0, "at_s": duration / 2.0}),
    );
    assert_eq!(stopped["phase"], "state-cause");
    // Killed without warning: the stop was acknowledged, so it is stored.
    server.0.kill().unwrap();
    server.0.wait().unwrap();
    let (_server, addr) = console(&study, &db);
    let (status, resumed) = http(&addr, "GET", "/api/session", Some(&token), None);
    assert_eq!(status, 200);
    assert_eq!(resumed, stopped);
    let decided = post(
        &addr,
        "/api/statement",
        &token,
        json!({"command": 0, "cause": "too-close"}),
    );
    assert_eq!(decided["last"]["decision"], "keep");
    assert_eq!(decided["last"]["outcome"], "interrupted");
    // Another participant's token never reaches this session; the researcher's pages need
    // the admin token.
    let (_, other) = http(
        &addr,
        "POST",
        "/api/participants",
        None,
        Some(json!({"consent": true})),
    );
    let (_, theirs) = http(&addr, "GET", "/api/session", other["token"].as_str(), None);
    assert_eq!(theirs["participant"], "P002");
    assert_eq!(
        http(&addr, "GET", "/api/session", Some("0123"), None).0,
        401
    );
    assert_eq!(
        http(&addr, "GET", "/api/admin/participants", Some(&token), None).0,
        401
    );
    let (status, rows) = http(
        &addr,
        "GET",
        "/api/admin/participants",
        Some("an-admin-token-for-tests"),
        None,
    );
    assert_eq!(status, 200);
    assert_eq!(rows.as_array().unwrap().len(), 2);
    let out = dir.path().join("export");
    succeed(trustcbr().args(["console", "export"]).arg(&db).arg(&out));
    let events = std::fs::read_to_string(out.join("events.jsonl")).unwrap();
    let kinds: Vec<String> = events
        .lines()
        .map(|l| serde_json::from_str::<Value>(l).unwrap())
        .filter(|e| e["participant"] == "P001")
        .map(|e| e["kind"].as_str().unwrap().to_owned())
        .collect();
    assert_eq!(
        kinds,
        ["enrolled", "shown", "stop", "statement", "decision"]
    );
    let decision: Value = events
        .lines()
        .map(|l| serde_json::from_str::<Value>(l).unwrap())
        .find(|e| e["kind"] == "decision")
        .unwrap();
    assert_eq!(decision["report"]["stated"], "too-close");
    assert_eq!(
        decision["report"]["duration_s"].as_f64(),
        Some(duration / 2.0)
    );
    let episodes = std::fs::read_to_string(out.join("episodes.jsonl")).unwrap();
    let first: Value = serde_json::from_str(episodes.lines().next().unwrap()).unwrap();
    assert_eq!(
        (
            &first["experiment"],
            &first["operator"],
            &first["commands"],
            &first["untrustworthy"]
        ),
        (
            &json!("study/explained"),
            &json!("P001"),
            &json!(1),
            &json!(1)
        )
    );
    assert_eq!(first["true_causes"], json!({"too-close": 1}));
    let told = succeed(trustcbr().args(["console", "explain"]).arg(&db).arg("P001"));
    assert!(
        told.starts_with("study/explained, arm case-based, participant P001: 1 commands, 1 untrustworthy, 1 behaviors; the session is under way"),
        "{told}"
    );
    assert!(told.contains("too-close"), "{told}");
    let unknown = refused(trustcbr().args(["console", "explain"]).arg(&db).arg("P009"));
    assert!(
        unknown.contains("has no participant P009 (it has P001 to P002)"),
        "{unknown}"
    );
    let report = dir.path().join("report");
    succeed(trustcbr().args(["console", "report"]).arg(&db).arg(&report));
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(report.join("report.json")).unwrap())
            .unwrap();
    assert_eq!(summary["participants"], 2);
    assert_eq!(summary["conditions"][0]["stops_mean"], 1.0);
}

#[test]
fn exporting_a_database_that_does_not_exist_makes_none() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("missing.db");
    let error = refused(
        trustcbr()
            .args(["console", "export"])
            .arg(&db)
            .arg(dir.path().join("out")),
    );
    assert!(error.contains("missing.db"), "{error}");
    assert!(!db.exists());
}
