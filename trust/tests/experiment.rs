//! The experiment machinery on a toy domain: pairing, determinism across thread counts,
//! statistics and the report files.

use cbr_core::{Behavior, BehaviorSpace, Component};
use rand::{Rng, RngCore};
use std::sync::Arc;
use trust::experiment::report::{ReportEntry, trials_jsonl, write_report};
use trust::experiment::{
    ExperimentPlan, ExperimentResult, OperatorChoice, Strategy, run_experiments,
};
use trust::{AdapterConfig, Cause, Domain, Outcome};

/// A 6 x 6 grid; an operator completes commands of behaviors near its favourite one.
struct Toy {
    space: Arc<BehaviorSpace>,
}

struct Favourite(Behavior);

impl Toy {
    fn new() -> Self {
        let c = |name: &str| Component::numeric(name, "", 0.0, 1.0, 6).unwrap();
        Self {
            space: Arc::new(BehaviorSpace::new(vec![c("a"), c("b")]).unwrap()),
        }
    }
}

impl Domain for Toy {
    type Operator = Favourite;

    fn name(&self) -> &str {
        "toy"
    }

    fn space(&self) -> &Arc<BehaviorSpace> {
        &self.space
    }

    fn run(&self, behavior: &Behavior, operator: &Favourite, rng: &mut dyn RngCore) -> Outcome {
        let distance = self.space.changes(behavior, &operator.0);
        let duration = 1.0 + f64::from(distance);
        if distance == 0 || rng.random_bool(0.05) {
            Outcome::completed(1.0, duration)
        } else {
            Outcome::interrupted(1.0, Cause::Deadline, duration)
        }
    }
}

fn operators() -> Vec<(String, Favourite)> {
    vec![
        ("low".to_owned(), Favourite(Behavior::new(&[1, 1]))),
        ("high".to_owned(), Favourite(Behavior::new(&[4, 5]))),
    ]
}

fn plans<'a>(
    toy: &'a Toy,
    ops: &'a [(String, Favourite)],
    trials: u32,
) -> Vec<ExperimentPlan<'a, Toy>> {
    vec![
        ExperimentPlan {
            name: "toy/low".into(),
            domain: toy,
            operators: ops,
            choice: OperatorChoice::Fixed(0),
            trials,
            adapter: AdapterConfig::default(),
            max_commands: 100_000,
        },
        ExperimentPlan {
            name: "toy/random".into(),
            domain: toy,
            operators: ops,
            choice: OperatorChoice::Random,
            trials,
            adapter: AdapterConfig::default(),
            max_commands: 100_000,
        },
    ]
}

/// Report entries for the results of `plans` (the `low` and `random` experiments).
fn entries<'a>(results: &'a [ExperimentResult], toy: &'a Toy) -> Vec<ReportEntry<'a>> {
    results
        .iter()
        .zip(["low", "random"])
        .map(|(result, operator)| ReportEntry {
            result,
            scenario: "toy",
            operator,
            space: &toy.space,
        })
        .collect()
}

fn run_with_threads(threads: usize, trials: u32, seed: u64) -> String {
    let toy = Toy::new();
    let ops = operators();
    let plans = plans(&toy, &ops, trials);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let results = pool
        .install(|| run_experiments(&plans, seed, &|_| {}))
        .unwrap();
    let entries = entries(&results, &toy);
    trials_jsonl(&entries)
}

#[test]
fn same_seed_same_trials_for_any_thread_count() {
    let one = run_with_threads(1, 40, 11);
    let two = run_with_threads(2, 40, 11);
    assert_eq!(one, two);
    assert_ne!(one, run_with_threads(2, 40, 12));
}

#[test]
fn strategies_are_paired_and_cases_help() {
    let toy = Toy::new();
    let ops = operators();
    let results = run_experiments(&plans(&toy, &ops, 60), 5, &|_| {}).unwrap();
    for result in &results {
        let [rw, cb] = &result.strategies;
        assert_eq!(rw.strategy, Strategy::RandomWalk);
        assert_eq!(cb.strategy, Strategy::CaseBased);
        assert_eq!(rw.trials.len(), 60);
        for (a, b) in rw.trials.iter().zip(&cb.trials) {
            // Same operator and initial behavior for both strategies of a pair.
            assert_eq!(
                (a.trial, &a.operator, a.initial),
                (b.trial, &b.operator, b.initial)
            );
        }
        assert!(cb.cases_acquired > 0);
        assert!(
            cb.behaviors.mean < rw.behaviors.mean,
            "{}: case-based {} vs random walk {}",
            result.name,
            cb.behaviors.mean,
            rw.behaviors.mean
        );
        assert!((0.0..=1.0).contains(&result.p_value));
    }
    // In the random-operator experiment both operators appear.
    let drawn: std::collections::HashSet<&str> = results[1].strategies[0]
        .trials
        .iter()
        .map(|t| t.operator.as_str())
        .collect();
    assert_eq!(drawn.len(), 2);
}

#[test]
fn the_report_folder_holds_every_file() {
    let toy = Toy::new();
    let ops = operators();
    let results = run_experiments(&plans(&toy, &ops, 10), 3, &|_| {}).unwrap();
    let entries = entries(&results, &toy);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("report");
    write_report(&out, &entries, "(trials: 10)", 1.5).unwrap();
    for name in [
        "table.md",
        "summary.json",
        "trials.jsonl",
        "config.ron",
        "curves-toy-low.svg",
        "finals-toy-random.svg",
    ] {
        assert!(out.join(name).is_file(), "{name} is missing");
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["elapsed_s"], 1.5);
    let first = &summary["experiments"][0];
    assert_eq!(first["scenario"], "toy");
    assert_eq!(first["operator"], "low");
    assert_eq!(first["trials"], 10);
    assert!(first["strategies"]["case-based"]["mean"].is_f64());
    assert!(first["strategies"]["random-walk"]["cases_acquired"].is_u64());
    let lines = std::fs::read_to_string(out.join("trials.jsonl")).unwrap();
    assert_eq!(lines.lines().count(), 2 * 2 * 10);
    let line: serde_json::Value = serde_json::from_str(lines.lines().next().unwrap()).unwrap();
    assert_eq!(line["experiment"], "toy/low");
    assert_eq!(line["strategy"], "random-walk");
    assert!(line["final"]["a"].is_f64());
    let svg = std::fs::read_to_string(out.join("curves-toy-low.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("case-based"));
}
