//! The built-in arms are read from the strategies' registry (`trust::search::strategies`)
//! wherever they are listed: the arms and their descriptions, the command line's refusal
//! of an unknown arm (the binary as a process), a report's page, and the table of
//! docs/search-strategies.md (the Python package's `strategies()` and `builtin_arms()` are
//! tested in python/tests/test_arms.py). A strategy registered by one more line reaches
//! each of them.

use trustcbr::lab;
use trustcbr::trust::search::strategies;

#[test]
fn each_strategy_gives_its_arm_and_its_case_based_arm_in_registry_order() {
    let mut expected = Vec::new();
    for strategy in strategies() {
        expected.push(strategy.name);
        expected.extend(strategy.with_cases.map(|with| with.name));
    }
    assert_eq!(lab::builtin_arm_names(), expected);
    for arm in lab::builtin_arms() {
        let described = lab::experiment::arm::describe(&arm.name.parse().unwrap()).unwrap();
        assert_eq!(described, arm.description, "{}", arm.name);
        let built = lab::Arm::builtin(arm.name, trustcbr::trust::RetrieverKind::Linear).unwrap();
        assert_eq!(built.reuses_cases(), arm.reuses_cases, "{}", arm.name);
    }
}

#[test]
fn the_docs_table_of_arms_is_the_registry_s() {
    let page = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/search-strategies.md"),
    )
    .unwrap();
    let table = page
        .split("| arm | search | reuses cases |\n| --- | --- | --- |\n")
        .nth(1)
        .expect("the table of arms");
    let listed: Vec<&str> = table
        .lines()
        .take_while(|line| line.starts_with('|'))
        .map(|line| line.split('|').nth(1).unwrap().trim().trim_matches('`'))
        .collect();
    assert_eq!(listed, lab::builtin_arm_names());
}

#[test]
fn the_command_line_names_every_registered_arm_when_it_refuses_one() {
    let dir = tempfile::tempdir().unwrap();
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_trustcbr"))
        .args(["reproduce", "--arms", "annealing", "--out"])
        .arg(dir.path().join("out"))
        .output()
        .unwrap();
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    let known = format!("known: {}", lab::builtin_arm_names().join(", "));
    assert!(stderr.contains(&known), "{stderr}");
}

#[test]
fn a_report_page_describes_each_arm_as_the_registry_does() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("small.ron");
    let arms: Vec<String> = lab::builtin_arm_names()
        .iter()
        .map(|name| format!("\"{name}\""))
        .collect();
    std::fs::write(
        &config,
        format!(
            "(seed: 1, trials: 2, arms: [{}], experiments: [(scenario: \"movement\", operator: \"balanced\")])",
            arms.join(", ")
        ),
    )
    .unwrap();
    let out = dir.path().join("out");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_trustcbr"))
        .arg("run")
        .arg(&config)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    let page = std::fs::read_to_string(out.join("report.html")).unwrap();
    for arm in lab::builtin_arms() {
        let described = arm.description.replace('&', "&amp;");
        assert!(
            page.contains(&described),
            "{}: {}",
            arm.name,
            arm.description
        );
    }
}
