//! The UGV domains keep the simulation contract: the lab's conformance kit
//! (`lab::testing::check_domain`) on movement and patrol, with the paper's operators and
//! the conflict ladder's (whose newer preferences judge through the same hooks).

use domains::{OperatorModel, Scenario, UgvDomain, builtin_operators};
use std::path::Path;

/// The paper's operators of `scenario` and those of its ladder's last rung.
fn operators(scenario: Scenario) -> Vec<(String, OperatorModel)> {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("operators/ladder")
        .join(scenario.as_str())
        .join("rung-4");
    let ladder = std::fs::read_dir(&folder)
        .unwrap_or_else(|e| panic!("{}: {e}", folder.display()))
        .map(|entry| entry.unwrap().path())
        .map(|path| OperatorModel::load(&path, scenario.causes()).unwrap());
    builtin_operators(scenario)
        .into_iter()
        .chain(ladder)
        .map(|op| (op.name.clone(), op))
        .collect()
}

#[test]
fn movement_keeps_the_contract() {
    lab::testing::check_domain(
        &UgvDomain::new(Scenario::Movement),
        &operators(Scenario::Movement),
    );
}

#[test]
fn patrol_keeps_the_contract() {
    lab::testing::check_domain(
        &UgvDomain::new(Scenario::Patrol),
        &operators(Scenario::Patrol),
    );
}
