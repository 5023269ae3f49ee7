//! End-to-end: the `render` and `landscape` subcommands write the files they promise, and
//! their pictures hold what they should, inside their view box.

use crate::support;

use support::{outside_view, succeed, svg_texts as texts, trustcbr};

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
    let texts = texts(&svg);
    for key in [
        "planned path",
        "explosive object",
        "harmless object",
        "10 m",
    ] {
        assert!(texts.contains(&key), "{key}: {texts:?}");
    }
    assert_eq!(outside_view(&svg), Vec::<String>::new());
}

#[test]
fn a_movement_render_has_a_scale_bar_and_no_patrol_legend() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run.svg");
    succeed(
        trustcbr()
            .args(["render", "--scenario", "movement", "--behavior"])
            .arg("speed=7,padding=0.1")
            .args(["--seed", "1", "-o"])
            .arg(&out),
    );
    let svg = std::fs::read_to_string(&out).unwrap();
    let texts = texts(&svg);
    // The scale bar: 10 m at 10 px a metre, labelled at 0, 5 and 10 m.
    for key in ["0", "5", "10 m", "planned path", "collision"] {
        assert!(texts.contains(&key), "{key}: {texts:?}");
    }
    assert!(svg.contains("width=\"100\" height=\"5\""), "the scale bar");
    assert!(
        !texts
            .iter()
            .any(|t| t.contains("object") || t.contains("scanned") || t.contains("explosive")),
        "{texts:?}"
    );
    assert_eq!(outside_view(&svg), Vec::<String>::new());
}

#[test]
fn every_landscape_heatmap_holds_its_colour_bar_in_view() {
    let pairs = [
        ("movement", "balanced", ["speed", "padding"].as_slice()),
        (
            "patrol",
            "speed-focused",
            ["speed", "padding", "scan_time", "scan_distance"].as_slice(),
        ),
    ];
    let mut runs = Vec::new();
    for (scenario, operator, components) in pairs {
        for x in components {
            for y in components.iter().filter(|y| *y != x) {
                runs.push((scenario, operator, format!("{x},{y}")));
            }
        }
    }
    std::thread::scope(|scope| {
        for chunk in runs.chunks(runs.len().div_ceil(2)) {
            scope.spawn(move || {
                for (scenario, operator, axes) in chunk {
                    let dir = tempfile::tempdir().unwrap();
                    succeed(
                        trustcbr()
                            .args(["landscape", "--scenario", scenario, "--operator", operator])
                            .args(["--runs", "1", "--components", axes, "--out"])
                            .arg(dir.path()),
                    );
                    let svg = std::fs::read_to_string(dir.path().join("landscape.svg")).unwrap();
                    let texts = texts(&svg);
                    for key in ["P(complete)", "0.0", "1.0"] {
                        assert!(texts.contains(&key), "{axes}: {key}");
                    }
                    assert_eq!(
                        outside_view(&svg),
                        Vec::<String>::new(),
                        "{scenario} {axes}"
                    );
                }
            });
        }
    });
}

#[test]
fn render_takes_out_as_the_other_commands_do() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("walk.svg");
    succeed(
        trustcbr()
            .args(["render", "--scenario", "movement", "--behavior"])
            .arg("speed=2,padding=0.3")
            .arg("--out")
            .arg(&out),
    );
    assert!(std::fs::read_to_string(&out).unwrap().starts_with("<svg"));
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
