//! End-to-end tests of `trustcbr run`, `reproduce` and `config` on small configs.

use crate::support;

use std::path::Path;
use support::{outside_view, succeed, svg_texts, trustcbr};

const SMALL: &str = r#"(
    seed: 7,
    trials: 4,
    landscape_runs: 20,
    experiments: [
        (scenario: "movement", operator: "balanced"),
        (scenario: "patrol", operator: "random"),
    ],
)"#;

fn run(config: &Path, out: &Path, threads: &str) -> String {
    succeed(
        trustcbr()
            .args([
                "run",
                config.to_str().unwrap(),
                "--threads",
                threads,
                "--out",
            ])
            .arg(out),
    )
}

#[test]
fn run_writes_a_complete_report() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("small.ron");
    std::fs::write(&config, SMALL).unwrap();
    let out = dir.path().join("report");
    let stdout = run(&config, &out, "2");
    assert!(stdout.contains("| movement | balanced | 4 |"), "{stdout}");
    assert!(stdout.contains("| patrol | random | 4 |"), "{stdout}");

    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert!(summary["elapsed_s"].as_f64().unwrap() > 0.0);
    assert_eq!(summary["recommended"], trustcbr::lab::RECOMMENDED_ARM);
    let experiments = summary["experiments"].as_array().unwrap();
    assert_eq!(experiments.len(), 2);
    assert_eq!(experiments[1]["scenario"], "patrol");
    assert_eq!(experiments[1]["operator"], "random");
    assert_eq!(experiments[1]["trials"], 4);
    for arm in lab::builtin_arm_names() {
        let s = &experiments[0]["strategies"][arm];
        assert!(s["mean"].as_f64().unwrap() >= 1.0, "{arm}");
        assert!(s["ci95"].as_f64().unwrap() >= 0.0);
        assert!(s["commands_mean"].as_f64().unwrap() >= 5.0);
        assert!(s["untrustworthy_mean"].as_f64().unwrap() >= 0.0);
        assert!((0.0..=1.0).contains(&s["found_share"].as_f64().unwrap()));
        assert!(s["cases_acquired"].is_u64());
        assert_eq!(s["started_from_cases"], 0);
    }
    let p = experiments[0]["p_value"].as_f64().unwrap();
    assert!((0.0..=1.0).contains(&p));
    // p-values against the reference arm (case-based by default), beside those against the
    // first.
    assert_eq!(experiments[0]["reference"], "case-based");
    let strategies = &experiments[0]["strategies"];
    assert!(strategies["case-based"]["t_test_p_vs_reference"].is_null());
    assert!(strategies["random-walk"]["t_test_p_vs_reference"].is_f64());
    assert!(strategies["random-walk"]["t_test_p_vs_first"].is_null());
    assert!(summary["provenance"]["version"].is_string());
    assert_eq!(summary["provenance"]["command_line"][1], "run");

    let trials = std::fs::read_to_string(out.join("trials.jsonl")).unwrap();
    let arms = lab::builtin_arm_names();
    assert_eq!(trials.lines().count(), 2 * arms.len() * 4);
    for line in trials.lines() {
        let t: serde_json::Value = serde_json::from_str(line).unwrap();
        let scenario = t["scenario"].as_str().unwrap();
        assert_eq!(
            t["experiment"].as_str().unwrap().split('/').next(),
            Some(scenario)
        );
        assert!(arms.contains(&t["arm"].as_str().unwrap()));
        assert!(t["behaviors_evaluated"].as_u64().unwrap() >= 1);
        assert!(t["commands"].as_u64().unwrap() >= t["untrustworthy"].as_u64().unwrap());
        assert!(t["found_trustworthy"].is_boolean());
        let components = if scenario == "movement" { 2 } else { 4 };
        assert_eq!(t["final"].as_object().unwrap().len(), components);
        assert!(t["final"]["speed"].is_f64());
        // In the random experiment the drawn operator is named, never "random".
        assert_ne!(t["operator"], "random");
    }
    // The config used is written back and runs again.
    let used = std::fs::read_to_string(out.join("config.ron")).unwrap();
    assert!(used.contains("trials: 4"));
    for plot in [
        "curves-movement-balanced.svg",
        "finals-movement-balanced.svg",
        "curves-patrol-random.svg",
        "finals-patrol-random.svg",
    ] {
        let svg = std::fs::read_to_string(out.join(plot)).unwrap();
        assert!(svg.starts_with("<svg"), "{plot}");
        assert_eq!(outside_view(&svg), Vec::<String>::new(), "{plot}");
        if plot.starts_with("finals") {
            // Over the operator's landscape: its colour bar and the outline's key.
            let texts = svg_texts(&svg);
            assert!(texts.contains(&"P(complete)"), "{plot}");
            assert!(texts.iter().any(|t| t.starts_with("outlined:")), "{plot}");
        }
    }
    assert!(out.join("table.md").is_file());
}

#[test]
fn one_and_two_threads_give_identical_trials() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("small.ron");
    std::fs::write(&config, SMALL).unwrap();
    run(&config, &dir.path().join("one"), "1");
    run(&config, &dir.path().join("two"), "2");
    for file in [
        "trials.jsonl",
        "finals-movement-balanced.svg",
        "finals-patrol-random.svg",
    ] {
        let one = std::fs::read(dir.path().join("one").join(file)).unwrap();
        let two = std::fs::read(dir.path().join("two").join(file)).unwrap();
        assert!(!one.is_empty());
        assert!(one == two, "{file} differs between 1 and 2 threads");
    }
}

#[test]
fn config_prints_the_embedded_paper_config_and_it_runs() {
    let text = succeed(trustcbr().arg("config"));
    assert!(text.contains("trials: 500"));
    assert_eq!(text.matches("(scenario:").count(), 7);
    // The printed config is a valid input for `run` (with fewer trials).
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("paper.ron");
    let fewer = text.replace("trials: 500", "trials: 1,\n    landscape_runs: 10");
    std::fs::write(&config, fewer).unwrap();
    let stdout = run(&config, &dir.path().join("out"), "2");
    let trials_column: Vec<&str> = stdout
        .lines()
        .filter(|l| l.starts_with("| movement |") || l.starts_with("| patrol |"))
        .map(|l| l.split('|').nth(3).unwrap().trim())
        .collect();
    assert_eq!(trials_column, ["1"; 7], "{stdout}");
}

#[test]
fn a_bad_config_names_file_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("bad.ron");
    std::fs::write(&config, "(seed: 1,\n trials: -3, experiments: [])").unwrap();
    let output = trustcbr()
        .args(["run", config.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains(&format!("{}:2:", config.display())),
        "{stderr}"
    );
}

#[test]
fn reproduce_accepts_overrides() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("results");
    let output = trustcbr()
        .args(["reproduce", "--trials", "1", "--seed", "3"])
        .args(["--landscape-runs", "10", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(output.status.success());
    // stderr is not a terminal here: plain progress lines, the last when the trials end
    // (7 experiments x 9 arms x 1 trial), each within 100 columns.
    let stderr = String::from_utf8(output.stderr).unwrap();
    let last = stderr.lines().last().unwrap_or_default();
    assert!(
        last.starts_with("progress: 63/63 trials done in ")
            && last.ends_with("; finishing the report's landscapes and limits"),
        "{stderr}"
    );
    assert!(
        stderr
            .lines()
            .all(|l| l.starts_with("progress: ") && l.len() <= 100),
        "{stderr}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["experiments"].as_array().unwrap().len(), 7);
    let used = std::fs::read_to_string(out.join("config.ron")).unwrap();
    assert!(used.contains("seed: 3") && used.contains("landscape_runs: 10"));
}

#[test]
fn arms_are_chosen_by_name_and_unknown_names_are_listed() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("small.ron");
    std::fs::write(&config, SMALL).unwrap();
    let out = dir.path().join("two-arms");
    succeed(
        trustcbr()
            .args([
                "run",
                config.to_str().unwrap(),
                "--arms",
                "uniform,cause-aware",
                "--out",
            ])
            .arg(&out),
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(
        summary["experiments"][0]["arms"],
        serde_json::json!(["uniform", "cause-aware"])
    );
    let refused_out = dir.path().join("refused");
    let output = trustcbr()
        .args([
            "run",
            config.to_str().unwrap(),
            "--arms",
            "uniform,annealing",
            "--out",
        ])
        .arg(&refused_out)
        .output()
        .unwrap();
    assert!(!output.status.success());
    assert!(!refused_out.exists(), "a refused run leaves no folder");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("annealing") && stderr.contains("known: random-walk, case-based"),
        "{stderr}"
    );
    // A config lists its arms too.
    std::fs::write(
        &config,
        SMALL.replace("trials: 4,", "trials: 2, arms: [\"case-based\"],"),
    )
    .unwrap();
    let stdout = run(&config, &dir.path().join("one-arm"), "2");
    assert!(
        stdout.contains("| Scenario | Operator | Trials | case-based |"),
        "{stdout}"
    );
}

#[test]
fn saved_case_bases_seed_the_next_run() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("small.ron");
    std::fs::write(&config, SMALL).unwrap();
    let saved = dir.path().join("cases");
    let arms = ["--arms", "random-walk,case-based,case-based+cause-aware"];
    succeed(
        trustcbr()
            .args(["run", config.to_str().unwrap()])
            .args(arms)
            .arg("--out")
            .arg(dir.path().join("first"))
            .arg("--save-cases")
            .arg(&saved),
    );
    let file = saved.join("movement-balanced").join("case-based.ron");
    let text = std::fs::read_to_string(&file).unwrap();
    let stored = text.matches("solution:").count();
    assert!(stored > 0, "{text}");
    // Both reusing arms of both experiments are saved; the random walk reads no cases.
    assert!(
        saved
            .join("patrol-random")
            .join("case-based+cause-aware.ron")
            .is_file()
    );
    assert!(
        !saved
            .join("movement-balanced")
            .join("random-walk.ron")
            .exists()
    );
    let out = dir.path().join("second");
    succeed(
        trustcbr()
            .args(["run", config.to_str().unwrap()])
            .args(arms)
            .arg("--out")
            .arg(&out)
            .arg("--cases")
            .arg(&saved),
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let strategies = &summary["experiments"][0]["strategies"];
    assert_eq!(strategies["case-based"]["started_from_cases"], stored);
    assert_eq!(strategies["random-walk"]["started_from_cases"], 0);
    // A case base of another space is refused, naming the space it records.
    std::fs::copy(saved.join("patrol-random").join("case-based.ron"), &file).unwrap();
    let output = trustcbr()
        .args(["run", config.to_str().unwrap()])
        .args(arms)
        .arg("--out")
        .arg(dir.path().join("third"))
        .arg("--cases")
        .arg(&saved)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        !output.status.success()
            && stderr.contains("learned in another behavior space (domain `patrol`)"),
        "{stderr}"
    );
}

#[test]
fn a_report_reruns_by_itself_with_its_operator_files() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("ops")).unwrap();
    std::fs::write(
        dir.path().join("ops").join("hasty.ron"),
        "(name: \"hasty\", t_complete: 10.0, p_deadline: 0.9, p_collision: 0.1)",
    )
    .unwrap();
    let config = dir.path().join("custom.ron");
    std::fs::write(
        &config,
        "(seed: 3, trials: 2, landscape_runs: 10, arms: [\"uniform\"], experiments: [(scenario: \"movement\", operator: \"hasty\", operator_files: [\"ops/hasty.ron\"])])",
    )
    .unwrap();
    let first = dir.path().join("first");
    run(&config, &first, "2");
    assert!(first.join("operators").join("hasty.ron").is_file());
    // Rerun from the report alone, somewhere else.
    let moved = dir.path().join("elsewhere");
    std::fs::rename(&first, &moved).unwrap();
    std::fs::remove_dir_all(dir.path().join("ops")).unwrap();
    let second = dir.path().join("second");
    run(&moved.join("config.ron"), &second, "2");
    assert_eq!(
        std::fs::read(moved.join("trials.jsonl")).unwrap(),
        std::fs::read(second.join("trials.jsonl")).unwrap()
    );
}

#[test]
fn the_printed_tables_fit_a_terminal() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("results");
    let stdout = succeed(
        trustcbr()
            .args([
                "reproduce",
                "--trials",
                "2",
                "--landscape-runs",
                "0",
                "--out",
            ])
            .arg(&out),
    );
    // The last line names the report folder, whose path is the user's.
    for line in stdout
        .lines()
        .filter(|l| !l.contains(out.to_str().unwrap()))
    {
        assert!(
            line.chars().count() <= 100,
            "{} columns: {line}",
            line.chars().count()
        );
    }
    assert!(
        stdout.contains("patrol/random: fewest behaviors"),
        "{stdout}"
    );
    assert!(
        std::fs::read_to_string(out.join("table.md"))
            .unwrap()
            .contains("| Wilcoxon p vs reference |")
    );
}

#[test]
fn populations_are_measured_and_every_arm_is_shown_against_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    let rung =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("domains/operators/ladder/movement/rung-4");
    let config = dir.path().join("ladder.ron");
    std::fs::write(
        &config,
        format!(
            r#"(
    seed: 3,
    trials: 6,
    landscape_runs: 0,
    limit: (runs: 20, budget: 40000, candidates: 8, candidate_runs: 100),
    arms: ["uniform", "conditioned"],
    experiments: [
        (scenario: "movement", operator: "random", population: Some((name: "disjoint")),
         operator_files: ["{}", "{}"],
         feedback: Some((explains: 0.3, wrong: 0.1))),
        (scenario: "movement", operator: "random",
         population: Some((name: "agreeing", family: Some((conflict: 0.0, size: 3, seed: 1))))),
    ],
)"#,
            rung.join("dispatcher.ron").display(),
            rung.join("supervisor.ron").display()
        ),
    )
    .unwrap();
    let out = dir.path().join("report");
    let stdout = run(&config, &out, "2");
    assert!(stdout.contains("| movement | disjoint | 6 |"), "{stdout}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let experiments = summary["experiments"].as_array().unwrap();
    let (disjoint, agreeing) = (&experiments[0], &experiments[1]);
    assert_eq!(disjoint["name"], "movement/disjoint");
    assert_eq!(agreeing["name"], "movement/agreeing");
    // Two operators whose trustworthy regions do not meet: a lower bound, no behavior
    // pleases both.
    let limit = &disjoint["limit"];
    assert_eq!(limit["operators"], 2);
    assert_eq!(limit["lower_bound"], true);
    assert_eq!(limit["population"]["trusted_by_all"], 0);
    assert_eq!(limit["population"]["one_behavior_pleases_all"], false);
    assert_eq!(limit["population"]["pairwise_jaccard"][0], 0.0);
    let paper = limit["paper_protocol"]["behaviors"].as_f64().unwrap();
    assert!((1.0..3.0).contains(&paper), "{paper}");
    assert_eq!(
        limit["free_first_choice"]["untrustworthy"]
            .as_f64()
            .unwrap(),
        0.0
    );
    // Three operators of one preference agree, up to landscape noise.
    let population = &agreeing["limit"]["population"];
    assert_eq!(population["one_behavior_pleases_all"], true);
    for j in population["pairwise_jaccard"].as_array().unwrap() {
        assert!(j.as_f64().unwrap() > 0.75, "{population}");
    }
    // Every arm carries its ratio to the limit; the tables show them.
    let ratio = &disjoint["strategies"]["uniform"]["ratio_to_limit"]["behaviors"];
    let mean = disjoint["strategies"]["uniform"]["mean"].as_f64().unwrap();
    assert!((ratio.as_f64().unwrap() - mean / paper).abs() < 1e-9);
    let table = std::fs::read_to_string(out.join("table.md")).unwrap();
    assert!(table.contains("| movement/disjoint | known-operator limit (lower bound: mean of 2 operators), random first behavior |"), "{table}");
    assert!(table.contains("| movement/disjoint | 2 |"), "{table}");
    for stem in ["summary", "summary-commands", "summary-untrustworthy"] {
        assert!(out.join(format!("{stem}.svg")).is_file(), "{stem}");
    }
    // A population drawn per trial needs `operator: "random"`.
    let bad = dir.path().join("bad.ron");
    std::fs::write(
        &bad,
        r#"(seed: 1, trials: 2, experiments: [(scenario: "movement", operator: "balanced",
            population: Some((name: "p", family: Some((conflict: 0.5, size: 2, seed: 1)))))])"#,
    )
    .unwrap();
    let output = trustcbr()
        .args(["run", bad.to_str().unwrap(), "--out"])
        .arg(dir.path().join("bad-report"))
        .output()
        .unwrap();
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("experiments[0].population: a population's members are drawn per trial: `operator` must be `random`"),
        "{stderr}"
    );
}

#[test]
fn explain_tells_a_trial_exactly_as_the_run_ran_it() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("small.ron");
    std::fs::write(&config, SMALL).unwrap();
    let out = dir.path().join("report");
    run(&config, &out, "2");
    // Every arm's explanations are measured against the truth in summary.json.
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    for arm in lab::builtin_arm_names() {
        let x = &summary["experiments"][1]["strategies"][arm]["explanations"];
        let given_up = x["given_up"].as_u64().unwrap();
        assert_eq!(
            x["perceivable"]["given_up"].as_u64().unwrap()
                + x["other"]["given_up"].as_u64().unwrap(),
            given_up
        );
        if given_up > 0 {
            assert!((0.0..=1.0).contains(&x["first_reason_right"].as_f64().unwrap()));
        }
    }
    // A case-based trial of the patrol experiment that gave a behavior up.
    let trials = std::fs::read_to_string(out.join("trials.jsonl")).unwrap();
    let trial: serde_json::Value = trials
        .lines()
        .map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap())
        .find(|t| {
            t["experiment"] == "patrol/random"
                && t["arm"] == "case-based"
                && !t["given_up"].as_array().unwrap().is_empty()
        })
        .expect("a case-based patrol trial with a switch");
    let records = trial["given_up"].as_array().unwrap();
    let given_up = records.len();
    for record in records {
        assert!(record["right"].is_boolean(), "{record}");
        assert!(record["reason"].is_string() || record["reason"].is_null());
    }
    let number = trial["trial"].as_u64().unwrap().to_string();
    let story = succeed(trustcbr().arg("explain").arg(&out).args([
        "--experiment",
        "patrol/random",
        "--arm",
        "case-based",
        "--trial",
        &number,
    ]));
    let commands = trial["commands"].as_u64().unwrap();
    assert!(
        story.starts_with(&format!(
            "patrol/random, arm case-based, trial {number} (operator {}): {commands} commands, {} untrustworthy, {} behaviors; thresholds +5 / -5",
            trial["operator"].as_str().unwrap(),
            trial["untrustworthy"],
            trial["behaviors_evaluated"],
        )),
        "{story}"
    );
    // One row per command, numbered in order, and one explanation per switch and end.
    let rows = story
        .lines()
        .filter(|l| {
            l.split_whitespace()
                .next()
                .is_some_and(|w| w.parse::<u64>().is_ok())
        })
        .count() as u64;
    assert_eq!(rows, commands, "{story}");
    let explained = story.lines().filter(|l| l.starts_with("  -> ")).count();
    let ended = usize::from(trial["found_trustworthy"].as_bool().unwrap());
    assert_eq!(explained, given_up + ended, "{story}");
    assert_eq!(
        story.lines().filter(|l| l.contains("-> Gave up")).count(),
        given_up
    );
    // Refusals name what exists.
    let refused = |args: &[&str]| {
        let output = trustcbr()
            .arg("explain")
            .arg(&out)
            .args(args)
            .output()
            .unwrap();
        assert!(!output.status.success());
        String::from_utf8(output.stderr).unwrap()
    };
    let err = refused(&[
        "--experiment",
        "patrol/x",
        "--arm",
        "case-based",
        "--trial",
        "0",
    ]);
    assert!(
        err.contains(
            "no experiment is named `patrol/x` (the config's: movement/balanced, patrol/random)"
        ),
        "{err}"
    );
    let err = refused(&[
        "--experiment",
        "patrol/random",
        "--arm",
        "x",
        "--trial",
        "0",
    ]);
    assert!(
        err.contains("has no arm `x` (its arms: random-walk, case-based"),
        "{err}"
    );
    let err = refused(&[
        "--experiment",
        "patrol/random",
        "--arm",
        "uniform",
        "--trial",
        "4",
    ]);
    assert!(
        err.contains("experiment `patrol/random` ran trials 0 to 3, not 4"),
        "{err}"
    );
    let output = trustcbr()
        .arg("explain")
        .arg(dir.path())
        .args(["--experiment", "a", "--arm", "b", "--trial", "0"])
        .output()
        .unwrap();
    let err = String::from_utf8(output.stderr).unwrap();
    assert!(
        err.contains("not a report folder (it has no config.ron)"),
        "{err}"
    );
    // The report draws a sample trial per experiment, with its explanations as captions.
    for stem in ["movement-balanced", "patrol-random"] {
        let svg = std::fs::read_to_string(out.join(format!("timeline-{stem}.svg"))).unwrap();
        assert_eq!(outside_view(&svg), Vec::<String>::new(), "{stem}");
        assert!(
            svg_texts(&svg)
                .iter()
                .any(|t| t.starts_with("trustworthy threshold"))
        );
    }
    let page = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(page.contains("<h2 id=\"explanations\">Explanations against the truth</h2>"));
    assert!(page.contains("<figcaption>The trust estimate of the behavior in use"));
}

/// A movement operator file of the plug-in guide's kind.
const NIGHT: &str = "(name: \"night\", t_complete: 20.0, p_deadline: 0.5, p_collision: 0.5)";

#[test]
fn an_experiment_written_as_the_plugin_guide_writes_it_runs_its_file_s_operator() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("night.ron"), NIGHT).unwrap();
    // docs/plugin-guide.md: `experiments: [(scenario: ..., operator_files: [...])]`.
    let suite = |operator: &str| {
        format!(
            "(seed: 3, trials: 3, landscape_runs: 0, arms: [\"uniform\", \"case-based\"], experiments: [(scenario: \"movement\", {operator}operator_files: [\"night.ron\"])])"
        )
    };
    let (guide, named) = (dir.path().join("guide.ron"), dir.path().join("named.ron"));
    std::fs::write(&guide, suite("")).unwrap();
    std::fs::write(&named, suite("operator: \"night\", ")).unwrap();
    let (from_guide, from_named) = (dir.path().join("guide"), dir.path().join("named"));
    let stdout = run(&guide, &from_guide, "2");
    assert!(stdout.contains("| movement | night |"), "{stdout}");
    run(&named, &from_named, "2");
    // The file's operator judged every trial, exactly as when named.
    let trials = std::fs::read_to_string(from_guide.join("trials.jsonl")).unwrap();
    assert_eq!(
        trials,
        std::fs::read_to_string(from_named.join("trials.jsonl")).unwrap()
    );
    assert!(
        trials.lines().all(|t| t.contains("\"operator\":\"night\"")),
        "{trials}"
    );
    // The echoed config names it, and reruns to the same trials.
    let echoed = std::fs::read_to_string(from_guide.join("config.ron")).unwrap();
    assert!(echoed.contains("operator: \"night\""), "{echoed}");
    let rerun = dir.path().join("rerun");
    run(&from_guide.join("config.ron"), &rerun, "1");
    assert_eq!(
        trials,
        std::fs::read_to_string(rerun.join("trials.jsonl")).unwrap()
    );
}

#[test]
fn an_experiment_with_neither_operator_nor_files_is_told_what_to_write() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("suite.ron");
    std::fs::write(
        &config,
        "(seed: 3, trials: 3,\n experiments: [(scenario: \"movement\")])",
    )
    .unwrap();
    let stderr = support::refused(trustcbr().arg("run").arg(&config));
    assert_eq!(
        stderr,
        format!(
            "error: {}: experiments[0].operator: is left out, and the experiment has no `operator_files` or `population` to choose it by: write `operator: \"NAME\"` with NAME one of movement's built-in operators (speed-focused, safety-focused, balanced), `operator: \"random\"` to draw one of them per trial, or `operator_files: [\"FILE.ron\"]` to run an operator of your own on every trial\n",
            config.display()
        )
    );
}
