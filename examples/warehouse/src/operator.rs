//! The simulated operators, as data: what each watches in a pick and how much each ending
//! weighs. A new operator is a RON file.
//!
//! The operator reads the trace in time order. When its deadline `t_complete` passes it
//! interrupts with probability `p_deadline`; if it lets the robot go on, it gives up at
//! `give_up_factor x t_complete` (the pick fails, too slow). On each collision it
//! interrupts with probability `p_collision`. A slot not found and a dropped item fail the
//! pick. A delivered item completes it, unless it arrived crushed and the packer notices
//! (probability `p_crushed`), which fails it.

use crate::cause::{DECLARED, WarehouseCause};
use crate::trace::{Event, Trace};
use rand::RngCore;
use std::convert::Infallible;
use std::path::Path;
use trustcbr::lab::contract::operator_file::{self, OperatorData, OperatorFileError, RangeCheck};
use trustcbr::lab::{Judgement, StandardFields};
use trustcbr::rand;
use trustcbr::serde::{Deserialize, Serialize};
use trustcbr::trust::OutcomeKind;

trustcbr::lab::standard_operator! {
    /// A simulated warehouse operator: besides the standard fields (`name`,
    /// `give_up_factor`, `weights`, `feedback`), what it watches in a pick.
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    #[serde(crate = "trustcbr::serde", deny_unknown_fields)]
    pub struct WarehouseOperator {
        /// The time the operator allows for one pick (s).
        pub t_complete: f64,
        /// Probability of interrupting when `t_complete` passes.
        pub p_deadline: f64,
        /// Probability of interrupting on each collision.
        pub p_collision: f64,
        /// Probability that a crushed item is noticed at packing (and the pick failed).
        pub p_crushed: f64,
    }
}

/// Why an operator file cannot be used (the warehouse has no rules of its own beyond the
/// lab's checks).
pub type OperatorError = OperatorFileError;

impl OperatorData for WarehouseOperator {
    type Invalid = Infallible;

    fn validate(&self, check: &mut RangeCheck) {
        check.probability("p_deadline", self.p_deadline);
        check.probability("p_collision", self.p_collision);
        check.probability("p_crushed", self.p_crushed);
        check.positive("t_complete", self.t_complete);
    }
}

impl WarehouseOperator {
    /// Parses and validates an operator against the warehouse's causes; `origin` names the
    /// source in errors.
    pub fn from_ron(text: &str, origin: &Path) -> Result<Self, OperatorError> {
        operator_file::from_ron(text, origin, &DECLARED)
    }

    /// Reads, parses and validates an operator file.
    pub fn load(path: &Path) -> Result<Self, OperatorError> {
        operator_file::load(path, &DECLARED)
    }

    /// Watches a pick and decides how it ends; random reactions draw from `rng`.
    pub fn judge(&self, trace: &Trace, rng: &mut dyn RngCore) -> Judgement {
        self.judge_attending(trace, 1.0, rng)
    }

    /// [`WarehouseOperator::judge`] by an operator whose `attention`, in `[0, 1]`, is the
    /// chance it notices what it would react to (`lab::contract::attention`): interrupting at the
    /// deadline or at a collision, and the packer's look at a crushed item, each happen
    /// with probability `p * attention` on the same draw, so at attention 1 this is
    /// exactly `judge`. What it overlooks lets the pick go on, and the first such cause is
    /// the judgement's `overlooked`. A missing slot, a dropped item and a pick past the
    /// operator's patience are noticed whatever the attention: the pick cannot go on.
    pub fn judge_attending(
        &self,
        trace: &Trace,
        attention: f64,
        rng: &mut dyn RngCore,
    ) -> Judgement {
        let too_slow = WarehouseCause::TooSlow.to_trust();
        let patience = self.patience(self.t_complete, self.p_deadline, too_slow);
        let failed = |cause: WarehouseCause, t| {
            Some(Judgement::weighed(
                OutcomeKind::Failed,
                cause.to_trust(),
                t,
                &self.weights,
            ))
        };
        let events = trace.events.iter().copied();
        self.judge_run(
            &patience,
            events,
            attention,
            rng,
            |attending, rng, t, event| {
                match event {
                    // The reaction is drawn at every collision, in trace order.
                    Event::Collision => {
                        let collision = WarehouseCause::Collision.to_trust();
                        attending.interrupts(rng, self.p_collision, collision, t, &self.weights)
                    }
                    Event::ItemNotFound => failed(WarehouseCause::ItemNotFound, t),
                    Event::DroppedItem => failed(WarehouseCause::DroppedItem, t),
                    Event::Delivered { crushed: true }
                        if attending.react(
                            rng,
                            self.p_crushed,
                            WarehouseCause::CrushedItem.to_trust(),
                        ) =>
                    {
                        failed(WarehouseCause::CrushedItem, t)
                    }
                    Event::Delivered { .. } => {
                        Some(Judgement::completed(self.weights.completed, t))
                    }
                }
            },
        )
    }
}

/// The operators shipped with the crate (`operators/*.ron`), in this order.
pub fn builtin_operators() -> Vec<WarehouseOperator> {
    let shipped = trustcbr::lab::shipped_operators!(
        &DECLARED,
        [
            "operators/throughput-focused.ron",
            "operators/care-focused.ron",
            "operators/balanced.ron",
        ]
    );
    shipped.expect("shipped operators are valid")
}
