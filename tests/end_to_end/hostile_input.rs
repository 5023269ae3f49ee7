//! End-to-end: hostile command-line input is refused at once, with a message naming the
//! problem, before any work is done.

use crate::support;

use std::path::Path;
use std::process::Command;
use support::{refused, succeed, trustcbr};

fn render(behavior: &str, out: &Path) -> String {
    refused(
        trustcbr()
            .args([
                "render",
                "--scenario",
                "patrol",
                "--behavior",
                behavior,
                "-o",
            ])
            .arg(out),
    )
}

#[test]
fn render_refuses_non_finite_repeated_and_missing_values() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run.svg");
    let rest = "padding=0.3,scan_time=2,scan_distance=0.5";
    for value in ["NaN", "inf", "-inf"] {
        let stderr = render(&format!("speed={value},{rest}"), &out);
        assert!(
            stderr.contains(&format!("`{value}` is not an admissible value of `speed`")),
            "{stderr}"
        );
    }
    let stderr = render(&format!("speed=3.5,speed=4.0,{rest}"), &out);
    assert!(
        stderr.contains("component `speed` is given twice"),
        "{stderr}"
    );
    let stderr = render("speed=2", &out);
    assert!(
        stderr.contains("no value given for components `padding`, `scan_time`, `scan_distance`"),
        "{stderr}"
    );
    assert!(!out.exists());
}

fn mkfifo(path: &Path) {
    let made = Command::new("mkfifo").arg(path).status().unwrap();
    assert!(made.success());
}

#[test]
fn fifos_and_devices_are_refused_as_input_files_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("input.ron");
    mkfifo(&fifo);
    let out = dir.path().join("report");
    for input in [fifo.as_path(), Path::new("/dev/zero")] {
        let stderr = refused(trustcbr().arg("run").arg(input).arg("--out").arg(&out));
        assert!(
            stderr.contains(&format!("{}: is a ", input.display()))
                && stderr.contains("not a regular file"),
            "{stderr}"
        );
        let stderr = refused(
            trustcbr()
                .args(["serve", "--domain"])
                .arg(input)
                .arg("--cases")
                .arg(dir.path().join("cases.ron")),
        );
        assert!(stderr.contains("not a regular file"), "{stderr}");
        let stderr = refused(
            trustcbr()
                .args(["serve", "--domain", "movement", "--cases"])
                .arg(input),
        );
        assert!(stderr.contains("not a regular file"), "{stderr}");
        let stderr = refused(
            trustcbr()
                .args(["landscape", "--scenario", "movement", "--operator"])
                .arg(input)
                .arg("--out")
                .arg(&out),
        );
        assert!(stderr.contains("not a regular file"), "{stderr}");
    }
    assert!(!out.exists());
}

#[test]
fn a_closed_reply_stream_is_reported_once() {
    use std::io::Write;
    use std::process::Stdio;
    let dir = tempfile::tempdir().unwrap();
    let mut server = trustcbr()
        .args(["serve", "--domain", "movement", "--cases"])
        .arg(dir.path().join("cases.db"))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The controller stops reading replies, then sends a request.
    drop(server.stdout.take());
    let mut stdin = server.stdin.take().unwrap();
    stdin.write_all(b"{\"request\":\"state\"}\n").ok();
    drop(stdin);
    let output = server.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("error: connection: Broken pipe (os error 32)\n"),
        "{stderr}"
    );
    assert_eq!(stderr.matches("Broken pipe").count(), 1, "{stderr}");
}

const TINY: &str =
    "(seed: 1, trials: 1, experiments: [(scenario: \"movement\", operator: \"balanced\")])";

/// `trustcbr run` of the one-trial config `TINY` (written in `dir`) into `out`.
fn run_tiny(dir: &Path, out: &Path) -> Command {
    let config = dir.join("tiny.ron");
    std::fs::write(&config, TINY).unwrap();
    let mut command = trustcbr();
    command.arg("run").arg(config).arg("--out").arg(out);
    command
}

#[test]
fn an_unusable_report_folder_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("report");
    std::fs::write(&file, b"not a folder").unwrap();
    let notes = dir.path().join("notes");
    std::fs::create_dir(&notes).unwrap();
    std::fs::write(notes.join("todo.txt"), b"mine").unwrap();
    let cases = [
        (file.as_path(), "exists and is a regular file, not a folder"),
        (
            Path::new("/proc/self/report"),
            "/proc/self: cannot create a folder in this folder: ",
        ),
        // A link is refused whatever it points to (here, the folder just refused).
        (Path::new("/proc/self"), "/proc/self: is a symbolic link; "),
        (
            notes.as_path(),
            "holds `todo.txt`, which is not part of a trustcbr report",
        ),
    ];
    for (out, expected) in cases {
        let output = run_tiny(dir.path(), out).output().unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{stderr}");
        assert!(stderr.contains(expected), "{stderr}");
        // The results table is printed after the work: nothing was computed.
        assert!(output.stdout.is_empty(), "{stderr}");
    }
    assert_eq!(std::fs::read(&file).unwrap(), b"not a folder");
    assert_eq!(std::fs::read(notes.join("todo.txt")).unwrap(), b"mine");
    // `landscape` writes beside other files, but checks its folder first too.
    let stderr = refused(
        trustcbr()
            .args([
                "landscape",
                "--scenario",
                "patrol",
                "--operator",
                "speed-focused",
            ])
            .args(["--runs", "1000", "--out"])
            .arg(&file),
    );
    assert!(stderr.contains("exists and is a regular file"), "{stderr}");
}

#[test]
fn an_earlier_report_is_replaced_without_its_stale_plots() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("report");
    std::fs::create_dir(&out).unwrap();
    for name in ["summary.json", "curves-patrol-gone.svg", "notes.txt"] {
        std::fs::write(out.join(name), b"old").unwrap();
    }
    // The report replaces its folder whole: a file of the user's in it is refused first.
    let stderr = refused(&mut run_tiny(dir.path(), &out));
    assert!(stderr.contains("holds `notes.txt`"), "{stderr}");
    std::fs::rename(out.join("notes.txt"), dir.path().join("notes.txt")).unwrap();
    let output = run_tiny(dir.path(), &out).output().unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(!out.join("curves-patrol-gone.svg").exists());
    assert_eq!(std::fs::read(dir.path().join("notes.txt")).unwrap(), b"old");
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("\"experiments\""), "{summary}");
}

#[test]
fn counts_out_of_range_are_refused() {
    for (args, expected) in [
        (
            &["reproduce", "--threads", "257"][..],
            "257 is not in 1..=256",
        ),
        (&["reproduce", "--threads", "0"], "0 is not in 1..=256"),
        (
            &["reproduce", "--trials", "100001"],
            "100001 is not in 1..=100000",
        ),
        (
            &[
                "landscape",
                "--scenario",
                "movement",
                "--operator",
                "balanced",
                "--runs",
                "0",
            ],
            "0 is not in 1..",
        ),
    ] {
        let stderr = refused(trustcbr().args(args));
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
    }
}

// Round four (issue 32): mission suites, names, saved case bases, `explain`.

/// A mission suite of one movement plan and `arms`, with `extra` added to the plan.
fn mission_suite(arms: &str, extra: &str) -> String {
    format!(
        r#"(
    seed: 3,
    arms: {arms},
    missions: [
        (
            name: "movement/paper",
            operators: (scenario: "movement", operator: "random"{extra}),
            count: 2,
            commands: 60,
            changes: (every: 30.0, takeover: 0.5),
        ),
    ],
)"#
    )
}

/// `trustcbr run` of the suite `text` (written in `dir` as `name`) into `DIR/report`.
fn run_text(dir: &Path, name: &str, text: &str) -> Command {
    let config = dir.join(name);
    std::fs::write(&config, text).unwrap();
    let mut command = trustcbr();
    command
        .arg("run")
        .arg(config)
        .arg("--out")
        .arg(dir.join("report"));
    command
}

#[test]
fn mission_suites_check_populations_as_experiment_suites_do() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("domains/operators/movement/balanced.ron"),
        dir.path().join("balanced.ron"),
    )
    .unwrap();
    let family = |f: &str| format!(r#", population: Some((name: "fam", family: Some({f})))"#);
    for (extra, expected) in [
        // A billion members aborted the process allocating 216 GB.
        (
            family("(conflict: 0.5, size: 1000000000, seed: 1)"),
            "missions[0].operators.population: `family.size` must be 1 to 64, got 1000000000",
        ),
        (
            family("(conflict: 0.5, size: 65, seed: 1)"),
            "must be 1 to 64, got 65",
        ),
        (
            family("(conflict: NaN, size: 4, seed: 1)"),
            "`family.conflict` must be in [0, 1], got NaN",
        ),
        (
            family("(conflict: 7.0, size: 4, seed: 1)"),
            "`family.conflict` must be in [0, 1], got 7",
        ),
        (
            family("(conflict: -3.0, size: 4, seed: 1)"),
            "`family.conflict` must be in [0, 1], got -3",
        ),
        (
            format!(
                "{}, operator_files: [\"balanced.ron\"]",
                family("(conflict: 0.5, size: 4, seed: 1)")
            ),
            "drawn from the family or listed in `operator_files`, not both",
        ),
    ] {
        let suite = mission_suite("[\"uniform\"]", &extra);
        let stderr = refused(&mut run_text(dir.path(), "missions.ron", &suite));
        assert!(
            stderr.contains("missions.ron: ") && stderr.contains(expected),
            "{extra}: {stderr}"
        );
        assert!(!dir.path().join("report").exists(), "{extra}");
    }
}

#[test]
fn thresholds_far_from_zero_are_refused_in_every_suite_kind() {
    let dir = tempfile::tempdir().unwrap();
    // ±1e308 once ran every mission, then spun for ever drawing the figure's axis.
    let far = "adapter: (thresholds: (trustworthy: 5.0, untrustworthy: -1e308)),";
    let mission =
        mission_suite("[\"uniform\"]", "").replacen("seed: 3,", &format!("seed: 3, {far}"), 1);
    let stderr = refused(&mut run_text(dir.path(), "missions.ron", &mission));
    assert!(
        stderr.contains(
            "adapter.thresholds.untrustworthy: must be at most 1000000 from 0 (the paper's are 5 and -5), got -1e308"
        ),
        "{stderr}"
    );
    let suite = TINY.replacen("trials: 1,", &format!("trials: 1, {far}"), 1);
    let stderr = refused(&mut run_text(dir.path(), "suite.ron", &suite));
    assert!(stderr.contains("got -1e308"), "{stderr}");
    // A trustworthy threshold no mission can reach is named as a short number.
    let high = "adapter: (thresholds: (trustworthy: 1e6, untrustworthy: -5.0)),";
    let mission =
        mission_suite("[\"uniform\"]", "").replacen("seed: 3,", &format!("seed: 3, {high}"), 1);
    let stderr = refused(&mut run_text(dir.path(), "missions.ron", &mission));
    assert!(
        stderr.contains("60 commands (commands) can never reach the trustworthy threshold 1000000"),
        "{stderr}"
    );
    assert!(!dir.path().join("report").exists());
}

#[test]
fn a_mission_suite_s_cost_counts_its_truth_runs_and_plans_and_missions() {
    let dir = tempfile::tempdir().unwrap();
    // Exactly 100 million commands, with a change (and 200 truth runs) every command.
    let suite = mission_suite("[\"uniform\"]", "")
        .replace("count: 2,", "count: 1,")
        .replace("commands: 60,", "commands: 100000000,")
        .replace("every: 30.0", "every: 1.0");
    let stderr = refused(&mut run_text(dir.path(), "missions.ron", &suite));
    assert!(
        stderr.contains(
            "missions: 20100000000 commands in all (arms x missions x (commands + 200 truth runs per expected change), twice for complacency plans); at most 100000000"
        ),
        "{stderr}"
    );
    // A million and one missions: every record is kept for the report.
    let suite = mission_suite("[\"uniform\"]", "").replace("count: 2,", "count: 1000001,");
    let stderr = refused(&mut run_text(dir.path(), "missions.ron", &suite));
    assert!(
        stderr.contains("missions: 1000001 missions in all (arms x missions, twice for complacency plans); at most 1000000"),
        "{stderr}"
    );
    // 1,001 plans: each writes a figure.
    let plan = r#"(name: "p", operators: (scenario: "movement", operator: "random"), count: 1, commands: 5, changes: (every: 30.0, takeover: 0.5))"#;
    let plans: Vec<String> = (0..1001)
        .map(|k| plan.replace("\"p\"", &format!("\"p{k}\"")))
        .collect();
    let suite = format!(
        "(seed: 1, arms: [\"uniform\"], missions: [{}])",
        plans.join(", ")
    );
    let stderr = refused(&mut run_text(dir.path(), "missions.ron", &suite));
    assert!(
        stderr.contains("missions: must be 1 to 1000, got 1001"),
        "{stderr}"
    );
    assert!(!dir.path().join("report").exists());
}

#[test]
fn names_are_given_once_in_every_suite_kind() {
    let dir = tempfile::tempdir().unwrap();
    let stderr = refused(&mut run_text(
        dir.path(),
        "missions.ron",
        &mission_suite("[\"uniform\", \"case-based\", \"uniform\"]", ""),
    ));
    assert!(
        stderr.contains("arms[2]: `uniform` is listed twice"),
        "{stderr}"
    );
    let plan = r#"(name: "movement/paper", operators: (scenario: "movement", operator: "random"), count: 1, commands: 5, changes: (every: 30.0, takeover: 0.5))"#;
    let twice = format!("(seed: 1, arms: [\"uniform\"], missions: [{plan}, {plan}])");
    let stderr = refused(&mut run_text(dir.path(), "missions.ron", &twice));
    assert!(
        stderr.contains("missions[1]: the plan `movement/paper` is already missions[0]"),
        "{stderr}"
    );
    let experiment = r#"(scenario: "movement", operator: "balanced")"#;
    let twice = format!("(seed: 1, trials: 1, experiments: [{experiment}, {experiment}])");
    let stderr = refused(&mut run_text(dir.path(), "suite.ron", &twice));
    assert!(
        stderr.contains(
            "experiments[1]: the experiment `movement/balanced` is already experiments[0]"
        ),
        "{stderr}"
    );
    assert!(!dir.path().join("report").exists());
}

#[test]
fn an_arm_starts_from_the_memory_s_guess_once_and_mission_suites_write_arms_as_suites_do() {
    let dir = tempfile::tempdir().unwrap();
    for arms in [
        "[\"case-based+learned-start+learned-start\"]",
        "[(name: \"case-based+learned-start\", initial: learned)]",
    ] {
        let stderr = refused(&mut run_text(
            dir.path(),
            "suite.ron",
            &TINY.replacen("trials: 1,", &format!("trials: 1, arms: {arms},"), 1),
        ));
        assert!(stderr.contains("learned-start"), "{arms}: {stderr}");
    }
    let stderr = refused(
        run_tiny(dir.path(), &dir.path().join("report"))
            .args(["--arms", "case-based+learned-start+learned-start"]),
    );
    assert!(
        stderr.contains("`case-based+learned-start+learned-start` says +learned-start twice"),
        "{stderr}"
    );
    // A sweep whose cells would all run and then fail to merge is refused at once.
    std::fs::write(dir.path().join("suite.ron"), TINY).unwrap();
    let sweep = dir.path().join("sweep.ron");
    std::fs::write(
        &sweep,
        "(suite: file(\"suite.ron\"), seeds: [1], parameters: [arms([[\"uniform\"], [\"case-based+learned-start+learned-start\"]])])",
    )
    .unwrap();
    let out = dir.path().join("sweep");
    let stderr = refused(trustcbr().arg("sweep").arg(&sweep).arg("--out").arg(&out));
    assert!(stderr.contains("says +learned-start twice"), "{stderr}");
    assert!(!out.exists());
    // A mission suite and a sweep write an arm's options as an experiment suite does.
    std::fs::write(
        &sweep,
        "(suite: file(\"suite.ron\"), seeds: [1], parameters: [arms([[\"uniform\"], [(name: \"uniform\", initial: learned)]])])",
    )
    .unwrap();
    succeed(trustcbr().arg("sweep").arg(&sweep).arg("--out").arg(&out));
    let suite = mission_suite(
        "[\"case-based\", (name: \"case-based\", initial: learned)]",
        "",
    )
    .replace("count: 2,", "count: 8,")
    .replace("commands: 60,", "commands: 120,");
    succeed(&mut run_text(dir.path(), "missions.ron", &suite));
    let records = std::fs::read_to_string(dir.path().join("report/missions.jsonl")).unwrap();
    let of = |arm: &str| -> Vec<serde_json::Value> {
        records
            .lines()
            .map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap())
            .filter(|r| r["arm"] == arm)
            .map(|r| r["record"].clone())
            .collect()
    };
    let (random, learned) = (of("case-based"), of("case-based+learned-start"));
    assert_eq!((random.len(), learned.len()), (8, 8), "{records}");
    // Its first mission starts from the random behavior (the memory is empty), later ones
    // from the guess once the memory holds a case, labelled, so its records differ from
    // the random start's.
    assert!(random.iter().all(|r| r.get("learned_start").is_none()));
    assert!(learned[0].get("learned_start").is_none());
    assert!(
        learned.iter().any(|r| r["learned_start"].is_array()),
        "{records}"
    );
    assert_ne!(random, learned);
    let md = std::fs::read_to_string(dir.path().join("report/missions.md")).unwrap();
    assert!(md.contains("case-based+learned-start"), "{md}");
}

#[test]
fn explain_and_sweep_name_a_mission_suite_as_one() {
    let dir = tempfile::tempdir().unwrap();
    let suite = mission_suite("[\"uniform\"]", "");
    succeed(&mut run_text(dir.path(), "missions.ron", &suite));
    let report = dir.path().join("report");
    let stderr = refused(trustcbr().arg("explain").arg(&report).args([
        "--experiment",
        "movement/paper",
        "--arm",
        "uniform",
        "--trial",
        "0",
    ]));
    assert!(
        stderr.contains(
            "missions: this is a mission suite (it lists `missions`), not an experiment suite"
        ),
        "{stderr}"
    );
    let sweep = dir.path().join("sweep.ron");
    std::fs::write(
        &sweep,
        "(suite: file(\"missions.ron\"), seeds: [1], parameters: [])",
    )
    .unwrap();
    let stderr = refused(
        trustcbr()
            .arg("sweep")
            .arg(&sweep)
            .arg("--out")
            .arg(dir.path().join("s")),
    );
    assert!(stderr.contains("this is a mission suite"), "{stderr}");
    assert!(!stderr.contains("Unexpected field"), "{stderr}");
}

#[test]
fn a_long_mission_is_drawn_summarised_and_a_short_one_command_by_command() {
    let dir = tempfile::tempdir().unwrap();
    let long = mission_suite("[\"uniform\"]", "")
        .replace("count: 2,", "count: 1,")
        .replace("commands: 60,", "commands: 30000,")
        .replace("every: 30.0", "every: 3000.0");
    succeed(&mut run_text(dir.path(), "missions.ron", &long));
    let svg =
        std::fs::read_to_string(dir.path().join("report/mission-movement-paper.svg")).unwrap();
    // 30,000 commands in 2,000 steps of 15: the legend says so, and the figure stays small.
    assert!(svg.contains("estimate (range per 15)"), "the legend");
    assert!(svg.len() < 400_000, "{} bytes", svg.len());
    assert!(
        support::outside_view(&svg).is_empty(),
        "{:?}",
        support::outside_view(&svg)
    );
    let short = mission_suite("[\"uniform\"]", "");
    succeed(&mut run_text(dir.path(), "missions.ron", &short));
    let svg =
        std::fs::read_to_string(dir.path().join("report/mission-movement-paper.svg")).unwrap();
    assert!(
        !svg.contains("range per"),
        "a short mission is drawn as it was"
    );
}

/// Case bases saved by `--save-cases`, as `run` writes them: the one-trial suite of `dir`
/// run with the case-based arm and `seed` into `saves` (its report in `DIR/first`).
fn save_cases(dir: &Path, saves: &Path, seed: &str) {
    succeed(
        run_tiny(dir, &dir.join("first"))
            .args([
                "--arms",
                "case-based",
                "--trials",
                "4",
                "--seed",
                seed,
                "--save-cases",
            ])
            .arg(saves),
    );
}

#[test]
fn save_cases_writes_over_no_file_but_a_case_base_saved_earlier() {
    let dir = tempfile::tempdir().unwrap();
    let saves = dir.path().join("saves");
    let target = saves.join("movement-balanced/case-based.ron");
    std::fs::create_dir_all(target.parent().unwrap()).unwrap();
    // An SQLite case base, then a text file: both kept, byte for byte.
    let elsewhere = dir.path().join("elsewhere");
    save_cases(dir.path(), &elsewhere, "1");
    let db = dir.path().join("fleet.db");
    succeed(
        trustcbr()
            .args(["cases", "import"])
            .arg(elsewhere.join("movement-balanced/case-based.ron"))
            .arg(&db)
            .args(["--domain", "movement"]),
    );
    for (content, what) in [
        (std::fs::read(&db).unwrap(), "an SQLite database"),
        (b"my notes".to_vec(), "not a RON case file"),
    ] {
        std::fs::write(&target, &content).unwrap();
        let out = dir.path().join("report");
        let stderr = refused(
            run_tiny(dir.path(), &out)
                .args(["--arms", "case-based", "--save-cases"])
                .arg(&saves),
        );
        assert!(
            stderr.contains(&format!(
                "{}: exists and is not a case base saved earlier ({what}); --save-cases writes over nothing else",
                target.display()
            )),
            "{stderr}"
        );
        assert_eq!(std::fs::read(&target).unwrap(), content);
        assert!(!out.exists(), "refused before any work");
    }
    // A case base saved earlier is replaced.
    std::fs::remove_file(&target).unwrap();
    save_cases(dir.path(), &saves, "1");
    save_cases(dir.path(), &saves, "2");
    assert!(std::fs::read_to_string(&target).unwrap().contains("cases:"));
}

#[test]
fn a_saved_case_base_that_is_a_symlink_loop_is_refused_not_taken_as_absent() {
    let dir = tempfile::tempdir().unwrap();
    let saves = dir.path().join("saves");
    save_cases(dir.path(), &saves, "1");
    let target = saves.join("movement-balanced/case-based.ron");
    std::fs::remove_file(&target).unwrap();
    std::os::unix::fs::symlink(&target, &target).unwrap();
    let stderr = refused(
        run_tiny(dir.path(), &dir.path().join("second"))
            .args(["--arms", "case-based", "--cases"])
            .arg(&saves),
    );
    let expected = format!(
        "{}: not a regular file (a symlink that cannot be followed",
        target.display()
    );
    assert!(stderr.contains(&expected), "{stderr}");
    let stderr = refused(
        trustcbr()
            .arg("explain")
            .arg(dir.path().join("first"))
            .args([
                "--experiment",
                "movement/balanced",
                "--arm",
                "case-based",
                "--trial",
                "0",
                "--cases",
            ])
            .arg(&saves),
    );
    assert!(stderr.contains(&expected), "{stderr}");
}

/// `explain` of trial 1 of the case-based arm of `report`, with `--cases` when given.
fn explain(report: &Path, cases: Option<&Path>) -> Command {
    let mut command = trustcbr();
    command.arg("explain").arg(report).args([
        "--experiment",
        "movement/balanced",
        "--arm",
        "case-based",
        "--trial",
        "1",
    ]);
    if let Some(cases) = cases {
        command.arg("--cases").arg(cases);
    }
    command
}

#[test]
fn explain_refuses_a_report_it_cannot_replay_as_it_ran() {
    let dir = tempfile::tempdir().unwrap();
    let saves = dir.path().join("saves");
    save_cases(dir.path(), &saves, "1");
    let report = dir.path().join("second");
    succeed(
        run_tiny(dir.path(), &report)
            .args(["--arms", "case-based", "--trials", "3", "--cases"])
            .arg(&saves),
    );
    let story = succeed(&mut explain(&report, Some(&saves)));
    assert!(story.contains("movement/balanced"), "{story}");
    // Without the case bases it started from, or with others.
    let stderr = refused(&mut explain(&report, None));
    assert!(
        stderr.contains("experiment `movement/balanced`, arm `case-based`: the run started it from saved case bases (`--cases`), and none is given"),
        "{stderr}"
    );
    let others = dir.path().join("others");
    save_cases(dir.path(), &others, "2");
    let base = "movement-balanced/case-based.ron";
    assert_ne!(
        std::fs::read(saves.join(base)).unwrap(),
        std::fs::read(others.join(base)).unwrap()
    );
    let stderr = refused(&mut explain(&report, Some(&others)));
    assert!(
        stderr.contains("holds other cases than the run started it from"),
        "{stderr}"
    );
    // A report made without case bases, explained with some.
    let plain = dir.path().join("plain");
    succeed(run_tiny(dir.path(), &plain).args(["--arms", "case-based", "--trials", "3"]));
    let stderr = refused(&mut explain(&plain, Some(&saves)));
    assert!(
        stderr.contains("the run started it with no case base, and --cases gives"),
        "{stderr}"
    );
    // The seed edited in config.ron.
    let config = plain.join("config.ron");
    let ran = std::fs::read_to_string(&config).unwrap();
    std::fs::write(&config, ran.replace("seed: 1,", "seed: 2,")).unwrap();
    let stderr = refused(&mut explain(&plain, None));
    assert!(
        stderr.contains(&format!(
            "{}: differs from the config the report ran",
            config.display()
        )),
        "{stderr}"
    );
    std::fs::write(&config, &ran).unwrap();
    succeed(&mut explain(&plain, None));
    // Another version wrote it.
    let summary_path = plain.join("summary.json");
    let summary = std::fs::read_to_string(&summary_path).unwrap();
    let mut older: serde_json::Value = serde_json::from_str(&summary).unwrap();
    older["provenance"]["version"] = "0.0.1".into();
    std::fs::write(&summary_path, older.to_string()).unwrap();
    let stderr = refused(&mut explain(&plain, None));
    assert!(
        stderr.contains("written by trustcbr 0.0.1, and this is trustcbr "),
        "{stderr}"
    );
    // A report of an earlier version records nothing to check: told, with a warning.
    let mut earlier: serde_json::Value = serde_json::from_str(&summary).unwrap();
    earlier["provenance"]
        .as_object_mut()
        .unwrap()
        .remove("replay");
    std::fs::write(&summary_path, earlier.to_string()).unwrap();
    let output = explain(&plain, None).output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(
        stderr.starts_with("warning: ") && stderr.contains("records no `replay`"),
        "{stderr}"
    );
}

#[test]
fn operator_files_name_each_cause_once_and_have_a_name() {
    let dir = tempfile::tempdir().unwrap();
    for (operator, expected) in [
        (
            "(name: \"twice\", t_complete: 15.0, p_deadline: 0.5, p_collision: 0.5, weights: (by_cause: {\"collision\": 1.0, \"collision\": 9.0}))",
            "gives the cause `collision` twice",
        ),
        (
            "(name: \"\", t_complete: 15.0, p_deadline: 0.5, p_collision: 0.5)",
            "operator name `` is empty",
        ),
    ] {
        std::fs::write(dir.path().join("op.ron"), operator).unwrap();
        let suite = "(seed: 1, trials: 1, experiments: [(scenario: \"movement\", operator: \"random\", operator_files: [\"op.ron\"])])";
        let stderr = refused(&mut run_text(dir.path(), "suite.ron", suite));
        assert!(stderr.contains(expected), "{stderr}");
    }
}

#[test]
fn explain_reads_a_report_s_config_ron_as_what_it_is() {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("report");
    std::fs::create_dir(&report).unwrap();
    std::os::unix::fs::symlink("/dev/zero", report.join("config.ron")).unwrap();
    let explain = |report: &Path| {
        refused(
            trustcbr()
                .arg("explain")
                .arg(report)
                .args(["--experiment", "movement/balanced", "--arm", "case-based"])
                .args(["--trial", "0"]),
        )
    };
    let stderr = explain(&report);
    assert!(
        stderr.contains("config.ron") && stderr.contains("not a regular file"),
        "{stderr}"
    );
    assert!(!stderr.contains("no config.ron"), "{stderr}");
    let empty = dir.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    assert!(explain(&empty).contains("not a report folder (it has no config.ron)"));
}
