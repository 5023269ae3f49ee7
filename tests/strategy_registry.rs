//! The built-in arms are read from the strategies' registry (`trust::search::strategies`)
//! wherever they are listed: the arms, their descriptions, and the table of
//! docs/search-strategies.md.

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
        let described = lab::experiment::arm::describe(arm.name).unwrap();
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
