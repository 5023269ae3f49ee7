//! The mission oracle: the reference a mission's arms are measured against
//! (docs/missions.md#the-oracle-labmission_oracle).
//!
//! The oracle is an agent on the same missions as the arms (the same first operator,
//! changes, runs and stated reasons: [`crate::mission`]'s streams) with two things no arm
//! has: it is **told of every change** (a takeover or a shift) the moment it happens, and it
//! **knows the landscape** of every member of the population: per behavior, whether it is
//! trustworthy for that member and the exact walk of its trust estimate
//! ([`crate::reference::known_operator`], the known-operator limit's estimate). With them it acts as the
//! known-operator limit's agent does:
//!
//! - at the mission's start, and at a change while it is still adapting, it begins an
//!   episode for the (new) member and tries behaviors in the order that minimises the
//!   expected untrustworthy commands until one is accepted (ascending expected
//!   untrustworthy commands over acceptance probability, [`limit::optimal_order`]);
//! - at a change after it settled, it keeps the behavior in use when that costs no more in
//!   expectation: its untrustworthy commands at the member's rate over the mean gap to the
//!   next change (gaps are memoryless), against an episode in the member's order without
//!   it ([`limit::order_cost`]); otherwise it begins that episode. A change *needs*
//!   adaptation, as for the arms, when the behavior in use is not trustworthy for the new
//!   member (its expected estimate falls); a behavior the member trusts may still be
//!   given up for one that fails less, and one it does not may be kept when every
//!   alternative costs more.
//!
//! Each tried behavior's estimate starts at 0 and walks with the outcomes the simulated
//! operator gives (the runs of the mission's own stream), so its walk, acceptance or
//! rejection are the adapter's rule ([`trust::Thresholds::verdict`]); its harm follows from
//! the behaviors it uses. Its records are counted as an arm's are ([`ChangeRecord`](crate::mission::ChangeRecord):
//! untrustworthy commands from the change until it settled again on an accepted behavior,
//! or the next change, or the end), so each arm's figures are compared with it as
//! multiples ([`crate::mission::report`]).
//!
//! Simulated rather than computed from the law: a change's cost is cut by the next change
//! and a mission's harm depends on which behaviors are in use when, both of which the
//! simulation on the mission's own course counts exactly as the arms' are counted, while
//! the law ([`crate::reference::limit_law`]) is of one uninterrupted episode.

use crate::contract::domain::Domain;
use crate::experiment::plan::PlanError;
use crate::experiment::simulate::{self, Conditions, SimulatedCommand};
use crate::mission::course::{Course, Judges, StreamName, begin_change, count_untrustworthy};
use crate::mission::plan::MissionPlan;
use crate::mission::record::{ChangeKind, OracleRecord};
use crate::reference::known_operator::{KnownLimitError, KnownOperator, known_operator};
use crate::reference::landscape::LandscapeError;
use crate::reference::limit;
use crate::seeds::{Purpose, stream, stream_seed};
use cbr_core::Behavior;
use rayon::prelude::*;
use trust::{OutcomeKind, TrustEstimate, Verdict};

/// What the oracle knows of one member of the population, per behavior in rank order.
#[derive(Clone, Debug, PartialEq)]
pub struct MemberKnowledge {
    /// Whether it is trustworthy for the member.
    pub trusted: Vec<bool>,
    /// The probability that one of its commands is untrustworthy.
    pub untrustworthy_rate: Vec<f64>,
    /// The probability that an episode accepts it.
    pub accept: Vec<f64>,
    /// The expected untrustworthy commands until an episode accepts or rejects it.
    pub untrustworthy: Vec<f64>,
    /// The behaviors (ranks) in the order the oracle tries them in an episode for the
    /// member: the known-operator agent's for untrustworthy commands.
    pub order: Vec<usize>,
}

impl MemberKnowledge {
    /// What the known-operator estimate `known` tells the oracle.
    pub fn of(known: &KnownOperator) -> Self {
        let accept: Vec<f64> = known.walks.iter().map(|w| w.accept).collect();
        let untrustworthy: Vec<f64> = known.walks.iter().map(|w| w.untrustworthy).collect();
        Self {
            trusted: known.trusted.clone(),
            untrustworthy_rate: known.untrustworthy_rate.clone(),
            order: limit::optimal_order(&accept, &untrustworthy),
            accept,
            untrustworthy,
        }
    }

    /// The expected untrustworthy commands of an episode in the member's order without
    /// the behavior of rank `without`, until one is accepted.
    fn readaptation_cost(&self, without: usize) -> f64 {
        let order: Vec<usize> = self
            .order
            .iter()
            .copied()
            .filter(|&r| r != without)
            .collect();
        limit::order_cost(&self.accept, &self.untrustworthy, &order)
    }

    /// Whether keeping the behavior of rank `rank` costs no more untrustworthy commands
    /// in expectation than adapting without it: its rate over the `gap` commands expected
    /// until the next change, against [`MemberKnowledge::readaptation_cost`].
    fn keeps(&self, rank: usize, gap: f64) -> bool {
        self.untrustworthy_rate[rank] * gap <= self.readaptation_cost(rank)
    }
}

/// The oracle of one mission plan: what it knows of each member in each context.
#[derive(Clone, Debug, PartialEq)]
pub struct MissionOracle {
    /// Each member's landscape, as the oracle uses it: in the population's order, and with
    /// context switches, the population in the first context, then in the second, and so
    /// on (member `k` in context `c` at `c * population + k`).
    pub members: Vec<MemberKnowledge>,
    /// The population's size.
    population: usize,
}

/// An episode under way: the member in its context it is for (its place in
/// [`MissionOracle::members`]), the next place in its order, the behavior excluded from
/// it, and the estimate of the behavior in use.
struct Episode {
    member: usize,
    next: usize,
    excluded: Option<Behavior>,
    estimate: TrustEstimate,
}

impl MissionOracle {
    /// Estimates what the oracle knows of each member of `plan`'s population in each of
    /// its contexts with `plan.limit` under the plan's thresholds; the landscape of place
    /// `k` of [`MissionOracle::members`] draws from the stream (`seed`, `index`, `k`) of
    /// [`Purpose::Limit`].
    pub fn estimate<D: Domain>(
        plan: &MissionPlan<'_, D>,
        seed: u64,
        index: u64,
    ) -> Result<Self, PlanError> {
        let judges = Judges::of(plan);
        let population = plan.operators.len();
        let contexts = plan.contexts.as_ref().map_or(1, |c| c.among.len());
        let members = (0..contexts * population)
            .map(|k| {
                let name = &plan.operators[k % population].0;
                let operator = judges.judge(k % population, k / population);
                let seed = stream_seed(seed, index, k as u64, Purpose::Limit);
                let known = known_operator(
                    plan.domain,
                    operator,
                    plan.adapter.thresholds,
                    plan.limit,
                    seed,
                );
                match known {
                    Ok(known) => Ok(MemberKnowledge::of(&known)),
                    Err(KnownLimitError::Landscape(LandscapeError::Interrupted(stop))) => {
                        Err(stop.into())
                    }
                    Err(reason) => Err(PlanError::Oracle {
                        plan: plan.name.clone(),
                        operator: name.clone(),
                        reason,
                    }),
                }
            })
            .collect::<Result<Vec<_>, PlanError>>()?;
        Ok(Self {
            members,
            population,
        })
    }

    /// The place in [`MissionOracle::members`] of member `member` in context `context`.
    fn knowledge(&self, member: usize, context: usize) -> usize {
        context * self.population + member
    }

    /// Runs the oracle through the mission `named` of `plan`.
    pub(crate) fn run_mission<D: Domain>(
        &self,
        plan: &MissionPlan<'_, D>,
        named: StreamName,
    ) -> Result<OracleRecord, PlanError> {
        let Course {
            first,
            first_context,
            scheduled,
            ..
        } = Course::of(plan, named);
        let judges = Judges::of(plan);
        let m = u64::from(named.mission);
        let mut runs = stream(named.seed, named.plan, m, Purpose::Runs);
        let mut stated = stream(named.seed, named.plan, m, Purpose::Feedback);
        let thresholds = plan.adapter.thresholds;
        let space = plan.domain.space();
        let mut record = OracleRecord {
            mission: named.mission,
            changes: Vec::new(),
            readaptations: 0,
            failures: 0,
            overlooked: 0,
            untrustworthy: 0,
        };
        let (mut member, mut context) = (first, first_context);
        let mut start = Episode {
            member: self.knowledge(member, context),
            next: 0,
            excluded: None,
            estimate: TrustEstimate::default(),
        };
        let mut behavior = self
            .next_candidate(&mut start, space)
            .expect("a space holds at least one behavior");
        let mut episode = Some(start);
        let mut felt = 0.0f64;
        let mut upcoming = scheduled.iter().peekable();
        let mut waiting: Option<usize> = None;
        for c in 0..plan.commands {
            while let Some(change) = upcoming.next_if(|s| s.at == c) {
                (member, context) = (change.operator, change.context);
                if change.kind == ChangeKind::Takeover {
                    felt = 0.0;
                }
                let knowing = self.knowledge(member, context);
                let knows = &self.members[knowing];
                let rank = space.rank(&behavior) as usize;
                let needed = !knows.trusted[rank];
                let k = begin_change(&mut record.changes, change, needed);
                waiting = Some(k);
                if episode.is_some() || !knows.keeps(rank, plan.mean_gap()) {
                    record.readaptations += 1;
                    let mut fresh = Episode {
                        member: knowing,
                        next: 0,
                        excluded: needed.then_some(behavior),
                        estimate: TrustEstimate::default(),
                    };
                    let next = self.next_candidate(&mut fresh, space).unwrap_or(behavior);
                    if next != behavior {
                        record.changes[k].notice(c);
                    }
                    behavior = next;
                    episode = Some(fresh);
                }
            }
            let attention = plan.complacency.map(|c| c.attention(felt));
            let operator = judges.judge(member, context);
            let channel = plan
                .feedback
                .unwrap_or_else(|| plan.domain.feedback(operator));
            let SimulatedCommand { judgement, outcome } = simulate::command(
                plan.domain,
                &behavior,
                operator,
                Conditions {
                    attention,
                    goal_change_at: None,
                },
                channel,
                &mut runs,
                &mut stated,
            )
            .map_err(|refused| refused.in_plan(&plan.name, plan.domain.name()))?;
            record.failures += u32::from(outcome.kind == OutcomeKind::Failed);
            record.overlooked += u32::from(judgement.overlooked.is_some());
            if outcome.is_untrustworthy() {
                count_untrustworthy(&mut record.untrustworthy, &mut record.changes, waiting);
            }
            if let Some(c) = plan.complacency {
                felt = c.setting.felt_after(felt, &outcome);
            }
            let Some(e) = episode.as_mut() else {
                continue;
            };
            e.estimate.record(&outcome);
            match e.estimate.verdict(&thresholds) {
                Verdict::Undecided => {}
                Verdict::Trustworthy => {
                    episode = None;
                    if let Some(k) = waiting.take() {
                        record.changes[k].trusted_again = Some(c + 1 - record.changes[k].at);
                    }
                }
                Verdict::Untrustworthy => match self.next_candidate(e, space) {
                    Some(next) => {
                        if let Some(k) = waiting {
                            record.changes[k].notice(c + 1);
                        }
                        behavior = next;
                    }
                    // Every behavior rejected: the last one stays in use, untrusted.
                    None => episode = None,
                },
            }
        }
        Ok(record)
    }

    /// The next behavior of `episode`'s order (skipping the excluded one), its estimate
    /// restarted; `None` once the order is exhausted.
    fn next_candidate(
        &self,
        episode: &mut Episode,
        space: &cbr_core::BehaviorSpace,
    ) -> Option<Behavior> {
        let order = &self.members[episode.member].order;
        while let Some(&rank) = order.get(episode.next) {
            episode.next += 1;
            let candidate = space.unrank(rank as u64);
            if Some(candidate) != episode.excluded {
                episode.estimate = TrustEstimate::default();
                return Some(candidate);
            }
        }
        None
    }
}

/// The oracle's missions of every plan, each plan's in parallel.
pub(crate) fn run_oracles<D: Domain>(
    plans: &[MissionPlan<'_, D>],
    seed: u64,
) -> Result<Vec<Vec<OracleRecord>>, PlanError> {
    plans
        .iter()
        .enumerate()
        .map(|(p, plan)| {
            let oracle = MissionOracle::estimate(plan, seed, p as u64)?;
            (0..plan.missions)
                .into_par_iter()
                .map(|mission| {
                    crate::interrupt::check()?;
                    oracle.run_mission(
                        plan,
                        StreamName {
                            seed,
                            plan: p as u64,
                            mission,
                        },
                    )
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Judgement;
    use crate::mission::{ChangeRecord, Changes, Noticed};
    use crate::reference::known_operator::LimitSettings;
    use crate::testing::ToyDomain;
    use trust::{AdapterConfig, Cause};

    const BUMPED: Cause = Cause::from_static("bumped");

    /// The value of the one component an operator is pleased with (every command of it
    /// completes, every other fails), or none (every command fails).
    struct Pleased(Option<u16>);

    impl crate::SimulatedOperator for Pleased {}

    fn toy() -> ToyDomain<Pleased> {
        ToyDomain::grid("line", &[4], &[BUMPED], |b, pleased: &Pleased, _, _| {
            if pleased.0 == Some(b.indices()[0]) {
                Judgement::completed(1.0, 1.0)
            } else {
                Judgement::failed(1.0, BUMPED, 1.0)
            }
        })
    }

    fn operators() -> Vec<(String, Pleased)> {
        vec![
            ("zero".to_owned(), Pleased(Some(0))),
            ("three".to_owned(), Pleased(Some(3))),
            ("nobody".to_owned(), Pleased(None)),
        ]
    }

    fn plan<'a>(
        domain: &'a ToyDomain<Pleased>,
        operators: &'a [(String, Pleased)],
    ) -> MissionPlan<'a, ToyDomain<Pleased>> {
        MissionPlan {
            name: "line".into(),
            domain,
            operators,
            missions: 1,
            commands: 60,
            changes: Changes {
                every: 12.0,
                takeover: 0.5,
            },
            contexts: None,
            complacency: None,
            adapter: AdapterConfig::default(),
            arms: Vec::new(),
            feedback: None,
            truth_runs: 10,
            limit: LimitSettings {
                runs: 20,
                budget: 80,
                candidates: 0,
                candidate_runs: 0,
                reference_episodes: 0,
            },
            competence: None,
            offer_safer: false,
            change_detector: None,
        }
    }

    fn knowledge(domain: &ToyDomain<Pleased>, operators: &[(String, Pleased)]) -> MissionOracle {
        let plan = plan(domain, operators);
        MissionOracle::estimate(&plan, 3, 0).unwrap()
    }

    fn change(
        at: u32,
        kind: ChangeKind,
        needed: bool,
        again: Option<u32>,
        untrustworthy: u32,
    ) -> ChangeRecord {
        ChangeRecord {
            at,
            kind,
            needed,
            trusted_again: again,
            untrustworthy,
            back: false,
            start: None,
            noticed: None,
        }
    }

    #[test]
    fn the_oracle_knows_each_member_s_region_and_tries_its_best_behaviors_first() {
        let (domain, operators) = (toy(), operators());
        let oracle = knowledge(&domain, &operators);
        // Every run is certain: the favourite is accepted after 5 completions, any other
        // behavior rejected after 5 failures (5 untrustworthy commands).
        let [zero, three, nobody] = oracle.members.as_slice() else {
            panic!("three members")
        };
        assert_eq!(zero.trusted, [true, false, false, false]);
        assert_eq!(zero.order, [0, 1, 2, 3]);
        assert_eq!(three.trusted, [false, false, false, true]);
        assert_eq!(three.order, [3, 0, 1, 2]);
        assert_eq!(nobody.trusted, [false; 4]);
        assert_eq!(nobody.order, [0, 1, 2, 3]);
        assert_eq!(
            (three.untrustworthy_rate[3], three.untrustworthy_rate[0]),
            (0.0, 1.0)
        );
        // Adapting for three without 0 tries 3 first and pays nothing; for nobody without
        // 3 it tries 0, 1, 2, each rejected after 5 failures.
        assert_eq!(three.readaptation_cost(0), 0.0);
        assert_eq!(nobody.readaptation_cost(3), 15.0);
        assert!(!three.keeps(0, 1.0) && nobody.keeps(3, 15.0) && !nobody.keeps(3, 15.5));
    }

    #[test]
    fn a_mission_of_the_oracle_by_hand() {
        let (domain, operators) = (toy(), operators());
        let plan = plan(&domain, &operators);
        let oracle = knowledge(&domain, &operators);
        let named = StreamName {
            seed: 3,
            plan: 0,
            mission: 1,
        };
        // The mission: `nobody` first, then `three` at 12, `nobody` at 21, `three` at 23,
        // `nobody` at 54; 60 commands.
        let course = Course::of(&plan, named);
        let schedule: Vec<(u32, usize)> = course
            .scheduled
            .iter()
            .map(|s| (s.at, s.operator))
            .collect();
        assert_eq!(
            (course.first, schedule),
            (2, vec![(12, 1), (21, 2), (23, 1), (54, 2)])
        );
        let kinds: Vec<ChangeKind> = course.scheduled.iter().map(|s| s.kind).collect();
        let record = oracle.run_mission(&plan, named).unwrap();
        // 0-11: nobody rejects 0 (0-4) and 1 (5-9), then 2 fails twice: 12 failures.
        // 12: still adapting: an episode for three, 2 given up at once (noticed after 0
        //     commands) and 3 accepted after 5 completions (12-16).
        // 21: 3 is not trusted by nobody, but kept: it fails at rate 1 over a mean gap of
        //     12 commands, and any episode without it 3 x 5 = 15 times; it fails twice.
        // 23: three trusts 3 (rate 0): kept.
        // 54: nobody: kept, it fails 6 times (54-59).
        assert_eq!(
            record.changes,
            [
                ChangeRecord {
                    noticed: Some(Noticed {
                        after: 0,
                        untrustworthy: 0
                    }),
                    ..change(12, kinds[0], true, Some(5), 0)
                },
                change(21, kinds[1], true, None, 2),
                change(23, kinds[2], false, None, 0),
                change(54, kinds[3], true, None, 6),
            ]
        );
        assert_eq!(record.readaptations, 1);
        assert_eq!(
            (record.failures, record.overlooked, record.untrustworthy),
            (20, 0, 20)
        );
        assert_eq!(record.harm(), 20);
    }

    #[test]
    fn the_oracle_keeps_a_behavior_the_new_member_trusts() {
        let domain = toy();
        let operators = vec![
            ("three".to_owned(), Pleased(Some(3))),
            ("also-three".to_owned(), Pleased(Some(3))),
        ];
        let plan = plan(&domain, &operators);
        let oracle = knowledge(&domain, &operators);
        for mission in 0..6 {
            let named = StreamName {
                seed: 3,
                plan: 0,
                mission,
            };
            let record = oracle.run_mission(&plan, named).unwrap();
            // 3 is accepted after commands 0-4 and kept through every later change: none
            // needed an adaptation, none is trusted again (it never stopped being), and
            // nothing went wrong. A change before 5 begins the episode again, accepted
            // after 5 more completions.
            assert!(!record.changes.is_empty());
            for c in &record.changes {
                let again = (c.at < 5).then_some(5);
                assert_eq!(
                    (c.needed, c.trusted_again, c.untrustworthy),
                    (false, again, 0),
                    "{c:?}"
                );
            }
            let early = record.changes.iter().filter(|c| c.at < 5).count() as u32;
            assert_eq!((record.readaptations, record.harm()), (early, 0));
        }
    }
}
