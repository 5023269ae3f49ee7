//! The robot's own competence: how well it expects a behavior to do the task, judged
//! from its own models and its own record, and the operator's trust beside it.
//!
//! Trust-guided adaptation optimises what the operator accepts. An operator may accept a
//! behavior that does the task badly in ways it does not see (an explosive left behind
//! looks like a clean patrol), so the robot keeps its own view of each behavior:
//!
//! - **Parts.** A domain declares the ways a command can fall short that its robot can
//!   judge ([`CompetencePart`]): each is either *seen* (an observation the robot perceives
//!   when it happens, such as a collision on its bumper) or *unseen* (the robot cannot
//!   perceive it, such as a wrong label it believes, and judges it by its model alone).
//! - **Prediction.** For a behavior the domain may predict each part's chance per command
//!   from what its designer gave the robot (a detector's accuracy table at the scan the
//!   behavior makes, a camera's spotting model), never from the operator.
//! - **Record.** [`CompetenceRecord`] counts, per behavior, the commands run and the seen
//!   parts perceived. A seen part's rate is the behavior's own count shrunk towards a prior
//!   with the weight of [`PRIOR_COMMANDS`] commands: the prediction when the domain gives
//!   one, else the robot's record over every behavior it ran. An unseen part's rate is the
//!   prediction.
//! - **Standard.** An experiment (or a robot's owner) sets the most each part may fall
//!   short per command ([`CompetenceStandard`]); a behavior whose every known part is within
//!   it is *competent*.
//! - **Calibration.** Beside the operator's estimate of the behavior in use
//!   ([`calibrate`]): *overtrust* is an estimate at the trustworthy threshold while the
//!   behavior is not competent (with the parts that fall short); *undertrust* is an
//!   estimate at the untrustworthy threshold while it is competent; otherwise calibrated.
//! - **Sure enough to alert.** A calibration is the robot's best guess; an alert interrupts
//!   the operator, so it waits until the robot is sure
//!   ([`CompetenceStandard::surely_short`]): a seen part falls short surely when its own
//!   record's rate is above the bound beyond chance (the Wilson score interval's lower end
//!   at [`ALERT_Z`], one-sided 95%), an unseen part when its prediction is above the bound
//!   (the robot has no record to doubt its model with).

use crate::{Cause, Observations, Outcome, Thresholds, Verdict};
use cbr_core::Behavior;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::sync::Arc;

/// How many commands' worth a seen part's prior weighs against a behavior's own record.
pub const PRIOR_COMMANDS: f64 = 4.0;

/// The standard normal quantile of the confidence a seen part needs to fall short surely:
/// one-sided 95%.
pub const ALERT_Z: f64 = 1.645;

/// The lower end of the Wilson score interval at `z` of `hits` in `trials` (0 with no
/// trials): the least rate the record makes plausible.
fn wilson_lower(hits: u32, trials: u32, z: f64) -> f64 {
    if trials == 0 {
        return 0.0;
    }
    let n = f64::from(trials);
    let p = f64::from(hits) / n;
    let z2 = z * z;
    let centre = p + z2 / (2.0 * n);
    let spread = z * (p * (1.0 - p) / n + z2 / (4.0 * n * n)).sqrt();
    ((centre - spread) / (1.0 + z2 / n)).max(0.0)
}

/// A way a command can fall short that the robot judges itself.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct CompetencePart {
    /// The part's name (same spelling rules as causes).
    pub name: Cause,
    /// The observation the robot perceives when this happens, which its record counts;
    /// `None`: it cannot perceive it and judges it by its domain's prediction alone.
    pub seen_as: Option<Cause>,
}

/// A part whose observation is not among those the robot perceives.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "competence part `{part}` is seen as `{observation}`, which is not an observation the robot perceives ({declared})"
)]
pub struct UnknownObservation {
    /// The part.
    pub part: Cause,
    /// The observation it names.
    pub observation: Cause,
    /// The observations declared, listed.
    pub declared: String,
}

/// The robot's estimate of one part for one behavior.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartEstimate {
    /// The part.
    pub name: Cause,
    /// The estimated chance a command falls short this way; `None` for an unseen part
    /// the domain predicts nothing for (unknown).
    pub rate: Option<f64>,
    /// The domain's prediction, if any.
    pub predicted: Option<f64>,
    /// For a seen part, the commands of this behavior in which the robot perceived it.
    pub perceived: Option<u32>,
}

/// The robot's own view of a behavior: each part's estimate and the commands behind it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Competence {
    /// The behavior.
    pub behavior: Behavior,
    /// Commands of it the robot's record holds.
    pub commands: u32,
    /// The parts, in the domain's order.
    pub parts: Vec<PartEstimate>,
}

impl Competence {
    /// The chance a command falls short in none of the known parts, taken as independent.
    pub fn clean(&self) -> f64 {
        self.parts
            .iter()
            .filter_map(|p| p.rate)
            .map(|r| 1.0 - r)
            .product()
    }
}

/// Commands run and seen parts perceived.
#[derive(Clone, Debug, Default, PartialEq)]
struct Counts {
    commands: u32,
    perceived: Vec<u32>,
}

impl Counts {
    fn add(&mut self, parts: usize, hits: impl Iterator<Item = usize>) {
        if self.perceived.len() < parts {
            self.perceived.resize(parts, 0);
        }
        self.commands += 1;
        for part in hits {
            self.perceived[part] += 1;
        }
    }

    fn perceived(&self, part: usize) -> u32 {
        self.perceived.get(part).copied().unwrap_or(0)
    }
}

/// What the robot perceived of each behavior it ran, for its competence estimates.
#[derive(Clone, Debug, PartialEq)]
pub struct CompetenceRecord {
    parts: Vec<CompetencePart>,
    /// Per part, the bit of its observation (`None` for an unseen part).
    bits: Vec<Option<usize>>,
    behaviors: HashMap<Behavior, Counts>,
    every: Counts,
}

impl CompetenceRecord {
    /// A record of `parts` over the robot's `observations` (in bit order); refused when a
    /// seen part's observation is not among them.
    pub fn new(
        parts: &[CompetencePart],
        observations: &[Cause],
    ) -> Result<Self, UnknownObservation> {
        let bits = parts
            .iter()
            .map(|part| {
                part.seen_as
                    .map(|seen| {
                        observations.iter().position(|&o| o == seen).ok_or_else(|| {
                            UnknownObservation {
                                part: part.name,
                                observation: seen,
                                declared: crate::cause::list_causes(observations),
                            }
                        })
                    })
                    .transpose()
            })
            .collect::<Result<_, _>>()?;
        Ok(Self {
            parts: parts.to_vec(),
            bits,
            behaviors: HashMap::new(),
            every: Counts::default(),
        })
    }

    /// The parts, in the domain's order.
    pub fn parts(&self) -> &[CompetencePart] {
        &self.parts
    }

    /// Which seen parts `observed` shows, by part number.
    fn hits(&self, observed: Observations) -> impl Iterator<Item = usize> + '_ {
        self.bits
            .iter()
            .enumerate()
            .filter_map(move |(part, bit)| bit.filter(|&b| observed.contains(b)).map(|_| part))
    }

    /// Records one command of `behavior`: what the robot perceived of it.
    pub fn record(&mut self, behavior: Behavior, outcome: &Outcome) {
        let parts = self.parts.len();
        let hits: Vec<usize> = self.hits(outcome.observed).collect();
        self.behaviors
            .entry(behavior)
            .or_default()
            .add(parts, hits.iter().copied());
        self.every.add(parts, hits.into_iter());
    }

    /// The robot's estimate of `behavior`, given its domain's `predicted` chance of each
    /// part (in the parts' order; `None` where it predicts nothing).
    pub fn estimate(&self, behavior: Behavior, predicted: &[Option<f64>]) -> Competence {
        let own = self.behaviors.get(&behavior);
        let commands = own.map_or(0, |c| c.commands);
        let parts = self
            .parts
            .iter()
            .enumerate()
            .map(|(i, part)| {
                let prediction = predicted.get(i).copied().flatten();
                if self.bits[i].is_none() {
                    return PartEstimate {
                        name: part.name,
                        rate: prediction,
                        predicted: prediction,
                        perceived: None,
                    };
                }
                // Over every behavior: Jeffreys' estimate, 1/2 with nothing recorded.
                let every = (f64::from(self.every.perceived(i)) + 0.5)
                    / (f64::from(self.every.commands) + 1.0);
                let prior = prediction.unwrap_or(every);
                let perceived = own.map_or(0, |c| c.perceived(i));
                PartEstimate {
                    name: part.name,
                    rate: Some(
                        (f64::from(perceived) + PRIOR_COMMANDS * prior)
                            / (f64::from(commands) + PRIOR_COMMANDS),
                    ),
                    predicted: prediction,
                    perceived: Some(perceived),
                }
            })
            .collect();
        Competence {
            behavior,
            commands,
            parts,
        }
    }
}

/// The most each part may fall short per command for a behavior to be competent.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CompetenceStandard {
    /// The most any part may fall short per command, in `[0, 1]`.
    pub at_most: f64,
    /// Parts held to another bound than `at_most`, by name.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub parts: Vec<(Cause, f64)>,
}

/// A standard's bound outside `[0, 1]`.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "the competence standard of `{part}` is {}; it must be a chance in [0, 1]",
    cbr_core::Shown(*.value)
)]
pub struct StandardError {
    /// The part (`at_most` for the bound of every part).
    pub part: String,
    /// The value given.
    pub value: f64,
}

impl CompetenceStandard {
    /// Every part held to `at_most`.
    pub fn uniform(at_most: f64) -> Result<Self, StandardError> {
        let standard = Self {
            at_most,
            parts: Vec::new(),
        };
        standard.validate()?;
        Ok(standard)
    }

    /// Checks that every bound is a chance.
    pub fn validate(&self) -> Result<(), StandardError> {
        let bad = |part: String, value: f64| {
            (!(0.0..=1.0).contains(&value)).then_some(StandardError { part, value })
        };
        match bad("at_most".to_owned(), self.at_most).or_else(|| {
            self.parts
                .iter()
                .find_map(|(name, value)| bad(name.as_str().to_owned(), *value))
        }) {
            Some(error) => Err(error),
            None => Ok(()),
        }
    }

    /// The bound of `part`.
    pub fn bound(&self, part: Cause) -> f64 {
        self.parts
            .iter()
            .find(|(name, _)| *name == part)
            .map_or(self.at_most, |&(_, bound)| bound)
    }

    /// The parts of `competence` above their bound (unknown parts are not judged).
    pub fn short(&self, competence: &Competence) -> Vec<Cause> {
        competence
            .parts
            .iter()
            .filter(|p| p.rate.is_some_and(|r| r > self.bound(p.name)))
            .map(|p| p.name)
            .collect()
    }

    /// The parts of `competence` surely above their bound, enough for an alert: a seen part
    /// whose own record is above it beyond chance ([`ALERT_Z`]), an unseen part whose
    /// prediction is above it.
    pub fn surely_short(&self, competence: &Competence) -> Vec<Cause> {
        competence
            .parts
            .iter()
            .filter(|p| {
                let bound = self.bound(p.name);
                match p.perceived {
                    Some(hits) => wilson_lower(hits, competence.commands, ALERT_Z) > bound,
                    None => p.rate.is_some_and(|r| r > bound),
                }
            })
            .map(|p| p.name)
            .collect()
    }

    /// Whether every known part of `competence` is within its bound.
    pub fn met_by(&self, competence: &Competence) -> bool {
        self.short(competence).is_empty()
    }
}

/// The operator's trust beside the robot's competence, for the behavior in use.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "verdict")]
pub enum Calibration {
    /// Trust and competence agree (or trust is still undecided).
    Calibrated,
    /// The operator's estimate is at the trustworthy threshold while the behavior is not
    /// competent: these parts fall short.
    Overtrust {
        /// The parts above their bound.
        short: Vec<Cause>,
    },
    /// The operator's estimate is at the untrustworthy threshold while the behavior is
    /// competent.
    Undertrust,
}

/// The calibration of the operator's `estimate` of a behavior (its value) against the
/// robot's `competence` of it under `standard`.
pub fn calibrate(
    estimate: f64,
    thresholds: &Thresholds,
    competence: &Competence,
    standard: &CompetenceStandard,
) -> Calibration {
    let short = standard.short(competence);
    match (thresholds.verdict(estimate), short.is_empty()) {
        (Verdict::Trustworthy, false) => Calibration::Overtrust { short },
        (Verdict::Untrustworthy, true) => Calibration::Undertrust,
        _ => Calibration::Calibrated,
    }
}

/// What a robot's models predict of a behavior, per part (its domain's
/// [`CompetenceRecord::estimate`] argument), shared across threads; it may borrow its
/// models for `'p`.
pub type Predictor<'p> = Arc<dyn Fn(&Behavior) -> Vec<Option<f64>> + Send + Sync + 'p>;

/// The robot's judge of its own competence on a mission: its record of every command,
/// its models' predictions and the standard it is held to.
#[derive(Clone)]
pub struct CompetenceJudge<'p> {
    record: CompetenceRecord,
    predict: Predictor<'p>,
    standard: CompetenceStandard,
}

impl std::fmt::Debug for CompetenceJudge<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CompetenceJudge")
            .field("record", &self.record)
            .field("standard", &self.standard)
            .finish_non_exhaustive()
    }
}

impl<'p> CompetenceJudge<'p> {
    /// A judge over `record`, with the models' `predict` and `standard`.
    pub fn new(
        record: CompetenceRecord,
        predict: Predictor<'p>,
        standard: CompetenceStandard,
    ) -> Self {
        Self {
            record,
            predict,
            standard,
        }
    }

    /// Records one command of `behavior`.
    pub fn record(&mut self, behavior: Behavior, outcome: &Outcome) {
        self.record.record(behavior, outcome);
    }

    /// The robot's estimate of `behavior`.
    pub fn competence(&self, behavior: Behavior) -> Competence {
        self.record.estimate(behavior, &(self.predict)(&behavior))
    }

    /// The standard.
    pub fn standard(&self) -> &CompetenceStandard {
        &self.standard
    }

    /// The robot's estimate of `behavior` and the parts it is sure fall short of the
    /// standard ([`CompetenceStandard::surely_short`]).
    pub fn surely_short(&self, behavior: Behavior) -> (Competence, Vec<Cause>) {
        let competence = self.competence(behavior);
        let short = self.standard.surely_short(&competence);
        (competence, short)
    }

    /// Among `candidates` (behaviors an operator trusted before), other than `behavior`,
    /// the one the robot judges competent (every known part within the standard,
    /// [`CompetenceStandard::met_by`]) with the highest chance of a clean command
    /// ([`Competence::clean`]; the first in order on a tie); `None` when none is.
    pub fn safer_than(
        &self,
        behavior: Behavior,
        candidates: impl IntoIterator<Item = Behavior>,
    ) -> Option<Behavior> {
        let mut best: Option<(Behavior, f64)> = None;
        for candidate in candidates {
            if candidate == behavior || best.is_some_and(|(b, _)| b == candidate) {
                continue;
            }
            let competence = self.competence(candidate);
            if !self.standard.met_by(&competence) {
                continue;
            }
            let clean = competence.clean();
            if best.is_none_or(|(_, c)| clean > c) {
                best = Some((candidate, clean));
            }
        }
        best.map(|(b, _)| b)
    }

    /// The calibration of the operator's `estimate` of `behavior` against the robot's
    /// competence.
    pub fn calibration(
        &self,
        behavior: Behavior,
        estimate: f64,
        thresholds: &Thresholds,
    ) -> Calibration {
        calibrate(
            estimate,
            thresholds,
            &self.competence(behavior),
            &self.standard,
        )
    }
}

/// The robot asks its operator to choose (the second design of docs/missions.md): the
/// operator trusts the behavior in use while the robot judges it not competent, for the
/// parts named.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CompetenceAlert {
    /// The behavior in use.
    pub behavior: Behavior,
    /// The operator's estimate of it (at the trustworthy threshold).
    pub estimate: f64,
    /// The robot's own estimate of it.
    pub competence: Competence,
    /// The parts above the standard.
    pub short: Vec<Cause>,
    /// A safer behavior the robot offers instead: one an operator trusted before (a
    /// retained case's solution) that the robot judges competent
    /// ([`CompetenceJudge::safer_than`]); `None` when it knows none. The operator may
    /// take it ([`crate::MissionAdapter::accept_offer`]) or keep the behavior in use and
    /// watch it afresh.
    pub offer: Option<Behavior>,
}

#[cfg(test)]
mod tests {
    use super::*;

    const BUMP: Cause = Cause::from_static("bump");
    const LATE: Cause = Cause::from_static("late");
    const WRONG_LABEL: Cause = Cause::from_static("wrong-label");

    fn parts() -> [CompetencePart; 2] {
        [
            CompetencePart {
                name: BUMP,
                seen_as: Some(BUMP),
            },
            CompetencePart {
                name: WRONG_LABEL,
                seen_as: None,
            },
        ]
    }

    fn close(a: Option<f64>, b: f64) -> bool {
        a.is_some_and(|a| (a - b).abs() < 1e-12)
    }

    #[test]
    fn a_seen_part_is_its_record_shrunk_towards_the_prediction_or_every_behavior() {
        let mut record = CompetenceRecord::new(&parts(), &[LATE, BUMP]).unwrap();
        let (a, b) = (Behavior::new(&[0]), Behavior::new(&[1]));
        let bumped = Outcome::completed(1.0, 1.0).observing(Observations::NONE.with(1));
        let late = Outcome::completed(1.0, 1.0).observing(Observations::NONE.with(0));
        // Nothing recorded: a seen part without prediction is 1/2; the unseen part is the
        // prediction, or unknown.
        let nothing = record.estimate(a, &[None, None]);
        assert!(close(nothing.parts[0].rate, 0.5));
        assert_eq!(nothing.parts[1].rate, None);
        // `a`: 2 bumps in 6 commands; `b`: none in 4 (a late command is no bump).
        for k in 0..6 {
            record.record(a, if k < 2 { &bumped } else { &late });
        }
        for _ in 0..4 {
            record.record(b, &late);
        }
        // Every behavior: (2 + 1/2) / (10 + 1) = 5/22; `a`: (2 + 4 x 5/22) / 10 = 32/110.
        let estimate = record.estimate(a, &[None, Some(0.3)]);
        assert_eq!(estimate.commands, 6);
        assert!(close(estimate.parts[0].rate, 32.0 / 110.0));
        assert_eq!(estimate.parts[0].perceived, Some(2));
        assert!(close(estimate.parts[1].rate, 0.3));
        // A prediction replaces every behavior's rate as the prior: (0 + 4 x 0.1) / 8.
        let estimate = record.estimate(b, &[Some(0.1), Some(0.3)]);
        assert!(close(estimate.parts[0].rate, 0.05));
        // Clean: (1 - 0.05)(1 - 0.3).
        assert!((estimate.clean() - 0.95 * 0.7).abs() < 1e-12);
    }

    #[test]
    fn the_wilson_lower_end_by_hand() {
        // 5 in 20 at z = 1.645: (0.25 + z²/40 - z sqrt(0.25 x 0.75 / 20 + z²/1600)) / (1 + z²/20).
        assert!((wilson_lower(5, 20, ALERT_Z) - 0.127_369_435_655_260_4).abs() < 1e-12);
        // None seen: nothing is plausibly above 0; no trials: 0.
        assert!(wilson_lower(0, 20, ALERT_Z).abs() < 1e-15);
        assert_eq!(wilson_lower(0, 0, ALERT_Z), 0.0);
    }

    #[test]
    fn a_seen_part_falls_short_surely_only_beyond_chance_an_unseen_one_by_its_prediction() {
        let standard = CompetenceStandard::uniform(0.1).unwrap();
        let competence = |commands: u32, bumps: u32, label: f64| Competence {
            behavior: Behavior::new(&[0]),
            commands,
            parts: vec![
                PartEstimate {
                    name: BUMP,
                    rate: Some(f64::from(bumps) / f64::from(commands)),
                    predicted: None,
                    perceived: Some(bumps),
                },
                PartEstimate {
                    name: WRONG_LABEL,
                    rate: Some(label),
                    predicted: Some(label),
                    perceived: None,
                },
            ],
        };
        // 3 bumps in 10: 0.3 is above 0.1, but the lower end is 0.127, above it too.
        assert_eq!(standard.surely_short(&competence(10, 3, 0.05)), vec![BUMP]);
        // 2 bumps in 10: the estimate falls short, surely not (lower end 0.069).
        let unsure = competence(10, 2, 0.05);
        assert_eq!(standard.short(&unsure), vec![BUMP]);
        assert!(standard.surely_short(&unsure).is_empty());
        // An unseen part's prediction above the bound is short surely.
        assert_eq!(
            standard.surely_short(&competence(10, 0, 0.11)),
            vec![WRONG_LABEL]
        );
    }

    #[test]
    fn a_part_seen_as_an_unknown_observation_is_refused() {
        let error = CompetenceRecord::new(&parts(), &[LATE]).unwrap_err();
        assert_eq!((error.part, error.observation), (BUMP, BUMP));
        assert!(error.to_string().contains("(late)"), "{error}");
    }

    #[test]
    fn calibration_sets_trust_beside_the_parts_that_fall_short() {
        let thresholds = Thresholds::default();
        let standard = CompetenceStandard {
            at_most: 0.1,
            parts: vec![(WRONG_LABEL, 0.02)],
        };
        let competence = |bump: f64, label: Option<f64>| Competence {
            behavior: Behavior::new(&[0]),
            commands: 10,
            parts: vec![
                PartEstimate {
                    name: BUMP,
                    rate: Some(bump),
                    predicted: None,
                    perceived: Some(1),
                },
                PartEstimate {
                    name: WRONG_LABEL,
                    rate: label,
                    predicted: label,
                    perceived: None,
                },
            ],
        };
        let (trusted, rejected, deciding) = (5.0, -5.0, 1.0);
        assert_eq!(
            calibrate(
                trusted,
                &thresholds,
                &competence(0.05, Some(0.05)),
                &standard
            ),
            Calibration::Overtrust {
                short: vec![WRONG_LABEL]
            }
        );
        assert_eq!(
            calibrate(
                trusted,
                &thresholds,
                &competence(0.2, Some(0.01)),
                &standard
            ),
            Calibration::Overtrust { short: vec![BUMP] }
        );
        // An unknown part is not judged.
        let unknown = competence(0.05, None);
        assert!(standard.met_by(&unknown));
        assert_eq!(
            calibrate(trusted, &thresholds, &unknown, &standard),
            Calibration::Calibrated
        );
        assert_eq!(
            calibrate(rejected, &thresholds, &unknown, &standard),
            Calibration::Undertrust
        );
        assert_eq!(
            calibrate(
                deciding,
                &thresholds,
                &competence(0.9, Some(0.9)),
                &standard
            ),
            Calibration::Calibrated
        );
    }

    #[test]
    fn a_standard_s_bounds_are_chances() {
        assert!(CompetenceStandard::uniform(0.1).is_ok());
        assert_eq!(
            CompetenceStandard::uniform(1.5).unwrap_err().part,
            "at_most"
        );
        let standard = CompetenceStandard {
            at_most: 0.1,
            parts: vec![(BUMP, -0.1)],
        };
        assert_eq!(standard.validate().unwrap_err().part, "bump");
    }
}
