//! Mission mode and the overtrust alert: hand-computed missions through the mission
//! wrapper of the adapter.

use cbr_core::{Behavior, BehaviorSpace, Context, ContextSpace, ContextVariable, NamedComponent};
use proptest::prelude::*;
use std::sync::Arc;
use trust::{
    AdapterConfig, AdapterError, Cause, ChangeDetector, CompetenceJudge, CompetencePart,
    CompetenceRecord, CompetenceStandard, Decision, Evaluated, MissionAdapter, MissionDecision,
    Observations, Outcome, Predictor, Source, SwitchStart, TrustAdapter, TrustCaseBase,
    TrustEstimate,
};

fn grid() -> Arc<BehaviorSpace> {
    Arc::new(
        BehaviorSpace::new(vec![
            NamedComponent::numeric("a", "", 0.0, 1.0, 4).unwrap(),
            NamedComponent::numeric("b", "", 0.0, 1.0, 4).unwrap(),
        ])
        .unwrap(),
    )
}

fn episode_adapter() -> TrustAdapter {
    TrustAdapter::new(grid(), AdapterConfig::default(), TrustCaseBase::new(), 3).unwrap()
}

fn mission_adapter() -> MissionAdapter<'static> {
    MissionAdapter::new(episode_adapter())
}

const KEEP: MissionDecision = MissionDecision::Episode(Decision::Keep);

const DONE: Outcome = Outcome::completed(1.0, 2.0);
const STOPPED: Outcome = Outcome::interrupted(1.0, 2.0);

/// A bump the robot perceived (observation 0).
fn bumped(outcome: Outcome) -> Outcome {
    outcome.observing(Observations::NONE.with(0))
}

/// The evaluated pairs of a re-adaptation from `b`: `b`, ten commands of 2 s.
fn episode_pairs(b: Behavior) -> Vec<Evaluated> {
    vec![Evaluated {
        behavior: b,
        time: 20.0,
    }]
}

/// Five completions settle the behavior in use.
fn settle(a: &mut MissionAdapter) {
    for _ in 0..4 {
        assert_eq!(a.record(&DONE).unwrap(), KEEP);
    }
    assert!(matches!(
        a.record(&DONE).unwrap(),
        MissionDecision::Episode(Decision::Settled(r)) if r.found_trustworthy
    ));
}

/// `outcome` at the paper's weight of 1/3.
fn third(outcome: Outcome) -> Outcome {
    Outcome {
        weight: 1.0 / 3.0,
        ..outcome
    }
}

/// Fifteen completions of weight 1/3 settle the behavior in use.
fn settle_in_thirds(a: &mut MissionAdapter) {
    for _ in 0..14 {
        assert_eq!(a.record(&third(DONE)).unwrap(), KEEP);
    }
    assert!(matches!(
        a.record(&third(DONE)).unwrap(),
        MissionDecision::Episode(Decision::Settled(r)) if r.found_trustworthy
    ));
}

#[test]
fn the_paper_s_episode_machine_stops_listening() {
    let mut a = episode_adapter();
    a.begin_episode(Behavior::new(&[1, 1])).unwrap();
    for _ in 0..4 {
        assert_eq!(a.record(&DONE).unwrap(), Decision::Keep);
    }
    assert!(matches!(a.record(&DONE).unwrap(), Decision::Settled(_)));
    assert_eq!(a.record(&DONE), Err(AdapterError::NoEpisode));
    assert!(a.standing().is_none());
}

#[test]
fn a_kept_behavior_is_given_up_only_once_it_has_fallen() {
    let b0 = Behavior::new(&[1, 1]);
    let fallen = TrustEstimate {
        value: -5.0,
        elapsed_s: 20.0,
        commands: 10,
    };
    let memory = trust::TrustMemory::new(
        TrustCaseBase::new(),
        trust::RetrieverKind::Linear.build(grid(), 0.95).unwrap(),
    );
    let mut adaptation = trust::Adaptation::new(grid(), AdapterConfig::default(), 3).unwrap();
    let above = TrustEstimate {
        value: -4.5,
        ..fallen
    };
    assert_eq!(
        adaptation.give_up_kept(b0, above, 9, &memory),
        Err(AdapterError::NotUntrustworthy { estimate: -4.5 })
    );
    assert_eq!(
        adaptation.give_up_kept(Behavior::new(&[9, 9]), fallen, 10, &memory),
        Err(AdapterError::ForeignBehavior)
    );
    assert!(adaptation.episode().is_none(), "refused: nothing began");
    // Ten interruptions of 2 s counted, the last five with a stated reason told to the
    // account: given up at once with that account and its evaluated pair.
    for _ in 0..5 {
        adaptation.account_kept(&STOPPED.stating(Some(trust::Cause::from_static("late"))));
    }
    let Decision::Switch {
        source,
        explanation,
        ..
    } = adaptation.give_up_kept(b0, fallen, 10, &memory).unwrap()
    else {
        panic!("expected a switch");
    };
    assert_eq!(source, Source::Search);
    let given_up = explanation.given_up.unwrap();
    assert_eq!(
        (given_up.commands, given_up.untrustworthy, given_up.estimate),
        (10, 10, -5.0)
    );
    assert_eq!(given_up.reasons[0].stated, 5);
    let episode = adaptation.episode().unwrap();
    assert_eq!(
        (episode.commands, episode.evaluated),
        (10, &episode_pairs(b0)[..])
    );
    assert_eq!(
        adaptation.give_up_kept(b0, fallen, 10, &memory),
        Err(AdapterError::EpisodeUnderWay)
    );
}

#[test]
fn a_mission_keeps_watching_and_readapts_after_ten_net_untrustworthy_commands() {
    let mut a = mission_adapter();
    let b0 = Behavior::new(&[1, 1]);
    a.begin_episode(b0).unwrap();
    settle(&mut a);
    // Fifty more completions: capped at +5, nothing banked.
    for _ in 0..50 {
        assert_eq!(a.record(&DONE).unwrap(), KEEP);
    }
    let watch = a.watching().unwrap();
    assert_eq!(
        (watch.behavior, watch.estimate.value, watch.commands),
        (b0, 5.0, 50)
    );
    assert_eq!(a.standing().unwrap().estimate, 5.0);
    // Nine interruptions: +5 - 9 = -4, kept.
    for _ in 0..9 {
        assert_eq!(a.record(&STOPPED).unwrap(), KEEP);
    }
    // The tenth: -5, the behavior is given up and a new episode starts.
    let MissionDecision::Episode(Decision::Switch {
        to,
        source,
        explanation,
    }) = a.record(&STOPPED).unwrap()
    else {
        panic!("expected a re-adaptation");
    };
    assert_eq!(source, Source::Search);
    assert_ne!(to, b0);
    let given_up = explanation.given_up.unwrap();
    assert_eq!(
        (given_up.behavior, given_up.commands, given_up.untrustworthy),
        (b0, 10, 10)
    );
    assert!(a.watching().is_none());
    let episode = a.adapter().episode().unwrap();
    assert_eq!(episode.current, to);
    // The evaluated pair: the ten commands (20 s) it took to fall from trusted.
    assert_eq!(episode.evaluated, episode_pairs(b0));
    // The evaluated pair: the ten commands (20 s) it took to fall from trusted.
    assert_eq!(episode.evaluated.len(), 1);
    assert_eq!(
        (episode.evaluated[0].behavior, episode.evaluated[0].time),
        (b0, 20.0)
    );
    // The re-adaptation settles as any episode does, and its case is retained (the first
    // episode's was not: no search found it).
    settle(&mut a);
    assert_eq!(a.adapter().cases().len(), 1);
    assert_eq!(
        a.adapter().cases().cases()[0].problem.evaluated,
        episode_pairs(b0)
    );
}

#[test]
fn a_change_detector_gives_a_watched_behavior_up_sooner_and_keeps_a_steady_one() {
    // At the paper's weights of 1/3, fifteen completions settle a behavior: its rate of
    // untrustworthy commands is at most q0 = 1 - 0.05^(1/16) = 0.1707 (the 95% bound of
    // Beta(1, 16)), so an interruption adds ln(0.5 / q0) = 1.0747 and a completion
    // ln(0.5 / (1 - q0)) = -0.5046; the threshold is ln(8000) = 8.987: nine interruptions
    // in a row raise it, where the paper's watch needs thirty.
    let mut a = mission_adapter().detecting_changes(ChangeDetector::default());
    let b0 = Behavior::new(&[1, 1]);
    a.begin_episode(b0).unwrap();
    settle_in_thirds(&mut a);
    // A steady behavior, one interruption in seven over 700 commands: kept throughout
    // (the statistic falls by 1.95 every seven commands).
    for k in 0..700 {
        let outcome = if k % 7 == 0 { STOPPED } else { DONE };
        assert_eq!(a.record(&third(outcome)).unwrap(), KEEP, "command {k}");
    }
    for _ in 0..8 {
        assert_eq!(a.record(&third(STOPPED)).unwrap(), KEEP);
    }
    let MissionDecision::Episode(Decision::Switch { explanation, .. }) =
        a.record(&third(STOPPED)).unwrap()
    else {
        panic!("expected the ninth interruption to give the behavior up");
    };
    let given_up = explanation.given_up.unwrap();
    assert_eq!((given_up.behavior, given_up.untrustworthy), (b0, 9));
    assert!((given_up.estimate - 2.0).abs() < 1e-9, "5 - 9/3");
    // Without a detector the same commands keep it.
    let mut plain = mission_adapter();
    plain.begin_episode(b0).unwrap();
    settle_in_thirds(&mut plain);
    for _ in 0..9 {
        assert_eq!(plain.record(&third(STOPPED)).unwrap(), KEEP);
    }
}

#[test]
fn a_change_test_starts_from_the_settling_episode_alone() {
    // Eight interruptions of a first operator who left, on the behavior the next
    // operator's episode begins on, are not that episode's: settled after fifteen completions, the
    // behavior is tested from q0 = 0.1707 and given up at the ninth interruption, as in
    // the test above. Counted in, the record (23 commands, 8 untrustworthy) would bound
    // q0 at the 95% quantile of Beta(9, 16), about 0.52, and the test would wait.
    let mut a = mission_adapter().detecting_changes(ChangeDetector::default());
    let b0 = Behavior::new(&[1, 1]);
    a.begin_episode(b0).unwrap();
    for _ in 0..8 {
        assert_eq!(a.record(&third(STOPPED)).unwrap(), KEEP);
    }
    assert!(a.abandon_episode().is_some(), "the first operator left");
    a.begin_episode(b0).unwrap();
    settle_in_thirds(&mut a);
    for _ in 0..8 {
        assert_eq!(a.record(&third(STOPPED)).unwrap(), KEEP);
    }
    assert!(matches!(
        a.record(&third(STOPPED)).unwrap(),
        MissionDecision::Episode(Decision::Switch { .. })
    ));
}

#[test]
fn a_new_operator_ends_the_watch_and_abandoning_ends_it_too() {
    let mut a = mission_adapter();
    a.begin_episode(Behavior::new(&[0, 0])).unwrap();
    settle(&mut a);
    assert!(a.watching().is_some());
    a.begin_episode(Behavior::new(&[2, 2])).unwrap();
    assert!(a.watching().is_none());
    settle(&mut a);
    assert_eq!(a.abandon_episode(), None);
    assert_eq!(a.record(&DONE), Err(AdapterError::NoEpisode));
}

#[test]
fn an_alert_when_the_operator_stops_reacting_to_what_the_robot_perceives() {
    let mut a = mission_adapter();
    a.begin_episode(Behavior::new(&[1, 2])).unwrap();
    // While deciding, the operator reacted to 3 bumps of 3 (the fleet's rate
    // (3 + 1) / (3 + 2) = 0.8, the operator's (3 + 2 x 0.8) / 5 = 0.92) and let 8 commands
    // without a signal pass (base: fleet 1/10, operator 0.2 / 10 = 0.02): a bump's own
    // rate is 0.9 / 0.98 = 45/49.
    for _ in 0..3 {
        assert_eq!(a.record(&bumped(STOPPED)).unwrap(), KEEP);
    }
    // Eight completions: -3 + 8 = +5, settled.
    for _ in 0..7 {
        assert_eq!(a.record(&DONE).unwrap(), KEEP);
    }
    assert!(matches!(
        a.record(&DONE).unwrap(),
        MissionDecision::Episode(Decision::Settled(_))
    ));
    // Bumps the operator lets pass: the estimate stays at +5, and each adds
    // ln((1 - 22.5/49) / (4/49)) = ln 6.625 to the evidence of a lapse; the third passes
    // ln 100.
    let step = 6.625f64.ln();
    for _ in 0..2 {
        assert_eq!(a.record(&bumped(DONE)).unwrap(), KEEP);
    }
    let MissionDecision::Alert(alert) = a.record(&bumped(DONE)).unwrap() else {
        panic!("expected an alert");
    };
    assert_eq!(alert.estimate, 5.0);
    assert!((alert.own_record - 3.0 * step).abs() < 1e-9);
    assert_eq!((alert.commands, alert.unacknowledged), (3, 3));
    // The evidence starts again: the next bump alone raises nothing.
    assert_eq!(a.record(&bumped(DONE)).unwrap(), KEEP);
    assert!((a.own_record().value() - step).abs() < 1e-9);
}

/// A bump the robot perceives (observation 0), and a wrong label it cannot see.
const BUMP: Cause = Cause::from_static("bump");
const WRONG: Cause = Cause::from_static("wrong-label");

/// The competence parts of these tests: a bump, seen; a wrong label, unseen.
fn competence_parts() -> [CompetencePart; 2] {
    [
        CompetencePart {
            name: BUMP,
            seen_as: Some(BUMP),
        },
        CompetencePart {
            name: WRONG,
            seen_as: None,
        },
    ]
}

#[test]
fn an_overtrust_alert_once_per_settled_behavior_the_robot_judges_not_competent() {
    let parts = competence_parts();
    // The model: behavior [1, 2] labels wrongly one command in five, every other one in
    // a hundred; bumps it does not predict.
    let careless = Behavior::new(&[1, 2]);
    let predict: Predictor =
        Arc::new(move |b: &Behavior| vec![None, Some(if *b == careless { 0.2 } else { 0.01 })]);
    let standard = CompetenceStandard {
        at_most: 0.5,
        parts: vec![(WRONG, 0.1)],
    };
    let judge = || {
        CompetenceJudge::new(
            CompetenceRecord::new(&parts, &[BUMP]).unwrap(),
            predict.clone(),
            standard.clone(),
        )
    };
    let mut a = mission_adapter().with_competence(judge());
    a.begin_episode(careless).unwrap();
    // Trusted while deciding (no calibration is judged during an episode), then settled.
    settle(&mut a);
    // The first watched command: trusted at +5, the wrong label's 0.2 above its 0.1.
    let MissionDecision::Overtrust(alert) = a.record(&DONE).unwrap() else {
        panic!("expected an overtrust alert");
    };
    assert_eq!((alert.behavior, alert.estimate), (careless, 5.0));
    assert_eq!(alert.short, [WRONG]);
    // Bumps: 0 of 6 commands; every behavior's (0 + 1/2) / (6 + 1), shrunk: (4 x 1/14) / 10.
    assert_eq!(alert.competence.commands, 6);
    assert!((alert.competence.parts[0].rate.unwrap() - 4.0 / 140.0).abs() < 1e-12);
    // Once per settled behavior.
    assert_eq!(a.record(&DONE).unwrap(), KEEP);
    assert_eq!(
        a.competence_judge().unwrap().competence(careless).commands,
        7
    );
    // A competent behavior raises nothing.
    let mut b = mission_adapter().with_competence(judge());
    b.begin_episode(Behavior::new(&[0, 0])).unwrap();
    settle(&mut b);
    for _ in 0..5 {
        assert_eq!(b.record(&DONE).unwrap(), KEEP);
    }
}

#[test]
fn an_overtrust_alert_offers_the_safest_competent_behavior_operators_trusted_before() {
    let parts = competence_parts();
    let careless = Behavior::new(&[1, 2]);
    let (careful, fair, sloppy) = (
        Behavior::new(&[3, 3]),
        Behavior::new(&[0, 1]),
        Behavior::new(&[2, 2]),
    );
    // Wrong labels: `careless` 0.2 and `sloppy` 0.15 (both above 0.1), `fair` 0.05,
    // `careful` 0.01.
    let predict: Predictor = Arc::new(move |b: &Behavior| {
        let wrong = match b.indices() {
            [1, 2] => 0.2,
            [2, 2] => 0.15,
            [0, 1] => 0.05,
            _ => 0.01,
        };
        vec![None, Some(wrong)]
    });
    let judge = CompetenceJudge::new(
        CompetenceRecord::new(&parts, &[BUMP]).unwrap(),
        predict,
        CompetenceStandard::uniform(0.1).unwrap(),
    );
    // Earlier operators trusted `sloppy`, `fair` and `careful` (solutions of retained
    // cases; `careless` too, which is never offered in its own place).
    let mut cases = TrustCaseBase::new();
    for solution in [sloppy, fair, careless, careful, fair] {
        cases.push(cbr_core::Case {
            problem: episode_pairs(solution).into(),
            solution,
        });
    }
    let adapter = TrustAdapter::new(grid(), AdapterConfig::default(), cases, 3).unwrap();
    let mut a = MissionAdapter::new(adapter).with_competence(judge);
    assert_eq!(
        a.accept_offer(careful).unwrap_err(),
        AdapterError::NotWatching
    );
    a.begin_episode(careless).unwrap();
    settle(&mut a);
    let MissionDecision::Overtrust(alert) = a.record(&DONE).unwrap() else {
        panic!("expected an overtrust alert");
    };
    // The competent ones are `fair` and `careful`; `careful` has the cleaner command.
    assert_eq!(alert.offer, Some(careful));
    // The operator takes it: watched from now on at the trustworthy threshold, and, being
    // competent, it raises no alert.
    assert_eq!(
        a.accept_offer(Behavior::new(&[9, 9])).unwrap_err(),
        AdapterError::ForeignBehavior
    );
    a.accept_offer(careful).unwrap();
    let watch = a.watching().unwrap();
    assert_eq!(
        (watch.behavior, watch.estimate.value, watch.commands),
        (careful, 5.0, 0)
    );
    for _ in 0..5 {
        assert_eq!(a.record(&DONE).unwrap(), KEEP);
    }
    assert_eq!(a.in_use().unwrap().0, careful);
    // Nothing competent to offer: no offer.
    let lone = CompetenceJudge::new(
        CompetenceRecord::new(&parts, &[BUMP]).unwrap(),
        Arc::new(|_: &Behavior| vec![None, Some(0.2)]),
        CompetenceStandard::uniform(0.1).unwrap(),
    );
    let mut b = mission_adapter().with_competence(lone);
    b.begin_episode(careless).unwrap();
    settle(&mut b);
    let MissionDecision::Overtrust(alert) = b.record(&DONE).unwrap() else {
        panic!("expected an overtrust alert");
    };
    assert_eq!(alert.offer, None);
}

#[test]
fn preferring_competent_behaviors_an_episode_passes_over_a_trusted_one_it_is_sure_of() {
    let parts = competence_parts();
    let careless = Behavior::new(&[1, 2]);
    // `careful_only`: only `careless` labels wrongly; `all_careless`: every behavior does.
    let judge = |all_careless: bool| {
        let predict: Predictor = Arc::new(move |b: &Behavior| {
            vec![
                None,
                Some(if all_careless || *b == careless {
                    0.2
                } else {
                    0.01
                }),
            ]
        });
        CompetenceJudge::new(
            CompetenceRecord::new(&parts, &[BUMP]).unwrap(),
            predict,
            CompetenceStandard::uniform(0.1).unwrap(),
        )
    };
    let four_then = |a: &mut MissionAdapter| {
        for _ in 0..4 {
            assert_eq!(a.record(&DONE).unwrap(), KEEP);
        }
        a.record(&DONE).unwrap()
    };
    let mut a = mission_adapter()
        .with_competence(judge(false))
        .preferring_competent(1);
    a.begin_episode(careless).unwrap();
    // Trusted after five completions, but surely not competent: given up, the search goes on.
    let MissionDecision::Episode(Decision::Switch {
        to, explanation, ..
    }) = four_then(&mut a)
    else {
        panic!("expected the trusted behavior to be passed over");
    };
    assert_ne!(to, careless);
    assert_eq!(explanation.given_up.unwrap().estimate, 5.0);
    assert!(a.watching().is_none());
    assert_eq!(a.adapter().cases().len(), 0, "nothing retained yet");
    // The next trusted behavior is competent: settled on, and retained.
    let MissionDecision::Episode(Decision::Settled(report)) = four_then(&mut a) else {
        panic!("expected a settled episode");
    };
    assert_eq!((report.settled, report.behaviors_evaluated), (to, 2));
    assert_eq!(a.watching().unwrap().behavior, to);
    assert_eq!(a.adapter().cases().len(), 1);
    // Every behavior careless and one pass: the second trusted one is kept all the same.
    let mut b = mission_adapter()
        .with_competence(judge(true))
        .preferring_competent(1);
    b.begin_episode(careless).unwrap();
    assert!(matches!(
        four_then(&mut b),
        MissionDecision::Episode(Decision::Switch { .. })
    ));
    assert!(matches!(
        four_then(&mut b),
        MissionDecision::Episode(Decision::Settled(r)) if r.found_trustworthy
    ));
    // Without a preference, the first trusted behavior settles (the paper's episode).
    let mut c = mission_adapter().with_competence(judge(true));
    c.begin_episode(careless).unwrap();
    settle(&mut c);
}

proptest! {
    /// In mission mode every outcome is answered (never `NoEpisode`), an episode runs or a
    /// behavior is watched after every answer, and the watched estimate never exceeds the
    /// trustworthy threshold nor reaches the untrustworthy one.
    #[test]
    fn a_mission_always_listens(
        outcomes in proptest::collection::vec((0u8..3, any::<bool>()), 1..400)
    ) {
        let mut a = mission_adapter();
        a.begin_episode(Behavior::new(&[0, 3])).unwrap();
        for (kind, bump) in outcomes {
            let outcome = match kind {
                0 => Outcome::completed(1.0, 1.0),
                1 => Outcome::failed(0.5, 1.0),
                _ => Outcome::interrupted(1.0, 1.0),
            };
            let outcome = if bump { bumped(outcome) } else { outcome };
            a.record(&outcome).unwrap();
            prop_assert!(a.adapter().episode().is_some() != a.watching().is_some());
            if let Some(w) = a.watching() {
                prop_assert!(w.estimate.value <= 5.0 && w.estimate.value > -5.0);
            }
        }
    }
}

#[test]
fn a_said_goal_change_leaves_the_watched_behavior_as_it_was() {
    let mut a = mission_adapter();
    let b0 = Behavior::new(&[1, 1]);
    a.begin_episode(b0).unwrap();
    settle(&mut a);
    let goal_change = STOPPED.saying_goal_change(true);
    // Nine interruptions about the behavior: +5 - 9 = -4.
    for _ in 0..9 {
        assert_eq!(a.record(&STOPPED).unwrap(), KEEP);
    }
    // Twenty said goal changes: still -4, still watched, nothing in its account.
    for _ in 0..20 {
        assert_eq!(a.record(&goal_change).unwrap(), KEEP);
    }
    let watch = a.watching().unwrap();
    assert_eq!((watch.estimate.value, watch.commands), (-4.0, 9));
    assert_eq!(a.standing().unwrap().untrustworthy, 9);
    // The tenth interruption about it re-adapts, as without the goal changes.
    assert!(matches!(
        a.record(&STOPPED).unwrap(),
        MissionDecision::Episode(Decision::Switch { .. })
    ));
}

fn cargo(value: &str) -> Context {
    let cargo = ContextVariable::new("cargo", &["normal", "hazardous", "explosive"]);
    ContextSpace::new(vec![cargo])
        .unwrap()
        .context([("cargo", value)])
        .unwrap()
}

/// Interruptions until the watched behavior falls: the behavior the new episode switched to.
fn fall(a: &mut MissionAdapter) -> Behavior {
    loop {
        if let MissionDecision::Episode(Decision::Switch { to, .. }) = a.record(&STOPPED).unwrap() {
            return to;
        }
    }
}

#[test]
fn a_context_switch_goes_back_to_what_the_robot_settled_on_there() {
    let mut a = mission_adapter();
    assert_eq!(
        a.switch_context(cargo("hazardous"), false),
        Err(AdapterError::NoEpisode)
    );
    let first = Behavior::new(&[0, 0]);
    a.begin_episode(first).unwrap();
    settle(&mut a);
    // Nothing known of hazardous cargo: the watched behavior stays watched, now there.
    let kept = a.switch_context(cargo("hazardous"), false).unwrap();
    assert_eq!(
        (kept.behavior, kept.from, kept.gave_up_watch),
        (first, SwitchStart::Kept, false)
    );
    assert_eq!(a.watching().unwrap().behavior, first);
    assert_eq!(a.adapter().context(), &cargo("hazardous"));
    // The operator minds it with hazardous cargo: it falls, and the episode that follows
    // settles on another behavior, learned with hazardous cargo.
    let hazardous = fall(&mut a);
    assert_ne!(hazardous, first);
    settle(&mut a);
    // Back to normal cargo: the behavior settled on there, in an episode of its own.
    let back = a.switch_context(Context::default(), false).unwrap();
    assert_eq!(
        (back.behavior, back.from, back.gave_up_watch),
        (first, SwitchStart::Resumed, true)
    );
    assert!(a.watching().is_none());
    assert_eq!(a.in_use().unwrap(), (first, TrustEstimate::default()));
    // Mid-episode, back to hazardous cargo: the episode ends and one begins from the
    // behavior settled on there.
    a.record(&DONE).unwrap();
    let again = a.switch_context(cargo("hazardous"), false).unwrap();
    assert_eq!(
        (again.behavior, again.from, again.gave_up_watch),
        (hazardous, SwitchStart::Resumed, false)
    );
    assert_eq!(a.in_use().unwrap(), (hazardous, TrustEstimate::default()));
    // A context never settled in, mid-episode: the episode begins again in it from the
    // behavior in use.
    a.record(&DONE).unwrap();
    let fresh = a.switch_context(cargo("explosive"), false).unwrap();
    assert_eq!(
        (fresh.behavior, fresh.from),
        (hazardous, SwitchStart::Restarted)
    );
    assert_eq!(a.in_use().unwrap(), (hazardous, TrustEstimate::default()));
    // A new operator: what was settled on for the last one is forgotten, and with a
    // learned start the case memory's guess for the context is taken (the case the
    // hazardous episode retained).
    a.abandon_episode();
    a.set_context(Context::default()).unwrap();
    a.begin_episode(Behavior::new(&[3, 3])).unwrap();
    let guessed = a.switch_context(cargo("hazardous"), true).unwrap();
    assert_eq!(
        (guessed.behavior, guessed.from),
        (hazardous, SwitchStart::Guessed)
    );
    // Without a learned start, or with no case in the context, it carries on.
    let blank = a.switch_context(cargo("explosive"), true).unwrap();
    assert_eq!(
        (blank.behavior, blank.from),
        (hazardous, SwitchStart::Restarted)
    );
}

/// Settled on `[0, 0]` in normal cargo, then (`[0, 0]` having fallen with hazardous cargo)
/// on another behavior there, the robot back in normal cargo resumes `[0, 0]`, an episode
/// from it. Returns the two behaviors.
fn resumed_in_normal_cargo(a: &mut MissionAdapter) -> (Behavior, Behavior) {
    let first = Behavior::new(&[0, 0]);
    a.begin_episode(first).unwrap();
    settle(a);
    a.switch_context(cargo("hazardous"), false).unwrap();
    let hazardous = fall(a);
    settle(a);
    let back = a.switch_context(Context::default(), false).unwrap();
    assert_eq!((back.behavior, back.from), (first, SwitchStart::Resumed));
    (first, hazardous)
}

/// To hazardous cargo (its behavior resumed) and back to normal cargo, where the behavior
/// last settled on was given up since: the episode under way begins again from the
/// behavior in use instead of resuming it.
fn back_and_forth_resumes_nothing_given_up(a: &mut MissionAdapter, hazardous: Behavior) {
    let there = a.switch_context(cargo("hazardous"), false).unwrap();
    assert_eq!(
        (there.behavior, there.from),
        (hazardous, SwitchStart::Resumed)
    );
    let again = a.switch_context(Context::default(), false).unwrap();
    assert_eq!(
        (again.behavior, again.from),
        (hazardous, SwitchStart::Restarted),
        "the behavior given up in this context was resumed"
    );
}

/// A behavior the robot gave up in a context is not resumed there: settled on in normal
/// cargo, it is resumed on the way back from hazardous cargo; once it has fallen there, a
/// later switch back does not go back to it (issue 52, item 11).
#[test]
fn a_context_switch_never_resumes_a_behavior_given_up_there() {
    let mut a = mission_adapter();
    let (first, hazardous) = resumed_in_normal_cargo(&mut a);
    settle(&mut a);
    assert_eq!(a.watching().unwrap().behavior, first);
    // Now the same operator minds it in normal cargo too: it falls, given up there, and
    // an episode searches on.
    assert_ne!(fall(&mut a), first);
    assert!(a.adapter().episode().is_some());
    back_and_forth_resumes_nothing_given_up(&mut a, hazardous);
}

/// An episode that gives up the behavior it resumed forgets it too: a switch away and
/// back mid-episode does not resume it again.
#[test]
fn an_episode_giving_up_a_resumed_behavior_forgets_it() {
    let mut a = mission_adapter();
    let (first, hazardous) = resumed_in_normal_cargo(&mut a);
    // Resumed, it begins an episode at 0: five interruptions give it up in that episode.
    assert_ne!(fall(&mut a), first);
    back_and_forth_resumes_nothing_given_up(&mut a, hazardous);
}
