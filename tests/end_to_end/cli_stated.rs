//! Stated preferences through the binary: an experiment's operators state what their files
//! say they mind (`stated`), each trial's line of `trials.jsonl` says what was stated, an arm
//! `NAME+ignores-statements` runs on the same trials as `NAME` without hearing it, and an arm
//! ignoring statements where none are stated, shares that are not probabilities, and
//! statements in a mission plan (where nothing would hear them), are refused, leaving
//! nothing behind.

use crate::support;

use support::{one_mission_suite, refused, run_suite, succeed, trustcbr};

fn suite(stated: &str, arms: &str) -> String {
    format!(
        r#"(
    seed: 7,
    trials: 12,
    landscape_runs: 0,
    limit: (runs: 0),
    arms: [{arms}],
    experiments: [(scenario: "movement", operator: "random"{stated})],
)"#
    )
}

#[test]
fn operators_state_their_preferences_and_a_deaf_twin_runs_the_same_trials() {
    let dir = tempfile::tempdir().unwrap();
    let arms = r#""case-based+cause-aware", "case-based+cause-aware+ignores-statements""#;
    let stdout = succeed(&mut run_suite(
        dir.path(),
        &suite(", stated: Some((said: 1.0))", arms),
    ));
    assert!(stdout.contains("movement/random/s1"), "{stdout}");
    let lines = std::fs::read_to_string(dir.path().join("out/trials.jsonl")).unwrap();
    let trials: Vec<serde_json::Value> = lines
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(trials.len(), 24);
    let (heard, deaf) = trials.split_at(12);
    for (h, d) in heard.iter().zip(deaf) {
        // The same trial: operator, first behavior and statements.
        for field in ["trial", "operator", "initial", "stated"] {
            assert_eq!(h[field], d[field], "{field}");
        }
        assert!(h.get("unheard").is_none(), "{h}");
        assert_eq!(d["unheard"], true);
        // The paper's movement operators, by hand from their files.
        let minds = |name: &str| {
            h["stated"]
                .as_array()
                .unwrap()
                .iter()
                .find(|s| s["name"] == name)
                .unwrap()["minds"]
                .as_bool()
                .unwrap()
        };
        let (hurry, bumps) = match h["operator"].as_str().unwrap() {
            "balanced" => (true, true),
            "safety-focused" => (false, true),
            "speed-focused" => (true, false),
            other => panic!("unknown operator {other}"),
        };
        assert_eq!((minds("hurry"), minds("avoid-bumps")), (hurry, bumps));
        assert!(!minds("keep-away-from-people") && !minds("keep-clear"));
    }
}

#[test]
fn ignoring_statements_none_state_and_shares_out_of_range_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let stderr = refused(&mut run_suite(
        dir.path(),
        &suite("", r#""cause-aware", "cause-aware+ignores-statements""#),
    ));
    assert!(
        stderr.contains("arms[1]: `cause-aware+ignores-statements` ignores what operators state up front, and no experiment here has `stated`"),
        "{stderr}"
    );
    // An experiment that cannot run is named first: the arms are weighed against the
    // experiments once those hold.
    let stderr = refused(&mut run_suite(
        dir.path(),
        &suite("", r#""cause-aware", "cause-aware+ignores-statements""#)
            .replace(r#"operator: "random""#, r#"operator: "nobody""#),
    ));
    assert!(
        stderr.contains("experiments[0].operator: unknown operator `nobody`"),
        "{stderr}"
    );
    let stderr = refused(&mut run_suite(
        dir.path(),
        &suite(
            ", stated: Some((said: 1.0, wrong: 1.3))",
            r#""cause-aware""#,
        ),
    ));
    assert!(
        stderr.contains("stated `wrong` must be a probability in [0, 1], got 1.3"),
        "{stderr}"
    );
    assert!(!dir.path().join("out").exists());
}

#[test]
fn a_mission_plan_s_operators_state_nothing_and_saying_they_do_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mission = one_mission_suite(
        r#"(scenario: "movement", operator: "random", stated: Some((said: 1.0, wrong: 0.0)))"#,
    );
    let stderr = refused(&mut run_suite(dir.path(), &mission));
    assert!(
        stderr.contains("`stated`: what operators state up front is simulated in experiment suites, not yet in missions"),
        "{stderr}"
    );
    assert!(!dir.path().join("out").exists());
}

#[test]
fn explain_says_what_the_trial_s_operator_stated() {
    let dir = tempfile::tempdir().unwrap();
    let arms = r#""case-based+cause-aware""#;
    succeed(&mut run_suite(
        dir.path(),
        &suite(", stated: Some((said: 1.0))", arms),
    ));
    let line = std::fs::read_to_string(dir.path().join("out/trials.jsonl")).unwrap();
    let trial: serde_json::Value = serde_json::from_str(line.lines().next().unwrap()).unwrap();
    let said: Vec<String> = trial["stated"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            let name = s["name"].as_str().unwrap();
            if s["minds"] == true {
                name.to_owned()
            } else {
                format!("not {name}")
            }
        })
        .collect();
    assert!(!said.is_empty());
    let story = succeed(
        trustcbr()
            .arg("explain")
            .arg(dir.path().join("out"))
            .args(["--experiment", trial["experiment"].as_str().unwrap()])
            .args(["--arm", "case-based+cause-aware", "--trial", "0"]),
    );
    assert!(
        story.contains(&format!(
            "the operator stated up front: {}",
            said.join(", ")
        )),
        "{story}"
    );
}

#[test]
fn an_arm_deaf_to_statements_whose_search_hears_none_is_its_twin_and_refused() {
    let dir = tempfile::tempdir().unwrap();
    let arms = r#""random-walk", "random-walk+ignores-statements""#;
    let stderr = refused(&mut run_suite(
        dir.path(),
        &suite(", stated: Some((said: 1.0))", arms),
    ));
    assert!(
        stderr.contains("arms[1]: `random-walk+ignores-statements` ignores what operators state up front, but its search (`random-walk`) hears no statement: the arm is its twin that hears"),
        "{stderr}"
    );
    assert!(!dir.path().join("out").exists());
}
