//! The known-operator limit is a floor: on random small landscapes whose outcome
//! distributions are known exactly, no arm's mean (behaviors, commands, untrustworthy
//! commands) falls below the limit by more than its noise.

use lab::Judgement;
use lab::reference::limit::{DEFAULT_MAX_STATES, Limit, Step, solve_walk};
use lab::testing::ToyDomain;
use lab::{Arm, ExperimentPlan, OperatorChoice, run_experiments};
use proptest::prelude::*;
use rand::Rng;
use trust::AdapterConfig;
use trust::{Cause, RetrieverKind, Thresholds};

const DULL: Cause = Cause::from_static("dull");

/// One component of `values` values; behavior `i` completes with probability `p[i]`, the
/// operator.
fn table(values: u16) -> ToyDomain<Vec<f64>> {
    ToyDomain::grid(
        "table",
        &[values],
        &[DULL],
        |behavior, p: &Vec<f64>, _, rng| {
            if rng.random::<f64>() < p[usize::from(behavior.get(0))] {
                Judgement::completed(1.0, 1.0)
            } else {
                Judgement::interrupted(1.0, DULL, 1.0)
            }
        },
    )
}

/// The exact limit of an operator with completion probabilities `p` (weights 1).
fn exact_limit(p: &[f64]) -> Limit {
    let walks: Vec<_> = p
        .iter()
        .map(|&q| {
            let steps = [
                Step {
                    prob: q,
                    delta: 1.0,
                    untrustworthy: false,
                },
                Step {
                    prob: 1.0 - q,
                    delta: -1.0,
                    untrustworthy: true,
                },
            ];
            solve_walk(&steps, Thresholds::default(), DEFAULT_MAX_STATES).unwrap()
        })
        .collect();
    Limit::from_outcomes(&walks).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 6, ..ProptestConfig::default() })]

    #[test]
    fn no_arm_beats_the_limit_beyond_noise(
        p in prop::collection::vec(prop::sample::select(vec![0.0, 0.3, 0.5, 0.7, 0.9, 1.0]), 3..7)
            .prop_filter("some behavior can be trusted", |p| p.iter().any(|&q| q > 0.0)),
    ) {
        let values = u16::try_from(p.len()).unwrap();
        let table = table(values);
        let operators = [("p".to_owned(), p.clone())];
        let plan = ExperimentPlan {
            name: "table".into(),
            domain: &table,
            operators: &operators,
            choice: OperatorChoice::Fixed(0),
            trials: 200,
            adapter: AdapterConfig::default(),
            arms: lab::builtin_arm_names()
                .iter()
                .map(|name| Arm::builtin(name, RetrieverKind::Linear).unwrap())
                .collect(),
            max_commands: 100_000,
            feedback: None,
            goal_changes: None,
            contexts: None,
            stated: None,
        };
        let result = run_experiments(&[plan], 11, &|_| {}).unwrap().remove(0);
        let limit = exact_limit(&p).paper;
        for arm in &result.arms {
            // Four standard errors (the CI is about two) below the limit is noise no more;
            // where every trial came out alike the CI is 0, and 2% of the limit stands for
            // the chance that 200 trials never met the rare longer episode.
            for (name, mean, limit) in [
                ("behaviors", arm.behaviors, limit.behaviors),
                ("commands", arm.commands, limit.commands),
                ("untrustworthy", arm.untrustworthy, limit.untrustworthy),
            ] {
                prop_assert!(
                    mean.mean + 2.0 * mean.ci95 + 0.02 * limit >= limit,
                    "{} {name}: {} ± {} below the limit {limit} on {p:?}",
                    arm.name, mean.mean, mean.ci95
                );
            }
        }
    }
}
