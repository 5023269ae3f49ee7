//! Hostile input, round five (issue 52, items 6, 7, 8, 9, 14, 17 and 18), through the
//! binary: every argument that is not UTF-8 is accepted as a path or refused by name, never
//! a panic; every job's cost is bounded before any work, the refusal giving the bound and
//! the estimate (a context cycle, the operators in contexts, a suite's operator files, a
//! competence measure); `serve`'s timeouts are refused before any case base exists,
//! whatever the transport, with their real range; numbers in messages are short; a
//! negative `--competence` reaches its range check.

use crate::support;

use std::ffi::OsStr;
use std::os::unix::ffi::OsStrExt;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use support::{one_mission_suite, refused, succeed, trustcbr};

/// A tiny one-trial suite of the paper's movement scenario, with `extra` fields in its
/// experiment.
fn tiny(extra: &str) -> String {
    format!(
        r#"(seed: 1, trials: 1, landscape_runs: 0, limit: (runs: 0),
    experiments: [(scenario: "movement", operator: "balanced"{extra})])"#
    )
}

/// `trustcbr run` of `text` written to `dir/suite.ron`, reporting to `dir/out`.
fn run(dir: &Path, text: &str) -> Command {
    let config = dir.join("suite.ron");
    std::fs::write(&config, text).unwrap();
    let mut command = trustcbr();
    command
        .arg("run")
        .arg(config)
        .arg("--out")
        .arg(dir.join("out"));
    command
}

/// Runs `command`, asserts it exited with `code` and printed `expected` as its whole
/// stderr, and that it printed nothing on stdout.
fn refused_with(command: &mut Command, code: i32, expected: &str) {
    let output = command.output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(code), "{stderr}");
    assert_eq!(stderr, expected);
    assert!(output.stdout.is_empty(), "{stderr}");
}

/// The names in `dir`, sorted.
fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

fn bytes(raw: &[u8]) -> &OsStr {
    OsStr::from_bytes(raw)
}

#[test]
fn an_argument_that_is_not_utf8_is_a_path_taken_as_given_or_a_name_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    // `run` and `reproduce` panicked (exit 101) on any such argument, recording the
    // command line: now a report folder named so is written, and the command line kept.
    let config = dir.path().join("suite.ron");
    std::fs::write(&config, tiny("")).unwrap();
    let out = dir.path().join(bytes(b"o\xfe"));
    succeed(trustcbr().arg("run").arg(&config).arg("--out").arg(&out));
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("o\u{FFFD}"), "{summary}");
    // A config path so named is read as any other path.
    let odd_config = dir.path().join(bytes(b"suite\xff.ron"));
    std::fs::write(&odd_config, tiny("")).unwrap();
    let out2 = dir.path().join("out2");
    succeed(
        trustcbr()
            .arg("run")
            .arg(&odd_config)
            .arg("--out")
            .arg(&out2),
    );
    assert!(out2.join("summary.json").is_file());
    let absent = dir.path().join(bytes(b"absent\xff.ron"));
    let stderr = refused(trustcbr().arg("run").arg(&absent));
    assert_eq!(
        stderr,
        format!(
            "error: {}: No such file or directory (os error 2)\n",
            absent.display()
        )
    );
    // `reproduce` refuses what it must refuse, without a panic.
    let cases = dir.path().join(bytes(b"c\xff"));
    refused_with(
        trustcbr()
            .arg("reproduce")
            .arg("--out")
            .arg(dir.path().join(bytes(b"r\xfe")))
            .arg("--cases")
            .arg(&cases),
        1,
        &format!("error: --cases {}: no such folder\n", cases.display()),
    );
    // A name (or a name that may be a file's, or a URL) is refused by clap, naming it.
    let text_only = "not UTF-8: names, URLs and files named beside names are read as text (a path given alone, such as --out or a config file, may be any bytes)";
    for (args, arg) in [
        (
            vec![
                bytes(b"serve"),
                bytes(b"--domain"),
                bytes(b"mo\xffve"),
                bytes(b"--cases"),
                bytes(b"x.db"),
            ],
            "'mo\u{FFFD}ve' for '--domain <DOMAIN>'",
        ),
        (
            vec![bytes(b"cases"), bytes(b"info"), bytes(b"b\xff.db")],
            "'b\u{FFFD}.db' for '<CASES>'",
        ),
        (
            vec![
                bytes(b"landscape"),
                bytes(b"--scenario"),
                bytes(b"movement"),
                bytes(b"--operator"),
                bytes(b"op\xff.ron"),
            ],
            "'op\u{FFFD}.ron' for '--operator <OPERATOR>'",
        ),
        (
            vec![
                bytes(b"run"),
                bytes(b"suite.ron"),
                bytes(b"--arms"),
                bytes(b"case-based,\xff"),
            ],
            "'\u{FFFD}' for '--arms <ARMS>'",
        ),
    ] {
        let output = trustcbr()
            .current_dir(dir.path())
            .args(&args)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{stderr}");
        assert!(
            stderr.starts_with(&format!("error: invalid value {arg}: {text_only}\n")),
            "{stderr}"
        );
    }
    assert!(!dir.path().join("x.db").exists());
}

#[test]
fn a_context_cycle_is_bounded_and_lists_each_context_once_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let long = vec![r#"{}, {"cargo": "hazardous"}"#; 1000].join(", ") + ", {}";
    refused_with(
        &mut run(
            dir.path(),
            &tiny(&format!(", contexts: Some((cycle: [{long}]))")),
        ),
        1,
        &format!(
            "error: {}: experiments[0].contexts.cycle: 2001 contexts in the cycle; at most 64: the report takes every operator in every context apart, and compares every two\n",
            dir.path().join("suite.ron").display()
        ),
    );
    refused_with(
        &mut run(
            dir.path(),
            &tiny(
                r#", contexts: Some((cycle: [{}, {"cargo": "hazardous"}, {"cargo": "hazardous"}]))"#,
            ),
        ),
        1,
        &format!(
            "error: {}: experiments[0].contexts.cycle[2]: the context `cargo=hazardous` is listed already, at contexts.cycle[1]; list each context once (trials take them in turn)\n",
            dir.path().join("suite.ron").display()
        ),
    );
    assert_eq!(entries(dir.path()), ["suite.ron"]);
}

/// A movement operator file named `name`.
fn operator(name: &str) -> String {
    format!(r#"(name: "{name}", t_complete: 15.0, p_deadline: 0.9, p_collision: 0.1)"#)
}

#[test]
fn a_suite_s_operator_files_and_its_operators_in_contexts_are_bounded_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let files: Vec<String> = (0..65).map(|k| format!("op{k}.ron")).collect();
    for (k, file) in files.iter().enumerate() {
        std::fs::write(dir.path().join(file), operator(&format!("op{k}"))).unwrap();
    }
    let listed = |n: usize| {
        files[..n]
            .iter()
            .map(|f| format!("{f:?}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let suite = |n: usize, extra: &str| {
        format!(
            r#"(seed: 1, trials: 1, landscape_runs: 0, limit: (runs: 0),
    experiments: [(scenario: "movement", operator: "random", operator_files: [{}]{extra})])"#,
            listed(n)
        )
    };
    let config = dir.path().join("suite.ron").display().to_string();
    refused_with(
        &mut run(dir.path(), &suite(65, "")),
        1,
        &format!(
            "error: {config}: experiments[0].operator_files: must be 0 to 64, got 65: each operator needs a landscape of its own, as a family's member does\n"
        ),
    );
    // 64 files and the scenario's 3 built-in operators, each in 4 contexts.
    let four = r#", contexts: Some((cycle: [{}, {"cargo": "hazardous"}, {"situation": "emergency"}, {"cargo": "hazardous", "situation": "emergency"}]))"#;
    refused_with(
        &mut run(dir.path(), &suite(64, four)),
        1,
        &format!(
            "error: {config}: experiments[0].contexts.cycle: 268 operators in contexts (67 operators x 4 contexts); at most 256: each needs a landscape and a known-operator limit, and the report compares every two\n"
        ),
    );
    assert!(!dir.path().join("out").exists());
}

/// `trustcbr competence` of `scenario` in front of its built-in operator `operator`
/// into `out`, with `args`.
fn competence(scenario: &str, operator: &str, out: &Path, args: &[&str]) -> Command {
    let mut command = trustcbr();
    command
        .args(["competence", "--scenario", scenario, "--operator", operator])
        .args(args)
        .arg("--out")
        .arg(out);
    command
}

#[test]
fn a_competence_measure_is_bounded_as_a_whole_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("competence");
    // The patrol space has 16000 behaviors: 100000 asked measure 16000.
    refused_with(
        &mut competence(
            "patrol",
            "speed-focused",
            &out,
            &["--behaviors", "100000", "--truth-runs", "100000"],
        ),
        1,
        "error: --behaviors x (the largest --seen + --truth-runs): 1600800000 commands in all (16000 behaviors, all of the space, x (50 commands seen + 100000 truth runs)); at most 100000000: about two minutes of simulation\n",
    );
    let seen: Vec<String> = (0..=10_000).map(|k| k.to_string()).collect();
    refused_with(
        &mut competence("movement", "balanced", &out, &["--seen", &seen.join(",")]),
        1,
        "error: --behaviors x --seen: 2000200 estimates in competence.json (200 behaviors x 10001 numbers of --seen); at most 50000: each is an entry of competence.json (about 1 KB)\n",
    );
    assert!(!out.exists());
    // The defaults are far within both.
    succeed(&mut competence(
        "movement",
        "balanced",
        &out,
        &["--behaviors", "5", "--truth-runs", "5"],
    ));
    assert_eq!(entries(&out), ["competence.json", "competence.md"]);
}

/// `trustcbr serve` of the movement scenario on stdin with the case base `cases` and
/// `args`, its stdin a pipe closed at once.
fn serve(cases: &Path, args: &[&str]) -> Output {
    trustcbr()
        .args(["serve", "--domain", "movement", "--cases"])
        .arg(cases)
        .args(args)
        .stdin(Stdio::piped())
        .output()
        .unwrap()
}

#[test]
fn serve_refuses_bad_timeouts_and_standards_before_any_case_base_exists_on_stdin() {
    let dir = tempfile::tempdir().unwrap();
    let cases = dir.path().join("fleet.db");
    let range = "must be a number of seconds more than 0 and at most 86400 (a day)";
    for (args, expected) in [
        (
            vec!["--idle-timeout", "0"],
            format!("error: --idle-timeout {range}, got 0\n"),
        ),
        (
            vec!["--write-timeout", "0"],
            format!("error: --write-timeout {range}, got 0\n"),
        ),
        (
            vec!["--idle-timeout", "1e30"],
            format!("error: --idle-timeout {range}, got 1e30\n"),
        ),
        (
            vec!["--write-timeout", "-1"],
            format!("error: --write-timeout {range}, got -1\n"),
        ),
        (
            vec!["--idle-timeout", "86400.5"],
            format!("error: --idle-timeout {range}, got 86400.5\n"),
        ),
        (
            vec!["--mission", "--competence", "-0.1"],
            "error: --competence: the competence standard of `at_most` is -0.1; it must be a chance in [0, 1]\n".to_owned(),
        ),
    ] {
        let output = serve(&cases, &args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
        assert_eq!(stderr, expected, "{args:?}");
        assert!(output.stdout.is_empty());
        assert_eq!(entries(dir.path()), Vec::<String>::new(), "{args:?}");
    }
    // A day is allowed, and the base is then created.
    let output = serve(
        &cases,
        &["--idle-timeout", "86400", "--write-timeout", "0.5"],
    );
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(cases.is_file());
}

#[test]
fn numbers_far_out_of_range_are_shown_short() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("suite.ron").display().to_string();
    let goal = refused(&mut run(
        dir.path(),
        &tiny(", goal_changes: Some((per_hour: 1e300))"),
    ));
    assert!(
        goal.contains("leave `goal_changes` out for none), got 1e300\n"),
        "{goal}"
    );
    let lambda = refused(&mut run(
        dir.path(),
        &tiny("").replace(
            "limit: (runs: 0),",
            "limit: (runs: 0), adapter: (lambda: 1e300),",
        ),
    ));
    assert!(
        lambda.starts_with(&format!(
            "error: {config}:1:82: field `lambda`: lambda must be in (0, 1], got 1e300\n"
        )),
        "{lambda}"
    );
    let mission = refused(&mut run(
        dir.path(),
        &one_mission_suite(r#"(scenario: "movement", operator: "random")"#)
            .replace("every: 10.0", "every: 1e-300"),
    ));
    assert_eq!(
        mission,
        format!(
            "error: {config}: missions[0].changes: changes.every: a mean number of commands >= 1, got 1e-300\n"
        )
    );
    assert_eq!(entries(dir.path()), ["suite.ron"]);
}
