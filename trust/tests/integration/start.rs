//! The learned first behavior: invariants over random case bases.

use cbr_core::{Behavior, BehaviorSpace, Case, Context, NamedComponent};
use proptest::prelude::*;
use trust::{Evaluated, TrustCaseBase, first_guess};

fn space() -> BehaviorSpace {
    BehaviorSpace::new(vec![
        NamedComponent::numeric("a", "", 0.0, 1.0, 5).unwrap(),
        NamedComponent::numeric("b", "", 0.0, 1.0, 4).unwrap(),
    ])
    .unwrap()
}

/// A case base of up to 12 cases, each with up to 4 rejected behaviors, in the 5 x 4 space.
fn case_base() -> impl Strategy<Value = TrustCaseBase> {
    let behavior = (0u16..5, 0u16..4).prop_map(|(a, b)| Behavior::new(&[a, b]));
    let case = (prop::collection::vec(behavior.clone(), 0..4), behavior);
    prop::collection::vec(case, 0..12).prop_map(|cases| {
        let mut base = TrustCaseBase::new();
        for (problem, solution) in cases {
            base.push(Case {
                problem: problem
                    .into_iter()
                    .map(|behavior| Evaluated {
                        behavior,
                        time: 1.0,
                    })
                    .collect(),
                solution,
            });
        }
        base
    })
}

proptest! {
    #[test]
    fn the_guess_is_the_best_remembered_solution(
        base in case_base(),
        lambda in prop::sample::select(vec![0.8, 0.95, 1.0]),
    ) {
        let space = space();
        let guess = first_guess(&base, &space, lambda, &Context::default());
        // None exactly when the memory is empty; deterministic.
        prop_assert_eq!(guess.is_none(), base.is_empty());
        prop_assert_eq!(guess, first_guess(&base, &space, lambda, &Context::default()));
        let Some(guess) = guess else { return Ok(()) };
        // A remembered solution, named by the earliest case that holds it.
        let cases = base.cases();
        prop_assert_eq!(cases[guess.case.index()].solution, guess.behavior);
        prop_assert!(cases[..guess.case.index()].iter().all(|c| c.solution != guess.behavior));
        // No solution has a higher estimate, computed here the slow way.
        let same = |a: &Behavior, b: &Behavior| a == b || space.similarity(a, b) > lambda;
        for candidate in cases.iter().map(|c| c.solution) {
            let trusted = cases.iter().filter(|c| same(&c.solution, &candidate)).count() as f64;
            let rejected = cases
                .iter()
                .filter(|c| c.problem.evaluated.iter().any(|e| same(&e.behavior, &candidate)))
                .count() as f64;
            let estimate = (trusted + 1.0) / (trusted + rejected + 2.0);
            prop_assert!(estimate <= guess.acceptance() + 1e-12);
        }
        prop_assert!(guess.acceptance() > 0.0 && guess.acceptance() < 1.0);
    }
}
