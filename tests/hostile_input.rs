//! End-to-end: hostile command-line input is refused at once, with a message naming the
//! problem, before any work is done.

use std::path::Path;
use std::process::{Command, Output};

fn trustcbr() -> Command {
    Command::new(env!("CARGO_BIN_EXE_trustcbr"))
}

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
        .arg(dir.path().join("cases.ron"))
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
