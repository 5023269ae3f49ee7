//! What the process tests share: the binary as a command and a run that must succeed, a
//! quick domain, a TCP server and the address it listens on, the cases a store holds, and
//! what an SVG figure shows and whether it stays in its view box.
//! Each test file uses part of it.
#![allow(dead_code)] // every test file compiles this module and uses only some of it

use serde_json::Value;
use service::store::{self, Location, StoreId};
use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};

/// The `trustcbr` binary under test, as a command to complete.
pub fn trustcbr() -> Command {
    Command::new(env!("CARGO_BIN_EXE_trustcbr"))
}

/// `trustcbr run` of the suite `text`, written to `dir/suite.ron`, reporting to `dir/out`.
pub fn run_suite(dir: &std::path::Path, text: &str) -> Command {
    let config = dir.join("suite.ron");
    std::fs::write(&config, text).unwrap();
    let mut command = trustcbr();
    command
        .arg("run")
        .arg(&config)
        .arg("--out")
        .arg(dir.join("out"));
    command
}

/// Runs `command`, asserts that it succeeded (showing its stderr if not), returns stdout.
pub fn succeed(command: &mut Command) -> String {
    let output = command.output().unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8(output.stdout).unwrap()
}

/// Runs `command`, asserts that it was refused with a user's error (status 1 or 2, the
/// message starting `error: `) rather than a panic, and returns its stderr.
pub fn refused(command: &mut Command) -> String {
    let output = command.output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(matches!(output.status.code(), Some(1 | 2)), "{stderr}");
    assert!(stderr.starts_with("error: "), "{stderr}");
    stderr
}

/// A 5 x 5 domain whose episodes end in three requests: `begin`, one interruption
/// (untrustworthy at -1: the adapter switches; the robot felt a collision), one completion
/// (trustworthy at +1). With
/// `reuse_cases` off every switch comes from the search, so every episode retains a case.
pub fn quick_domain(reuse_cases: bool) -> String {
    format!(
        r#"(
    space: (components: [
        (name: "speed", unit: "m/s", values: Numeric(min: 1.0, step: 1.0, count: 5)),
        (name: "padding", unit: "m", values: Numeric(min: 0.2, step: 0.2, count: 5)),
    ]),
    causes: [(name: "collision"), (name: "stuck")],
    observations: ["collision"],
    adapter: (thresholds: (trustworthy: 1.0, untrustworthy: -1.0), reuse_cases: {reuse_cases}),
)"#
    )
}

/// The three requests of a quick episode.
pub const EPISODE: [&str; 3] = [
    r#"{"request": "begin"}"#,
    r#"{"outcome": "interrupted", "weight": 1.0, "duration_s": 4.0, "observed": ["collision"]}"#,
    r#"{"outcome": "completed", "weight": 1.0, "duration_s": 6.0}"#,
];

/// A server process, killed when dropped (even when a test fails).
pub struct Server(pub Child);

impl Drop for Server {
    fn drop(&mut self) {
        self.0.kill().ok();
        self.0.wait().ok();
    }
}

/// Starts `serve`, made by `command` with `--listen`, and reads its stderr until it says
/// where it listens, then keeps draining it (so the server never blocks on its log).
/// Returns the server and the address.
pub fn listening(command: &mut Command) -> (Server, String) {
    let mut server = Server(
        command
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap(),
    );
    let mut log = BufReader::new(server.0.stderr.take().expect("stderr is piped"));
    let addr = loop {
        let mut line = String::new();
        assert_ne!(
            log.read_line(&mut line).unwrap(),
            0,
            "the server exited early"
        );
        if let Some(addr) = line.trim().strip_prefix("listening on ") {
            break addr.to_owned();
        }
    };
    std::thread::spawn(move || for _ in log.lines() {});
    (server, addr)
}

/// Every case stored at `location`, by store id, its solution in real units of `space`;
/// the store must open, and no id may appear twice.
pub fn stored_solutions(
    location: &Location,
    space: &cbr_core::BehaviorSpace,
) -> BTreeMap<StoreId, Value> {
    let mut store =
        store::open_existing(location).unwrap_or_else(|e| panic!("the case base must open: {e}"));
    let mut rows = Vec::new();
    store
        .read_after(None, &mut |c| {
            rows.push((c.id, service::reply::behavior(space, &c.case.solution)));
            Ok(())
        })
        .unwrap();
    let count = rows.len();
    let by_id: BTreeMap<StoreId, Value> = rows.into_iter().collect();
    assert_eq!(by_id.len(), count, "a case id appears twice");
    by_id
}

/// The texts of an SVG written by plotters (each element's content is on its own line).
pub fn svg_texts(svg: &str) -> Vec<&str> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            t.split_once('>')
                .and_then(|(_, rest)| rest.split_once("</text>"))
        })
        .map(|(text, _)| text.trim())
        .collect()
}

/// The value of attribute `name` in the element's opening tag `tag`.
fn attribute(tag: &str, name: &str) -> Option<f64> {
    let start = tag.find(&format!(" {name}=\""))? + name.len() + 3;
    tag[start..].split('"').next()?.parse().ok()
}

/// The rectangles and texts of an SVG that reach outside its view box, described. A
/// text's width is overestimated as 0.6 em a character and placed by its anchor; rotated
/// texts (axis titles) are skipped. A text may take its font size and anchor from the
/// group (`<g ...>`) around it.
pub fn outside_view(svg: &str) -> Vec<String> {
    let head = svg.split('>').next().unwrap();
    let (width, height) = (
        attribute(head, "width").unwrap(),
        attribute(head, "height").unwrap(),
    );
    let mut outside = Vec::new();
    for rect in svg.split("<rect").skip(1) {
        let tag = rect.split('>').next().unwrap();
        let [x, y, w, h] = ["x", "y", "width", "height"].map(|a| attribute(tag, a).unwrap());
        if x < 0.0 || y < 0.0 || x + w > width || y + h > height {
            outside.push(format!("rect {tag}"));
        }
    }
    // The opening tag of the group a text is in, if any (groups are not nested here).
    let mut group = String::new();
    let follow = |between: &str, group: &mut String| {
        for piece in between.split('<').skip(1) {
            if let Some(attributes) = piece.strip_prefix("g ") {
                *group = format!(" {}", attributes.split('>').next().unwrap_or_default());
            } else if piece.starts_with("/g>") {
                group.clear();
            }
        }
    };
    let mut pieces = svg.split("<text");
    follow(pieces.next().unwrap_or_default(), &mut group);
    for text in pieces {
        let (tag, rest) = text.split_once('>').unwrap();
        let (content, after) = rest.split_once("</text>").unwrap();
        let content = content.trim();
        let own = |name: &str| attribute(tag, name).or_else(|| attribute(&group, name));
        let anchored = |anchor: &str| {
            let key = format!("text-anchor=\"{anchor}\"");
            tag.contains(&key) || (!tag.contains("text-anchor") && group.contains(&key))
        };
        if !tag.contains("transform") {
            let size = own("font-size").unwrap();
            let w = content.chars().count() as f64 * 0.6 * size;
            let x = attribute(tag, "x").unwrap();
            let left = if anchored("end") {
                x - w
            } else if anchored("middle") {
                x - w / 2.0
            } else {
                x
            };
            let y = attribute(tag, "y").unwrap();
            if left < 0.0 || left + w > width || y < 0.0 || y + size > height {
                outside.push(format!(
                    "text `{content}` at x {left:.0} to {:.0}, y {y:.0}",
                    left + w
                ));
            }
        }
        follow(after, &mut group);
    }
    outside
}

/// A mission suite of one small plan, `movement/paper`, whose operators are `operators`
/// (an experiment's fields, as a mission plan's `operators`).
pub fn one_mission_suite(operators: &str) -> String {
    format!(
        r#"(
    seed: 1,
    arms: ["uniform"],
    missions: [(
        name: "movement/paper",
        operators: {operators},
        count: 2,
        commands: 20,
        changes: (every: 10.0, takeover: 0.5),
    )],
)"#
    )
}
