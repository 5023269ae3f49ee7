//! End to end: `examples/controller.py` (Python standard library only) drives
//! `trustcbr serve` like a robot controller, twice on the same case file, and through a
//! mission (`serve --mission`).

use std::path::Path;
use std::process::Command;

fn python3_available() -> bool {
    Command::new("python3")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

fn run_controller(cases: &Path, seed: u32) -> String {
    controller(cases, &["--episodes", "20", "--seed", &seed.to_string()])
}

/// Runs the example against the binary under test with the case file `cases` and `args`;
/// returns its stdout.
fn controller(cases: &Path, args: &[&str]) -> String {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/controller.py");
    let output = Command::new("python3")
        .arg(script)
        .args(["--server", env!("CARGO_BIN_EXE_trustcbr"), "--cases"])
        .arg(cases)
        .args(args)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "the controller failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    stdout
}

/// The number after `key` in `text`.
fn number_after(text: &str, key: &str) -> usize {
    let rest = &text[text
        .find(key)
        .unwrap_or_else(|| panic!("no `{key}` in\n{text}"))
        + key.len()..];
    rest.split(|c: char| !c.is_ascii_digit())
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

#[test]
fn the_example_controller_drives_the_server() {
    if !python3_available() {
        eprintln!("SKIPPED: python3 is not installed, so examples/controller.py cannot run");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let cases = dir.path().join("cases.db");
    let first = run_controller(&cases, 1);
    assert!(
        first.contains("domain movement: 0 cases at start"),
        "{first}"
    );
    assert!(first.contains("episodes: 20, trustworthy: 20"), "{first}");
    // Every switch is explained to the operator in a sentence.
    assert!(
        first
            .lines()
            .any(|l| l.starts_with("  Gave up speed=") && l.contains(". Now speed=")),
        "{first}"
    );
    let learned = number_after(&first, ", cases: ");
    assert!(learned > 0, "{first}");
    assert_eq!(
        service::exchange::info(&service::Location::Sqlite(cases.clone()))
            .unwrap()
            .cases,
        learned
    );
    // A second mission starts from the case base the first one left.
    let second = run_controller(&cases, 2);
    assert!(
        second.contains(&format!("domain movement: {learned} cases at start")),
        "{second}"
    );
    assert!(number_after(&second, ", cases: ") >= learned);
}

#[test]
fn the_example_controller_runs_a_mission_through_changes_and_an_alert() {
    if !python3_available() {
        eprintln!("SKIPPED: python3 is not installed, so examples/controller.py cannot run");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    // Seed 2: the first behavior settles slow, an operator in a hurry takes over, and later
    // the route gets crowded while the operator looks away.
    let out = controller(&dir.path().join("cases.db"), &["--mission", "--seed", "2"]);
    // Outcomes after `settled` are answered: the world's changes are noticed and followed.
    assert!(out.contains("(the robot is not told)"), "{out}");
    assert!(
        out.lines()
            .any(|l| l.starts_with("command ") && l.ends_with(" fell, re-adapting")),
        "{out}"
    );
    assert!(number_after(&out, "re-adapted ") >= 1, "{out}");
    // The complacent operator lets bumps pass: the robot asks for supervision.
    assert!(
        out.contains("the robot asks the operator to supervise\n  Please supervise speed="),
        "{out}"
    );
    assert!(number_after(&out, "after settling, ") >= 1, "alerts: {out}");
}

/// The interpreter itself (not a shim that needs `PATH`), so `PATH` can be emptied.
fn python3_executable() -> String {
    let output = Command::new("python3")
        .args(["-c", "import sys; print(sys.executable)"])
        .output()
        .unwrap();
    String::from_utf8(output.stdout).unwrap().trim().to_owned()
}

#[test]
fn the_example_controller_finds_the_server_without_path_or_says_what_to_pass() {
    if !python3_available() {
        eprintln!("SKIPPED: python3 is not installed, so examples/controller.py cannot run");
        return;
    }
    let python = python3_executable();
    let dir = tempfile::tempdir().unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/controller.py");
    // In the repository, the build under `target/` is found.
    let output = Command::new(&python)
        .arg(&script)
        .arg("--cases")
        .arg(dir.path().join("cases.db"))
        .args(["--episodes", "1"])
        .env("PATH", "/nonexistent")
        .env_remove("TRUSTCBR")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(stdout.contains("episodes: 1, trustworthy: 1"), "{stdout}");
    // Away from the repository, the controller says what to pass.
    let alone = dir.path().join("controller.py");
    std::fs::copy(&script, &alone).unwrap();
    let output = Command::new(&python)
        .arg(&alone)
        .env("PATH", "/nonexistent")
        .env_remove("TRUSTCBR")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("--server PATH") && stderr.contains("cargo install --path ."),
        "{stderr}"
    );
}
