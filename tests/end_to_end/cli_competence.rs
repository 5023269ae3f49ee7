//! End-to-end: `competence` measures the robot's own competence estimates against the
//! simulator's truth and writes its report; bad settings are refused before anything is
//! written.

use crate::support;

use support::{succeed, trustcbr};

#[test]
fn competence_writes_a_report_of_every_part() {
    let dir = tempfile::tempdir().unwrap();
    let stdout = succeed(
        trustcbr()
            .args(["competence", "--scenario", "patrol"])
            .args(["--operator", "detection-focused", "--behaviors", "12"])
            .args(["--truth-runs", "20", "--seen", "0,5", "--standard", "0.2"])
            .arg("--out")
            .arg(dir.path()),
    );
    assert!(stdout.contains("competence.md") && stdout.contains("competence.json"));
    let md = std::fs::read_to_string(dir.path().join("competence.md")).unwrap();
    assert!(md.contains("| `explosive-missed` | model |"), "{md}");
    assert!(
        md.contains("| `collision` | record (`collision`) |"),
        "{md}"
    );
    assert!(md.contains("Standard: at most 0.2 per command"), "{md}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("competence.json")).unwrap())
            .unwrap();
    assert_eq!(json["parts"].as_array().unwrap().len(), 7);
    assert_eq!(json["per_behavior"].as_array().unwrap().len(), 12);
    // Every behavior is judged at each number of commands, one way or the other.
    for agreement in json["agreement"].as_array().unwrap() {
        let counts = &agreement["counts"];
        let sum: u64 = ["competent", "not_competent", "missed", "false_alarm"]
            .iter()
            .map(|k| counts[k].as_u64().unwrap())
            .sum();
        assert_eq!(sum, 12);
    }
    // The model judges the unseen parts alike after any number of commands.
    let missed = &json["parts"][5]["errors"];
    assert_eq!(missed[0], missed[1]);
}

#[test]
fn competence_refuses_settings_out_of_range_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    for (args, expected) in [
        (vec!["--seen", "5,2"], "`seen` in increasing order"),
        (vec!["--standard", "1.5"], "must be a chance in [0, 1]"),
    ] {
        let output = trustcbr()
            .args([
                "competence",
                "--scenario",
                "movement",
                "--operator",
                "balanced",
            ])
            .args(args)
            .arg("--out")
            .arg(dir.path())
            .output()
            .unwrap();
        assert!(!output.status.success());
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(stderr.contains(expected), "{stderr}");
    }
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}
