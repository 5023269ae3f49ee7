//! End-to-end: the `render` and `landscape` subcommands write the files they promise.

mod support;

use support::trustcbr;

#[test]
fn render_writes_an_svg_of_one_run() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run.svg");
    let status = trustcbr()
        .args(["render", "--scenario", "patrol", "--behavior"])
        .arg("speed=2,padding=0.3,scan_time=2,scan_distance=0.5")
        .args(["--seed", "3", "-o"])
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    let svg = std::fs::read_to_string(&out).unwrap();
    assert!(svg.starts_with("<svg"));
    assert!(svg.contains("speed=2 m/s"));
    assert!(svg.contains("operator speed-focused:"));
    assert!(svg.contains("stroke-dasharray=\"6,4\""), "the planned path");
}

#[test]
fn render_refuses_a_bad_behavior() {
    let dir = tempfile::tempdir().unwrap();
    let output = trustcbr()
        .args([
            "render",
            "--scenario",
            "movement",
            "--behavior",
            "speed=3.3,padding=0.4",
            "-o",
        ])
        .arg(dir.path().join("x.svg"))
        .output()
        .unwrap();
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("speed"));
}

#[test]
fn landscape_writes_a_heatmap_and_a_table() {
    let dir = tempfile::tempdir().unwrap();
    let status = trustcbr()
        .args([
            "landscape",
            "--scenario",
            "movement",
            "--operator",
            "balanced",
        ])
        .args(["--runs", "2", "--out"])
        .arg(dir.path())
        .status()
        .unwrap();
    assert!(status.success());
    let svg = std::fs::read_to_string(dir.path().join("landscape.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("padding (m)") && svg.contains("speed (m/s)"));
    let csv = std::fs::read_to_string(dir.path().join("landscape.csv")).unwrap();
    let mut lines = csv.lines();
    assert!(
        lines
            .next()
            .unwrap()
            .starts_with("speed,padding,runs,completed,p_complete")
    );
    assert_eq!(lines.count(), 400);
}
