//! The searcher conformance kit: [`check_searcher`] states what every search strategy
//! must do and checks it with proptest on random spaces and random evidence.

use crate::search::TrustSearcher;
use crate::{Cause, Evaluated, Observations, Outcome};
use cbr_core::testing::{SpaceShape, behavior_spaces};
use cbr_core::{Behavior, BehaviorSpace, NamedComponent, Proposal, Rationale};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestCaseError, TestRunner};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::HashSet;

/// Drives `searcher` through one episode on `space` with outcomes drawn from `rng`: each
/// proposed behavior gets a few commands, is evaluated, and the searcher is asked again,
/// until it says the space is exhausted. Returns every proposal.
fn drive(
    searcher: &mut TrustSearcher,
    space: &BehaviorSpace,
    rng: &mut ChaCha8Rng,
) -> Result<Vec<Proposal>, TestCaseError> {
    let mut evaluated: Vec<Evaluated> = Vec::new();
    let mut proposals = Vec::new();
    let mut current = space.draw(rng);
    searcher.begin_episode(space, &current);
    loop {
        let commands = rng.random_range(1..4);
        for _ in 0..commands {
            let outcome = if rng.random_bool(0.3) {
                Outcome::completed(1.0, 1.0)
            } else if rng.random_bool(0.5) {
                Outcome::failed(0.5, 2.0).stating(Some(Cause::from_static("dropped-item")))
            } else {
                Outcome::interrupted(1.0, 3.0).observing(Observations::NONE.with(1))
            };
            searcher.observe(&current, &outcome);
        }
        evaluated.push(Evaluated {
            behavior: current,
            time: rng.random_range(0.0..10.0),
        });
        let proposal = searcher.propose(space, &evaluated, rng);
        proposals.push(proposal);
        let tried: HashSet<Behavior> = evaluated.iter().map(|e| e.behavior).collect();
        match proposal {
            Proposal::Next(b) => {
                prop_assert!(space.contains(&b), "{b:?} is not in the space");
                check_rationale(&searcher.rationale(&b))?;
                prop_assert!(
                    !tried.contains(&b),
                    "{b:?} was already evaluated while {} behaviors were untried",
                    space.size() - tried.len() as u64
                );
                current = b;
            }
            Proposal::Exhausted { keep } => {
                prop_assert_eq!(
                    tried.len() as u64,
                    space.size(),
                    "exhausted while behaviors were untried"
                );
                prop_assert!(tried.contains(&keep), "keeps {:?}, never evaluated", keep);
                break;
            }
        }
        prop_assert!(
            proposals.len() as u64 <= space.size(),
            "more proposals than behaviors"
        );
    }
    searcher.end_episode(&evaluated, None);
    Ok(proposals)
}

/// What a rationale must be: a short, plain, one-line text (at most 160 bytes) and a
/// confidence that is a probability.
fn check_rationale(rationale: &Rationale) -> Result<(), TestCaseError> {
    let text = match rationale {
        Rationale::Explores { how } => how,
        Rationale::Expects { what, confidence } => {
            if let Some(p) = confidence {
                prop_assert!(
                    (0.0..=1.0).contains(p),
                    "the rationale's confidence {p} is not a probability"
                );
            }
            what
        }
    };
    prop_assert!(
        !text.trim().is_empty() && text.len() <= 160 && !text.contains('\n'),
        "a rationale is one plain line of at most 160 bytes, got {text:?}"
    );
    Ok(())
}

/// Checks the properties every searcher must have, for searchers made by `build`:
/// - it never proposes a behavior outside the space, nor one evaluated in the episode
///   while unevaluated ones remain, and says `Exhausted` only when every behavior has
///   been evaluated, keeping one of them;
/// - a one-behavior space and a fully evaluated space are handled;
/// - it is deterministic: the same seed and evidence give the same proposals;
/// - it stays correct across episodes (two episodes in a row on one searcher);
/// - every proposal's rationale ([`cbr_core::Searcher::rationale`]) is one plain line with
///   a confidence that is a probability;
/// - a searcher that says it does not learn across episodes
///   ([`cbr_core::Searcher::learns_across_episodes`]) proposes after an earlier episode
///   exactly what a fresh one proposes (or experiment runners, which give such searchers
///   a fresh instance per trial, would silently change what it does).
///
/// # Panics
/// With the failing case (proptest's minimal one) when a property does not hold.
pub fn check_searcher(build: impl Fn() -> Box<TrustSearcher>) {
    let mut runner = TestRunner::new(Config {
        cases: 64,
        failure_persistence: None,
        ..Config::default()
    });
    let result = runner.run(&(behavior_spaces(SpaceShape::small()), any::<u64>()), |(space, seed)| {
        let mut first = build();
        let a = drive(first.as_mut(), &space, &mut ChaCha8Rng::seed_from_u64(seed))?;
        // A second episode on the same searcher.
        let after = drive(
            first.as_mut(),
            &space,
            &mut ChaCha8Rng::seed_from_u64(seed ^ 1),
        )?;
        let b = drive(
            build().as_mut(),
            &space,
            &mut ChaCha8Rng::seed_from_u64(seed),
        )?;
        prop_assert_eq!(a, b, "not deterministic for a seed");
        if !first.learns_across_episodes() {
            let fresh = drive(
                build().as_mut(),
                &space,
                &mut ChaCha8Rng::seed_from_u64(seed ^ 1),
            )?;
            prop_assert_eq!(
                after,
                fresh,
                "proposes differently after an earlier episode, though `learns_across_episodes` says it does not learn: return `true` from it"
            );
        }
        Ok(())
    });
    if let Err(e) = result {
        panic!("searcher check failed: {e}");
    }
    // One behavior: the first proposal with no evidence is that behavior; once it is
    // evaluated the space is exhausted and it is kept.
    let one = BehaviorSpace::new(vec![
        NamedComponent::numeric("only", "", 0.0, 1.0, 1).expect("a valid grid"),
    ])
    .expect("a valid space");
    let only = Behavior::new(&[0]);
    let mut rng = ChaCha8Rng::seed_from_u64(0);
    let mut searcher = build();
    searcher.begin_episode(&one, &only);
    assert_eq!(
        searcher.propose(&one, &[], &mut rng),
        Proposal::Next(only),
        "with no evidence the one behavior is proposed"
    );
    searcher.observe(
        &only,
        &Outcome::failed(1.0, 1.0).stating(Some(Cause::from_static("stalled"))),
    );
    let evaluated = [Evaluated {
        behavior: only,
        time: 1.0,
    }];
    assert_eq!(
        searcher.propose(&one, &evaluated, &mut rng),
        Proposal::Exhausted { keep: only },
        "a fully evaluated one-behavior space keeps its behavior"
    );
}
