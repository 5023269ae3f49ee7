//! The simulation contract: what a task domain gives the laboratory.
//!
//! A domain has a behavior space, declares the causes of failure an operator may have and
//! the observations its robot perceives, and can run one command with a behavior in front
//! of an operator, returning the command's [`Judgement`]: the [`Outcome`](trust::Outcome) the robot is
//! told (with what it perceived) and, separately, the operator's true reason, which only
//! evaluation reads. The experiment runner needs nothing else, so a new robot or task
//! plugs in by implementing [`Domain`]. What a domain may model beyond that is a trait
//! each, here too: its operators' attention ([`Attentive`]), goal changes
//! ([`GoalChanging`]) and its robot's own competence ([`SelfJudging`]), which the domain
//! answers for through [`Domain::attentive`] and its siblings; how a plan holds the one it
//! needs is [`crate::contract::capability`].
//!
//! The contract lives here, with the runner, and not in `trust`, the crate a robot
//! embeds: `trust` does not depend on this crate, so nothing in it can name a
//! [`Judgement`] or its truth. What `trust` sees of a domain is its [`Vocabulary`] (the
//! causes, observations and hints a robot also knows), built by [`vocabulary`].

use crate::contract::feedback::FeedbackChannel;
use crate::contract::judgement::Judgement;
use crate::contract::operator::SimulatedOperator;
use cbr_core::{Behavior, BehaviorSpace, Context, ContextSpace};
use rand::RngCore;
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
    fn run(
        &self,
        behavior: &Behavior,
        operator: &Self::Operator,
        rng: &mut dyn RngCore,
    ) -> Judgement;

    /// This domain as one that models its operators' attention ([`Attentive`]): a domain
    /// that implements it answers `Some(self)`. `None` by default.
    fn attentive(&self) -> Option<&dyn Attentive<Operator = Self::Operator>> {
        None
    }

    /// This domain as one that models goal changes ([`GoalChanging`]): a domain that
    /// implements it answers `Some(self)`. `None` by default.
    fn goal_changing(&self) -> Option<&dyn GoalChanging<Operator = Self::Operator>> {
        None
    }

    /// This domain as one whose robot judges its own competence ([`SelfJudging`]): a
    /// domain that implements it answers `Some(self)`. `None` by default.
    fn self_judging(&self) -> Option<&dyn SelfJudging<Operator = Self::Operator>> {
        None
    }
}

/// A domain whose operators may overlook what they would react to when attentive.
pub trait Attentive: Domain {
    /// [`Domain::run`] under an operator whose `attention`, in `[0, 1]`, is the chance it
    /// notices a problem it would react to when attentive (1: the paper's operator, who
    /// notices everything it minds). A problem it overlooks lets the run go on, and is
    /// named in the judgement's [`Judgement::overlooked`] for evaluation. Only the domain
    /// knows which of its reactions an operator can overlook and how the run goes on past
    /// one. At attention 1 this is exactly [`Domain::run`]'s judgement, draw for draw.
    fn run_attending(
        &self,
        behavior: &Behavior,
        operator: &Self::Operator,
        attention: f64,
        rng: &mut dyn RngCore,
    ) -> Judgement;
}

/// A domain whose operators' goals may change during a command (a threat appears, the
/// operator sends the robot elsewhere).
pub trait GoalChanging: Domain {
    /// The command at `attention` ([`Attentive::run_attending`]; 1 for a domain that does
    /// not model attention) when the operator's goals change `at_s` seconds into it: a
    /// command that has not ended by then is interrupted then, for that reason and not the
    /// behavior's ([`Judgement::redirected`]), with what the robot perceived until then. A
    /// command that ends first is judged as if nothing had changed, draw for draw.
    fn run_redirected(
        &self,
        behavior: &Behavior,
        operator: &Self::Operator,
        attention: f64,
        at_s: f64,
        rng: &mut dyn RngCore,
    ) -> Judgement;
}

/// A domain whose robot judges its own competence ([`trust::competence`]) and whose
/// simulator knows the truth to measure that judgement against.
pub trait SelfJudging: Domain {
    /// The ways a command can fall short that the robot judges itself, each seen (one of
    /// [`Domain::observations`]) or unseen.
    fn competence_parts(&self) -> &[CompetencePart];

    /// What the robot's own models predict of `behavior`: per part of
    /// [`SelfJudging::competence_parts`], the chance a command falls short that way,
    /// `None` where no model says. Only what the robot knows may enter (its sensors'
    /// tables, its settings, its briefing), never the operator.
    fn predict_competence(&self, behavior: &Behavior) -> Vec<Option<f64>>;

    /// For evaluation only, as the truth: one whole command of `behavior` with nobody to
    /// stop it, drawing all randomness from `rng`, and for each part (in their order)
    /// whether it fell short in it, or `None` where the part does not apply to this
    /// command (a patrol that never set out passed no object).
    fn competence_truth(&self, behavior: &Behavior, rng: &mut dyn RngCore) -> Vec<Option<bool>>;
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
