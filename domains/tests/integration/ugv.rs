//! The UGV domain end to end: determinism, clearance of plans, and how operators judge
//! real simulated runs.

use cbr_core::Behavior;
use domains::causes;
use domains::geometry::Shape;
use domains::{EventKind, OperatorModel, Scenario, UgvDomain, builtin_operators};
use lab::Domain;
use proptest::prelude::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::path::Path;
use std::sync::OnceLock;
use trust::OutcomeKind;

fn domain(scenario: Scenario) -> &'static UgvDomain {
    static DOMAINS: [OnceLock<UgvDomain>; 2] = [OnceLock::new(), OnceLock::new()];
    DOMAINS[scenario as usize].get_or_init(|| UgvDomain::new(scenario))
}

fn behavior(scenario: Scenario, text: &str) -> Behavior {
    domain(scenario).space().parse(text).unwrap()
}

#[test]
fn the_same_seed_gives_the_same_trace() {
    for (scenario, text) in [
        (Scenario::Movement, "speed=6,padding=0.2"),
        (
            Scenario::Patrol,
            "speed=3,padding=0.3,scan_time=2,scan_distance=0.5",
        ),
    ] {
        let b = behavior(scenario, text);
        let d = domain(scenario);
        for seed in 0..20 {
            let a = d.simulate(&b, &mut ChaCha8Rng::seed_from_u64(seed), true);
            let c = d.simulate(&b, &mut ChaCha8Rng::seed_from_u64(seed), true);
            assert_eq!(a.trace, c.trace);
            assert_eq!(a.driven, c.driven);
            assert_eq!(a.objects, c.objects);
        }
        // And different seeds give different runs.
        let a = d.simulate(&b, &mut ChaCha8Rng::seed_from_u64(1), true);
        let c = d.simulate(&b, &mut ChaCha8Rng::seed_from_u64(2), true);
        assert_ne!(a.driven, c.driven);
    }
}

#[test]
fn the_route_needs_a_speed_to_meet_the_deadline() {
    // Slowest speed: no run arrives within 15 s; fastest: some do.
    let d = domain(Scenario::Movement);
    let arrivals = |text: &str| {
        let b = behavior(Scenario::Movement, text);
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        (0..50)
            .filter_map(|_| {
                let run = d.simulate(&b, &mut rng, false);
                run.trace.events.iter().find_map(|e| match e.kind {
                    EventKind::Arrived { .. } => Some(e.t),
                    _ => None,
                })
            })
            .collect::<Vec<f64>>()
    };
    assert!(arrivals("speed=0.5,padding=1").iter().all(|&t| t > 15.0));
    assert!(arrivals("speed=10,padding=1").iter().any(|&t| t <= 15.0));
}

#[test]
fn nominal_drives_bracket_the_movement_deadline() {
    let d = domain(Scenario::Movement);
    let b = behavior(Scenario::Movement, "speed=0.5,padding=0.5");
    let plan = d.plan(&b, 0).unwrap();
    let robot = &d.world().robot;
    assert!(domains::drive::nominal_duration(plan, robot, 0.5) > 15.0);
    assert!(domains::drive::nominal_duration(plan, robot, 10.0) < 15.0);
    // The direct route is the 45 m from depot to clinic, bent only slightly at the pinch.
    assert!((45.0..46.0).contains(&plan.length()));
}

#[test]
fn an_operator_with_p_collision_zero_never_interrupts_for_a_collision() {
    let mut op = builtin_operators(Scenario::Movement)[2].clone();
    op.p_collision = 0.0;
    let d = domain(Scenario::Movement);
    let b = behavior(Scenario::Movement, "speed=5,padding=0.1");
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut collided = 0;
    for _ in 0..300 {
        let mut probe = rng.clone();
        collided += d.simulate(&b, &mut probe, false).trace.collisions();
        assert_ne!(d.run(&b, &op, &mut rng).truth, Some(causes::COLLISION));
    }
    assert!(
        collided > 0,
        "the behavior must collide for the test to mean anything"
    );
}

#[test]
fn a_clean_run_within_the_deadline_completes() {
    for scenario in Scenario::ALL {
        let d = domain(scenario);
        let text = match scenario {
            Scenario::Movement => "speed=4.5,padding=0.5",
            Scenario::Patrol => "speed=2,padding=0.3,scan_time=3,scan_distance=0.25",
        };
        let b = behavior(scenario, text);
        let mut clean = 0;
        for seed in 0..200 {
            let run = d.simulate(&b, &mut ChaCha8Rng::seed_from_u64(seed), false);
            let spotless = run.trace.events.iter().all(|e| match e.kind {
                EventKind::Labelled {
                    explosive,
                    labelled_explosive,
                    ..
                } => explosive == labelled_explosive,
                // Measurements, not endings: the paper's operators ignore them.
                EventKind::Arrived { .. }
                | EventKind::PassedPerson { .. }
                | EventKind::ClosestPass { .. }
                | EventKind::Scanned { .. } => true,
                _ => false,
            });
            let last = run.trace.events.last().unwrap().t;
            for op in builtin_operators(scenario) {
                if spotless && last <= op.t_complete {
                    clean += 1;
                    let outcome = op
                        .judge(&run.trace, &mut ChaCha8Rng::seed_from_u64(seed))
                        .outcome;
                    assert_eq!(outcome.kind, OutcomeKind::Completed);
                    assert_eq!(outcome.duration_s, last);
                }
            }
        }
        assert!(clean > 0, "{scenario}: no clean run to check");
    }
}

#[test]
fn stuck_runs_are_interrupted_for_being_stuck() {
    let d = domain(Scenario::Movement);
    let b = behavior(Scenario::Movement, "speed=5,padding=2");
    let op = &builtin_operators(Scenario::Movement)[0];
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let stuck = (0..200)
        .map(|_| d.run(&b, op, &mut rng))
        .filter(|o| o.truth == Some(causes::STUCK))
        .inspect(|o| assert_eq!(o.outcome.kind, OutcomeKind::Interrupted))
        .count();
    // Blocked only when people stand in the way: sometimes, not always.
    assert!(stuck > 0 && stuck < 200, "{stuck}");
}

#[test]
fn a_new_operator_needs_no_code() {
    let text = r#"(
        name: "impatient",
        t_complete: 10.0,
        p_deadline: 1.0,
        p_collision: 0.0,
        give_up_factor: 1.5,
    )"#;
    let op = OperatorModel::from_ron(
        text,
        Path::new("impatient.ron"),
        Scenario::Movement.causes(),
    )
    .unwrap();
    let d = domain(Scenario::Movement);
    let b = behavior(Scenario::Movement, "speed=2,padding=0.5");
    let outcome = d.run(&b, &op, &mut ChaCha8Rng::seed_from_u64(1));
    assert_eq!(outcome.truth, Some(causes::DEADLINE));
    assert_eq!(outcome.outcome.duration_s, 10.0);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    #[test]
    fn planned_paths_keep_their_clearance(padding in 0u16..20, humans in 0u32..16, patrol: bool) {
        let scenario = if patrol { Scenario::Patrol } else { Scenario::Movement };
        let d = domain(scenario);
        let mut b = Behavior::new(&vec![0; d.space().components().len()]);
        b = b.with(1, padding);
        let clearance = d.world().robot.radius + d.settings(&b).padding;
        if let Some(plan) = d.plan(&b, humans) {
            let obstacles: Vec<&Shape> = d.world().obstacles_with(humans).collect();
            for w in plan.points.windows(2) {
                for o in &obstacles {
                    prop_assert!(o.distance_to_segment(w[0], w[1]) >= clearance - 1e-6);
                }
            }
            prop_assert_eq!(plan.points.first(), d.route().first());
            prop_assert_eq!(plan.points.last(), d.route().last());
        }
    }
}

#[test]
fn padding_keeps_the_scanner_away_from_objects() {
    let d = domain(Scenario::Patrol);
    let radius = d.world().robot.radius;
    for (text, gap) in [
        ("speed=2,padding=1,scan_time=1,scan_distance=0.25", 1.0),
        ("speed=2,padding=0.1,scan_time=1,scan_distance=0.75", 0.75),
    ] {
        let b = behavior(Scenario::Patrol, text);
        let mut scanned = 0;
        for seed in 0..20 {
            let run = d.simulate(&b, &mut ChaCha8Rng::seed_from_u64(seed), false);
            for fate in run.objects.iter().filter(|f| f.scanned_from.is_some()) {
                let from = fate.scanned_from.unwrap();
                assert!((from.dist(fate.object.at) - (radius + gap)).abs() < 1e-9);
                scanned += 1;
            }
        }
        assert!(scanned > 0);
    }
}

#[test]
fn the_patrol_deadline_binds_slow_robots() {
    let d = domain(Scenario::Patrol);
    let late = |text: &str| {
        let b = behavior(Scenario::Patrol, text);
        let mut rng = ChaCha8Rng::seed_from_u64(8);
        (0..40)
            .filter(|_| {
                let run = d.simulate(&b, &mut rng, false);
                run.trace.events.last().is_some_and(|e| e.t > 120.0)
            })
            .count()
    };
    assert_eq!(
        late("speed=0.5,padding=0.3,scan_time=2.5,scan_distance=0.5"),
        40
    );
    assert_eq!(
        late("speed=3,padding=0.3,scan_time=2.5,scan_distance=0.5"),
        0
    );
}

#[test]
fn the_robot_perceives_what_ended_a_run_when_it_can_and_nothing_else() {
    use trust::Observations;
    for scenario in Scenario::ALL {
        let d = domain(scenario);
        let declared = d.observations();
        let bit = |name| declared.iter().position(|&o| o == name);
        for op in builtin_operators(scenario) {
            let mut seen = Observations::NONE;
            for seed in 0..300u64 {
                let mut rng = ChaCha8Rng::seed_from_u64(seed);
                let b = d.space().draw(&mut rng);
                let judgement = d.run(&b, &op, &mut rng);
                let observed = judgement.outcome.observed;
                assert!(observed.indices().all(|i| i < declared.len()));
                assert_eq!(judgement.outcome.stated, None, "a run states nothing");
                // What ended the run, when the robot can perceive it, it perceived.
                let must = match judgement.truth {
                    Some(c)
                        if [causes::COLLISION, causes::STUCK, causes::DETONATION].contains(&c) =>
                    {
                        bit(c)
                    }
                    _ => None,
                };
                if let Some(i) = must {
                    assert!(observed.contains(i), "{judgement:?}");
                }
                seen = Observations::from_bits(seen.bits() | observed.bits());
            }
            // Over 300 random behaviors the robot makes most of its observations.
            for name in [causes::COLLISION, domains::perception::BEHIND_PLAN] {
                assert!(seen.contains(bit(name).unwrap()), "{scenario}: {name}");
            }
        }
    }
}

/// The paper's operators in the UGV's contexts (`operators/contexts/`,
/// docs/simulation.md#context): on a routine job with normal cargo each judges exactly as
/// its paper file; in an emergency every one minds lateness and tolerates bumps; with
/// hazardous cargo, alone or in an emergency, every one minds bumps and fast passes near
/// people present and tolerates lateness, at the paper's two reactions.
#[test]
fn the_paper_operators_in_contexts_follow_the_sites_rules() {
    use domains::operator::Comfort;
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("operators");
    let space = domains::job_context::contexts();
    let context = |pairs: &[(&str, &str)]| space.context(pairs.iter().copied()).unwrap();
    let emergency = context(&[("situation", "emergency")]);
    let hazardous = [
        context(&[("cargo", "hazardous")]),
        context(&[("cargo", "hazardous"), ("situation", "emergency")]),
    ];
    let care = Comfort {
        distance: 3.6,
        speed: 1.4,
        p: 0.95,
        expected_too: false,
    };
    let mut seen = 0;
    for scenario in [Scenario::Movement, Scenario::Patrol] {
        let folder = root.join("contexts").join(scenario.as_str());
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            let there = OperatorModel::load(&path, scenario.causes()).unwrap();
            let paper_path = root.join(scenario.as_str()).join(path.file_name().unwrap());
            let paper = OperatorModel::load(&paper_path, scenario.causes()).unwrap();
            let mut routine = there.in_context(&cbr_core::Context::default());
            routine.contexts.clear();
            assert_eq!(routine, paper, "{}", path.display());
            let urgent = there.in_context(&emergency);
            assert_eq!((urgent.p_deadline, urgent.p_collision), (0.95, 0.05));
            assert_eq!(urgent.comfort, paper.comfort);
            for careful in hazardous.iter().map(|c| there.in_context(c)) {
                assert_eq!((careful.p_deadline, careful.p_collision), (0.05, 0.95));
                assert_eq!(careful.comfort, Some(care));
                assert_eq!(careful.t_complete, paper.t_complete);
            }
            seen += 1;
        }
    }
    assert_eq!(seen, 5);
}

/// What the paper's operators would state, by hand from their files: minding what they
/// react to with probability at least 0.5, and none of the preferences they do not have.
#[test]
fn the_paper_operators_state_what_their_files_say_they_mind() {
    let said = |scenario: Scenario, operator: &OperatorModel| -> Vec<String> {
        domain(scenario)
            .true_statements(operator)
            .iter()
            .map(ToString::to_string)
            .collect()
    };
    let movement = builtin_operators(Scenario::Movement);
    let by_name =
        |ops: &[OperatorModel], name: &str| ops.iter().find(|o| o.name == name).unwrap().clone();
    assert_eq!(
        said(Scenario::Movement, &by_name(&movement, "safety-focused")),
        [
            "not hurry",
            "avoid-bumps",
            "not keep-away-from-people",
            "not keep-clear"
        ]
    );
    assert_eq!(
        said(Scenario::Movement, &by_name(&movement, "speed-focused")),
        [
            "hurry",
            "not avoid-bumps",
            "not keep-away-from-people",
            "not keep-clear"
        ]
    );
    // Patrol operators react to every missed object and false alarm (their files leave
    // the probabilities at 1) and keep no scan standard.
    let patrol = builtin_operators(Scenario::Patrol);
    assert_eq!(
        said(Scenario::Patrol, &by_name(&patrol, "detection-focused")),
        [
            "not hurry",
            "not avoid-bumps",
            "not keep-away-from-people",
            "not keep-clear",
            "scan-every-object",
            "no-false-alarms",
            "not scan-closely"
        ]
    );
    // Exactly at the threshold an operator minds it; just below, it does not.
    let mut edge = by_name(&movement, "balanced");
    edge.p_deadline = 0.5;
    edge.p_collision = 0.499;
    assert_eq!(
        said(Scenario::Movement, &edge)[..2],
        ["hurry", "not avoid-bumps"]
    );
    assert_eq!(
        domain(Scenario::Patrol).statements(),
        domains::statements::PATROL
    );
}
