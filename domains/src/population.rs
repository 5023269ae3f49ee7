//! A parametric family of operators whose single parameter, `conflict` in `[0, 1]`, sets
//! how much its members disagree (`docs/simulation.md`, "Operators who disagree").
//!
//! Members start from a shared **base**, one of the paper's operators that holds neither
//! side's distinctive demand (movement: safety-focused; patrol: detection-focused), and
//! move towards one of two poles, each argued from physics rather than tuned:
//! - the **hurried dispatcher** is the paper's speed-focused operator: the task on time
//!   (movement 15 s, patrol 120 s, interrupted at the deadline with probability 0.95),
//!   bumps tolerated (0.05);
//! - the **pedestrian-zone supervisor** watches a street with people in it: it
//!   interrupts (0.95) a robot that passes a crossing or a stop where people stand, or a
//!   person, within 3.6 m (the outer edge of social distance) faster than 1.4 m/s
//!   (walking pace), or whose body comes within 0.25 m of anything (three standard
//!   deviations of the robot's own path following at walking pace: the next pass could
//!   touch); it stops it on a collision (0.95) and gives it time: about twice the time the
//!   route takes at walking pace (movement 60 s, patrol 240 s), rarely interrupted then
//!   (0.05). On patrol it also wants scans it can believe: from at most 0.5 m for at
//!   least 2.5 s (where the detector errs less than 1 % either way).
//!
//! A member at position `x` in `[-1, 1]` is the base moved `|x|` of the way to the
//! dispatcher (`x < 0`) or the supervisor (`x > 0`): the deadline geometrically, the
//! reaction probabilities linearly ([`lab::population::family::geometric`] and
//! [`lab::population::family::linear`]), each supervisor preference on with probability `0.95 x`.
//! The weights are the paper's for the scenario.
//!
//! [`family`] draws `size` members through [`lab::population::family::two_pole_family`], the
//! supervisor on the positive side: each draws a side and a spread `u` in `[0, 1)`, and
//! sits at `x = -+lambda` with `lambda = conflict (1 - (1 - conflict) u)`. At conflict 0
//! every member is the base (one preference set); at conflict 1 every member is one of
//! the two poles; in between, members spread over `[conflict^2, conflict]` of the way to
//! their pole.

use crate::Scenario;
use crate::operator::{Clearance, Comfort, OperatorModel, ScanStandard};
use lab::population::family::{geometric, linear, toward, two_pole_family};
use trust::OutcomeWeights;

/// An operator's deadline and reaction probabilities.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Pole {
    t_complete: f64,
    p_deadline: f64,
    p_collision: f64,
}

/// Probability with which the supervisor reacts to what it minds.
const P_MIND: f64 = 0.95;
/// Walking pace (m/s), the supervisor's comfort speed near people.
pub const WALKING_PACE: f64 = crate::perception::WALKING_PACE;
/// Social distance's outer edge (m): strangers inside it share a space.
pub const SOCIAL_DISTANCE: f64 = 3.6;
/// The least body gap the supervisor accepts (m).
pub const NEAR_MISS_GAP: f64 = 0.25;
/// The supervisor's scan protocol: at most this far (m)...
pub const SCAN_MAX_DISTANCE: f64 = 0.5;
/// ...for at least this long (s).
pub const SCAN_MIN_TIME: f64 = 2.5;

/// The base, the dispatcher and the supervisor.
fn poles(scenario: Scenario) -> (Pole, Pole, Pole) {
    let pole = |t_complete, p_deadline, p_collision| Pole {
        t_complete,
        p_deadline,
        p_collision,
    };
    match scenario {
        Scenario::Movement => (
            pole(15.0, 0.05, 0.95),
            pole(15.0, 0.95, 0.05),
            pole(60.0, 0.05, 0.95),
        ),
        Scenario::Patrol => (
            pole(120.0, 0.05, 0.05),
            pole(120.0, 0.95, 0.05),
            pole(240.0, 0.05, 0.95),
        ),
    }
}

/// The paper's weights for the scenario: all 1 in movement; in patrol 1/3 for every
/// outcome and 1 for a detonation.
pub(crate) fn paper_weights(scenario: Scenario) -> OutcomeWeights {
    match scenario {
        Scenario::Movement => OutcomeWeights::default(),
        Scenario::Patrol => {
            let third = 1.0 / 3.0;
            OutcomeWeights {
                completed: third,
                default: third,
                by_cause: [(crate::causes::DETONATION, 1.0)].into_iter().collect(),
            }
        }
    }
}

/// The member of the family at position `x` in `[-1, 1]` (-1: the hurried dispatcher,
/// 0: the base, 1: the pedestrian-zone supervisor), named `name`.
pub fn member(scenario: Scenario, x: f64, name: &str) -> OperatorModel {
    let x = x.clamp(-1.0, 1.0);
    let (base, dispatcher, supervisor) = poles(scenario);
    let (to, f) = toward(x, dispatcher, supervisor);
    let p = P_MIND * x.max(0.0);
    let on = p > 0.0;
    // Exact at the ends: the base and the poles are the operators they are argued as.
    OperatorModel {
        name: name.to_owned(),
        t_complete: geometric(base.t_complete, to.t_complete, f),
        p_deadline: linear(base.p_deadline, to.p_deadline, f),
        p_collision: linear(base.p_collision, to.p_collision, f),
        p_missed_object: 1.0,
        p_false_alarm: 1.0,
        give_up_factor: 2.0,
        weights: paper_weights(scenario),
        comfort: on.then_some(Comfort {
            distance: SOCIAL_DISTANCE,
            speed: WALKING_PACE,
            p,
            expected_too: true,
        }),
        clearance: on.then_some(Clearance {
            gap: NEAR_MISS_GAP,
            p,
        }),
        scan_standard: (on && scenario == Scenario::Patrol).then_some(ScanStandard {
            max_distance: SCAN_MAX_DISTANCE,
            min_time: SCAN_MIN_TIME,
            p,
        }),
        // How an operator explains itself is the experiment's to vary, not the family's.
        feedback: lab::FeedbackChannel::SILENT,
        contexts: Vec::new(),
    }
}

/// The conflict of each rung of the shipped ladder (`operators/ladder/<scenario>/rung-k`);
/// rung 0 is the paper's operators, not members of the family.
pub const LADDER: [f64; 5] = [0.0, 0.1, 1.0 / 3.0, 2.0 / 3.0, 1.0];

/// The positions of a rung of the conflict ladder at `conflict`: one member either side
/// of the base, `conflict` of the way to its pole (at 1, the two poles).
pub fn rung_positions(conflict: f64) -> [f64; 2] {
    let c = conflict.clamp(0.0, 1.0);
    [-c, c]
}

/// `size` operators drawn from the family at `conflict` in `[0, 1]` with a seeded,
/// portable generator ([`lab::population::family::two_pole_family`]); named
/// `family-c{conflict:.2}-{i}`.
pub fn family(scenario: Scenario, conflict: f64, size: usize, seed: u64) -> Vec<OperatorModel> {
    two_pole_family(conflict, size, seed, |x, name| member(scenario, x, name))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unnamed(mut op: OperatorModel) -> OperatorModel {
        op.name.clear();
        op
    }

    #[test]
    fn a_seed_gives_the_same_family() {
        for scenario in Scenario::ALL {
            assert_eq!(family(scenario, 0.4, 9, 7), family(scenario, 0.4, 9, 7));
            assert_ne!(family(scenario, 0.4, 9, 7), family(scenario, 0.4, 9, 8));
        }
    }

    #[test]
    fn names_are_distinct() {
        let names: Vec<String> = family(Scenario::Patrol, 2.0 / 3.0, 5, 1)
            .into_iter()
            .map(|o| o.name)
            .collect();
        assert_eq!(names[3], "family-c0.67-3");
        let mut unique = names.clone();
        unique.dedup();
        assert_eq!(unique.len(), 5);
    }

    #[test]
    fn at_conflict_zero_members_are_identical() {
        for scenario in Scenario::ALL {
            let members: Vec<OperatorModel> = family(scenario, 0.0, 8, 3)
                .into_iter()
                .map(unnamed)
                .collect();
            assert!(members.iter().all(|m| *m == members[0]));
            assert_eq!(members[0], unnamed(member(scenario, 0.0, "")));
            // The base is a paper operator.
            let mut base = crate::builtin_operators(scenario).remove(1);
            base.name.clear();
            assert_eq!(members[0], base);
        }
    }

    #[test]
    fn at_conflict_one_members_are_poles() {
        for scenario in Scenario::ALL {
            let dispatcher = unnamed(member(scenario, -1.0, ""));
            let supervisor = unnamed(member(scenario, 1.0, ""));
            let members: Vec<OperatorModel> = family(scenario, 1.0, 16, 5)
                .into_iter()
                .map(unnamed)
                .collect();
            assert!(members.iter().all(|m| *m == dispatcher || *m == supervisor));
            assert!(members.contains(&dispatcher) && members.contains(&supervisor));
        }
    }

    #[test]
    fn halfway_members_by_hand() {
        // Halfway to the supervisor: the deadline geometrically from 15 s to 60 s,
        // sqrt(15 x 60) = 30 s; both probabilities are the same at base and pole; each
        // preference on with 0.95 x 0.5.
        let m = member(Scenario::Movement, 0.5, "m");
        assert!((m.t_complete - 30.0).abs() < 1e-12);
        assert_eq!((m.p_deadline, m.p_collision), (0.05, 0.95));
        assert_eq!(m.comfort.map(|c| c.p), Some(0.475));
        // Halfway to the dispatcher: the deadline stays 15 s, p_deadline from 0.05 to
        // 0.95 and p_collision from 0.95 to 0.05 meet at 0.5; no preference.
        let m = member(Scenario::Movement, -0.5, "m");
        assert!((m.t_complete - 15.0).abs() < 1e-12);
        assert!((m.p_deadline - 0.5).abs() < 1e-15 && (m.p_collision - 0.5).abs() < 1e-15);
        assert_eq!((m.comfort, m.clearance), (None, None));
    }

    #[test]
    fn the_dispatcher_is_the_papers_speed_focused_operator() {
        for scenario in Scenario::ALL {
            let mut paper = crate::builtin_operators(scenario).remove(0);
            assert_eq!(paper.name, "speed-focused");
            paper.name.clear();
            assert_eq!(unnamed(member(scenario, -1.0, "")), paper);
        }
    }

    #[test]
    fn the_ladder_files_are_members() {
        use std::path::Path;
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("operators/ladder");
        for scenario in Scenario::ALL {
            for (k, conflict) in LADDER.into_iter().enumerate().skip(1) {
                for (x, role) in rung_positions(conflict)
                    .into_iter()
                    .zip(["dispatcher", "supervisor"])
                {
                    let path = root.join(format!("{scenario}/rung-{k}/{role}.ron"));
                    let file = OperatorModel::load(&path, scenario.causes()).unwrap();
                    let expected = member(scenario, x, &file.name);
                    // The files give four decimals.
                    let close = |a: f64, b: f64| (a - b).abs() <= 5e-5 * b.abs().max(1.0);
                    assert!(close(file.t_complete, expected.t_complete), "{path:?}");
                    assert!(close(file.p_deadline, expected.p_deadline), "{path:?}");
                    assert!(close(file.p_collision, expected.p_collision), "{path:?}");
                    let p = |o: &OperatorModel| o.comfort.map_or(0.0, |c| c.p);
                    assert!(close(p(&file), p(&expected)), "{path:?}");
                    assert_eq!(file.weights, expected.weights, "{path:?}");
                    assert_eq!(
                        file.comfort.map(|c| c.expected_too),
                        expected.comfort.map(|c| c.expected_too)
                    );
                    assert_eq!(file.clearance.is_some(), expected.clearance.is_some());
                    assert_eq!(
                        file.scan_standard.is_some(),
                        expected.scan_standard.is_some()
                    );
                }
            }
            // Rung 0 is the paper's operators.
            let dir = root.join(format!("{scenario}/rung-0"));
            for paper in crate::builtin_operators(scenario) {
                let path = dir.join(format!("{}.ron", paper.name));
                assert_eq!(
                    OperatorModel::load(&path, scenario.causes()).unwrap(),
                    paper
                );
            }
        }
    }
}
