//! An experiment weighs contexts as its domain declares them, as `serve` does: a domain
//! that declares two contexts fully alike runs its trials exactly as if there were no
//! contexts, and one that matches them exactly (the default) reuses no case across them.

use cbr_core::{Behavior, Context, ContextSpace, ContextVariable};
use lab::testing::ToyDomain;
use lab::{Arm, ExperimentPlan, Judgement, OperatorChoice, TrialContexts, run_experiments};
use rand::Rng;
use trust::search::Uniform;
use trust::{AdapterConfig, Cause, RetrieverKind};

const WRONG: Cause = Cause::from_static("wrong");

/// A 6 x 6 grid whose one operator accepts only (5, 5), in every context alike, whose
/// robot knows its cargo: two values, alike to `alike` (1 on the diagonal).
fn domain(alike: Option<f64>) -> ToyDomain<()> {
    let mut cargo = ContextVariable::new("cargo", &["normal", "hazardous"]);
    cargo.similarity = alike.map(|s| vec![vec![1.0, s], vec![s, 1.0]]);
    ToyDomain::grid("toy", &[6, 6], &[WRONG], |behavior, _: &(), _, rng| {
        let duration = rng.random_range(1.0..2.0);
        if *behavior == Behavior::new(&[5, 5]) {
            Judgement::completed(1.0, duration)
        } else {
            Judgement::failed(1.0, WRONG, duration)
        }
    })
    .in_contexts(ContextSpace::new(vec![cargo]).unwrap())
}

/// The case-based arm's trials: in normal and hazardous cargo in turn, or, without
/// `contexts`, all in the default context.
fn trials(domain: &ToyDomain<()>, contexts: bool) -> Vec<lab::TrialRecord> {
    let operators = [("only".to_owned(), ())];
    let cycle = vec![
        Context::default(),
        lab::Domain::contexts(domain)
            .context([("cargo", "hazardous")])
            .unwrap(),
    ];
    let plan = ExperimentPlan {
        name: "toy".into(),
        domain,
        operators: &operators,
        choice: OperatorChoice::Fixed(0),
        trials: 30,
        adapter: AdapterConfig::default(),
        arms: vec![Arm::case_based(
            "case-based",
            |_| Box::new(Uniform::new()),
            |measure| RetrieverKind::InvertedIndex.build_measure(measure),
        )],
        max_commands: 10_000,
        feedback: None,
        goal_changes: None,
        contexts: contexts.then(|| TrialContexts::new(cycle).unwrap()),
        stated: None,
    };
    let mut results = run_experiments(&[plan], 3, &|_| {}).unwrap();
    results.remove(0).arms.remove(0).trials
}

/// What a trial did, its context aside.
fn course(trial: &lab::TrialRecord) -> (Behavior, u64, u32, u32) {
    (
        trial.report.settled,
        trial.report.commands,
        trial.report.reused,
        trial.report.searched,
    )
}

#[test]
fn contexts_declared_alike_are_no_contexts_and_exact_ones_share_no_case() {
    let without: Vec<_> = trials(&domain(Some(1.0)), false)
        .iter()
        .map(course)
        .collect();
    let alike: Vec<_> = trials(&domain(Some(1.0)), true)
        .iter()
        .map(course)
        .collect();
    assert_eq!(alike, without);
    let exact = trials(&domain(None), true);
    assert_ne!(exact.iter().map(course).collect::<Vec<_>>(), without);
    // The first hazardous trial finds no case to reuse, though the normal one before it
    // retained one.
    assert!(exact[0].report.retained.is_some());
    assert_eq!(exact[1].report.reused, 0);
    assert!(
        without[1].2 > 0,
        "the same trial reuses the case without contexts"
    );
}
