//! A searcher is told what the robot perceives and what the operator says, never the
//! truth: a domain whose true reasons and observations differ, watched by a spy searcher.

use cbr_core::{Behavior, BehaviorSpace, Proposal, Searcher};
use lab::testing::ToyDomain;
use lab::{Arm, ExperimentPlan, OperatorChoice, run_experiments, trace_trial};
use lab::{FeedbackChannel, Judgement};
use proptest::prelude::*;
use rand::{Rng, RngCore};
use std::sync::{Arc, Mutex};
use trust::AdapterConfig;
use trust::search::Uniform;
use trust::{Cause, Evaluated, Explanation, Observations, Outcome, RetrieverKind};

/// The operator's real reason: never perceived by the robot.
const HIDDEN: Cause = Cause::from_static("hidden-reason");
/// Another reason the operator could name.
const OTHER: Cause = Cause::from_static("other-reason");
/// What the robot perceives on every failure: a beep of its own.
const BEEP: Cause = Cause::from_static("beep");

/// A 4 x 4 grid whose operator accepts only behavior (3, 3); every other command fails
/// for the hidden reason while the robot hears a beep.
type Secretive = ToyDomain<()>;

fn secretive() -> Secretive {
    secretive_with_truth(HIDDEN)
}

/// The same domain whose operator's real reason is `truth`.
fn secretive_with_truth(truth: Cause) -> Secretive {
    ToyDomain::grid(
        "secretive",
        &[4, 4],
        &[HIDDEN, OTHER],
        move |behavior, _: &(), _, rng| {
            let duration = rng.random_range(1.0..2.0);
            if *behavior == Behavior::new(&[3, 3]) {
                Judgement::completed(1.0, duration)
            } else {
                Judgement::failed(1.0, truth, duration).observing(Observations::NONE.with(0))
            }
        },
    )
    .perceiving(&[BEEP], &[])
}

/// Uniform search that writes down every outcome it is told.
struct Spy {
    seen: Arc<Mutex<Vec<Outcome>>>,
    search: Uniform,
}

impl Searcher for Spy {
    type Evidence = Evaluated;
    type Feedback = Outcome;

    fn name(&self) -> &str {
        "spy"
    }

    fn propose(
        &mut self,
        space: &BehaviorSpace,
        evaluated: &[Evaluated],
        rng: &mut dyn RngCore,
    ) -> Proposal {
        self.search.propose(space, evaluated, rng)
    }

    fn observe(&mut self, _behavior: &Behavior, outcome: &Outcome) {
        self.seen.lock().unwrap().push(*outcome);
    }
}

/// Every outcome the spy is told over 20 trials under `feedback`, after checking that the
/// trial records keep the truth the spy never saw.
fn told(feedback: Option<FeedbackChannel>) -> Vec<Outcome> {
    told_with_seed(feedback, 5)
}

/// [`told`] with the experiment's master seed.
fn told_with_seed(feedback: Option<FeedbackChannel>, seed: u64) -> Vec<Outcome> {
    let domain = secretive();
    let operators = [("only".to_owned(), ())];
    let seen = Arc::new(Mutex::new(Vec::new()));
    let spy_log = seen.clone();
    let plan = ExperimentPlan {
        name: "secretive".into(),
        domain: &domain,
        operators: &operators,
        choice: OperatorChoice::Fixed(0),
        trials: 20,
        adapter: AdapterConfig::default(),
        arms: vec![Arm::search_only("spy", move |_| {
            Box::new(Spy {
                seen: spy_log.clone(),
                search: Uniform::new(),
            })
        })],
        max_commands: 10_000,
        feedback,
        goal_changes: None,
        contexts: None,
        stated: None,
    };
    let results = run_experiments(&[plan], seed, &|_| {}).unwrap();
    for trial in &results[0].arms[0].trials {
        // Every untrustworthy command's true reason is recorded, for evaluation.
        let expected = match trial.report.untrustworthy {
            0 => None,
            n => Some(u32::try_from(n).unwrap()),
        };
        assert_eq!(trial.true_causes.get(&HIDDEN).copied(), expected);
        assert_eq!(trial.true_causes.len(), usize::from(expected.is_some()));
    }
    let outcomes = seen.lock().unwrap().clone();
    assert!(outcomes.iter().any(Outcome::is_untrustworthy));
    outcomes
}

#[test]
fn a_silent_operator_leaves_the_robot_only_what_it_perceives() {
    for outcome in told(None) {
        assert_eq!(
            outcome.stated, None,
            "nothing was said, the truth never leaks"
        );
        assert_eq!(
            outcome.observed.contains(0),
            outcome.is_untrustworthy(),
            "the beep is perceived on every failure and only then"
        );
    }
}

#[test]
fn an_operator_who_explains_is_heard_rightly_or_wrongly() {
    let honest = FeedbackChannel::new(1.0, 0.0).unwrap();
    for outcome in told(Some(honest)) {
        let expected = outcome.is_untrustworthy().then_some(HIDDEN);
        assert_eq!(outcome.stated, expected);
    }
    // Always wrong: the robot hears the other reason, never the true one.
    let liar = FeedbackChannel::new(1.0, 1.0).unwrap();
    for outcome in told(Some(liar)) {
        let expected = outcome.is_untrustworthy().then_some(OTHER);
        assert_eq!(outcome.stated, expected);
    }
}

#[test]
fn feedback_changes_what_is_said_not_what_happens() {
    // The channel draws on a stream of its own: the same commands and durations (trials
    // may run on several threads, so the spy's log is compared in sorted order).
    let happened = |feedback| {
        let mut commands: Vec<(bool, u64)> = told(feedback)
            .iter()
            .map(|o| (o.is_untrustworthy(), o.duration_s.to_bits()))
            .collect();
        commands.sort_unstable();
        commands
    };
    let explained = happened(Some(FeedbackChannel::new(0.3, 0.1).unwrap()));
    assert_eq!(happened(None), explained);
}

/// Every explanation of 20 trials of two arms (uniform search and case reuse) when the
/// operator's real reason is `truth`, with the share of given-up behaviors the
/// explanations got right.
fn explanations(truth: Cause, feedback: Option<FeedbackChannel>) -> (Vec<Explanation>, u32) {
    let domain = secretive_with_truth(truth);
    let operators = [("only".to_owned(), ())];
    let results = run_experiments(&[two_arms(&domain, &operators, feedback)], 9, &|_| {}).unwrap();
    let mut all = Vec::new();
    let mut right = 0;
    for (a, arm) in results[0].arms.iter().enumerate() {
        right += arm.explained.right;
        // The records keep a digest; the explanations themselves are replayed.
        for trial in 0..20 {
            let (_, commands) =
                trace_trial(&two_arms(&domain, &operators, feedback), 0, a, trial, 9).unwrap();
            all.extend(commands.into_iter().filter_map(|c| c.explanation));
        }
    }
    (all, right)
}

/// 20 trials of uniform search and of case reuse over `domain`.
fn two_arms<'a>(
    domain: &'a Secretive,
    operators: &'a [(String, ())],
    feedback: Option<FeedbackChannel>,
) -> ExperimentPlan<'a, Secretive> {
    ExperimentPlan {
        name: "secretive".into(),
        domain,
        operators,
        choice: OperatorChoice::Fixed(0),
        trials: 20,
        adapter: AdapterConfig::default(),
        arms: vec![
            Arm::search_only("uniform", |_| Box::new(Uniform::new())),
            Arm::case_based(
                "case-based",
                |_| Box::new(Uniform::new()),
                |measure| RetrieverKind::Linear.build_measure(measure),
            ),
        ],
        max_commands: 10_000,
        feedback,
        goal_changes: None,
        contexts: None,
        stated: None,
    }
}

#[test]
fn a_traced_trial_is_the_trial_the_experiment_ran() {
    let domain = secretive();
    let operators = [("only".to_owned(), ())];
    let feedback = Some(FeedbackChannel::new(0.3, 0.1).unwrap());
    let results = run_experiments(&[two_arms(&domain, &operators, feedback)], 9, &|_| {}).unwrap();
    for (arm, trial) in [(0, 0), (1, 13), (0, 19)] {
        let plan = two_arms(&domain, &operators, feedback);
        let (record, commands) = trace_trial(&plan, 0, arm, trial, 9).unwrap();
        assert_eq!(record, results[0].arms[arm].trials[trial as usize]);
        assert_eq!(commands.len() as u64, record.report.commands);
        // The estimate is each behavior's running sum, restarted after every switch.
        let mut estimate = 0.0;
        let mut told = Vec::new();
        for c in &commands {
            estimate += c.outcome.contribution();
            assert_eq!(c.estimate, estimate);
            if let Some(x) = &c.explanation {
                told.push(x.clone());
                estimate = 0.0;
            }
        }
        // One per behavior given up, and the end's; each digested in the record.
        let ended = usize::from(record.report.found_trustworthy);
        assert_eq!(told.len(), record.given_up.len() + ended);
        for (x, digest) in told.iter().zip(&record.given_up) {
            assert_eq!(x.given_up.as_ref().unwrap().decided_reason(), digest.reason);
        }
    }
}

#[test]
fn explanations_are_made_of_what_the_robot_was_told_never_of_the_truth() {
    // Two operators who differ only in their real reason: a silent one tells the robot
    // the same either way, so every explanation is the same, and (the beep names no
    // cause) each infers the two causes at even odds.
    let (hidden, right_hidden) = explanations(HIDDEN, None);
    let (other, right_other) = explanations(OTHER, None);
    assert!(hidden.iter().any(|e| e.given_up.is_some()));
    assert_eq!(hidden, other);
    for e in hidden.iter().filter_map(|e| e.given_up.as_ref()) {
        for r in &e.reasons {
            assert_eq!((r.stated, r.perceived), (0, 0));
            assert!((r.inferred - 0.5).abs() < 1e-12, "{r:?}");
        }
    }
    // The robot cannot decide between even odds: no reason stands out, and the
    // evaluation counts that as wrong whatever the truth.
    for e in hidden.iter().filter_map(|e| e.given_up.as_ref()) {
        assert_eq!(e.decided_reason(), None);
    }
    assert_eq!((right_hidden, right_other), (0, 0));
    // An operator who always explains, rightly: every first reason is the truth.
    let honest = FeedbackChannel::new(1.0, 0.0).unwrap();
    let (told, _) = explanations(OTHER, Some(honest));
    for e in told.iter().filter_map(|e| e.given_up.as_ref()) {
        assert_eq!(e.decided_reason(), Some(OTHER));
        assert_eq!(u64::from(e.reasons[0].stated), e.untrustworthy);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    /// Whatever the seed and the channel, the searcher is told a reason only for an
    /// untrustworthy command and only through the channel: never when it is silent, the
    /// truth when it is never wrong, another cause when it is always wrong; what it
    /// perceives is the beep on every failure.
    #[test]
    fn the_truth_reaches_a_searcher_only_through_the_channel(
        seed in any::<u64>(),
        explains in prop::sample::select(vec![0.0, 0.3, 1.0]),
        wrong in prop::sample::select(vec![0.0, 1.0]),
    ) {
        let channel = FeedbackChannel::new(explains, wrong).unwrap();
        for outcome in told_with_seed(Some(channel), seed) {
            prop_assert_eq!(outcome.observed.contains(0), outcome.is_untrustworthy());
            match outcome.stated {
                None => {}
                Some(reason) => {
                    prop_assert!(outcome.is_untrustworthy() && explains > 0.0);
                    prop_assert_eq!(reason == HIDDEN, wrong == 0.0);
                }
            }
        }
    }
}
