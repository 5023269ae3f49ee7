//! A learned first behavior: the case memory's best guess of a behavior that an operator
//! the robot does not yet know will trust (docs/search-strategies.md#a-learned-first-behavior).
//!
//! The paper starts every episode from a random behavior. Before the first command there
//! is no evidence about the operator at hand, so Algorithm 1 (which compares the episode's
//! evaluated pairs with each case's) has nothing to match; what the memory can still say
//! is how the operators it met received each behavior. Every case is one operator's
//! episode: its solution is a behavior that operator trusted, its problem the behaviors
//! that operator rejected first. For each distinct remembered solution `s`, in case-base
//! order:
//!
//! - `trusted`: the cases whose solution is `s` or similar to it above `lambda`;
//! - `rejected`: the cases whose problem holds a behavior that is `s` or similar to it
//!   above `lambda` (Algorithm 2's notion of "the same behavior");
//! - its acceptance estimate, `(trusted + 1) / (trusted + rejected + 2)`: the share of
//!   remembered operators who accepted it, with Laplace's rule of succession so that a
//!   solution met once does not outrank one trusted by many and rejected by few.
//!
//! Only the cases learned in the robot's context count (an exact match, as retrieval's
//! default): what operators accepted with normal cargo says little of what they accept
//! with hazardous cargo.
//!
//! [`first_guess`] is the solution with the highest estimate; ties go to the most often
//! trusted, then to the earliest case. It is a remembered solution or `None` (an empty
//! case base, or none learned in the context): the caller then keeps its own choice (the paper's random draw). This
//! module reads only the case base; it is neither Algorithm 1 nor a search strategy.

use crate::{TrustCase, TrustCaseBase};
use cbr_core::{Behavior, BehaviorSpace, CaseId, Context};

/// The memory's best guess of a first behavior, with the tallies behind it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FirstGuess {
    /// The behavior to start from: a remembered case's solution.
    pub behavior: Behavior,
    /// The earliest case whose solution it is.
    pub case: CaseId,
    /// Cases whose solution is this behavior or similar to it above `lambda`.
    pub trusted: u32,
    /// Cases whose problem holds this behavior or one similar to it above `lambda`.
    pub rejected: u32,
}

impl FirstGuess {
    /// The Laplace-smoothed share of remembered operators who accepted the behavior,
    /// `(trusted + 1) / (trusted + rejected + 2)`.
    pub fn acceptance(&self) -> f64 {
        f64::from(self.trusted + 1) / f64::from(self.trusted + self.rejected + 2)
    }

    /// Whether `self` is a better guess than `other` by the module's rule (higher
    /// acceptance, then more often trusted); equal guesses are left to case-base order.
    /// The acceptances are compared as exact fractions.
    fn beats(&self, other: &FirstGuess) -> bool {
        let estimate = |g: &FirstGuess| {
            (
                u64::from(g.trusted) + 1,
                u64::from(g.trusted) + u64::from(g.rejected) + 2,
            )
        };
        let ((a, b), (c, d)) = (estimate(self), estimate(other));
        (a * d, self.trusted) > (c * b, other.trusted)
    }
}

/// The memory's best guess of a first behavior for an operator it knows nothing about
/// in `context` (the module's rule), or `None` when no case of `cases` was learned in it.
/// `lambda` is Algorithm 2's similarity threshold: behaviors more similar than it count
/// as the same.
pub fn first_guess(
    cases: &TrustCaseBase,
    space: &BehaviorSpace,
    lambda: f64,
    context: &Context,
) -> Option<FirstGuess> {
    let same = |a: &Behavior, b: &Behavior| a == b || space.similarity(a, b) > lambda;
    let in_context = |case: &TrustCase| case.problem.context == *context;
    let mut best: Option<FirstGuess> = None;
    for (id, case) in cases.iter().filter(|(_, case)| in_context(case)) {
        let candidate = case.solution;
        // Each distinct solution once, under its earliest case.
        if cases.cases()[..id.index()]
            .iter()
            .any(|earlier| in_context(earlier) && earlier.solution == candidate)
        {
            continue;
        }
        let count = |hit: &dyn Fn(&TrustCase) -> bool| {
            let hits = cases.cases().iter().filter(|c| in_context(c) && hit(c));
            u32::try_from(hits.count()).unwrap_or(u32::MAX)
        };
        let guess = FirstGuess {
            behavior: candidate,
            case: id,
            trusted: count(&|c| same(&c.solution, &candidate)),
            rejected: count(&|c| {
                c.problem
                    .evaluated
                    .iter()
                    .any(|e| same(&e.behavior, &candidate))
            }),
        };
        if best.as_ref().is_none_or(|b| guess.beats(b)) {
            best = Some(guess);
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Evaluated, TrustProblem};
    use cbr_core::{Case, ContextSpace, ContextVariable, NamedComponent};

    /// One numeric component of 11 values on [0, 1]: adjacent values are 0.9 similar, so
    /// every value stands alone at the paper's lambda (0.95).
    fn line() -> BehaviorSpace {
        BehaviorSpace::new(vec![
            NamedComponent::numeric("x", "", 0.0, 1.0, 11).unwrap(),
        ])
        .unwrap()
    }

    fn b(i: u16) -> Behavior {
        Behavior::new(&[i])
    }

    fn case(rejected: &[u16], trusted: u16) -> TrustCase {
        let evaluated = rejected.iter().map(|&i| Evaluated {
            behavior: b(i),
            time: 10.0,
        });
        Case {
            problem: TrustProblem::new(evaluated.collect()),
            solution: b(trusted),
        }
    }

    fn base(cases: Vec<TrustCase>) -> TrustCaseBase {
        let mut base = TrustCaseBase::new();
        for c in cases {
            base.push(c);
        }
        base
    }

    #[test]
    fn an_empty_memory_has_no_guess() {
        assert_eq!(
            first_guess(&TrustCaseBase::new(), &line(), 0.95, &Context::default()),
            None
        );
    }

    #[test]
    fn acceptance_by_hand() {
        // Three operators: two trusted 5, one of them after rejecting 3; the third
        // rejected 5 and trusted 3.
        //   5: trusted 2, rejected 1 -> 3/5 = 0.6
        //   3: trusted 1, rejected 1 -> 2/4 = 0.5
        let cases = base(vec![case(&[3], 5), case(&[], 5), case(&[5, 9], 3)]);
        let guess = first_guess(&cases, &line(), 0.95, &Context::default()).unwrap();
        assert_eq!(guess.behavior, b(5));
        assert_eq!(guess.case, CaseId(0));
        assert_eq!((guess.trusted, guess.rejected), (2, 1));
        assert!((guess.acceptance() - 0.6).abs() < 1e-12);
    }

    #[test]
    fn laplace_keeps_one_lucky_case_below_a_well_tried_one() {
        // 7: trusted once, never rejected -> 2/3 = 0.667.
        // 2: trusted 8 times, rejected twice -> 9/12 = 0.75: the better bet.
        let mut cases = vec![case(&[], 7)];
        cases.extend((0..8).map(|_| case(&[], 2)));
        cases.extend((0..2).map(|_| case(&[2], 10)));
        let guess = first_guess(&base(cases), &line(), 0.95, &Context::default()).unwrap();
        assert_eq!(guess.behavior, b(2));
        assert_eq!((guess.trusted, guess.rejected), (8, 2));
        // 10 (trusted twice, rejected never: 3/4) ties with 2 at 0.75; 2 was trusted
        // more often.
        assert_eq!(guess.acceptance(), 0.75);
    }

    #[test]
    fn ties_go_to_the_more_trusted_then_to_the_earliest() {
        // 4: 1 trusted, 0 rejected -> 2/3; 8: 1 trusted, 0 rejected -> 2/3: the earliest.
        let cases = base(vec![case(&[1], 8), case(&[1], 4)]);
        assert_eq!(
            first_guess(&cases, &line(), 0.95, &Context::default())
                .unwrap()
                .behavior,
            b(8)
        );
        // 4: 3 trusted, 1 rejected -> 4/6; 8: 1 trusted, 0 rejected -> 2/3: equal, 4 more
        // trusted.
        let cases = base(vec![
            case(&[], 8),
            case(&[], 4),
            case(&[], 4),
            case(&[4], 4),
        ]);
        let guess = first_guess(&cases, &line(), 0.95, &Context::default()).unwrap();
        assert_eq!((guess.behavior, guess.case), (b(4), CaseId(1)));
        assert_eq!((guess.trusted, guess.rejected), (3, 1));
    }

    #[test]
    fn similar_behaviors_count_as_the_same_above_lambda() {
        // At lambda 0.85, values one step apart (0.9 similar) are the same behavior; two
        // steps (0.8) are not.
        //   5: trusted by cases 0 and 1 (6 is one step off), rejected by case 2 (4): 3/5.
        //   6: trusted by cases 0 (5) and 1; 4 is two steps off: 3/4.
        //   9: trusted by case 2 alone: 2/3.
        let cases = base(vec![case(&[], 5), case(&[], 6), case(&[4], 9)]);
        let guess = first_guess(&cases, &line(), 0.85, &Context::default()).unwrap();
        assert_eq!(guess.behavior, b(6));
        assert_eq!((guess.trusted, guess.rejected), (2, 0));
        // At the paper's 0.95 they stand alone: 5, 6 and 9 are each trusted once and
        // rejected never (2/3); the earliest wins.
        let guess = first_guess(&cases, &line(), 0.95, &Context::default()).unwrap();
        assert_eq!(
            (guess.behavior, guess.trusted, guess.rejected),
            (b(5), 1, 0)
        );
    }

    #[test]
    fn a_behavior_rejected_more_often_than_trusted_still_is_a_guess() {
        // The memory only ever holds solutions: the best of them, however poor.
        let cases = base(vec![case(&[6], 6), case(&[6], 3), case(&[3, 6], 9)]);
        let guess = first_guess(&cases, &line(), 0.95, &Context::default()).unwrap();
        // 6: trusted 1, rejected 3 -> 2/6; 3: trusted 1, rejected 1 -> 2/4; 9: 1, 0 -> 2/3.
        assert_eq!(guess.behavior, b(9));
    }

    #[test]
    fn only_cases_learned_in_the_context_count() {
        let space = ContextSpace::new(vec![ContextVariable::new(
            "cargo",
            &["normal", "hazardous"],
        )])
        .unwrap();
        let hazardous = space.context([("cargo", "hazardous")]).unwrap();
        let in_hazard = |rejected: &[u16], trusted: u16| {
            let mut c = case(rejected, trusted);
            c.problem.context = hazardous.clone();
            c
        };
        // Normal cargo: 5 trusted twice. Hazardous cargo: 2 trusted once, 5 rejected once.
        let cases = base(vec![case(&[], 5), in_hazard(&[5], 2), case(&[2], 5)]);
        let normal = first_guess(&cases, &line(), 0.95, &Context::default()).unwrap();
        // In normal cargo 2 was rejected once and never trusted: 5 (3/4) wins.
        assert_eq!(
            (normal.behavior, normal.trusted, normal.rejected),
            (b(5), 2, 0)
        );
        let hazard = first_guess(&cases, &line(), 0.95, &hazardous).unwrap();
        assert_eq!((hazard.behavior, hazard.case), (b(2), CaseId(1)));
        assert_eq!((hazard.trusted, hazard.rejected), (1, 0));
        // A context no case was learned in has no guess.
        let emergency = ContextSpace::new(vec![ContextVariable::new("cargo", &["normal", "x"])])
            .unwrap()
            .context([("cargo", "x")])
            .unwrap();
        assert_eq!(first_guess(&cases, &line(), 0.95, &emergency), None);
    }
}
