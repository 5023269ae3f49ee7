//! End-to-end: hostile command-line input is refused at once, with a message naming the
//! problem, before any work is done.

mod support;

use std::path::Path;
use std::process::{Command, Output};
use support::trustcbr;

/// Runs `command`, checks that it failed with an error (status 1, or 2 for a usage error)
/// rather than a panic, and returns its stderr.
fn refused(command: &mut Command) -> String {
    let output: Output = command.output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(matches!(output.status.code(), Some(1 | 2)), "{stderr}");
    assert!(stderr.starts_with("error: "), "{stderr}");
    stderr
}

fn render(behavior: &str, out: &Path) -> String {
    refused(
        trustcbr()
            .args([
                "render",
                "--scenario",
                "patrol",
                "--behavior",
                behavior,
                "-o",
            ])
            .arg(out),
    )
}

#[test]
fn render_refuses_non_finite_repeated_and_missing_values() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run.svg");
    let rest = "padding=0.3,scan_time=2,scan_distance=0.5";
    for value in ["NaN", "inf", "-inf"] {
        let stderr = render(&format!("speed={value},{rest}"), &out);
        assert!(
            stderr.contains(&format!("`{value}` is not an admissible value of `speed`")),
            "{stderr}"
        );
    }
    let stderr = render(&format!("speed=3.5,speed=4.0,{rest}"), &out);
    assert!(
        stderr.contains("component `speed` is given twice"),
        "{stderr}"
    );
    let stderr = render("speed=2", &out);
    assert!(
        stderr.contains("no value given for components `padding`, `scan_time`, `scan_distance`"),
        "{stderr}"
    );
    assert!(!out.exists());
}

fn mkfifo(path: &Path) {
    let made = Command::new("mkfifo").arg(path).status().unwrap();
    assert!(made.success());
}

#[test]
fn fifos_and_devices_are_refused_as_input_files_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("input.ron");
    mkfifo(&fifo);
    let out = dir.path().join("report");
    for input in [fifo.as_path(), Path::new("/dev/zero")] {
        let stderr = refused(trustcbr().arg("run").arg(input).arg("--out").arg(&out));
        assert!(
            stderr.contains(&format!("{}: is a ", input.display()))
                && stderr.contains("not a regular file"),
            "{stderr}"
        );
        let stderr = refused(
            trustcbr()
                .args(["serve", "--domain"])
                .arg(input)
                .arg("--cases")
                .arg(dir.path().join("cases.ron")),
        );
        assert!(stderr.contains("not a regular file"), "{stderr}");
        let stderr = refused(
            trustcbr()
                .args(["serve", "--domain", "movement", "--cases"])
                .arg(input),
        );
        assert!(stderr.contains("not a regular file"), "{stderr}");
        let stderr = refused(
            trustcbr()
                .args(["landscape", "--scenario", "movement", "--operator"])
                .arg(input)
                .arg("--out")
                .arg(&out),
        );
        assert!(stderr.contains("not a regular file"), "{stderr}");
    }
    assert!(!out.exists());
}

#[test]
fn a_closed_reply_stream_is_reported_once() {
    use std::io::Write;
    use std::process::Stdio;
    let dir = tempfile::tempdir().unwrap();
    let mut server = trustcbr()
        .args(["serve", "--domain", "movement", "--cases"])
        .arg(dir.path().join("cases.db"))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The controller stops reading replies, then sends a request.
    drop(server.stdout.take());
    let mut stdin = server.stdin.take().unwrap();
    stdin.write_all(b"{\"request\":\"state\"}\n").ok();
    drop(stdin);
    let output = server.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("error: connection: Broken pipe (os error 32)\n"),
        "{stderr}"
    );
    assert_eq!(stderr.matches("Broken pipe").count(), 1, "{stderr}");
}

const TINY: &str =
    "(seed: 1, trials: 1, experiments: [(scenario: \"movement\", operator: \"balanced\")])";

/// `trustcbr run` of the one-trial config `TINY` (written in `dir`) into `out`.
fn run_tiny(dir: &Path, out: &Path) -> Command {
    let config = dir.join("tiny.ron");
    std::fs::write(&config, TINY).unwrap();
    let mut command = trustcbr();
    command.arg("run").arg(config).arg("--out").arg(out);
    command
}

#[test]
fn an_unusable_report_folder_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("report");
    std::fs::write(&file, b"not a folder").unwrap();
    let notes = dir.path().join("notes");
    std::fs::create_dir(&notes).unwrap();
    std::fs::write(notes.join("todo.txt"), b"mine").unwrap();
    let cases = [
        (file.as_path(), "exists and is a regular file, not a folder"),
        (
            Path::new("/proc/self"),
            "/proc/self: cannot create a file in this folder: ",
        ),
        (
            notes.as_path(),
            "holds `todo.txt`, which is not part of a trustcbr report",
        ),
    ];
    for (out, expected) in cases {
        let output = run_tiny(dir.path(), out).output().unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{stderr}");
        assert!(stderr.contains(expected), "{stderr}");
        // The results table is printed after the work: nothing was computed.
        assert!(output.stdout.is_empty(), "{stderr}");
    }
    assert_eq!(std::fs::read(&file).unwrap(), b"not a folder");
    assert_eq!(std::fs::read(notes.join("todo.txt")).unwrap(), b"mine");
    // `landscape` writes beside other files, but checks its folder first too.
    let stderr = refused(
        trustcbr()
            .args([
                "landscape",
                "--scenario",
                "patrol",
                "--operator",
                "speed-focused",
            ])
            .args(["--runs", "1000", "--out"])
            .arg(&file),
    );
    assert!(stderr.contains("exists and is a regular file"), "{stderr}");
}

#[test]
fn an_earlier_report_is_replaced_without_its_stale_plots() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("report");
    std::fs::create_dir(&out).unwrap();
    for name in ["summary.json", "curves-patrol-gone.svg", "notes.txt"] {
        std::fs::write(out.join(name), b"old").unwrap();
    }
    let output = run_tiny(dir.path(), &out).output().unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(!out.join("curves-patrol-gone.svg").exists());
    assert_eq!(std::fs::read(out.join("notes.txt")).unwrap(), b"old");
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("\"experiments\""), "{summary}");
}

#[test]
fn counts_out_of_range_are_refused() {
    for (args, expected) in [
        (
            &["reproduce", "--threads", "257"][..],
            "257 is not in 1..=256",
        ),
        (&["reproduce", "--threads", "0"], "0 is not in 1..=256"),
        (
            &["reproduce", "--trials", "100001"],
            "100001 is not in 1..=100000",
        ),
        (
            &[
                "landscape",
                "--scenario",
                "movement",
                "--operator",
                "balanced",
                "--runs",
                "0",
            ],
            "0 is not in 1..",
        ),
    ] {
        let stderr = refused(trustcbr().args(args));
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
    }
}
