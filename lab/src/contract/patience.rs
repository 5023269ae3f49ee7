//! An operator's patience with one run (docs/simulation.md, "The operators"): the time it
//! allows, past which it interrupts with some probability, and the later moment it gives
//! up and counts the run as failed.
//!
//! Every domain's operator watches a run the same way around its own reactions: it reads
//! the run's events in time order; the first event after its deadline (or the run's end
//! past it) makes it react to the lateness once, an interruption dated at the deadline;
//! an event after `give_up_factor x` the deadline is never seen, because the operator has
//! given up and failed the run at that moment. A run whose events end without an ending
//! is one that never ends: the operator waits past its deadline and gives up.
//! [`Patience::watch`] is that loop; a domain gives it the events and its reactions to
//! each, and every draw comes in the order the loop meets them (one draw for the
//! lateness, at the first event past the deadline, before that event's own reactions).

use crate::contract::attention::Attending;
use crate::contract::judgement::Judgement;
use rand::RngCore;
use trust::{Cause, OutcomeKind, OutcomeWeights};

/// How long an operator waits for one run, and what it does when the wait is too long.
///
/// ```
/// use lab::Judgement;
/// use lab::contract::attention::Attending;
/// use lab::contract::patience::Patience;
/// use rand::SeedableRng;
/// use rand_chacha::ChaCha8Rng;
/// use trust::{Cause, OutcomeWeights};
///
/// const LATE: Cause = Cause::from_static("late");
/// const BUMP: Cause = Cause::from_static("bump");
///
/// // Allows 10 s, never interrupts a late run, gives up at 20 s.
/// let patient = Patience { deadline_s: 10.0, p_interrupt: 0.0, give_up_factor: 2.0, cause: LATE };
/// let weights = OutcomeWeights::default();
/// let mut rng = ChaCha8Rng::seed_from_u64(3);
/// // A run that bumps at 4 s (never minded) and ends at 15 s completes at 15 s.
/// let events = [(4.0, "bump"), (15.0, "arrived")];
/// let judged = Attending::judge(1.0, |attending| {
///     patient.watch(events, &weights, attending, &mut rng, |_, _, t, event| {
///         (event == "arrived").then(|| Judgement::completed(weights.completed, t))
///     })
/// });
/// assert_eq!(judged, Judgement::completed(1.0, 15.0));
///
/// // One ending at 25 s is failed at 20 s, for lateness.
/// let late = [(4.0, "bump"), (25.0, "arrived")];
/// let judged = Attending::judge(1.0, |attending| {
///     patient.watch(late, &weights, attending, &mut rng, |_, _, t, event| {
///         (event == "arrived").then(|| Judgement::completed(weights.completed, t))
///     })
/// });
/// assert_eq!(judged, Judgement::failed(1.0, LATE, 20.0));
///
/// // An operator who always stops a late run stops it at its deadline.
/// let strict = Patience { p_interrupt: 1.0, ..patient };
/// let judged = Attending::judge(1.0, |attending| {
///     strict.watch(late, &weights, attending, &mut rng, |attending, rng, t, event| match event {
///         "bump" if attending.react(rng, 0.0, BUMP) => {
///             Some(Judgement::weighed(trust::OutcomeKind::Interrupted, BUMP, t, &weights))
///         }
///         "arrived" => Some(Judgement::completed(weights.completed, t)),
///         _ => None,
///     })
/// });
/// assert_eq!(judged, Judgement::interrupted(1.0, LATE, 10.0));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Patience {
    /// The time the operator allows for the run (s): its deadline.
    pub deadline_s: f64,
    /// The probability that it interrupts once the deadline has passed.
    pub p_interrupt: f64,
    /// It gives up at this multiple of the deadline and the run fails (at least 1).
    pub give_up_factor: f64,
    /// The cause of both: the interruption at the deadline and the failure at giving up.
    pub cause: Cause,
}

/// The give-up factor of an operator file that states none (serde's `default`): 2, an
/// operator calls a robot lost when it takes twice the time it should (docs/simulation.md,
/// "The operators"). Write `#[serde(default = "trustcbr::lab::contract::patience::default_give_up_factor")]`
/// on the field.
pub fn default_give_up_factor() -> f64 {
    2.0
}

impl Patience {
    /// The moment the operator gives up (s): `give_up_factor x deadline_s`.
    pub fn give_up_s(&self) -> f64 {
        self.deadline_s * self.give_up_factor
    }

    /// How a run whose `events` are `(time, event)` in time order ends for an operator
    /// `attending` to it with this patience, its judgements weighed by `weights`.
    ///
    /// At each event, first the deadline: the first event later than `deadline_s` (or the
    /// events' end, if none is) draws the lateness reaction once
    /// ([`Attending::react`] with `p_interrupt`), which interrupts the run at `deadline_s`.
    /// Then giving up: an event later than [`Patience::give_up_s`] is not watched, and the
    /// run fails at that moment. Otherwise `react(attending, rng, time, event)` says how
    /// the event ends the run, or `None` when the run goes on. Events that run out
    /// without an ending are a run that never ends: it fails when the operator gives up.
    pub fn watch<E, R: RngCore + ?Sized>(
        &self,
        events: impl IntoIterator<Item = (f64, E)>,
        weights: &OutcomeWeights,
        attending: &mut Attending,
        rng: &mut R,
        mut react: impl FnMut(&mut Attending, &mut R, f64, E) -> Option<Judgement>,
    ) -> Judgement {
        let give_up = self.give_up_s();
        let mut deadline_seen = false;
        let never_ends = [(f64::INFINITY, None)];
        let timeline = events.into_iter().map(|(t, e)| (t, Some(e)));
        for (t, event) in timeline.chain(never_ends) {
            if !deadline_seen && t > self.deadline_s {
                deadline_seen = true;
                if attending.react(rng, self.p_interrupt, self.cause) {
                    return self.ending(OutcomeKind::Interrupted, self.deadline_s, weights);
                }
            }
            if t > give_up {
                break;
            }
            if let Some(ending) = event.and_then(|e| react(attending, rng, t, e)) {
                return ending;
            }
        }
        self.ending(OutcomeKind::Failed, give_up, weights)
    }

    fn ending(&self, kind: OutcomeKind, t: f64, weights: &OutcomeWeights) -> Judgement {
        Judgement::weighed(kind, self.cause, t, weights)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    const LATE: Cause = Cause::from_static("late");
    const BUMP: Cause = Cause::from_static("bump");

    fn patience(p_interrupt: f64) -> Patience {
        Patience {
            deadline_s: 10.0,
            p_interrupt,
            give_up_factor: 1.5,
            cause: LATE,
        }
    }

    fn weights() -> OutcomeWeights {
        OutcomeWeights {
            completed: 0.5,
            default: 2.0,
            by_cause: [(BUMP, 3.0)].into_iter().collect(),
        }
    }

    /// The judgement of `events` (`true`: a bump the operator always minds; `false`: the
    /// run's end) and the events the operator was asked about.
    fn judge(patience: Patience, events: &[(f64, bool)], attention: f64) -> (Judgement, Vec<f64>) {
        let weights = weights();
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut asked = Vec::new();
        let judged = Attending::judge(attention, |attending| {
            patience.watch(
                events.iter().copied(),
                &weights,
                attending,
                &mut rng,
                |attending, rng, t, bump| {
                    asked.push(t);
                    if !bump {
                        return Some(Judgement::completed(weights.completed, t));
                    }
                    attending
                        .react(rng, 1.0, BUMP)
                        .then(|| Judgement::weighed(OutcomeKind::Interrupted, BUMP, t, &weights))
                },
            )
        });
        (judged, asked)
    }

    #[test]
    fn a_run_ending_before_the_deadline_is_the_events_judgement() {
        let (judged, asked) = judge(patience(1.0), &[(3.0, true), (8.0, false)], 1.0);
        assert_eq!(judged, Judgement::interrupted(3.0, BUMP, 3.0));
        assert_eq!(asked, [3.0]);
        let (judged, _) = judge(patience(1.0), &[(8.0, false)], 1.0);
        assert_eq!(judged, Judgement::completed(0.5, 8.0));
    }

    #[test]
    fn the_lateness_is_drawn_at_the_first_event_past_the_deadline_and_dated_at_it() {
        // Always interrupting: the run ending at 12 s is stopped at 10 s, its end unseen.
        let (judged, asked) = judge(patience(1.0), &[(12.0, false)], 1.0);
        assert_eq!(judged, Judgement::interrupted(2.0, LATE, 10.0));
        assert!(asked.is_empty());
        // Never interrupting: the run completes at 12 s, before giving up at 15 s.
        let (judged, asked) = judge(patience(0.0), &[(12.0, false)], 1.0);
        assert_eq!(judged, Judgement::completed(0.5, 12.0));
        assert_eq!(asked, [12.0]);
    }

    #[test]
    fn past_giving_up_nothing_is_watched_and_the_run_fails_then() {
        let (judged, asked) = judge(patience(0.0), &[(16.0, false)], 1.0);
        assert_eq!(judged, Judgement::failed(2.0, LATE, 15.0));
        assert!(asked.is_empty());
    }

    #[test]
    fn a_run_that_never_ends_meets_the_deadline_then_the_operator_gives_up() {
        let (judged, _) = judge(patience(1.0), &[], 1.0);
        assert_eq!(judged, Judgement::interrupted(2.0, LATE, 10.0));
        let (judged, _) = judge(patience(0.0), &[], 1.0);
        assert_eq!(judged, Judgement::failed(2.0, LATE, 15.0));
    }

    #[test]
    fn an_inattentive_operator_overlooks_the_deadline_and_says_so() {
        let (judged, _) = judge(patience(1.0), &[(12.0, false)], 0.0);
        assert_eq!(
            judged,
            Judgement::completed(0.5, 12.0).overlooking(Some(LATE))
        );
    }

    #[test]
    fn each_lateness_reaction_is_one_draw_before_the_event_s_own() {
        // The deadline's draw, then the bump's: the same two draws as a hand-written loop.
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut plain = ChaCha8Rng::seed_from_u64(11);
        let weights = weights();
        let mut attending = Attending::new(1.0);
        let judged = patience(0.5).watch(
            [(12.0, ())],
            &weights,
            &mut attending,
            &mut rng,
            |attending, rng, t, ()| {
                attending
                    .react(rng, 0.5, BUMP)
                    .then(|| Judgement::weighed(OutcomeKind::Interrupted, BUMP, t, &weights))
            },
        );
        let late = rand::Rng::random::<f64>(&mut plain) < 0.5;
        let bumped = !late && rand::Rng::random::<f64>(&mut plain) < 0.5;
        let expected = match (late, bumped) {
            (true, _) => Judgement::interrupted(2.0, LATE, 10.0),
            (false, true) => Judgement::interrupted(3.0, BUMP, 12.0),
            (false, false) => Judgement::failed(2.0, LATE, 15.0),
        };
        assert_eq!(judged, expected);
        assert_eq!(rng.next_u64(), plain.next_u64());
    }
}
