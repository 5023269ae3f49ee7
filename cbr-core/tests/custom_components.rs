//! Users' own kinds of component, written only through the public API as a user's crate
//! would: a log-scale grid and a small taxonomy with a tree similarity. They join a space
//! with a built-in grid, and the space measures, searches, parses, displays and stores them
//! like the built-in kinds (RON and JSON round trips, registry lookups, space identity).

use cbr_core::{
    Behavior, BehaviorSpace, Component, ComponentError, ComponentKind, KindProblem, NamedComponent,
    Values, register_component_kind, registered_component_kinds,
};
use files::parse_ron;
use proptest::prelude::*;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::path::Path;

/// `count` values `min, min * ratio, min * ratio^2, ...`; similarity falls linearly with
/// the distance in log scale, one change is one grid step.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(try_from = "LogGridDefinition", into = "LogGridDefinition")]
struct LogGrid {
    min: f64,
    ratio: f64,
    count: u16,
}

#[derive(Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct LogGridDefinition {
    min: f64,
    ratio: f64,
    count: u16,
}

impl TryFrom<LogGridDefinition> for LogGrid {
    type Error = String;

    fn try_from(d: LogGridDefinition) -> Result<Self, String> {
        if !(d.min > 0.0 && d.min.is_finite() && d.ratio > 1.0 && d.ratio.is_finite()) {
            return Err(format!(
                "`min` must be > 0 and `ratio` > 1, got {} and {}",
                d.min, d.ratio
            ));
        }
        Ok(LogGrid {
            min: d.min,
            ratio: d.ratio,
            count: d.count,
        })
    }
}

impl From<LogGrid> for LogGridDefinition {
    fn from(g: LogGrid) -> Self {
        LogGridDefinition {
            min: g.min,
            ratio: g.ratio,
            count: g.count,
        }
    }
}

fn log_grid(min: f64, ratio: f64, count: u16) -> LogGrid {
    LogGrid { min, ratio, count }
}

impl LogGrid {
    fn value(&self, index: u16) -> f64 {
        self.min * self.ratio.powi(i32::from(index))
    }
}

impl Component for LogGrid {
    fn value_count(&self) -> usize {
        usize::from(self.count)
    }
    fn similarity(&self, a: u16, b: u16) -> f64 {
        // |ln x_a - ln x_b| / ln(max / min) is the index distance over count - 1.
        1.0 - f64::from(a.abs_diff(b)) / f64::from(self.count - 1)
    }
    fn adjacent(&self, a: u16, b: u16) -> bool {
        a.abs_diff(b) == 1
    }
    fn parse(&self, text: &str) -> Option<u16> {
        let x: f64 = text.trim().parse().ok()?;
        (0..self.count).find(|&i| (self.value(i) - x).abs() <= 1e-9 * self.value(i))
    }
    fn write_value(&self, index: u16, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(out, "{}", self.value(index))
    }
    fn axis_value(&self, index: u16) -> Option<f64> {
        Some(self.value(index).log2())
    }
}

impl ComponentKind for LogGrid {
    const KIND: &'static str = "log-grid";
}

/// Labelled nodes of a tree (each node's parent comes before it; node 0 is the root).
/// Similarity is Wu and Palmer's `2 depth(lca) / (depth(a) + depth(b))`, the root at depth
/// 1; one change moves to a parent or a child.
#[derive(Clone, Debug, Serialize, Deserialize)]
struct Taxonomy {
    labels: Vec<String>,
    parents: Vec<Option<u16>>,
}

impl Taxonomy {
    fn planners() -> Self {
        let nodes = [
            ("planner", None),
            ("sampling", Some(0)),
            ("rrt", Some(1)),
            ("prm", Some(1)),
            ("graph", Some(0)),
            ("astar", Some(4)),
        ];
        Taxonomy {
            labels: nodes.iter().map(|(l, _)| (*l).to_owned()).collect(),
            parents: nodes.iter().map(|(_, p)| *p).collect(),
        }
    }

    fn ancestry(&self, mut node: u16) -> Vec<u16> {
        let mut path = vec![node];
        while let Some(parent) = self.parents[usize::from(node)] {
            path.push(parent);
            node = parent;
        }
        path.reverse();
        path
    }
}

impl Component for Taxonomy {
    fn value_count(&self) -> usize {
        self.labels.len()
    }
    fn similarity(&self, a: u16, b: u16) -> f64 {
        let (pa, pb) = (self.ancestry(a), self.ancestry(b));
        let common = pa.iter().zip(&pb).take_while(|(x, y)| x == y).count();
        2.0 * common as f64 / (pa.len() + pb.len()) as f64
    }
    fn adjacent(&self, a: u16, b: u16) -> bool {
        self.parents[usize::from(a)] == Some(b) || self.parents[usize::from(b)] == Some(a)
    }
    fn parse(&self, text: &str) -> Option<u16> {
        let text = text.trim();
        self.labels.iter().position(|l| l == text).map(|i| i as u16)
    }
    fn write_value(&self, index: u16, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        out.write_str(&self.labels[usize::from(index)])
    }
}

impl ComponentKind for Taxonomy {
    const KIND: &'static str = "taxonomy";
}

/// What a user's program does at start-up, before it reads any space.
fn register() {
    register_component_kind::<LogGrid>().unwrap();
    register_component_kind::<Taxonomy>().unwrap();
}

fn space() -> BehaviorSpace {
    register();
    let scan = log_grid(0.125, 2.0, 6);
    BehaviorSpace::new(vec![
        NamedComponent::numeric("speed", "m/s", 0.5, 0.5, 4).unwrap(),
        NamedComponent::custom("scan_time", "s", scan).unwrap(),
        NamedComponent::custom("planner", "", Taxonomy::planners()).unwrap(),
    ])
    .unwrap()
}

#[test]
fn similarity_follows_the_kinds() {
    let space = space();
    let planner = &space.components()[2];
    // rrt (depth 3) and prm (depth 3) share `sampling` (depth 2): 2 x 2 / 6.
    assert_eq!(planner.similarity(2, 3), 4.0 / 6.0);
    // rrt and astar share only the root: 2 x 1 / 6.
    assert_eq!(planner.similarity(2, 5), 2.0 / 6.0);
    // rrt and sampling: 2 x 2 / (3 + 2).
    assert_eq!(planner.similarity(2, 1), 0.8);
    let a = space
        .parse("speed=0.5, scan_time=0.125, planner=rrt")
        .unwrap();
    let b = space.parse("speed=2, scan_time=0.5, planner=prm").unwrap();
    // speed: 1 - 3/3 = 0; scan time: 1 - 2/5 = 0.6; planner: 2/3. Mean of the three.
    let expected = (0.0 + 0.6 + 4.0 / 6.0) / 3.0;
    assert!((space.similarity(&a, &b) - expected).abs() < 1e-12);
    assert_eq!(space.similarity(&a, &a), 1.0);
}

#[test]
fn changes_are_paths_of_adjacent_values() {
    let space = space();
    let planner = &space.components()[2];
    // rrt -> sampling -> planner -> graph -> astar.
    assert_eq!(planner.changes(2, 5), 4);
    assert_eq!(planner.changes(2, 3), 2);
    assert_eq!(planner.max_changes(), 4);
    assert_eq!(planner.adjacent(1).collect::<Vec<_>>(), vec![0, 2, 3]);
    assert_eq!(space.components()[1].max_changes(), 5);
    assert_eq!(space.max_changes(), 3 + 5 + 4);
    let rrt = space.parse("speed=1, scan_time=1, planner=rrt").unwrap();
    let shown: Vec<String> = space
        .neighbours(&rrt)
        .map(|b| space.display(&b).to_string())
        .collect();
    assert_eq!(
        shown,
        [
            "speed=0.5 m/s, scan_time=1 s, planner=rrt",
            "speed=1.5 m/s, scan_time=1 s, planner=rrt",
            "speed=1 m/s, scan_time=0.5 s, planner=rrt",
            "speed=1 m/s, scan_time=2 s, planner=rrt",
            "speed=1 m/s, scan_time=1 s, planner=sampling",
        ]
    );
    let mut seen = 0;
    for d in 0..=space.max_changes() {
        space.for_each_at_changes(&rrt, d, &mut |b| {
            assert_eq!(space.changes(&rrt, &b), d);
            seen += 1;
        });
    }
    assert_eq!(seen, space.size());
}

#[test]
fn neighbourhoods_are_exact() {
    let space = space();
    for centre in space.iter().step_by(7) {
        for threshold in [0.5, 0.8, 0.9] {
            let mut found = Vec::new();
            space.for_each_more_similar(&centre, threshold, &mut |b| found.push(b));
            let expected: Vec<Behavior> = space
                .iter()
                .filter(|b| space.similarity(&centre, b) > threshold)
                .collect();
            assert_eq!(found, expected);
        }
    }
}

#[test]
fn values_parse_display_and_describe_in_real_units() {
    let space = space();
    let scan = &space.components()[1];
    assert_eq!(scan.index_of_text(" 0.25 "), Some(1));
    assert_eq!(scan.index_of_text("0.3"), None);
    assert_eq!(scan.display_value(5).to_string(), "4");
    assert_eq!(scan.numeric_value(5), 2.0, "the axis value: log2 of 4 s");
    assert_eq!(scan.describe_values(), "one of 0.125, 0.25, 0.5, 1, 2, 4");
    let err = space
        .parse("speed=1, scan_time=3, planner=rrt")
        .unwrap_err();
    assert_eq!(
        err.to_string(),
        "`3` is not an admissible value of `scan_time` (one of 0.125, 0.25, 0.5, 1, 2, 4)"
    );
    let planner = &space.components()[2];
    assert!(!planner.is_numeric());
    assert_eq!(planner.numeric_value(3), 3.0, "no axis value: the index");
    assert_eq!(planner.values.kind_name(), "custom kind `taxonomy`");
}

#[test]
fn spaces_round_trip_through_ron_and_json() {
    let space = space();
    let ron_text = ron::to_string(&space).unwrap();
    // The definition's keys are in field order or sorted, as serde_json is built.
    assert!(
        ron_text
            .contains(r#"(name:"scan_time",unit:"s",values:Custom(kind:"log-grid",definition:{"#)
            && ron_text.contains(r#""ratio":2.0"#),
        "{ron_text}"
    );
    let back: BehaviorSpace = parse_ron(&ron_text, Path::new("space.ron")).unwrap();
    assert_eq!(back, space);
    assert_eq!(back.first_difference(&space), None);
    let json = serde_json::to_string(&space).unwrap();
    assert!(
        json.contains(r#"{"Custom":{"kind":"taxonomy","definition":{"#)
            && json.contains(r#""labels":["planner","sampling","rrt","prm","graph","astar"]"#),
        "{json}"
    );
    let back: BehaviorSpace = serde_json::from_str(&json).unwrap();
    assert_eq!(back, space);
    let pretty = ron::ser::to_string_pretty(&space, ron::ser::PrettyConfig::default()).unwrap();
    assert_eq!(ron::from_str::<BehaviorSpace>(&pretty).unwrap(), space);
}

#[test]
fn a_hand_written_definition_is_a_map() {
    register();
    let text = r#"(components: [
        (name: "scan_time", unit: "s", values: Custom(kind: "log-grid", definition: {"min": 1, "ratio": 10, "count": 3})),
    ])"#;
    let space: BehaviorSpace = parse_ron(text, Path::new("space.ron")).unwrap();
    assert_eq!(
        space.display(&Behavior::new(&[2])).to_string(),
        "scan_time=100 s"
    );
}

#[test]
fn unknown_kinds_and_bad_definitions_are_named() {
    register();
    let text = r#"(components: [
        (name: "x", values: Custom(kind: "spiral", definition: {"turns": 3})),
    ])"#;
    let err = parse_ron::<BehaviorSpace>(text, Path::new("space.ron")).unwrap_err();
    assert!(
        err.message.starts_with(
            "unknown component kind `spiral` (registered: log-grid, taxonomy); the program must register it"
        ),
        "{err}"
    );
    assert_eq!(err.line, 2);
    let text = r#"(components: [
        (name: "x", values: Custom(kind: "log-grid", definition: {"min": 1.0, "ratio": 0.5, "count": 3})),
    ])"#;
    let err = parse_ron::<BehaviorSpace>(text, Path::new("space.ron")).unwrap_err();
    assert_eq!(
        err.message,
        "component kind `log-grid`: `min` must be > 0 and `ratio` > 1, got 1 and 0.5"
    );
    assert!(registered_component_kinds().contains(&"log-grid"));
}

#[test]
fn a_kind_name_belongs_to_one_type() {
    #[derive(Debug, Serialize, Deserialize)]
    struct Impostor;
    impl Component for Impostor {
        fn value_count(&self) -> usize {
            1
        }
        fn similarity(&self, _: u16, _: u16) -> f64 {
            1.0
        }
        fn adjacent(&self, _: u16, _: u16) -> bool {
            false
        }
        fn parse(&self, _: &str) -> Option<u16> {
            Some(0)
        }
        fn write_value(&self, _: u16, out: &mut fmt::Formatter<'_>) -> fmt::Result {
            out.write_str("only")
        }
    }
    impl ComponentKind for Impostor {
        const KIND: &'static str = "taxonomy";
    }
    register();
    let err = register_component_kind::<Impostor>().unwrap_err();
    assert!(
        err.to_string()
            .starts_with("component kind `taxonomy` is already registered by `"),
        "{err}"
    );
}

#[test]
fn ill_formed_kinds_are_refused_when_built() {
    let forest = Taxonomy {
        labels: vec!["sampling".into(), "rrt".into(), "graph".into()],
        parents: vec![None, Some(0), None],
    };
    let err = NamedComponent::custom("planner", "", forest).unwrap_err();
    assert_eq!(
        err.to_string(),
        "component `planner`: kind `taxonomy`: `graph` cannot be reached from `sampling` by changes; adjacency must connect every value"
    );
    // Values closer than the kind's parsing tolerance (1e-9 relative): the second value,
    // shown as `1.0000000001`, parses back to the first.
    let crowded = log_grid(1.0, 1.0000000001, 2);
    let err = NamedComponent::custom("x", "", crowded).unwrap_err();
    assert!(
        matches!(
            &err,
            ComponentError::Kind { problem, .. }
                if matches!(problem.problem, KindProblem::ShownValueDoesNotParse { index: 1, parsed: Some(0), .. })
        ),
        "{err}"
    );
    let invalid = log_grid(1.0, 0.5, 2);
    let err = NamedComponent::custom("x", "", invalid).unwrap_err();
    assert!(
        err.to_string()
            .starts_with("component `x`: kind `log-grid`: its definition does not round-trip:"),
        "{err}"
    );
}

/// A kind that only states its similarity and adjacency, to compare the framework's
/// derived changes with a built-in kind's own formulas.
#[derive(Debug, Serialize, Deserialize)]
struct Plain {
    count: u16,
    /// Every other value adjacent (like labels) rather than neighbouring indices.
    complete: bool,
}

impl Component for Plain {
    fn value_count(&self) -> usize {
        usize::from(self.count)
    }
    fn similarity(&self, a: u16, b: u16) -> f64 {
        f64::from(u8::from(a == b))
    }
    fn adjacent(&self, a: u16, b: u16) -> bool {
        if self.complete {
            a != b
        } else {
            a.abs_diff(b) == 1
        }
    }
    fn parse(&self, text: &str) -> Option<u16> {
        text.trim().parse().ok().filter(|&i| i < self.count)
    }
    fn write_value(&self, index: u16, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(out, "{index}")
    }
}

impl ComponentKind for Plain {
    const KIND: &'static str = "plain";
}

proptest! {
    #[test]
    fn derived_changes_agree_with_the_built_in_kinds(count in 1u16..40, complete: bool) {
        let custom = NamedComponent::custom("c", "", Plain { count, complete }).unwrap();
        let labels: Vec<String> = (0..count).map(|i| i.to_string()).collect();
        let labels: Vec<&str> = labels.iter().map(String::as_str).collect();
        let built_in = if complete {
            NamedComponent::categorical("c", &labels).unwrap()
        } else {
            NamedComponent::numeric("c", "", 0.0, 1.0, count).unwrap()
        };
        prop_assert!(matches!(custom.values, Values::Custom(_)));
        prop_assert_eq!(custom.max_changes(), built_in.max_changes());
        for a in 0..count {
            prop_assert_eq!(
                custom.adjacent(a).collect::<Vec<_>>(),
                built_in.adjacent(a).collect::<Vec<_>>()
            );
            for b in 0..count {
                prop_assert_eq!(custom.changes(a, b), built_in.changes(a, b));
            }
        }
    }
}
