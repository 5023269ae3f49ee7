//! The doors of a plug-in the warehouse goes through, one by one: what its robot perceives
//! and what that hints at (the domain kit checks them against each other), operators who
//! explain themselves, a family of operators who disagree, and a searcher of its own
//! checked by the searcher conformance kit and offered as arms through the catalog.

use std::path::Path;
use trustcbr::cbr_core::{Behavior, BehaviorSpace, Proposal, Rationale, Searcher};
use trustcbr::lab::{Domain, FeedbackChannel};
use trustcbr::rand::SeedableRng;
use trustcbr::rand::rngs::StdRng;
use trustcbr::trust::testing::{check_searcher, check_searcher_on};
use trustcbr::trust::{Cause, Evaluated, Observations, Outcome, RetrieverKind};
use trustcbr::{Catalog, Family, Readings};
use warehouse::perception::{BEHIND_PLAN, FIRM_GRIP, OBSERVATIONS, SAFETY_STOP};
use warehouse::population::{family, member};
use warehouse::searcher::Trouble;
use warehouse::space::warehouse_space;
use warehouse::{
    Troubleshooter, WarehouseCatalog, WarehouseCause, WarehouseDomain, WarehouseOperator,
    builtin_operators,
};

fn shipped(name: &str) -> WarehouseOperator {
    builtin_operators()
        .into_iter()
        .find(|o| o.name == name)
        .unwrap()
}

#[test]
fn observations_and_hints_are_declared_and_hint_only_at_what_is_not_perceived() {
    let domain = WarehouseDomain::new();
    let names: Vec<&str> = domain.observations().iter().map(Cause::as_str).collect();
    assert_eq!(
        names,
        [
            "safety-stop",
            "item-not-found",
            "firm-grip",
            "dropped-item",
            "behind-plan"
        ]
    );
    for hint in domain.hints() {
        // A hint points at a cause the robot cannot perceive: none is named after one.
        assert!(!domain.observations().contains(&hint.suggests), "{hint:?}");
        assert!(domain.causes().iter().any(|d| d.name == hint.suggests));
    }
}

#[test]
fn an_operator_file_may_carry_its_feedback_channel() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("talkative.ron");
    let text = |explains: &str| {
        format!(
            "(name: \"talkative\", t_complete: 60.0, p_deadline: 0.9, p_collision: 0.9,\n \
             p_crushed: 0.5,\n feedback: (explains: {explains}, wrong: 0.1))"
        )
    };
    std::fs::write(&path, text("0.3")).unwrap();
    let operator = WarehouseOperator::load(&path).unwrap();
    let domain = WarehouseDomain::new();
    assert_eq!(
        domain.feedback(&operator),
        FeedbackChannel::new(0.3, 0.1).unwrap()
    );
    // The shipped operators say nothing, as the paper's.
    for operator in builtin_operators() {
        assert!(domain.feedback(&operator).is_silent(), "{}", operator.name);
    }
    // A share out of range is refused where it is written.
    std::fs::write(&path, text("1.5")).unwrap();
    let err = WarehouseOperator::load(&path).unwrap_err().to_string();
    assert!(
        err.contains("talkative.ron:3:")
            && err.contains("feedback `explains` must be a probability in [0, 1], got 1.5"),
        "{err}"
    );
}

fn unnamed(mut operator: WarehouseOperator) -> WarehouseOperator {
    operator.name.clear();
    operator
}

#[test]
fn the_family_runs_from_throughput_through_the_balanced_operator_to_care() {
    for (x, pole) in [
        (-1.0, "throughput-focused"),
        (0.0, "balanced"),
        (1.0, "care-focused"),
    ] {
        assert_eq!(unnamed(member(x, "")), unnamed(shipped(pole)), "{x}");
    }
    // Halfway to care: sqrt(60 x 120) s; 0.95 -> 0.05 deadline, 0.5 -> 0.95 damage; the
    // care pole's weights (damage 1, the rest 0.5).
    let half = member(0.5, "half");
    assert!((half.t_complete - 7200f64.sqrt()).abs() < 1e-9);
    assert!((half.p_deadline - 0.5).abs() < 1e-12);
    assert!((half.p_collision - 0.95).abs() < 1e-12);
    assert!((half.p_crushed - 0.725).abs() < 1e-12);
    assert_eq!(half.weights, shipped("care-focused").weights);
    assert_eq!(member(-0.5, "").weights, shipped("balanced").weights);
    // Every member is a valid operator: it round-trips through an operator file.
    let text = trustcbr::ron::to_string(&member(-0.3, "m")).unwrap();
    assert_eq!(
        WarehouseOperator::from_ron(&text, Path::new("m.ron")).unwrap(),
        member(-0.3, "m")
    );
}

#[test]
fn conflict_sets_how_far_members_sit_from_the_base() {
    let at = |conflict: f64| -> Vec<WarehouseOperator> {
        family(conflict, 16, 7).into_iter().map(unnamed).collect()
    };
    assert!(at(0.0).iter().all(|m| *m == unnamed(shipped("balanced"))));
    let poles = [
        unnamed(shipped("throughput-focused")),
        unnamed(shipped("care-focused")),
    ];
    let one = at(1.0);
    assert!(one.iter().all(|m| poles.contains(m)));
    assert!(poles.iter().all(|p| one.contains(p)), "both sides drawn");
    assert_eq!(family(0.5, 5, 3), family(0.5, 5, 3));
    assert_ne!(family(0.5, 5, 3), family(0.5, 5, 4));
    assert_eq!(family(0.5, 5, 3)[4].name, "family-c0.50-4");
    // Through the catalog, for a suite's `population: (family: ...)`.
    let drawn = WarehouseCatalog
        .family(
            "picking",
            &Family {
                conflict: 0.5,
                size: 5,
                seed: 3,
            },
            &Readings::new(),
        )
        .unwrap();
    assert_eq!(
        drawn.into_iter().map(|(_, o)| o).collect::<Vec<_>>(),
        family(0.5, 5, 3)
    );
}

fn interrupted(perceived: &[Cause]) -> Outcome {
    Outcome::interrupted(1.0, 30.0).observing(Observations::named(
        &OBSERVATIONS,
        perceived.iter().copied(),
    ))
}

fn failed(perceived: &[Cause]) -> Outcome {
    Outcome::failed(1.0, 30.0).observing(Observations::named(
        &OBSERVATIONS,
        perceived.iter().copied(),
    ))
}

#[test]
fn troubles_are_read_from_what_the_robot_was_told_and_perceived() {
    let dropped = WarehouseCause::DroppedItem.to_trust();
    // What the operator says comes first.
    assert_eq!(
        Trouble::of(&interrupted(&[SAFETY_STOP]).stating(Some(dropped))),
        [Trouble::Slipped]
    );
    // A perceived drop or missing slot is the trouble.
    assert_eq!(
        Trouble::of(&failed(&[FIRM_GRIP, dropped])),
        [Trouble::Slipped]
    );
    assert_eq!(
        Trouble::of(&failed(&[WarehouseCause::ItemNotFound.to_trust()])),
        [Trouble::Misplaced]
    );
    // An interruption with no stop perceived can only be the deadline.
    assert_eq!(Trouble::of(&interrupted(&[FIRM_GRIP])), [Trouble::Late]);
    assert_eq!(
        Trouble::of(&interrupted(&[SAFETY_STOP, BEHIND_PLAN])),
        [Trouble::Crossing, Trouble::Late]
    );
    // A failure without a firm grip can only be a pick given up.
    assert_eq!(Trouble::of(&failed(&[SAFETY_STOP])), [Trouble::Late]);
    assert_eq!(Trouble::of(&failed(&[FIRM_GRIP])), [Trouble::Crushed]);
}

/// The troubleshooter's proposal after `outcome` three times on `from`.
fn repair(from: &str, outcome: Outcome) -> (Behavior, Behavior, Rationale) {
    let space = warehouse_space();
    let from = space.parse(from).unwrap();
    let mut searcher = Troubleshooter::new();
    searcher.begin_episode(&space, &from);
    for _ in 0..3 {
        searcher.observe(&from, &outcome);
    }
    let evaluated = [Evaluated {
        behavior: from,
        time: 90.0,
    }];
    let Proposal::Next(to) = searcher.propose(&space, &evaluated, &mut StdRng::seed_from_u64(1))
    else {
        panic!("1,799 behaviors are untried");
    };
    (from, to, searcher.rationale(&to))
}

/// The components (by name) on which `a` and `b` differ.
fn changed(space: &BehaviorSpace, a: &Behavior, b: &Behavior) -> Vec<String> {
    space
        .components()
        .iter()
        .enumerate()
        .filter(|&(k, _)| a.get(k) != b.get(k))
        .map(|(_, c)| c.name.clone())
        .collect()
}

#[test]
fn the_troubleshooter_changes_the_component_the_trouble_implicates() {
    let space = warehouse_space();
    let speed = |b: &Behavior| space.components()[2].numeric_value(b.get(2));
    let force = |b: &Behavior| space.components()[3].numeric_value(b.get(3));
    // Hard stops: slower, nothing else.
    let (from, to, why) = repair(
        "gripper=suction,map=as-built,speed=2,grip_force=50",
        interrupted(&[SAFETY_STOP]),
    );
    assert_eq!(changed(&space, &from, &to), ["speed"]);
    assert!(speed(&to) < 2.0);
    assert!(matches!(why, Rationale::Expects { .. }), "{why:?}");
    // A drop: firmer, same gripper.
    let (from, to, _) = repair(
        "gripper=parallel-jaw,map=live,speed=1,grip_force=20",
        failed(&[WarehouseCause::DroppedItem.to_trust()]),
    );
    assert_eq!(changed(&space, &from, &to), ["grip_force"]);
    assert!(force(&to) > 20.0);
    // At the strongest grip there is no firmer one: another gripper.
    let (from, to, _) = repair(
        "gripper=parallel-jaw,map=live,speed=1,grip_force=100",
        failed(&[WarehouseCause::DroppedItem.to_trust()]),
    );
    assert_ne!(to.get(0), from.get(0));
    assert_eq!((to.get(1), to.get(2)), (from.get(1), from.get(2)));
    // A misplaced slot on the as-built plan: a fresher map.
    let (from, to, _) = repair(
        "gripper=suction,map=as-built,speed=1,grip_force=50",
        failed(&[WarehouseCause::ItemNotFound.to_trust()]),
    );
    assert_eq!(changed(&space, &from, &to), ["map"]);
    // Too slow on the live map, whose speed is capped at 1 m/s: no faster speed drives
    // faster on it, so a map that lets the robot drive above 1 m/s.
    let (from, to, _) = repair(
        "gripper=suction,map=live,speed=1.5,grip_force=50",
        interrupted(&[]),
    );
    assert_ne!(to.get(1), from.get(1));
    assert!(speed(&to) > 1.0);
    assert_eq!((to.get(0), to.get(3)), (from.get(0), from.get(3)));
    // Unexplained commands implicate nothing: it explores.
    let space = warehouse_space();
    let from = space
        .parse("gripper=suction,map=live,speed=1,grip_force=50")
        .unwrap();
    let mut searcher = Troubleshooter::new();
    searcher.begin_episode(&space, &from);
    let evaluated = [Evaluated {
        behavior: from,
        time: 3.0,
    }];
    let Proposal::Next(to) = searcher.propose(&space, &evaluated, &mut StdRng::seed_from_u64(2))
    else {
        panic!("untried behaviors remain");
    };
    assert!(matches!(
        searcher.rationale(&to),
        Rationale::Explores { .. }
    ));
}

#[test]
fn the_troubleshooter_keeps_the_searcher_contract() {
    // On the kit's random spaces (none has the warehouse's components: it explores)...
    check_searcher(|| Box::new(Troubleshooter::new()));
    // ...and on the warehouse's own, where the kit's stated drops implicate the grip.
    check_searcher_on(&warehouse_space(), || Box::new(Troubleshooter::new()));
}

#[test]
fn the_catalog_offers_the_troubleshooter_alone_and_behind_case_reuse() {
    let arms = WarehouseCatalog.arms(RetrieverKind::Linear);
    let names: Vec<&str> = arms.iter().map(|a| a.name()).collect();
    assert_eq!(names, ["troubleshooter", "case-based+troubleshooter"]);
    assert!(!arms[0].reuses_cases() && arms[1].reuses_cases());
}
