//! Every arm against its experiment's reference arm ([`ReportEntry::reference`]): the
//! effect sizes (each arm's mean behaviors evaluated as a ratio to the reference's, with a
//! paired bootstrap interval) and the paired tests behind the p-values.

use super::entry::ReportEntry;
use crate::experiment::record::PairedTests;
use crate::seeds::{Purpose, stream};
use crate::stats::{RatioCi, paired_bootstrap_ratio, paired_t_test, wilcoxon_signed_rank};
use rayon::prelude::*;

/// Resamples of the paired bootstrap of an effect size.
pub(super) const BOOTSTRAP_RESAMPLES: usize = 2000;

/// Each arm's effect size in experiment number `experiment` (its place in the report):
/// its mean behaviors evaluated as a ratio to the reference arm's, with the paired
/// bootstrap's 95% interval (arm `a` resampled from stream `(seed, experiment, a,
/// Bootstrap)`); `None` for the reference itself, and for every arm when the reference
/// is not among them or evaluated nothing.
pub fn effect_sizes(e: &ReportEntry<'_>, experiment: usize) -> Vec<Option<RatioCi>> {
    against_reference(e, |a, counts, base| {
        let mut rng = stream(e.seed, experiment as u64, a as u64, Purpose::Bootstrap);
        paired_bootstrap_ratio(counts, base, BOOTSTRAP_RESAMPLES, &mut rng)
    })
    .into_iter()
    .map(Option::flatten)
    .collect()
}

/// `compare(a, counts, reference_counts)` for each arm `a` of `e` but its reference arm
/// ([`ReportEntry::reference`]), over the behaviors evaluated per trial; `None` for the
/// reference itself, and for every arm when the reference is not among them.
fn against_reference<T>(
    e: &ReportEntry<'_>,
    compare: impl Fn(usize, &[f64], &[f64]) -> T,
) -> Vec<Option<T>> {
    let Some(reference) = e.result.arm(e.reference) else {
        return e.result.arms.iter().map(|_| None).collect();
    };
    let base = reference.counts();
    e.result
        .arms
        .iter()
        .enumerate()
        .map(|(a, arm)| (arm.name != reference.name).then(|| compare(a, &arm.counts(), &base)))
        .collect()
}

/// The effect sizes of every entry ([`effect_sizes`]), in the entries' order: the
/// bootstrap runs once per report, and the entries' in parallel (each has its streams).
pub fn all_effect_sizes(entries: &[ReportEntry<'_>]) -> Vec<Vec<Option<RatioCi>>> {
    entries
        .par_iter()
        .enumerate()
        .map(|(k, e)| effect_sizes(e, k))
        .collect()
}

/// Each arm of `e` against its reference arm ([`ReportEntry::reference`]): paired tests
/// of the behaviors evaluated per trial; `None` for the reference itself, and for every
/// arm when the reference is not among them.
pub fn versus_reference(e: &ReportEntry<'_>) -> Vec<Option<PairedTests>> {
    against_reference(e, |_, counts, base| PairedTests {
        t_test_p: paired_t_test(base, counts).unwrap_or(1.0),
        wilcoxon_p: wilcoxon_signed_rank(base, counts).unwrap_or(1.0),
    })
}
