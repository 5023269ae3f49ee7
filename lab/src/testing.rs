//! The domain conformance kit (feature `testing`): [`check_domain`] states the rules of
//! the simulation contract ([`Domain`]) that a test can check, and checks them on a
//! domain and its operators.
//!
//! A domain author calls `lab::testing::check_domain(&domain, &operators)` from a test of
//! the domain's crate, with the lab's `testing` feature (a plug-in gets it through
//! `trustcbr`'s `testing` feature). The UGV's movement and patrol domains and the warehouse example pass it
//! (`domains/tests/conformance.rs`, `examples/warehouse/tests/model.rs`).

use crate::domain::{Domain, Judgement};
use cbr_core::Behavior;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use trust::{Cause, Observations, OutcomeKind};

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
/// - [`Domain::run_attending`] at attention 1 is exactly [`Domain::run`], draw for draw,
///   and whatever an inattentive run overlooks is a declared cause.
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
            let run = |attention: Option<f64>| {
                let mut rng = ChaCha8Rng::seed_from_u64(seed);
                match attention {
                    None => domain.run(&behavior, operator, &mut rng),
                    Some(a) => domain.run_attending(&behavior, operator, a, &mut rng),
                }
            };
            let judgement = run(None);
            if run(None) != judgement {
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
            if run(Some(1.0)) != judgement {
                return Err(broken(
                    "`run_attending` at attention 1 differs from `run` on the same stream: at full attention it must be exactly `run`".to_owned(),
                    case(),
                ));
            }
            let inattentive = run(Some(0.0));
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
