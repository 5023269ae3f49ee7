//! The UGV robot's judgement of its own competence ([`trust::competence`]): the ways a
//! command can fall short that it judges, what its models predict of a behavior, and, for
//! evaluation, the truth of a whole command (docs/simulation.md, "The robot's own
//! competence").
//!
//! **Seen parts**, counted by its record: each of its observations that is a shortfall
//! of the task, `collision`, `stuck`, `behind-plan` (late against its own plan),
//! `near-person-fast` and `close-pass`. `raised-alarm` and `detonation` are not parts:
//! an alarm is what a patrol is for (whether it was false the robot cannot see), and a
//! detonation is the consequence of a missed explosive, the unseen part below.
//!
//! **Unseen parts** (patrol), predicted from what the robot's designer gave it:
//! - `explosive-missed`: an explosive left behind, not spotted or labelled harmless. Per
//!   explosive, the chance is `1 - p_spot(d, v) a_e(T, g)`, with the camera's spotting
//!   model `p_spot` at the behavior's speed `v`, the detector's accuracy on explosives
//!   `a_e` at its scan time `T` and gap `g` (its scan distance, or its padding when that is
//!   larger), and the object's lateral distance `d` from the path, which the robot does
//!   not know in advance: it takes `d` uniform over the briefing's lateral band (objects
//!   lie in the band either side of the patrol line, which its path follows). Over the
//!   briefing's count of explosives (uniform from 0 to its most), a command misses at
//!   least one with chance `1 - E[(1 - m)^X]`, `m` the chance averaged over the band.
//! - `false-alarm`: a harmless object labelled explosive; likewise with `1 - a_h(T, g)`
//!   per harmless object spotted, over the `N - X` harmless objects.
//!
//! **The truth** of a command, for evaluation only: a whole run with nobody to stop it,
//! its seen parts as the robot perceives them over the whole run, and its unseen parts
//! from the fate of every object, for a run that set out (a stuck robot's objects are the
//! `stuck` part's, so the parts stay distinct and the prediction is of a run that goes).

use crate::causes::{COLLISION, FALSE_ALARM, STUCK};
use crate::detector::Detector;
use crate::patrol::PatrolSetup;
use crate::perception::{BEHIND_PLAN, CLOSE_PASS, NEAR_PERSON_FAST};
use crate::ugv::{Run, Settings};
use crate::{Scenario, perceive};
use trust::{Cause, CompetencePart};

/// An explosive left behind: not spotted, or labelled harmless.
pub const EXPLOSIVE_MISSED: Cause = Cause::from_static("explosive-missed");

/// A part the robot perceives as the observation of the same name.
const fn seen(name: Cause) -> CompetencePart {
    CompetencePart {
        name,
        seen_as: Some(name),
    }
}

/// The movement robot's parts, all seen.
pub const MOVEMENT: [CompetencePart; 5] = [
    seen(COLLISION),
    seen(STUCK),
    seen(BEHIND_PLAN),
    seen(NEAR_PERSON_FAST),
    seen(CLOSE_PASS),
];

/// The patrol robot's parts: the movement robot's, and the two it cannot perceive.
pub const PATROL: [CompetencePart; 7] = [
    MOVEMENT[0],
    MOVEMENT[1],
    MOVEMENT[2],
    MOVEMENT[3],
    MOVEMENT[4],
    CompetencePart {
        name: EXPLOSIVE_MISSED,
        seen_as: None,
    },
    CompetencePart {
        name: FALSE_ALARM,
        seen_as: None,
    },
];

/// The parts of `scenario`.
pub fn parts(scenario: Scenario) -> &'static [CompetencePart] {
    match scenario {
        Scenario::Movement => &MOVEMENT,
        Scenario::Patrol => &PATROL,
    }
}

/// Points of the midpoint rule over the lateral band.
const BAND_POINTS: u32 = 64;

/// What the robot's models predict of a behavior with `settings`, per part of
/// `scenario`: nothing for a seen part, the two unseen parts of a patrol from its camera,
/// its detector and its briefing (`setup`).
pub fn predict(
    scenario: Scenario,
    settings: &Settings,
    setup: &PatrolSetup,
    detector: &Detector,
) -> Vec<Option<f64>> {
    let mut predicted = vec![None; parts(scenario).len()];
    if scenario == Scenario::Patrol {
        let gap = settings.scan_distance.max(settings.padding);
        let (low, high) = setup.lateral_band;
        // Per object kind, the chance of a shortfall averaged over the band.
        let (mut missed, mut false_alarm) = (0.0, 0.0);
        for k in 0..BAND_POINTS {
            let d = low + (high - low) * (f64::from(k) + 0.5) / f64::from(BAND_POINTS);
            let spotted = setup.p_spot(d, settings.speed);
            missed += 1.0 - spotted * detector.accuracy(true, settings.scan_time, gap);
            false_alarm += spotted * (1.0 - detector.accuracy(false, settings.scan_time, gap));
        }
        missed /= f64::from(BAND_POINTS);
        false_alarm /= f64::from(BAND_POINTS);
        let most = setup.max_explosive.min(setup.objects);
        let counts = (0..=most).map(|x| (x as i32, (setup.objects - x) as i32));
        let none_missed = counts
            .clone()
            .map(|(x, _)| (1.0 - missed).powi(x))
            .sum::<f64>()
            / (most + 1) as f64;
        let none_false = counts
            .map(|(_, harmless)| (1.0 - false_alarm).powi(harmless))
            .sum::<f64>()
            / (most + 1) as f64;
        predicted[5] = Some(1.0 - none_missed);
        predicted[6] = Some(1.0 - none_false);
    }
    predicted
}

/// The truth of the whole run `run` of `scenario`: which parts it fell short in. The
/// unseen parts apply only to a run that set out (a stuck robot passed no object: what it
/// left behind is the `stuck` part's).
pub fn truth(scenario: Scenario, run: &Run) -> Vec<Option<bool>> {
    let observations = crate::perception::observations(scenario);
    let perceived = perceive(&run.trace, f64::INFINITY, observations);
    let set_out = run.plan.is_some();
    parts(scenario)
        .iter()
        .map(|part| match part.seen_as {
            Some(observation) => Some(perceived.contains_named(observations, observation)),
            None if !set_out => None,
            None if part.name == EXPLOSIVE_MISSED => Some(
                run.objects
                    .iter()
                    .any(|o| o.object.explosive && o.labelled_explosive != Some(true)),
            ),
            None => Some(
                run.objects
                    .iter()
                    .any(|o| !o.object.explosive && o.labelled_explosive == Some(true)),
            ),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::detector::normal_cdf;

    #[test]
    fn every_seen_part_is_an_observation_of_its_scenario() {
        for scenario in [Scenario::Movement, Scenario::Patrol] {
            let observations = crate::perception::observations(scenario);
            assert!(trust::CompetenceRecord::new(parts(scenario), observations).is_ok());
        }
    }

    #[test]
    fn a_perfect_camera_and_detector_leave_only_the_chances_of_labels_by_hand() {
        // A camera that always spots, one object, at most one explosive: the command
        // misses an explosive with chance 1/2 x (1 - a_e), and false-alarms with
        // 1/2 x (1 - a_h) (the object harmless when there is no explosive) + 0.
        let setup = PatrolSetup {
            objects: 1,
            max_explosive: 1,
            p_frame: 1.0,
            exposure: 0.0,
            ..PatrolSetup::default()
        };
        let detector = Detector::default();
        let settings = Settings {
            speed: 1.0,
            padding: 0.1,
            scan_time: 1.0,
            scan_distance: 0.5,
        };
        let predicted = predict(Scenario::Patrol, &settings, &setup, &detector);
        // At 0.5 m the signal is 20 counts/s: a_e = Phi(10 / sqrt 40), a_h = Phi(10 / sqrt 20).
        let a_e = normal_cdf(10.0 / 40f64.sqrt());
        let a_h = normal_cdf(10.0 / 20f64.sqrt());
        assert!((predicted[5].unwrap() - 0.5 * (1.0 - a_e)).abs() < 1e-12);
        assert!((predicted[6].unwrap() - 0.5 * (1.0 - a_h)).abs() < 1e-12);
        assert!(predicted[..5].iter().all(Option::is_none));
        assert_eq!(
            predict(Scenario::Movement, &settings, &setup, &detector),
            vec![None; 5]
        );
    }
}
