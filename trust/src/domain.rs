//! The plug-in contract between a task domain and the trust machinery.
//!
//! A domain has a behavior space, declares the causes of failure an operator may have and
//! the observations its robot perceives, and can run one command with a behavior in front
//! of an operator, returning the command's [`Judgement`]: the [`Outcome`](crate::Outcome)
//! the robot is told (with what it perceived) and, separately, the operator's true reason,
//! which only evaluation reads. The experiment runner needs nothing else, so a new robot
//! or task plugs in by implementing this trait.

use crate::{Cause, DeclaredCause, FeedbackChannel, Hint, Judgement};
use cbr_core::{Behavior, BehaviorSpace};
use rand::RngCore;
use std::sync::Arc;

/// A task domain: a behavior space and a way to run one command.
pub trait Domain: Send + Sync {
    /// The operator model that judges a run (e.g. preferences loaded from RON).
    type Operator: Send + Sync;

    /// The domain's name (e.g. `movement`).
    fn name(&self) -> &str;

    /// The behaviors the robot can adopt.
    fn space(&self) -> &Arc<BehaviorSpace>;

    /// The causes the truth of a [`Domain::run`] (and an operator's stated reason) may name
    /// (the experiment runner refuses any other, naming the domain, the cause and these).
    fn causes(&self) -> &[DeclaredCause];

    /// What the robot perceives itself, by name (same spelling rules as causes): bit `i` of
    /// an outcome's [`Observations`](crate::Observations) is `observations()[i]`. At most
    /// [`Observations::CAPACITY`](crate::Observations::CAPACITY); none by default.
    fn observations(&self) -> &[Cause] {
        &[]
    }

    /// Which observations hint at which causes the robot cannot perceive itself (what a
    /// robot's designer knows of its operators, the same for all of them), for the
    /// explanations' inferences ([`crate::explain`]); none by default.
    fn hints(&self) -> &[Hint] {
        &[]
    }

    /// How `operator` explains itself; the paper's silent operator by default. An
    /// experiment may override it for all its operators.
    fn feedback(&self, _operator: &Self::Operator) -> FeedbackChannel {
        FeedbackChannel::SILENT
    }

    /// Runs one command with `behavior` under `operator`, drawing all randomness from
    /// `rng`, and returns how it ended: what the robot is told and perceives (nothing
    /// stated: the runner applies the operator's feedback channel on a stream of its own)
    /// and the operator's true reason.
    fn run(
        &self,
        behavior: &Behavior,
        operator: &Self::Operator,
        rng: &mut dyn RngCore,
    ) -> Judgement;

    /// [`Domain::run`] under an operator whose `attention`, in `[0, 1]`, is the chance it
    /// notices a problem it would react to when attentive (1: the paper's operator, who
    /// notices everything it minds). A problem it overlooks lets the run go on, and is
    /// named in the judgement's [`Judgement::overlooked`] for evaluation. A domain whose
    /// operators never lose attention keeps this default, which ignores `attention`; one
    /// that overrides it must return exactly [`Domain::run`]'s judgement at attention 1.
    fn run_attending(
        &self,
        behavior: &Behavior,
        operator: &Self::Operator,
        attention: f64,
        rng: &mut dyn RngCore,
    ) -> Judgement {
        let _ = attention;
        self.run(behavior, operator, rng)
    }
}
