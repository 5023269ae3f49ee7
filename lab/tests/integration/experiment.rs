//! The experiment machinery on a toy domain: pairing, determinism across thread counts,
//! statistics and the report files.

use cbr_core::{Behavior, BehaviorSpace};
use cbr_core::{LinearRetriever, Proposal, Searcher};
use lab::reference::known_operator::{ExperimentLimit, LimitSettings, known_operator};
use lab::reference::population_reference::ReferencePlan;
use lab::report::{
    Provenance, ReportEntry, arms_table, limit_table, population_table, summary, table,
    trials_jsonl, versus_reference, write_report,
};
use lab::testing::ToyDomain;
use lab::{Arm, ExperimentPlan, ExperimentResult, OperatorChoice, run_experiments};
use lab::{Domain, Judgement};
use rand::{Rng, RngCore};
use trust::AdapterConfig;
use trust::search::{draw_untried, propose_untried};
use trust::{Cause, Evaluated, Outcome, RetrieverKind, SetSimilarity, Thresholds, TrustRetriever};

/// The toy domain's one cause.
const TOO_SLOW: Cause = Cause::from_static("too-slow");

/// A 6 x 6 grid; an operator completes commands of behaviors near its favourite one, and
/// interrupts the others as too slow.
type Toy = ToyDomain<Favourite>;

struct Favourite(Behavior);

impl lab::SimulatedOperator for Favourite {}

/// The toy domain declaring `causes` (its runs name `too-slow` all the same).
fn toy_declaring(causes: &[Cause]) -> Toy {
    ToyDomain::grid(
        "toy",
        &[6, 6],
        causes,
        |behavior, operator: &Favourite, _, rng| {
            // The grid's behaviors are one change per step of one value.
            let distance: u32 = (0..2)
                .map(|k| u32::from(behavior.get(k).abs_diff(operator.0.get(k))))
                .sum();
            let duration = 1.0 + f64::from(distance);
            if distance == 0 || rng.random_bool(0.05) {
                Judgement::completed(1.0, duration)
            } else {
                Judgement::interrupted(1.0, TOO_SLOW, duration)
            }
        },
    )
}

fn toy() -> Toy {
    toy_declaring(&[TOO_SLOW])
}

fn operators() -> Vec<(String, Favourite)> {
    vec![
        ("low".to_owned(), Favourite(Behavior::new(&[1, 1]))),
        ("high".to_owned(), Favourite(Behavior::new(&[4, 5]))),
    ]
}

/// A user's own searcher, written outside the library: the untried behavior with the
/// smallest rank among a few drawn ones.
struct SmallestOfFour;

impl Searcher for SmallestOfFour {
    type Evidence = Evaluated;
    type Feedback = Outcome;

    fn name(&self) -> &str {
        "smallest-of-four"
    }

    fn propose(
        &mut self,
        space: &BehaviorSpace,
        evaluated: &[Evaluated],
        rng: &mut dyn RngCore,
    ) -> Proposal {
        propose_untried(space, evaluated, rng, |tried, rng| {
            draw_untried(space, tried, 4, rng)
                .into_iter()
                .min_by_key(|b| space.rank(b))
        })
    }
}

/// A user's own retriever factory: the reference scan, built by hand.
fn users_retriever(measure: SetSimilarity) -> Box<TrustRetriever> {
    Box::new(LinearRetriever::new(measure))
}

/// Every built-in arm, then a user's searcher alone and with a user's retriever.
fn arms() -> Vec<Arm> {
    let mut arms: Vec<Arm> = lab::builtin_arm_names()
        .iter()
        .map(|name| Arm::builtin(name, RetrieverKind::InvertedIndex).unwrap())
        .collect();
    arms.push(Arm::search_only("smallest-of-four", |_| {
        Box::new(SmallestOfFour)
    }));
    arms.push(Arm::case_based(
        "case-based+smallest-of-four",
        |_| Box::new(SmallestOfFour),
        users_retriever,
    ));
    arms
}

fn plans<'a>(
    toy: &'a Toy,
    ops: &'a [(String, Favourite)],
    trials: u32,
) -> Vec<ExperimentPlan<'a, Toy>> {
    let plan = |name: &str, choice| ExperimentPlan {
        name: name.into(),
        domain: toy,
        operators: ops,
        choice,
        trials,
        adapter: AdapterConfig::default(),
        arms: arms(),
        max_commands: 100_000,
        feedback: None,
        goal_changes: None,
        contexts: None,
        stated: None,
    };
    vec![
        plan("toy/low", OperatorChoice::Fixed(0)),
        plan("toy/random", OperatorChoice::Random),
    ]
}

/// Report entries for the results of `plans` (the `low` and `random` experiments).
fn entries<'a>(results: &'a [ExperimentResult], toy: &'a Toy) -> Vec<ReportEntry<'a>> {
    results
        .iter()
        .zip(["low", "random"])
        .map(|(result, operator)| ReportEntry {
            timeline: None,
            result,
            scenario: "toy",
            operator,
            space: toy.space(),
            landscapes: &[],
            limit: None,
            reference: "case-based",
            seed: 1,
        })
        .collect()
}

fn run_with_threads(threads: usize, trials: u32, seed: u64) -> String {
    let toy = toy();
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
fn arms_are_paired_and_cases_help() {
    let toy = toy();
    let ops = operators();
    let results = run_experiments(&plans(&toy, &ops, 60), 5, &|_| {}).unwrap();
    for result in &results {
        let names: Vec<&str> = result.arms.iter().map(|a| a.name.as_str()).collect();
        assert_eq!(
            names[..lab::builtin_arm_names().len()],
            lab::builtin_arm_names()
        );
        assert_eq!(
            names[lab::builtin_arm_names().len()..],
            ["smallest-of-four", "case-based+smallest-of-four"]
        );
        let rw = result.arm("random-walk").unwrap();
        let cb = result.arm("case-based").unwrap();
        for arm in &result.arms {
            assert_eq!(arm.trials.len(), 60);
            for (a, b) in rw.trials.iter().zip(&arm.trials) {
                // Same operator and initial behavior for every arm of a pair.
                assert_eq!(
                    (a.trial, &a.operator, a.initial),
                    (b.trial, &b.operator, b.initial)
                );
            }
            // Each arm but the first is tested against the first.
            assert_eq!(arm.versus_first.is_none(), arm.name == "random-walk");
            if let Some(tests) = arm.versus_first {
                assert!((0.0..=1.0).contains(&tests.t_test_p));
                assert!((0.0..=1.0).contains(&tests.wilcoxon_p));
            }
            assert_eq!(arm.final_cases.is_some(), arm.reuses_cases);
        }
        // The report tests every arm against its reference; against the first, as the
        // runner does.
        let toy_entry = |reference| ReportEntry {
            timeline: None,
            result,
            scenario: "toy",
            operator: "low",
            space: toy.space(),
            landscapes: &[],
            limit: None,
            reference,
            seed: 1,
        };
        let tests = versus_reference(&toy_entry("case-based"));
        for (arm, tests) in result.arms.iter().zip(&tests) {
            assert_eq!(tests.is_none(), arm.name == "case-based");
        }
        let against_first = versus_reference(&toy_entry("random-walk"));
        for (arm, tests) in result.arms.iter().zip(against_first) {
            assert_eq!(tests, arm.versus_first);
        }
        assert!(
            versus_reference(&toy_entry("none"))
                .iter()
                .all(Option::is_none)
        );
        assert!(cb.cases_acquired > 0);
        assert!(
            cb.behaviors.mean < rw.behaviors.mean,
            "{}: case-based {} vs random walk {}",
            result.name,
            cb.behaviors.mean,
            rw.behaviors.mean
        );
    }
    // In the random-operator experiment both operators appear.
    let drawn: std::collections::HashSet<&str> = results[1].arms[0]
        .trials
        .iter()
        .map(|t| t.operator.as_str())
        .collect();
    assert_eq!(drawn.len(), 2);
}

#[test]
fn the_report_folder_holds_every_file() {
    let toy = toy();
    let ops = operators();
    let results = run_experiments(&plans(&toy, &ops, 10), 3, &|_| {}).unwrap();
    let mut entries = entries(&results, &toy);
    // The `low` operator's limit: it trusts only its favourite behavior (36 in the space;
    // 5% of other commands complete by chance), so the paper's protocol needs about
    // 1 + 35/36 behaviors and a free first choice exactly one.
    let settings = LimitSettings {
        runs: 200,
        budget: 0,
        candidates: 4,
        candidate_runs: 400,
        reference_episodes: 0,
    };
    let low = known_operator(&toy, &ops[0].1, Thresholds::default(), settings, 9).unwrap();
    let limit = ExperimentLimit::of(&[("low", &low)], None).unwrap();
    assert_eq!(limit.conflict.trusted_by_all, 1);
    assert!((limit.limit.paper.behaviors - (1.0 + 35.0 / 36.0)).abs() < 0.02);
    assert!((limit.limit.free_first.behaviors - 1.0).abs() < 1e-9);
    entries[0].limit = Some(&limit);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("report");
    let provenance = Provenance {
        tool: "toy".into(),
        version: "1.0".into(),
        git_commit: None,
        command_line: vec!["toy".into(), "run".into()],
        replay: None,
    };
    write_report(&out, &entries, None, "(trials: 10)", 1.5, &provenance).unwrap();
    for name in [
        "table.md",
        "summary.json",
        "trials.jsonl",
        "config.ron",
        "curves-toy-low.svg",
        "finals-toy-random.svg",
        "summary.svg",
        "report.html",
    ] {
        assert!(out.join(name).is_file(), "{name} is missing");
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["elapsed_s"], 1.5);
    assert_eq!(summary["recommended"], lab::RECOMMENDED_ARM);
    assert_eq!(summary["provenance"]["command_line"][1], "run");
    let first = &summary["experiments"][0];
    assert_eq!(first["limit"]["operators"], 1);
    assert_eq!(first["limit"]["lower_bound"], false);
    assert_eq!(summary["experiments"][1]["limit"], serde_json::Value::Null);
    let ratio = first["strategies"]["uniform"]["ratio_to_limit"]["behaviors"]
        .as_f64()
        .unwrap();
    let mean = first["strategies"]["uniform"]["mean"].as_f64().unwrap();
    assert!((ratio - mean / limit.limit.paper.behaviors).abs() < 1e-12);
    let table = std::fs::read_to_string(out.join("table.md")).unwrap();
    assert!(
        table.contains("| toy/low | known-operator limit, random first behavior |"),
        "{table}"
    );
    assert_eq!(first["scenario"], "toy");
    assert_eq!(first["operator"], "low");
    assert_eq!(first["trials"], 10);
    for arm in lab::builtin_arm_names().iter().chain(&["smallest-of-four"]) {
        let s = &first["strategies"][arm];
        for key in [
            "mean",
            "ci95",
            "commands_mean",
            "untrustworthy_mean",
            "found_share",
        ] {
            assert!(s[key].is_f64(), "{arm}: {key}");
        }
        assert!(s["cases_acquired"].is_u64(), "{arm}");
    }
    let lines = std::fs::read_to_string(out.join("trials.jsonl")).unwrap();
    assert_eq!(
        lines.lines().count(),
        2 * (lab::builtin_arm_names().len() + 2) * 10
    );
    let line: serde_json::Value = serde_json::from_str(lines.lines().next().unwrap()).unwrap();
    assert_eq!(line["experiment"], "toy/low");
    assert_eq!(line["arm"], "random-walk");
    assert!(line["final"]["c0"].is_f64());
    let svg = std::fs::read_to_string(out.join("curves-toy-low.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("case-based+smallest-of-four"));
    // The page holds the same figures as the files, inline (the learning curves without
    // their per-trial dots), each with a caption, and fetches nothing.
    let page = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(!page.contains(&svg) && page.contains("toy/low: behaviors evaluated per trial"));
    assert!(page.contains(&std::fs::read_to_string(out.join("summary.svg")).unwrap()));
    assert!(page.contains(&std::fs::read_to_string(out.join("finals-toy-low.svg")).unwrap()));
    assert_eq!(
        page.matches("<figure>").count(),
        page.matches("<figcaption>").count()
    );
    assert!(page.contains("<a href=\"#glossary\">") && page.contains("<h2 id=\"glossary\">"));
    assert!(!page.contains("url(http") && !page.contains("@import"));
    assert!(!page.contains("<script") && !page.contains("<link") && !page.contains("src="));
}

#[test]
fn the_disagreement_table_and_summary_say_how_far_apart_the_operators_rates_are() {
    // Each operator completes its favourite behavior always and every other one 5% of the
    // time: of the 36 behaviors, only the two favourites have rates more than 0.5 apart,
    // and the regions (each operator's favourite alone) do not meet.
    let toy = toy();
    let ops = operators();
    let results = run_experiments(&plans(&toy, &ops, 2), 1, &|_| {}).unwrap();
    let mut entries = entries(&results, &toy);
    let settings = LimitSettings {
        runs: 200,
        budget: 0,
        candidates: 0,
        candidate_runs: 0,
        reference_episodes: 0,
    };
    let known: Vec<_> = ops
        .iter()
        .map(|(_, o)| known_operator(&toy, o, Thresholds::default(), settings, 9).unwrap())
        .collect();
    let plan = ReferencePlan {
        thresholds: Thresholds::default(),
        episodes: 200,
        seed: 3,
    };
    let limit =
        ExperimentLimit::of(&[("low", &known[0]), ("high", &known[1])], Some(plan)).unwrap();
    // The population reference, free to choose its first, takes `low`'s favourite (the
    // lower rank of two equal bets): facing `low` it is accepted; facing `high` it fails
    // (which `low` never lets happen, so `high` is known) and `high`'s favourite follows.
    // Half 1, half 2 behaviors; the limit takes each favourite at once.
    let reference = limit.population_reference.unwrap();
    assert!(
        (reference.free_first.behaviors - 1.5).abs() < 0.01,
        "{reference:?}"
    );
    assert!((limit.limit.free_first.behaviors - 1.0).abs() < 1e-9);
    assert!(reference.paper.untrustworthy > limit.limit.paper.untrustworthy);
    assert!(limit_table(&[]).is_empty());
    assert_eq!(reference.episodes, 200);
    assert_eq!(limit.conflict.jaccard, vec![0.0]);
    entries[0].limit = Some(&limit);
    let table = population_table(&entries);
    assert!(
        table.starts_with("| Experiment | Operators | Trusted by each | Trusted by all | Jaccard (pairs) | Rates >0.5 apart (pairs) | One behavior pleases all |\n"),
        "{table}"
    );
    assert!(
        table.contains("| toy/low | 2 | 1, 1 | 0 (0.0%) | 0.00 | 0.06 | no |"),
        "{table}"
    );
    let summary = summary(&entries, None, 0.0, &Provenance::default());
    let population = &summary["experiments"][0]["limit"]["population"];
    assert_eq!(
        population["pairwise_rate_gap"],
        serde_json::json!([2.0 / 36.0])
    );
    assert_eq!(population["pairwise_jaccard"], serde_json::json!([0.0]));
    let reference = &summary["experiments"][0]["limit"]["population_reference"];
    assert_eq!(reference["episodes_per_operator"], 200);
    assert_eq!(
        reference["free_first_choice"]["behaviors"],
        serde_json::json!(limit.population_reference.unwrap().free_first.behaviors)
    );
    let arm = &summary["experiments"][0]["strategies"]["case-based"];
    assert!(arm["ratio_to_population_reference"]["behaviors"].is_number());
    let limits = limit_table(&entries);
    assert!(
        limits.contains("| toy/low | population reference (× limit) |"),
        "{limits}"
    );
    assert!(limits.contains("(× population reference)"), "{limits}");
}

#[test]
fn trials_cut_off_are_counted_in_the_table_not_shown_clean() {
    let toy = toy();
    let ops = operators();
    let mut plans = plans(&toy, &ops, 8);
    for plan in &mut plans {
        // Five commands cannot reach a threshold of 5 and leave room to adapt.
        plan.max_commands = 4;
        plan.arms.truncate(2);
    }
    let results = run_experiments(&plans, 1, &|_| {}).unwrap();
    let entries = entries(&results, &toy);
    let text = table(&entries);
    assert!(text.contains("(8 cut off)"), "{text}");
}

#[test]
fn the_found_trustworthy_column_appears_only_when_some_trial_falls_short() {
    let toy = toy();
    let ops = operators();
    // Every toy trial ends on the operator's favourite: a column of 100% says nothing.
    let results = run_experiments(&plans(&toy, &ops, 6), 2, &|_| {}).unwrap();
    let text = arms_table(&entries(&results, &toy));
    assert!(!text.contains("Found trustworthy"), "{text}");
    // Trials cut off after four commands never reach the trustworthy threshold: 0.0%.
    let mut short = plans(&toy, &ops, 6);
    for plan in &mut short {
        plan.max_commands = 4;
        plan.arms.truncate(2);
    }
    let results = run_experiments(&short, 2, &|_| {}).unwrap();
    let text = arms_table(&entries(&results, &toy));
    assert!(text.contains("| Found trustworthy |"), "{text}");
    assert!(text.contains("| 0.0% ± 0.0 |"), "{text}");
}

#[test]
fn an_outcome_with_an_undeclared_cause_stops_the_run_with_the_declared_ones() {
    let toy = toy_declaring(&[Cause::from_static("dropped-item")]);
    let ops = operators();
    // Both the chains run in order (case reuse) and those run in parallel report it.
    for arm in [0, 1] {
        let mut plans = plans(&toy, &ops, 5);
        plans.truncate(1);
        let kept = plans[0].arms.remove(arm);
        plans[0].arms = vec![kept];
        let err = run_experiments(&plans, 1, &|_| {}).unwrap_err();
        assert_eq!(
            err.to_string(),
            "toy/low: domain `toy` reported an outcome whose cause `too-slow` is not declared (declared: dropped-item)"
        );
    }
}

#[test]
fn plot_names_never_collide() {
    let toy = toy();
    let ops = operators();
    let plans: Vec<ExperimentPlan<'_, Toy>> = ["toy/low", "toy low", "toy-low"]
        .into_iter()
        .map(|name| {
            let mut plan = plans(&toy, &ops, 3).remove(0);
            plan.name = name.into();
            plan.arms.truncate(2);
            plan
        })
        .collect();
    let results = run_experiments(&plans, 2, &|_| {}).unwrap();
    let entries: Vec<ReportEntry<'_>> = results
        .iter()
        .map(|result| ReportEntry {
            timeline: None,
            result,
            scenario: "toy",
            operator: "low",
            space: toy.space(),
            landscapes: &[],
            limit: None,
            reference: "case-based",
            seed: 1,
        })
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let written = write_report(
        dir.path(),
        &entries,
        None,
        "()",
        0.1,
        &Provenance::default(),
    )
    .unwrap();
    let on_disk = std::fs::read_dir(dir.path()).unwrap().count();
    assert_eq!(written.len(), on_disk);
    // Three experiments, each with a curve and a heatmap, plus the four text files, the
    // three summary figures, the effect sizes, the four figures over trials and the page.
    assert_eq!(on_disk, 3 * 2 + 4 + 3 + 1 + 4 + 1);
}

#[test]
fn a_learned_start_begins_from_the_memory_once_it_holds_a_case() {
    let toy = toy();
    let ops = operators();
    let learned = |name: &str| Arm::builtin(name, RetrieverKind::Linear).unwrap();
    let mut plans = plans(&toy, &ops, 30);
    for plan in &mut plans {
        plan.arms = vec![
            learned("case-based"),
            learned("case-based+learned-start"),
            // A search-only arm reads the cases it retains only to start from them.
            learned("uniform+learned-start"),
        ];
    }
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| run_experiments(&plans, 4, &|_| {}))
            .unwrap()
    };
    let results = run(2);
    assert_eq!(
        trials_jsonl(&entries(&results, &toy)),
        trials_jsonl(&entries(&run(1), &toy))
    );
    for result in &results {
        let random = &result.arms[0];
        for arm in &result.arms[1..] {
            assert_eq!(arm.initial, lab::Initial::Learned);
            let cases = arm
                .final_cases
                .as_ref()
                .expect("an arm that reads cases keeps them");
            let mut held = 0;
            for (t, paired) in arm.trials.iter().zip(&random.trials) {
                assert_eq!(t.operator, paired.operator);
                // An empty memory has no guess: the trial's random behavior, as every arm
                // draws it; afterwards a remembered solution.
                assert_eq!(t.learned_start, held > 0, "{} trial {}", arm.name, t.trial);
                if t.learned_start {
                    assert!(
                        cases.cases()[..held]
                            .iter()
                            .any(|c| c.solution == t.initial)
                    );
                } else {
                    assert_eq!(t.initial, paired.initial);
                }
                held += usize::from(t.report.retained.is_some());
            }
            assert_eq!(held, cases.len());
            // The replay of a later trial is the trial that ran.
            let index = result.arms.iter().position(|a| a.name == arm.name).unwrap();
            let plan = plans.iter().find(|p| p.name == result.name).unwrap();
            let k = plans.iter().position(|p| p.name == result.name).unwrap();
            let (record, _) = lab::trace_trial(plan, k as u64, index, 20, 4).unwrap();
            assert_eq!(record, arm.trials[20]);
        }
    }
    // With one operator who trusts one behavior, the memory's guess is that behavior
    // once it has been found: the learned arms need fewer behaviors.
    let low = &results[0];
    assert!(
        low.arms[1].behaviors.mean < low.arms[0].behaviors.mean,
        "{} vs {}",
        low.arms[1].behaviors.mean,
        low.arms[0].behaviors.mean
    );
    let later: Vec<_> = low.arms[1].trials[10..].iter().collect();
    assert!(
        later
            .iter()
            .all(|t| t.initial == ops[0].1.0 && t.report.behaviors_evaluated == 1)
    );
}
