//! The contexts an experiment's trials run in (docs/simulation.md#context): trial `k` runs
//! in the `k`-th context of a cycle, modulo its length, so every arm meets the same
//! context in the same trial and arms stay paired. Its operator judges by the preferences
//! it states for that context ([`crate::Domain::operator_in_context`]); the robot is told
//! the context, unless its arm is blind to it as the paper's robot is
//! ([`crate::Arm::blind_to_context`]: its episodes and cases then all stay in the default
//! context). [`by_context`] breaks an experiment's results down by context, each arm
//! against its blind twin on the same trials, for the reports.

use crate::experiment::arm_name::{ArmName, NameOptions};
use crate::experiment::record::{ArmResult, TrialRecord};
use crate::stats::{MeanCi, mean_ci95_or_zero, wilcoxon_signed_rank};
use cbr_core::Context;
use std::collections::BTreeMap;

/// The contexts of an experiment's trials.
#[derive(Clone, Debug, PartialEq)]
pub struct TrialContexts {
    cycle: Vec<Context>,
}

impl TrialContexts {
    /// Trials in the contexts of `cycle`, in turn (at least one). `None` for an empty
    /// cycle.
    pub fn new(cycle: Vec<Context>) -> Option<Self> {
        (!cycle.is_empty()).then_some(Self { cycle })
    }

    /// The context trial `trial` runs in.
    pub fn of_trial(&self, trial: u32) -> &Context {
        &self.cycle[trial as usize % self.cycle.len()]
    }

    /// The contexts in turn.
    pub fn cycle(&self) -> &[Context] {
        &self.cycle
    }
}

/// One arm's trials in one context, or in all of them.
#[derive(Clone, Debug, PartialEq)]
pub struct ArmInContext {
    /// The context; `None`: every trial, whatever its context.
    pub context: Option<Context>,
    /// The arm's trials in it.
    pub trials: usize,
    /// Behaviors evaluated per trial.
    pub behaviors: MeanCi,
    /// Untrustworthy commands per trial.
    pub untrustworthy: MeanCi,
    /// The arm against its twin blind to the context, on the same trials, where the
    /// experiment runs both.
    pub versus_blind: Option<VersusBlind>,
}

/// An arm told its context against its twin blind to it (`NAME+context-blind`) on the
/// same trials: the mean paired differences, told minus blind, and their Wilcoxon
/// signed-rank p-values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VersusBlind {
    /// Behaviors evaluated per trial, told minus blind.
    pub behaviors: f64,
    /// The p-value of the behaviors' differences.
    pub behaviors_p: f64,
    /// Untrustworthy commands per trial, told minus blind.
    pub untrustworthy: f64,
    /// The p-value of the untrustworthy commands' differences.
    pub untrustworthy_p: f64,
}

/// Whether any trial of `arms` ran in a context other than the default one.
pub fn any_contexts<'a>(mut arms: impl Iterator<Item = &'a ArmResult>) -> bool {
    arms.any(|arm| arm.trials.iter().any(|t| !t.context.is_default()))
}

/// Each arm of an experiment over all its trials, then broken down by the contexts its
/// trials ran in (the default one first), each told arm against its blind twin where the
/// experiment runs it.
pub fn by_context(arms: &[ArmResult]) -> Vec<(&str, Vec<ArmInContext>)> {
    arms.iter()
        .map(|arm| {
            let twin = blind_twin(&arm.name).and_then(|name| arms.iter().find(|a| a.name == name));
            (arm.name.as_str(), in_contexts(arm, twin))
        })
        .collect()
}

/// The name of the arm `name`'s twin blind to the context; `None` for an arm already
/// blind.
pub(crate) fn blind_twin(name: &ArmName) -> Option<ArmName> {
    let options = name.options();
    (!options.context_blind).then(|| {
        name.with_options(NameOptions {
            context_blind: true,
            ..options
        })
    })
}

fn in_contexts(arm: &ArmResult, twin: Option<&ArmResult>) -> Vec<ArmInContext> {
    // The twin's trials by number, so that each trial finds its pair once.
    let twin_trials: Option<BTreeMap<u32, &TrialRecord>> =
        twin.map(|twin| twin.trials.iter().map(|t| (t.trial, t)).collect());
    let mut contexts: BTreeMap<Option<&Context>, Vec<&TrialRecord>> = BTreeMap::new();
    for trial in &arm.trials {
        contexts.entry(None).or_default().push(trial);
        contexts
            .entry(Some(&trial.context))
            .or_default()
            .push(trial);
    }
    contexts
        .into_iter()
        .map(|(context, trials)| {
            let column = |f: fn(&TrialRecord) -> u64, of: &[&TrialRecord]| -> Vec<f64> {
                of.iter().map(|t| f(t) as f64).collect()
            };
            let behaviors = |t: &TrialRecord| t.report.behaviors_evaluated;
            let untrustworthy = |t: &TrialRecord| t.report.untrustworthy;
            let versus_blind = twin_trials.as_ref().and_then(|twin| {
                let paired: Vec<&TrialRecord> = trials
                    .iter()
                    .map(|t| twin.get(&t.trial).copied())
                    .collect::<Option<_>>()?;
                let compare = |f: fn(&TrialRecord) -> u64| {
                    let (told, blind) = (column(f, &trials), column(f, &paired));
                    let mean = told.iter().zip(&blind).map(|(a, b)| a - b).sum::<f64>()
                        / told.len() as f64;
                    (mean, wilcoxon_signed_rank(&told, &blind).unwrap_or(1.0))
                };
                let ((b, b_p), (u, u_p)) = (compare(behaviors), compare(untrustworthy));
                Some(VersusBlind {
                    behaviors: b,
                    behaviors_p: b_p,
                    untrustworthy: u,
                    untrustworthy_p: u_p,
                })
            });
            ArmInContext {
                context: context.cloned(),
                trials: trials.len(),
                behaviors: mean_ci95_or_zero(&column(behaviors, &trials)),
                untrustworthy: mean_ci95_or_zero(&column(untrustworthy, &trials)),
                versus_blind,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use cbr_core::{ContextSpace, ContextVariable};

    #[test]
    fn trials_take_the_contexts_in_turn() {
        let space = ContextSpace::new(vec![ContextVariable::new(
            "cargo",
            &["normal", "hazardous"],
        )])
        .unwrap();
        let hazardous = space.context([("cargo", "hazardous")]).unwrap();
        let cycle = vec![Context::default(), hazardous.clone()];
        let contexts = TrialContexts::new(cycle).unwrap();
        assert_eq!(contexts.of_trial(0), &Context::default());
        assert_eq!(contexts.of_trial(3), &hazardous);
        assert_eq!(contexts.cycle().len(), 2);
        assert_eq!(TrialContexts::new(Vec::new()), None);
    }

    #[test]
    fn each_arm_by_context_against_its_blind_twin_by_hand() {
        let space = ContextSpace::new(vec![ContextVariable::new(
            "cargo",
            &["normal", "hazardous"],
        )])
        .unwrap();
        let hazardous = space.context([("cargo", "hazardous")]).unwrap();
        // Trials 0 and 2 in the default context, 1 and 3 with hazardous cargo.
        let in_turn = |mut arm: ArmResult| {
            for t in &mut arm.trials {
                if t.trial % 2 == 1 {
                    t.context = hazardous.clone();
                }
            }
            arm
        };
        let arms = [
            in_turn(ArmResult::of_trials(
                "x",
                &[(true, 4), (true, 6), (true, 8), (true, 2)],
            )),
            in_turn(ArmResult::of_trials(
                "x+context-blind",
                &[(true, 5), (true, 9), (true, 8), (true, 6)],
            )),
        ];
        assert!(any_contexts(arms.iter()));
        assert!(!any_contexts(
            [ArmResult::of_trials("y", &[(true, 1)])].iter()
        ));
        let rows = by_context(&arms);
        let (name, told) = &rows[0];
        assert_eq!(*name, "x");
        assert_eq!(told.len(), 3);
        // Over every trial: differences -1, -3, 0 and -4.
        assert_eq!(told[0].context, None);
        assert_eq!((told[0].trials, told[0].untrustworthy.mean), (4, 5.0));
        assert_eq!(told[0].versus_blind.unwrap().untrustworthy, -2.0);
        assert_eq!(told[1].context, Some(Context::default()));
        assert_eq!((told[1].trials, told[1].untrustworthy.mean), (2, 6.0));
        let versus = told[1].versus_blind.unwrap();
        // Differences 4 - 5 and 8 - 8; behaviors the same in every trial.
        assert_eq!((versus.untrustworthy, versus.behaviors), (-0.5, 0.0));
        assert_eq!(versus.behaviors_p, 1.0);
        assert_eq!(told[2].context, Some(hazardous));
        // Differences 6 - 9 and 2 - 6.
        assert_eq!(told[2].versus_blind.unwrap().untrustworthy, -3.5);
        assert_eq!(told[2].untrustworthy.mean, 4.0);
        // The blind arm has no twin of its own.
        assert!(rows[1].1.iter().all(|r| r.versus_blind.is_none()));
        let twin = |name: &str| blind_twin(&ArmName::parse(name).unwrap());
        assert_eq!(
            twin("x+learned-start+competent").unwrap(),
            "x+context-blind+learned-start+competent"
        );
        assert_eq!(twin("x+context-blind"), None);
    }
}
