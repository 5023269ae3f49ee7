//! Simulated commands, one at a time: the step every simulated command takes, and one
//! behavior's commands in front of one operator with no adapter to tell.
//!
//! The step (`command`, crate-private): the domain runs the command in front of the
//! operator (the paper's attentive one, or one at its attention: a domain that does not
//! model attention refuses that), its truth is checked to be a cause the domain declares,
//! and a feedback channel states a reason (or none) on a stream of its own. A trial and a
//! mission take it for every command, then tell their adapter.
//!
//! A [`Simulation`] takes it again and again for one behavior and one operator (its own
//! channel), drawing the runs from the stream of `seed` and the stated reasons from stream
//! [`FEEDBACK_STREAM`] of the same seed, one command after the other: the tool's
//! `simulate` prints each command, and Python's `trustcbr.simulate(seed=S)` is the first
//! command of `Simulation::new(.., S)`.

use crate::experiment::plan::PlanError;
use crate::{
    AttentionNotModelled, Attentive, Domain, FeedbackChannel, GoalChanging, Judgement,
    check_attention,
};
use cbr_core::Behavior;
use rand::{RngCore, SeedableRng};
use rand_chacha::ChaCha8Rng;
use trust::{Outcome, UndeclaredCause, find_declared};

/// The stream of a simulation's seed that draws the operator's stated reasons (the runs
/// draw from stream 0).
pub const FEEDBACK_STREAM: u64 = 1;

/// One simulated command: the domain's judgement, and the outcome the robot is told.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimulatedCommand {
    /// What the domain's run yielded: the outcome before any reason was stated, the
    /// operator's true reason and what it overlooked (evaluation only).
    pub judgement: Judgement,
    /// The outcome the robot is told: the judgement's, with the reason the operator's
    /// feedback channel stated, if any.
    pub outcome: Outcome,
}

/// Why [`command`] could not simulate a command: the run's truth is not a cause the
/// domain declares.
#[derive(Debug)]
pub(crate) struct Refused(Box<UndeclaredCause>);

impl Refused {
    /// The error that stops the plan named `plan` over the domain named `domain`.
    pub(crate) fn in_plan(self, plan: &str, domain: &str) -> PlanError {
        PlanError::UndeclaredCause {
            plan: plan.to_owned(),
            domain: domain.to_owned(),
            reason: self.0,
        }
    }
}

/// An operator's attention below 1, with the domain as one that models it.
pub(crate) type Attention<'c, O> = (f64, &'c dyn Attentive<Operator = O>);

/// What the operator of a simulated command is like at that moment.
pub(crate) struct Conditions<'c, O> {
    /// Its attention (`None`: the paper's attentive operator).
    pub(crate) attention: Option<Attention<'c, O>>,
    /// Seconds into the command at which its goals change, with the domain as one that
    /// models them (`None`: they do not).
    pub(crate) goal_change_at: Option<(f64, &'c dyn GoalChanging<Operator = O>)>,
}

/// Runs one command of `domain` with `behavior` in front of `operator`, the paper's
/// attentive one ([`Domain::run`]) when its `attention` is `None`, else one at that
/// attention ([`crate::Attentive::run_attending`]); with `goal_change_at`, the operator's
/// goals change that many seconds in ([`crate::GoalChanging::run_redirected`], at
/// `attention` or 1). The run draws from `runs`; `channel` states a reason, or says a goal
/// change, from `stated`. A truth the domain does not declare is refused (the runs stream
/// has drawn the run; nothing is drawn from `stated`).
pub(crate) fn command<D: Domain + ?Sized>(
    domain: &D,
    behavior: &Behavior,
    operator: &D::Operator,
    Conditions {
        attention,
        goal_change_at,
    }: Conditions<'_, D::Operator>,
    channel: FeedbackChannel,
    runs: &mut dyn RngCore,
    stated: &mut dyn RngCore,
) -> Result<SimulatedCommand, Refused> {
    let judgement = match (attention, goal_change_at) {
        (None, None) => domain.run(behavior, operator, runs),
        (Some((attention, attentive)), None) => {
            attentive.run_attending(behavior, operator, attention, runs)
        }
        (attention, Some((at_s, changing))) => {
            let attention = attention.map_or(1.0, |(attention, _)| attention);
            changing.run_redirected(behavior, operator, attention, at_s, runs)
        }
    };
    let causes = domain.causes();
    if let Some(cause) = judgement.truth {
        find_declared(causes, cause).map_err(|e| Refused(Box::new(e)))?;
    }
    let outcome = if judgement.redirected {
        judgement
            .outcome
            .saying_goal_change(channel.says_goal_change(stated))
    } else {
        judgement
            .outcome
            .stating(channel.state(judgement.truth, causes, stated))
    };
    Ok(SimulatedCommand { judgement, outcome })
}

/// Why a simulation cannot start or go on.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SimulationError {
    /// The attention is not a probability.
    #[error(
        "attention must be a number in [0, 1] (1: the paper's attentive operator), got {}",
        cbr_core::Shown(*.0)
    )]
    Attention(f64),
    /// The behavior is not one of the domain's space.
    #[error("the value indices {indices:?} are not a behavior of domain `{domain}`")]
    Behavior {
        /// The domain's name.
        domain: String,
        /// The behavior's value indices.
        indices: Vec<u16>,
    },
    /// An attention below 1 was asked of a domain that does not model attention.
    #[error(transparent)]
    AttentionNotModelled(AttentionNotModelled),
    /// The domain reported a judgement whose true reason it does not declare.
    #[error("domain `{domain}` reported an outcome whose {reason}")]
    UndeclaredCause {
        /// The domain's name.
        domain: String,
        /// The cause and the declared ones.
        reason: Box<UndeclaredCause>,
    },
}

/// One behavior's commands in front of one operator, endless: an iterator of
/// [`SimulatedCommand`]s (take as many as wanted), each drawn after the one before.
pub struct Simulation<'a, D: Domain + ?Sized> {
    domain: &'a D,
    behavior: Behavior,
    operator: &'a D::Operator,
    /// The attention below 1, with the domain as one that models it (`None`: 1).
    attention: Option<Attention<'a, D::Operator>>,
    channel: FeedbackChannel,
    runs: ChaCha8Rng,
    stated: ChaCha8Rng,
}

impl<'a, D: Domain + ?Sized> Simulation<'a, D> {
    /// The commands of `behavior` (of `domain`'s space) in front of `operator` at
    /// `attention` (in `[0, 1]`; below 1 only on a domain that models it,
    /// [`crate::Attentive`]), every draw from `seed`; the operator states reasons through
    /// its own feedback channel ([`Domain::feedback`]).
    pub fn new(
        domain: &'a D,
        behavior: Behavior,
        operator: &'a D::Operator,
        attention: f64,
        seed: u64,
    ) -> Result<Self, SimulationError> {
        if !(0.0..=1.0).contains(&attention) {
            return Err(SimulationError::Attention(attention));
        }
        if !domain.space().contains(&behavior) {
            return Err(SimulationError::Behavior {
                domain: domain.name().to_owned(),
                indices: behavior.indices().to_vec(),
            });
        }
        // At full attention, the paper's operator: `Domain::run`, which every domain has
        // and `Attentive::run_attending` equals there.
        let attention = if attention < 1.0 {
            let attentive =
                check_attention(domain).map_err(SimulationError::AttentionNotModelled)?;
            Some((attention, attentive))
        } else {
            None
        };
        let mut stated = ChaCha8Rng::seed_from_u64(seed);
        stated.set_stream(FEEDBACK_STREAM);
        Ok(Self {
            domain,
            behavior,
            operator,
            attention,
            channel: domain.feedback(operator),
            runs: ChaCha8Rng::seed_from_u64(seed),
            stated,
        })
    }
}

impl<D: Domain + ?Sized> Iterator for Simulation<'_, D> {
    type Item = Result<SimulatedCommand, SimulationError>;

    fn next(&mut self) -> Option<Self::Item> {
        Some(
            command(
                self.domain,
                &self.behavior,
                self.operator,
                Conditions {
                    attention: self.attention,
                    goal_change_at: None,
                },
                self.channel,
                &mut self.runs,
                &mut self.stated,
            )
            .map_err(|Refused(reason)| SimulationError::UndeclaredCause {
                domain: self.domain.name().to_owned(),
                reason,
            }),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::ToyDomain;
    use rand::Rng;
    use trust::Cause;

    const SLOW: Cause = Cause::from_static("slow");
    const BUMP: Cause = Cause::from_static("bump");

    /// A command of behavior `(k)` is interrupted as slow with probability `k / 4`, and
    /// an operator at attention `a` overlooks it with probability `1 - a` (the command
    /// then completes, the slowness named as overlooked).
    fn coin() -> ToyDomain<()> {
        ToyDomain::grid("coin", &[5], &[SLOW], |b, _, attention, rng| {
            if rng.random::<f64>() >= f64::from(b.get(0)) / 4.0 {
                return Judgement::completed(1.0, 1.0);
            }
            if rng.random::<f64>() >= attention {
                return Judgement {
                    overlooked: Some(SLOW),
                    ..Judgement::completed(1.0, 1.0)
                };
            }
            Judgement {
                outcome: Outcome::interrupted(1.0, 2.0),
                truth: Some(SLOW),
                overlooked: None,
                redirected: false,
            }
        })
    }

    fn kinds(simulation: Simulation<'_, ToyDomain<()>>, count: usize) -> Vec<Judgement> {
        simulation
            .take(count)
            .map(|c| c.unwrap().judgement)
            .collect()
    }

    #[test]
    fn the_commands_are_the_runs_of_one_stream_of_the_seed_one_after_the_other() {
        let domain = coin();
        let half = Behavior::new(&[2]);
        let simulated = kinds(Simulation::new(&domain, half, &(), 1.0, 7).unwrap(), 40);
        let mut runs = ChaCha8Rng::seed_from_u64(7);
        let by_hand: Vec<Judgement> = (0..40).map(|_| domain.run(&half, &(), &mut runs)).collect();
        assert_eq!(simulated, by_hand);
        // Both kinds happen at one chance in two, so the commands do differ.
        assert!(simulated.iter().any(|j| j.truth.is_some()));
        assert!(simulated.iter().any(|j| j.truth.is_none()));
        // Behavior 0 always completes, behavior 4 is always interrupted, at attention 1.
        let never = kinds(
            Simulation::new(&domain, Behavior::new(&[0]), &(), 1.0, 7).unwrap(),
            20,
        );
        assert!(never.iter().all(|j| j.truth.is_none()));
        let always = kinds(
            Simulation::new(&domain, Behavior::new(&[4]), &(), 1.0, 7).unwrap(),
            20,
        );
        assert!(
            always
                .iter()
                .all(|j| j.truth == Some(SLOW) && j.overlooked.is_none())
        );
        // At attention 0 the operator overlooks every problem.
        let blind = kinds(
            Simulation::new(&domain, Behavior::new(&[4]), &(), 0.0, 7).unwrap(),
            20,
        );
        assert!(
            blind
                .iter()
                .all(|j| j.truth.is_none() && j.overlooked == Some(SLOW))
        );
    }

    #[test]
    fn an_attention_outside_zero_to_one_and_a_behavior_outside_the_space_are_refused() {
        let domain = coin();
        let refused = |behavior: Behavior, attention: f64| {
            Simulation::new(&domain, behavior, &(), attention, 0)
                .err()
                .unwrap()
                .to_string()
        };
        for attention in [1.5, -0.1, f64::NAN] {
            assert_eq!(
                refused(Behavior::new(&[1]), attention),
                format!(
                    "attention must be a number in [0, 1] (1: the paper's attentive operator), got {attention}"
                )
            );
        }
        assert_eq!(
            refused(Behavior::new(&[5]), 1.0),
            "the value indices [5] are not a behavior of domain `coin`"
        );
    }

    #[test]
    fn a_truth_the_domain_does_not_declare_is_refused_naming_it() {
        let domain = ToyDomain::grid("bumpy", &[2], &[SLOW], |_, _: &(), _, _| Judgement {
            outcome: Outcome::failed(1.0, 1.0),
            truth: Some(BUMP),
            overlooked: None,
            redirected: false,
        });
        let mut simulation = Simulation::new(&domain, Behavior::new(&[0]), &(), 1.0, 0).unwrap();
        assert_eq!(
            simulation.next().unwrap().unwrap_err().to_string(),
            "domain `bumpy` reported an outcome whose cause `bump` is not declared (declared: slow)"
        );
    }
}
