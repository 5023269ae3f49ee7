//! End to end: a benchmark suite (`benchmark: true`) of two populations of one scenario
//! writes its benchmark into `table.md`, `summary.json` and the page, with its ECDF figure.

use crate::support;

use std::path::Path;
use support::{succeed, trustcbr};

#[test]
fn a_benchmark_suite_reports_every_arm_over_its_populations() {
    let dir = tempfile::tempdir().unwrap();
    let ladder = Path::new(env!("CARGO_MANIFEST_DIR")).join("domains/operators/ladder/movement");
    let files = |rung: &str, names: &[&str]| {
        names
            .iter()
            .map(|n| format!("{:?}", ladder.join(rung).join(format!("{n}.ron"))))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let config = dir.path().join("bench.ron");
    std::fs::write(
        &config,
        format!(
            r#"(
    seed: 5,
    trials: 6,
    landscape_runs: 0,
    limit: (runs: 5, budget: 0, candidates: 4, candidate_runs: 20),
    arms: ["random-walk", "case-based", "uniform"],
    benchmark: true,
    experiments: [
        (scenario: "movement", operator: "random", population: Some((name: "nested")),
         operator_files: [{}]),
        (scenario: "movement", operator: "random", population: Some((name: "apart")),
         operator_files: [{}]),
    ],
)"#,
            files("rung-0", &["speed-focused", "safety-focused"]),
            files("rung-2", &["dispatcher", "supervisor"]),
        ),
    )
    .unwrap();
    let out = dir.path().join("report");
    succeed(
        trustcbr()
            .args(["run", config.to_str().unwrap(), "--threads", "2", "--out"])
            .arg(&out),
    );
    let read = |name: &str| std::fs::read_to_string(out.join(name)).unwrap();

    let table = read("table.md");
    assert!(
        table.contains("## Benchmark: every arm over the populations"),
        "{table}"
    );
    assert!(table.contains("### movement: 2 populations"), "{table}");
    assert!(
        table.contains(
            "| W/T/L vs uniform | W/T/L vs case-based | Untrustworthy × limit, trials 1–6 |"
        ),
        "{table}"
    );
    // The reference against itself has no verdict; every other arm one per population.
    let uniform_row = table
        .lines()
        .find(|l| l.starts_with("| uniform |"))
        .unwrap();
    assert_eq!(uniform_row.matches(" — |").count(), 1, "{uniform_row}");

    let summary: serde_json::Value = serde_json::from_str(&read("summary.json")).unwrap();
    let [movement] = summary["benchmark"].as_array().unwrap().as_slice() else {
        panic!("one scenario: {summary}");
    };
    assert_eq!(movement["scenario"], "movement");
    assert_eq!(
        movement["populations"],
        serde_json::json!(["movement/nested", "movement/apart"])
    );
    assert_eq!(movement["windows"], serde_json::json!([[1, 6]]));
    let random_walk = &movement["arms"]["random-walk"];
    for versus in ["uniform", "case-based"] {
        let t = &random_walk["versus"][versus];
        let populations = ["wins", "ties", "losses"].map(|k| t[k].as_u64().unwrap());
        assert_eq!(populations.iter().sum::<u64>(), 2, "{t}");
    }
    let ratio = &random_walk["ratio_to_limit"]["behaviors"];
    let (mean, low, high) = (
        ratio["geometric_mean"].as_f64().unwrap(),
        ratio["ci95_low"].as_f64().unwrap(),
        ratio["ci95_high"].as_f64().unwrap(),
    );
    assert!(low <= mean && mean <= high, "{ratio}");
    // The geometric mean of the two populations' own ratios to their limits.
    let own: Vec<f64> = summary["experiments"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| {
            e["strategies"]["random-walk"]["ratio_to_limit"]["behaviors"]
                .as_f64()
                .unwrap()
        })
        .collect();
    assert!(
        ((own[0] * own[1]).sqrt() - mean).abs() < 1e-9,
        "{own:?} {mean}"
    );
    // The best arm of each population, after the fact: the geometric mean over the two
    // populations of the lowest ratio any of the three arms reached there.
    let lowest: Vec<f64> = summary["experiments"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| {
            ["random-walk", "case-based", "uniform"]
                .map(|arm| {
                    e["strategies"][arm]["ratio_to_limit"]["untrustworthy"]
                        .as_f64()
                        .unwrap()
                })
                .into_iter()
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    let best = &movement["best_of_each_population"];
    let envelope = best["ratio_to_limit"]["untrustworthy"].as_f64().unwrap();
    assert!(
        ((lowest[0] * lowest[1]).sqrt() - envelope).abs() < 1e-9,
        "{lowest:?} {best}"
    );
    assert_eq!(
        best["ratio_to_limit_over_trials"][0]["trials"],
        serde_json::json!([1, 6])
    );
    let best_row = table
        .lines()
        .find(|l| l.starts_with("| best arm of each population, after the fact (not an arm) |"))
        .unwrap();
    // No test against the reference arms: a dash for each.
    assert_eq!(best_row.matches(" — |").count(), 2, "{best_row}");
    assert!(
        best_row.contains(&format!(" {envelope:.2} |")),
        "{best_row}"
    );
    assert_eq!(random_walk["ecdf"]["pairs"], 12);
    // The limit's curve: its points climb to at most 1, and its mean is the limit's (both
    // populations ran 6 trials, so they weigh alike in both).
    let limit = &movement["limit_ecdf"];
    let points = limit["settled_within"].as_array().unwrap();
    assert!(!points.is_empty(), "{limit}");
    let shares: Vec<f64> = points.iter().map(|p| p[1].as_f64().unwrap()).collect();
    assert!(shares.windows(2).all(|w| w[0] <= w[1]), "{shares:?}");
    let never = limit["never_settled"].as_f64().unwrap();
    assert!(
        (shares.last().unwrap() + never - 1.0).abs() < 1e-9,
        "{limit}"
    );
    let (mean, expected) = (
        limit["untrustworthy_mean"].as_f64().unwrap(),
        movement["limit_untrustworthy_mean"].as_f64().unwrap(),
    );
    assert!(
        (mean - expected).abs() < 1e-9 * (1.0 + expected),
        "{mean} {expected}"
    );

    assert!(out.join("benchmark-movement-ecdf.svg").is_file());
    let page = read("report.html");
    assert!(
        page.contains("<h2 id=\"benchmark\">"),
        "the page has the benchmark section"
    );
    assert!(
        page.contains("best arm of each population, after the fact"),
        "the page has the best arm of each population"
    );
    assert!(read("config.ron").contains("benchmark: true"));
}
