//! The `warehouse` binary end to end, as a user runs it: the embedded suite (case reuse,
//! the informed searches and the warehouse's own troubleshooter beat the random walk), the
//! population and mission suites, `serve` with the warehouse's own arm, and every other
//! command of the tool over the warehouse catalog.

use serde_json::Value;
use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};
use trustcbr::testing::SuiteRun;

fn warehouse() -> Command {
    Command::new(env!("CARGO_BIN_EXE_warehouse"))
}

/// Runs `command`, asserts that it succeeded (showing its stderr if not), returns stdout.
fn succeed(command: &mut Command) -> String {
    let output = command.output().unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8(output.stdout).unwrap()
}

/// Runs `command`, asserts that it failed, returns stderr.
fn fail(command: &mut Command) -> String {
    let output = command.output().unwrap();
    assert!(!output.status.success());
    String::from_utf8(output.stderr).unwrap()
}

/// Runs `warehouse serve --domain picking ARGS CASES`, sends `requests` (one JSON line
/// each) and returns its replies once it has answered them all and exited.
fn serve(args: &[&str], cases: &Path, requests: &[&str]) -> Vec<Value> {
    let mut server = warehouse()
        .args(["serve", "--domain", "picking"])
        .args(args)
        .arg(cases)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut input = requests.join("\n");
    input.push('\n');
    server
        .stdin
        .take()
        .unwrap()
        .write_all(input.as_bytes())
        .unwrap();
    let output = server.wait_with_output().unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8(output.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

fn json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The arms that must need fewer behaviors than the paper's random walk: case reuse, and
/// the informed searches (the warehouse's troubleshooter among them) with and without it.
const BETTER_THAN_THE_WALK: [&str; 7] = [
    "case-based",
    "cause-aware",
    "model-based",
    "case-based+cause-aware",
    "case-based+model-based",
    "troubleshooter",
    "case-based+troubleshooter",
];

#[test]
fn reproduce_case_reuse_and_informed_search_beat_the_random_walk() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("report");
    let stdout = succeed(warehouse().arg("reproduce").arg("--out").arg(&out));
    assert!(
        stdout.contains("| picking | care-focused | 200 |"),
        "{stdout}"
    );
    let summary = json(&out.join("summary.json"));
    assert_eq!(summary["provenance"]["tool"], "warehouse");
    let experiments = summary["experiments"].as_array().unwrap();
    assert_eq!(experiments.len(), 4);
    for experiment in experiments {
        let name = experiment["name"].as_str().unwrap();
        assert_eq!(experiment["arms"][0], "random-walk", "{name}");
        let walk = experiment["strategies"]["random-walk"]["mean"]
            .as_f64()
            .unwrap();
        for arm in BETTER_THAN_THE_WALK {
            let s = &experiment["strategies"][arm];
            let mean = s["mean"].as_f64().unwrap();
            let p = s["t_test_p_vs_first"].as_f64().unwrap();
            assert!(
                mean < walk && p < 0.01,
                "{name}: {arm} needs {mean} behaviors against the walk's {walk}, p = {p}"
            );
            assert_eq!(s["truncated"], 0, "{name}: {arm}");
        }
    }
}

/// A small suite with an operator of the user's own, from a file next to it.
const SUITE: &str = r#"(
    seed: 5,
    trials: 6,
    arms: ["random-walk", "case-based", "cause-aware"],
    experiments: [
        (scenario: "picking", operator: "night-shift", operator_files: ["night-shift.ron"]),
        (scenario: "picking", operator: "random", operator_files: ["night-shift.ron"]),
    ],
)"#;

const NIGHT_SHIFT: &str = r#"(
    name: "night-shift",
    t_complete: 60.0,
    p_deadline: 0.5,
    p_collision: 0.5,
    p_crushed: 0.5,
    weights: (by_cause: {"dropped-item": 1.0, "too-slow": 0.5}),
)"#;

#[test]
fn run_config_and_operator_files_with_results_independent_of_threads() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("suite.ron");
    std::fs::write(&config, SUITE).unwrap();
    std::fs::write(dir.path().join("night-shift.ron"), NIGHT_SHIFT).unwrap();
    let trials = |threads: &str| {
        let out = dir.path().join(format!("report-{threads}"));
        let stdout = succeed(
            warehouse()
                .arg("run")
                .arg(&config)
                .args(["--threads", threads, "--out"])
                .arg(&out),
        );
        assert!(stdout.contains("| picking | night-shift | 6 |"), "{stdout}");
        std::fs::read_to_string(out.join("trials.jsonl")).unwrap()
    };
    let one = trials("1");
    assert_eq!(one, trials("2"));
    let first: Value = serde_json::from_str(one.lines().next().unwrap()).unwrap();
    let last = first["final"].as_object().unwrap();
    let mut names: Vec<&str> = last.keys().map(String::as_str).collect();
    names.sort();
    assert_eq!(names, ["grip_force", "gripper", "map", "speed"]);

    // `config` prints the embedded suite, which `run` accepts as it is.
    let printed = succeed(warehouse().arg("config"));
    assert!(
        printed.contains("operator: \"throughput-focused\""),
        "{printed}"
    );

    // A scenario the catalog does not know is refused with the known ones listed.
    let wrong = dir.path().join("wrong.ron");
    std::fs::write(&wrong, SUITE.replace("\"picking\"", "\"movement\"")).unwrap();
    let err = fail(warehouse().arg("run").arg(&wrong));
    assert!(
        err.contains("unknown scenario `movement` (known: picking)"),
        "{err}"
    );
}

#[test]
fn landscape_sweep_serve_and_render() {
    let dir = tempfile::tempdir().unwrap();
    // Landscape over the two categorical components.
    let out = dir.path().join("landscape");
    succeed(
        warehouse()
            .args([
                "landscape",
                "--scenario",
                "picking",
                "--operator",
                "balanced",
            ])
            .args(["--runs", "4", "--components", "gripper,map", "--out"])
            .arg(&out),
    );
    let csv = std::fs::read_to_string(out.join("landscape.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 1_800);
    assert!(
        csv.lines()
            .nth(1)
            .unwrap()
            .starts_with("suction,as-built,0.25,5,4,"),
        "{csv}"
    );
    assert!(
        std::fs::read_to_string(out.join("landscape.svg"))
            .unwrap()
            .contains("<svg")
    );

    // A sweep over two seeds and two values of lambda, on the embedded suite.
    let sweep = dir.path().join("sweep.ron");
    std::fs::write(
        &sweep,
        r#"(suite: embedded, trials: Some(3), arms: Some(["random-walk", "case-based"]),
            seeds: [1, 2], parameters: [lambda([0.9, 0.95])])"#,
    )
    .unwrap();
    let out = dir.path().join("sweep");
    let stdout = succeed(warehouse().arg("sweep").arg(&sweep).arg("--out").arg(&out));
    assert!(stdout.contains("2 cells x 2 seeds"), "{stdout}");
    assert!(
        std::fs::read_to_string(out.join("report/sweep.md"))
            .unwrap()
            .contains("| lambda=0.9 |")
    );

    // Serve the picking scenario over stdin/stdout: begin, then one interruption.
    let replies = serve(
        &["--cases"],
        &dir.path().join("cases.sqlite"),
        &[
            r#"{"id": 1, "request": "begin"}"#,
            r#"{"id": 2, "outcome": "interrupted", "weight": 1.0, "stated": "collision", "duration_s": 12.0}"#,
        ],
    );
    assert_eq!(replies.len(), 2, "{replies:?}");
    assert_eq!(replies[0]["ok"], "begun", "{replies:?}");
    let behavior = replies[0]["behavior"].as_object().expect("a behavior");
    assert_eq!(behavior.len(), 4, "{behavior:?}");
    assert!(behavior["gripper"].is_string(), "{behavior:?}");
    assert_eq!(replies[1]["id"], 2);
    assert_eq!(replies[1]["trust"], -1.0, "{replies:?}");

    // The warehouse draws no pictures.
    let err = fail(warehouse().args([
        "render",
        "--scenario",
        "picking",
        "--behavior",
        "gripper=suction,map=live,speed=1,grip_force=50",
    ]));
    assert!(
        err.contains("warehouse draws no pictures of picking runs"),
        "{err}"
    );
}

/// `serve --help` of a plug-in's tool sums up the protocol and points at a text its user
/// can reach (the rustdoc of `service`, which a plug-in's build has), not at a file of
/// trustcbr's source tree alone.
#[test]
fn serve_help_sums_up_the_protocol_and_says_where_it_is_in_full() {
    let help = succeed(warehouse().args(["serve", "--help"]));
    for told in [
        r#"{"request": "begin"}"#,
        r#""ok" is "keep", "switch""#,
        "the page `service::protocol` of the rustdoc of the `service` crate",
        "`cargo doc -p service --open`",
    ] {
        assert!(help.contains(told), "{told} missing from:\n{help}");
    }
    // The short help keeps to the options.
    let short = succeed(warehouse().args(["serve", "-h"]));
    assert!(!short.contains("service::protocol"), "{short}");
}

/// `simulate` is the plug-in's too: the picking scenario's commands, one JSON line each,
/// the same for the same seed.
#[test]
fn simulate_prints_picking_commands() {
    let simulate = || {
        succeed(warehouse().args([
            "simulate",
            "--scenario",
            "picking",
            "--operator",
            "balanced",
            "--behavior",
            "gripper=suction,map=live,speed=1,grip_force=50",
            "--count",
            "20",
            "--seed",
            "2",
        ]))
    };
    let stdout = simulate();
    assert_eq!(stdout, simulate());
    let commands: Vec<Value> = stdout
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(commands.len(), 20);
    for c in &commands {
        assert_eq!(c["truth"].is_null(), c["outcome"] == "completed", "{c}");
    }
}

/// A shipped suite file of the crate, its counts made small by `replacements`.
fn small_suite(name: &str, replacements: &[(&str, &str)]) -> String {
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("experiments")
        .join(name);
    let mut text = std::fs::read_to_string(shipped).unwrap();
    for (from, to) in replacements {
        assert!(text.contains(from), "{name} has no `{from}`");
        text = text.replace(from, to);
    }
    text
}

/// `suite` run by the warehouse binary through the tool kit (`trustcbr::testing`).
fn run_suite(suite: &str) -> SuiteRun {
    trustcbr::testing::run_suite(env!("CARGO_BIN_EXE_warehouse"), suite, &[], &[])
}

#[test]
fn the_population_suite_draws_operators_who_disagree_from_the_family() {
    let suite = small_suite(
        "population.ron",
        &[
            // No landscapes nor limits: what is checked here is who judges the trials.
            (
                "trials: 200,",
                "trials: 4, landscape_runs: 0, limit: (runs: 0),",
            ),
            ("size: 8", "size: 2"),
        ],
    );
    let summary = run_suite(&suite).summary;
    let names: Vec<&str> = summary["experiments"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "picking/conflict-0",
            "picking/conflict-0.5",
            "picking/conflict-1",
            "picking/conflict-1-explained"
        ]
    );
    // Operators who explain put the robot's account of a rejection right far more often
    // than silent ones, whose deadlines and collisions it can only infer.
    let right = |k: usize| {
        summary["experiments"][k]["strategies"]["random-walk"]["explanations"]["first_reason_right"]
            .as_f64()
            .unwrap()
    };
    assert!(
        right(3) > right(2) + 0.3,
        "{} against {}",
        right(3),
        right(2)
    );
}

#[test]
fn the_mission_suite_runs_among_operators_who_change_unannounced() {
    let suite = small_suite(
        "missions.ron",
        &[
            ("count: 100", "count: 3"),
            ("commands: 400", "commands: 120"),
        ],
    );
    let run = run_suite(&suite);
    let records: Vec<Value> = run
        .read("missions.jsonl")
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    // Two attentive plans and one complacent plan (run ignoring and answering alerts),
    // four arms each, three missions of each.
    assert_eq!(records.len(), (2 + 2) * 4 * 3);
    let troubleshot = records
        .iter()
        .filter(|r| r["arm"] == "case-based+troubleshooter")
        .count();
    assert_eq!(troubleshot, 4 * 3);
    let changes: usize = records
        .iter()
        .map(|r| r["record"]["changes"].as_array().unwrap().len())
        .sum();
    assert!(changes > 0, "operators change during missions");
    let markdown = run.read("missions.md");
    assert!(
        markdown.contains("## picking/conflict-1/complacent"),
        "{markdown}"
    );
}

#[test]
fn serve_answers_with_the_warehouses_own_troubleshooter() {
    let dir = tempfile::tempdir().unwrap();
    // Five interruptions with a protective stop perceived bring the estimate to -5: the
    // troubleshooter reads stops and proposes the same behavior, only slower.
    let stopped = r#"{"outcome": "interrupted", "weight": 1.0, "duration_s": 20.0, "observed": ["safety-stop"]}"#;
    let mut requests = vec![
        r#"{"request": "begin", "behavior": "gripper=suction,map=as-built,speed=2,grip_force=50"}"#,
    ];
    requests.extend([stopped; 5]);
    let replies = serve(
        &["--arm", "troubleshooter", "--cases"],
        &dir.path().join("cases.sqlite"),
        &requests,
    );
    assert_eq!(replies.len(), 6, "{replies:?}");
    let switch = &replies[5];
    assert_eq!(switch["ok"], "switch", "{switch}");
    let next = &switch["explanation"]["next"];
    assert_eq!(next["strategy"], "troubleshooter", "{switch}");
    assert_eq!(next["rationale"]["kind"], "expects", "{switch}");
    let behavior = switch["behavior"].as_object().unwrap();
    assert_eq!(behavior["gripper"], "suction");
    assert_eq!(behavior["map"], "as-built");
    assert_eq!(behavior["grip_force"], 50.0);
    assert!(behavior["speed"].as_f64().unwrap() < 2.0, "{switch}");
    // The robot attributes the stops to what they hint at: collisions.
    let reasons = &switch["explanation"]["given_up"]["reasons"];
    assert_eq!(reasons[0]["cause"], "collision", "{switch}");
}
