//! Cause-aware search: learn from what untrustworthy outcomes tell the robot which
//! component values bring which troubles, and move away from the troubles this operator
//! reacts to.
//!
//! The robot is not told the operator's true reason. What an untrustworthy outcome tells
//! it is a set of *signals* ([`Signal`]): the reason the operator stated, when it gave one
//! (it may be wrong), each thing the robot perceived itself during the command (a bump, an
//! explosion, running behind its plan: the domain's declared observations), or, when there
//! is neither, that it was unexplained. For each signal the searcher counts, per component
//! and value, how many untrustworthy commands carried it, so it knows, for instance, that
//! bumps fall as one component rises while unexplained interruptions rise with it. These
//! counts persist across episodes (the physics of a robot does not change with the
//! operator) and grow within an episode with every command.
//!
//! How much each signal matters is its *burden*: the weight of this episode's
//! untrustworthy outcomes carrying it (what the current operator has shown it reacts to;
//! an outcome with several signals shares its weight among them), plus the mean burden of
//! an earlier episode (so a signal this operator has not yet shown still counts as much as
//! it usually does). When the operator stated preferences up front
//! ([`cbr_core::Searcher::hear`]), that mean is taken over the earlier episodes whose
//! operators stated the same (every statement heard now, and maybe more), shrunk towards
//! the mean of all earlier episodes with the weight of [`STATED_PRIOR_EPISODES`] episode:
//! the searcher learns what a statement means from the burdens that followed it, so it
//! needs no table of what names mean, and a statement that often proves wrong carries
//! little. A proposal draws a pool
//! of untried behaviors uniformly at random and takes the one whose predicted burden is
//! smallest. The rate of a cause at a behavior is predicted from the per-value rates of
//! its components, combined as independent multiplicative effects on the cause's overall
//! rate (a naive-Bayes reading of the counts), each per-value rate smoothed towards the
//! overall rate. Drawing the pool at random keeps the search exploring where the counts
//! say nothing; no rule about any particular domain or cause is written here.

use super::propose_untried;
use super::registry::{Look, Marker, Strategy, WithCases};
use super::untried::{cheapest, draw_untried};
use super::value_counts::ValueCounts;
use crate::Cause;
use crate::{Evaluated, Outcome};
use cbr_core::{Behavior, BehaviorSpace, Proposal, Rationale, Searcher, Statement};
use rand::RngCore;

/// Untried behaviors drawn and scored per proposal.
pub const CAUSE_AWARE_POOL: usize = 128;

/// Weight of the overall rate in each per-value rate, in commands (a Beta-prior strength).
const PRIOR_COMMANDS: f64 = 2.0;

/// How many episodes' worth the mean burden of all earlier episodes weighs against the
/// episodes whose operators stated the same (a statement heard for the first time weighs
/// nothing; one heard after one episode weighs half). Set a priori, not tuned: one
/// episode is the least that lets a single earlier operator count.
pub const STATED_PRIOR_EPISODES: f64 = 1.0;

/// What an untrustworthy outcome tells the robot about why it happened.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Signal {
    /// The operator said so (rightly or not).
    Stated(Cause),
    /// The robot perceived the domain's observation number `usize` during the command.
    Observed(usize),
    /// Nothing was stated and nothing perceived.
    Unexplained,
}

impl Signal {
    /// The signals of an untrustworthy outcome: its stated reason and each observation,
    /// or [`Signal::Unexplained`] when it has neither.
    pub fn of(outcome: &Outcome) -> Vec<Signal> {
        let mut signals: Vec<Signal> = outcome.stated.map(Signal::Stated).into_iter().collect();
        signals.extend(outcome.observed.indices().map(Signal::Observed));
        if signals.is_empty() {
            signals.push(Signal::Unexplained);
        }
        signals
    }
}

/// What is known about one signal.
#[derive(Clone, Debug)]
struct CauseRecord {
    signal: Signal,
    /// Untrustworthy commands that carried this signal (all episodes).
    counts: ValueCounts,
    /// Weight of this episode's untrustworthy outcomes carrying this signal.
    burden: f64,
    /// Weight of the earlier episodes' untrustworthy outcomes carrying this signal.
    past_burden: f64,
}

/// The earlier episodes whose operators stated the same set of statements.
#[derive(Clone, Debug)]
struct StatedEpisodes {
    /// The set, sorted.
    stated: Vec<Statement>,
    /// Episodes of it ended with some burden.
    episodes: f64,
    /// Their burden per signal, in the order of [`CauseAware::causes`].
    burdens: Vec<f64>,
}

/// The cause-aware searcher.
#[derive(Clone, Debug, Default)]
pub struct CauseAware {
    commands: ValueCounts,
    causes: Vec<CauseRecord>,
    /// Episodes ended so far.
    episodes: f64,
    /// What this episode's operator stated, sorted.
    stated: Vec<Statement>,
    /// The earlier episodes by what their operators stated (none stated: not kept).
    by_statements: Vec<StatedEpisodes>,
    /// Untried behaviors scored for the last proposal (for its rationale).
    last_pool: usize,
}

/// The cause-aware search as the tool offers it, alone and after case reuse.
pub const STRATEGY: Strategy = Strategy {
    name: "cause-aware",
    description: "learns from why commands failed (stated reasons, perceived events) which component values cause trouble, and avoids them",
    look: Look {
        colour: [230, 159, 0],
        marker: Marker::TriangleUp,
    },
    with_cases: Some(WithCases {
        name: "case-based+cause-aware",
        description: "case reuse first, the cause-aware search when no case fits",
        look: Look {
            colour: [86, 180, 233],
            marker: Marker::Hexagon,
        },
    }),
    build: || Box::new(CauseAware::new()),
};

impl CauseAware {
    /// A cause-aware searcher that knows nothing yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// How much each cause matters now, in the order of [`CauseAware::causes`]: this
    /// episode's burden, plus the mean burden of an earlier episode (the operators met so
    /// far), so a cause not yet met in this episode still counts as much as it usually
    /// does; with statements heard, the mean of the episodes whose operators stated the
    /// same, shrunk towards it.
    fn weights(&self) -> Vec<f64> {
        let mean = |c: &CauseRecord| c.past_burden / self.episodes.max(1.0);
        if self.stated.is_empty() {
            return self.causes.iter().map(|c| c.burden + mean(c)).collect();
        }
        let mut episodes = 0.0;
        let mut burdens = vec![0.0; self.causes.len()];
        for group in self.agreeing() {
            episodes += group.episodes;
            for (sum, burden) in burdens.iter_mut().zip(&group.burdens) {
                *sum += burden;
            }
        }
        self.causes
            .iter()
            .zip(burdens)
            .map(|(c, burden)| {
                c.burden
                    + (burden + STATED_PRIOR_EPISODES * mean(c))
                        / (episodes + STATED_PRIOR_EPISODES)
            })
            .collect()
    }

    /// The earlier episodes whose operators stated everything heard now.
    fn agreeing(&self) -> impl Iterator<Item = &StatedEpisodes> {
        self.by_statements
            .iter()
            .filter(|group| self.stated.iter().all(|s| group.stated.contains(s)))
    }

    /// `log(rate)` tables of the causes that matter: for each, its weight, the log of its
    /// overall rate and per component the log ratio of each value's rate to the overall
    /// rate.
    fn log_rate_tables(&self, space: &BehaviorSpace) -> Vec<(f64, f64, Vec<Vec<f64>>)> {
        self.causes
            .iter()
            .zip(self.weights())
            .filter(|(_, weight)| *weight > 0.0)
            .map(|(c, weight)| {
                let overall = (c.counts.total() + 1.0) / (self.commands.total() + 2.0);
                let tables = space
                    .components()
                    .iter()
                    .enumerate()
                    .map(|(k, component)| {
                        (0..component.len())
                            .map(|v| {
                                let rate = (c.counts.at(k, v) + PRIOR_COMMANDS * overall)
                                    / (self.commands.at(k, v) + PRIOR_COMMANDS);
                                (rate / overall).ln()
                            })
                            .collect()
                    })
                    .collect();
                (weight, overall.ln(), tables)
            })
            .collect()
    }
}

impl CauseAware {
    /// Moves the episode's burdens into the earlier episodes' (once per episode).
    fn close_episode(&mut self) {
        if self.causes.iter().any(|c| c.burden > 0.0) {
            self.episodes += 1.0;
            if !self.stated.is_empty() {
                self.remember_statements();
            }
        }
        for c in &mut self.causes {
            c.past_burden += c.burden;
            c.burden = 0.0;
        }
    }

    /// Adds this episode's burdens to the earlier episodes whose operators stated the same.
    fn remember_statements(&mut self) {
        let index = match self
            .by_statements
            .iter()
            .position(|group| group.stated == self.stated)
        {
            Some(i) => i,
            None => {
                self.by_statements.push(StatedEpisodes {
                    stated: self.stated.clone(),
                    episodes: 0.0,
                    burdens: Vec::new(),
                });
                self.by_statements.len() - 1
            }
        };
        let group = &mut self.by_statements[index];
        group.episodes += 1.0;
        group.burdens.resize(self.causes.len(), 0.0);
        for (sum, c) in group.burdens.iter_mut().zip(&self.causes) {
            *sum += c.burden;
        }
    }
}

/// Predicted burden of `behavior`: the burden-weighted sum of its predicted cause rates.
fn predicted_burden(tables: &[(f64, f64, Vec<Vec<f64>>)], behavior: &Behavior) -> f64 {
    tables
        .iter()
        .map(|(burden, log_overall, per_component)| {
            let log_rate = log_overall
                + per_component
                    .iter()
                    .zip(behavior.indices())
                    .map(|(table, &v)| table[usize::from(v)])
                    .sum::<f64>();
            burden * log_rate.exp().min(1.0)
        })
        .sum()
}

impl Searcher for CauseAware {
    type Evidence = Evaluated;
    type Feedback = Outcome;

    fn name(&self) -> &str {
        STRATEGY.name
    }

    // It weighs signals by what earlier operators who stated the same bore, in every
    // context alike.
    fn reads_context(&self) -> bool {
        false
    }

    fn learns_across_episodes(&self) -> bool {
        true
    }

    fn begin_episode(&mut self, _space: &BehaviorSpace, _initial: &Behavior) {
        self.close_episode();
        self.stated.clear();
    }

    fn hear(&mut self, stated: &[Statement]) {
        self.stated = stated.to_vec();
        self.stated.sort();
    }

    fn observe(&mut self, behavior: &Behavior, outcome: &Outcome) {
        self.commands.add(behavior);
        if !outcome.is_untrustworthy() {
            return;
        }
        let signals = Signal::of(outcome);
        let share = outcome.weight / signals.len() as f64;
        for signal in signals {
            let index = match self.causes.iter().position(|c| c.signal == signal) {
                Some(i) => i,
                None => {
                    self.causes.push(CauseRecord {
                        signal,
                        counts: ValueCounts::default(),
                        burden: 0.0,
                        past_burden: 0.0,
                    });
                    self.causes.len() - 1
                }
            };
            let record = &mut self.causes[index];
            record.counts.add(behavior);
            record.burden += share;
        }
    }

    fn propose(
        &mut self,
        space: &BehaviorSpace,
        evaluated: &[Evaluated],
        rng: &mut dyn RngCore,
    ) -> Proposal {
        propose_untried(space, evaluated, rng, |tried, rng| {
            let pool = draw_untried(space, tried, CAUSE_AWARE_POOL, rng);
            self.last_pool = pool.len();
            let tables = self.log_rate_tables(space);
            cheapest(pool, |b| predicted_burden(&tables, b))
        })
    }

    fn rationale(&self, _proposed: &Behavior) -> Rationale {
        if self.weights().iter().all(|&weight| weight <= 0.0) {
            return Rationale::Explores {
                how: "no trouble counted yet: an untried behavior drawn uniformly".into(),
            };
        }
        let agreeing: f64 = self.agreeing().map(|group| group.episodes).sum();
        let stated = if self.stated.is_empty() || agreeing == 0.0 {
            String::new()
        } else {
            format!(", weighed as by {agreeing} earlier operators who stated the same")
        };
        Rationale::Expects {
            what: format!(
                "the fewest of the troubles this operator reacts to, of {} untried behaviors{stated}",
                self.last_pool
            )
            .into(),
            confidence: None,
        }
    }

    fn end_episode(&mut self, _evaluated: &[Evaluated], _settled: Option<&Behavior>) {
        self.close_episode();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Observations;
    use cbr_core::NamedComponent;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    /// Causes of a made-up pick-and-place domain: nothing here knows them.
    const DROPPED: Cause = Cause::from_static("dropped-item");
    const TOO_SLOW: Cause = Cause::from_static("too-slow");
    const OVERHEATED: Cause = Cause::from_static("overheated");

    #[test]
    fn moves_away_from_the_values_that_bring_the_operators_cause() {
        // Two components of 10 values. Dropped items happen only at low values of `a`;
        // slow runs only at low values of `b`. The operator of this episode is bothered
        // by dropped items alone, so the searcher should raise `a` and may leave `b`.
        let c = |name: &str| NamedComponent::numeric(name, "", 0.0, 1.0, 10).unwrap();
        let space = BehaviorSpace::new(vec![c("a"), c("b")]).unwrap();
        let mut searcher = CauseAware::new();
        for a in 0..10u16 {
            for b in 0..10u16 {
                let behavior = Behavior::new(&[a, b]);
                for _ in 0..5 {
                    let outcome = if a < 3 {
                        Outcome::interrupted(1.0, 1.0).stating(Some(DROPPED))
                    } else if b < 3 {
                        Outcome::interrupted(1.0, 1.0).stating(Some(TOO_SLOW))
                    } else {
                        Outcome::completed(1.0, 1.0)
                    };
                    searcher.observe(&behavior, &outcome);
                }
            }
        }
        // A new episode: the initial behavior drops items.
        searcher.end_episode(&[], None);
        let initial = Behavior::new(&[1, 8]);
        searcher.begin_episode(&space, &initial);
        for _ in 0..5 {
            searcher.observe(
                &initial,
                &Outcome::interrupted(1.0, 1.0).stating(Some(DROPPED)),
            );
        }
        let evaluated = [Evaluated {
            behavior: initial,
            time: 5.0,
        }];
        for seed in 0..20 {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            match searcher.propose(&space, &evaluated, &mut rng) {
                Proposal::Next(b) => assert!(b.get(0) >= 3, "{b:?} still drops items"),
                other => panic!("unexpected {other:?}"),
            }
        }
    }

    #[test]
    fn the_per_value_rate_by_hand() {
        // 10 commands in all, 4 with dropped items, all at a = 0 (4 of its 5 commands).
        // Overall rate (4 + 1) / (10 + 2) = 5/12. At a = 0: (4 + 2 * 5/12) / (5 + 2) =
        // (4 + 0.8333) / 7 = 0.690476; at a = 1: (0 + 0.8333) / (5 + 2) = 0.119048.
        let space =
            BehaviorSpace::new(vec![NamedComponent::numeric("a", "", 0.0, 1.0, 2).unwrap()])
                .unwrap();
        let mut searcher = CauseAware::new();
        let (low, high) = (Behavior::new(&[0]), Behavior::new(&[1]));
        for i in 0..5 {
            let o = if i < 4 {
                Outcome::interrupted(1.0, 1.0).stating(Some(DROPPED))
            } else {
                Outcome::completed(1.0, 1.0)
            };
            searcher.observe(&low, &o);
            searcher.observe(&high, &Outcome::completed(1.0, 1.0));
        }
        let tables = searcher.log_rate_tables(&space);
        assert_eq!(tables.len(), 1);
        // Burden 4, so the predicted burden is 4 * rate.
        assert!((predicted_burden(&tables, &low) - 4.0 * 0.690476).abs() < 1e-5);
        assert!((predicted_burden(&tables, &high) - 4.0 * 0.119048).abs() < 1e-5);
    }

    #[test]
    fn every_signal_is_counted_apart() {
        // Two stated causes, an observation and an unexplained outcome, each at its own
        // value of `a`: four records, each with the burden of its own outcomes.
        let space = crate::search::grid(&[4]);
        let mut searcher = CauseAware::new();
        let outcomes = [
            Outcome::failed(0.5, 1.0).stating(Some(DROPPED)),
            Outcome::failed(1.0, 1.0).stating(Some(TOO_SLOW)),
            Outcome::failed(1.5, 1.0).observing(Observations::NONE.with(2)),
            Outcome::failed(2.0, 1.0),
        ];
        for (v, outcome) in outcomes.iter().enumerate() {
            searcher.observe(&Behavior::new(&[v as u16]), outcome);
        }
        let seen: Vec<(Signal, f64)> = searcher
            .causes
            .iter()
            .map(|c| (c.signal, c.burden))
            .collect();
        assert_eq!(
            seen,
            [
                (Signal::Stated(DROPPED), 0.5),
                (Signal::Stated(TOO_SLOW), 1.0),
                (Signal::Observed(2), 1.5),
                (Signal::Unexplained, 2.0)
            ]
        );
        assert_eq!(searcher.log_rate_tables(&space).len(), 4);
        // The behavior with the lightest signal is predicted the least burdensome.
        let tables = searcher.log_rate_tables(&space);
        let burdens: Vec<f64> = (0..4u16)
            .map(|v| predicted_burden(&tables, &Behavior::new(&[v])))
            .collect();
        assert!(burdens.windows(2).all(|w| w[0] < w[1]), "{burdens:?}");
    }

    #[test]
    fn an_outcome_with_several_signals_shares_its_weight() {
        let mut searcher = CauseAware::new();
        let both = Outcome::interrupted(1.0, 1.0)
            .stating(Some(OVERHEATED))
            .observing(Observations::NONE.with(0));
        assert_eq!(
            Signal::of(&both),
            [Signal::Stated(OVERHEATED), Signal::Observed(0)]
        );
        searcher.observe(&Behavior::new(&[0]), &both);
        let burdens: Vec<f64> = searcher.causes.iter().map(|c| c.burden).collect();
        assert_eq!(burdens, [0.5, 0.5]);
        // A completion carries no signal.
        searcher.observe(&Behavior::new(&[0]), &Outcome::completed(1.0, 1.0));
        assert_eq!(searcher.causes.len(), 2);
    }

    #[test]
    fn statements_weigh_causes_as_operators_who_stated_the_same_by_hand() {
        // Two earlier episodes: an operator who stated "avoid-bumps" bore 3 of bumps
        // (observation 0); one who stated "not avoid-bumps" bore 2 unexplained.
        let bumps = Outcome::interrupted(1.0, 1.0).observing(Observations::NONE.with(0));
        let unexplained = Outcome::interrupted(1.0, 1.0);
        let avoid = [Statement::new("avoid-bumps", true)];
        let (space, b) = (crate::search::grid(&[4]), Behavior::new(&[0]));
        let mut searcher = CauseAware::new();
        searcher.begin_episode(&space, &b);
        searcher.hear(&avoid);
        for _ in 0..3 {
            searcher.observe(&b, &bumps);
        }
        searcher.end_episode(&[], None);
        searcher.begin_episode(&space, &b);
        searcher.hear(&[avoid[0].negated()]);
        for _ in 0..2 {
            searcher.observe(&b, &unexplained);
        }
        searcher.end_episode(&[], None);
        // Signal 0 is bumps, 1 unexplained. Means over both episodes: 3/2 and 2/2.
        searcher.begin_episode(&space, &b);
        assert_eq!(searcher.weights(), [1.5, 1.0]);
        // Stated "avoid-bumps": one agreeing episode, shrunk towards the mean with one
        // episode's weight: (3 + 1.5) / 2 and (0 + 1.0) / 2.
        searcher.hear(&avoid);
        assert_eq!(searcher.weights(), [2.25, 0.5]);
        // A statement no earlier operator made: the means.
        searcher.hear(&[Statement::new("hurry", true)]);
        assert_eq!(searcher.weights(), [1.5, 1.0]);
        // Statements heard again at the next episode's start are forgotten there.
        searcher.hear(&avoid);
        searcher.end_episode(&[], None);
        searcher.begin_episode(&space, &b);
        assert_eq!(searcher.weights(), [1.5, 1.0]);
    }

    #[test]
    fn an_episode_stating_more_agrees_with_one_stating_less() {
        let bumps = Outcome::interrupted(1.0, 1.0).observing(Observations::NONE.with(0));
        let (space, b) = (crate::search::grid(&[4]), Behavior::new(&[0]));
        let mut searcher = CauseAware::new();
        searcher.begin_episode(&space, &b);
        searcher.hear(&[
            Statement::new("hurry", false),
            Statement::new("avoid-bumps", true),
        ]);
        searcher.observe(&b, &bumps);
        searcher.end_episode(&[], None);
        searcher.begin_episode(&space, &b);
        searcher.hear(&[Statement::new("avoid-bumps", true)]);
        assert_eq!(searcher.agreeing().count(), 1);
        searcher.hear(&[Statement::new("avoid-bumps", false)]);
        assert_eq!(searcher.agreeing().count(), 0);
    }
}
