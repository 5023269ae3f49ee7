//! What an experiment is: its plan ([`ExperimentPlan`]: the domain, operators, arms,
//! trials and conditions), which operator judges each trial ([`OperatorChoice`]), why a
//! plan cannot run ([`PlanError`]), and the fresh adapter each arm starts from.

use crate::contract::stating::Stating;
use crate::experiment::arm::Arm;
use crate::reference::known_operator::KnownLimitError;
use crate::{Domain, FeedbackChannel, GoalChangesOn, TrialContexts};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;
use trust::{
    AdapterConfig, ConfigError, SetSimilarity, TrustAdapter, TrustMemory, UndeclaredCause,
};

/// Which operator judges each trial.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OperatorChoice {
    /// Always the operator at this index.
    Fixed(usize),
    /// One drawn uniformly per trial.
    Random,
}

/// One experiment to run.
pub struct ExperimentPlan<'a, D: Domain> {
    /// Name used in reports, e.g. `movement/speed-focused`.
    pub name: String,
    /// The domain and the operators available in it, with their names.
    pub domain: &'a D,
    /// The operators, by name.
    pub operators: &'a [(String, D::Operator)],
    /// Which operator judges each trial.
    pub choice: OperatorChoice,
    /// Number of trials per arm.
    pub trials: u32,
    /// The adapter every arm starts from: its thresholds, `lambda`, retention and unit of
    /// time are every arm's; whether cases are reused, the search strategy and the
    /// retriever are each arm's own, and replace the config's.
    pub adapter: AdapterConfig,
    /// The arms compared, paired trial by trial; every other arm is tested against the
    /// first.
    pub arms: Vec<Arm>,
    /// Commands after which a trial is abandoned as unfinished (a guard against operators
    /// whose outcomes never reach a threshold).
    pub max_commands: u64,
    /// How every operator of the plan explains itself, overriding each operator's own
    /// channel ([`Domain::feedback`]); `None` keeps the operators' own.
    pub feedback: Option<FeedbackChannel>,
    /// How often the operators' goals change ([`crate::experiment::goal_change`]), with the
    /// domain as one that models them; `None`, the paper's assumption: never.
    pub goal_changes: Option<GoalChangesOn<'a, D::Operator>>,
    /// The contexts the trials run in, and whether the robot is told them
    /// ([`crate::experiment::trial_contexts`]); `None`: every trial in the default context, as the paper's.
    pub contexts: Option<TrialContexts>,
    /// What the operators state up front ([`crate::contract::stating`]); `None`, the paper's
    /// operators: nothing.
    pub stated: Option<Stating>,
}

/// Why experiments cannot be run.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PlanError {
    /// Thresholds or lambda are unusable.
    #[error("{plan}: {reason}")]
    Config {
        /// The plan's name.
        plan: String,
        /// What is wrong.
        reason: ConfigError,
    },
    /// A plan has no arm.
    #[error("{plan}: no arm to run")]
    NoArms {
        /// The plan's name.
        plan: String,
    },
    /// The domain reported a judgement whose true reason it does not declare.
    #[error("{plan}: domain `{domain}` reported an outcome whose {reason}")]
    UndeclaredCause {
        /// The plan's name.
        plan: String,
        /// The domain's name.
        domain: String,
        /// The cause and the declared ones (boxed: a rare error should not make every
        /// result that may carry one larger).
        reason: Box<UndeclaredCause>,
    },
    /// Two arms of a plan share a name.
    #[error("{plan}: two arms are named `{arm}`")]
    DuplicateArm {
        /// The plan's name.
        plan: String,
        /// The name.
        arm: String,
    },
    /// An arm's searcher broke its contract: it proposed a behavior outside the space, or
    /// one the episode had already evaluated.
    #[error(
        "{plan}: the search of arm `{arm}` proposed {behavior}, which {problem}; a searcher proposes behaviors of the space that the episode has not evaluated (trust::testing::check_searcher checks a searcher for this)"
    )]
    Searcher {
        /// The plan's name.
        plan: String,
        /// The arm's name.
        arm: String,
        /// The behavior, in real units (as value indices when outside the space).
        behavior: String,
        /// What is wrong with it.
        problem: &'static str,
    },
    /// A mission plan's context switches are unusable.
    #[error("{plan}: {reason}")]
    Contexts {
        /// The plan's name.
        plan: String,
        /// Why.
        reason: String,
    },
    /// A plan's operators state preferences up front in a domain that declares no names
    /// to state them in ([`Domain::statements`]).
    #[error(
        "{plan}: domain `{domain}` declares no statements (Domain::statements), so its operators have nothing to state: remove `stated`"
    )]
    NoStatements {
        /// The plan's name.
        plan: String,
        /// The domain's name.
        domain: String,
    },
    /// A plan sets a competence standard its domain cannot judge.
    #[error("{plan}: {reason}")]
    Competence {
        /// The plan's name.
        plan: String,
        /// Why.
        reason: String,
    },
    /// A mission plan's oracle could not learn an operator's landscape
    /// ([`crate::mission::oracle`]).
    #[error("{plan}: the mission oracle, operator `{operator}`: {reason}")]
    Oracle {
        /// The plan's name.
        plan: String,
        /// The operator's name.
        operator: String,
        /// Why its known-operator estimate failed.
        reason: KnownLimitError,
    },
    /// A stop was requested ([`crate::interrupt`]) before every trial had run.
    #[error(transparent)]
    Interrupted(#[from] crate::Interrupted),
}

impl<D: Domain> ExperimentPlan<'_, D> {
    pub(crate) fn validate(&self) -> Result<(), PlanError> {
        let config = |reason: ConfigError| PlanError::Config {
            plan: self.name.clone(),
            reason,
        };
        self.adapter.validate().map_err(config)?;
        if self.arms.is_empty() {
            return Err(PlanError::NoArms {
                plan: self.name.clone(),
            });
        }
        for (i, arm) in self.arms.iter().enumerate() {
            if self.arms[..i].iter().any(|a| a.name() == arm.name()) {
                return Err(PlanError::DuplicateArm {
                    plan: self.name.clone(),
                    arm: arm.name().to_owned(),
                });
            }
        }
        if self.stated.is_some() && self.domain.statements().is_empty() {
            return Err(PlanError::NoStatements {
                plan: self.name.clone(),
                domain: self.domain.name().to_owned(),
            });
        }
        Ok(())
    }

    /// Whether no operator of the plan ever states a reason: its channel, or every
    /// operator's own, is silent, so explanations learn nothing across episodes.
    pub(crate) fn never_told(&self) -> bool {
        match self.feedback {
            Some(channel) => channel.is_silent(),
            None => self
                .operators
                .iter()
                .all(|(_, operator)| self.domain.feedback(operator).is_silent()),
        }
    }

    /// A fresh adapter for `arm`, from its starting cases.
    pub(crate) fn adapter(&self, arm: &Arm) -> Result<TrustAdapter, PlanError> {
        fresh_adapter(self.domain, &self.adapter, arm).map_err(|reason| PlanError::Config {
            plan: self.name.clone(),
            reason,
        })
    }
}

/// A fresh adapter for `arm` over `domain`'s space, from the arm's starting cases, its
/// own case reuse, retriever and searcher and the rest of `adapter`, explaining itself in
/// the domain's terms. Its search stream is reseeded before every episode.
pub(crate) fn fresh_adapter<D: Domain>(
    domain: &D,
    adapter: &AdapterConfig,
    arm: &Arm,
) -> Result<TrustAdapter, ConfigError> {
    let space = domain.space();
    let measure = SetSimilarity::of_domain(
        space.clone(),
        adapter.lambda,
        Arc::new(domain.contexts().clone()),
    )?;
    let retriever = arm.build_retriever(measure);
    let cases = arm.starting_cases().cloned().unwrap_or_default();
    let parameters = AdapterConfig {
        reuse_cases: arm.reuses_cases(),
        ..*adapter
    }
    .parameters();
    Ok(TrustAdapter::with_parts(
        space.clone(),
        parameters,
        TrustMemory::new(cases, retriever),
        arm.build_searcher(space),
        ChaCha8Rng::seed_from_u64(0),
    )?
    .with_vocabulary(crate::vocabulary(domain)))
}
