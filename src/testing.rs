//! The kit for a plug-in's tool (feature `testing`), beside the conformance kits of its
//! parts (`trust::testing`, `lab::testing`): the tool's binary run as a user runs it, as a
//! real process, on a suite written to a fresh temporary folder, its report read back.
//!
//! A plug-in's end-to-end test is then the suite and what it asserts of the report:
//!
//! ```no_run
//! // In a plug-in's tests/: `env!("CARGO_BIN_EXE_courier")`, its own binary.
//! let tool = std::path::Path::new("target/debug/trustcbr");
//! let run = trustcbr::testing::run_suite(
//!     tool,
//!     r#"(seed: 1, trials: 5, arms: ["case-based"],
//!         experiments: [(scenario: "movement", operator: "night", operator_files: ["night.ron"])])"#,
//!     &[("night.ron", r#"(name: "night", t_complete: 20.0, p_deadline: 0.5, p_collision: 0.5)"#)],
//!     &["--landscape-runs", "0"],
//! );
//! assert_eq!(run.summary["experiments"][0]["name"], "movement/night");
//! ```

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

/// A suite a tool's binary ran: what it printed and its report. The temporary folder it
/// ran in (the suite, its files, the report) is removed when this is dropped.
#[derive(Debug)]
pub struct SuiteRun {
    folder: tempfile::TempDir,
    /// The report folder the tool wrote (`--out`).
    pub report: PathBuf,
    /// What the tool printed on its standard output.
    pub stdout: String,
    /// The report's `summary.json`.
    pub summary: Value,
}

impl SuiteRun {
    /// The folder the suite (`suite.ron`) and its files were written to.
    pub fn folder(&self) -> &Path {
        self.folder.path()
    }

    /// The text of the report's file `name` (`trials.jsonl`, `missions.jsonl`,
    /// `table.md`, ...).
    ///
    /// # Panics
    ///
    /// When the report has no such file.
    pub fn read(&self, name: &str) -> String {
        let path = self.report.join(name);
        std::fs::read_to_string(&path)
            .unwrap_or_else(|e| panic!("the report has no {}: {e}", path.display()))
    }
}

/// Runs `tool run suite.ron --out report ARGS` in a fresh temporary folder holding `suite`
/// (a suite's RON text) as `suite.ron` and each `(name, text)` of `files` beside it (the
/// operator files it names, relative to it), and reads the report back.
///
/// # Panics
///
/// When the folder cannot be written, the tool cannot be started or fails (the panic shows
/// its standard error), or the report has no readable `summary.json`: a test's assertion.
pub fn run_suite(
    tool: impl AsRef<Path>,
    suite: &str,
    files: &[(&str, &str)],
    args: &[&str],
) -> SuiteRun {
    let folder = tempfile::tempdir().expect("a temporary folder");
    let config = folder.path().join("suite.ron");
    std::fs::write(&config, suite).expect("the suite written");
    for (name, text) in files {
        std::fs::write(folder.path().join(name), text).expect("a file beside the suite");
    }
    let report = folder.path().join("report");
    let tool = tool.as_ref();
    let output = Command::new(tool)
        .arg("run")
        .arg(&config)
        .arg("--out")
        .arg(&report)
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("{} could not start: {e}", tool.display()));
    assert!(
        output.status.success(),
        "{} run failed:\n{}",
        tool.display(),
        String::from_utf8_lossy(&output.stderr)
    );
    let summary = std::fs::read_to_string(report.join("summary.json"))
        .ok()
        .and_then(|text| serde_json::from_str(&text).ok())
        .unwrap_or_else(|| panic!("{} wrote no readable summary.json", report.display()));
    SuiteRun {
        folder,
        report,
        stdout: String::from_utf8_lossy(&output.stdout).into_owned(),
        summary,
    }
}
