//! A parametric family of operators between two poles, whose one parameter, `conflict` in
//! `[0, 1]`, sets how much its members disagree (docs/simulation.md, "Operators who
//! disagree"); the domain says what the poles and the members in between are.
//!
//! A member sits at a position `x` in `[-1, 1]`: 0 is the domain's *base* operator, -1
//! and 1 its two *poles*, and `|x|` how far of the way from the base to the pole on its
//! side the member has moved. [`two_pole_family`] draws `size` positions from a seeded,
//! portable generator (ChaCha8): per member, a side (`bool`), then a spread `u` in
//! `[0, 1)`, and
//!
//! ```text
//! lambda = conflict (1 - (1 - conflict) u),    x = lambda on the `true` side, -lambda on the other,
//! ```
//!
//! so at conflict 0 every member is the base, at conflict 1 every member is one of the
//! two poles, and in between `|x|` lies in `[conflict^2, conflict]`. The domain builds the
//! member at each position, moving each of its numbers from the base to the pole with
//! [`geometric`] (a scale, such as a deadline: equal ratios for equal steps) or
//! [`linear`] (a probability), both exact at the ends.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// `size` members drawn from a two-pole family at `conflict` (clamped to `[0, 1]`) with
/// the generator seeded by `seed`: `member(x, name)` builds the member at position `x`
/// (see the [module documentation](self) for how positions are drawn), named
/// `family-c{conflict:.2}-{i}` (`family-c0.67-3`: the fourth member at conflict 2/3).
///
/// ```
/// use lab::population::family::two_pole_family;
///
/// let positions = two_pole_family(0.5, 4, 7, |x, name| (name.to_owned(), x));
/// assert_eq!(positions[3].0, "family-c0.50-3");
/// assert!(positions.iter().all(|&(_, x)| (0.25..=0.5).contains(&x.abs())));
/// // At conflict 1 every member is a pole.
/// let poles = two_pole_family(1.0, 8, 7, |x, _| x);
/// assert!(poles.iter().all(|x| x.abs() == 1.0));
/// ```
pub fn two_pole_family<O>(
    conflict: f64,
    size: usize,
    seed: u64,
    mut member: impl FnMut(f64, &str) -> O,
) -> Vec<O> {
    let c = conflict.clamp(0.0, 1.0);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..size)
        .map(|i| {
            let positive = rng.random::<bool>();
            let u = rng.random::<f64>();
            let lambda = c * (1.0 - (1.0 - c) * u);
            let x = if positive { lambda } else { -lambda };
            member(x, &format!("family-c{c:.2}-{i}"))
        })
        .collect()
}

/// The pole on the side of position `x` (`negative` below 0, `positive` from 0 on) and
/// how far towards it a member at `x` lies, `|x|` with `x` clamped to `[-1, 1]`: the
/// share a member moves each number from the base (with [`geometric`] and [`linear`]).
///
/// ```
/// use lab::population::family::toward;
///
/// assert_eq!(toward(-0.25, "hurried", "careful"), ("hurried", 0.25));
/// assert_eq!(toward(0.0, "hurried", "careful"), ("careful", 0.0));
/// assert_eq!(toward(3.0, "hurried", "careful"), ("careful", 1.0));
/// ```
pub fn toward<T>(x: f64, negative: T, positive: T) -> (T, f64) {
    let x = x.clamp(-1.0, 1.0);
    if x < 0.0 {
        (negative, -x)
    } else {
        (positive, x)
    }
}

/// The number `f` of the way from `base` to `pole` on a geometric scale,
/// `base^(1 - f) pole^f` (for a scale such as a deadline: `f = 1/2` of the way from 15 s
/// to 60 s is 30 s); exactly `base` at `f = 0` and `pole` at `f = 1`.
///
/// ```
/// use lab::population::family::geometric;
///
/// assert_eq!(geometric(15.0, 60.0, 0.0), 15.0);
/// assert!((geometric(15.0, 60.0, 0.5) - 30.0).abs() < 1e-12);
/// assert_eq!(geometric(15.0, 60.0, 1.0), 60.0);
/// ```
pub fn geometric(base: f64, pole: f64, f: f64) -> f64 {
    base.powf(1.0 - f) * pole.powf(f)
}

/// The number `f` of the way from `base` to `pole` on a linear scale,
/// `base + (pole - base) f` (for a probability); exactly `base` at `f = 0` and `pole` at
/// `f = 1`.
///
/// ```
/// use lab::population::family::linear;
///
/// assert_eq!(linear(0.05, 0.95, 0.0), 0.05);
/// assert_eq!(linear(0.25, 0.75, 0.5), 0.5);
/// // 0.05 + (0.95 - 0.05) * 1 is not 0.95 in floating point; the pole is.
/// assert_eq!(linear(0.05, 0.95, 1.0), 0.95);
/// ```
pub fn linear(base: f64, pole: f64, f: f64) -> f64 {
    if f == 1.0 {
        pole
    } else {
        base + (pole - base) * f
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    // Named, as both globs bring a `Rng`.
    use rand::Rng;

    #[test]
    fn positions_by_hand() {
        // Seed 7's first draws, by the formula: each member's side and spread come from
        // the same ChaCha8 stream, a `bool` then an `f64`.
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let (side, u) = (rng.random::<bool>(), rng.random::<f64>());
        let x = two_pole_family(0.5, 1, 7, |x, _| x)[0];
        // lambda = 0.5 (1 - 0.5 u) = 0.5 - 0.25 u.
        let lambda = 0.5 - 0.25 * u;
        assert_eq!(x, if side { lambda } else { -lambda });
    }

    #[test]
    fn interpolation_by_hand() {
        let close = |a: f64, b: f64| (a - b).abs() < 1e-12 * b;
        // 120 s to 240 s: half way is 120 sqrt(2) s, a quarter 120 2^(1/4) s.
        assert!(close(geometric(120.0, 240.0, 0.5), 169.705_627_484_771_4));
        assert!(close(geometric(120.0, 240.0, 0.25), 142.704_853_800_326_5));
        assert!(close(geometric(10.0, 1000.0, 0.5), 100.0));
        // 0.95 to 0.05, a quarter of the way: 0.95 - 0.9 / 4.
        assert!(close(linear(0.95, 0.05, 0.25), 0.725));
        assert!(close(linear(0.05, 0.95, 0.5), 0.5));
    }

    proptest! {
        #[test]
        fn positions_lie_between_conflict_squared_and_conflict(
            conflict in 0.0f64..=1.0, size in 0usize..40, seed: u64,
        ) {
            let xs = two_pole_family(conflict, size, seed, |x, _| x);
            prop_assert_eq!(xs.len(), size);
            let low = conflict * conflict;
            for x in xs {
                prop_assert!(
                    x.abs() >= low - 1e-12 && x.abs() <= conflict,
                    "|{}| not in [{}, {}]", x, low, conflict
                );
            }
        }

        #[test]
        fn conflict_zero_is_the_base_and_one_the_poles(size in 1usize..40, seed: u64) {
            prop_assert!(two_pole_family(0.0, size, seed, |x, _| x).iter().all(|&x| x == 0.0));
            prop_assert!(two_pole_family(1.0, size, seed, |x, _| x).iter().all(|&x| x.abs() == 1.0));
        }

        #[test]
        fn a_seed_gives_one_family_with_distinct_names(
            conflict in 0.0f64..=1.0, size in 0usize..20, seed: u64,
        ) {
            let members = |s| two_pole_family(conflict, size, s, |x, name| (x, name.to_owned()));
            let family = members(seed);
            prop_assert_eq!(&family, &members(seed));
            for (i, (_, name)) in family.iter().enumerate() {
                prop_assert!(name.ends_with(&format!("-{i}")), "{}", name);
            }
        }

        #[test]
        fn interpolations_are_exact_at_the_ends_and_between_the_ends(
            base in 0.001f64..1000.0, pole in 0.001f64..1000.0, f in 0.0f64..=1.0,
        ) {
            prop_assert_eq!(geometric(base, pole, 0.0), base);
            prop_assert_eq!(geometric(base, pole, 1.0), pole);
            prop_assert_eq!(linear(base, pole, 0.0), base);
            prop_assert_eq!(linear(base, pole, 1.0), pole);
            let (lo, hi) = (base.min(pole), base.max(pole));
            let slack = 1e-9 * hi;
            for value in [geometric(base, pole, f), linear(base, pole, f)] {
                prop_assert!(value >= lo - slack && value <= hi + slack, "{}", value);
            }
        }
    }
}
