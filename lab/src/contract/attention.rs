//! An operator's attention while it judges one run (docs/simulation.md, "Complacency"):
//! each reaction it would have with probability `p` happens with probability
//! `p * attention`, on the same single draw, and the first problem it overlooks is kept for
//! the judgement.
//!
//! One draw per reaction, compared with `p * attention`, is what makes an operator at
//! attention 1 judge exactly as the operator without attention, draw for draw: the
//! contract [`Attentive::run_attending`](crate::Attentive::run_attending) states and
//! `lab::testing::check_domain` checks (feature `testing`). A domain's `judge_attending`
//! is [`Attending::judge`] over its way of watching a run, which asks the [`Attending`] it
//! is handed at each reaction; its `judge` is `judge_attending` at attention 1.

use crate::contract::judgement::Judgement;
use rand::{Rng, RngCore};
use trust::{Cause, OutcomeKind, OutcomeWeights};

/// The attention of an operator judging one run, and the first problem it overlooked.
///
/// ```
/// use lab::Judgement;
/// use lab::contract::attention::Attending;
/// use rand::SeedableRng;
/// use rand_chacha::ChaCha8Rng;
/// use trust::Cause;
///
/// const BUMP: Cause = Cause::from_static("bump");
/// const LATE: Cause = Cause::from_static("late");
///
/// // An operator who notices nothing: it would always react to a bump, and overlooks it.
/// let mut rng = ChaCha8Rng::seed_from_u64(1);
/// let mut blind = Attending::new(0.0);
/// assert!(!blind.react(&mut rng, 1.0, BUMP));
/// assert!(!blind.react(&mut rng, 1.0, LATE));
/// assert_eq!(blind.overlooked(), Some(BUMP), "the first problem overlooked");
/// let judged = blind.finish(Judgement::completed(1.0, 30.0));
/// assert_eq!(judged.overlooked, Some(BUMP));
///
/// // A reaction it would never have is not overlooked: there was nothing to notice.
/// let mut calm = Attending::new(0.0);
/// assert!(!calm.react(&mut rng, 0.0, BUMP));
/// assert_eq!(calm.overlooked(), None);
///
/// // A whole judgement: an operator who would always stop the robot at a bump, and
/// // always at the deadline, watching a run with a bump at 2 s that ends at 8 s, past
/// // its deadline; at attention 0 it overlooks both, and the judgement names the bump.
/// let judged = Attending::judge(0.0, |attending| {
///     if attending.react(&mut rng, 1.0, BUMP) {
///         return Judgement::interrupted(1.0, BUMP, 2.0);
///     }
///     if attending.react(&mut rng, 1.0, LATE) {
///         return Judgement::interrupted(1.0, LATE, 6.0);
///     }
///     Judgement::completed(1.0, 8.0)
/// });
/// assert_eq!(judged, Judgement::completed(1.0, 8.0).overlooking(Some(BUMP)));
///
/// // Fully attentive, it reacts exactly when `draw < p`, on the same draws.
/// let mut attentive = Attending::new(1.0);
/// let mut same = ChaCha8Rng::seed_from_u64(7);
/// let mut plain = ChaCha8Rng::seed_from_u64(7);
/// for p in [0.1, 0.5, 0.9] {
///     use rand::Rng;
///     assert_eq!(attentive.react(&mut same, p, BUMP), plain.random::<f64>() < p);
/// }
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Attending {
    attention: f64,
    overlooked: Option<Cause>,
}

impl Attending {
    /// An operator whose `attention`, in `[0, 1]`, is the chance it notices a problem it
    /// would react to (1: it notices all it minds); nothing overlooked yet.
    pub fn new(attention: f64) -> Self {
        Self {
            attention,
            overlooked: None,
        }
    }

    /// Whether the operator reacts to `cause`, which it minds with probability `p`: one
    /// draw `d` from `rng`, a reaction when `d < p * attention`. When it would have
    /// reacted attentively (`d < p`) but does not, `cause` is overlooked (kept if it is the
    /// first).
    pub fn react<R: RngCore + ?Sized>(&mut self, rng: &mut R, p: f64, cause: Cause) -> bool {
        let draw = rng.random::<f64>();
        if draw < p * self.attention {
            return true;
        }
        if draw < p && self.overlooked.is_none() {
            self.overlooked = Some(cause);
        }
        false
    }

    /// An interruption for `cause` at `t` (s), weighed as `weights` weigh `cause`, when the
    /// operator reacts to it ([`Attending::react`] with `p`: one draw); `None` when it
    /// lets the run go on. The usual reaction inside [`crate::contract::patience::Patience::watch`].
    pub fn interrupts<R: RngCore + ?Sized>(
        &mut self,
        rng: &mut R,
        p: f64,
        cause: Cause,
        t: f64,
        weights: &OutcomeWeights,
    ) -> Option<Judgement> {
        self.react(rng, p, cause)
            .then(|| Judgement::weighed(OutcomeKind::Interrupted, cause, t, weights))
    }

    /// The judgement `watch` returns for an operator at `attention`, naming the first
    /// problem it overlooked: the whole of a domain's `judge_attending` (its `watch` asks
    /// the [`Attending`] it is handed at each reaction).
    pub fn judge(attention: f64, watch: impl FnOnce(&mut Attending) -> Judgement) -> Judgement {
        let mut attending = Self::new(attention);
        let judgement = watch(&mut attending);
        attending.finish(judgement)
    }

    /// The first problem overlooked so far.
    pub fn overlooked(&self) -> Option<Cause> {
        self.overlooked
    }

    /// `judgement` naming the first problem overlooked before it
    /// ([`Judgement::overlooked`]).
    #[must_use]
    pub fn finish(&self, judgement: Judgement) -> Judgement {
        judgement.overlooking(self.overlooked)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    const BUMP: Cause = Cause::from_static("bump");
    const LATE: Cause = Cause::from_static("late");

    /// A generator whose every `f64` draw is `value` (rand's `f64` is the top 53 bits of a
    /// `u64` over 2^53).
    struct Fixed(f64);

    impl RngCore for Fixed {
        fn next_u32(&mut self) -> u32 {
            (self.next_u64() >> 32) as u32
        }
        fn next_u64(&mut self) -> u64 {
            ((self.0 * (1u64 << 53) as f64) as u64) << 11
        }
        fn fill_bytes(&mut self, dest: &mut [u8]) {
            dest.fill(0);
        }
    }

    #[test]
    fn a_draw_below_p_times_attention_reacts_between_it_and_p_overlooks() {
        // p = 0.8, attention 0.5: react below 0.4, overlook in [0.4, 0.8), nothing above.
        for (draw, reacts, overlooked) in [
            (0.25, true, None),
            (0.375, true, None),
            (0.5, false, Some(BUMP)),
            (0.75, false, Some(BUMP)),
            (0.875, false, None),
        ] {
            let mut attending = Attending::new(0.5);
            assert_eq!(
                attending.react(&mut Fixed(draw), 0.8, BUMP),
                reacts,
                "{draw}"
            );
            assert_eq!(attending.overlooked(), overlooked, "{draw}");
        }
    }

    #[test]
    fn the_first_problem_overlooked_is_kept() {
        let mut attending = Attending::new(0.25);
        assert!(!attending.react(&mut Fixed(0.5), 1.0, LATE));
        assert!(!attending.react(&mut Fixed(0.5), 1.0, BUMP));
        assert!(attending.react(&mut Fixed(0.125), 1.0, BUMP));
        let judged = attending.finish(Judgement::interrupted(1.0, BUMP, 3.0));
        assert_eq!(judged.overlooked, Some(LATE));
        assert_eq!(judged.truth, Some(BUMP));
    }

    #[test]
    fn each_reaction_takes_exactly_one_draw() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let mut plain = ChaCha8Rng::seed_from_u64(5);
        let mut attending = Attending::new(0.3);
        for p in [0.0, 0.2, 1.0, 0.7] {
            attending.react(&mut rng, p, BUMP);
            let _: f64 = plain.random();
        }
        assert_eq!(rng.next_u64(), plain.next_u64());
    }
}
