//! `trustcbr run` on mission suites, as a real process: the report's files, a rerun into
//! the same folder, a rerun from the report alone (its config and copied operator files)
//! somewhere else, and bad suites refused with the file and the field.

use std::path::Path;
use std::process::{Command, Output};

const SUITE: &str = r#"(
    seed: 5,
    arms: ["case-based", "uniform"],
    missions: [
        (
            name: "movement/paper",
            operators: (scenario: "movement", operator: "random"),
            count: 3,
            commands: 120,
            changes: (every: 40.0, takeover: 0.5),
        ),
        (
            name: "patrol/paper/complacent",
            operators: (scenario: "patrol", operator: "random"),
            count: 2,
            commands: 120,
            changes: (every: 60.0, takeover: 0.5),
            complacency: Some((memory: 20.0, floor: 0.3)),
        ),
    ],
)
"#;

fn trustcbr(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_trustcbr"))
        .args(args)
        .output()
        .unwrap()
}

fn succeeded(output: &Output) {
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
}

fn run(config: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "run",
        config.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    trustcbr(&args)
}

#[test]
fn a_mission_suite_writes_its_report_and_reruns_into_the_same_folder() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("missions.ron");
    std::fs::write(&config, SUITE).unwrap();
    let out = dir.path().join("report");
    let ran = run(&config, &out, &["--threads", "2"]);
    assert!(
        ran.status.success(),
        "{}",
        String::from_utf8_lossy(&ran.stderr)
    );
    let stdout = String::from_utf8(ran.stdout).unwrap();
    assert!(stdout.contains("## movement/paper") && stdout.contains("## patrol/paper/complacent"));
    let mut files: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    assert_eq!(
        files,
        [
            "config.ron",
            "mission-movement-paper.svg",
            "mission-patrol-paper-complacent.svg",
            "missions.jsonl",
            "missions.md",
            "provenance.json",
            "summary.json"
        ]
    );
    // What wrote it, as an experiment report's summary records it.
    let provenance: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("provenance.json")).unwrap())
            .unwrap();
    assert_eq!(provenance["tool"], "trustcbr");
    assert_eq!(provenance["version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(provenance["command_line"][1], "run");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary[0]["plan"], "movement/paper");
    assert_eq!(summary[0]["recommended"], trustcbr::lab::RECOMMENDED_ARM);
    assert_eq!(summary[1]["arms"].as_array().unwrap().len(), 4);
    assert_eq!(
        std::fs::read_to_string(out.join("missions.jsonl"))
            .unwrap()
            .lines()
            .count(),
        2 * 3 + 4 * 2
    );
    let md = std::fs::read_to_string(out.join("missions.md")).unwrap();
    assert!(md.contains("case-based, alerts answered"));
    // The same seed, again into the same folder: the same report.
    let again = run(&config, &out, &["--threads", "1"]);
    assert!(
        again.status.success(),
        "{}",
        String::from_utf8_lossy(&again.stderr)
    );
    assert_eq!(
        std::fs::read_to_string(out.join("missions.md")).unwrap(),
        md
    );
}

#[test]
fn a_mission_suite_that_lists_no_arms_runs_the_recommended_one() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("missions.ron");
    let suite = crate::support::one_mission_suite(r#"(scenario: "movement", operator: "random")"#)
        .replace("    arms: [\"uniform\"],\n", "");
    assert!(!suite.contains("arms"));
    std::fs::write(&config, suite).unwrap();
    let out = dir.path().join("report");
    succeeded(&run(&config, &out, &[]));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let arms: Vec<&str> = summary[0]["arms"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a["arm"].as_str().unwrap())
        .collect();
    assert_eq!(arms, [trustcbr::lab::RECOMMENDED_ARM]);
}

#[test]
fn bad_mission_suites_are_refused_with_the_file_and_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("bad.ron");
    std::fs::write(
        &config,
        SUITE.replace(
            "takeover: 0.5),\n        ),\n        (",
            "takeover: 1.5),\n        ),\n        (",
        ),
    )
    .unwrap();
    let out = dir.path().join("report");
    let refused = run(&config, &out, &[]);
    assert!(!refused.status.success());
    let stderr = String::from_utf8(refused.stderr).unwrap();
    assert!(
        stderr
            .contains("bad.ron: missions[0].changes: changes.takeover: a share in [0, 1], got 1.5"),
        "{stderr}"
    );
    assert!(!out.exists(), "a refused suite creates no folder");
    std::fs::write(&config, SUITE.replace("count: 3", "count: \"three\"")).unwrap();
    let stderr = String::from_utf8(run(&config, &out, &[]).stderr).unwrap();
    assert!(
        stderr.contains("bad.ron:8:20: Expected integer"),
        "{stderr}"
    );
    std::fs::write(&config, SUITE).unwrap();
    let stderr = String::from_utf8(run(&config, &out, &["--trials", "5"]).stderr).unwrap();
    assert!(
        stderr.contains("--trials applies to experiment suites"),
        "{stderr}"
    );
}

#[test]
fn a_mission_report_reruns_by_itself_from_another_folder() {
    let dir = tempfile::tempdir().unwrap();
    // Two operator files of the same file name, in folders of their own.
    for (shift, t_complete) in [("day", 12.0), ("night", 20.0)] {
        let folder = dir.path().join("ops").join(shift);
        std::fs::create_dir_all(&folder).unwrap();
        std::fs::write(
            folder.join("shift.ron"),
            format!(
                "(name: \"{shift}-shift\", t_complete: {t_complete:.1}, p_deadline: 0.8, p_collision: 0.2)"
            ),
        )
        .unwrap();
    }
    let operators = r#"operators: (scenario: "movement", operator: "random",
                population: Some((name: "shifts")), builtin_operators: ["balanced"],
                operator_files: ["ops/day/shift.ron", "ops/night/shift.ron"]),"#;
    let suite = format!(
        r#"(
    seed: 11,
    arms: ["case-based", "uniform"],
    missions: [
        (name: "movement/shifts", {operators} count: 2, commands: 100,
         changes: (every: 30.0, takeover: 0.5)),
        (name: "movement/shifts/complacent", {operators} count: 2, commands: 100,
         changes: (every: 30.0, takeover: 0.5), complacency: Some((memory: 20.0, floor: 0.3))),
    ],
)"#
    );
    let config = dir.path().join("missions.ron");
    std::fs::write(&config, suite).unwrap();
    let first = dir.path().join("first");
    succeeded(&run(&config, &first, &[]));
    let copied = |name: &str| first.join("operators").join(name);
    assert!(copied("shift.ron").is_file() && copied("shift-2.ron").is_file());
    assert_eq!(
        std::fs::read_to_string(copied("shift-2.ron")).unwrap(),
        std::fs::read_to_string(dir.path().join("ops/night/shift.ron")).unwrap()
    );
    let written = std::fs::read_to_string(first.join("config.ron")).unwrap();
    assert!(
        written.contains("\"operators/shift.ron\"") && !written.contains("ops/"),
        "{written}"
    );
    // The report alone, moved away from the suite and its operator files (removed), run
    // from yet another working directory.
    let moved = dir.path().join("elsewhere").join("report");
    std::fs::create_dir(dir.path().join("elsewhere")).unwrap();
    std::fs::rename(&first, &moved).unwrap();
    std::fs::remove_dir_all(dir.path().join("ops")).unwrap();
    let cwd = dir.path().join("cwd");
    std::fs::create_dir(&cwd).unwrap();
    let second = dir.path().join("second");
    let again = Command::new(env!("CARGO_BIN_EXE_trustcbr"))
        .current_dir(&cwd)
        .args(["run", moved.join("config.ron").to_str().unwrap(), "--out"])
        .arg(&second)
        .output()
        .unwrap();
    succeeded(&again);
    for file in [
        "missions.jsonl",
        "summary.json",
        "missions.md",
        "config.ron",
    ] {
        assert_eq!(
            std::fs::read(moved.join(file)).unwrap(),
            std::fs::read(second.join(file)).unwrap(),
            "{file}"
        );
    }
}

/// The missions' lines of `missions.jsonl` for `arm`.
fn arm_lines(report: &Path, arm: &str) -> Vec<serde_json::Value> {
    std::fs::read_to_string(report.join("missions.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap())
        .filter(|v| v["arm"] == arm)
        .collect()
}

/// Runs `suite` without its competence standard, written to `config`, into `out`; returns
/// the refusal's stderr (nothing is written).
fn refused_without_standard(config: &Path, suite: &str, out: &Path) -> String {
    std::fs::write(
        config,
        suite.replace("            competence: Some((at_most: 0.1)),\n", ""),
    )
    .unwrap();
    let refused = run(config, out, &[]);
    assert!(!refused.status.success());
    assert!(!out.exists());
    String::from_utf8(refused.stderr).unwrap()
}

#[test]
fn an_arm_preferring_competent_behaviors_runs_on_a_plan_with_a_standard_and_is_refused_elsewhere() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("competent.ron");
    let suite = r#"(
    seed: 5,
    arms: ["uniform", "uniform+competent"],
    missions: [
        (
            name: "patrol/paper",
            operators: (scenario: "patrol", operator: "random"),
            count: 4,
            commands: 150,
            changes: (every: 60.0, takeover: 0.5),
            competence: Some((at_most: 0.1)),
        ),
    ],
)
"#;
    std::fs::write(&config, suite).unwrap();
    let out = dir.path().join("report");
    succeeded(&run(&config, &out, &[]));
    let (plain, preferring) = (
        arm_lines(&out, "uniform"),
        arm_lines(&out, "uniform+competent"),
    );
    assert_eq!((plain.len(), preferring.len()), (4, 4));
    // The same missions (operators and changes drawn for every arm alike) ...
    let changes = |lines: &[serde_json::Value]| -> Vec<serde_json::Value> {
        lines
            .iter()
            .map(|l| l["record"]["changes"].clone())
            .collect()
    };
    let at = |lines: &[serde_json::Value]| -> Vec<Vec<u64>> {
        changes(lines)
            .iter()
            .map(|c| {
                c.as_array()
                    .unwrap()
                    .iter()
                    .map(|c| c["at"].as_u64().unwrap())
                    .collect()
            })
            .collect()
    };
    assert_eq!(at(&plain), at(&preferring));
    // ... met differently: passing over trusted behaviors changes what is watched.
    let watched = |lines: &[serde_json::Value]| -> Vec<serde_json::Value> {
        lines
            .iter()
            .map(|l| l["record"]["calibration"].clone())
            .collect()
    };
    assert_ne!(watched(&plain), watched(&preferring));

    // Without a standard the plan judges nothing: refused, naming the field.
    let stderr = refused_without_standard(&config, suite, &dir.path().join("none"));
    assert!(
        stderr.contains("competent.ron: missions[0].competence: the arm `uniform+competent` prefers behaviors the robot judges competent, and this plan judges nothing"),
        "{stderr}"
    );
    // An experiment suite settles on the first trusted behavior: refused.
    let experiments = dir.path().join("experiments.ron");
    let embedded = String::from_utf8(trustcbr(&["config"]).stdout).unwrap();
    let arms_at = embedded.find("arms: [").unwrap();
    let arms_end = arms_at + embedded[arms_at..].find(']').unwrap() + 1;
    let with_arm = format!(
        "{}arms: [\"case-based\", \"case-based+competent\"]{}",
        &embedded[..arms_at],
        &embedded[arms_end..]
    );
    std::fs::write(&experiments, with_arm).unwrap();
    let stderr = String::from_utf8(run(&experiments, &dir.path().join("e"), &[]).stderr).unwrap();
    assert!(
        stderr.contains("arms[1]: `case-based+competent` prefers behaviors the robot judges competent, which only a mission plan with a competence standard judges"),
        "{stderr}"
    );
    // Twice is refused as learned-start twice is.
    let stderr = String::from_utf8(
        trustcbr(&[
            "serve",
            "--domain",
            "patrol",
            "--cases",
            dir.path().join("c.db").to_str().unwrap(),
            "--arm",
            "uniform+competent+competent",
        ])
        .stderr,
    )
    .unwrap();
    assert!(stderr.contains("says +competent twice"), "{stderr}");
}

#[test]
fn an_answered_alert_may_offer_a_safer_behavior_the_operator_takes_when_it_trusts_it() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("offer.ron");
    let suite = r#"(
    seed: 5,
    arms: ["uniform"],
    missions: [
        (
            name: "movement/paper/complacent",
            operators: (scenario: "movement", operator: "random"),
            count: 30,
            commands: 300,
            changes: (every: 150.0, takeover: 0.5),
            complacency: Some((memory: 20.0, floor: 0.3)),
            competence: Some((at_most: 0.1, offer_safer: true)),
        ),
    ],
)
"#;
    std::fs::write(&config, suite).unwrap();
    let out = dir.path().join("report");
    succeeded(&run(&config, &out, &[]));
    let lines = arm_lines(&out, "uniform");
    let count = |answered: bool, field: &str| -> u64 {
        lines
            .iter()
            .filter(|l| l["answers_alerts"] == answered)
            .map(|l| l["record"]["calibration"][field].as_u64().unwrap_or(0))
            .sum()
    };
    // Offers are made only where alerts are answered, and some are taken.
    assert_eq!((count(false, "offered"), count(false, "taken")), (0, 0));
    let (offered, taken) = (count(true, "offered"), count(true, "taken"));
    assert!(
        offered > 0 && taken > 0 && taken <= offered,
        "{offered} {taken}"
    );
    let report = std::fs::read_to_string(out.join("missions.md")).unwrap();
    assert!(
        report.contains(&format!(
            "uniform, alerts answered: {offered} answered alerts offered a safer behavior; the operator took {taken}"
        )),
        "{report}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let text = summary.to_string();
    assert!(text.contains(&format!(
        "\"offers\":{{\"offered\":{offered},\"taken\":{taken}}}"
    )));
    // Offers need alerts to offer them: an offer is part of the competence section, and
    // a plan cannot write one outside it.
    std::fs::write(
        &config,
        suite.replace(
            "competence: Some((at_most: 0.1, offer_safer: true)),",
            "offer_safer: true,",
        ),
    )
    .unwrap();
    let none = dir.path().join("none");
    let refused = run(&config, &none, &[]);
    assert!(!refused.status.success() && !none.exists());
    let stderr = String::from_utf8(refused.stderr).unwrap();
    assert!(
        stderr.contains("offer.ron:12:") && stderr.contains("offer_safer"),
        "{stderr}"
    );
}

/// A mission suite whose robot's context switches: movement's paper operators in contexts
/// (the shipped files, by absolute path), one arm beside its blind twin.
fn context_suite(arms: &str, switches: &str) -> String {
    let operators =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("domains/operators/contexts/movement");
    let file = |name: &str| format!("{:?}", operators.join(name).to_str().unwrap());
    format!(
        r#"(
    seed: 3,
    arms: [{arms}],
    missions: [
        (
            name: "movement/paper",
            operators: (
                scenario: "movement",
                operator: "random",
                population: Some((name: "paper")),
                operator_files: [{}, {}],
            ),
            count: 4,
            commands: 150,
            changes: (every: 100.0, takeover: 0.5),
            {switches}
        ),
    ],
)
"#,
        file("speed-focused.ron"),
        file("safety-focused.ron"),
    )
}

#[test]
fn a_mission_suite_may_switch_the_robot_s_context_and_pairs_each_arm_with_its_blind_twin() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("contexts.ron");
    let switches = r#"context_switches: Some((among: [{}, {"cargo": "hazardous"}], every: 30.0)),"#;
    let arms = r#""case-based+learned-start", "case-based+context-blind+learned-start""#;
    std::fs::write(&config, context_suite(arms, switches)).unwrap();
    let out = dir.path().join("report");
    succeeded(&run(&config, &out, &["--threads", "2"]));
    let md = std::fs::read_to_string(out.join("missions.md")).unwrap();
    assert!(
        md.contains("Announced context switches")
            && md.contains("| case-based+learned-start | case-based+context-blind+learned-start |"),
        "{md}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let switched = &summary[0]["context_switches"];
    assert_eq!(
        switched["versus_blind"][0]["arm"],
        "case-based+learned-start"
    );
    assert!(switched["oracle"]["all"]["switches"].as_u64().unwrap() > 0);
    // Every mission record gives its switches, and the context it started in when not
    // the default.
    let told = arm_lines(&out, "case-based+learned-start");
    assert_eq!(told.len(), 4);
    assert!(told.iter().any(|line| {
        line["record"]["changes"]
            .as_array()
            .unwrap()
            .iter()
            .any(|c| c["kind"] == "context")
    }));
    // The report reruns by itself: its config names the copied operator files.
    let rerun = dir.path().join("rerun");
    succeeded(&run(&out.join("config.ron"), &rerun, &[]));
    assert_eq!(
        std::fs::read_to_string(rerun.join("missions.md")).unwrap(),
        md
    );
}

#[test]
fn bad_context_switches_are_refused_with_the_file_and_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("bad.ron");
    let out = dir.path().join("report");
    let refused = |text: String| {
        std::fs::write(&config, text).unwrap();
        let ran = run(&config, &out, &[]);
        assert!(!ran.status.success());
        assert!(!out.exists(), "a refused suite creates no folder");
        String::from_utf8(ran.stderr).unwrap()
    };
    let stderr = refused(context_suite(
        r#""case-based""#,
        r#"context_switches: Some((among: [{}, {"cargo": "radioactive"}], every: 30.0)),"#,
    ));
    assert!(
        stderr.contains("bad.ron: missions[0].context_switches.among[1]: context variable `cargo` may be normal, hazardous, not `radioactive`"),
        "{stderr}"
    );
    let stderr = refused(context_suite(
        r#""case-based""#,
        r#"context_switches: Some((among: [{}], every: 30.0)),"#,
    ));
    assert!(
        stderr.contains(
            "missions[0].context_switches: context_switches.among: at least two contexts"
        ),
        "{stderr}"
    );
}
