//! A population of the catalog's built-in operators, named in a suite config
//! (`builtin_operators`) beside operator files: its members and their order, the names
//! refused (unknown, twice, with a family, without a population, a file's name taken), and a suite held in a
//! string, as a catalog embeds one, run through the binary with only its members judging.

use crate::support;

use std::collections::BTreeSet;
use std::path::Path;
use support::{succeed, trustcbr};
use trustcbr::UgvCatalog;
use trustcbr::catalog::resolve_readings;
use trustcbr::suite::SuiteConfig;

/// A movement experiment whose population is `members` (the fields after `population`).
fn suite(members: &str) -> String {
    format!(
        "(seed: 4, trials: 6, landscape_runs: 0, limit: (runs: 0), arms: [\"uniform\"], experiments: [(scenario: \"movement\", operator: \"random\", population: Some((name: \"pair\")), {members})])"
    )
}

fn refused(config: &str) -> String {
    SuiteConfig::from_ron(&UgvCatalog, config, Path::new("pair.ron"))
        .unwrap_err()
        .to_string()
}

#[test]
fn a_population_holds_the_built_in_operators_it_names_then_its_files() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("hasty.ron"),
        "(name: \"hasty\", t_complete: 10.0, p_deadline: 0.9, p_collision: 0.1)",
    )
    .unwrap();
    let origin = dir.path().join("pair.ron");
    let config = SuiteConfig::from_ron(
        &UgvCatalog,
        &suite(
            "builtin_operators: [\"safety-focused\", \"speed-focused\"], operator_files: [\"hasty.ron\"]",
        ),
        &origin,
    )
    .unwrap();
    let spec = &config.experiments[0];
    assert_eq!(spec.name(), "movement/pair");
    let readings = resolve_readings(&UgvCatalog, &config.readings).unwrap();
    let members = spec.operators(&UgvCatalog, &origin, &readings).unwrap();
    let names: Vec<&str> = members.iter().map(|(name, _)| name.as_str()).collect();
    // The order named, not the catalog's (speed-focused, safety-focused, balanced); the
    // file last; `balanced`, not named, is no member.
    assert_eq!(names, ["safety-focused", "speed-focused", "hasty"]);
    let builtins = trustcbr::Catalog::operators(&UgvCatalog, "movement", &readings);
    assert_eq!(members[0], builtins[1]);
    assert_eq!(members[1], builtins[0]);
    assert_eq!(members[2].1.t_complete, 10.0);
    // The field reads back as written.
    let back = SuiteConfig::from_ron(&UgvCatalog, &config.to_ron(), &origin).unwrap();
    assert_eq!(back, config);
}

#[test]
fn names_a_population_cannot_hold_are_refused_with_the_known_ones() {
    assert_eq!(
        refused(&suite(
            "builtin_operators: [\"speed-focused\", \"careful\"]"
        )),
        "pair.ron: experiments[0].builtin_operators[1]: unknown operator `careful` for movement (known: speed-focused, safety-focused, balanced)"
    );
    assert_eq!(
        refused(&suite(
            "builtin_operators: [\"balanced\", \"speed-focused\", \"balanced\"]"
        )),
        "pair.ron: experiments[0].builtin_operators[2]: `balanced` is named twice"
    );
    let drawn = suite("builtin_operators: [\"balanced\"]").replace(
        "(name: \"pair\")",
        "(name: \"pair\", family: Some((conflict: 0.5, size: 3, seed: 1)))",
    );
    assert_eq!(
        refused(&drawn),
        "pair.ron: experiments[0].population: a population is drawn from the family or listed in `builtin_operators`, not both"
    );
    let no_population = suite("builtin_operators: [\"balanced\"]")
        .replace("population: Some((name: \"pair\")), ", "");
    assert_eq!(
        refused(&no_population),
        "pair.ron: experiments[0].builtin_operators: built-in operators are named as a population's members: add `population: Some((name: ...))`, or leave them out (without a population every built-in operator of movement takes part)"
    );
    assert_eq!(
        refused(&suite("feedback: None")),
        "pair.ron: experiments[0].population: a population needs its members: `builtin_operators`, `operator_files` or a `family`"
    );
}

#[test]
fn a_file_whose_operator_name_is_taken_is_named_with_what_holds_it() {
    let dir = tempfile::tempdir().unwrap();
    let operator = |name: &str| {
        format!("(name: \"{name}\", t_complete: 10.0, p_deadline: 0.9, p_collision: 0.1)")
    };
    for (file, name) in [
        ("hasty.ron", "hasty"),
        ("also-hasty.ron", "hasty"),
        ("balanced.ron", "balanced"),
        ("random.ron", "random"),
    ] {
        std::fs::write(dir.path().join(file), operator(name)).unwrap();
    }
    let origin = dir.path().join("pair.ron");
    let refused = |members: &str| {
        SuiteConfig::from_ron(&UgvCatalog, &suite(members), &origin)
            .unwrap_err()
            .to_string()
    };
    let at = origin.display();
    assert_eq!(
        refused("builtin_operators: [\"balanced\"], operator_files: [\"balanced.ron\"]"),
        format!(
            "{at}: experiments[0].operator_files[0]: operator name `balanced` is taken by a built-in operator"
        )
    );
    assert_eq!(
        refused("operator_files: [\"hasty.ron\", \"balanced.ron\", \"also-hasty.ron\"]"),
        format!(
            "{at}: experiments[0].operator_files[2]: operator name `hasty` is taken by `operator_files[0]`"
        )
    );
    assert_eq!(
        refused("operator_files: [\"random.ron\"]"),
        format!(
            "{at}: experiments[0].operator_files[0]: operator name `random` is reserved: it draws an operator per trial"
        )
    );
}

#[test]
fn a_suite_without_files_runs_a_population_of_built_in_operators() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("pair.ron");
    std::fs::write(
        &config,
        suite("builtin_operators: [\"speed-focused\", \"safety-focused\"]"),
    )
    .unwrap();
    let out = dir.path().join("report");
    succeed(trustcbr().arg("run").arg(&config).arg("--out").arg(&out));
    let trials = std::fs::read_to_string(out.join("trials.jsonl")).unwrap();
    let judges: BTreeSet<String> = trials
        .lines()
        .map(|line| {
            let record: serde_json::Value = serde_json::from_str(line).unwrap();
            record["operator"].as_str().unwrap().to_owned()
        })
        .collect();
    assert_eq!(trials.lines().count(), 6);
    assert!(
        judges.is_subset(&BTreeSet::from([
            "speed-focused".to_owned(),
            "safety-focused".to_owned()
        ])),
        "{judges:?}"
    );
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("movement/pair"), "{summary}");
}
