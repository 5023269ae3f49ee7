//! The contexts an experiment's trials run in (docs/simulation.md#context): trial `k` runs
//! in the `k`-th context of a cycle, modulo its length, so every arm meets the same
//! context in the same trial and arms stay paired. Its operator judges by the preferences
//! it states for that context ([`crate::Domain::operator_in_context`]); the robot is told
//! the context, unless its arm is blind to it as the paper's robot is
//! ([`crate::Arm::blind_to_context`]: its episodes and cases then all stay in the default
//! context).

use cbr_core::Context;

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
}
