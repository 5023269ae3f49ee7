//! Goal changes in experiments: interruptions that are not about the behavior, said or
//! unsaid, on a toy domain whose operator trusts every behavior.

use lab::testing::{Bare, ToyDomain};
use lab::{
    Arm, Domain, ExperimentPlan, FeedbackChannel, GoalChanges, GoalChangesOn, Judgement,
    OperatorChoice, check_goal_changes, run_experiments,
};
use trust::AdapterConfig;
use trust::Cause;
use trust::search::Uniform;

const SLOW: Cause = Cause::from_static("slow");

/// Every command completes after 10 s: the operator trusts every behavior, and only a
/// goal change can interrupt one.
fn steady() -> ToyDomain<()> {
    ToyDomain::grid("steady", &[4, 4], &[SLOW], |_, _: &(), _, _| {
        Judgement::completed(1.0, 10.0)
    })
}

fn plan<'a, D: Domain<Operator = ()>>(
    domain: &'a D,
    operators: &'a [(String, ())],
    feedback: Option<FeedbackChannel>,
    goal_changes: Option<GoalChangesOn<'a, ()>>,
) -> ExperimentPlan<'a, D> {
    ExperimentPlan {
        name: "steady".into(),
        domain,
        operators,
        choice: OperatorChoice::Fixed(0),
        trials: 200,
        adapter: AdapterConfig::default(),
        arms: vec![Arm::search_only("uniform", |_| Box::new(Uniform::new()))],
        max_commands: 10_000,
        feedback,
        goal_changes,
        contexts: None,
        stated: None,
    }
}

/// Goal changes every 20 s on average, on `domain`: half the 10 s commands are cut.
fn often(domain: &ToyDomain<()>) -> Option<GoalChangesOn<'_, ()>> {
    Some(GoalChangesOn::goal_changing(
        GoalChanges::new(180.0).unwrap(),
        domain,
    ))
}

#[test]
fn unsaid_goal_changes_give_up_behaviors_the_operator_trusts_and_said_ones_do_not() {
    let domain = steady();
    let operators = [("any".to_owned(), ())];
    let unsaid = &run_experiments(
        &[plan(&domain, &operators, None, often(&domain))],
        1,
        &|_| {},
    )
    .unwrap()[0]
        .arms[0];
    let said_channel = FeedbackChannel::SILENT.saying_goal_changes(1.0).unwrap();
    let said = &run_experiments(
        &[plan(
            &domain,
            &operators,
            Some(said_channel),
            often(&domain),
        )],
        1,
        &|_| {},
    )
    .unwrap()[0]
        .arms[0];
    // Unsaid: P(cut) = 1 - e^-0.5 = 0.39 a command, so five cuts before five completions
    // happen often enough that some trial gives its first behavior up.
    let given_up: usize = unsaid.trials.iter().map(|t| t.report.evaluated.len()).sum();
    assert!(given_up > 0);
    for t in &unsaid.trials {
        let record = t
            .goal_changes
            .expect("a plan with goal changes records them");
        assert_eq!(record.said, 0);
        // The adapter counted every goal change as an interruption: the only ones.
        assert_eq!(t.report.untrustworthy, u64::from(record.happened));
        // Nothing is ever perceived here, so the guess takes every unsaid goal change.
        assert_eq!(record.guessed, record.happened);
        assert_eq!((record.about_behavior, record.false_guesses), (0, 0));
    }
    // Said: no behavior is ever given up; each trial settles on its first behavior after
    // five completions, with its goal changes counted as commands and nothing else.
    let mut happened = 0;
    for t in &said.trials {
        let record = t.goal_changes.unwrap();
        assert_eq!(record.said, record.happened);
        assert!(t.report.evaluated.is_empty());
        assert_eq!(t.report.settled, t.initial);
        assert_eq!(t.report.untrustworthy, 0);
        assert_eq!(t.report.commands, 5 + u64::from(record.happened));
        happened += record.happened;
    }
    // About 0.39 / 0.61 = 0.65 goal changes per completion, five completions a trial.
    let per_trial = f64::from(happened) / 200.0;
    assert!((per_trial - 3.24).abs() < 0.6, "{per_trial}");
}

#[test]
fn a_plan_without_goal_changes_runs_as_before() {
    let domain = steady();
    let operators = [("any".to_owned(), ())];
    let results = run_experiments(&[plan(&domain, &operators, None, None)], 1, &|_| {}).unwrap();
    for t in &results[0].arms[0].trials {
        assert_eq!(t.goal_changes, None);
        assert_eq!((t.report.commands, t.report.untrustworthy), (5, 0));
    }
}

#[test]
fn goal_changes_are_refused_on_a_domain_that_does_not_model_them() {
    // The toy domain without its capabilities: a plan written in Rust could not hold it
    // as `GoalChanging` (the compiler refuses), and a plan read from a file asks it.
    let err = check_goal_changes(&Bare(steady())).err().unwrap();
    assert_eq!(
        err.to_string(),
        "domain `steady` does not model goal changes: it does not implement `GoalChanging` (its `Domain::goal_changing` answers None), so no command could be cut by one; `goal_changes` needs a domain that models them (docs/plugin-guide.md)"
    );
}
