//! Missions whose robot's context switches and is told so: the switches are the same for
//! every arm and the oracle, an arm blind to its context meets them on the same missions,
//! the learned start reads the context, the oracle knows each operator in each context,
//! and the report gives the switches apart from the operator changes.

use cbr_core::{Behavior, Case, Context, ContextSpace, ContextVariable};
use lab::mission::ChangeRecord;
use lab::mission::contexts::{
    SwitchFigures, switch_targets, switches_back_by_start, versus_blind_twins,
};
use lab::mission::report::{missions_json, missions_markdown};
use lab::mission::summary::MissionSummary;
use lab::mission::{
    ChangeKind, Changes, ContextSwitches, MissionPlan, MissionResult, run_missions,
};
use lab::reference::known_operator::LimitSettings;
use lab::testing::ToyDomain;
use lab::{Arm, Domain, Judgement, PlanError};
use rand::Rng;
use trust::{
    AdapterConfig, Cause, Evaluated, RetrieverKind, SwitchStart, TrustCaseBase, TrustProblem,
};

const BUMPED: Cause = Cause::from_static("bumped");

/// The behavior an operator trusts: every other one bumps four times in five.
struct Favourite(Behavior);

impl lab::SimulatedOperator for Favourite {}

/// A 6 x 6 grid whose robot knows its cargo (normal, hazardous); with hazardous cargo
/// every operator's favourite is the mirror image of its own (`(5 - x, 5 - y)`).
fn toy() -> ToyDomain<Favourite> {
    ToyDomain::grid(
        "toy",
        &[6, 6],
        &[BUMPED],
        |behavior, operator: &Favourite, _, rng| {
            let bumps = if *behavior == operator.0 { 0.05 } else { 0.8 };
            if rng.random_bool(bumps) {
                Judgement::interrupted(1.0, BUMPED, 1.0)
            } else {
                Judgement::completed(1.0, 1.0)
            }
        },
    )
    .in_contexts(
        ContextSpace::new(vec![ContextVariable::new(
            "cargo",
            &["normal", "hazardous"],
        )])
        .unwrap(),
    )
    .judging_in_context(|operator, context| {
        (context.get("cargo") == Some("hazardous")).then(|| {
            let [x, y] = operator.0.indices()[..] else {
                unreachable!("two components")
            };
            Favourite(Behavior::new(&[5 - x, 5 - y]))
        })
    })
}

fn hazardous(domain: &ToyDomain<Favourite>) -> Context {
    domain.contexts().context([("cargo", "hazardous")]).unwrap()
}

fn operators() -> Vec<(String, Favourite)> {
    vec![
        ("low".to_owned(), Favourite(Behavior::new(&[1, 1]))),
        ("high".to_owned(), Favourite(Behavior::new(&[4, 5]))),
    ]
}

fn arm(name: &str) -> Arm {
    Arm::builtin(name, RetrieverKind::Linear).unwrap()
}

fn plan<'a>(
    domain: &'a ToyDomain<Favourite>,
    operators: &'a [(String, Favourite)],
    missions: u32,
    arms: Vec<Arm>,
) -> MissionPlan<'a, ToyDomain<Favourite>> {
    MissionPlan {
        name: "toy".into(),
        domain,
        operators,
        missions,
        commands: 300,
        changes: Changes {
            every: 150.0,
            takeover: 0.5,
        },
        contexts: Some(ContextSwitches {
            among: vec![Context::default(), hazardous(domain)],
            every: 50.0,
        }),
        complacency: None,
        adapter: AdapterConfig::default(),
        arms,
        feedback: None,
        truth_runs: 50,
        limit: LimitSettings::default(),
        competence: None,
        offer_safer: false,
        change_detector: None,
    }
}

fn run(plan: MissionPlan<'_, ToyDomain<Favourite>>, seed: u64) -> Result<MissionResult, PlanError> {
    Ok(run_missions(&[plan], seed, &|_| {})?.remove(0))
}

#[test]
fn every_arm_and_the_oracle_meet_the_same_switches_and_the_report_gives_them_apart() {
    let (domain, operators) = (toy(), operators());
    let arms = vec![
        arm("case-based+learned-start"),
        arm("case-based+context-blind+learned-start"),
    ];
    let result = run(plan(&domain, &operators, 20, arms), 7).unwrap();
    assert!(result.context_switches);
    let course = |changes: &[lab::mission::ChangeRecord]| -> Vec<(u32, ChangeKind, bool)> {
        changes.iter().map(|c| (c.at, c.kind, c.back)).collect()
    };
    let [told, blind] = result.arms.as_slice() else {
        panic!("two arms")
    };
    for (k, m) in told.missions.iter().enumerate() {
        assert_eq!(course(&m.changes), course(&blind.missions[k].changes));
        assert_eq!(course(&m.changes), course(&result.oracle[k].changes));
        assert_eq!(m.context, blind.missions[k].context);
        // Two contexts: every switch after the first goes back to one the mission was in.
        let switches: Vec<bool> = m
            .changes
            .iter()
            .filter(|c| c.kind == ChangeKind::Context)
            .map(|c| c.back)
            .collect();
        assert!(switches.iter().skip(1).all(|&back| back), "{switches:?}");
        assert!(switches.first().is_none_or(|&back| !back));
        // What the told robot went on with is recorded at each switch, and only there:
        // not at an operator change (it is not told), nor for its blind twin or the
        // oracle.
        for c in &m.changes {
            assert_eq!(c.start.is_some(), c.kind == ChangeKind::Context, "{c:?}");
        }
        let unrecorded = |changes: &[ChangeRecord]| changes.iter().all(|c| c.start.is_none());
        assert!(unrecorded(&blind.missions[k].changes));
        assert!(unrecorded(&result.oracle[k].changes));
    }
    let switches: usize = told
        .missions
        .iter()
        .map(|m| {
            m.changes
                .iter()
                .filter(|c| c.kind == ChangeKind::Context)
                .count()
        })
        .sum();
    // About 300 / 50 switches a mission.
    assert!((60..=180).contains(&switches), "{switches}");
    // The operator changes' figures leave the switches out; the switches' figures count
    // them all.
    let summary = MissionSummary::of(told);
    let figures = SwitchFigures::of(told.missions.iter().flat_map(|m| &m.changes));
    let changes: usize = told.missions.iter().map(|m| m.changes.len()).sum();
    assert_eq!(summary.changes + figures.all.changes, changes);
    assert_eq!(figures.all.changes, switches);
    // The oracle knows each operator in each context: after a switch it tries the
    // operator's favourite there first.
    let oracle = SwitchFigures::of(result.oracle.iter().flat_map(|m| &m.changes));
    let oracle_back = oracle.back.untrustworthy_per_change.unwrap().mean;
    let told_back = figures.back.untrustworthy_per_change.unwrap().mean;
    assert!(oracle_back < told_back, "{oracle_back} {told_back}");
    // The report: a section of its own, the twins paired switch by switch, the targets.
    let [versus] = versus_blind_twins(&result).try_into().unwrap();
    assert_eq!(
        (versus.arm.as_str(), versus.twin.as_str()),
        (
            "case-based+learned-start",
            "case-based+context-blind+learned-start"
        )
    );
    assert_eq!(versus.switches, figures.back.changes);
    let targets = switch_targets(&result, 0);
    assert_eq!(targets.len(), 2, "{targets:?}");
    assert!(targets[0].starts_with("best arm after a switch back"));
    let md = missions_markdown(std::slice::from_ref(&result));
    assert!(md.contains("Announced context switches") && md.contains("Told against blind"));
    let json = missions_json(std::slice::from_ref(&result));
    assert_eq!(
        json[0]["context_switches"]["versus_blind"][0]["switches_back"],
        versus.switches
    );
    // Every switch back of the told arm in one kind or another; none for the blind twin.
    let by_start = switches_back_by_start(told, &result.oracle);
    assert_eq!(
        by_start.iter().map(|r| r.switches).sum::<usize>(),
        figures.back.changes
    );
    assert!(switches_back_by_start(blind, &result.oracle).is_empty());
    assert!(md.contains("Switches back by what the told robot went on with"));
    let first = &json[0]["context_switches"]["arms"][0]["back_by_start"][0];
    assert_eq!(first["switches"], by_start[0].switches);
}

#[test]
fn switches_back_by_what_the_robot_went_on_with_by_hand() {
    let (domain, operators) = (toy(), operators());
    let arms = vec![arm("case-based")];
    let mut result = run(plan(&domain, &operators, 1, arms), 7).unwrap();
    let change = |at, kind, back, start, needed, untrustworthy| ChangeRecord {
        at,
        kind,
        needed,
        trusted_again: None,
        untrustworthy,
        back,
        start,
        noticed: None,
    };
    let (kept, resumed) = (Some(SwitchStart::Kept), Some(SwitchStart::Resumed));
    // The arm: two switches back it kept (2 and 4 untrustworthy commands, one needing
    // adaptation), one it resumed from (6), a first switch (not back) and an operator
    // change, which are left out.
    result.arms[0].missions[0].changes = vec![
        change(10, ChangeKind::Context, false, kept, false, 9),
        change(20, ChangeKind::Context, true, kept, true, 2),
        change(30, ChangeKind::Shift, false, None, true, 9),
        change(40, ChangeKind::Context, true, resumed, false, 6),
        change(50, ChangeKind::Context, true, kept, false, 4),
    ];
    // The oracle on the same changes: 1, 0 and 2 on the kept ones' switches, 3 on the
    // resumed one's.
    result.oracle[0].changes = vec![
        change(10, ChangeKind::Context, false, None, false, 5),
        change(20, ChangeKind::Context, true, None, true, 1),
        change(30, ChangeKind::Shift, false, None, false, 7),
        change(40, ChangeKind::Context, true, None, false, 3),
        change(50, ChangeKind::Context, true, None, false, 0),
    ];
    result.oracle[0].mission = result.arms[0].missions[0].mission;
    let [kept, resumed] = switches_back_by_start(&result.arms[0], &result.oracle)
        .try_into()
        .unwrap();
    assert_eq!(
        (kept.start, kept.switches, kept.needed),
        (SwitchStart::Kept, 2, 1)
    );
    assert!((kept.untrustworthy.mean - 3.0).abs() < 1e-12);
    assert!((kept.oracle.mean - 0.5).abs() < 1e-12);
    assert_eq!(
        (resumed.start, resumed.switches, resumed.needed),
        (SwitchStart::Resumed, 1, 0)
    );
    assert!((resumed.untrustworthy.mean - 6.0).abs() < 1e-12);
    assert!((resumed.oracle.mean - 3.0).abs() < 1e-12);
}

#[test]
fn the_learned_start_reads_the_context_a_mission_starts_in() {
    let (domain, operators) = (toy(), operators());
    // One case learned with normal cargo (the low operator's favourite) and one with
    // hazardous cargo (its mirror image): the memory's guess in each context is its own.
    let case = |context: Context, solution: Behavior| Case {
        problem: TrustProblem {
            context,
            evaluated: vec![Evaluated {
                behavior: Behavior::new(&[3, 3]),
                time: 5.0,
            }],
        },
        solution,
    };
    let mut cases = TrustCaseBase::new();
    cases.push(case(Context::default(), Behavior::new(&[1, 1])));
    cases.push(case(hazardous(&domain), Behavior::new(&[4, 4])));
    let with_cases = |name: &str| arm(name).with_starting_cases(cases.clone());
    let mut started = Vec::new();
    for seed in 0..12 {
        let arms = vec![
            with_cases("case-based+learned-start"),
            with_cases("case-based+context-blind+learned-start"),
            with_cases("case-based"),
        ];
        let result = run(plan(&domain, &operators, 1, arms), seed).unwrap();
        let [told, blind, random] = result.arms.as_slice() else {
            panic!("three arms")
        };
        let (told, blind, random) = (&told.missions[0], &blind.missions[0], &random.missions[0]);
        let expected = if told.context == hazardous(&domain) {
            Behavior::new(&[4, 4])
        } else {
            Behavior::new(&[1, 1])
        };
        assert_eq!(told.learned_start, Some(expected), "seed {seed}");
        // The blind twin is in the default context whatever the cargo: it starts from the
        // case learned there.
        assert_eq!(blind.learned_start, Some(Behavior::new(&[1, 1])));
        assert_eq!(random.learned_start, None);
        started.push(told.context.clone());
    }
    assert!(started.contains(&Context::default()) && started.contains(&hazardous(&domain)));
}

#[test]
fn switches_need_two_contexts() {
    let (domain, operators) = (toy(), operators());
    let mut one = plan(&domain, &operators, 1, vec![arm("case-based")]);
    one.contexts.as_mut().unwrap().among.truncate(1);
    let err = run(one, 1).unwrap_err().to_string();
    assert!(err.contains("at least two contexts"), "{err}");
    let mut twice = plan(&domain, &operators, 1, vec![arm("case-based")]);
    twice.contexts.as_mut().unwrap().among[1] = Context::default();
    let err = run(twice, 1).unwrap_err().to_string();
    assert!(err.contains("among[1]: a context already listed"), "{err}");
}
