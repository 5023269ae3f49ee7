//! The simulation contract: what a task domain gives the laboratory.
//!
//! A domain has a behavior space, declares the causes of failure an operator may have and
//! the observations its robot perceives, and can run one command with a behavior in front
//! of an operator, returning the command's [`Judgement`]: the [`Outcome`](trust::Outcome) the robot is
//! told (with what it perceived) and, separately, the operator's true reason, which only
//! evaluation reads. The experiment runner needs nothing else, so a new robot or task
//! plugs in by implementing [`Domain`]. Missions whose operators grow complacent need one
//! more hook, [`Domain::run_attending`]: a domain that keeps its default does not model
//! attention, and [`check_attention`] says so before such a mission runs.
//!
//! The contract lives here, with the runner, and not in `trust`, the crate a robot
//! embeds: `trust` does not depend on this crate, so nothing in it can name a
//! [`Judgement`] or its truth. What `trust` sees of a domain is its [`Vocabulary`] (the
//! causes, observations and hints a robot also knows), built by [`vocabulary`].

use crate::contract::feedback::FeedbackChannel;
use crate::contract::judgement::Judgement;
use crate::contract::operator::SimulatedOperator;
use cbr_core::{Behavior, BehaviorSpace, Context, ContextSpace};
use rand::{RngCore, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;
use trust::{Cause, CompetencePart, DeclaredCause, Hint, Vocabulary};

/// The context space of a domain that declares none.
static NO_CONTEXTS: ContextSpace = ContextSpace::NONE;

/// A task domain: a behavior space and a way to run one command.
pub trait Domain: Send + Sync {
    /// The operator model that judges a run (e.g. preferences loaded from RON, declared
    /// with [`standard_operator!`](crate::standard_operator)).
    type Operator: SimulatedOperator + Send + Sync;

    /// The domain's name (e.g. `movement`).
    fn name(&self) -> &str;

    /// The behaviors the robot can adopt.
    fn space(&self) -> &Arc<BehaviorSpace>;

    /// The causes the truth of a [`Domain::run`] (and an operator's stated reason) may name
    /// (the experiment runner refuses any other, naming the domain, the cause and these).
    fn causes(&self) -> &[DeclaredCause];

    /// What the robot perceives itself, by name (same spelling rules as causes): bit `i` of
    /// an outcome's [`Observations`](trust::Observations) is `observations()[i]`. At most
    /// [`Observations::CAPACITY`](trust::Observations::CAPACITY); none by default.
    fn observations(&self) -> &[Cause] {
        &[]
    }

    /// The context variables the robot knows (what it carries, the situation it was sent
    /// into: [`cbr_core::context`]), which cases are matched by; none by default.
    fn contexts(&self) -> &ContextSpace {
        &NO_CONTEXTS
    }

    /// `operator` as it judges in `context` (its preferences there), or `None` when it
    /// judges every context alike (the default: a domain whose operators state no
    /// preferences by context). A simulated command in a context is judged by the operator
    /// this returns.
    fn operator_in_context(
        &self,
        operator: &Self::Operator,
        context: &Context,
    ) -> Option<Self::Operator> {
        let _ = (operator, context);
        None
    }

    /// The names an operator may state preferences in up front ([`cbr_core::statement`]:
    /// for a robot, "hurry" or "avoid bumps"), each naming something the domain's
    /// operators may or may not mind; none by default.
    fn statements(&self) -> &[String] {
        &[]
    }

    /// For simulation, the truth of what `operator` would state: for each of
    /// [`Domain::statements`], in order, whether it minds it. An experiment with `stated`
    /// ([`crate::contract::stating`]) draws what the robot is told from it. Nothing by default.
    fn true_statements(&self, operator: &Self::Operator) -> Vec<cbr_core::Statement> {
        let _ = operator;
        Vec::new()
    }

    /// Which observations hint at which causes the robot cannot perceive itself (what a
    /// robot's designer knows of its operators, the same for all of them), for the
    /// explanations' inferences ([`trust::explain`]); none by default.
    fn hints(&self) -> &[Hint] {
        &[]
    }

    /// How `operator` explains itself: by default what the operator says of itself
    /// ([`SimulatedOperator::feedback`], its file's `feedback` for a standard operator; the
    /// paper's silent operator otherwise). An experiment may override it for all its
    /// operators.
    fn feedback(&self, operator: &Self::Operator) -> FeedbackChannel {
        operator.feedback()
    }

    /// Runs one command with `behavior` under `operator`, drawing all randomness from
    /// `rng`, and returns how it ended: what the robot is told and perceives (nothing
    /// stated: the runner applies the operator's feedback channel on a stream of its own)
    /// and the operator's true reason.
    ///
    /// By default, [`Domain::run_attending`] at attention 1 (the paper's attentive
    /// operator), so a domain that models attention writes its command once. A domain
    /// must override one of the two: one that overrides neither panics here, naming
    /// itself, on its first command (the domain kit, `lab::testing::check_domain`,
    /// runs one first).
    fn run(
        &self,
        behavior: &Behavior,
        operator: &Self::Operator,
        rng: &mut dyn RngCore,
    ) -> Judgement {
        self.run_attending(behavior, operator, 1.0, rng)
            .unwrap_or_else(|| {
                panic!(
                    "domain `{}` overrides neither `Domain::run` nor `Domain::run_attending`: it cannot run a command",
                    self.name()
                )
            })
    }

    /// [`Domain::run`] under an operator whose `attention`, in `[0, 1]`, is the chance it
    /// notices a problem it would react to when attentive (1: the paper's operator, who
    /// notices everything it minds). A problem it overlooks lets the run go on, and is
    /// named in the judgement's [`Judgement::overlooked`] for evaluation.
    ///
    /// `None`, the default, says the domain does not model its operators' attention: only
    /// the domain knows which of its reactions an operator can overlook and how the run
    /// goes on past one, so no rule can stand in for it. A mission plan with operators who
    /// grow complacent ([`crate::mission::Complacency`]) is refused on such a domain
    /// before anything runs ([`check_attention`]). A domain that models attention
    /// overrides this, answers `Some` for every behavior, operator and attention, and at
    /// attention 1 returns exactly [`Domain::run`]'s judgement, draw for draw.
    fn run_attending(
        &self,
        behavior: &Behavior,
        operator: &Self::Operator,
        attention: f64,
        rng: &mut dyn RngCore,
    ) -> Option<Judgement> {
        let _ = (behavior, operator, attention, rng);
        None
    }

    /// [`Domain::run_attending`] (at `attention`) when the operator's goals change
    /// `at_s` seconds into the command (a threat appears, it sends the robot elsewhere):
    /// a command that has not ended by then is interrupted then, for that reason and not
    /// the behavior's ([`Judgement::redirected`]), with what the robot perceived until
    /// then. A command that ends first is judged as if nothing had changed.
    ///
    /// `None`, the default, says the domain does not model goal changes: only the domain
    /// knows what its robot perceived until a moment, and how an operator weighs an
    /// interruption the robot cannot attribute. A plan with goal changes
    /// ([`crate::experiment::goal_change::GoalChanges`]) is refused on such a domain before anything
    /// runs ([`check_goal_changes`]). A domain that models them overrides this, answers
    /// `Some` for every behavior, operator, attention and moment, and at an `at_s` past
    /// the command's end returns exactly [`Domain::run_attending`]'s judgement, draw for
    /// draw.
    fn run_redirected(
        &self,
        behavior: &Behavior,
        operator: &Self::Operator,
        attention: f64,
        at_s: f64,
        rng: &mut dyn RngCore,
    ) -> Option<Judgement> {
        let _ = (behavior, operator, attention, at_s, rng);
        None
    }

    /// The ways a command can fall short that the robot judges itself, each seen (one of
    /// [`Domain::observations`]) or unseen ([`trust::competence`]); none by default.
    fn competence_parts(&self) -> &[CompetencePart] {
        &[]
    }

    /// What the robot's own models predict of `behavior`: per part of
    /// [`Domain::competence_parts`], the chance a command falls short that way, `None`
    /// where no model says. Only what the robot knows may enter (its sensors' tables, its
    /// settings, its briefing), never the operator. Nothing predicted by default.
    fn predict_competence(&self, behavior: &Behavior) -> Vec<Option<f64>> {
        let _ = behavior;
        vec![None; self.competence_parts().len()]
    }

    /// For evaluation only, as the truth: one whole command of `behavior` with nobody to
    /// stop it, drawing all randomness from `rng`, and for each part of
    /// [`Domain::competence_parts`] (in their order) whether it fell short in it, or
    /// `None` where the part does not apply to this command (a patrol that never set out
    /// passed no object). `None`, the default: the domain gives no truth to measure the
    /// robot's competence against ([`crate::reference::competence_truth::measure`] refuses it).
    fn competence_truth(
        &self,
        behavior: &Behavior,
        rng: &mut dyn RngCore,
    ) -> Option<Vec<Option<bool>>> {
        let _ = (behavior, rng);
        None
    }
}

/// A domain asked to run operators who may overlook problems, which keeps the default
/// [`Domain::run_attending`]: its operators notice everything they mind, so a
/// complacent operator could not be simulated.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "domain `{domain}` does not model its operators' attention: it keeps the default `Domain::run_attending`, so operators who grow complacent would still notice everything and alerts could change nothing; a plan with `complacency` needs a domain that overrides `Domain::run_attending` (docs/plugin-guide.md)"
)]
pub struct AttentionNotModelled {
    /// The domain's name.
    pub domain: String,
}

/// Whether `domain` models its operators' attention: [`Domain::run_attending`] is asked
/// once per operator of `operators` (a behavior of the space at attention 1, on a stream
/// of its own, so no stream of a run is touched), and must answer for each.
pub fn check_attention<D: Domain + ?Sized>(
    domain: &D,
    operators: &[(String, D::Operator)],
) -> Result<(), AttentionNotModelled> {
    let answers = every_operator_answers(domain, operators, |behavior, operator, probe| {
        domain
            .run_attending(behavior, operator, 1.0, probe)
            .is_some()
    });
    answers.then_some(()).ok_or_else(|| AttentionNotModelled {
        domain: domain.name().to_owned(),
    })
}

/// Whether `hook` answers for every one of `operators` on the space's first behavior,
/// asked once each on one probe stream: how a plan tells whether its domain overrides an
/// optional hook (a domain overrides it for every run or none).
fn every_operator_answers<D: Domain + ?Sized>(
    domain: &D,
    operators: &[(String, D::Operator)],
    hook: impl Fn(&Behavior, &D::Operator, &mut ChaCha8Rng) -> bool,
) -> bool {
    let behavior = domain.space().unrank(0);
    let mut probe = ChaCha8Rng::seed_from_u64(0);
    operators
        .iter()
        .all(|(_, operator)| hook(&behavior, operator, &mut probe))
}

/// A domain asked to run operators whose goals change, which keeps the default
/// [`Domain::run_redirected`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "domain `{domain}` does not model goal changes: it keeps the default `Domain::run_redirected`, so no command could be cut by one; `goal_changes` needs a domain that overrides `Domain::run_redirected` (docs/plugin-guide.md)"
)]
pub struct GoalChangesNotModelled {
    /// The domain's name.
    pub domain: String,
}

/// Whether `domain` models goal changes: [`Domain::run_redirected`] is asked once per
/// operator of `operators` (a behavior of the space, its goals changing at once, on a
/// stream of its own, so no stream of a run is touched), and must answer for each.
pub fn check_goal_changes<D: Domain + ?Sized>(
    domain: &D,
    operators: &[(String, D::Operator)],
) -> Result<(), GoalChangesNotModelled> {
    let answers = every_operator_answers(domain, operators, |behavior, operator, probe| {
        domain
            .run_redirected(behavior, operator, 1.0, 0.0, probe)
            .is_some()
    });
    answers.then_some(()).ok_or_else(|| GoalChangesNotModelled {
        domain: domain.name().to_owned(),
    })
}

/// The names an adaptation explains itself in: `domain`'s declared causes, its
/// observations (in bit order) and its hints.
pub fn vocabulary<D: Domain + ?Sized>(domain: &D) -> Vocabulary {
    Vocabulary {
        causes: domain.causes().iter().map(|d| d.name).collect(),
        observations: domain.observations().to_vec(),
        hints: domain.hints().to_vec(),
    }
}
