//! How well the robot judges its own competence: its estimates of behaviors drawn from
//! the space ([`trust::competence`]), after as many commands as it has run of each,
//! against the simulator's truth ([`SelfJudging::competence_truth`]).
//!
//! For each of distinct behaviors drawn uniformly from the space, the robot runs commands in front of
//! an operator (who may interrupt them: the robot perceives only what happened until the
//! command ended, as on a real mission), and its estimate is taken after each number of
//! commands of [`CompetenceSettings::seen`]. Its record over every behavior, the prior of
//! a seen part without a prediction, holds every drawn behavior's commands up to that
//! number (a robot that has run the whole sample that often). The truth of a part is the
//! share of `truth_runs` whole commands, with nobody to stop the robot, that fell short
//! in it. Both are judged against the experiment's [`CompetenceStandard`].

use crate::contract::capability::{SelfJudgingNotModelled, check_self_judging};
use crate::seeds::{Purpose, stream};
use crate::stats::{MeanCi, mean_ci95};
use crate::{Domain, SelfJudging};
use cbr_core::Behavior;
use rand::RngCore;
use rayon::prelude::*;
use serde::Serialize;
use serde_json::json;
use trust::competence::{StandardError, UnknownObservation};
use trust::{Competence, CompetencePart, CompetenceRecord, CompetenceStandard, PartEstimate};

/// What to measure.
#[derive(Clone, Debug, PartialEq)]
pub struct CompetenceSettings {
    /// Distinct behaviors drawn from the space (at least 1; every behavior of a space
    /// that has no more).
    pub behaviors: u32,
    /// After how many commands of a behavior its estimate is taken, increasing (0: the
    /// prediction and the record over every behavior alone).
    pub seen: Vec<u32>,
    /// Whole commands per behavior behind its truth (at least 1).
    pub truth_runs: u32,
    /// The master seed.
    pub seed: u64,
    /// The standard both the estimates and the truth are judged against.
    pub standard: CompetenceStandard,
}

/// Why a measure cannot run.
#[derive(Debug, thiserror::Error)]
pub enum CompetenceError {
    /// The domain declares no competence part.
    #[error("domain `{domain}` declares no competence part (`SelfJudging::competence_parts`)")]
    NoParts {
        /// The domain.
        domain: String,
    },
    /// The domain does not model its robot's competence ([`SelfJudging`]).
    #[error(transparent)]
    NotModelled(#[from] SelfJudgingNotModelled),
    /// A seen part names an observation the robot does not perceive.
    #[error(transparent)]
    Observation(#[from] UnknownObservation),
    /// A bound of the standard is not a chance.
    #[error(transparent)]
    Standard(#[from] StandardError),
    /// The settings ask for nothing, or take estimates out of order.
    #[error(
        "a competence measure needs at least one behavior and one truth run, and `seen` in increasing order (got {behaviors} behaviors, {truth_runs} truth runs, seen {seen:?})"
    )]
    Settings {
        /// Behaviors asked for.
        behaviors: u32,
        /// Truth runs asked for.
        truth_runs: u32,
        /// Estimates asked for.
        seen: Vec<u32>,
    },
    /// Stopped by the user.
    #[error(transparent)]
    Interrupted(#[from] crate::Interrupted),
}

/// One behavior: its truth and the robot's estimates of it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BehaviorCompetence {
    /// The behavior.
    pub behavior: Behavior,
    /// Per part, the share of the truth's whole commands it applied to that fell short in
    /// it (`None`: it applied to none).
    pub truth: Vec<Option<f64>>,
    /// The robot's estimate after each number of commands of [`CompetenceSettings::seen`].
    pub estimates: Vec<Competence>,
}

/// The robot's estimates of every behavior measured, beside the truth.
#[derive(Clone, Debug, PartialEq)]
pub struct CompetenceAccuracy {
    /// The domain's name.
    pub domain: String,
    /// The operator's name.
    pub operator: String,
    /// The domain's parts.
    pub parts: Vec<CompetencePart>,
    /// What was measured.
    pub settings: CompetenceSettings,
    /// The behaviors, in the order drawn.
    pub behaviors: Vec<BehaviorCompetence>,
}

/// One part's error at one number of commands, over the behaviors where it is known.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PartError {
    /// The mean absolute difference between estimate and truth.
    pub absolute: MeanCi,
    /// The mean signed difference (estimate minus truth): above 0 the robot is too
    /// pessimistic.
    pub bias: MeanCi,
}

/// How the robot's verdict (competent or not) agrees with the truth's, in behaviors.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Agreement {
    /// Competent, and judged so.
    pub competent: u32,
    /// Not competent, and judged so.
    pub not_competent: u32,
    /// Not competent, but judged competent: an overtrust the robot would not see.
    pub missed: u32,
    /// Competent, but judged not: an overtrust it would see where there is none.
    pub false_alarm: u32,
}

impl Agreement {
    /// The share of behaviors judged as the truth judges them.
    pub fn accuracy(&self) -> f64 {
        let all = self.competent + self.not_competent + self.missed + self.false_alarm;
        f64::from(self.competent + self.not_competent) / f64::from(all.max(1))
    }
}

/// The truth of `behavior` in `domain`: per part, the share of `runs` whole commands it
/// applied to that fell short in it (`None`: it applied to none), drawn from `rng`
/// ([`SelfJudging::competence_truth`]).
pub fn true_rates<D: SelfJudging + ?Sized>(
    domain: &D,
    behavior: &Behavior,
    runs: u32,
    rng: &mut dyn RngCore,
) -> Vec<Option<f64>> {
    // Per part: commands it fell short in, and commands it applied to.
    let mut fell_short = vec![(0u32, 0u32); domain.competence_parts().len()];
    for _ in 0..runs {
        for (count, short) in fell_short
            .iter_mut()
            .zip(domain.competence_truth(behavior, rng))
        {
            if let Some(short) = short {
                count.0 += u32::from(short);
                count.1 += 1;
            }
        }
    }
    fell_short
        .iter()
        .map(|&(short, applied)| (applied > 0).then(|| f64::from(short) / f64::from(applied)))
        .collect()
}

/// The truth of `behavior` as a [`Competence`] of `parts`: every part's rate its true
/// share `truth` ([`true_rates`]).
pub fn true_competence(
    parts: &[CompetencePart],
    behavior: Behavior,
    truth: &[Option<f64>],
) -> Competence {
    Competence {
        behavior,
        commands: 0,
        parts: parts
            .iter()
            .zip(truth)
            .map(|(part, &truth)| PartEstimate {
                name: part.name,
                rate: truth,
                predicted: None,
                perceived: None,
            })
            .collect(),
    }
}

/// How `competence.md` begins ([`CompetenceAccuracy::markdown`]): what recognizes a
/// report of this kind ([`is_competence_markdown`]).
pub const MARKDOWN_TITLE: &str = "# The robot's own competence: ";

/// Whether `bytes` are a `competence.md` this module wrote (it begins with
/// [`MARKDOWN_TITLE`]).
pub fn is_competence_markdown(bytes: &[u8]) -> bool {
    bytes.starts_with(MARKDOWN_TITLE.as_bytes())
}

/// The keys of `competence.json` ([`CompetenceAccuracy::json`]), all of which a file of
/// this kind has.
const JSON_KEYS: [&str; 8] = [
    "domain",
    "operator",
    "behaviors",
    "truth_runs",
    "seed",
    "seen",
    "standard",
    "parts",
];

/// Whether `bytes` are a `competence.json` this module wrote: a JSON object with every
/// key [`CompetenceAccuracy::json`] writes.
pub fn is_competence_json(bytes: &[u8]) -> bool {
    serde_json::from_slice::<serde_json::Value>(bytes)
        .ok()
        .and_then(|v| {
            v.as_object()
                .map(|o| JSON_KEYS.iter().all(|k| o.contains_key(*k)))
        })
        .unwrap_or(false)
}

impl CompetenceAccuracy {
    /// Part `part`'s error after the `k`-th number of commands of the settings' `seen`;
    /// `None` when the robot knows it for no behavior.
    pub fn part_error(&self, k: usize, part: usize) -> Option<PartError> {
        let (absolute, signed): (Vec<f64>, Vec<f64>) = self
            .behaviors
            .iter()
            .filter_map(|b| {
                let (rate, truth) = (b.estimates[k].parts[part].rate?, b.truth[part]?);
                Some(((rate - truth).abs(), rate - truth))
            })
            .unzip();
        Some(PartError {
            absolute: mean_ci95(&absolute)?,
            bias: mean_ci95(&signed)?,
        })
    }

    /// The verdicts' agreement after the `k`-th number of commands of `seen`.
    pub fn agreement(&self, k: usize) -> Agreement {
        let standard = &self.settings.standard;
        let mut agreement = Agreement::default();
        for b in &self.behaviors {
            let truly = standard.met_by(&true_competence(&self.parts, b.behavior, &b.truth));
            let judged = standard.met_by(&b.estimates[k]);
            match (truly, judged) {
                (true, true) => agreement.competent += 1,
                (false, false) => agreement.not_competent += 1,
                (false, true) => agreement.missed += 1,
                (true, false) => agreement.false_alarm += 1,
            }
        }
        agreement
    }

    /// The mean true rate of part `part` over the behaviors it applied to.
    pub fn truth_mean(&self, part: usize) -> Option<f64> {
        let truths: Vec<f64> = self
            .behaviors
            .iter()
            .filter_map(|b| b.truth[part])
            .collect();
        mean_ci95(&truths).map(|m| m.mean)
    }

    /// The report in Markdown.
    pub fn markdown(&self) -> String {
        let s = &self.settings;
        let mut out = format!(
            "{MARKDOWN_TITLE}{}, operator {}\n\n{} behaviors drawn uniformly from the space (seed {}); the truth of each from {} whole commands with nobody to stop the robot; the robot's estimates after {} commands of each, in front of the operator. Standard: at most {} per command for every part{}.\n\n",
            self.domain,
            self.operator,
            s.behaviors,
            s.seed,
            s.truth_runs,
            s.seen
                .iter()
                .map(u32::to_string)
                .collect::<Vec<_>>()
                .join(", "),
            s.standard.at_most,
            s.standard
                .parts
                .iter()
                .map(|(p, b)| format!(", {b} for `{p}`"))
                .collect::<String>(),
        );
        out.push_str("## Each part: mean absolute error (and bias, estimate minus truth)\n\n| part | judged by | mean true rate |");
        for k in &s.seen {
            out.push_str(&format!(" after {k} |"));
        }
        out.push_str("\n|---|---|---:|");
        out.push_str(&"---:|".repeat(s.seen.len()));
        out.push('\n');
        for (i, part) in self.parts.iter().enumerate() {
            let judged = match part.seen_as {
                Some(observation) => format!("record (`{observation}`)"),
                None => "model".to_owned(),
            };
            out.push_str(&format!(
                "| `{}` | {} | {} |",
                part.name,
                judged,
                self.truth_mean(i)
                    .map_or("none".to_owned(), |m| format!("{m:.4}"))
            ));
            for k in 0..s.seen.len() {
                out.push_str(&match self.part_error(k, i) {
                    Some(e) => format!(
                        " {:.4} ± {:.4} ({:+.4}) |",
                        e.absolute.mean, e.absolute.ci95, e.bias.mean
                    ),
                    None => " unknown |".to_owned(),
                });
            }
            out.push('\n');
        }
        out.push_str("\n## Competent or not: the robot's verdict against the truth's, in behaviors\n\n| commands seen | competent, judged so | not competent, judged so | not competent, judged competent | competent, judged not | agreement |\n|---:|---:|---:|---:|---:|---:|\n");
        for (k, seen) in s.seen.iter().enumerate() {
            let a = self.agreement(k);
            out.push_str(&format!(
                "| {seen} | {} | {} | {} | {} | {:.1}% |\n",
                a.competent,
                a.not_competent,
                a.missed,
                a.false_alarm,
                100.0 * a.accuracy()
            ));
        }
        out
    }

    /// The report as JSON: settings, per part and number of commands the errors, the
    /// agreements, and every behavior.
    pub fn json(&self) -> serde_json::Value {
        let s = &self.settings;
        json!({
            "domain": self.domain,
            "operator": self.operator,
            "behaviors": s.behaviors,
            "truth_runs": s.truth_runs,
            "seed": s.seed,
            "seen": s.seen,
            "standard": s.standard,
            "parts": self.parts.iter().enumerate().map(|(i, part)| json!({
                "name": part.name,
                "seen_as": part.seen_as,
                "mean_true_rate": self.truth_mean(i),
                "errors": (0..s.seen.len()).map(|k| self.part_error(k, i).map(|e| json!({
                    "absolute": e.absolute,
                    "bias": e.bias,
                }))).collect::<Vec<_>>(),
            })).collect::<Vec<_>>(),
            "agreement": (0..s.seen.len()).map(|k| {
                let a = self.agreement(k);
                json!({"seen": s.seen[k], "counts": a, "accuracy": a.accuracy()})
            }).collect::<Vec<_>>(),
            "per_behavior": self.behaviors,
        })
    }
}

/// An empty record of `domain`'s competence parts, for a robot held to `standard`; refused
/// when the domain declares no part, a bound of the standard is not a chance, or a seen
/// part is not one of the domain's observations.
pub fn empty_record<O: crate::SimulatedOperator + Send + Sync>(
    domain: &dyn SelfJudging<Operator = O>,
    standard: &CompetenceStandard,
) -> Result<CompetenceRecord, CompetenceError> {
    let parts = domain.competence_parts();
    if parts.is_empty() {
        return Err(CompetenceError::NoParts {
            domain: domain.name().to_owned(),
        });
    }
    standard.validate()?;
    Ok(CompetenceRecord::new(parts, domain.observations())?)
}

/// Measures the robot's estimates of `settings.behaviors` behaviors of `domain` against
/// the truth, its commands judged by `operator` (named `operator_name` in the report), in
/// parallel on the current rayon pool; `progress()` is called after each behavior.
pub fn measure<D: Domain>(
    domain: &D,
    operator_name: &str,
    operator: &D::Operator,
    settings: &CompetenceSettings,
    progress: &(dyn Fn() + Sync),
) -> Result<CompetenceAccuracy, CompetenceError> {
    let judging = check_self_judging(domain)?;
    let empty = empty_record(judging, &settings.standard)?;
    let parts = judging.competence_parts();
    if settings.behaviors == 0
        || settings.truth_runs == 0
        || settings.seen.windows(2).any(|w| w[0] >= w[1])
    {
        return Err(CompetenceError::Settings {
            behaviors: settings.behaviors,
            truth_runs: settings.truth_runs,
            seen: settings.seen.clone(),
        });
    }
    let space = domain.space();
    // Distinct behaviors (a record counts a behavior's commands together): the whole
    // space when it has no more than asked for.
    let behaviors: Vec<Behavior> = if space.size() <= u64::from(settings.behaviors) {
        (0..space.size()).map(|rank| space.unrank(rank)).collect()
    } else {
        let mut draw = stream(settings.seed, 0, 0, Purpose::Competence);
        let mut drawn = std::collections::HashSet::new();
        let mut behaviors = Vec::with_capacity(settings.behaviors as usize);
        while behaviors.len() < settings.behaviors as usize {
            let behavior = space.draw(&mut draw);
            if drawn.insert(behavior) {
                behaviors.push(behavior);
            }
        }
        behaviors
    };
    let most = settings.seen.last().copied().unwrap_or(0);
    // Per behavior: the outcomes of its commands, and its truth.
    let runs = behaviors
        .par_iter()
        .enumerate()
        .map(|(i, behavior)| {
            crate::interrupt::check()?;
            let mut commands = stream(settings.seed, 1, i as u64, Purpose::Competence);
            let outcomes: Vec<trust::Outcome> = (0..most)
                .map(|_| domain.run(behavior, operator, &mut commands).outcome)
                .collect();
            let mut whole = stream(settings.seed, 2, i as u64, Purpose::Competence);
            let truth = true_rates(judging, behavior, settings.truth_runs, &mut whole);
            progress();
            Ok((outcomes, truth))
        })
        .collect::<Result<Vec<_>, CompetenceError>>()?;
    // Per number of commands: a record holding every behavior's first commands.
    let records: Vec<CompetenceRecord> = settings
        .seen
        .iter()
        .map(|&k| {
            let mut record = empty.clone();
            for (behavior, (outcomes, _)) in behaviors.iter().zip(&runs) {
                for outcome in &outcomes[..k as usize] {
                    record.record(*behavior, outcome);
                }
            }
            record
        })
        .collect();
    let behaviors = behaviors
        .iter()
        .zip(runs)
        .map(|(&behavior, (_, truth))| {
            let predicted = judging.predict_competence(&behavior);
            BehaviorCompetence {
                behavior,
                truth,
                estimates: records
                    .iter()
                    .map(|r| r.estimate(behavior, &predicted))
                    .collect(),
            }
        })
        .collect();
    Ok(CompetenceAccuracy {
        domain: domain.name().to_owned(),
        operator: operator_name.to_owned(),
        parts: parts.to_vec(),
        settings: settings.clone(),
        behaviors,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Judgement;
    use cbr_core::{BehaviorSpace, NamedComponent};
    use rand::RngCore;
    use std::sync::Arc;
    use trust::{Cause, DeclaredCause, Observations};

    const BUMP: Cause = Cause::from_static("bump");
    const WRONG: Cause = Cause::from_static("wrong");

    /// Way 0 always bumps and never goes wrong; way 1 never bumps, and what could go
    /// wrong does not apply to it. The robot's model says a wrong command one time in two
    /// for both.
    struct TwoWays {
        space: Arc<BehaviorSpace>,
        parts: [CompetencePart; 2],
    }

    impl TwoWays {
        fn new() -> Self {
            let way = NamedComponent::numeric("way", "", 0.0, 1.0, 2).unwrap();
            Self {
                space: Arc::new(BehaviorSpace::new(vec![way]).unwrap()),
                parts: [
                    CompetencePart {
                        name: BUMP,
                        seen_as: Some(BUMP),
                    },
                    CompetencePart {
                        name: WRONG,
                        seen_as: None,
                    },
                ],
            }
        }
    }

    impl Domain for TwoWays {
        type Operator = ();
        fn name(&self) -> &str {
            "two-ways"
        }
        fn space(&self) -> &Arc<BehaviorSpace> {
            &self.space
        }
        fn causes(&self) -> &[DeclaredCause] {
            &[]
        }
        fn observations(&self) -> &[Cause] {
            &[BUMP]
        }
        fn run(&self, behavior: &Behavior, _: &(), _: &mut dyn RngCore) -> Judgement {
            let bumped = behavior.get(0) == 0;
            Judgement::completed(1.0, 1.0)
                .observing(Observations::named(&[BUMP], bumped.then_some(BUMP)))
        }
        fn self_judging(&self) -> Option<&dyn SelfJudging<Operator = ()>> {
            Some(self)
        }
    }

    impl SelfJudging for TwoWays {
        fn competence_parts(&self) -> &[CompetencePart] {
            &self.parts
        }
        fn predict_competence(&self, _: &Behavior) -> Vec<Option<f64>> {
            vec![None, Some(0.5)]
        }
        fn competence_truth(&self, behavior: &Behavior, _: &mut dyn RngCore) -> Vec<Option<bool>> {
            // Way 1 never reaches what could go wrong.
            let bumps = behavior.get(0) == 0;
            vec![Some(bumps), bumps.then_some(false)]
        }
    }

    #[test]
    fn estimates_against_the_truth_by_hand() {
        let domain = TwoWays::new();
        let settings = CompetenceSettings {
            behaviors: 20,
            seen: vec![0, 2],
            truth_runs: 3,
            seed: 7,
            standard: CompetenceStandard::uniform(0.6).unwrap(),
        };
        let accuracy = measure(&domain, "anyone", &(), &settings, &|| {}).unwrap();
        // A space of two: both behaviors, the bumper (way 0) first.
        assert_eq!(accuracy.behaviors.len(), 2);
        // Nothing recorded: the seen part is 1/2 for both, off by 1/2 (too low for the
        // bumper, too high for the other); the model is off by 1/2 where it applies.
        let before = accuracy.part_error(0, 0).unwrap();
        assert_eq!((before.absolute.mean, before.bias.mean), (0.5, 0.0));
        assert_eq!(accuracy.part_error(0, 1).unwrap().absolute.mean, 0.5);
        // After 2 commands each: every behavior's rate (2 + 1/2) / (4 + 1) = 1/2; the
        // bumper's estimate (2 + 4 x 1/2) / 6 = 2/3, off by 1/3; the other's 2/6, off by
        // 1/3.
        let after = accuracy.part_error(1, 0).unwrap();
        assert!((after.absolute.mean - 1.0 / 3.0).abs() < 1e-12);
        assert!(after.bias.mean.abs() < 1e-12);
        // The standard (0.6): truly, the bumper is not competent and the other is.
        // Before any command both look competent (1/2 and 1/2): the bumper is a missed
        // overtrust; after two, its 2/3 exceeds 0.6 and the other's 1/3 does not.
        assert_eq!(
            accuracy.agreement(0),
            Agreement {
                competent: 1,
                not_competent: 0,
                missed: 1,
                false_alarm: 0
            }
        );
        assert_eq!(accuracy.agreement(1).accuracy(), 1.0);
    }

    #[test]
    fn a_domain_that_does_not_judge_itself_is_refused() {
        struct Blind(TwoWays);
        impl Domain for Blind {
            type Operator = ();
            fn name(&self) -> &str {
                "blind"
            }
            fn space(&self) -> &Arc<BehaviorSpace> {
                self.0.space()
            }
            fn causes(&self) -> &[DeclaredCause] {
                &[]
            }
            fn observations(&self) -> &[Cause] {
                &[BUMP]
            }
            fn run(&self, b: &Behavior, o: &(), rng: &mut dyn RngCore) -> Judgement {
                self.0.run(b, o, rng)
            }
        }
        let settings = CompetenceSettings {
            behaviors: 2,
            seen: vec![0],
            truth_runs: 1,
            seed: 0,
            standard: CompetenceStandard::uniform(0.1).unwrap(),
        };
        let error = measure(&Blind(TwoWays::new()), "x", &(), &settings, &|| {}).unwrap_err();
        assert!(
            matches!(error, CompetenceError::NotModelled { .. }),
            "{error}"
        );
        assert!(
            error.to_string().contains("`blind` does not model"),
            "{error}"
        );
        let mut backwards = settings.clone();
        backwards.seen = vec![5, 2];
        assert!(matches!(
            measure(&TwoWays::new(), "x", &(), &backwards, &|| {}),
            Err(CompetenceError::Settings { .. })
        ));
    }
}
