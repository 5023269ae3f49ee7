//! End-to-end: `sweep merge` is correct or refused. Every run file is checked against its
//! place (cell, seed, the content of the suite it ran, trials, experiments and arms, values
//! a run can have); two folders holding different versions of one run are refused naming
//! both; every missing run is named (a shard that could not write says where and why, and
//! its runs are named missing); nothing of the report is written when a merge is
//! refused, and a huge value is refused at once instead of hanging the report.

use crate::support;

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use support::{succeed, trustcbr};

const SUITE: &str = r#"(
    seed: 1,
    trials: 2,
    arms: ["random-walk"],
    experiments: [(scenario: "movement", operator: "balanced")],
)"#;

const SWEEP: &str = r#"(suite: file("suite.ron"), seeds: [1, 2], parameters: [lambda([0.8])])"#;

/// A sweep of 2 cells x 2 seeds, its suite file, and shard folders run from it.
struct Sweep {
    dir: tempfile::TempDir,
}

impl Sweep {
    fn new() -> Self {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("suite.ron"), SUITE).unwrap();
        std::fs::write(dir.path().join("sweep.ron"), SWEEP).unwrap();
        Self { dir }
    }

    fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }

    /// Runs shard `shard` (`I/N`) into the folder `name`; returns its path.
    fn shard(&self, shard: &str, name: &str) -> PathBuf {
        let out = self.path(name);
        succeed(
            trustcbr()
                .arg("sweep")
                .arg(self.path("sweep.ron"))
                .args(["--shard", shard, "--out"])
                .arg(&out),
        );
        out
    }

    /// `sweep merge` of `folders` into `report`, which must fail quickly without writing
    /// anything there; returns its stderr.
    fn refused(&self, folders: &[&Path]) -> String {
        let report = self.path("report");
        let started = Instant::now();
        let output = trustcbr()
            .args(["sweep", "merge"])
            .arg(self.path("sweep.ron"))
            .args(folders)
            .arg("--out")
            .arg(&report)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
        assert_eq!(output.status.code(), Some(1), "{stderr}");
        assert!(stderr.starts_with("error: "), "{stderr}");
        assert!(started.elapsed() < Duration::from_secs(10), "{stderr}");
        let written = std::fs::read_dir(&report).map_or(0, |d| d.count());
        assert_eq!(written, 0, "a refused merge wrote into the report folder");
        stderr
    }

    /// `sweep merge` of `folders` into `report`, which must succeed.
    fn merged(&self, folders: &[&Path]) {
        succeed(
            trustcbr()
                .args(["sweep", "merge"])
                .arg(self.path("sweep.ron"))
                .args(folders)
                .arg("--out")
                .arg(self.path("report")),
        );
    }
}

/// Reads the run file `run` of `folder`, lets `edit` change it, writes it back.
fn edit(folder: &Path, run: &str, edit: impl FnOnce(&mut Value)) {
    let path = folder.join("runs").join(run);
    let mut json: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    edit(&mut json);
    std::fs::write(&path, serde_json::to_string_pretty(&json).unwrap()).unwrap();
}

#[test]
fn every_missing_run_is_named() {
    let sweep = Sweep::new();
    let first = sweep.shard("1/2", "first");
    let stderr = sweep.refused(&[&first]);
    assert!(
        stderr.contains(&format!(
            "2 of 4 runs are in none of the folders ({}): runs/base/seed-2.json, runs/lambda-0-8/seed-2.json; run the shards that hold them first",
            first.display()
        )),
        "{stderr}"
    );
    let second = sweep.shard("2/2", "second");
    sweep.merged(&[&first, &second]);
}

#[test]
fn a_run_out_of_its_place_or_of_another_suite_is_refused() {
    let sweep = Sweep::new();
    let all = sweep.shard("1/1", "all");
    let runs = all.join("runs");
    let original = std::fs::read(runs.join("base/seed-2.json")).unwrap();

    // Another seed's run copied over this one's.
    std::fs::copy(runs.join("base/seed-1.json"), runs.join("base/seed-2.json")).unwrap();
    let stderr = sweep.refused(&[&all]);
    assert!(
        stderr.contains(&format!(
            "{}: this is the run of cell `base`, seed 1, not of cell `base`, seed 2 whose place it holds",
            runs.join("base/seed-2.json").display()
        )),
        "{stderr}"
    );
    std::fs::write(runs.join("base/seed-2.json"), &original).unwrap();

    // An empty run, and a run with its results removed.
    std::fs::write(runs.join("base/seed-2.json"), "").unwrap();
    let stderr = sweep.refused(&[&all]);
    assert!(
        stderr.contains("seed-2.json: EOF while parsing"),
        "{stderr}"
    );
    std::fs::write(runs.join("base/seed-2.json"), &original).unwrap();
    edit(&all, "base/seed-2.json", |run| {
        run["experiments"] = serde_json::json!({});
    });
    let stderr = sweep.refused(&[&all]);
    assert!(
        stderr.contains("its results do not cover every experiment and arm exactly once"),
        "{stderr}"
    );
    std::fs::write(runs.join("base/seed-2.json"), &original).unwrap();

    // A value no run can have (it made the report's interval infinite and hung it).
    edit(&all, "base/seed-2.json", |run| {
        run["experiments"]["movement/balanced"]["random-walk"]["behaviors"] =
            serde_json::json!(1e200);
    });
    let stderr = sweep.refused(&[&all]);
    assert!(
        stderr.contains(
            "experiment `movement/balanced`, arm `random-walk`: behaviors must be a number from 0 to 1000000, got 1e200"
        ),
        "{stderr}"
    );
    std::fs::write(runs.join("base/seed-2.json"), &original).unwrap();
    sweep.merged(&[&all]);
    std::fs::remove_dir_all(sweep.path("report")).unwrap();

    // The suite file edited since the runs were made: the sweep file is the same.
    std::fs::write(
        sweep.path("suite.ron"),
        SUITE.replace("trials: 2", "trials: 3"),
    )
    .unwrap();
    let stderr = sweep.refused(&[&all]);
    assert!(
        stderr.contains("this run was made from another suite than the sweep's"),
        "{stderr}"
    );
}

#[test]
fn two_versions_of_one_run_are_refused_naming_both_folders() {
    let sweep = Sweep::new();
    let one = sweep.shard("1/1", "one");
    let two = sweep.shard("1/1", "two");
    // The same runs in both folders: merged as one.
    sweep.merged(&[&one, &two]);
    edit(&two, "lambda-0-8/seed-1.json", |run| {
        let behaviors = &mut run["experiments"]["movement/balanced"]["random-walk"]["behaviors"];
        *behaviors = serde_json::json!(behaviors.as_f64().unwrap() + 1.0);
    });
    std::fs::remove_dir_all(sweep.path("report")).unwrap();
    let stderr = sweep.refused(&[&one, &two]);
    assert!(
        stderr.contains(&format!(
            "{}: differs from {}: two versions of one run; remove the wrong one",
            two.join("runs/lambda-0-8/seed-1.json").display(),
            one.join("runs/lambda-0-8/seed-1.json").display()
        )),
        "{stderr}"
    );
}

#[test]
fn a_failed_shards_empty_folder_counts_as_holding_no_run() {
    let sweep = Sweep::new();
    let first = sweep.shard("1/2", "first");
    let failed = sweep.path("failed");
    std::fs::create_dir(&failed).unwrap();
    let stderr = sweep.refused(&[&first, &failed]);
    assert!(
        stderr.contains("2 of 4 runs are in none of the folders"),
        "{stderr}"
    );
}

#[test]
fn a_shard_that_cannot_write_names_the_path_and_the_reason_and_its_runs_are_named_missing() {
    let sweep = Sweep::new();
    let first = sweep.shard("1/2", "first");
    // A regular file where the shard's folder should go: the folder cannot be created,
    // whoever runs the shard (root included).
    let blocked = sweep.path("blocked");
    std::fs::write(&blocked, b"a file").unwrap();
    let out = blocked.join("shard-2");
    let output = trustcbr()
        .arg("sweep")
        .arg(sweep.path("sweep.ron"))
        .args(["--shard", "2/2", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert_eq!(
        stderr,
        format!(
            "error: {}: cannot create this folder: Not a directory (os error 20)\n",
            out.display()
        )
    );
    assert_eq!(std::fs::read(&blocked).unwrap(), b"a file");
    let stderr = sweep.refused(&[&first, &out]);
    assert!(
        stderr.contains("2 of 4 runs are in none of the folders")
            && stderr.contains("runs/base/seed-2.json, runs/lambda-0-8/seed-2.json"),
        "{stderr}"
    );
}

#[test]
fn a_sweep_folder_holds_one_sweep_and_nothing_else() {
    let sweep = Sweep::new();
    // A folder of unrelated files is refused before any work.
    let notes = sweep.path("notes");
    std::fs::create_dir(&notes).unwrap();
    std::fs::write(notes.join("todo.txt"), "mine").unwrap();
    let output = trustcbr()
        .arg("sweep")
        .arg(sweep.path("sweep.ron"))
        .arg("--out")
        .arg(&notes)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains(&format!(
            "{}: the folder holds `todo.txt`, which is not part of a trustcbr sweep",
            notes.display()
        )),
        "{stderr}"
    );
    assert_eq!(std::fs::read_dir(&notes).unwrap().count(), 1);
    // A folder reused for another sweep loses the old one's runs and figures.
    let out = sweep.path("out");
    succeed(
        trustcbr()
            .arg("sweep")
            .arg(sweep.path("sweep.ron"))
            .arg("--out")
            .arg(&out),
    );
    assert!(out.join("report/sweep-lambda.svg").is_file());
    assert!(out.join("runs/lambda-0-8/seed-1.json").is_file());
    std::fs::write(
        sweep.path("sweep.ron"),
        SWEEP.replace("lambda([0.8])", "time_unit([commands])"),
    )
    .unwrap();
    succeed(
        trustcbr()
            .arg("sweep")
            .arg(sweep.path("sweep.ron"))
            .arg("--out")
            .arg(&out),
    );
    assert!(out.join("report/sweep-time_unit.svg").is_file());
    assert!(!out.join("report/sweep-lambda.svg").exists());
    assert!(!out.join("runs/lambda-0-8").exists());
}
