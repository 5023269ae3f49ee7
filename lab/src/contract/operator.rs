//! What the laboratory reads of a simulated operator, and the fields every operator file
//! shares.
//!
//! Every domain's operator type implements [`SimulatedOperator`]: how it explains itself
//! and what a completion weighs for it, both with defaults (the paper's silent operator;
//! no completion weight known), which [`Domain::feedback`](crate::Domain::feedback) and
//! the tool's `Catalog::completion_weight` read unless a domain overrides them.
//!
//! An operator read from a file has four fields whatever its domain: its `name`, its
//! patience (`give_up_factor`, [`GiveUpFactor`]), its outcome `weights` and its
//! `feedback` channel ([`StandardFields`]). A plug-in declares its operator with
//! [`standard_operator!`](crate::standard_operator), which adds the four fields (with
//! their defaults in the file) around the domain's own, implements both traits from
//! them, and leaves the domain to write only what is its own: its fields, their ranges
//! ([`OperatorData::validate`](crate::contract::operator_file::OperatorData::validate)) and how it
//! watches a run ([`StandardFields::patience`] builds its [`Patience`]). The operator-file
//! loader checks the standard fields itself (`give_up_factor` at least 1, the weights
//! against the declared causes), so no domain repeats those checks.
//!
//! ```
//! use lab::contract::operator::{SimulatedOperator, StandardFields};
//! use lab::contract::operator_file::{self, OperatorData, RangeCheck};
//! use serde::{Deserialize, Serialize};
//! use std::convert::Infallible;
//! use std::path::Path;
//! use trust::{Cause, DeclaredCause};
//!
//! lab::standard_operator! {
//!     /// A courier's dispatcher: how long a delivery may take, and how often it
//!     /// interrupts a late one.
//!     #[derive(Clone, Debug, Serialize, Deserialize)]
//!     #[serde(deny_unknown_fields)]
//!     pub struct Dispatcher {
//!         /// The time a delivery may take (s).
//!         pub t_complete: f64,
//!         /// The chance it interrupts a late delivery.
//!         pub p_deadline: f64,
//!     }
//! }
//!
//! impl OperatorData for Dispatcher {
//!     type Invalid = Infallible;
//!
//!     fn validate(&self, check: &mut RangeCheck) {
//!         check.positive("t_complete", self.t_complete);
//!         check.probability("p_deadline", self.p_deadline);
//!     }
//! }
//!
//! const LATE: Cause = Cause::from_static("late");
//! let causes = [DeclaredCause::new(LATE)];
//! let night: Dispatcher = operator_file::from_ron(
//!     r#"(name: "night", t_complete: 600.0, p_deadline: 0.2, feedback: (explains: 0.5))"#,
//!     Path::new("ops/night.ron"),
//!     &causes,
//! )?;
//! // The standard fields, with their defaults: patience 2, completions weigh 1.
//! assert_eq!((night.name(), night.give_up_factor()), ("night", 2.0));
//! assert_eq!(night.completion_weight(), Some(1.0));
//! assert_eq!(night.feedback().explains, 0.5);
//! let patience = night.patience(night.t_complete, night.p_deadline, LATE);
//! assert_eq!(patience.give_up_s(), 1200.0);
//!
//! // The loader checks the standard fields after the domain's own.
//! let err = operator_file::from_ron::<Dispatcher>(
//!     r#"(name: "day", t_complete: 600.0, p_deadline: 0.2, give_up_factor: 0.5)"#,
//!     Path::new("ops/day.ron"),
//!     &causes,
//! )
//! .unwrap_err();
//! assert_eq!(
//!     err.to_string(),
//!     "ops/day.ron: operator `day`: `give_up_factor` must be a finite number >= 1, got 0.5"
//! );
//! # Ok::<(), lab::contract::operator_file::OperatorFileError>(())
//! ```

use crate::contract::attention::Attending;
use crate::contract::feedback::FeedbackChannel;
use crate::contract::judgement::Judgement;
use crate::contract::patience::{Patience, default_give_up_factor};
use rand::RngCore;
use serde::{Deserialize, Serialize};
use trust::Cause;
/// The weights' type, re-exported for [`standard_operator!`](crate::standard_operator)'s
/// expansion in a crate that does not depend on `trust` by name.
pub use trust::OutcomeWeights;

/// What the laboratory reads of any domain's operator (the bound on
/// [`Domain::Operator`](crate::Domain::Operator)). Both methods have defaults, so an
/// operator type without these fields implements it with `impl SimulatedOperator for T {}`;
/// [`standard_operator!`](crate::standard_operator) implements it from the standard fields.
pub trait SimulatedOperator {
    /// How the operator explains itself; the paper's silent operator by default. An
    /// experiment may override it for all its operators.
    fn feedback(&self) -> FeedbackChannel {
        FeedbackChannel::SILENT
    }

    /// What one completed command weighs for the operator (its `weights.completed`), which
    /// bounds how fast trust can reach a threshold; `None` (the default) when the operator
    /// has no such weight.
    fn completion_weight(&self) -> Option<f64> {
        None
    }
}

// Operators of toy domains in tests and examples: plain values (a favourite value, a
// table of completion chances) with no feedback or weights of their own.
impl SimulatedOperator for () {}
impl SimulatedOperator for u16 {}
impl SimulatedOperator for f64 {}
impl SimulatedOperator for Vec<f64> {}

/// The fields every operator file has: its name, its patience, its outcome weights and
/// its feedback channel. [`standard_operator!`](crate::standard_operator) implements it;
/// a domain with an operator type of its own shape implements the accessors by hand.
pub trait StandardFields: SimulatedOperator {
    /// The operator's name, as errors and reports show it.
    fn name(&self) -> &str;

    /// The operator gives up on a run at this multiple of its deadline (at least 1: the
    /// loader refuses less).
    fn give_up_factor(&self) -> f64;

    /// How much each ending weighs for the operator.
    fn weights(&self) -> &OutcomeWeights;

    /// The weights, for the loader to check against the declared causes (which fill in
    /// their default weights).
    fn weights_mut(&mut self) -> &mut OutcomeWeights;

    /// The operator's patience with a run whose deadline is `deadline_s`, interrupted once
    /// late with probability `p_interrupt`, both the interruption and giving up blamed on
    /// `cause`; it gives up at [`StandardFields::give_up_factor`] times the deadline.
    fn patience(&self, deadline_s: f64, p_interrupt: f64, cause: Cause) -> Patience {
        Patience {
            deadline_s,
            p_interrupt,
            give_up_factor: self.give_up_factor(),
            cause,
        }
    }

    /// How a run ends for this operator at `attention` (1: the paper's attentive
    /// operator): the run's `(time, event)` pairs, in time order, watched with `patience`
    /// ([`Patience::watch`], its endings weighed by the operator's weights), `react`
    /// saying how each event ends the run (`None`: it goes on; ask the [`Attending`] it is
    /// handed at each reaction), and the judgement naming the first problem overlooked
    /// ([`Attending::judge`]). The whole of a domain's `judge_attending` but its
    /// reactions.
    fn judge_run<E, R: RngCore + ?Sized>(
        &self,
        patience: &Patience,
        events: impl IntoIterator<Item = (f64, E)>,
        attention: f64,
        rng: &mut R,
        react: impl FnMut(&mut Attending, &mut R, f64, E) -> Option<Judgement>,
    ) -> Judgement
    where
        Self: Sized,
    {
        Attending::judge(attention, |attending| {
            patience.watch(events, self.weights(), attending, rng, react)
        })
    }
}

/// An operator's patience as its file writes it: `give_up_factor: 2.5`, a multiple of
/// its deadline (at least 1); 2 when the file leaves it out
/// ([`default_give_up_factor`]). A number in the file, a newtype in Rust only so that the
/// default needs no path in a plug-in's serde attributes.
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd, Serialize, Deserialize)]
#[serde(transparent)]
pub struct GiveUpFactor(pub f64);

impl Default for GiveUpFactor {
    fn default() -> Self {
        Self(default_give_up_factor())
    }
}

/// Declares a plug-in's operator type with the standard fields
/// ([`StandardFields`](crate::contract::operator::StandardFields)) around the domain's own:
/// `name: String` first, then the fields written, then `give_up_factor:`
/// [`GiveUpFactor`](crate::contract::operator::GiveUpFactor), `weights: OutcomeWeights` and
/// `feedback:` [`FeedbackChannel`](crate::FeedbackChannel) (each of the last three
/// optional in a file), and implements
/// [`SimulatedOperator`](crate::contract::operator::SimulatedOperator) (the `feedback` field, the
/// weights' completion) and `StandardFields` from them.
///
/// The struct's attributes are the caller's and must derive serde's `Deserialize` (the
/// added fields carry `#[serde(default)]`); a crate that reaches serde through another
/// crate says so as usual (`#[serde(crate = "trustcbr::serde")]`). See the
/// [`operator`](crate::contract::operator) module for an example.
#[macro_export]
macro_rules! standard_operator {
    (
        $(#[$meta:meta])*
        $vis:vis struct $name:ident {
            $(
                $(#[$field_meta:meta])*
                $field_vis:vis $field:ident : $ty:ty
            ),* $(,)?
        }
    ) => {
        $(#[$meta])*
        $vis struct $name {
            /// The operator's name (e.g. `cautious`).
            pub name: ::std::string::String,
            $(
                $(#[$field_meta])*
                $field_vis $field: $ty,
            )*
            /// The operator gives up at this multiple of its deadline (at least 1; 2 when
            /// absent).
            #[serde(default)]
            pub give_up_factor: $crate::contract::operator::GiveUpFactor,
            /// How much each ending weighs (the declared defaults when absent).
            #[serde(default)]
            pub weights: $crate::contract::operator::OutcomeWeights,
            /// How the operator explains itself (`feedback: (explains: 0.3, wrong: 0.1)`);
            /// silent, as the paper's operator, when absent. An experiment's `feedback`
            /// overrides it.
            #[serde(default)]
            pub feedback: $crate::FeedbackChannel,
        }

        impl $crate::contract::operator::SimulatedOperator for $name {
            fn feedback(&self) -> $crate::FeedbackChannel {
                self.feedback
            }

            fn completion_weight(&self) -> ::std::option::Option<f64> {
                ::std::option::Option::Some(self.weights.completed)
            }
        }

        impl $crate::contract::operator::StandardFields for $name {
            fn name(&self) -> &str {
                &self.name
            }

            fn give_up_factor(&self) -> f64 {
                self.give_up_factor.0
            }

            fn weights(&self) -> &$crate::contract::operator::OutcomeWeights {
                &self.weights
            }

            fn weights_mut(&mut self) -> &mut $crate::contract::operator::OutcomeWeights {
                &mut self.weights
            }
        }
    };
}
