//! The searcher conformance kit: [`check_searcher`] states what every search strategy
//! must do and checks it with proptest on random spaces and random evidence;
//! [`searcher_conformance`] checks the same on the spaces a caller gives (a domain's own)
//! and returns the rule broken, with its case, instead of panicking.

use crate::search::TrustSearcher;
use crate::{Cause, Evaluated, Observations, Outcome};
use cbr_core::testing::{SpaceShape, behavior_spaces};
use cbr_core::{Behavior, BehaviorSpace, NamedComponent, Proposal, Rationale};
use proptest::prelude::*;
use proptest::strategy::{BoxedStrategy, Just};
use proptest::test_runner::{Config, TestCaseError, TestError, TestRunner};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::HashSet;

/// A rule of the searcher contract ([`check_searcher`] lists them).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum SearcherRule {
    /// A proposal outside the space.
    InSpace,
    /// A proposal already evaluated in the episode while untried behaviors remained.
    Untried,
    /// `Exhausted` while behaviors were untried.
    ExhaustedOnlyWhenAllTried,
    /// `Exhausted` keeping a behavior the episode never evaluated.
    KeepsAnEvaluated,
    /// More proposals in an episode than behaviors in the space.
    AtMostOneProposalPerBehavior,
    /// A rationale that is not one plain line, or a confidence that is not a probability.
    Rationale,
    /// Different proposals for the same seed and evidence (randomness drawn from elsewhere
    /// than the generator it is given, or from a clock).
    Deterministic,
    /// A searcher that says it does not learn across episodes proposes differently after
    /// an earlier episode than a fresh one.
    ForgetsUnlessItLearns,
}

impl SearcherRule {
    /// What to change in a Rust searcher that breaks the rule.
    pub fn advice(self) -> &'static str {
        match self {
            Self::InSpace => "propose only behaviors of the space given",
            Self::Untried => "propose a behavior not in `evaluated` while any is untried",
            Self::ExhaustedOnlyWhenAllTried | Self::AtMostOneProposalPerBehavior => {
                "say `Exhausted` exactly when every behavior of the space was evaluated"
            }
            Self::KeepsAnEvaluated => "keep a behavior of `evaluated` when exhausted",
            Self::Rationale => {
                "make `rationale` one plain line of at most 160 bytes, its confidence in [0, 1]"
            }
            Self::Deterministic => "draw every random number from the generator `propose` is given",
            Self::ForgetsUnlessItLearns => {
                "return `true` from `learns_across_episodes`: the searcher carries something from one episode to the next"
            }
        }
    }

    /// The rule's short name (stable, for messages and other languages' advice).
    pub fn name(self) -> &'static str {
        match self {
            Self::InSpace => "in-space",
            Self::Untried => "untried",
            Self::ExhaustedOnlyWhenAllTried => "exhausted-only-when-all-tried",
            Self::KeepsAnEvaluated => "keeps-an-evaluated",
            Self::AtMostOneProposalPerBehavior => "one-proposal-per-behavior",
            Self::Rationale => "rationale",
            Self::Deterministic => "deterministic",
            Self::ForgetsUnlessItLearns => "forgets-unless-it-learns",
        }
    }
}

/// A rule a searcher broke, on one case: the space, the episode's evaluated behaviors up
/// to the failing proposal, and that proposal.
#[derive(Clone, Debug)]
pub struct SearcherFailure {
    /// The rule broken.
    pub rule: SearcherRule,
    /// What happened, in one sentence (Rust terms).
    pub message: String,
    /// The space searched (boxed: a failure travels in a `Result`).
    pub space: Box<BehaviorSpace>,
    /// The episode's evaluated behaviors when the searcher failed, in order.
    pub evaluated: Vec<Evaluated>,
    /// The failing proposal (`None`: the rule is about the episode as a whole).
    pub proposal: Option<Proposal>,
    /// The seed the episode's outcomes and the searcher's generator were drawn from.
    pub seed: u64,
}

impl std::fmt::Display for SearcherFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "searcher check failed ({}): {}",
            self.rule.name(),
            self.message
        )
    }
}

/// What breaks a rule inside one driven episode, before the space and seed are attached.
struct Broken {
    rule: SearcherRule,
    message: String,
    evaluated: Vec<Evaluated>,
    proposal: Option<Proposal>,
}

impl Broken {
    fn new(rule: SearcherRule, message: String) -> Self {
        Self {
            rule,
            message,
            evaluated: Vec::new(),
            proposal: None,
        }
    }

    fn at(mut self, evaluated: &[Evaluated], proposal: Proposal) -> Self {
        self.evaluated = evaluated.to_vec();
        self.proposal = Some(proposal);
        self
    }
}

/// Proposals an episode on a given space (a domain's own, often thousands of behaviors)
/// is driven for; episodes on the kit's small random spaces run to exhaustion.
const GIVEN_SPACE_PROPOSALS: u64 = 24;

/// Fresh searchers compared with one another before a difference after an earlier
/// episode is blamed on learning rather than on randomness drawn from elsewhere.
const FRESH_AGAIN: usize = 8;

/// Cases checked on a given space (each case is four episodes).
const GIVEN_SPACE_CASES: u32 = 12;

/// Drives `searcher` through one episode on `space` with outcomes drawn from `rng`: each
/// proposed behavior gets a few commands, is evaluated, and the searcher is asked again,
/// until it says the space is exhausted or it has made `most` proposals. Returns every
/// proposal.
fn drive(
    searcher: &mut TrustSearcher,
    space: &BehaviorSpace,
    rng: &mut ChaCha8Rng,
    most: u64,
) -> Result<Vec<Proposal>, Broken> {
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
                if !space.contains(&b) {
                    return Err(Broken::new(
                        SearcherRule::InSpace,
                        format!("{b:?} is not in the space"),
                    )
                    .at(&evaluated, proposal));
                }
                check_rationale(&searcher.rationale(&b))
                    .map_err(|broken| broken.at(&evaluated, proposal))?;
                if tried.contains(&b) {
                    return Err(Broken::new(
                        SearcherRule::Untried,
                        format!(
                            "{b:?} was already evaluated while {} behaviors were untried",
                            space.size() - tried.len() as u64
                        ),
                    )
                    .at(&evaluated, proposal));
                }
                current = b;
            }
            Proposal::Exhausted { keep } => {
                if tried.len() as u64 != space.size() {
                    return Err(Broken::new(
                        SearcherRule::ExhaustedOnlyWhenAllTried,
                        format!(
                            "exhausted while {} of {} behaviors were untried",
                            space.size() - tried.len() as u64,
                            space.size()
                        ),
                    )
                    .at(&evaluated, proposal));
                }
                if !tried.contains(&keep) {
                    return Err(Broken::new(
                        SearcherRule::KeepsAnEvaluated,
                        format!("keeps {keep:?}, never evaluated"),
                    )
                    .at(&evaluated, proposal));
                }
                break;
            }
        }
        if proposals.len() as u64 > space.size() {
            return Err(Broken::new(
                SearcherRule::AtMostOneProposalPerBehavior,
                "more proposals than behaviors".into(),
            )
            .at(&evaluated, proposal));
        }
        if proposals.len() as u64 >= most {
            break;
        }
    }
    searcher.end_episode(&evaluated, None);
    Ok(proposals)
}

/// What a rationale must be: a short, plain, one-line text (at most 160 bytes) and a
/// confidence that is a probability.
fn check_rationale(rationale: &Rationale) -> Result<(), Broken> {
    let text = match rationale {
        Rationale::Explores { how } => how,
        Rationale::Expects { what, confidence } => {
            if let Some(p) = confidence
                && !(0.0..=1.0).contains(p)
            {
                return Err(Broken::new(
                    SearcherRule::Rationale,
                    format!("the rationale's confidence {p} is not a probability"),
                ));
            }
            what
        }
    };
    if text.trim().is_empty() || text.len() > 160 || text.contains('\n') {
        return Err(Broken::new(
            SearcherRule::Rationale,
            format!("a rationale is one plain line of at most 160 bytes, got {text:?}"),
        ));
    }
    Ok(())
}

/// Every rule on one space and seed: an episode, a second on the same searcher, the same
/// episode on a fresh searcher, and (for a searcher that does not learn) the second
/// episode on a fresh one.
fn check_case(
    build: &dyn Fn() -> Box<TrustSearcher>,
    space: &BehaviorSpace,
    seed: u64,
    most: u64,
) -> Result<(), Broken> {
    let episode = |searcher: &mut TrustSearcher, seed: u64| {
        drive(searcher, space, &mut ChaCha8Rng::seed_from_u64(seed), most)
    };
    let mut first = build();
    let a = episode(first.as_mut(), seed)?;
    let after = episode(first.as_mut(), seed ^ 1)?;
    let b = episode(build().as_mut(), seed)?;
    if a != b {
        return Err(Broken::new(
            SearcherRule::Deterministic,
            "two fresh searchers proposed differently for the same seed and evidence".into(),
        ));
    }
    if !first.learns_across_episodes() {
        let fresh = episode(build().as_mut(), seed ^ 1)?;
        if after != fresh {
            // A searcher drawing from elsewhere than its generator differs from a fresh
            // one for that reason too: tell the two apart with more fresh ones (on a
            // small space, two may agree by chance).
            let mut nondeterministic = false;
            for _ in 0..FRESH_AGAIN {
                if episode(build().as_mut(), seed ^ 1)? != fresh {
                    nondeterministic = true;
                    break;
                }
            }
            return Err(if nondeterministic {
                Broken::new(
                    SearcherRule::Deterministic,
                    "two fresh searchers proposed differently for the same seed and evidence"
                        .into(),
                )
            } else {
                Broken::new(
                    SearcherRule::ForgetsUnlessItLearns,
                    "proposes differently after an earlier episode, though `learns_across_episodes` says it does not learn".into(),
                )
            });
        }
    }
    Ok(())
}

/// The edge cases of one space: with one behavior, the first proposal with no evidence is
/// that behavior; once it is evaluated the space is exhausted and it is kept.
fn check_one_behavior(build: &dyn Fn() -> Box<TrustSearcher>) -> Result<(), SearcherFailure> {
    let one = BehaviorSpace::new(vec![
        NamedComponent::numeric("only", "", 0.0, 1.0, 1).expect("a valid grid"),
    ])
    .expect("a valid space");
    let only = Behavior::new(&[0]);
    let mut rng = ChaCha8Rng::seed_from_u64(0);
    let mut searcher = build();
    searcher.begin_episode(&one, &only);
    let failure = |rule, message: &str, evaluated: &[Evaluated], proposal| SearcherFailure {
        rule,
        message: message.to_owned(),
        space: Box::new(one.clone()),
        evaluated: evaluated.to_vec(),
        proposal: Some(proposal),
        seed: 0,
    };
    let first = searcher.propose(&one, &[], &mut rng);
    if first != Proposal::Next(only) {
        return Err(failure(
            SearcherRule::ExhaustedOnlyWhenAllTried,
            "with no evidence, the one behavior of a one-behavior space is proposed",
            &[],
            first,
        ));
    }
    searcher.observe(
        &only,
        &Outcome::failed(1.0, 1.0).stating(Some(Cause::from_static("stalled"))),
    );
    let evaluated = [Evaluated {
        behavior: only,
        time: 1.0,
    }];
    let last = searcher.propose(&one, &evaluated, &mut rng);
    if last != (Proposal::Exhausted { keep: only }) {
        return Err(failure(
            SearcherRule::Untried,
            "a fully evaluated one-behavior space is exhausted, keeping its behavior",
            &evaluated,
            last,
        ));
    }
    Ok(())
}

/// Checks every rule of [`check_searcher`] for searchers made by `build`, on random
/// small spaces when `space` is `None`; returns the rule broken on proptest's minimal
/// failing case. Given a `space` (a domain's own, for a strategy that reads its
/// components by name), episodes there are cut after a few dozen proposals (a domain's
/// space may hold thousands of behaviors), so the rules about exhaustion and the
/// one-behavior space are left to the random spaces.
pub fn searcher_conformance(
    space: Option<&BehaviorSpace>,
    build: &dyn Fn() -> Box<TrustSearcher>,
) -> Result<(), SearcherFailure> {
    let given = space.is_some();
    let (spaces, cases, most): (BoxedStrategy<BehaviorSpace>, u32, u64) = match space {
        Some(space) => (
            Just(space.clone()).boxed(),
            GIVEN_SPACE_CASES,
            GIVEN_SPACE_PROPOSALS,
        ),
        None => (behavior_spaces(SpaceShape::small()).boxed(), 64, u64::MAX),
    };
    let mut runner = TestRunner::new(Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    });
    let result = runner.run(&(spaces, any::<u64>()), |(space, seed)| {
        check_case(build, &space, seed, most).map_err(|broken| TestCaseError::fail(broken.message))
    });
    match result {
        Ok(()) => {}
        Err(TestError::Fail(_, (space, seed))) => {
            // The minimal case, run again for its details (every rule is deterministic
            // on a case, or is the determinism rule itself).
            let broken = check_case(build, &space, seed, most)
                .err()
                .unwrap_or_else(|| {
                    Broken::new(
                        SearcherRule::Deterministic,
                        "failed once on this case and passed when run again".into(),
                    )
                });
            return Err(SearcherFailure {
                rule: broken.rule,
                message: broken.message,
                space: Box::new(space),
                evaluated: broken.evaluated,
                proposal: broken.proposal,
                seed,
            });
        }
        Err(TestError::Abort(reason)) => {
            return Err(SearcherFailure {
                rule: SearcherRule::InSpace,
                message: format!("the check could not run: {reason}"),
                space: Box::new(
                    BehaviorSpace::new(vec![
                        NamedComponent::numeric("only", "", 0.0, 1.0, 1).expect("a valid grid"),
                    ])
                    .expect("a valid space"),
                ),
                evaluated: Vec::new(),
                proposal: None,
                seed: 0,
            });
        }
    }
    if given {
        Ok(())
    } else {
        check_one_behavior(build)
    }
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
/// With the rule broken and the failing case (proptest's minimal one) when a property
/// does not hold ([`searcher_conformance`] returns it instead).
pub fn check_searcher(build: impl Fn() -> Box<TrustSearcher>) {
    panic_on_failure(searcher_conformance(None, &build));
}

/// [`check_searcher`] on a domain's own `space` (as [`searcher_conformance`] checks it
/// there: episodes cut after a few dozen proposals), for a strategy that reads its
/// components by name: `check_searcher_on(domain.space(), || Box::new(Mine::new()))`.
///
/// # Panics
/// As [`check_searcher`], with the rule broken and the failing case.
pub fn check_searcher_on(space: &BehaviorSpace, build: impl Fn() -> Box<TrustSearcher>) {
    panic_on_failure(searcher_conformance(Some(space), &build));
}

/// Panics with `result`'s failure, its advice and its case, if it has one.
fn panic_on_failure(result: Result<(), SearcherFailure>) {
    if let Err(failure) = result {
        panic!(
            "{failure} ({}); on the space {:?} (seed {}), after {:?}, proposing {:?}",
            failure.rule.advice(),
            failure.space.components(),
            failure.seed,
            failure.evaluated,
            failure.proposal
        );
    }
}
