//! Summary statistics for experiment results: mean with a 95% confidence interval, the
//! paired t-test and Wilcoxon signed-rank test between two arms' per-trial counts, the
//! ratio of their means with a paired bootstrap confidence interval, and the percentile
//! the bootstrap intervals take their ends at.

use rand::Rng;
use statrs::distribution::{ContinuousCDF, Normal, StudentsT};

/// A ratio of two means with its 95% confidence interval.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RatioCi {
    /// `mean(a) / mean(b)`.
    pub ratio: f64,
    /// The interval's lower end.
    pub low: f64,
    /// The interval's upper end.
    pub high: f64,
}

/// `mean(a) / mean(b)` with the 95% interval of the paired bootstrap: `resamples` times,
/// the same `n` pairs `(a[i], b[i])` drawn with replacement from `rng` for both, the ratio
/// of their means; the 2.5th and 97.5th percentiles of those ratios. `None` if the slices
/// differ in length, are empty, or `b`'s mean is 0.
pub fn paired_bootstrap_ratio<R: Rng + ?Sized>(
    a: &[f64],
    b: &[f64],
    resamples: usize,
    rng: &mut R,
) -> Option<RatioCi> {
    let n = a.len();
    let sum = |v: &[f64]| v.iter().sum::<f64>();
    if n != b.len() || n == 0 || sum(b) == 0.0 {
        return None;
    }
    let mut ratios: Vec<f64> = (0..resamples.max(1))
        .map(|_| {
            let (mut sa, mut sb) = (0.0, 0.0);
            for _ in 0..n {
                let i = rng.random_range(0..n);
                sa += a[i];
                sb += b[i];
            }
            sa / sb
        })
        .filter(|r| r.is_finite())
        .collect();
    ratios.sort_by(f64::total_cmp);
    Some(RatioCi {
        ratio: sum(a) / sum(b),
        low: percentile(&ratios, 0.025)?,
        high: percentile(&ratios, 0.975)?,
    })
}

/// The `q` quantile of `sorted` (ascending) by the nearest rank, `sorted[round((n - 1) *
/// q)]`, as the bootstrap intervals take their ends; `None` when it is empty.
pub fn percentile(sorted: &[f64], q: f64) -> Option<f64> {
    let last = sorted.len().checked_sub(1)?;
    sorted.get((last as f64 * q).round() as usize).copied()
}

/// Mean and the half-width of its 95% confidence interval (Student's t). Serialized as
/// `{"mean", "ci95"}`, as every report's JSON gives it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct MeanCi {
    /// Sample mean.
    pub mean: f64,
    /// Half-width of the 95% confidence interval (0 for fewer than two values).
    pub ci95: f64,
}

/// The mean of `values` with its 95% confidence interval; `None` for no values.
pub fn mean_ci95(values: &[f64]) -> Option<MeanCi> {
    let n = values.len();
    if n == 0 {
        return None;
    }
    let mean = values.iter().sum::<f64>() / n as f64;
    if n < 2 {
        return Some(MeanCi { mean, ci95: 0.0 });
    }
    let sd = sample_sd(values, mean);
    let t = t_975(n - 1);
    Some(MeanCi {
        mean,
        ci95: t * sd / (n as f64).sqrt(),
    })
}

/// [`mean_ci95`], with 0 ± 0 for no values (a summary that must show a figure).
pub fn mean_ci95_or_zero(values: &[f64]) -> MeanCi {
    mean_ci95(values).unwrap_or(MeanCi {
        mean: 0.0,
        ci95: 0.0,
    })
}

/// Student's t quantile at 0.975 for `df` degrees of freedom (at least 1). The quantile
/// is found numerically, so small degrees of freedom (the moving windows of the learning
/// curves ask for them thousands of times) are computed once.
fn t_975(df: usize) -> f64 {
    const CACHED: usize = 64;
    static SMALL: std::sync::OnceLock<Vec<f64>> = std::sync::OnceLock::new();
    let quantile = |df: usize| {
        StudentsT::new(0.0, 1.0, df as f64)
            .expect("degrees of freedom >= 1")
            .inverse_cdf(0.975)
    };
    if df <= CACHED {
        SMALL.get_or_init(|| (1..=CACHED).map(quantile).collect())[df - 1]
    } else {
        quantile(df)
    }
}

fn sample_sd(values: &[f64], mean: f64) -> f64 {
    let n = values.len() as f64;
    (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
}

/// Two-sided p-value of the paired t-test of `a[i] - b[i]` against a mean difference of 0.
///
/// With no variation in the differences the test degenerates: 1 when they are all 0 and 0
/// otherwise. `None` if the slices differ in length or hold fewer than two pairs.
pub fn paired_t_test(a: &[f64], b: &[f64]) -> Option<f64> {
    if a.len() != b.len() || a.len() < 2 {
        return None;
    }
    let differences: Vec<f64> = a.iter().zip(b).map(|(x, y)| x - y).collect();
    let n = differences.len() as f64;
    let mean = differences.iter().sum::<f64>() / n;
    let sd = sample_sd(&differences, mean);
    if sd == 0.0 {
        return Some(if mean == 0.0 { 1.0 } else { 0.0 });
    }
    let t = mean / (sd / n.sqrt());
    let distribution = StudentsT::new(0.0, 1.0, n - 1.0).expect("degrees of freedom >= 1");
    Some((2.0 * distribution.cdf(-t.abs())).clamp(0.0, 1.0))
}

/// Two-sided p-value of the Wilcoxon signed-rank test of `a[i] - b[i]` against a median
/// difference of 0, by the normal approximation with the tie correction (no continuity
/// correction); zero differences are dropped (Wilcoxon's treatment). Robust to the heavy
/// tails of behavior counts, where the t-test is not.
///
/// 1 when every difference is 0; `None` if the slices differ in length or are empty.
pub fn wilcoxon_signed_rank(a: &[f64], b: &[f64]) -> Option<f64> {
    signed_rank_test(a, b).map(|test| test.p)
}

/// The Wilcoxon signed-rank test of `a[i] - b[i]`: its standardized statistic and its
/// two-sided p-value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SignedRank {
    /// `(W+ - E[W+]) / sd(W+)`, `W+` the rank sum of the positive differences: above 0
    /// when `a` tends to be the larger, below 0 when `b` does (0 when every difference is
    /// 0).
    pub z: f64,
    /// The two-sided p-value ([`wilcoxon_signed_rank`]).
    pub p: f64,
}

/// [`wilcoxon_signed_rank`] with the direction of the difference: which of `a` and `b`
/// tends to be the larger, as its statistic says. `None` if the slices differ in length or
/// are empty.
pub fn signed_rank_test(a: &[f64], b: &[f64]) -> Option<SignedRank> {
    if a.len() != b.len() || a.is_empty() {
        return None;
    }
    let no_difference = SignedRank { z: 0.0, p: 1.0 };
    let mut differences: Vec<f64> = a
        .iter()
        .zip(b)
        .map(|(x, y)| x - y)
        .filter(|d| *d != 0.0)
        .collect();
    if differences.is_empty() {
        return Some(no_difference);
    }
    differences.sort_by(|x, y| x.abs().total_cmp(&y.abs()));
    let n = differences.len() as f64;
    let (mut positive_ranks, mut tie_term) = (0.0, 0.0);
    let mut start = 0;
    while start < differences.len() {
        let magnitude = differences[start].abs();
        let end = start
            + differences[start..]
                .iter()
                .take_while(|d| d.abs() == magnitude)
                .count();
        // Tied magnitudes share the mean of their ranks start + 1 ..= end.
        let rank = (start + 1 + end) as f64 / 2.0;
        positive_ranks +=
            rank * differences[start..end].iter().filter(|d| **d > 0.0).count() as f64;
        let t = (end - start) as f64;
        tie_term += t * t * t - t;
        start = end;
    }
    let mean = n * (n + 1.0) / 4.0;
    let variance = n * (n + 1.0) * (2.0 * n + 1.0) / 24.0 - tie_term / 48.0;
    if variance <= 0.0 {
        return Some(no_difference);
    }
    let z = (positive_ranks - mean) / variance.sqrt();
    let normal = Normal::new(0.0, 1.0).expect("a standard normal");
    Some(SignedRank {
        z,
        p: (2.0 * normal.cdf(-z.abs())).clamp(0.0, 1.0),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn bootstrap_ratios_bracket_the_ratio() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        let a: Vec<f64> = (0..40).map(|i| f64::from(i % 5 + 1)).collect();
        let b: Vec<f64> = a.iter().map(|x| 2.0 * x).collect();
        // Every resample keeps the pairs, so a ratio of exactly one half holds throughout.
        let r = paired_bootstrap_ratio(&a, &b, 200, &mut rng).unwrap();
        assert_eq!((r.ratio, r.low, r.high), (0.5, 0.5, 0.5));
        let c: Vec<f64> = (0..40).map(|i| f64::from(i % 7 + 1)).collect();
        let r = paired_bootstrap_ratio(&c, &a, 500, &mut rng).unwrap();
        assert!(r.low < r.ratio && r.ratio < r.high, "{r:?}");
        assert_eq!(paired_bootstrap_ratio(&a, &[0.0; 40], 10, &mut rng), None);
        assert_eq!(paired_bootstrap_ratio(&a, &b[1..], 10, &mut rng), None);
    }

    #[test]
    fn mean_and_interval_by_hand() {
        // Values 2, 4, 4, 4, 5, 5, 7, 9: mean 5, sample variance 32/7, sd 2.13809.
        // t(0.975, 7) = 2.36462, half-width 2.36462 * 2.13809 / sqrt(8) = 1.78749.
        let m = mean_ci95(&[2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0]).unwrap();
        assert!((m.mean - 5.0).abs() < 1e-12);
        assert!((m.ci95 - 1.78749).abs() < 1e-4, "{}", m.ci95);
        assert_eq!(mean_ci95(&[]), None);
        assert_eq!(mean_ci95(&[3.0]).unwrap().ci95, 0.0);
    }

    #[test]
    fn paired_t_test_by_hand() {
        // a - b = [2, 1, 3, 2, 2] -> mean 2, sd sqrt(0.5),
        // t = 2 / (0.70711 / sqrt(5)) = 6.32456 with 4 degrees of freedom: two-sided p = 0.003198.
        let a = [12.0, 11.0, 13.0, 12.0, 12.0];
        let b = [10.0, 10.0, 10.0, 10.0, 10.0];
        let p = paired_t_test(&a, &b).unwrap();
        assert!((p - 0.003198).abs() < 1e-5, "{p}");
        assert_eq!(paired_t_test(&a, &a), Some(1.0));
        assert_eq!(paired_t_test(&[1.0, 1.0], &[0.0, 0.0]), Some(0.0));
        assert_eq!(paired_t_test(&[1.0], &[0.0]), None);
    }

    #[test]
    fn wilcoxon_by_hand() {
        // Differences 1, 2, 3, 4, 5 (and a zero, dropped): W+ = 15, n = 5, mean 7.5,
        // variance 5 * 6 * 11 / 24 = 13.75, z = 7.5 / 3.708099 = 2.022600, p = 0.043115.
        let a = [3.0, 4.0, 5.0, 6.0, 7.0, 9.0];
        let b = [2.0, 2.0, 2.0, 2.0, 2.0, 9.0];
        let p = wilcoxon_signed_rank(&a, &b).unwrap();
        assert!((p - 0.043115).abs() < 1e-5, "{p}");
        // Differences -1, 1, 2, 2 (ties): ranks 1.5, 1.5, 3.5, 3.5; W+ = 8.5; mean 5;
        // variance 4 * 5 * 9 / 24 - (6 + 6) / 48 = 7.25; z = 3.5 / 2.692582 = 1.299867,
        // p = 0.193647.
        let p = wilcoxon_signed_rank(&[0.0, 1.0, 2.0, 2.0], &[1.0, 0.0, 0.0, 0.0]).unwrap();
        assert!((p - 0.193647).abs() < 1e-5, "{p}");
        assert_eq!(wilcoxon_signed_rank(&a, &a), Some(1.0));
        assert_eq!(wilcoxon_signed_rank(&[], &[]), None);
        // The statistic's sign says which side is the larger: z = +2.0226 above, and its
        // opposite with the sides swapped.
        let z = signed_rank_test(&a, &b).unwrap().z;
        assert!((z - 2.022600).abs() < 1e-5, "{z}");
        assert!((signed_rank_test(&b, &a).unwrap().z + z).abs() < 1e-12);
        assert_eq!(signed_rank_test(&a, &a).unwrap().z, 0.0);
    }

    #[test]
    fn percentiles_by_nearest_rank() {
        // Five values: q = 0.025 rounds (4 * 0.025 = 0.1) to rank 0, q = 0.975 (3.9) to 4,
        // the median (2.0) to 2.
        let sorted = [1.0, 2.0, 3.0, 4.0, 5.0];
        assert_eq!(percentile(&sorted, 0.025), Some(1.0));
        assert_eq!(percentile(&sorted, 0.975), Some(5.0));
        assert_eq!(percentile(&sorted, 0.5), Some(3.0));
        assert_eq!(percentile(&[], 0.5), None);
    }
}
