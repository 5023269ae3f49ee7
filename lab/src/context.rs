//! The contexts an experiment's trials run in (docs/simulation.md#context): trial `k` runs
//! in the `k`-th context of a cycle, modulo its length, so every arm meets the same
//! context in the same trial and arms stay paired. Its operator judges by the preferences
//! it states for that context ([`crate::Domain::operator_in_context`]); the robot is told
//! the context, or, for the paper's context-blind robot, is not (its episodes and cases
//! then all stay in the default context).

use cbr_core::Context;

/// The contexts of an experiment's trials, and whether the robot is told them.
#[derive(Clone, Debug, PartialEq)]
pub struct TrialContexts {
    cycle: Vec<Context>,
    told: bool,
}

impl TrialContexts {
    /// Trials in the contexts of `cycle`, in turn (at least one), the robot told them
    /// when `told`. `None` for an empty cycle.
    pub fn new(cycle: Vec<Context>, told: bool) -> Option<Self> {
        (!cycle.is_empty()).then_some(Self { cycle, told })
    }

    /// The context trial `trial` runs in.
    pub fn of_trial(&self, trial: u32) -> &Context {
        &self.cycle[trial as usize % self.cycle.len()]
    }

    /// The context the robot is told in trial `trial`: the trial's, or the default one
    /// for a robot not told.
    pub fn told_in(&self, trial: u32) -> Context {
        if self.told {
            self.of_trial(trial).clone()
        } else {
            Context::default()
        }
    }

    /// The contexts in turn.
    pub fn cycle(&self) -> &[Context] {
        &self.cycle
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cbr_core::{ContextSpace, ContextVariable};

    #[test]
    fn trials_take_the_contexts_in_turn_and_a_blind_robot_is_told_none() {
        let space = ContextSpace::new(vec![ContextVariable::new(
            "cargo",
            &["normal", "hazardous"],
        )])
        .unwrap();
        let hazardous = space.context([("cargo", "hazardous")]).unwrap();
        let cycle = vec![Context::default(), hazardous.clone()];
        let told = TrialContexts::new(cycle.clone(), true).unwrap();
        assert_eq!(told.of_trial(0), &Context::default());
        assert_eq!(told.of_trial(3), &hazardous);
        assert_eq!(told.told_in(3), hazardous);
        let blind = TrialContexts::new(cycle, false).unwrap();
        assert_eq!(blind.of_trial(3), &hazardous);
        assert_eq!(blind.told_in(3), Context::default());
        assert_eq!(TrialContexts::new(Vec::new(), true), None);
    }
}
