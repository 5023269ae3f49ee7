//! Cause-aware search: learn from the causes outcomes carry which component values bring
//! which causes, and move away from the causes this operator reacts to.
//!
//! Every command outcome is an observation of the behavior in use. For each cause an
//! outcome can carry (whatever names the domain gives them, plus "no cause stated"), the
//! searcher counts, per component and value, how many commands ended with that cause, so
//! it knows, for instance, that dropped items fall as one component rises while slow runs
//! rise with it. These counts persist across episodes (the physics of a robot
//! does not change with the operator) and grow within an episode with every command.
//!
//! How much each cause matters is its *burden*: the weight of this episode's
//! untrustworthy outcomes with that cause (what the current operator has shown it reacts
//! to), plus the mean burden of an earlier episode (so a cause this operator has not yet
//! met still counts as much as it usually does). A proposal draws a pool
//! of untried behaviors uniformly at random and takes the one whose predicted burden is
//! smallest. The rate of a cause at a behavior is predicted from the per-value rates of
//! its components, combined as independent multiplicative effects on the cause's overall
//! rate (a naive-Bayes reading of the counts), each per-value rate smoothed towards the
//! overall rate. Drawing the pool at random keeps the search exploring where the counts
//! say nothing; no rule about any particular domain or cause is written here.

use super::propose_untried;
use super::untried::draw_untried;
use crate::Cause;
use crate::estimate::OutcomeKind;
use crate::{Evaluated, Outcome};
use cbr_core::{Behavior, BehaviorSpace, Proposal, Searcher};
use rand::RngCore;

/// Untried behaviors drawn and scored per proposal.
pub const CAUSE_AWARE_POOL: usize = 128;

/// Weight of the overall rate in each per-value rate, in commands (a Beta-prior strength).
const PRIOR_COMMANDS: f64 = 2.0;

/// Counts of commands by component value.
#[derive(Clone, Debug, Default)]
struct ValueCounts {
    total: f64,
    /// `by_value[k][v]`: commands with component `k` at value index `v`.
    by_value: Vec<Vec<f64>>,
}

impl ValueCounts {
    fn add(&mut self, behavior: &Behavior) {
        self.total += 1.0;
        if self.by_value.len() < behavior.len() {
            self.by_value.resize(behavior.len(), Vec::new());
        }
        for (k, &v) in behavior.indices().iter().enumerate() {
            let counts = &mut self.by_value[k];
            let v = usize::from(v);
            if counts.len() <= v {
                counts.resize(v + 1, 0.0);
            }
            counts[v] += 1.0;
        }
    }

    fn at(&self, component: usize, value: usize) -> f64 {
        self.by_value
            .get(component)
            .and_then(|c| c.get(value))
            .copied()
            .unwrap_or(0.0)
    }
}

/// What is known about one cause.
#[derive(Clone, Debug)]
struct CauseRecord {
    cause: Option<Cause>,
    /// Commands that ended untrustworthy with this cause (all episodes).
    counts: ValueCounts,
    /// Weight of this episode's untrustworthy outcomes with this cause.
    burden: f64,
    /// Weight of the earlier episodes' untrustworthy outcomes with this cause.
    past_burden: f64,
}

/// The cause-aware searcher.
#[derive(Clone, Debug, Default)]
pub struct CauseAware {
    commands: ValueCounts,
    causes: Vec<CauseRecord>,
    /// Episodes ended so far.
    episodes: f64,
}

impl CauseAware {
    /// A cause-aware searcher that knows nothing yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// How much cause `c` matters now: this episode's burden, plus the mean burden of an
    /// earlier episode (the operators met so far), so a cause not yet met in this
    /// episode still counts as much as it usually does.
    fn weight(&self, c: &CauseRecord) -> f64 {
        c.burden + c.past_burden / self.episodes.max(1.0)
    }

    /// `log(rate)` tables of the causes that matter: for each, its weight, the log of its
    /// overall rate and per component the log ratio of each value's rate to the overall
    /// rate.
    fn log_rate_tables(&self, space: &BehaviorSpace) -> Vec<(f64, f64, Vec<Vec<f64>>)> {
        self.causes
            .iter()
            .filter(|c| self.weight(c) > 0.0)
            .map(|c| {
                let overall = (c.counts.total + 1.0) / (self.commands.total + 2.0);
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
                (self.weight(c), overall.ln(), tables)
            })
            .collect()
    }
}

impl CauseAware {
    /// Moves the episode's burdens into the earlier episodes' (once per episode).
    fn close_episode(&mut self) {
        if self.causes.iter().any(|c| c.burden > 0.0) {
            self.episodes += 1.0;
        }
        for c in &mut self.causes {
            c.past_burden += c.burden;
            c.burden = 0.0;
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
        "cause-aware"
    }

    fn learns_across_episodes(&self) -> bool {
        true
    }

    fn begin_episode(&mut self, _space: &BehaviorSpace, _initial: &Behavior) {
        self.close_episode();
    }

    fn observe(&mut self, behavior: &Behavior, outcome: &Outcome) {
        self.commands.add(behavior);
        if outcome.kind == OutcomeKind::Completed {
            return;
        }
        let index = match self.causes.iter().position(|c| c.cause == outcome.cause) {
            Some(i) => i,
            None => {
                self.causes.push(CauseRecord {
                    cause: outcome.cause,
                    counts: ValueCounts::default(),
                    burden: 0.0,
                    past_burden: 0.0,
                });
                self.causes.len() - 1
            }
        };
        let record = &mut self.causes[index];
        record.counts.add(behavior);
        record.burden += outcome.weight;
    }

    fn propose(
        &mut self,
        space: &BehaviorSpace,
        evaluated: &[Evaluated],
        rng: &mut dyn RngCore,
    ) -> Proposal {
        propose_untried(space, evaluated, rng, |tried, rng| {
            let pool = draw_untried(space, tried, CAUSE_AWARE_POOL, rng);
            let tables = self.log_rate_tables(space);
            pool.iter()
                .map(|b| (predicted_burden(&tables, b), *b))
                .fold(
                    None,
                    |best: Option<(f64, Behavior)>, (score, b)| match best {
                        Some((s, _)) if s <= score => best,
                        _ => Some((score, b)),
                    },
                )
                .map(|(_, b)| b)
        })
    }

    fn end_episode(&mut self, _evaluated: &[Evaluated], _settled: Option<&Behavior>) {
        self.close_episode();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
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
                        Outcome::interrupted(1.0, DROPPED, 1.0)
                    } else if b < 3 {
                        Outcome::interrupted(1.0, TOO_SLOW, 1.0)
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
            searcher.observe(&initial, &Outcome::interrupted(1.0, DROPPED, 1.0));
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
                Outcome::interrupted(1.0, DROPPED, 1.0)
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
    fn every_cause_a_domain_names_is_counted_apart() {
        // Three causes and an unstated one, each at its own value of `a`: four records,
        // each with the burden of its own outcomes.
        let space = crate::search::grid(&[4]);
        let mut searcher = CauseAware::new();
        let causes = [Some(DROPPED), Some(TOO_SLOW), Some(OVERHEATED), None];
        for (v, cause) in causes.iter().enumerate() {
            let behavior = Behavior::new(&[v as u16]);
            let outcome = Outcome {
                cause: *cause,
                ..Outcome::failed(0.5 * (v as f64 + 1.0), DROPPED, 1.0)
            };
            searcher.observe(&behavior, &outcome);
        }
        let seen: Vec<(Option<Cause>, f64)> = searcher
            .causes
            .iter()
            .map(|c| (c.cause, c.burden))
            .collect();
        assert_eq!(
            seen,
            [
                (Some(DROPPED), 0.5),
                (Some(TOO_SLOW), 1.0),
                (Some(OVERHEATED), 1.5),
                (None, 2.0)
            ]
        );
        assert_eq!(searcher.log_rate_tables(&space).len(), 4);
        // The behavior with the lightest cause is predicted the least burdensome.
        let tables = searcher.log_rate_tables(&space);
        let burdens: Vec<f64> = (0..4u16)
            .map(|v| predicted_burden(&tables, &Behavior::new(&[v])))
            .collect();
        assert!(burdens.windows(2).all(|w| w[0] < w[1]), "{burdens:?}");
    }
}
