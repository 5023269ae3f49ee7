//! The model's arithmetic, computed by hand: driving and stopping, grasping, the item mix,
//! the maps, whole picks under fixed draws, what the robot perceives of them, and the
//! operators' judgements.

use proptest::prelude::*;
use std::path::Path;
use trustcbr::lab::{Domain, Judgement};
use trustcbr::rand::{RngCore, SeedableRng};
use trustcbr::trust::Observations;
use warehouse::WarehouseCause;
use warehouse::domain::{Settings, WarehouseDomain};
use warehouse::gripper::{Grasp, Gripper};
use warehouse::items::{ITEM_MIX, draw_item};
use warehouse::map::MapSource;
use warehouse::motion::{leg_time, stop_for, time_at};
use warehouse::operator::{WarehouseOperator, builtin_operators};
use warehouse::perception::{BEHIND_PLAN, FIRM_GRIP, OBSERVATIONS, SAFETY_STOP, perceive};
use warehouse::trace::{Event, Trace};

/// A generator that returns the same word forever: `0` makes every uniform draw 0.0, `!0`
/// makes it the largest value below 1.
struct Constant(u64);

impl RngCore for Constant {
    fn next_u32(&mut self) -> u32 {
        self.0 as u32
    }
    fn next_u64(&mut self) -> u64 {
        self.0
    }
    fn fill_bytes(&mut self, dest: &mut [u8]) {
        dest.fill(self.0 as u8);
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

#[test]
fn legs_follow_the_trapezoid() {
    // 20 m at 2 m/s, 0.5 m/s^2: 4 m to reach speed (4 s), 12 m cruising (6 s), 4 m to stop.
    assert!(close(leg_time(20.0, 2.0), 14.0));
    assert!(close(time_at(2.0, 20.0, 2.0), 8f64.sqrt()));
    assert!(close(time_at(10.0, 20.0, 2.0), 7.0));
    assert!(close(time_at(18.0, 20.0, 2.0), 14.0 - 8f64.sqrt()));
    // 4 m is too short to reach 2 m/s: a triangle peaking at sqrt(0.5 x 4) m/s.
    assert!(close(leg_time(4.0, 2.0), 2.0 * 8f64.sqrt()));
}

#[test]
fn stops_brake_just_hard_enough_or_collide() {
    // At 2 m/s, seen 3 m ahead: 0.6 m to react, 2.4 m to brake: 4 / 4.8 m/s^2. Lost:
    // 2 / (2 x 0.833) braking + 2 / (2 x 0.5) accelerating + 2 s wait.
    let stop = stop_for(2.0, 3.0);
    assert!(!stop.collided);
    assert!(close(stop.decel, 4.0 / 4.8));
    assert!(close(stop.time_lost, 1.2 + 2.0 + 2.0));
    // Seen 1 m ahead: 0.4 m to brake needs 5 m/s^2 > 2: a collision, braking at 2.
    let stop = stop_for(2.0, 1.0);
    assert!(stop.collided);
    assert!(close(stop.decel, 2.0));
    assert!(close(stop.time_lost, 0.5 + 2.0 + 2.0 + 5.0));
    // Seen within the reaction distance: a collision.
    assert!(stop_for(2.0, 0.5).collided);
    // At 1 m/s, seen 4 m ahead: 0.135 m/s^2 would do; it brakes at its nominal 0.5.
    let stop = stop_for(1.0, 4.0);
    assert!(!stop.collided);
    assert!(close(stop.decel, 0.5));
    assert!(close(stop.time_lost, 1.0 + 1.0 + 2.0));
    // At 2.5 m/s every crossing seen nearer than 0.75 + 6.25 / 4 = 2.3125 m is hit.
    assert!(stop_for(2.5, 2.3).collided);
    assert!(!stop_for(2.5, 2.33).collided);
}

fn item(class: usize, mass_kg: f64) -> warehouse::items::Item {
    warehouse::items::Item {
        class,
        mass_kg,
        surface: ITEM_MIX[class].surface,
        crush_limit_n: ITEM_MIX[class].crush_limit_n.unwrap_or(f64::INFINITY),
    }
}

#[test]
fn grasps_hold_by_seal_or_friction_and_crush_by_squeeze() {
    // Every uniform draw 0.0: the grasp lands at 0.7 of nominal.
    let mut worst = Constant(0);
    // Suction at 50 N on a 2 kg carton: seal 0.5, 50 x 0.5 x 0.7 = 17.5 N; the load at
    // 0.5 m/s^2 is 2 x (9.81 + 3 x 0.5) = 22.62 N: it slips as it pulls away.
    let carton = item(0, 2.0);
    let grasp = Grasp::new(Gripper::Suction, 50.0, &carton, &mut worst);
    assert!(close(grasp.holding_n, 17.5));
    assert!(close(grasp.load(0.5), 22.62));
    assert!(grasp.slips(0.5));
    // Landing at 1.3 of nominal (the largest draw): 32.5 N holds even through a full
    // safety stop, 2 x (9.81 + 3 x 2) = 31.62 N.
    let grasp = Grasp::new(Gripper::Suction, 50.0, &carton, &mut Constant(!0));
    assert!((grasp.holding_n - 32.5).abs() < 1e-6);
    assert!(!grasp.slips(2.0));
    // Jaws on a 3 kg oily part: 2 x 0.15 x 100 N x 0.7 = 21 N against 3 x 10.56 N.
    let part = item(4, 3.0);
    let grasp = Grasp::new(Gripper::ParallelJaw, 100.0, &part, &mut worst);
    assert!(close(grasp.holding_n, 21.0));
    assert!(grasp.slips(0.5));
    assert!(!grasp.crushed, "nothing crushes a machined part");
    // Produce stands 15 N between rigid pads: jaws at 20 N crush it; soft fingers commanded
    // 80 N give 40 N, spread over four times the area (60 N): intact.
    let produce = item(3, 0.5);
    assert!(Grasp::new(Gripper::ParallelJaw, 20.0, &produce, &mut worst).crushed);
    let soft = Grasp::new(Gripper::SoftFingers, 80.0, &produce, &mut worst);
    assert!(!soft.crushed);
    assert!(close(soft.holding_n, 2.0 * 0.9 * 40.0 * 0.7));
}

#[test]
fn the_item_mix_is_a_distribution_and_draws_are_placed_by_share() {
    let total: f64 = ITEM_MIX.iter().map(|c| c.share).sum();
    assert!(close(total, 1.0));
    // The smallest draws: the first class, its lightest item, its weakest packaging.
    let first = draw_item(&mut Constant(0));
    assert_eq!(first.class, 0);
    assert!(close(first.mass_kg, 0.5));
    assert!(close(first.crush_limit_n, 120.0 * 0.8));
    // The largest draws: the last class (hardware), its heaviest item.
    let last = draw_item(&mut Constant(!0));
    assert_eq!(ITEM_MIX[last.class].name, "hardware");
    assert!((last.mass_kg - 6.0).abs() < 1e-6);
    assert!(last.crush_limit_n.is_infinite());
}

#[test]
fn maps_misplace_slots_or_cap_the_speed() {
    assert_eq!(MapSource::AsBuilt.misplaced_share(), 0.20);
    assert_eq!(MapSource::LastSurvey.misplaced_share(), 0.04);
    assert_eq!(MapSource::Live.misplaced_share(), 0.0);
    assert_eq!(MapSource::Live.driving_speed(2.5), 1.0);
    assert_eq!(MapSource::Live.driving_speed(0.75), 0.75);
    assert_eq!(MapSource::LastSurvey.driving_speed(2.5), 2.5);
}

fn settings(gripper: Gripper, map: MapSource, speed: f64, grip_force: f64) -> Settings {
    Settings {
        gripper,
        map,
        speed,
        grip_force,
    }
}

#[test]
fn a_pick_with_every_draw_zero() {
    // The item: a 0.5 kg carton (crush limit 96 N); the shelf 10 m away; someone crosses
    // at every aisle end, stepping out 0.5 m ahead. One aisle end (5.4 m) per leg.
    // Out at 1 m/s: the crossing is reached at 2 s (ramp) + 4.4 s = 6.4 s and hit (0.2 m to
    // brake would need 2.5 m/s^2); the leg takes 12 s + 0.25 + 1 + 2 + 5 s lost = 20.25 s.
    // Label scan 1 s, the live map's slot is right, suction grasp 1.5 s: t = 22.75 s.
    // Holding 0.5 x 50 x 0.7 = 17.5 N against at most 0.5 x (9.81 + 3 x 2) = 7.9 N.
    // Back: the crossing at 22.75 + 6.4 s, the leg 20.25 s, release 0.5 s: 43.5 s.
    let domain = WarehouseDomain::new();
    let trace = domain.simulate(
        settings(Gripper::Suction, MapSource::Live, 1.0, 50.0),
        &mut Constant(0),
    );
    let expected = [
        (6.4, Event::Collision),
        (29.15, Event::Collision),
        (43.5, Event::Delivered { crushed: false }),
    ];
    assert_eq!(trace.events.len(), expected.len(), "{trace:?}");
    for (&(t, e), &(t_expected, e_expected)) in trace.events.iter().zip(&expected) {
        assert!(close(t, t_expected), "{t} != {t_expected}");
        assert_eq!(e, e_expected);
    }
    // With the last survey instead, the zero draw falls in its 4% of misplaced slots: the
    // pick ends at the label scan, 21.25 s.
    let trace = domain.simulate(
        settings(Gripper::Suction, MapSource::LastSurvey, 1.0, 50.0),
        &mut Constant(0),
    );
    assert_eq!(trace.events.len(), 2);
    assert!(close(trace.events[1].0, 21.25));
    assert_eq!(trace.events[1].1, Event::ItemNotFound);
}

#[test]
fn a_pick_with_every_draw_at_its_largest() {
    // A 6 kg oily part 40 m away; nobody crosses. Jaws at 100 N hold 2 x 0.15 x 100 x 1.3 =
    // 39 N against 6 x (9.81 + 1.5 x 0.5) = 63.4 N: dropped as the robot pulls away, after
    // the 24 s leg at 2 m/s, the 1 s label scan and the 3 s grasp.
    let domain = WarehouseDomain::new();
    let trace = domain.simulate(
        settings(Gripper::ParallelJaw, MapSource::AsBuilt, 2.0, 100.0),
        &mut Constant(!0),
    );
    assert_eq!(trace.events.len(), 1);
    assert!((trace.events[0].0 - 28.0).abs() < 1e-6);
    assert_eq!(trace.events[0].1, Event::DroppedItem);
}

#[test]
fn the_robot_perceives_its_stops_its_grip_and_its_plan() {
    // The pick of `a_pick_with_every_draw_zero`: both crossings are hit at 2 m/s^2, beyond
    // the nominal 0.5, so both are protective stops (6.4 s, 29.15 s). The plan: legs of
    // 12 s, the scan, the cup's 1.5 s and 0.5 s: 27 s. The cup's 50 N over its spread of 2
    // squeeze 25 N, below the carton's rating (120 x 0.8 = 96 N): not firm.
    let domain = WarehouseDomain::new();
    let trace = domain.simulate(
        settings(Gripper::Suction, MapSource::Live, 1.0, 50.0),
        &mut Constant(0),
    );
    assert!(close(trace.planned_s, 27.0));
    let stops = &trace.safety_stops;
    assert_eq!(stops.len(), 2);
    assert!(close(stops[0], 6.4) && close(stops[1], 29.15));
    let grasp = trace.grasp.unwrap();
    assert!(close(grasp.t, 22.75));
    assert_eq!((grasp.squeeze_n, grasp.rated_n), (25.0, 96.0));
    // Up to the first stop, up to the plan, and past it (delivered at 43.5 s).
    assert_eq!(perceive(&trace, 6.0), Observations::NONE);
    assert_eq!(
        perceive(&trace, 6.4),
        Observations::named(&OBSERVATIONS, [SAFETY_STOP])
    );
    assert_eq!(
        perceive(&trace, 27.0),
        Observations::named(&OBSERVATIONS, [SAFETY_STOP])
    );
    assert_eq!(
        perceive(&trace, 43.5),
        Observations::named(&OBSERVATIONS, [SAFETY_STOP, BEHIND_PLAN])
    );
    // Judged: the balanced operator stops the robot at the first collision (draw 0), and
    // the judgement carries what the robot perceived until then; left to finish (draws
    // near 1), the pick is delivered late against the plan.
    let behavior = domain
        .space()
        .parse("gripper=suction,map=live,speed=1,grip_force=50")
        .unwrap();
    let stopped = domain.run(&behavior, &operator("balanced"), &mut Constant(0));
    assert_eq!(stopped.truth, Some(WarehouseCause::Collision.to_trust()));
    assert_eq!(
        stopped.outcome.observed,
        Observations::named(&OBSERVATIONS, [SAFETY_STOP])
    );
    // Jaws at 100 N squeeze the carton over its rating: a firm grip, and it is crushed.
    let jaws = domain.simulate(
        settings(Gripper::ParallelJaw, MapSource::Live, 1.0, 100.0),
        &mut Constant(0),
    );
    let end = jaws.events.last().unwrap();
    assert_eq!(end.1, Event::Delivered { crushed: true });
    assert_eq!(
        perceive(&jaws, end.0),
        Observations::named(&OBSERVATIONS, [SAFETY_STOP, FIRM_GRIP, BEHIND_PLAN])
    );
}

#[test]
fn a_pick_without_a_stop_ends_on_its_plan_and_perceives_its_endings() {
    // Nobody crosses (draws near 1): the oily part is dropped as the robot pulls away at
    // 28 s (`a_pick_with_every_draw_at_its_largest`), long before its plan's end.
    let domain = WarehouseDomain::new();
    let dropped = domain.simulate(
        settings(Gripper::ParallelJaw, MapSource::AsBuilt, 2.0, 100.0),
        &mut Constant(!0),
    );
    assert!(dropped.safety_stops.is_empty());
    assert_eq!(
        perceive(&dropped, 28.0),
        Observations::named(&OBSERVATIONS, [WarehouseCause::DroppedItem.to_trust()])
    );
    // A cup's seal on oily metal holds 0.9 x 100 x 1.3 = 117 N against 6 x (9.81 + 3 x
    // 0.5) = 67.9 N: delivered after 24 + 1 + 1.5 + 24 + 0.5 = 51 s, exactly its plan; the
    // part stands any squeeze, so no grip on it is firm.
    let delivered = domain.simulate(
        settings(Gripper::Suction, MapSource::AsBuilt, 2.0, 100.0),
        &mut Constant(!0),
    );
    let &(end, event) = delivered.events.last().unwrap();
    assert_eq!(event, Event::Delivered { crushed: false });
    assert_eq!(end, delivered.planned_s);
    assert!(close(end, 51.0));
    assert_eq!(perceive(&delivered, end), Observations::NONE);
    // A slot not found is perceived as what it is.
    let missing = trace(&[(21.25, Event::ItemNotFound)]);
    assert_eq!(
        perceive(
            &Trace {
                planned_s: 40.0,
                ..missing
            },
            21.25
        ),
        Observations::named(&OBSERVATIONS, [WarehouseCause::ItemNotFound.to_trust()])
    );
}

#[test]
fn behaviors_read_as_settings() {
    let domain = WarehouseDomain::new();
    assert_eq!(domain.space().size(), 1_800);
    let behavior = domain
        .space()
        .parse("gripper=soft-fingers,map=live,speed=1.5,grip_force=40")
        .unwrap();
    assert_eq!(
        domain.settings(&behavior),
        settings(Gripper::SoftFingers, MapSource::Live, 1.5, 40.0)
    );
}

fn trace(events: &[(f64, Event)]) -> Trace {
    let mut trace = Trace::default();
    for &(t, e) in events {
        trace.push(t, e);
    }
    trace
}

fn operator(name: &str) -> WarehouseOperator {
    builtin_operators()
        .into_iter()
        .find(|o| o.name == name)
        .unwrap()
}

#[test]
fn operators_judge_what_they_watch() {
    let mut never = Constant(!0); // every reaction draw is ~1: no probabilistic reaction
    let mut always = Constant(0); // every reaction draw is 0: every reaction
    let care = operator("care-focused");
    let delivered = trace(&[
        (20.0, Event::Collision),
        (50.0, Event::Delivered { crushed: true }),
    ]);
    // Care-focused: stops at the collision (weight 0.5), when it reacts.
    assert_eq!(
        care.judge(&delivered, &mut always),
        Judgement::interrupted(0.5, WarehouseCause::Collision.to_trust(), 20.0)
    );
    // Not reacting to the collision, it still sees nothing crushed unless it looks.
    assert_eq!(
        care.judge(&delivered, &mut never),
        Judgement::completed(0.5, 50.0)
    );
    let crushed = trace(&[(50.0, Event::Delivered { crushed: true })]);
    assert_eq!(
        care.judge(&crushed, &mut always),
        Judgement::failed(1.0, WarehouseCause::CrushedItem.to_trust(), 50.0)
    );
    // Throughput-focused: 45 s deadline; interrupts at it, or gives up at 90 s.
    let throughput = operator("throughput-focused");
    let late = trace(&[(70.0, Event::Delivered { crushed: false })]);
    assert_eq!(
        throughput.judge(&late, &mut always),
        Judgement::interrupted(1.0, WarehouseCause::TooSlow.to_trust(), 45.0)
    );
    assert_eq!(
        throughput.judge(&late, &mut never),
        Judgement::completed(1.0, 70.0)
    );
    let very_late = trace(&[(95.0, Event::Delivered { crushed: false })]);
    assert_eq!(
        throughput.judge(&very_late, &mut never),
        Judgement::failed(1.0, WarehouseCause::TooSlow.to_trust(), 90.0)
    );
    // A drop and a missing slot fail the pick whatever the draws.
    for (event, cause) in [
        (Event::DroppedItem, WarehouseCause::DroppedItem),
        (Event::ItemNotFound, WarehouseCause::ItemNotFound),
    ] {
        let ended = trace(&[(30.0, event)]);
        assert_eq!(
            throughput.judge(&ended, &mut never),
            Judgement::failed(1.0, cause.to_trust(), 30.0)
        );
    }
    // A trace without an ending is a pick that never ends.
    assert_eq!(
        throughput.judge(&Trace::default(), &mut never),
        Judgement::failed(1.0, WarehouseCause::TooSlow.to_trust(), 90.0)
    );
}

#[test]
fn an_inattentive_operator_overlooks_what_it_minds_and_the_pick_goes_on() {
    let half = || Constant(1 << 63); // every reaction draw is 0.5
    let care = operator("care-focused"); // p_collision 0.95, p_crushed 0.95
    let delivered = trace(&[
        (20.0, Event::Collision),
        (50.0, Event::Delivered { crushed: true }),
    ]);
    // Attention 0.5: 0.5 is not below 0.95 x 0.5 = 0.475, but is below 0.95: both the
    // collision and the crushed item are overlooked, the first is named.
    let judged = care.judge_attending(&delivered, 0.5, &mut half());
    assert_eq!(
        judged,
        Judgement::completed(0.5, 50.0).overlooking(Some(WarehouseCause::Collision.to_trust()))
    );
    // Attention 0.6: 0.5 is below 0.95 x 0.6 = 0.57, so it stops at the collision.
    assert_eq!(
        care.judge_attending(&delivered, 0.6, &mut half()),
        Judgement::interrupted(0.5, WarehouseCause::Collision.to_trust(), 20.0)
    );
    // Noticing nothing, the throughput-focused operator lets a late pick finish, and the
    // deadline it would have enforced is what it overlooked.
    let throughput = operator("throughput-focused");
    let late = trace(&[(70.0, Event::Delivered { crushed: false })]);
    assert_eq!(
        throughput.judge_attending(&late, 0.0, &mut Constant(0)),
        Judgement::completed(1.0, 70.0).overlooking(Some(WarehouseCause::TooSlow.to_trust()))
    );
    // A drop ends the pick whatever the attention.
    let dropped = trace(&[(30.0, Event::DroppedItem)]);
    assert_eq!(
        throughput.judge_attending(&dropped, 0.0, &mut Constant(0)),
        Judgement::failed(1.0, WarehouseCause::DroppedItem.to_trust(), 30.0)
    );
}

#[test]
fn operator_files_are_checked_where_they_are_wrong() {
    let origin = Path::new("ops/x.ron");
    let err = WarehouseOperator::from_ron(
        "(name: \"x\",\n t_complete: 45.0,\n p_deadlin: 1.0)",
        origin,
    )
    .unwrap_err()
    .to_string();
    assert!(err.starts_with("ops/x.ron:3:"), "{err}");
    let text = "(name: \"x\", t_complete: 45.0, p_deadline: 1.0, p_collision: 1.5, p_crushed: 0.1)";
    let err = WarehouseOperator::from_ron(text, origin)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("`p_collision` must be a probability in [0, 1], got 1.5"),
        "{err}"
    );
    let text = "(name: \"x\", t_complete: 45.0, p_deadline: 1.0, p_collision: 0.5, p_crushed: 0.1,
                 weights: (by_cause: {\"squashed\": 1.0}))";
    let err = WarehouseOperator::from_ron(text, origin)
        .unwrap_err()
        .to_string();
    assert!(
        err.starts_with("ops/x.ron: operator `x`: `weights.by_cause`: ")
            && err.contains("`squashed` is not declared (declared: too-slow, collision,"),
        "{err}"
    );
    let text = "(name: \"x\", t_complete: 45.0, p_deadline: 1.0, p_collision: 0.5, p_crushed: 0.1,
                 weights: (by_cause: {\"dropped-item\": -1.0}))";
    let err = WarehouseOperator::from_ron(text, origin)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("`weights.by_cause.dropped-item` must be a finite number >= 0"),
        "{err}"
    );
}

proptest! {
    #[test]
    fn picks_are_ordered_end_once_and_repeat_with_their_seed(
        seed: u64, gripper in 0usize..3, map in 0usize..3, speed in 1u32..=10, force in 1u32..=20,
    ) {
        let domain = WarehouseDomain::new();
        let s = settings(
            Gripper::ALL[gripper], MapSource::ALL[map], f64::from(speed) * 0.25, f64::from(force) * 5.0,
        );
        let run = |seed| domain.simulate(s, &mut trustcbr::rand::rngs::StdRng::seed_from_u64(seed));
        let trace = run(seed);
        prop_assert_eq!(&trace, &run(seed));
        let (last, before) = trace.events.split_last().unwrap();
        prop_assert!(before.iter().all(|(_, e)| *e == Event::Collision));
        prop_assert!(trace.events.windows(2).all(|w| w[0].0 <= w[1].0));
        if s.map == MapSource::Live {
            prop_assert_ne!(last.1, Event::ItemNotFound);
        }
    }
}

/// The conformance kits reach a plug-in through the tool's `testing` feature alone (this
/// crate depends on `trustcbr` and nothing else of the workspace).
#[test]
fn the_kits_reach_a_plug_in_through_the_tool() {
    trustcbr::trust::testing::check_searcher(|| {
        Box::new(trustcbr::trust::search::CauseAware::new())
    });
}

/// The warehouse keeps the simulation contract (the lab's domain kit) with every shipped
/// operator.
#[test]
fn the_warehouse_keeps_the_simulation_contract() {
    let operators =
        trustcbr::lab::contract::operator_file::named(warehouse::operator::builtin_operators());
    trustcbr::lab::testing::check_domain(&WarehouseDomain::new(), &operators);
}
