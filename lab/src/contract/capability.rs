//! What a domain may model beyond one command in front of the paper's attentive operator,
//! each a trait of its own beside [`Domain`] (in [`crate::contract::domain`]): operators
//! whose attention lapses ([`Attentive`]), goals that change during a command
//! ([`GoalChanging`]), and a robot that judges its own competence against a truth the
//! simulator knows ([`SelfJudging`]); and how a plan holds the capability it needs.
//!
//! A domain that models one implements its trait and answers the matching query of
//! [`Domain`] ([`Domain::attentive`], [`Domain::goal_changing`],
//! [`Domain::self_judging`]) with itself; the queries answer `None` by default.
//!
//! A plan setting that needs a capability holds it beside the setting ([`Needing`]): the
//! capability is a reference to the domain as the trait, which only a domain whose type
//! implements the trait can give. Where a plan is written in Rust, `&domain` coerces to
//! it, so a plan that needs a capability its domain lacks does not compile; where a plan
//! is read from a file, the query is asked once, where it enters, and a domain that lacks
//! the capability is refused there with its name and the trait ([`check_attention`],
//! [`check_goal_changes`], [`check_self_judging`]).

use crate::contract::domain::{Attentive, Domain, GoalChanging, SelfJudging};

/// A plan with operators who grow complacent, over a domain that does not implement
/// [`Attentive`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "domain `{domain}` does not model its operators' attention: it does not implement `Attentive` (its `Domain::attentive` answers None), so operators who grow complacent would still notice everything and alerts could change nothing; a plan with `complacency` needs a domain that models attention (docs/plugin-guide.md)"
)]
pub struct AttentionNotModelled {
    /// The domain's name.
    pub domain: String,
}

/// A plan with goal changes, over a domain that does not implement [`GoalChanging`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "domain `{domain}` does not model goal changes: it does not implement `GoalChanging` (its `Domain::goal_changing` answers None), so no command could be cut by one; `goal_changes` needs a domain that models them (docs/plugin-guide.md)"
)]
pub struct GoalChangesNotModelled {
    /// The domain's name.
    pub domain: String,
}

/// `domain` as a domain that models its operators' attention, or why not: what a plan
/// read from a file asks once, where it enters.
pub fn check_attention<D: Domain + ?Sized>(
    domain: &D,
) -> Result<&dyn Attentive<Operator = D::Operator>, AttentionNotModelled> {
    domain.attentive().ok_or_else(|| AttentionNotModelled {
        domain: domain.name().to_owned(),
    })
}

/// `domain` as a domain that models goal changes, or why not.
pub fn check_goal_changes<D: Domain + ?Sized>(
    domain: &D,
) -> Result<&dyn GoalChanging<Operator = D::Operator>, GoalChangesNotModelled> {
    domain
        .goal_changing()
        .ok_or_else(|| GoalChangesNotModelled {
            domain: domain.name().to_owned(),
        })
}

/// `domain` as a domain whose robot judges its own competence, or why not.
pub fn check_self_judging<D: Domain + ?Sized>(
    domain: &D,
) -> Result<&dyn SelfJudging<Operator = D::Operator>, SelfJudgingNotModelled> {
    domain.self_judging().ok_or_else(|| SelfJudgingNotModelled {
        domain: domain.name().to_owned(),
    })
}

/// A plan with a competence standard, over a domain that does not implement
/// [`SelfJudging`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "domain `{domain}` does not model its robot's competence: it does not implement `SelfJudging` (its `Domain::self_judging` answers None), so there are no parts to judge and no truth to measure them against (docs/plugin-guide.md)"
)]
pub struct SelfJudgingNotModelled {
    /// The domain's name.
    pub domain: String,
}

/// A plan's setting with the capability of the plan's domain it needs (`C`, one of the
/// traits above as `dyn`): see the module's documentation for how one is had. Written in
/// Rust, [`Needing::attentive`] and its siblings take the domain as its own type, so the
/// compiler refuses one whose type lacks the trait:
///
/// ```compile_fail
/// # use lab::{Attentive, Domain, Judgement};
/// # use lab::contract::capability::Needing;
/// # use lab::mission::{Complacency, ComplacencyOn};
/// # use cbr_core::{Behavior, BehaviorSpace};
/// # use std::sync::Arc;
/// # use trust::DeclaredCause;
/// /// A domain that does not model attention.
/// struct Plain(Arc<BehaviorSpace>);
/// impl Domain for Plain {
///     type Operator = ();
///     fn name(&self) -> &str { "plain" }
///     fn space(&self) -> &Arc<BehaviorSpace> { &self.0 }
///     fn causes(&self) -> &[DeclaredCause] { &[] }
///     fn run(&self, _: &Behavior, _: &(), _: &mut dyn rand::RngCore) -> Judgement {
///         Judgement::completed(1.0, 1.0)
///     }
/// }
/// fn complacent(domain: &Plain, model: Complacency) -> ComplacencyOn<'_, ()> {
///     // Refused by the compiler: `Plain` does not implement `Attentive`.
///     ComplacencyOn::attentive(model, domain)
/// }
/// ```
pub struct Needing<'a, T, C: ?Sized> {
    /// The setting.
    pub setting: T,
    /// The plan's domain as the capability the setting needs.
    pub capability: &'a C,
}

impl<'a, T, O> Needing<'a, T, dyn Attentive<Operator = O> + 'a> {
    /// `setting` with `domain`, whose type models attention.
    pub fn attentive<D: Attentive<Operator = O>>(setting: T, domain: &'a D) -> Self {
        Self {
            setting,
            capability: domain,
        }
    }
}

impl<'a, T, O> Needing<'a, T, dyn GoalChanging<Operator = O> + 'a> {
    /// `setting` with `domain`, whose type models goal changes.
    pub fn goal_changing<D: GoalChanging<Operator = O>>(setting: T, domain: &'a D) -> Self {
        Self {
            setting,
            capability: domain,
        }
    }
}

impl<'a, T, O> Needing<'a, T, dyn SelfJudging<Operator = O> + 'a> {
    /// `setting` with `domain`, whose type's robot judges its own competence.
    pub fn self_judging<D: SelfJudging<Operator = O>>(setting: T, domain: &'a D) -> Self {
        Self {
            setting,
            capability: domain,
        }
    }
}

impl<T: Clone, C: ?Sized> Clone for Needing<'_, T, C> {
    fn clone(&self) -> Self {
        Self {
            setting: self.setting.clone(),
            capability: self.capability,
        }
    }
}

impl<T: Copy, C: ?Sized> Copy for Needing<'_, T, C> {}

impl<T: std::fmt::Debug, C: ?Sized> std::fmt::Debug for Needing<'_, T, C> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Needing")
            .field("setting", &self.setting)
            .finish_non_exhaustive()
    }
}
