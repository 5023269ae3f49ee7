//! Searchers chosen online: two strategies share an episode's proposals, and which of them
//! leads is learned across episodes by a bandit whose loss is what the episode cost the
//! operator.
//!
//! [`super::Alternating`] gives two strategies one turn each, whatever they have cost so
//! far: on a population where one of them finds trusted behaviors cheaply and the other
//! never does, every other proposal is wasted for good. [`Bandit`] learns which one to
//! trust with the lead instead. It treats each episode as a round of a bandit with two
//! arms, "the first leads" and "the second leads":
//!
//! - **The round.** At the episode's first proposal it draws the leader `i` with
//!   probability `p_i ∝ exp(-η_t L_i)` (`L_i` the leader's estimated cumulative loss,
//!   `t` the round); then each proposal is the leader's with probability
//!   `1 -` [`FOLLOWER_SHARE`], the other's otherwise. The follower's share bounds what a
//!   wrong lead costs: an episode that the follower alone would end after `n` proposals
//!   ends after about `n / FOLLOWER_SHARE` (4n) at worst, where taking turns ends it after
//!   about `2n`, and a right lead ends it after about `n / (1 - FOLLOWER_SHARE)` (1.33n).
//! - **The loss.** The untrustworthy commands the operator endured on behaviors the two
//!   proposed in the episode (not those on a remembered case's behavior, which the bandit
//!   did not choose), scaled by [`LOSS_SCALE`] and capped at 1: an episode that costs
//!   `LOSS_SCALE` or more is as bad as any. Only the leader's estimate moves, by the loss
//!   divided by the probability it was drawn with (an unbiased estimate of every arm's
//!   loss, the other's being 0 with the other's probability).
//! - **The rate.** `η_t = sqrt(ln 2 / (2 t))`: Exp3 with the anytime rate, whose expected
//!   regret against the better lead in hindsight, over `T` rounds of losses in `[0, 1]`
//!   chosen by any adversary, is at most `2 sqrt(T K ln K)` for `K` arms (Bubeck and
//!   Cesa-Bianchi, *Regret Analysis of Stochastic and Nonstochastic Multi-armed Bandit
//!   Problems*, 2012, Theorem 3.1): with `K = 2`, at most `2.36 sqrt(T)` scaled losses, so
//!   the average regret per episode falls as `1 / sqrt(T)`. An adversary is the right
//!   model here: the case base and both strategies learn as the episodes go by, so the
//!   losses of a lead are not drawn from one law.
//!
//! Rounds are the episodes in which the bandit proposed at all: an episode a remembered
//! case ended tells nothing about its searchers and moves nothing. Both strategies observe
//! every outcome and every episode's end, as with taking turns, so each learns from what
//! the other proposed.

use super::pair::Pair;
use super::registry::{Look, Marker, Strategy, WithCases};
use super::{CauseAware, Conditioned, ModelBased};
use crate::{Evaluated, Outcome};
use cbr_core::{Behavior, BehaviorSpace, Context, Proposal, Rationale, Searcher, Statement};
use rand::{Rng, RngCore};
use std::collections::HashSet;

/// The conditioned search whose own search, when nothing remembered fits, is the
/// cause-aware and the model-based searches with the lead learned (`bandit`): `hedged`
/// with its fixed turns replaced by [`Bandit`].
pub const STRATEGY: Strategy = Strategy {
    name: "bandit",
    description: "the conditioned search, whose own search when nothing remembered fits is led by whichever of the cause-aware and model-based searches has cost this population's episodes fewer untrustworthy commands (Exp3 over episodes), the other proposing a quarter of the time",
    look: Look {
        colour: [86, 180, 233],
        marker: Marker::Star,
    },
    with_cases: Some(WithCases {
        name: "case-based+bandit",
        description: "case reuse first, the bandit-led search when no case fits",
        look: Look {
            colour: [204, 121, 167],
            marker: Marker::Square,
        },
    }),
    build: || Box::new(led_conditioned()),
};

/// The searcher of [`STRATEGY`]: a conditioned searcher that remembers no episode yet,
/// falling back to the cause-aware and the model-based searches under a learned lead.
pub fn led_conditioned() -> Conditioned<Bandit<CauseAware, ModelBased>> {
    Conditioned::with_fallback(
        STRATEGY.name,
        Bandit::new(CauseAware::new(), ModelBased::new()),
    )
}

/// The share of an episode's proposals the follower makes: a quarter, so that a wrong
/// lead at most doubles what taking turns would cost (`n / FOLLOWER_SHARE` against `2n`)
/// while a right one saves a third of it (`n / (1 - FOLLOWER_SHARE)` against `2n`). Set a
/// priori from that bound, not tuned.
pub const FOLLOWER_SHARE: f64 = 0.25;

/// The untrustworthy commands at which an episode's loss reaches its cap of 1. Set a
/// priori: about five times the known-operator limit's untrustworthy commands in the
/// benchmark's patrol populations (about 19) and ten times movement's (about 7), so that
/// losses spread over `[0, 1]` for the episodes a search usually has, and an episode cut
/// off after hundreds of them counts as the worst.
pub const LOSS_SCALE: f64 = 100.0;

/// Two searchers sharing an episode's proposals, the lead learned across episodes (see the
/// module documentation).
#[derive(Clone, Debug)]
pub struct Bandit<A, B> {
    pair: Pair<A, B>,
    /// Each lead's estimated cumulative loss.
    losses: [f64; 2],
    /// Rounds played (episodes in which the bandit proposed).
    rounds: u32,
    /// This episode's leader and the probability it was drawn with, once drawn.
    leader: Option<(usize, f64)>,
    /// The behaviors the two proposed in this episode.
    proposed: HashSet<Behavior>,
    /// The untrustworthy commands endured on them.
    untrustworthy: u32,
}

impl<A, B> Bandit<A, B> {
    /// `first` and `second` sharing proposals, neither yet preferred.
    pub fn new(first: A, second: B) -> Self {
        Self {
            pair: Pair::new(first, second),
            losses: [0.0; 2],
            rounds: 0,
            leader: None,
            proposed: HashSet::new(),
            untrustworthy: 0,
        }
    }

    /// The probability that each searcher leads the next round.
    pub fn lead_probabilities(&self) -> [f64; 2] {
        let round = f64::from(self.rounds + 1);
        let rate = (std::f64::consts::LN_2 / (2.0 * round)).sqrt();
        let least = self.losses[0].min(self.losses[1]);
        let weights = self.losses.map(|loss| (-rate * (loss - least)).exp());
        let total = weights[0] + weights[1];
        weights.map(|w| w / total)
    }

    /// The loss of an episode that cost `untrustworthy` commands: scaled and capped.
    fn loss(untrustworthy: u32) -> f64 {
        (f64::from(untrustworthy) / LOSS_SCALE).min(1.0)
    }
}

impl<A, B> Searcher for Bandit<A, B>
where
    A: Searcher<Evidence = Evaluated, Feedback = Outcome>,
    B: Searcher<Evidence = Evaluated, Feedback = Outcome>,
{
    type Evidence = Evaluated;
    type Feedback = Outcome;

    fn name(&self) -> &str {
        "lead-bandit"
    }

    fn learns_across_episodes(&self) -> bool {
        true
    }

    fn reads_context(&self) -> bool {
        self.pair.reads_context()
    }

    fn hears_statements(&self) -> bool {
        self.pair.hears_statements()
    }

    fn enter_context(&mut self, context: &Context) {
        self.pair.enter_context(context);
    }

    fn hear(&mut self, stated: &[Statement]) {
        self.pair.hear(stated);
    }

    fn begin_episode(&mut self, space: &BehaviorSpace, initial: &Behavior) {
        self.leader = None;
        self.proposed.clear();
        self.untrustworthy = 0;
        self.pair.begin_episode(space, initial);
    }

    fn propose(
        &mut self,
        space: &BehaviorSpace,
        evaluated: &[Evaluated],
        rng: &mut dyn RngCore,
    ) -> Proposal {
        let leader = match self.leader {
            Some((leader, _)) => leader,
            None => {
                let [first, second] = self.lead_probabilities();
                let drawn = if rng.random::<f64>() < first {
                    (0, first)
                } else {
                    (1, second)
                };
                self.leader = Some(drawn);
                drawn.0
            }
        };
        let follows = rng.random::<f64>() < FOLLOWER_SHARE;
        let proposal = self
            .pair
            .propose((leader == 1) != follows, space, evaluated, rng);
        if let Proposal::Next(behavior) = proposal {
            self.proposed.insert(behavior);
        }
        proposal
    }

    fn rationale(&self, proposed: &Behavior) -> Rationale {
        self.pair.rationale(proposed)
    }

    fn observe(&mut self, behavior: &Behavior, outcome: &Outcome) {
        if outcome.is_untrustworthy() && self.proposed.contains(behavior) {
            self.untrustworthy += 1;
        }
        self.pair.observe(behavior, outcome);
    }

    fn end_episode(&mut self, evaluated: &[Evaluated], settled: Option<&Behavior>) {
        if let Some((leader, probability)) = self.leader.take() {
            self.losses[leader] += Self::loss(self.untrustworthy) / probability;
            self.rounds += 1;
        }
        self.pair.end_episode(evaluated, settled);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::search::{Fixed, grid};
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn pair() -> Bandit<Fixed, Fixed> {
        let fixed = |at| Fixed {
            at,
            ..Fixed::default()
        };
        Bandit::new(fixed(1), fixed(2))
    }

    fn failed() -> Outcome {
        Outcome::failed(1.0, 1.0)
    }

    #[test]
    fn a_costly_lead_loses_weight_by_the_exp3_rule() {
        let space = grid(&[10]);
        let mut bandit = pair();
        assert_eq!(bandit.lead_probabilities(), [0.5, 0.5]);
        let start = Behavior::new(&[0]);
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        bandit.begin_episode(&space, &start);
        let Proposal::Next(proposed) = bandit.propose(&space, &[], &mut rng) else {
            panic!("a fixed searcher always proposes");
        };
        let (leader, drawn_with) = bandit.leader.unwrap();
        assert_eq!(drawn_with, 0.5);
        // 50 untrustworthy commands on a proposed behavior, 30 on the starting one (which
        // the bandit did not choose) and a completion: a loss of 50 / 100.
        for _ in 0..50 {
            bandit.observe(&proposed, &failed());
        }
        for _ in 0..30 {
            bandit.observe(&start, &failed());
        }
        bandit.observe(&proposed, &Outcome::completed(1.0, 1.0));
        bandit.end_episode(&[], Some(&proposed));
        // The leader's estimate: 0.5 / 0.5 = 1; the other's 0.
        let mut losses = [0.0; 2];
        losses[leader] = 1.0;
        assert_eq!(bandit.losses, losses);
        assert_eq!(bandit.rounds, 1);
        // Round 2's rate: sqrt(ln 2 / 4) = 0.41628; the costly lead's weight
        // exp(-0.41628) = 0.65950 against 1: probability 0.65950 / 1.65950 = 0.39741.
        let p = bandit.lead_probabilities()[leader];
        assert!((p - 0.397_41).abs() < 1e-5, "{p}");
        // Both searchers heard every outcome and the episode's end.
        assert_eq!(
            (bandit.pair.first.observed, bandit.pair.second.observed),
            (81, 81)
        );
        assert_eq!((bandit.pair.first.ended, bandit.pair.second.ended), (1, 1));
    }

    #[test]
    fn an_episode_the_bandit_never_proposed_in_is_no_round() {
        let space = grid(&[10]);
        let mut bandit = pair();
        let start = Behavior::new(&[0]);
        bandit.begin_episode(&space, &start);
        bandit.observe(&start, &failed());
        bandit.end_episode(&[], Some(&start));
        assert_eq!((bandit.losses, bandit.rounds), ([0.0; 2], 0));
    }

    #[test]
    fn the_follower_makes_about_a_quarter_of_the_proposals() {
        let space = grid(&[10]);
        let mut bandit = pair();
        // The second searcher's lead has cost far more: the first leads almost surely.
        bandit.losses = [0.0, 1000.0];
        bandit.rounds = 10;
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        bandit.begin_episode(&space, &Behavior::new(&[0]));
        let proposals = 4000;
        let mut second = 0;
        for _ in 0..proposals {
            let Proposal::Next(b) = bandit.propose(&space, &[], &mut rng) else {
                panic!("a fixed searcher always proposes");
            };
            // The rationale is the proposer's.
            let cbr_core::Rationale::Explores { how } = bandit.rationale(&b) else {
                panic!("fixed searchers explore");
            };
            assert_eq!(how, format!("always {}", b.get(0)));
            second += usize::from(b.get(0) == 2);
        }
        assert_eq!(bandit.leader.map(|(leader, _)| leader), Some(0));
        // A binomial(4000, 0.25) count: mean 1000, standard deviation 27.4.
        assert!((900..=1100).contains(&second), "{second}");
    }

    #[test]
    fn the_loss_is_capped_at_one() {
        assert_eq!(Bandit::<Fixed, Fixed>::loss(50), 0.5);
        assert_eq!(Bandit::<Fixed, Fixed>::loss(250), 1.0);
    }
}
