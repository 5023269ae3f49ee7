//! The adapter's configuration: the paper's parameters (thresholds, `lambda`, retention,
//! the unit of time) and the kinds of its parts (retriever, search strategy), as a file or
//! a request names them, checked before an adapter is built.

use crate::estimate::{ThresholdError, Thresholds};
use crate::evaluated::{LambdaError, validate_lambda};
use crate::retrieval::RetrieverKind;
use crate::search::SearchKind;
use crate::{TrustCaseBase, TrustMemory};
use cbr_core::BehaviorSpace;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The adapter's configuration, as a file or a request names it: its [`Parameters`] and
/// the kinds of its parts (the retriever and the search strategy); the defaults are the
/// paper's.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AdapterConfig {
    /// The trust thresholds (paper: +5 / -5).
    pub thresholds: Thresholds,
    /// Algorithm 2's behavior-similarity threshold (paper: 0.95), in `(0, 1]`; checked
    /// when deserialized, so a parser reports the position of a bad value.
    #[serde(deserialize_with = "crate::evaluated::deserialize_lambda")]
    pub lambda: f64,
    /// Reuse cases (Algorithm 1) before searching; `false` is the search strategy alone.
    pub reuse_cases: bool,
    /// The retriever that answers Algorithm 1's queries.
    pub retriever: RetrieverKind,
    /// The search strategy.
    pub search: SearchKind,
    /// Which episodes are retained as cases (docs/model.md#open-readings).
    pub retention: Retention,
    /// The unit of an evaluated pair's time `t` (docs/model.md#open-readings).
    pub time_unit: TimeUnit,
}

/// What the episode machine itself follows: every field of an [`AdapterConfig`] but the
/// kinds of its parts. An adapter built from ready-made parts ([`Adaptation::with_parts`],
/// [`TrustAdapter::with_parts`]) takes these, so no field it would not read is handed to
/// it. The defaults are the paper's.
///
/// [`Adaptation::with_parts`]: super::Adaptation::with_parts
/// [`TrustAdapter::with_parts`]: super::TrustAdapter::with_parts
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Parameters {
    /// The trust thresholds (paper: +5 / -5).
    pub thresholds: Thresholds,
    /// Algorithm 2's behavior-similarity threshold (paper: 0.95), in `(0, 1]`: what
    /// counts as the same behavior when a reused case is explained and a first behavior
    /// is guessed (the memory's retriever is built with its own).
    pub lambda: f64,
    /// Reuse cases (Algorithm 1) before searching; `false` is the search strategy alone.
    pub reuse_cases: bool,
    /// Which episodes are retained as cases (docs/model.md#open-readings).
    pub retention: Retention,
    /// The unit of an evaluated pair's time `t` (docs/model.md#open-readings).
    pub time_unit: TimeUnit,
}

impl Default for Parameters {
    fn default() -> Self {
        AdapterConfig::default().parameters()
    }
}

impl Parameters {
    /// Checks every field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.thresholds.validate()?;
        validate_lambda(self.lambda)?;
        Ok(())
    }
}

/// Which successful episodes are retained as cases. The paper glosses its own
/// rule as "the agent could not find a solution by only using the case base"; the two
/// readings differ when a search step is followed by a successful reuse.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum Retention {
    /// Any adaptation of the episode came from the search strategy (the default: broader
    /// problem coverage, many cases whose solution is already stored).
    #[default]
    AnySearch,
    /// The final, trustworthy behavior itself came from the search strategy (few cases).
    FinalFromSearch,
}

/// What the time `t` of an evaluated pair counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum TimeUnit {
    /// Task seconds summed over the commands run with the behavior (the default).
    #[default]
    TaskSeconds,
    /// The number of commands run with the behavior.
    Commands,
}

impl Default for AdapterConfig {
    fn default() -> Self {
        Self {
            thresholds: Thresholds::default(),
            lambda: 0.95,
            reuse_cases: true,
            retriever: RetrieverKind::default(),
            search: SearchKind::default(),
            retention: Retention::default(),
            time_unit: TimeUnit::default(),
        }
    }
}

/// An adapter configuration that cannot be used. The reason is part of the message, so
/// it is not chained as a source too (or it would be shown twice).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ConfigError {
    /// Bad thresholds.
    #[error("thresholds: {0}")]
    Thresholds(ThresholdError),
    /// Bad lambda.
    #[error("lambda: {0}")]
    Lambda(LambdaError),
}

impl From<ThresholdError> for ConfigError {
    fn from(reason: ThresholdError) -> Self {
        Self::Thresholds(reason)
    }
}

impl From<LambdaError> for ConfigError {
    fn from(reason: LambdaError) -> Self {
        Self::Lambda(reason)
    }
}

impl AdapterConfig {
    /// Checks every field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.parameters().validate()
    }

    /// What the episode machine follows of this config: every field but the kinds of its
    /// parts.
    pub fn parameters(&self) -> Parameters {
        let Self {
            thresholds,
            lambda,
            reuse_cases,
            retriever: _,
            search: _,
            retention,
            time_unit,
        } = *self;
        Parameters {
            thresholds,
            lambda,
            reuse_cases,
            retention,
            time_unit,
        }
    }

    /// The case memory this config's retriever keeps over `cases` in `space`.
    pub fn memory(
        &self,
        space: Arc<BehaviorSpace>,
        cases: TrustCaseBase,
    ) -> Result<TrustMemory, ConfigError> {
        let retriever = self.retriever.build(space, self.lambda)?;
        Ok(TrustMemory::new(cases, retriever))
    }
}
