//! End-to-end: `population` writes an instance of the prior over operators as operator
//! files that the tool's own loader reads back to exactly the drawn members, that the
//! tool's other commands take, and refuses to mix two populations in one folder.

use crate::support;

use domains::{Scenario, UgvDomain, prior};
use lab::Instance;
use std::path::Path;
use support::{succeed, trustcbr};
use trustcbr::{Catalog, Readings, UgvCatalog};

/// The `.ron` files in `dir`, sorted.
fn ron_files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".ron"))
        .collect();
    names.sort();
    names
}

/// Writes `instance` of `scenario` into `out` and checks every file against the prior's
/// own members, loaded back with the loader `--operator FILE` uses.
fn writes_the_members(scenario: Scenario, instance: &str, screened: bool, out: &Path) {
    let mut command = trustcbr();
    command
        .args(["population", "--scenario", scenario.as_str()])
        .args(["--instance", instance, "--out"])
        .arg(out);
    if !screened {
        command.arg("--unscreened");
    }
    let stdout = succeed(&mut command);
    let instance: Instance = instance.parse().unwrap();
    let members = prior::population(&UgvDomain::new(scenario), &instance, screened).unwrap();
    assert!(stdout.contains(&format!(
        "{} members of instance {instance} (seed {})",
        members.len(),
        instance.seed()
    )));
    let mut expected: Vec<String> = members
        .iter()
        .map(|m| format!("{}.ron", m.operator.name))
        .collect();
    expected.sort();
    assert_eq!(ron_files(out), expected);
    for member in &members {
        let path = out.join(format!("{}.ron", member.operator.name));
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.starts_with(&format!(
            "// Operator `{}`, one of the {} members of instance {instance} (seed {}) of the\n// operator prior `{}`, {scenario}",
            member.operator.name,
            members.len(),
            instance.seed(),
            prior::PRIOR,
        )), "{text}");
        let (name, loaded) = UgvCatalog
            .load_operator(scenario.as_str(), &path, &Readings::new())
            .unwrap();
        assert_eq!(name, member.operator.name);
        assert_eq!(loaded, member.operator);
    }
}

#[test]
fn a_movement_instance_is_written_as_loadable_operator_files_and_rewritten_alike() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("dev-2");
    writes_the_members(Scenario::Movement, "dev-2", true, &out);
    let before: Vec<Vec<u8>> = ron_files(&out)
        .iter()
        .map(|f| std::fs::read(out.join(f)).unwrap())
        .collect();
    // The same command again: the same files, byte for byte.
    writes_the_members(Scenario::Movement, "dev-2", true, &out);
    let after: Vec<Vec<u8>> = ron_files(&out)
        .iter()
        .map(|f| std::fs::read(out.join(f)).unwrap())
        .collect();
    assert_eq!(before, after);
    // A written member is an operator the other commands take.
    let first = out.join(&ron_files(&out)[0]);
    let landscape = dir.path().join("landscape");
    succeed(
        trustcbr()
            .args(["landscape", "--scenario", "movement", "--runs", "2"])
            .arg("--operator")
            .arg(&first)
            .arg("--out")
            .arg(&landscape),
    );
    assert!(landscape.join("landscape.csv").is_file());
}

#[test]
fn a_patrol_evaluation_instance_unscreened_is_the_first_draws() {
    let dir = tempfile::tempdir().unwrap();
    writes_the_members(Scenario::Patrol, "eval-3", false, dir.path());
    let text = std::fs::read_to_string(dir.path().join("eval-3-0.ron")).unwrap();
    assert!(text.contains("(seed 1000000003)"), "{text}");
    assert!(
        text.contains("Unscreened: its stream's first draw"),
        "{text}"
    );
}

#[test]
fn another_instance_is_not_written_over_a_population() {
    let dir = tempfile::tempdir().unwrap();
    writes_the_members(Scenario::Movement, "dev-5", false, dir.path());
    let output = trustcbr()
        .args([
            "population",
            "--scenario",
            "movement",
            "--instance",
            "dev-6",
        ])
        .args(["--unscreened", "--out"])
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("the folder holds `dev-5-0.ron`, which is not a member of dev-6"),
        "{stderr}"
    );
    assert!(!dir.path().join("dev-6-0.ron").exists());
}

#[test]
fn bad_instances_and_scenarios_are_refused_with_what_is_allowed() {
    let dir = tempfile::tempdir().unwrap();
    let refused = |args: &[&str]| {
        let output = trustcbr()
            .arg("population")
            .args(args)
            .arg("--out")
            .arg(dir.path())
            .output()
            .unwrap();
        assert!(!output.status.success(), "{args:?}");
        String::from_utf8_lossy(&output.stderr).into_owned()
    };
    let err = refused(&["--scenario", "movement", "--instance", "test-3"]);
    assert!(
        err.contains("`test-3` is not an instance name: `dev-K` or `eval-K`"),
        "{err}"
    );
    let err = refused(&["--scenario", "movement", "--instance", "eval-1000000"]);
    assert!(
        err.contains("instance `eval-1000000` does not exist"),
        "{err}"
    );
    let err = refused(&["--scenario", "drive", "--instance", "dev-1"]);
    assert!(
        err.contains("unknown scenario `drive` (known: movement, patrol)"),
        "{err}"
    );
    assert!(ron_files(dir.path()).is_empty());
}
