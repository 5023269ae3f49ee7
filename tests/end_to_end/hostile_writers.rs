//! End-to-end: every writer writes only inside the folder or file the user named, never
//! through a symbolic link, replaces only what it wrote itself, and a report folder is
//! swapped in whole, so a failed write leaves the earlier report as it was
//! (docs/robustness.md, "Writing files").

use crate::support;

use std::collections::BTreeMap;
use std::fs;
use std::os::unix::fs::symlink;
use std::path::{Path, PathBuf};
use std::process::Command;
use support::{refused, succeed, trustcbr};

/// A one-experiment suite whose experiment is `experiment`.
fn suite(experiment: &str, trials: u32) -> String {
    format!("(seed: 1, trials: {trials}, experiments: [{experiment}])")
}

const BALANCED: &str = r#"(scenario: "movement", operator: "balanced")"#;
const SPEED_FOCUSED: &str = r#"(scenario: "movement", operator: "speed-focused")"#;

/// `trustcbr run CONFIG --out OUT`, the suite written to `dir/NAME.ron`.
fn run(dir: &Path, name: &str, text: &str, out: &Path) -> Command {
    let config = dir.join(format!("{name}.ron"));
    fs::write(&config, text).unwrap();
    let mut command = trustcbr();
    command.arg("run").arg(config).arg("--out").arg(out);
    command
}

/// Every entry of `dir` (not following links) by name, with its bytes (a link: its
/// target, a folder: nothing).
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            let path = e.path();
            let kind = e.file_type().unwrap();
            let bytes = if kind.is_symlink() {
                fs::read_link(&path)
                    .unwrap()
                    .into_os_string()
                    .into_encoded_bytes()
            } else if kind.is_file() {
                fs::read(&path).unwrap()
            } else {
                Vec::new()
            };
            (e.file_name().to_string_lossy().into_owned(), bytes)
        })
        .collect()
}

fn names(dir: &Path) -> Vec<String> {
    snapshot(dir).into_keys().collect()
}

#[test]
fn a_report_folder_of_symlinks_is_refused_and_what_they_point_to_stays() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    succeed(&mut run(dir.path(), "a", &suite(BALANCED, 1), &out));
    // Every file of the report replaced by a link to a file outside it.
    let outside = dir.path().join("outside");
    fs::create_dir(&outside).unwrap();
    for name in names(&out) {
        if out.join(&name).is_file() {
            fs::write(outside.join(&name), format!("precious {name}")).unwrap();
            fs::remove_file(out.join(&name)).unwrap();
            symlink(outside.join(&name), out.join(&name)).unwrap();
        }
    }
    let before = (snapshot(&outside), snapshot(&out));
    let stderr = refused(&mut run(dir.path(), "a", &suite(BALANCED, 2), &out));
    assert!(
        stderr.contains(": is a symbolic link; nothing is written through one"),
        "{stderr}"
    );
    assert_eq!((snapshot(&outside), snapshot(&out)), before);

    // The report folder itself a link: refused, whatever it points to.
    let link = dir.path().join("link");
    symlink(&outside, &link).unwrap();
    let stderr = refused(&mut run(dir.path(), "a", &suite(BALANCED, 1), &link));
    assert!(
        stderr.contains(&format!("{}: is a symbolic link", link.display())),
        "{stderr}"
    );
    assert_eq!(snapshot(&outside), before.0);
    assert_eq!(names(dir.path()), ["a.ron", "link", "out", "outside"]);
}

#[test]
fn a_new_report_replaces_the_earlier_one_whole_and_figures_never_mix() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    succeed(&mut run(dir.path(), "a", &suite(BALANCED, 1), &out));
    assert!(out.join("curves-movement-balanced.svg").is_file());
    succeed(&mut run(dir.path(), "b", &suite(SPEED_FOCUSED, 1), &out));
    let figures: Vec<String> = names(&out)
        .into_iter()
        .filter(|n| n.starts_with("curves-"))
        .collect();
    assert_eq!(figures, ["curves-movement-speed-focused.svg"]);
    // Nothing is left beside the folder: the new report's folder was renamed into place
    // and the earlier one removed.
    assert_eq!(names(dir.path()), ["a.ron", "b.ron", "out"]);
    // An earlier report beside a file of the user's is refused, and both stay.
    fs::write(out.join("notes.txt"), "mine").unwrap();
    let before = snapshot(&out);
    let stderr = refused(&mut run(dir.path(), "a", &suite(BALANCED, 1), &out));
    assert!(
        stderr.contains("the folder holds `notes.txt`, which is not part of a trustcbr report"),
        "{stderr}"
    );
    assert_eq!(snapshot(&out), before);
}

/// `trustcbr ARGS` with files capped at 8 blocks of 512 bytes and the signal that would
/// end the process ignored, so a write past the cap fails with "File too large" as on a
/// full disk, even for root; asserts that it failed so, saying that the report `folder`
/// is left as it was.
fn fails_to_write(args: &[&Path], folder: &Path) {
    let output = Command::new("sh")
        .arg("-c")
        .arg("trap '' XFSZ; ulimit -f 8; exec \"$0\" \"$@\"")
        .arg(env!("CARGO_BIN_EXE_trustcbr"))
        .args(args)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains(&format!(
            "{}: the report could not be written, and the folder is left as it was",
            folder.display()
        )),
        "{stderr}"
    );
    assert!(stderr.contains("File too large"), "{stderr}");
}

#[test]
fn a_report_that_fails_to_write_leaves_the_earlier_one_byte_identical() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    succeed(&mut run(dir.path(), "a", &suite(BALANCED, 1), &out));
    let before = snapshot(&out);
    // A write that fails part way: the report's larger files are over the cap.
    let config = dir.path().join("b.ron");
    fs::write(&config, suite(SPEED_FOCUSED, 3)).unwrap();
    fails_to_write(&[Path::new("run"), &config, Path::new("--out"), &out], &out);
    assert_eq!(snapshot(&out), before);
    assert_eq!(names(dir.path()), ["a.ron", "b.ron", "out"]);
}

/// The sweep of [`sweep_config`].
const SWEEP: &str = r#"(suite: file("suite.ron"), seeds: [1, 2], parameters: [lambda([0.8])])"#;

/// A sweep of 2 cells x 2 seeds over one experiment and two arms, its suite and config
/// ([`SWEEP`]) in `dir`; returns the config's path.
fn sweep_config(dir: &Path) -> PathBuf {
    let suite = format!(
        r#"(seed: 1, trials: 2, arms: ["random-walk", "case-based"], experiments: [{BALANCED}])"#
    );
    fs::write(dir.join("suite.ron"), suite).unwrap();
    let config = dir.join("sweep.ron");
    fs::write(&config, SWEEP).unwrap();
    config
}

#[test]
fn a_sweep_report_that_fails_to_write_leaves_the_earlier_one_byte_identical() {
    let dir = tempfile::tempdir().unwrap();
    let config = sweep_config(dir.path());
    let out = dir.path().join("out");
    succeed(trustcbr().arg("sweep").arg(&config).arg("--out").arg(&out));
    let report = out.join("report");
    let before = (snapshot(&report), snapshot(&out.join("runs/base")));
    // Capped below the report's largest file (its plot, written last) and above the run
    // files: the runs are written again, the report fails part way.
    let largest = before.0.values().map(Vec::len).max().unwrap();
    let runs = before.1.values().map(Vec::len).max().unwrap();
    assert!(runs < 8 * 512 && largest > 8 * 512, "{runs} {largest}");
    fails_to_write(
        &[Path::new("sweep"), &config, Path::new("--out"), &out],
        &report,
    );
    assert_eq!(
        (snapshot(&report), snapshot(&out.join("runs/base"))),
        before
    );
    assert_eq!(names(&out), ["report", "runs", "sweep.ron"]);
    // A merge's report likewise.
    let merged = dir.path().join("merged");
    let merge: [&Path; 6] = [
        Path::new("sweep"),
        Path::new("merge"),
        &config,
        &out,
        Path::new("--out"),
        &merged,
    ];
    succeed(trustcbr().args(merge));
    let earlier = snapshot(&merged.join("report"));
    assert_eq!(earlier, before.0, "a merged report is one machine's");
    fails_to_write(&merge, &merged.join("report"));
    assert_eq!(snapshot(&merged.join("report")), earlier);
    assert_eq!(names(&merged), ["report"]);
}

#[test]
fn a_sweep_report_folder_is_replaced_whole_and_never_holds_other_files_or_links() {
    let dir = tempfile::tempdir().unwrap();
    let config = sweep_config(dir.path());
    let out = dir.path().join("out");
    let sweep = || {
        let mut command = trustcbr();
        command.arg("sweep").arg(&config).arg("--out").arg(&out);
        command
    };
    // A folder of an earlier version, its report beside its runs: the report moves into
    // `report/`, and nothing of the old one stays beside the runs.
    fs::create_dir(&out).unwrap();
    fs::write(out.join("sweep.ron"), SWEEP).unwrap();
    for name in ["sweep.md", "sweep.json", "sweep-old.svg"] {
        fs::write(out.join(name), "earlier").unwrap();
    }
    succeed(&mut sweep());
    assert_eq!(names(&out), ["report", "runs", "sweep.ron"]);
    assert_eq!(
        names(&out.join("report")),
        ["sweep-lambda.svg", "sweep.json", "sweep.md"]
    );
    // A file of the user's in the report folder would go with it: refused before any
    // work, and everything stays.
    fs::write(out.join("report/notes.txt"), "mine").unwrap();
    let before = snapshot(&out.join("report"));
    // Refused, naming `name` in the sweep's folder and saying `what`.
    let refused_at = |name: &str, what: &str| {
        let stderr = refused(&mut sweep());
        let expected = format!("{}: {what}", out.join(name).display());
        assert!(stderr.contains(&expected), "{stderr}");
    };
    refused_at(
        "report",
        "the folder holds `notes.txt`, which is not part of a trustcbr sweep report",
    );
    assert_eq!(snapshot(&out.join("report")), before);
    fs::remove_file(out.join("report/notes.txt")).unwrap();
    // A link in it, or the report folder a link: refused, what they point to unchanged.
    let outside = dir.path().join("outside.md");
    fs::write(&outside, "precious").unwrap();
    fs::remove_file(out.join("report/sweep.md")).unwrap();
    symlink(&outside, out.join("report/sweep.md")).unwrap();
    refused_at("report/sweep.md", "is a symbolic link");
    let elsewhere = dir.path().join("elsewhere");
    fs::rename(out.join("report"), &elsewhere).unwrap();
    symlink(&elsewhere, out.join("report")).unwrap();
    refused_at("report", "is a symbolic link");
    assert_eq!(fs::read(&outside).unwrap(), b"precious");
    assert!(
        fs::symlink_metadata(out.join("report"))
            .unwrap()
            .is_symlink()
    );
    assert_eq!(
        names(dir.path()),
        ["elsewhere", "out", "outside.md", "suite.ron", "sweep.ron"]
    );
}

#[test]
fn numbers_spelled_out_in_names_give_short_figure_names() {
    let dir = tempfile::tempdir().unwrap();
    for (k, experiment) in [
        r#"(scenario: "movement", operator: "balanced", goal_changes: Some((per_hour: 1e-300)))"#,
        r#"(scenario: "movement", operator: "balanced", stated: Some((said: 1e-300)))"#,
    ]
    .into_iter()
    .enumerate()
    {
        let out = dir.path().join(format!("out-{k}"));
        succeed(&mut run(dir.path(), "tiny", &suite(experiment, 1), &out));
        let longest = names(&out).into_iter().map(|n| n.len()).max().unwrap();
        assert!(longest <= 150, "a file name of {longest} bytes");
    }
}

fn population(out: &Path) -> Command {
    let mut command = trustcbr();
    command
        .args([
            "population",
            "--scenario",
            "movement",
            "--instance",
            "dev-5",
        ])
        .arg("--out")
        .arg(out);
    command
}

#[test]
fn population_replaces_only_its_own_members_and_never_through_a_link() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("population");
    succeed(&mut population(&out));
    let members = names(&out);
    assert!(members.len() >= 2, "{members:?}");
    // Its own files, written again.
    succeed(&mut population(&out));
    let outside = dir.path().join("victim.ron");
    fs::write(&outside, "precious").unwrap();
    let link = out.join(&members[0]);
    fs::remove_file(&link).unwrap();
    symlink(&outside, &link).unwrap();
    let before = snapshot(&out);
    let stderr = refused(&mut population(&out));
    assert!(
        stderr.contains(&format!(
            "{}: is a symbolic link; nothing is written through one",
            link.display()
        )),
        "{stderr}"
    );
    assert_eq!(fs::read(&outside).unwrap(), b"precious");
    assert_eq!(snapshot(&out), before);

    // A regular file with a member's name that is not that member: refused unchanged.
    fs::remove_file(&link).unwrap();
    fs::write(&link, "my own notes").unwrap();
    let before = snapshot(&out);
    let stderr = refused(&mut population(&out));
    assert!(
        stderr.contains(&format!(
            "{}: exists and is not an operator file",
            link.display()
        )),
        "{stderr}"
    );
    assert_eq!(snapshot(&out), before);
    // The population folder a link: refused.
    let folder_link = dir.path().join("elsewhere");
    symlink(&out, &folder_link).unwrap();
    let stderr = refused(&mut population(&folder_link));
    assert!(stderr.contains("is a symbolic link"), "{stderr}");
    assert_eq!(snapshot(&out), before);
}

fn competence(out: &Path) -> Command {
    let mut command = trustcbr();
    command
        .args(["competence", "--scenario", "patrol"])
        .args(["--operator", "detection-focused", "--behaviors", "2"])
        .args(["--truth-runs", "2", "--seen", "0"])
        .arg("--out")
        .arg(out);
    command
}

fn landscape(out: &Path) -> Command {
    let mut command = trustcbr();
    command
        .args([
            "landscape",
            "--scenario",
            "movement",
            "--operator",
            "balanced",
        ])
        .args(["--runs", "1", "--out"])
        .arg(out);
    command
}

/// `command` (writing `files` into `out`) refuses a link and a foreign file in the place
/// of each file, leaving everything unchanged, and replaces its own earlier files.
fn refuses_links_and_foreign_files(command: fn(&Path) -> Command, files: [&str; 2]) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    succeed(&mut command(&out));
    // Its own earlier output is replaced.
    succeed(&mut command(&out));
    let outside = dir.path().join("outside");
    fs::write(&outside, "precious").unwrap();
    for file in files {
        let own = fs::read(out.join(file)).unwrap();
        for planted in ["link", "foreign"] {
            let path = out.join(file);
            fs::remove_file(&path).unwrap();
            if planted == "link" {
                symlink(&outside, &path).unwrap();
            } else {
                fs::write(&path, "my notes").unwrap();
            }
            let before = snapshot(&out);
            let stderr = refused(&mut command(&out));
            let expected = if planted == "link" {
                format!("{}: is a symbolic link", path.display())
            } else {
                format!("{}: exists and is not a", path.display())
            };
            assert!(stderr.contains(&expected), "{stderr}");
            assert!(stderr.contains("give --out another folder"), "{stderr}");
            assert_eq!(snapshot(&out), before);
            assert_eq!(fs::read(&outside).unwrap(), b"precious");
        }
        fs::remove_file(out.join(file)).unwrap();
        fs::write(out.join(file), own).unwrap();
    }
    succeed(&mut command(&out));
    let written: Vec<PathBuf> = files.iter().map(|f| out.join(f)).collect();
    assert!(written.iter().all(|p| p.is_file() && !p.is_symlink()));
}

#[test]
fn competence_replaces_only_its_own_report_and_never_through_a_link() {
    refuses_links_and_foreign_files(competence, ["competence.md", "competence.json"]);
}

#[test]
fn landscape_replaces_only_its_own_files_and_never_through_a_link() {
    refuses_links_and_foreign_files(landscape, ["landscape.svg", "landscape.csv"]);
}

/// `render -o`, `cases export` and `--save-cases` write nothing through a symbolic link:
/// a link at the file they would write is refused and it, and what it points to, stay as
/// they were (they wrote the file the link pointed to).
#[test]
fn render_export_and_saved_cases_never_write_through_a_link() {
    let dir = tempfile::tempdir().unwrap();
    let outside = dir.path().join("outside.txt");
    fs::write(&outside, "keep me").unwrap();
    let link = |name: &str| {
        let path = dir.path().join(name);
        symlink(&outside, &path).unwrap();
        path
    };
    let unchanged = |path: &Path| {
        assert!(fs::symlink_metadata(path).unwrap().file_type().is_symlink());
        assert_eq!(fs::read_to_string(&outside).unwrap(), "keep me");
    };

    let svg = link("walk.svg");
    let stderr = refused(
        trustcbr()
            .args(["render", "--scenario", "movement", "--behavior"])
            .arg("speed=2,padding=0.3")
            .arg("--out")
            .arg(&svg),
    );
    assert!(stderr.contains("is a symbolic link"), "{stderr}");
    unchanged(&svg);

    // A case base to export, saved by a small run with --save-cases.
    let saved = dir.path().join("saved");
    succeed(
        run(
            dir.path(),
            "small",
            &suite(BALANCED, 4),
            &dir.path().join("report"),
        )
        .arg("--save-cases")
        .arg(&saved),
    );
    let base = saved.join("movement-balanced").join("case-based.ron");
    assert!(base.is_file());
    let export = link("export.ron");
    let stderr = refused(trustcbr().args(["cases", "export"]).arg(&base).arg(&export));
    assert!(
        stderr.contains("a symbolic link: nothing is written through one"),
        "{stderr}"
    );
    unchanged(&export);

    // The saved case base itself replaced by a link: the next run refuses before any work.
    fs::remove_file(&base).unwrap();
    symlink(&outside, &base).unwrap();
    let text = r#"(seed: 1, trials: 4, arms: ["case-based"], experiments: [(scenario: "movement", operator: "balanced")])"#;
    let stderr = refused(
        run(dir.path(), "again", text, &dir.path().join("report2"))
            .arg("--save-cases")
            .arg(&saved),
    );
    assert!(
        stderr.contains("case-based.ron: exists and is not a case base saved earlier (a symbolic link: nothing is written through one"),
        "{stderr}"
    );
    assert!(!dir.path().join("report2").exists(), "{stderr}");
    unchanged(&base);
}
