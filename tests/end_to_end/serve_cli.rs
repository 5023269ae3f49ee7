//! `trustcbr serve` as a process: the loopback TCP mode, and the start-up errors a user can
//! cause (bad domain file, corrupt case base, a case base of another space, a FIFO or a
//! device as the case base, non-loopback address), each with a clear message and a
//! non-zero exit, and no file modified.

use serde_json::Value;
use std::io::{BufRead, BufReader, Write};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Command, Output, Stdio};

use crate::support;

fn serve(args: &[&str], cases: &Path) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_trustcbr"));
    command.arg("serve").args(args).arg("--cases").arg(cases);
    command
}

fn failure(output: &Output) -> String {
    assert!(
        !output.status.success(),
        "the server should have refused to start"
    );
    String::from_utf8_lossy(&output.stderr).into_owned()
}

#[test]
fn a_bad_domain_file_names_file_line_column_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let domain = dir.path().join("robot.ron");
    let text = "(\n    space: (components: [\n        (name: \"speed\", values: Numeric(min: 0.5, step: -0.5, count: 20)),\n    ]),\n)\n";
    std::fs::write(&domain, text).unwrap();
    let cases = dir.path().join("cases.db");
    let output = serve(&["--domain", domain.to_str().unwrap()], &cases)
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let stderr = failure(&output);
    let column = text.lines().nth(2).unwrap().find("step: -0.5").unwrap() + "step: -0.5".len() + 1;
    assert!(
        stderr.contains(&format!(
            "robot.ron:3:{column}: field `step` must be a finite number > 0, got -0.5"
        )),
        "{stderr}"
    );
    assert!(!cases.exists());
}

#[test]
fn the_example_domain_file_is_served() {
    let dir = tempfile::tempdir().unwrap();
    let domain = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/domain.ron");
    let mut child = serve(
        &["--domain", domain.to_str().unwrap()],
        &dir.path().join("c.db"),
    )
    .stdin(Stdio::piped())
    .stdout(Stdio::piped())
    .stderr(Stdio::null())
    .spawn()
    .unwrap();
    let requests = concat!(
        r#"{"request": "config"}"#,
        "\n",
        r#"{"request": "begin", "behavior": {"speed": 1.5, "padding": 0.3, "planner": "rrt"}}"#,
        "\n",
    );
    child
        .stdin
        .take()
        .unwrap()
        .write_all(requests.as_bytes())
        .unwrap();
    let output = child.wait_with_output().unwrap();
    assert!(output.status.success());
    let replies: Vec<Value> = output
        .stdout
        .split(|&b| b == b'\n')
        .filter(|l| !l.is_empty())
        .map(|l| serde_json::from_slice(l).unwrap())
        .collect();
    assert_eq!(replies[0]["behaviors"], 8 * 10 * 3);
    assert_eq!(replies[0]["adapter"]["thresholds"]["trustworthy"], 3.0);
    assert_eq!(
        replies[1]["behavior"],
        serde_json::json!({"speed": 1.5, "padding": 0.3, "planner": "rrt"})
    );
}

#[test]
fn corrupt_case_bases_are_refused_and_left_untouched() {
    let dir = tempfile::tempdir().unwrap();
    let corrupt: [(&str, &[u8], &str); 3] = [
        // A RON file cut short: the position of the error.
        (
            "cases.ron",
            b"(cases: [(problem: [(behavior: [1, 2], time: 3.0)], solution: [4, ",
            ":1:",
        ),
        // SQLite's header and nothing a database holds.
        ("cases.db", b"SQLite format 3\0 but then nothing else", ": "),
        // Not a database at all.
        ("notes.db", b"shopping list", ": not a trustcbr case base"),
    ];
    for (name, bytes, expected) in corrupt {
        let cases = dir.path().join(name);
        std::fs::write(&cases, bytes).unwrap();
        let output = serve(&["--domain", "movement"], &cases)
            .stdin(Stdio::null())
            .output()
            .unwrap();
        let stderr = failure(&output);
        assert!(
            stderr.contains(&format!("{}{expected}", cases.display())),
            "{stderr}"
        );
        assert_eq!(std::fs::read(&cases).unwrap(), bytes);
    }
}

#[test]
fn a_case_base_of_another_space_is_refused_naming_the_difference() {
    let dir = tempfile::tempdir().unwrap();
    let cases = dir.path().join("cases.db");
    let created = serve(&["--domain", "movement"], &cases)
        .stdin(Stdio::null())
        .output()
        .unwrap();
    assert!(created.status.success());
    let output = serve(&["--domain", "patrol"], &cases)
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let stderr = failure(&output);
    assert!(
        stderr.contains(
            "the case base was learned in another behavior space (domain `movement`): number of components 2 in the case base, 4 here"
        ),
        "{stderr}"
    );
}

#[test]
fn a_fifo_or_a_device_as_the_case_base_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("cases.db");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    let zero = dir.path().join("zero.db");
    std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
    let zero_ron = dir.path().join("zero.ron");
    std::os::unix::fs::symlink("/dev/zero", &zero_ron).unwrap();
    for (path, kind) in [
        (&fifo, "a FIFO"),
        (&zero, "a device"),
        (&zero_ron, "a device"),
    ] {
        // A server that opened the FIFO would block for ever; one that read /dev/zero
        // would grow without bound. Both must be refused at once.
        let output = serve(&["--domain", "movement"], path)
            .stdin(Stdio::null())
            .output()
            .unwrap();
        let stderr = failure(&output);
        assert!(
            stderr.contains(&format!(
                "{}: not a regular file ({kind}); a case base must be a regular file or absent",
                path.display()
            )),
            "{stderr}"
        );
    }
}

#[test]
fn only_loopback_addresses_are_served() {
    let dir = tempfile::tempdir().unwrap();
    let output = serve(
        &["--domain", "movement", "--listen", "0.0.0.0:0"],
        &dir.path().join("c.db"),
    )
    .output()
    .unwrap();
    assert!(failure(&output).contains("only loopback addresses"));
}

#[test]
fn each_tcp_connection_is_its_own_episode_over_the_shared_cases() {
    let dir = tempfile::tempdir().unwrap();
    let (_server, addr) = support::listening(&mut serve(
        &["--domain", "movement", "--listen", "127.0.0.1:0"],
        &dir.path().join("c.db"),
    ));
    let exchange = |requests: &[&str]| -> Vec<Value> {
        let stream = TcpStream::connect(&addr).unwrap();
        let mut writer = &stream;
        let mut reader = BufReader::new(&stream);
        requests
            .iter()
            .map(|r| {
                writeln!(writer, "{r}").unwrap();
                let mut line = String::new();
                reader.read_line(&mut line).unwrap();
                serde_json::from_str(&line).unwrap()
            })
            .collect()
    };
    let first = exchange(&[
        r#"{"request": "begin", "behavior": {"speed": 2.0, "padding": 0.5}, "id": 1}"#,
        r#"{"outcome": "completed", "weight": 1.0, "duration_s": 9.0, "id": "two"}"#,
        "not json",
        r#"{"request": "state"}"#,
    ]);
    assert_eq!(first[0]["ok"], "begun");
    assert_eq!(first[0]["id"], 1);
    assert_eq!(first[1]["ok"], "keep");
    assert_eq!(first[1]["id"], "two");
    assert!(
        first[2]["error"]
            .as_str()
            .unwrap()
            .starts_with("malformed JSON")
    );
    assert_eq!(first[3]["episode"]["trust"], 1.0);
    // A second connection is another controller: no episode of its own yet.
    let second = exchange(&[r#"{"request": "state"}"#]);
    assert_eq!(second[0]["episode"], Value::Null);
    assert_eq!(second[0]["cases"], 0);
}

#[test]
fn request_ids_come_back_byte_for_byte_as_sent() {
    let dir = tempfile::tempdir().unwrap();
    let domain = dir.path().join("quick.ron");
    std::fs::write(&domain, support::quick_domain(false)).unwrap();
    let mut child = serve(
        &["--domain", domain.to_str().unwrap()],
        &dir.path().join("c.db"),
    )
    .stdin(Stdio::piped())
    .stdout(Stdio::piped())
    .stderr(Stdio::null())
    .spawn()
    .unwrap();
    // 2^64 and beyond, a huge negative, floats a double does not hold, an exponent, a
    // string: each comes back as its text was sent, on a reply object and on a listing.
    let ids = [
        "18446744073709551615",
        "18446744073709551616",
        "-9223372036854775808",
        "-123456789012345678901234567890",
        "0.1000000000000000055511151231257827",
        "2.50",
        "1e400",
        r#""robot-3/42""#,
    ];
    let mut requests = String::new();
    for id in ids {
        requests.push_str(&format!("{{\"request\": \"state\", \"id\": {id}}}\n"));
    }
    requests.push_str(&format!("{{\"request\": \"cases\", \"id\": {}}}\n", ids[1]));
    requests.push_str("{\"request\": \"state\", \"id\": [1]}\n");
    child
        .stdin
        .take()
        .unwrap()
        .write_all(requests.as_bytes())
        .unwrap();
    let output = child.wait_with_output().unwrap();
    let replies: Vec<String> = String::from_utf8(output.stdout)
        .unwrap()
        .lines()
        .map(str::to_owned)
        .collect();
    assert_eq!(replies.len(), ids.len() + 2, "{replies:?}");
    for (id, reply) in ids.iter().zip(&replies) {
        assert!(
            reply.starts_with(r#"{"ok":"state","#) && reply.ends_with(&format!(r#","id":{id}}}"#)),
            "{id}: {reply}"
        );
    }
    let listing = &replies[ids.len()];
    assert_eq!(
        listing,
        &format!(r#"{{"ok":"cases","cases":[],"id":{}}}"#, ids[1])
    );
    let refused: Value = serde_json::from_str(&replies[ids.len() + 1]).unwrap();
    assert!(refused.get("id").is_none(), "{refused}");
    assert_eq!(
        refused["error"],
        "field `id`: expected a string, a number, a boolean or null, got an array"
    );
}

/// The `config` reply of `serve` over `cases` with `args`.
fn served_config(args: &[&str], cases: &Path) -> Value {
    let mut child = serve(args, cases)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(b"{\"request\":\"config\"}\n")
        .unwrap();
    let output = child.wait_with_output().unwrap();
    let stdout = String::from_utf8(output.stdout).unwrap();
    serde_json::from_str(stdout.lines().next().unwrap()).unwrap()
}

#[test]
fn serve_serves_the_recommended_arm_unless_told_another_or_the_domain_s_own() {
    let dir = tempfile::tempdir().unwrap();
    let help = support::succeed(support::trustcbr().args(["serve", "--help"]));
    assert!(
        help.contains(&format!("[default: {}]", trustcbr::lab::RECOMMENDED_ARM)),
        "{help}"
    );
    let recommended = served_config(&["--domain", "movement"], &dir.path().join("a.db"));
    assert_eq!(recommended["strategy"], "nested");
    assert_eq!(recommended["adapter"]["reuse_cases"], true);
    // `domain` serves the domain's own config: a built-in scenario's is the paper's.
    let own = served_config(
        &["--domain", "movement", "--arm", "domain"],
        &dir.path().join("b.db"),
    );
    assert_eq!(own["strategy"], "random-walk");
    assert_eq!(own["adapter"]["search"], "random_walk");
    assert_eq!(own["adapter"]["reuse_cases"], true);
}

#[test]
fn serve_runs_any_arm_by_name_and_refuses_an_unknown_one_before_creating_a_base() {
    let dir = tempfile::tempdir().unwrap();
    let cases = dir.path().join("cases.db");
    let interrupted = r#"{"outcome": "interrupted", "weight": 1.0, "duration_s": 5.0}"#;
    let mut input = String::from("{\"request\":\"config\"}\n{\"request\":\"begin\"}\n");
    for _ in 0..5 {
        input.push_str(interrupted);
        input.push('\n');
    }
    let mut child = serve(
        &["--domain", "movement", "--arm", "case-based+conditioned"],
        &cases,
    )
    .stdin(Stdio::piped())
    .stdout(Stdio::piped())
    .stderr(Stdio::piped())
    .spawn()
    .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(input.as_bytes())
        .unwrap();
    let output = child.wait_with_output().unwrap();
    assert!(output.status.success());
    let replies: Vec<Value> = String::from_utf8(output.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(replies[0]["strategy"], "conditioned");
    assert_eq!(replies[0]["adapter"]["reuse_cases"], true);
    // The fifth interruption gives the first behavior up; with no case yet, the arm's
    // fallback search proposes, and says so.
    let switch = replies.last().unwrap();
    assert_eq!(switch["ok"], "switch");
    assert_eq!(switch["explanation"]["next"]["strategy"], "conditioned");
    // A search-only arm reuses no case.
    let config = served_config(&["--domain", "movement", "--arm", "uniform"], &cases);
    assert_eq!(config["strategy"], "uniform");
    assert_eq!(config["adapter"]["reuse_cases"], false);
    // An unknown arm is refused, naming the known ones, and creates no case base.
    let fresh = dir.path().join("fresh.db");
    let refused_arm = |arm: &str| {
        let output = serve(&["--domain", "movement", "--arm", arm], &fresh)
            .stdin(Stdio::null())
            .output()
            .unwrap();
        failure(&output)
    };
    let stderr = refused_arm("annealing");
    assert!(
        stderr.contains("--arm: unknown arm `annealing` (known: random-walk, case-based"),
        "{stderr}"
    );
    assert!(!fresh.exists());
    // A robot blind to its context is one its controller tells none: refused as an arm.
    let stderr = refused_arm("case-based+context-blind");
    assert!(
        stderr.contains("--arm: `case-based+context-blind` is blind to the robot's context, which a controller tells `serve`"),
        "{stderr}"
    );
    assert!(stderr.contains("send none; serve `case-based`"), "{stderr}");
    // Written twice, or beside another option serve refuses: the name suggested is one
    // serve serves.
    for (arm, served) in [
        ("case-based+context-blind+context-blind", "case-based"),
        ("uniform+ignores-statements+learned-start", "uniform"),
        ("case-based+learned-start+competent", "case-based+competent"),
    ] {
        let stderr = refused_arm(arm);
        assert!(
            stderr.contains(&format!("; serve `{served}`")),
            "{arm}: {stderr}"
        );
    }
    assert!(!fresh.exists());
}
