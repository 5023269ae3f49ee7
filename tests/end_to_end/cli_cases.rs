//! `trustcbr cases export | import | info` as processes: a case base learned by `serve`
//! goes to RON and back into another database unchanged; a RON file of another space is
//! refused naming the difference; a RON case file is served read-only and is never an
//! import's target; the case bases `--save-cases` writes are read as they are.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use crate::support;

fn trustcbr(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_trustcbr"))
        .args(args)
        .output()
        .unwrap()
}

fn succeeded(output: Output) -> String {
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8(output.stdout).unwrap()
}

/// Runs `serve` on `cases` for `episodes` episodes that each retain a case; returns its
/// replies.
fn learn(domain: &Path, cases: &Path, episodes: usize) -> Vec<serde_json::Value> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_trustcbr"))
        .args(["serve", "--domain"])
        .arg(domain)
        .arg("--cases")
        .arg(cases)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut input = child.stdin.take().unwrap();
    for _ in 0..episodes {
        writeln!(input, r#"{{"request": "begin"}}"#).unwrap();
        writeln!(
            input,
            r#"{{"outcome": "interrupted", "weight": 1, "duration_s": 3, "stated": "stuck"}}"#
        )
        .unwrap();
        writeln!(
            input,
            r#"{{"outcome": "completed", "weight": 1, "duration_s": 5}}"#
        )
        .unwrap();
    }
    drop(input);
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    succeeded(output)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .chain(std::iter::once(serde_json::Value::String(stderr)))
        .collect()
}

/// The quick domain's file in `dir`, and the two cases two episodes learned in
/// `learned.db` exported to `cases.ron`.
fn learned_and_exported(dir: &Path) -> (PathBuf, PathBuf) {
    let domain = dir.join("quick.ron");
    std::fs::write(&domain, support::quick_domain(false)).unwrap();
    let db = dir.join("learned.db");
    learn(&domain, &db, 2);
    let exported = dir.join("cases.ron");
    succeeded(trustcbr(&[
        "cases",
        "export",
        db.to_str().unwrap(),
        exported.to_str().unwrap(),
    ]));
    (domain, exported)
}

#[test]
fn a_case_base_goes_to_ron_and_back_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    let domain = dir.path().join("quick.ron");
    std::fs::write(&domain, support::quick_domain(false)).unwrap();
    let db = dir.path().join("learned.db");
    learn(&domain, &db, 4);
    let info = succeeded(trustcbr(&["cases", "info", db.to_str().unwrap()]));
    assert!(
        info.contains(&format!("domain:    {}", domain.display())),
        "{info}"
    );
    assert!(
        info.contains("25 behaviors: speed (5 values, weight 1), padding (5 values, weight 1)"),
        "{info}"
    );
    assert!(info.contains("cases:     4 (ids 1 to 4)"), "{info}");

    let exported = dir.path().join("exported.ron");
    let said = succeeded(trustcbr(&[
        "cases",
        "export",
        db.to_str().unwrap(),
        exported.to_str().unwrap(),
    ]));
    assert_eq!(
        said.trim(),
        format!("wrote 4 cases to {}", exported.display())
    );
    let text = std::fs::read_to_string(&exported).unwrap();
    assert!(
        text.contains("space:") && text.contains("\"speed\""),
        "{text}"
    );

    let copy = dir.path().join("copy.db");
    succeeded(trustcbr(&[
        "cases",
        "import",
        exported.to_str().unwrap(),
        copy.to_str().unwrap(),
        "--domain",
        domain.to_str().unwrap(),
    ]));
    let again = dir.path().join("again.ron");
    succeeded(trustcbr(&[
        "cases",
        "export",
        copy.to_str().unwrap(),
        again.to_str().unwrap(),
    ]));
    assert_eq!(std::fs::read_to_string(&again).unwrap(), text);

    // The movement space differs from this file's: refused, and nothing is created.
    let other = dir.path().join("other.db");
    let output = trustcbr(&[
        "cases",
        "import",
        exported.to_str().unwrap(),
        other.to_str().unwrap(),
        "--domain",
        "movement",
    ]);
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("component 0 (speed): min 1 in the case base, 0.5 here"),
        "{stderr}"
    );
    assert!(!other.exists());
}

#[test]
fn a_ron_case_file_is_served_read_only() {
    let dir = tempfile::tempdir().unwrap();
    let (domain, exported) = learned_and_exported(dir.path());
    let before = std::fs::read(&exported).unwrap();
    let replies = learn(&domain, &exported, 2);
    let stderr = replies.last().unwrap().as_str().unwrap();
    assert!(stderr.contains("2 cases loaded"), "{stderr}");
    assert!(
        stderr.contains("served read-only, no case is retained"),
        "{stderr}"
    );
    let settled: Vec<_> = replies.iter().filter(|r| r["ok"] == "settled").collect();
    assert_eq!(settled.len(), 2);
    assert!(
        settled
            .iter()
            .all(|r| r["retained"].is_null() && r["cases"] == 2)
    );
    assert_eq!(std::fs::read(&exported).unwrap(), before);
}

#[test]
fn saved_case_bases_are_read_by_cases_info_and_import() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("small.ron");
    std::fs::write(
        &config,
        r#"(seed: 7, trials: 4, landscape_runs: 0, arms: ["case-based"],
            experiments: [(scenario: "movement", operator: "balanced")])"#,
    )
    .unwrap();
    let saved = dir.path().join("saved");
    succeeded(
        Command::new(env!("CARGO_BIN_EXE_trustcbr"))
            .args(["run", config.to_str().unwrap(), "--out"])
            .arg(dir.path().join("report"))
            .arg("--save-cases")
            .arg(&saved)
            .output()
            .unwrap(),
    );
    let file = saved.join("movement-balanced").join("case-based.ron");
    let stored = std::fs::read_to_string(&file)
        .unwrap()
        .matches("solution:")
        .count();
    assert!(stored > 0);

    let info = succeeded(trustcbr(&["cases", "info", file.to_str().unwrap()]));
    assert!(info.contains("domain:    movement"), "{info}");
    assert!(
        info.contains("400 behaviors: speed (20 values, weight 1), padding (20 values, weight 1)"),
        "{info}"
    );
    assert!(info.contains(&format!("cases:     {stored} ")), "{info}");

    // Into a database of the scenario it was learned in, and out again unchanged.
    let db = dir.path().join("movement.db");
    let said = succeeded(trustcbr(&[
        "cases",
        "import",
        file.to_str().unwrap(),
        db.to_str().unwrap(),
        "--domain",
        "movement",
    ]));
    assert!(
        said.starts_with(&format!("imported {stored} cases")),
        "{said}"
    );
    let exported = dir.path().join("exported.ron");
    succeeded(trustcbr(&[
        "cases",
        "export",
        db.to_str().unwrap(),
        exported.to_str().unwrap(),
    ]));
    assert_eq!(
        std::fs::read_to_string(&exported).unwrap(),
        std::fs::read_to_string(&file).unwrap()
    );
}

#[test]
fn importing_into_a_ron_file_says_it_is_read_only() {
    let dir = tempfile::tempdir().unwrap();
    let (domain, exported) = learned_and_exported(dir.path());
    let before = std::fs::read(&exported).unwrap();
    let existing = dir.path().join("existing.ron");
    std::fs::copy(&exported, &existing).unwrap();

    // A new RON file is not created, an existing one is not changed.
    let new = dir.path().join("new.ron");
    for target in [&new, &existing] {
        let output = trustcbr(&[
            "cases",
            "import",
            exported.to_str().unwrap(),
            target.to_str().unwrap(),
            "--domain",
            domain.to_str().unwrap(),
        ]);
        assert!(!output.status.success());
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(
            stderr.contains(&format!(
                "{}: RON case files are read-only; import the cases into an SQLite file or a postgres:// URL instead",
                target.display()
            )),
            "{stderr}"
        );
        assert!(!stderr.contains("no case base there"), "{stderr}");
    }
    assert!(!new.exists());
    assert_eq!(std::fs::read(&existing).unwrap(), before);
    assert_eq!(std::fs::read(&exported).unwrap(), before);
}
