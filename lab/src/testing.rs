//! Testing a domain and testing with one (feature `testing`).
//!
//! - [`check_domain`], the domain conformance kit: it states the rules of the simulation
//!   contract ([`Domain`]) that a test can check, and checks them on a domain and its
//!   operators.
//! - [`ToyDomain`]: a small domain whose runs follow a rule the test writes (a grid of
//!   numeric components, declared causes and observations), for tests of the machinery
//!   that runs domains: one type instead of a domain written out in every test file.
//!
//! A domain author calls `lab::testing::check_domain(&domain, &operators)` from a test of
//! the domain's crate, with the lab's `testing` feature (a plug-in gets it through
//! `trustcbr`'s `testing` feature). The UGV's movement and patrol domains and the warehouse example pass it
//! (`domains/tests/integration/conformance.rs`, `examples/warehouse/tests/model.rs`).

use crate::contract::domain::{Attentive, Domain, GoalChanging};
use crate::contract::judgement::Judgement;
use crate::contract::operator::SimulatedOperator;
use cbr_core::{Behavior, BehaviorSpace, Context, ContextSpace, NamedComponent};
use rand::{RngCore, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;
use trust::{Cause, DeclaredCause, Hint, Observations, OutcomeKind};

/// Behaviors drawn per operator.
pub const BEHAVIORS: u64 = 48;

/// A rule of the simulation contract a domain breaks, with the case that shows it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("domain `{domain}` breaks the contract: {rule}{}", case.as_deref().map(|c| format!(" ({c})")).unwrap_or_default())]
pub struct Violation {
    /// The domain's name.
    pub domain: String,
    /// The rule broken, as a sentence.
    pub rule: String,
    /// The operator, behavior and seed that show it, when one does.
    pub case: Option<String>,
}

/// Checks `domain` against the rules of [`Domain`] with each of `operators` (name and
/// model), panicking with the first rule broken ([`try_check_domain`] returns it):
///
/// - its declared causes have distinct names, and so have its observations, at most
///   [`Observations::CAPACITY`] of them;
/// - every hint names a declared observation and a declared cause;
/// - every operator's feedback channel is usable;
/// - a run is a function of its random stream: the same seed gives the same judgement;
/// - a run's outcome is valid (weight and duration finite and at least 0, a confidence in
///   `[0, 1]`), names no observation beyond those declared and states nothing (stating is
///   the feedback channel's);
/// - a completion has no true reason, and every true reason is a declared cause;
/// - an attentive run overlooks nothing;
/// - a domain that models attention ([`Domain::attentive`]) runs, at attention 1,
///   exactly [`Domain::run`], draw for draw, and whatever an inattentive run overlooks is
///   a declared cause;
/// - a domain that models goal changes ([`Domain::goal_changing`]) runs exactly
///   [`Domain::run`] when the goals change after the command's end, and cuts a command
///   halfway through when they change then.
///
/// # Panics
/// With the rule broken and the case that shows it.
pub fn check_domain<D: Domain>(domain: &D, operators: &[(String, D::Operator)]) {
    if let Err(violation) = try_check_domain(domain, operators) {
        panic!("{violation}");
    }
}

/// [`check_domain`], returning the first rule broken instead of panicking.
pub fn try_check_domain<D: Domain>(
    domain: &D,
    operators: &[(String, D::Operator)],
) -> Result<(), Violation> {
    let broken = |rule: String, case: Option<String>| Violation {
        domain: domain.name().to_owned(),
        rule,
        case,
    };
    let causes: Vec<Cause> = domain.causes().iter().map(|d| d.name).collect();
    if let Some(twice) = first_repeated(&causes) {
        return Err(broken(format!("cause `{twice}` is declared twice"), None));
    }
    let observations = domain.observations();
    if let Some(twice) = first_repeated(observations) {
        return Err(broken(
            format!("observation `{twice}` is declared twice"),
            None,
        ));
    }
    if observations.len() > Observations::CAPACITY {
        return Err(broken(
            format!(
                "{} observations are declared, more than the {} an outcome can carry",
                observations.len(),
                Observations::CAPACITY
            ),
            None,
        ));
    }
    for hint in domain.hints() {
        if !observations.contains(&hint.observation) {
            return Err(broken(
                format!(
                    "a hint names observation `{}`, which is not declared",
                    hint.observation
                ),
                None,
            ));
        }
        if !causes.contains(&hint.suggests) {
            return Err(broken(
                format!(
                    "a hint suggests cause `{}`, which is not declared",
                    hint.suggests
                ),
                None,
            ));
        }
    }
    // Bits at and above the number of declared observations name none.
    let undeclared_bits = u32::MAX.checked_shl(observations.len() as u32).unwrap_or(0);
    let space = domain.space();
    for (name, operator) in operators {
        let channel = domain.feedback(operator);
        if crate::FeedbackChannel::new(channel.explains, channel.wrong).is_err() {
            return Err(broken(
                format!("operator `{name}`'s feedback channel is not usable"),
                None,
            ));
        }
        let mut draws = ChaCha8Rng::seed_from_u64(0);
        for seed in 0..BEHAVIORS {
            let behavior = space.draw(&mut draws);
            let case = || Some(describe(name, space, &behavior, seed));
            let rng = || ChaCha8Rng::seed_from_u64(seed);
            let run = || domain.run(&behavior, operator, &mut rng());
            let attending = |attentive: &dyn Attentive<Operator = D::Operator>, attention| {
                attentive.run_attending(&behavior, operator, attention, &mut rng())
            };
            let judgement = run();
            if run() != judgement {
                return Err(broken(
                    "two runs on the same random stream differ: every draw must come from the generator passed to `run`".to_owned(),
                    case(),
                ));
            }
            check_judgement(&judgement, &causes, undeclared_bits)
                .map_err(|rule| broken(rule, case()))?;
            if judgement.overlooked.is_some() {
                return Err(broken(
                    "an attentive run (`run`) overlooked a problem".to_owned(),
                    case(),
                ));
            }
            if let Some(changing) = domain.goal_changing() {
                check_goal_change(changing, operator, &behavior, seed, &judgement)
                    .map_err(|rule| broken(rule, case()))?;
            }
            let Some(modelled) = domain.attentive() else {
                continue;
            };
            let (attentive, inattentive) = (attending(modelled, 1.0), attending(modelled, 0.0));
            if attentive != judgement {
                return Err(broken(
                    "`run_attending` at attention 1 differs from `run` on the same stream: at full attention it must be exactly `run`".to_owned(),
                    case(),
                ));
            }
            check_judgement(&inattentive, &causes, undeclared_bits)
                .map_err(|rule| broken(rule, case()))?;
            if let Some(cause) = inattentive.overlooked.filter(|c| !causes.contains(c)) {
                return Err(broken(
                    format!(
                        "an inattentive run overlooked `{cause}`, which is not a declared cause"
                    ),
                    case(),
                ));
            }
        }
    }
    Ok(())
}

/// The rules of [`GoalChanging::run_redirected`], as a sentence for the first one
/// broken: a goal change after the command's end changes nothing (`judgement` is
/// [`Domain::run`]'s on the same stream), and one halfway through a command that lasts
/// cuts it there, as an interruption with no true reason.
fn check_goal_change<O: SimulatedOperator + Send + Sync>(
    domain: &dyn GoalChanging<Operator = O>,
    operator: &O,
    behavior: &Behavior,
    seed: u64,
    judgement: &Judgement,
) -> Result<(), String> {
    let redirected = |at_s| {
        domain.run_redirected(
            behavior,
            operator,
            1.0,
            at_s,
            &mut ChaCha8Rng::seed_from_u64(seed),
        )
    };
    if redirected(f64::INFINITY) != *judgement {
        return Err("`run_redirected` with no goal change before the command's end differs from `run` on the same stream: it must be exactly `run`".to_owned());
    }
    let duration = judgement.outcome.duration_s;
    if duration <= 0.0 {
        return Ok(());
    }
    let halfway = redirected(duration / 2.0);
    let cut = halfway.redirected
        && halfway.truth.is_none()
        && halfway.outcome.kind == OutcomeKind::Interrupted
        && halfway.outcome.duration_s == duration / 2.0;
    if !cut {
        return Err(format!(
            "`run_redirected` with a goal change halfway through a command of {duration} s did not interrupt it then (`Judgement::redirected`, no true reason, {} s)",
            duration / 2.0
        ));
    }
    Ok(())
}

/// The rules every judgement keeps, as a sentence for the first one it breaks.
fn check_judgement(
    judgement: &Judgement,
    causes: &[Cause],
    undeclared_bits: u32,
) -> Result<(), String> {
    let outcome = &judgement.outcome;
    outcome
        .validate()
        .map_err(|e| format!("a run returned an invalid outcome: {e}"))?;
    if outcome.observed.bits() & undeclared_bits != 0 {
        return Err(format!(
            "a run perceived observation bits {:#b} beyond the {} declared",
            outcome.observed.bits() & undeclared_bits,
            undeclared_bits.trailing_zeros()
        ));
    }
    if outcome.stated.is_some() {
        return Err(
            "a run stated a reason: stating is the feedback channel's, which the runner applies"
                .to_owned(),
        );
    }
    if judgement.redirected || outcome.goal_change {
        return Err(
            "a run with no goal change was cut by one, or said one: only `run_redirected` cuts a command, and saying is the feedback channel's".to_owned(),
        );
    }
    match (outcome.kind, judgement.truth) {
        (OutcomeKind::Completed, Some(truth)) => Err(format!(
            "a completed run has a true reason (`{truth}`): a completion has none"
        )),
        (_, Some(truth)) if !causes.contains(&truth) => Err(format!(
            "a run's true reason `{truth}` is not a declared cause"
        )),
        _ => Ok(()),
    }
}

/// The first name that appears twice in `names`.
fn first_repeated(names: &[Cause]) -> Option<Cause> {
    names
        .iter()
        .enumerate()
        .find(|&(i, n)| names[..i].contains(n))
        .map(|(_, &n)| n)
}

/// `operator `x`, behavior speed=1 m/s, padding=0.2 m, seed 3`.
fn describe(
    operator: &str,
    space: &cbr_core::BehaviorSpace,
    behavior: &Behavior,
    seed: u64,
) -> String {
    format!(
        "operator `{operator}`, behavior {}, seed {seed}",
        space.display(behavior)
    )
}

/// `D` reduced to [`Domain`]'s required methods (its name, space, causes and runs), with
/// no capability: what a plug-in that implements no more than it must is, for tests of
/// the plans that need a capability (attention, goal changes) and refuse it.
pub struct Bare<D>(pub D);

impl<D: Domain> Domain for Bare<D> {
    type Operator = D::Operator;

    fn name(&self) -> &str {
        self.0.name()
    }

    fn space(&self) -> &Arc<BehaviorSpace> {
        self.0.space()
    }

    fn causes(&self) -> &[DeclaredCause] {
        self.0.causes()
    }

    fn run(&self, behavior: &Behavior, operator: &D::Operator, rng: &mut dyn RngCore) -> Judgement {
        self.0.run(behavior, operator, rng)
    }
}

/// How a [`ToyDomain`] runs one command: the behavior, the operator, its attention (1 for
/// [`Domain::run`]) and the run's random stream.
pub type ToyRule<O> = dyn Fn(&Behavior, &O, f64, &mut dyn RngCore) -> Judgement + Send + Sync;

/// How a [`ToyDomain`]'s operator judges in a context ([`Domain::operator_in_context`]).
pub type ToyInContext<O> = dyn Fn(&O, &Context) -> Option<O> + Send + Sync;

/// A small domain for tests: a grid of numeric components `c0, c1, ...` (values `0, 1, ...`),
/// the causes and observations it declares, and a rule the test writes for one command
/// under an operator of type `O`. [`Domain::run`] is the rule at attention 1 and
/// [`Domain::run_attending`] the rule at the attention given, so a rule that reads its
/// attention models an operator who may overlook problems, and one that ignores it keeps
/// the contract by construction.
pub struct ToyDomain<O> {
    name: String,
    space: Arc<BehaviorSpace>,
    causes: Vec<DeclaredCause>,
    observations: Vec<Cause>,
    hints: Vec<Hint>,
    contexts: ContextSpace,
    rule: Box<ToyRule<O>>,
    in_context: Option<Box<ToyInContext<O>>>,
}

impl<O> ToyDomain<O> {
    /// A domain named `name` over a grid of `sizes[k]` values per component, declaring
    /// `causes`, whose commands follow `rule`.
    pub fn grid(
        name: &str,
        sizes: &[u16],
        causes: &[Cause],
        rule: impl Fn(&Behavior, &O, f64, &mut dyn RngCore) -> Judgement + Send + Sync + 'static,
    ) -> Self {
        let components = sizes
            .iter()
            .enumerate()
            .map(|(k, &n)| {
                NamedComponent::numeric(&format!("c{k}"), "", 0.0, 1.0, n).expect("a valid grid")
            })
            .collect();
        Self {
            name: name.to_owned(),
            space: Arc::new(BehaviorSpace::new(components).expect("a valid space")),
            causes: causes.iter().copied().map(DeclaredCause::new).collect(),
            observations: Vec::new(),
            hints: Vec::new(),
            contexts: ContextSpace::NONE,
            rule: Box::new(rule),
            in_context: None,
        }
    }

    /// The same domain declaring the context variables of `contexts` (with any similarity
    /// it declares between their values).
    #[must_use]
    pub fn in_contexts(mut self, contexts: ContextSpace) -> Self {
        self.contexts = contexts;
        self
    }

    /// The same domain whose operators judge in a context as `in_context` says (`None`:
    /// as in their own file).
    #[must_use]
    pub fn judging_in_context(
        mut self,
        in_context: impl Fn(&O, &Context) -> Option<O> + Send + Sync + 'static,
    ) -> Self {
        self.in_context = Some(Box::new(in_context));
        self
    }

    /// The same domain declaring `observations` (in bit order) and `hints`.
    #[must_use]
    pub fn perceiving(mut self, observations: &[Cause], hints: &[Hint]) -> Self {
        self.observations = observations.to_vec();
        self.hints = hints.to_vec();
        self
    }
}

impl<O: SimulatedOperator + Send + Sync> Domain for ToyDomain<O> {
    type Operator = O;

    fn name(&self) -> &str {
        &self.name
    }

    fn space(&self) -> &Arc<BehaviorSpace> {
        &self.space
    }

    fn causes(&self) -> &[DeclaredCause] {
        &self.causes
    }

    fn observations(&self) -> &[Cause] {
        &self.observations
    }

    fn hints(&self) -> &[Hint] {
        &self.hints
    }

    fn contexts(&self) -> &ContextSpace {
        &self.contexts
    }

    fn operator_in_context(&self, operator: &O, context: &Context) -> Option<O> {
        self.in_context.as_ref()?(operator, context)
    }

    fn run(&self, behavior: &Behavior, operator: &O, rng: &mut dyn RngCore) -> Judgement {
        (self.rule)(behavior, operator, 1.0, rng)
    }

    fn attentive(&self) -> Option<&dyn Attentive<Operator = O>> {
        Some(self)
    }

    fn goal_changing(&self) -> Option<&dyn GoalChanging<Operator = O>> {
        Some(self)
    }
}

impl<O: SimulatedOperator + Send + Sync> Attentive for ToyDomain<O> {
    fn run_attending(
        &self,
        behavior: &Behavior,
        operator: &O,
        attention: f64,
        rng: &mut dyn RngCore,
    ) -> Judgement {
        (self.rule)(behavior, operator, attention, rng)
    }
}

impl<O: SimulatedOperator + Send + Sync> GoalChanging for ToyDomain<O> {
    /// The rule's command, cut at `at_s` when it would last longer: the toy's rule says
    /// nothing of when it perceived what, so a cut command perceived nothing; it weighs
    /// what the whole command would have.
    fn run_redirected(
        &self,
        behavior: &Behavior,
        operator: &O,
        attention: f64,
        at_s: f64,
        rng: &mut dyn RngCore,
    ) -> Judgement {
        let judgement = (self.rule)(behavior, operator, attention, rng);
        if at_s < judgement.outcome.duration_s {
            Judgement::redirected(judgement.outcome.weight, at_s)
        } else {
            judgement
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::Rng;
    use std::sync::atomic::{AtomicU64, Ordering};

    const SLOW: Cause = Cause::from_static("slow");
    const BUMP: Cause = Cause::from_static("bump");

    /// The operator wants behavior `(k, k)`; others are interrupted as slow.
    fn fair() -> ToyDomain<u16> {
        ToyDomain::grid("fair", &[4, 4], &[SLOW], |b, &k, _, rng| {
            if *b == Behavior::new(&[k, k]) || rng.random_bool(0.1) {
                Judgement::completed(1.0, 1.0)
            } else {
                Judgement::interrupted(1.0, SLOW, 1.0)
            }
        })
    }

    fn operators() -> Vec<(String, u16)> {
        vec![("one".to_owned(), 1), ("three".to_owned(), 3)]
    }

    fn rule_broken(domain: &ToyDomain<u16>) -> String {
        try_check_domain(domain, &operators()).unwrap_err().rule
    }

    #[test]
    fn a_domain_that_keeps_the_contract_passes() {
        check_domain(&fair(), &operators());
        let perceiving = fair().perceiving(
            &[BUMP],
            &[Hint {
                observation: BUMP,
                suggests: SLOW,
            }],
        );
        check_domain(&perceiving, &operators());
    }

    #[test]
    fn each_broken_rule_is_named() {
        let twice = ToyDomain::grid("twice", &[2], &[SLOW, SLOW], |_, _: &u16, _, _| {
            Judgement::completed(1.0, 1.0)
        });
        assert_eq!(rule_broken(&twice), "cause `slow` is declared twice");
        let hint = fair().perceiving(
            &[BUMP],
            &[Hint {
                observation: BUMP,
                suggests: Cause::from_static("glare"),
            }],
        );
        assert_eq!(
            rule_broken(&hint),
            "a hint suggests cause `glare`, which is not declared"
        );
        // A run that draws from a generator of its own.
        let draws = AtomicU64::new(0);
        let restless = ToyDomain::grid("restless", &[2], &[SLOW], move |_, _: &u16, _, _| {
            let n = draws.fetch_add(1, Ordering::Relaxed);
            Judgement::completed(1.0, 1.0 + n as f64)
        });
        assert!(rule_broken(&restless).starts_with("two runs on the same random stream differ"));
        let told = ToyDomain::grid("told", &[2], &[SLOW], |_, _: &u16, _, _| {
            let j = Judgement::interrupted(1.0, SLOW, 1.0);
            Judgement {
                outcome: j.outcome.stating(Some(SLOW)),
                ..j
            }
        });
        assert!(rule_broken(&told).starts_with("a run stated a reason"));
        let lucky = ToyDomain::grid("lucky", &[2], &[SLOW], |_, _: &u16, _, _| Judgement {
            truth: Some(SLOW),
            ..Judgement::completed(1.0, 1.0)
        });
        assert!(rule_broken(&lucky).starts_with("a completed run has a true reason"));
        let secret = ToyDomain::grid("secret", &[2], &[SLOW], |_, _: &u16, _, _| {
            Judgement::failed(1.0, BUMP, 1.0)
        });
        assert_eq!(
            rule_broken(&secret),
            "a run's true reason `bump` is not a declared cause"
        );
        let felt = ToyDomain::grid("felt", &[2], &[SLOW], |_, _: &u16, _, _| {
            Judgement::completed(1.0, 1.0).observing(Observations::NONE.with(0))
        });
        assert!(rule_broken(&felt).starts_with("a run perceived observation bits 0b1"));
        let negative = ToyDomain::grid("negative", &[2], &[SLOW], |_, _: &u16, _, _| {
            Judgement::completed(-1.0, 1.0)
        });
        assert!(rule_broken(&negative).starts_with("a run returned an invalid outcome"));
        let careless = ToyDomain::grid("careless", &[2], &[SLOW], |_, _: &u16, _, _| {
            Judgement::completed(1.0, 1.0).overlooking(Some(SLOW))
        });
        assert_eq!(
            rule_broken(&careless),
            "an attentive run (`run`) overlooked a problem"
        );
        let case = try_check_domain(&careless, &operators()).unwrap_err().case;
        assert_eq!(
            case.as_deref(),
            Some("operator `one`, behavior c0=1, seed 0")
        );
    }

    /// An attending hook a test writes over the `fair` domain.
    type Hook = fn(&ToyDomain<u16>, &Behavior, &u16, f64, &mut dyn RngCore) -> Judgement;

    /// The `fair` domain with an attending hook of the test's.
    struct Attending {
        fair: ToyDomain<u16>,
        hook: Hook,
    }

    impl Domain for Attending {
        type Operator = u16;
        fn name(&self) -> &str {
            "attending"
        }
        fn space(&self) -> &Arc<BehaviorSpace> {
            self.fair.space()
        }
        fn causes(&self) -> &[DeclaredCause] {
            self.fair.causes()
        }
        fn run(&self, b: &Behavior, k: &u16, rng: &mut dyn RngCore) -> Judgement {
            self.fair.run(b, k, rng)
        }
        fn attentive(&self) -> Option<&dyn Attentive<Operator = u16>> {
            Some(self)
        }
    }

    impl Attentive for Attending {
        fn run_attending(
            &self,
            b: &Behavior,
            k: &u16,
            attention: f64,
            rng: &mut dyn RngCore,
        ) -> Judgement {
            (self.hook)(&self.fair, b, k, attention, rng)
        }
    }

    /// A domain that models neither attention nor goal changes.
    struct Unmodelled<'a>(&'a ToyDomain<u16>);

    impl Domain for Unmodelled<'_> {
        type Operator = u16;
        fn name(&self) -> &str {
            "unmodelled"
        }
        fn space(&self) -> &Arc<BehaviorSpace> {
            self.0.space()
        }
        fn causes(&self) -> &[DeclaredCause] {
            self.0.causes()
        }
        fn run(&self, b: &Behavior, k: &u16, rng: &mut dyn RngCore) -> Judgement {
            self.0.run(b, k, rng)
        }
    }

    fn attending_rule_broken(hook: Hook) -> String {
        let domain = Attending { fair: fair(), hook };
        try_check_domain(&domain, &operators()).unwrap_err().rule
    }

    #[test]
    fn a_domain_that_does_not_model_attention_keeps_the_contract() {
        let fair = fair();
        check_domain(&Unmodelled(&fair), &operators());
        let lacking = crate::check_attention(&Unmodelled(&fair)).err().unwrap();
        assert_eq!(lacking.domain, "unmodelled");
        assert!(crate::check_goal_changes(&Unmodelled(&fair)).is_err());
        assert!(crate::check_attention(&fair).is_ok());
        assert!(crate::check_goal_changes(&fair).is_ok());
    }

    #[test]
    fn an_attending_hook_that_breaks_the_contract_is_named() {
        // At attention 1 it is not the plain run.
        let rule = attending_rule_broken(|_, _, _, _, _| Judgement::completed(1.0, 1.0));
        assert!(
            rule.starts_with("`run_attending` at attention 1 differs"),
            "{rule}"
        );
        // Inattentive, it overlooks a cause the domain does not declare.
        let rule = attending_rule_broken(|fair, b, k, attention, rng| {
            let run = fair.run_attending(b, k, attention, rng);
            if attention < 1.0 {
                run.overlooking(Some(Cause::from_static("unheard-of")))
            } else {
                run
            }
        });
        assert!(
            rule.starts_with("an inattentive run overlooked `unheard-of`"),
            "{rule}"
        );
    }
}
