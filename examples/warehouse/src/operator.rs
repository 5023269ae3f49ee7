//! The simulated operators, as data: what each watches in a pick and how much each ending
//! weighs. A new operator is a RON file.
//!
//! The operator reads the trace in time order. When its deadline `t_complete` passes it
//! interrupts with probability `p_deadline`; if it lets the robot go on, it gives up at
//! `give_up_factor x t_complete` (the pick fails, too slow). On each collision it
//! interrupts with probability `p_collision`. A slot not found and a dropped item fail the
//! pick. A delivered item completes it, unless it arrived crushed and the packer notices
//! (probability `p_crushed`), which fails it.

use crate::cause::WarehouseCause;
use crate::trace::{Event, Trace};
use rand::{Rng, RngCore};
use std::fmt;
use std::path::{Path, PathBuf};
use trustcbr::files::{FileError, RonError, parse_ron, read_text};
use trustcbr::lab::{FeedbackChannel, Judgement};
use trustcbr::rand;
use trustcbr::serde::{Deserialize, Serialize};
use trustcbr::trust::{OutcomeKind, OutcomeWeights, WeightsError};

fn two() -> f64 {
    2.0
}

/// A simulated warehouse operator.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(crate = "trustcbr::serde", deny_unknown_fields)]
pub struct WarehouseOperator {
    /// The operator's name (e.g. `throughput-focused`).
    pub name: String,
    /// The time the operator allows for one pick (s).
    pub t_complete: f64,
    /// Probability of interrupting when `t_complete` passes.
    pub p_deadline: f64,
    /// Probability of interrupting on each collision.
    pub p_collision: f64,
    /// Probability that a crushed item is noticed at packing (and the pick failed).
    pub p_crushed: f64,
    /// The operator gives up at this multiple of `t_complete` (the pick fails, too slow).
    #[serde(default = "two")]
    pub give_up_factor: f64,
    /// Outcome weights.
    #[serde(default)]
    pub weights: OutcomeWeights,
    /// How the operator explains itself (`feedback: (explains: 0.3, wrong: 0.1)`); silent,
    /// as the paper's operator, when absent. An experiment's `feedback` overrides it.
    #[serde(default)]
    pub feedback: FeedbackChannel,
}

/// Why an operator file cannot be used.
#[derive(Debug)]
pub enum OperatorError {
    /// The file could not be read.
    Io(FileError),
    /// The file is not a valid operator in RON (the error names line:column).
    Syntax(RonError),
    /// A weight is out of range, or `weights.by_cause` names a cause the warehouse does
    /// not declare.
    Weights {
        /// The file.
        file: PathBuf,
        /// The operator's name.
        operator: String,
        /// What is wrong with the weights.
        reason: WeightsError,
    },
    /// A value is out of its allowed range.
    Range {
        /// The file.
        file: PathBuf,
        /// The operator's name.
        operator: String,
        /// The field, e.g. `p_collision`.
        field: String,
        /// The allowed range.
        allowed: &'static str,
        /// The value given.
        value: f64,
    },
}

impl fmt::Display for OperatorError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io(e) => e.fmt(f),
            Self::Syntax(e) => e.fmt(f),
            Self::Weights {
                file,
                operator,
                reason,
            } => write!(f, "{}: operator `{operator}`: {reason}", file.display()),
            Self::Range {
                file,
                operator,
                field,
                allowed,
                value,
            } => write!(
                f,
                "{}: operator `{operator}`: `{field}` must be {allowed}, got {value}",
                file.display()
            ),
        }
    }
}

impl std::error::Error for OperatorError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io(e) => e.source(),
            Self::Syntax(e) => e.source(),
            Self::Weights { .. } | Self::Range { .. } => None,
        }
    }
}

impl From<FileError> for OperatorError {
    fn from(e: FileError) -> Self {
        Self::Io(e)
    }
}

impl From<RonError> for OperatorError {
    fn from(e: RonError) -> Self {
        Self::Syntax(e)
    }
}

impl WarehouseOperator {
    /// Parses and validates an operator; `origin` names the source in errors.
    pub fn from_ron(text: &str, origin: &Path) -> Result<Self, OperatorError> {
        let mut operator: Self = parse_ron(text, origin)?;
        operator.validate(origin)?;
        operator
            .weights
            .check(&crate::cause::DECLARED)
            .map_err(|reason| OperatorError::Weights {
                file: origin.to_owned(),
                operator: operator.name.clone(),
                reason,
            })?;
        Ok(operator)
    }

    /// Reads, parses and validates an operator file.
    pub fn load(path: &Path) -> Result<Self, OperatorError> {
        Self::from_ron(&read_text(path)?, path)
    }

    fn validate(&self, origin: &Path) -> Result<(), OperatorError> {
        let range = |field: String, allowed, value| OperatorError::Range {
            file: origin.to_owned(),
            operator: self.name.clone(),
            field,
            allowed,
            value,
        };
        for (field, p) in [
            ("p_deadline", self.p_deadline),
            ("p_collision", self.p_collision),
            ("p_crushed", self.p_crushed),
        ] {
            if !(0.0..=1.0).contains(&p) {
                return Err(range(field.into(), "a probability in [0, 1]", p));
            }
        }
        if !(self.t_complete.is_finite() && self.t_complete > 0.0) {
            return Err(range(
                "t_complete".into(),
                "a finite number of seconds > 0",
                self.t_complete,
            ));
        }
        if !(self.give_up_factor.is_finite() && self.give_up_factor >= 1.0) {
            return Err(range(
                "give_up_factor".into(),
                "a finite number >= 1",
                self.give_up_factor,
            ));
        }
        Ok(())
    }

    /// Watches a pick and decides how it ends; random reactions draw from `rng`.
    pub fn judge(&self, trace: &Trace, rng: &mut dyn RngCore) -> Judgement {
        let give_up = self.t_complete * self.give_up_factor;
        let mut deadline_seen = false;
        // A trace without an ending (never the simulation's) is a pick that never ends:
        // the operator waits for it past every deadline.
        let events = trace.events.iter().map(|&(t, e)| (t, Some(e)));
        for (t, event) in events.chain([(f64::INFINITY, None)]) {
            if !deadline_seen && t > self.t_complete {
                deadline_seen = true;
                if rng.random::<f64>() < self.p_deadline {
                    return self.ending(
                        OutcomeKind::Interrupted,
                        WarehouseCause::TooSlow,
                        self.t_complete,
                    );
                }
            }
            if t > give_up {
                break;
            }
            match event {
                // The reaction is drawn at every collision, in trace order.
                Some(Event::Collision) if rng.random::<f64>() < self.p_collision => {
                    return self.ending(OutcomeKind::Interrupted, WarehouseCause::Collision, t);
                }
                Some(Event::ItemNotFound) => {
                    return self.ending(OutcomeKind::Failed, WarehouseCause::ItemNotFound, t);
                }
                Some(Event::DroppedItem) => {
                    return self.ending(OutcomeKind::Failed, WarehouseCause::DroppedItem, t);
                }
                Some(Event::Delivered { crushed }) => {
                    if crushed && rng.random::<f64>() < self.p_crushed {
                        return self.ending(OutcomeKind::Failed, WarehouseCause::CrushedItem, t);
                    }
                    return Judgement::completed(self.weights.completed, t);
                }
                Some(Event::Collision) | None => {}
            }
        }
        self.ending(OutcomeKind::Failed, WarehouseCause::TooSlow, give_up)
    }

    /// A failure or interruption with `cause` at `t`, weighted by this operator.
    fn ending(&self, kind: OutcomeKind, cause: WarehouseCause, t: f64) -> Judgement {
        Judgement::new(
            kind,
            self.weights.of(cause.to_trust()),
            Some(cause.to_trust()),
            t,
        )
    }
}

/// The operators shipped with the crate (`operators/*.ron`), in this order.
pub fn builtin_operators() -> Vec<WarehouseOperator> {
    [
        (
            "operators/throughput-focused.ron",
            include_str!("../operators/throughput-focused.ron"),
        ),
        (
            "operators/care-focused.ron",
            include_str!("../operators/care-focused.ron"),
        ),
        (
            "operators/balanced.ron",
            include_str!("../operators/balanced.ron"),
        ),
    ]
    .into_iter()
    .map(|(origin, text)| {
        WarehouseOperator::from_ron(text, Path::new(origin)).expect("shipped operators are valid")
    })
    .collect()
}
