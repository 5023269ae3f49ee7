//! The online adapter: hand-computed episodes and invariants.

use cbr_core::{
    Behavior, BehaviorSpace, Case, CaseBase, CaseId, CaseMemory, ContextSpace, ContextVariable,
    LinearRetriever, NamedComponent,
};
use proptest::prelude::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;
use trust::search::RandomWalk;
use trust::{
    Account, AdapterConfig, AdapterError, AttributedReason, Cause, Decision, Evaluated,
    Explanation, Grounds, Hint, Next, Observations, Outcome, Parameters, Selection, SetSimilarity,
    Source, TrustAdapter, TrustCaseBase, TrustProblem, Vocabulary, select_behavior,
};

/// Causes of a made-up domain.
const DROPPED: Cause = Cause::from_static("dropped-item");
const STALLED: Cause = Cause::from_static("stalled");
const TOO_SLOW: Cause = Cause::from_static("too-slow");

fn grid(sizes: &[u16]) -> Arc<BehaviorSpace> {
    Arc::new(
        BehaviorSpace::new(
            sizes
                .iter()
                .enumerate()
                .map(|(k, &n)| NamedComponent::numeric(&format!("c{k}"), "", 0.0, 1.0, n).unwrap())
                .collect(),
        )
        .unwrap(),
    )
}

fn interrupt(duration: f64) -> Outcome {
    Outcome::interrupted(1.0, duration).stating(Some(DROPPED))
}

fn adapter(space: &Arc<BehaviorSpace>, config: AdapterConfig) -> TrustAdapter {
    TrustAdapter::new(space.clone(), config, TrustCaseBase::new(), 7).unwrap()
}

#[test]
fn an_episode_by_hand() {
    let space = grid(&[3, 3]);
    let mut a = adapter(&space, AdapterConfig::default());
    let b0 = Behavior::new(&[1, 1]);
    a.begin_episode(b0).unwrap();
    // Four interruptions of weight 1: trust -4 > -5, keep.
    for _ in 0..4 {
        assert_eq!(a.record(&interrupt(2.0)).unwrap(), Decision::Keep);
    }
    // The fifth: -5 <= -5, untrustworthy after 5 x 2 s = 10 s. Empty case base: search.
    let Decision::Switch { to: b1, source, .. } = a.record(&interrupt(2.0)).unwrap() else {
        panic!("expected a switch");
    };
    assert_eq!(source, Source::Search);
    assert_eq!(
        space.changes(&b0, &b1),
        1,
        "the walk moves one change from E_max"
    );
    assert_eq!(
        a.episode().unwrap().evaluated,
        &[Evaluated {
            behavior: b0,
            time: 10.0
        }]
    );
    // The new behavior starts from 0: five completions reach +5.
    for _ in 0..4 {
        assert_eq!(
            a.record(&Outcome::completed(1.0, 3.0)).unwrap(),
            Decision::Keep
        );
    }
    let Decision::Settled(report) = a.record(&Outcome::completed(1.0, 3.0)).unwrap() else {
        panic!("expected the episode to end");
    };
    assert!(report.found_trustworthy);
    assert_eq!(report.settled, b1);
    assert_eq!(report.behaviors_evaluated, 2);
    assert_eq!(report.commands, 10);
    // One search adaptation and a trustworthy behavior: the case is retained.
    assert_eq!(report.retained, Some(CaseId(0)));
    assert_eq!(a.cases().len(), 1);
    assert_eq!(a.cases().cases()[0].solution, b1);

    // The next operator behaves alike: after b0 fails in 10 s again, E_past = [(b0, 10)].
    // Case 0's E_past is [(b0, 10)]: identical behavior, time similarity 1 - 0/10 = 1 > 0,
    // and its final behavior b1 is unevaluated, so it is reused.
    a.begin_episode(b0).unwrap();
    for _ in 0..4 {
        a.record(&interrupt(2.0)).unwrap();
    }
    // The explanation, by hand: b0 was used for 5 commands, all interrupted (estimate
    // -5), each with the stated reason dropped-item; case 0 matches the one behavior
    // given up (b0 itself, similarity 1).
    let explanation = Explanation {
        given_up: Some(Account {
            behavior: b0,
            commands: 5,
            untrustworthy: 5,
            estimate: -5.0,
            reasons: vec![AttributedReason {
                cause: DROPPED,
                weight: 5.0,
                stated: 5,
                perceived: 0,
                inferred: 0.0,
            }],
        }),
        next: Next::Switch {
            behavior: b1,
            source: Source::Case {
                case: CaseId(0),
                similarity: 1.0,
            },
            grounds: Grounds::Matches {
                matched: 1,
                given_up: 1,
            },
        },
    };
    assert_eq!(
        a.record(&interrupt(2.0)).unwrap(),
        Decision::Switch {
            to: b1,
            source: Source::Case {
                case: CaseId(0),
                similarity: 1.0
            },
            explanation: Box::new(explanation.clone()),
        }
    );
    for _ in 0..4 {
        a.record(&Outcome::completed(1.0, 3.0)).unwrap();
    }
    let Decision::Settled(report) = a.record(&Outcome::completed(1.0, 3.0)).unwrap() else {
        panic!("expected the episode to end");
    };
    // Every decision is explained: the switch, then the end (b1 trusted after 5
    // completions, estimate +5).
    assert_eq!(
        report.explanations,
        vec![
            explanation,
            Explanation {
                given_up: None,
                next: Next::Kept {
                    behavior: b1,
                    trustworthy: true,
                    commands: 5,
                    estimate: 5.0,
                },
            },
        ]
    );
    // Solved by the case base alone: nothing new is retained.
    assert_eq!(
        (report.reused, report.searched, report.retained),
        (1, 0, None)
    );
    assert_eq!(a.cases().len(), 1);
}

#[test]
fn search_only_ignores_cases() {
    let space = grid(&[3, 3]);
    let b0 = Behavior::new(&[1, 1]);
    let mut cases = TrustCaseBase::new();
    cases.push(Case {
        problem: vec![Evaluated {
            behavior: b0,
            time: 10.0,
        }]
        .into(),
        solution: Behavior::new(&[2, 2]),
    });
    let config = AdapterConfig {
        reuse_cases: false,
        ..AdapterConfig::default()
    };
    let mut a = TrustAdapter::new(space, config, cases, 1).unwrap();
    a.begin_episode(b0).unwrap();
    for _ in 0..4 {
        a.record(&interrupt(2.0)).unwrap();
    }
    let Decision::Switch { to, source, .. } = a.record(&interrupt(2.0)).unwrap() else {
        panic!("expected a switch");
    };
    assert_eq!(source, Source::Search);
    assert_ne!(to, Behavior::new(&[2, 2]), "(2,2) is two changes away");
}

#[test]
fn exhausting_the_space_keeps_e_max() {
    let space = grid(&[2]);
    let mut a = adapter(&space, AdapterConfig::default());
    a.begin_episode(Behavior::new(&[0])).unwrap();
    // Behavior 0 fails after 5 commands of 1 s (t = 5).
    for _ in 0..5 {
        a.record(&interrupt(1.0)).unwrap();
    }
    // Behavior 1 fails after 5 commands of 3 s (t = 15): every behavior is evaluated and
    // E_max is behavior 1.
    for _ in 0..4 {
        a.record(&interrupt(3.0)).unwrap();
    }
    let Decision::Settled(report) = a.record(&interrupt(3.0)).unwrap() else {
        panic!("expected the episode to end");
    };
    assert!(!report.found_trustworthy);
    assert_eq!(report.settled, Behavior::new(&[1]));
    assert_eq!(report.behaviors_evaluated, 2);
    assert_eq!(report.retained, None);
}

#[test]
fn refused_calls_leave_the_state_alone() {
    let space = grid(&[3]);
    let mut a = adapter(&space, AdapterConfig::default());
    assert_eq!(a.record(&interrupt(1.0)), Err(AdapterError::NoEpisode));
    assert_eq!(
        a.begin_episode(Behavior::new(&[7])),
        Err(AdapterError::ForeignBehavior)
    );
    a.begin_episode(Behavior::new(&[0])).unwrap();
    a.record(&interrupt(1.0)).unwrap();
    let before = a.episode().unwrap().estimate;
    let refused = a.record(&Outcome::completed(f64::NAN, 1.0)).unwrap_err();
    assert!(matches!(refused, AdapterError::Outcome(_)));
    assert!(std::error::Error::source(&refused).is_none());
    assert!(a.record(&Outcome::completed(-1.0, 1.0)).is_err());
    assert_eq!(a.episode().unwrap().estimate, before);
    assert_eq!(
        a.begin_episode(Behavior::new(&[1])),
        Err(AdapterError::EpisodeUnderWay)
    );
}

#[test]
fn bad_configs_are_rejected() {
    let space = grid(&[3]);
    let bad_lambda = AdapterConfig {
        lambda: 1.5,
        ..AdapterConfig::default()
    };
    assert!(TrustAdapter::new(space.clone(), bad_lambda, TrustCaseBase::new(), 0).is_err());
    // Ready-made parts follow parameters checked as well; the kinds of parts a config
    // names are no parameters.
    let bad = Parameters {
        lambda: 0.0,
        ..Parameters::default()
    };
    let memory = AdapterConfig::default()
        .memory(space.clone(), TrustCaseBase::new())
        .unwrap();
    let parts = TrustAdapter::with_parts(
        space.clone(),
        bad,
        memory,
        Box::new(RandomWalk::new()),
        ChaCha8Rng::seed_from_u64(0),
    );
    assert!(matches!(parts, Err(trust::ConfigError::Lambda(_))));
    let uniform = AdapterConfig {
        search: trust::SearchKind::named("uniform").unwrap(),
        retriever: trust::RetrieverKind::InvertedIndex,
        ..AdapterConfig::default()
    };
    assert_eq!(uniform.parameters(), Parameters::default());
    let mut reversed = AdapterConfig::default();
    reversed.thresholds.trustworthy = -5.0;
    reversed.thresholds.untrustworthy = 5.0;
    let Err(refused) = TrustAdapter::new(space, reversed, TrustCaseBase::new(), 0) else {
        panic!("reversed thresholds were accepted");
    };
    // The reason is in the message and not chained as a source, so a report of the whole
    // chain shows it once.
    assert!(refused.to_string().starts_with("thresholds: "), "{refused}");
    assert!(std::error::Error::source(&refused).is_none());
    // Configs read from RON are checked as they are read, naming the field.
    let e = ron::from_str::<AdapterConfig>("(lambda: 0.0)").unwrap_err();
    assert!(
        e.code
            .to_string()
            .starts_with("field `lambda`: lambda must be in (0, 1]")
    );
    let read: AdapterConfig = ron::from_str("(lambda: 1.0)").unwrap();
    assert_eq!(read.lambda, 1.0);
}

fn arbitrary_case_base(space: Arc<BehaviorSpace>) -> impl Strategy<Value = TrustCaseBase> {
    let size = space.size();
    prop::collection::vec(
        (
            prop::collection::vec((0..size, 0.0f64..60.0), 1..5),
            0..size,
            any::<bool>(),
        ),
        0..12,
    )
    .prop_map(move |cases| {
        let cargo = ContextSpace::new(vec![ContextVariable::new(
            "cargo",
            &["normal", "hazardous"],
        )])
        .unwrap();
        let mut base = TrustCaseBase::new();
        for (problem, solution, hazardous) in cases {
            let evaluated = problem.into_iter().map(|(r, t)| Evaluated {
                behavior: space.unrank(r),
                time: t,
            });
            let cargo_value = if hazardous { "hazardous" } else { "normal" };
            base.push(Case {
                problem: TrustProblem::in_context(
                    cargo.context([("cargo", cargo_value)]).unwrap(),
                    evaluated.collect(),
                ),
                solution: space.unrank(solution),
            });
        }
        base
    })
}

proptest! {
    #[test]
    fn select_never_returns_an_evaluated_behavior(
        base in arbitrary_case_base(grid(&[3, 4])),
        picks in prop::collection::vec((0u64..12, 0.0f64..60.0), 1..11),
        seed in any::<u64>(),
    ) {
        let space = grid(&[3, 4]);
        let mut e_past: Vec<Evaluated> = Vec::new();
        for (r, t) in picks {
            let behavior = space.unrank(r);
            if e_past.iter().all(|e| e.behavior != behavior) {
                e_past.push(Evaluated { behavior, time: t });
            }
        }
        prop_assume!((e_past.len() as u64) < space.size());
        let measure = SetSimilarity::new(space.clone(), 0.95).unwrap();
        let memory = CaseMemory::new(base, Box::new(LinearRetriever::new(measure)));
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let chosen = match select_behavior(&TrustProblem::new(e_past.clone()), Some(&memory), &mut RandomWalk::new(), &space, &mut rng) {
            Selection::Next { behavior, source: Source::Case { similarity, .. } } => {
                prop_assert!(similarity > 0.0);
                behavior
            }
            Selection::Next { behavior, source: Source::Search } => behavior,
            other @ Selection::Exhausted { .. } => return Err(TestCaseError::fail(format!("stopped early: {other:?}"))),
        };
        prop_assert!(e_past.iter().all(|e| e.behavior != chosen));
    }

    #[test]
    fn the_adapter_never_drops_a_retained_case(
        outcomes in prop::collection::vec((0u8..3, 0.0f64..1.0, 0.1f64..30.0), 1..400),
        seed in any::<u64>(),
    ) {
        let space = grid(&[3, 3]);
        let mut a = TrustAdapter::new(space.clone(), AdapterConfig::default(), TrustCaseBase::new(), seed).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut retained = Vec::new();
        a.begin_episode(space.draw(&mut rng)).unwrap();
        for (kind, weight, duration) in outcomes {
            let outcome = match kind {
                0 => Outcome::completed(weight * 2.0, duration),
                1 => Outcome::failed(weight * 2.0, duration).stating(Some(STALLED)),
                _ => Outcome::interrupted(weight * 2.0, duration).stating(Some(TOO_SLOW)),
            };
            if let Decision::Settled(report) = a.record(&outcome).unwrap() {
                if let Some(id) = report.retained {
                    retained.push((id, report.evaluated.clone(), report.settled));
                }
                a.begin_episode(space.draw(&mut rng)).unwrap();
            }
        }
        prop_assert_eq!(a.cases().len(), retained.len());
        for (id, evaluated, settled) in retained {
            let case = a.cases().get(id).unwrap();
            prop_assert_eq!(&case.problem.evaluated, &evaluated);
            prop_assert_eq!(case.solution, settled);
        }
    }

    #[test]
    fn a_case_base_round_trips_through_ron(base in arbitrary_case_base(grid(&[4, 5, 2]))) {
        let text = ron::ser::to_string_pretty(&base, ron::ser::PrettyConfig::default()).unwrap();
        let back: CaseBase<TrustProblem, Behavior> = ron::from_str(&text).unwrap();
        prop_assert_eq!(back, base);
    }

    #[test]
    fn set_similarity_stays_in_unit_interval_and_self_similarity_is_one(
        picks in prop::collection::vec((0u64..40, 0.0f64..60.0), 1..8),
        other in prop::collection::vec((0u64..40, 0.0f64..60.0), 0..8),
    ) {
        let space = grid(&[4, 5, 2]);
        let measure = SetSimilarity::new(space.clone(), 0.95).unwrap();
        let mut e1: Vec<Evaluated> = Vec::new();
        for (r, t) in picks {
            let behavior = space.unrank(r);
            if e1.iter().all(|e| e.behavior != behavior) {
                e1.push(Evaluated { behavior, time: t });
            }
        }
        let e2: Vec<Evaluated> = other.into_iter().map(|(r, t)| Evaluated { behavior: space.unrank(r), time: t }).collect();
        let s = measure.compare(&e1, &e2);
        prop_assert!((0.0..=1.0).contains(&s));
        let s = measure.compare(&e2, &e1);
        prop_assert!((0.0..=1.0).contains(&s));
        if e1.iter().any(|e| e.time > 0.0) {
            prop_assert_eq!(measure.compare(&e1, &e1), 1.0);
        }
    }
}

/// A searcher that always proposes the same untried behavior, to script episodes.
struct Always(Behavior);

impl cbr_core::Searcher for Always {
    type Evidence = Evaluated;
    type Feedback = Outcome;

    fn name(&self) -> &str {
        "always"
    }

    fn propose(
        &mut self,
        _space: &BehaviorSpace,
        _evaluated: &[Evaluated],
        _rng: &mut dyn rand::RngCore,
    ) -> cbr_core::Proposal {
        cbr_core::Proposal::Next(self.0)
    }
}

#[test]
fn both_readings_of_retention_and_both_units_of_time() {
    // A case learned earlier: (0,4) was untrustworthy after 10 s, (4,4) was the answer.
    // The episode starts at (0,0), far from the case's behaviors (no similarity), so the
    // search moves to (0,4); that fails after 10 s too, so the case now fits and its
    // solution (4,4) is reused and found trustworthy. A search step followed by a reuse:
    // retained under `any_search`, not under `final_from_search`.
    let space = grid(&[5, 5]);
    let (start, searched, solution) = (
        Behavior::new(&[0, 0]),
        Behavior::new(&[0, 4]),
        Behavior::new(&[4, 4]),
    );
    let run = |retention: trust::Retention, time_unit: trust::TimeUnit| {
        let mut base = TrustCaseBase::new();
        base.push(Case {
            problem: vec![Evaluated {
                behavior: searched,
                time: if time_unit == trust::TimeUnit::Commands {
                    5.0
                } else {
                    10.0
                },
            }]
            .into(),
            solution,
        });
        let parameters = Parameters {
            retention,
            time_unit,
            ..Parameters::default()
        };
        let measure = SetSimilarity::new(space.clone(), parameters.lambda).unwrap();
        let mut a = TrustAdapter::with_parts(
            space.clone(),
            parameters,
            CaseMemory::new(base, Box::new(LinearRetriever::new(measure))),
            Box::new(Always(searched)),
            ChaCha8Rng::seed_from_u64(1),
        )
        .unwrap();
        a.begin_episode(start).unwrap();
        for _ in 0..4 {
            a.record(&interrupt(2.0)).unwrap();
        }
        assert!(matches!(
            a.record(&interrupt(2.0)).unwrap(),
            Decision::Switch {
                source: Source::Search,
                ..
            }
        ));
        for _ in 0..4 {
            a.record(&interrupt(2.0)).unwrap();
        }
        let Decision::Switch { to, source, .. } = a.record(&interrupt(2.0)).unwrap() else {
            panic!("expected a switch");
        };
        assert_eq!(to, solution);
        assert!(matches!(source, Source::Case { .. }), "{source:?}");
        // Five commands of 2 s: t is 10 s, or 5 commands.
        let times: Vec<f64> = a
            .episode()
            .unwrap()
            .evaluated
            .iter()
            .map(|e| e.time)
            .collect();
        for _ in 0..4 {
            a.record(&Outcome::completed(1.0, 1.0)).unwrap();
        }
        let Decision::Settled(report) = a.record(&Outcome::completed(1.0, 1.0)).unwrap() else {
            panic!("expected the episode to end");
        };
        (report.retained.is_some(), times)
    };
    use trust::{Retention, TimeUnit};
    assert_eq!(
        run(Retention::AnySearch, TimeUnit::TaskSeconds),
        (true, vec![10.0, 10.0])
    );
    assert_eq!(
        run(Retention::FinalFromSearch, TimeUnit::TaskSeconds),
        (false, vec![10.0, 10.0])
    );
    assert_eq!(
        run(Retention::AnySearch, TimeUnit::Commands),
        (true, vec![5.0, 5.0])
    );
}

/// An episode whose explanation is known: the robot perceives bumps (`stalled` is what it
/// perceives, bit 0) and running late (bit 1, a hint at `too-slow`); the operator states
/// `dropped-item` once.
#[test]
fn a_hand_built_episode_explains_its_switch() {
    let late = Cause::from_static("late");
    let vocabulary = Vocabulary {
        causes: vec![DROPPED, STALLED, TOO_SLOW],
        observations: vec![STALLED, late],
        hints: vec![Hint {
            observation: late,
            suggests: TOO_SLOW,
        }],
    };
    let space = Arc::new(
        BehaviorSpace::new(vec![
            NamedComponent::numeric("speed", "m/s", 1.0, 1.0, 3).unwrap(),
        ])
        .unwrap(),
    );
    let mut a = TrustAdapter::new(space, AdapterConfig::default(), TrustCaseBase::new(), 7)
        .unwrap()
        .with_vocabulary(vocabulary);
    let cut = || Outcome::interrupted(1.0, 1.0);
    let b0 = Behavior::new(&[0]);
    a.begin_episode(b0).unwrap();
    let stalled = Observations::NONE.with(0);
    let behind = Observations::NONE.with(1);
    // Two stalls perceived, one stated drop, two late runs with nothing stated: -5.
    for outcome in [
        cut().observing(stalled),
        cut().observing(stalled),
        cut().stating(Some(DROPPED)),
        cut().observing(behind),
    ] {
        assert_eq!(a.record(&outcome).unwrap(), Decision::Keep);
    }
    let standing = a.standing().unwrap();
    assert_eq!((standing.commands, standing.untrustworthy), (4, 4));
    let Decision::Switch { explanation, .. } = a.record(&cut().observing(behind)).unwrap() else {
        panic!("expected a switch");
    };
    // Each late run, by hand: `stalled` is ruled out (it would have been perceived);
    // dropped-item scores 0.5 (prior) + 0 (it was stated with nothing perceived, not with
    // `late`), too-slow 0.5 + 2 (the hint): p(too-slow) = 2.5 / 3. Weights: stalled 2,
    // too-slow 5/3, dropped-item 1 + 1/3.
    let given_up = explanation.given_up.as_ref().unwrap();
    assert_eq!((given_up.commands, given_up.untrustworthy), (5, 5));
    assert_eq!(given_up.estimate, -5.0);
    let causes: Vec<Cause> = given_up.reasons.iter().map(|r| r.cause).collect();
    assert_eq!(causes, vec![STALLED, TOO_SLOW, DROPPED]);
    assert_eq!(
        given_up.reasons[0],
        AttributedReason {
            cause: STALLED,
            weight: 2.0,
            stated: 0,
            perceived: 2,
            inferred: 0.0
        }
    );
    assert!((given_up.reasons[1].weight - 5.0 / 3.0).abs() < 1e-12);
    assert!((given_up.reasons[1].inferred - 2.5 / 3.0).abs() < 1e-12);
    assert_eq!(given_up.reasons[2].stated, 1);
    assert!((given_up.reasons[2].weight - 4.0 / 3.0).abs() < 1e-12);
    let Next::Switch {
        source: Source::Search,
        grounds: Grounds::Rationale { strategy, .. },
        ..
    } = &explanation.next
    else {
        panic!("an empty case base: the search proposes");
    };
    assert_eq!(strategy, "random-walk");
    let sentence = explanation.sentence(a.space());
    assert!(
        sentence.starts_with(
            "Gave up speed=1 m/s after 5 commands (5 untrustworthy): most likely stalled (perceived twice), then too-slow (inferred, p = 0.83), then dropped-item (stated once; inferred, p = 0.17). Now speed="
        ),
        "{sentence}"
    );
    assert!(sentence.ends_with("random-walk search, exploring: one random step from the behavior that resisted longest."), "{sentence}");
    // The new behavior starts with no account.
    assert!(a.standing().unwrap().reasons.is_empty());
    assert!(matches!(
        a.episode().unwrap().explanations,
        [Explanation {
            given_up: Some(Account { .. }),
            ..
        }]
    ));
}

#[test]
fn a_said_goal_change_counts_for_nothing_but_a_command() {
    let space = grid(&[3, 3]);
    let mut a = adapter(&space, AdapterConfig::default());
    let b0 = Behavior::new(&[1, 1]);
    a.begin_episode(b0).unwrap();
    let goal_change = Outcome::interrupted(1.0, 2.0).saying_goal_change(true);
    // Four interruptions (-4), then three said goal changes: still -4, kept.
    for _ in 0..4 {
        assert_eq!(a.record(&interrupt(2.0)).unwrap(), Decision::Keep);
    }
    for _ in 0..3 {
        assert_eq!(a.record(&goal_change).unwrap(), Decision::Keep);
    }
    let episode = a.episode().unwrap();
    assert_eq!(episode.estimate.value, -4.0);
    assert_eq!(episode.estimate.commands, 4);
    assert_eq!(episode.estimate.elapsed_s, 8.0);
    // The fifth interruption about the behavior gives it up, after 4 x 2 s of evidence
    // plus its own 2 s (the goal changes' 6 s are not the behavior's time).
    let Decision::Switch { explanation, .. } = a.record(&interrupt(2.0)).unwrap() else {
        panic!("expected a switch");
    };
    let given_up = explanation.given_up.unwrap();
    assert_eq!((given_up.commands, given_up.untrustworthy), (5, 5));
    assert_eq!(a.episode().unwrap().evaluated[0].time, 10.0);
    // The episode counts every command the operator gave: 8.
    let report = a.abandon_episode().unwrap();
    assert_eq!((report.commands, report.untrustworthy), (8, 5));
}

#[test]
fn an_unsaid_goal_change_is_an_interruption_like_any_other() {
    let space = grid(&[3, 3]);
    let mut a = adapter(&space, AdapterConfig::default());
    a.begin_episode(Behavior::new(&[1, 1])).unwrap();
    for _ in 0..4 {
        assert_eq!(
            a.record(&Outcome::interrupted(1.0, 2.0)).unwrap(),
            Decision::Keep
        );
    }
    assert!(matches!(
        a.record(&Outcome::interrupted(1.0, 2.0)).unwrap(),
        Decision::Switch { .. }
    ));
}

#[test]
fn a_goal_change_is_said_only_of_an_interruption_without_a_reason() {
    let space = grid(&[3, 3]);
    let mut a = adapter(&space, AdapterConfig::default());
    a.begin_episode(Behavior::new(&[1, 1])).unwrap();
    let failed = Outcome::failed(1.0, 2.0).saying_goal_change(true);
    let err = a.record(&failed).unwrap_err();
    assert_eq!(
        err.to_string(),
        "invalid outcome: goal_change is said only of an interruption with no stated reason (the operator stopped the robot for something other than the behavior), got outcome `failed`"
    );
    let reasoned = interrupt(2.0).saying_goal_change(true);
    assert!(
        a.record(&reasoned)
            .unwrap_err()
            .to_string()
            .ends_with("got outcome `interrupted` with a stated reason")
    );
    // Refused outcomes leave the episode as it was.
    assert_eq!(a.episode().unwrap().estimate.commands, 0);
}

/// A searcher that writes down every context it is told.
struct ContextWatcher {
    told: Arc<std::sync::Mutex<Vec<cbr_core::Context>>>,
}

impl cbr_core::Searcher for ContextWatcher {
    type Evidence = Evaluated;
    type Feedback = Outcome;

    fn name(&self) -> &str {
        "context-watcher"
    }

    fn enter_context(&mut self, context: &cbr_core::Context) {
        self.told.lock().unwrap().push(context.clone());
    }

    fn propose(
        &mut self,
        space: &BehaviorSpace,
        _evaluated: &[Evaluated],
        rng: &mut dyn rand::RngCore,
    ) -> cbr_core::Proposal {
        cbr_core::Proposal::Next(space.draw(rng))
    }
}

#[test]
fn a_searcher_is_told_each_context_the_robot_is_told_and_none_mid_episode() {
    let space = grid(&[3, 3]);
    let contexts = ContextSpace::new(vec![ContextVariable::new(
        "cargo",
        &["normal", "hazardous"],
    )])
    .unwrap();
    let hazardous = contexts.context([("cargo", "hazardous")]).unwrap();
    let told = Arc::new(std::sync::Mutex::new(Vec::new()));
    let parameters = Parameters::default();
    let measure = SetSimilarity::new(space.clone(), parameters.lambda).unwrap();
    let mut adapter = TrustAdapter::with_parts(
        space.clone(),
        parameters,
        CaseMemory::new(
            TrustCaseBase::new(),
            Box::new(LinearRetriever::new(measure)),
        ),
        Box::new(ContextWatcher { told: told.clone() }),
        ChaCha8Rng::seed_from_u64(1),
    )
    .unwrap();
    adapter.set_context(hazardous.clone()).unwrap();
    adapter.begin_episode(Behavior::new(&[0, 0])).unwrap();
    // Refused mid-episode: the searcher is not told.
    assert!(matches!(
        adapter.set_context(cbr_core::Context::default()),
        Err(AdapterError::EpisodeUnderWay)
    ));
    adapter.abandon_episode();
    adapter.set_context(cbr_core::Context::default()).unwrap();
    assert_eq!(
        *told.lock().unwrap(),
        [hazardous, cbr_core::Context::default()]
    );
}
