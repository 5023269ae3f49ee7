//! A study's report: per condition, what the participants cost the robot (behaviors
//! evaluated, commands, stops) and how the robot's inverse trust estimate ranks against the
//! participants' own ratings (Spearman's rank correlation, with a 95% interval by a
//! bootstrap over participants), as the work the paper builds on compared its metric with
//! trust surveys.

use crate::export::{ExportError, Recorded, Summary, csv_field, summarize, write_all};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};
use std::path::Path;

/// Resamples of the bootstrap interval.
pub const BOOTSTRAP_RESAMPLES: usize = 2000;

/// The ranks of `values` from 1, ties given the mean of the ranks they span.
pub fn ranks(values: &[f64]) -> Vec<f64> {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    let mut ranks = vec![0.0; values.len()];
    let mut i = 0;
    while i < order.len() {
        let mut j = i;
        while j + 1 < order.len() && values[order[j + 1]] == values[order[i]] {
            j += 1;
        }
        let mean = (i + j) as f64 / 2.0 + 1.0;
        for &k in &order[i..=j] {
            ranks[k] = mean;
        }
        i = j + 1;
    }
    ranks
}

/// Pearson's correlation of `x` and `y`; `None` when either does not vary.
fn pearson(x: &[f64], y: &[f64]) -> Option<f64> {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx) * (a - mx);
        syy += (b - my) * (b - my);
    }
    (sxx > 0.0 && syy > 0.0).then(|| sxy / (sxx * syy).sqrt())
}

/// Spearman's rank correlation of the pairs; `None` with fewer than three pairs or when
/// either side does not vary.
pub fn spearman(pairs: &[(f64, f64)]) -> Option<f64> {
    if pairs.len() < 3 {
        return None;
    }
    let x: Vec<f64> = pairs.iter().map(|p| p.0).collect();
    let y: Vec<f64> = pairs.iter().map(|p| p.1).collect();
    pearson(&ranks(&x), &ranks(&y))
}

/// Spearman's correlation over every participant's (rating, estimate) pairs and its 95%
/// percentile interval from resampling participants with replacement (a participant's
/// ratings are not independent of each other; participants are). Resamples where the
/// correlation is undefined are left out of the interval.
pub fn correlation(groups: &[Vec<(f64, f64)>], seed: u64) -> (Option<f64>, Option<(f64, f64)>) {
    let all: Vec<(f64, f64)> = groups.iter().flatten().copied().collect();
    let rho = spearman(&all);
    if rho.is_none() || groups.len() < 2 {
        return (rho, None);
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut draws = Vec::with_capacity(BOOTSTRAP_RESAMPLES);
    for _ in 0..BOOTSTRAP_RESAMPLES {
        let sample: Vec<(f64, f64)> = (0..groups.len())
            .flat_map(|_| groups[rng.random_range(0..groups.len())].iter().copied())
            .collect();
        if let Some(r) = spearman(&sample) {
            draws.push(r);
        }
    }
    if draws.len() < BOOTSTRAP_RESAMPLES / 2 {
        return (rho, None);
    }
    draws.sort_by(f64::total_cmp);
    let at = |q: f64| draws[((draws.len() - 1) as f64 * q).round() as usize];
    (rho, Some((at(0.025), at(0.975))))
}

fn mean(values: &[f64]) -> Option<f64> {
    (!values.is_empty()).then(|| values.iter().sum::<f64>() / values.len() as f64)
}

fn shown(value: Option<f64>) -> String {
    value.map_or("–".into(), |v| format!("{v:.2}"))
}

/// Writes `report.md` and `report.json` of the study at `location` into `out`.
pub fn report(location: &str, out: &Path) -> Result<Value, ExportError> {
    let recorded = Recorded::open(location)?;
    let everyone = recorded.everyone()?;
    let study = &recorded.study;
    let summaries: Vec<Summary> = everyone
        .iter()
        .map(|(p, events)| summarize(study, p, events))
        .collect();
    let mut conditions = Vec::new();
    let mut table = String::from(
        "| condition | arm | participants | finished | behaviors evaluated | commands | stops | found trustworthy | ratings | Spearman rho (rating, estimate) | 95% CI |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for (k, condition) in study.conditions.iter().enumerate() {
        let members: Vec<&Summary> = summaries
            .iter()
            .filter(|s| s.condition == condition.name)
            .collect();
        let finished: Vec<&&Summary> = members.iter().filter(|s| s.ended.is_some()).collect();
        let behaviors: Vec<f64> = finished
            .iter()
            .filter_map(|s| s.ended.as_ref()?["behaviors_evaluated"].as_f64())
            .collect();
        let commands: Vec<f64> = members.iter().map(|s| s.commands as f64).collect();
        let stops: Vec<f64> = members.iter().map(|s| s.stops as f64).collect();
        let found = finished
            .iter()
            .filter(|s| {
                s.ended
                    .as_ref()
                    .is_some_and(|r| r["ok"] == "settled" && r["trustworthy"] == true)
            })
            .count();
        let groups: Vec<Vec<(f64, f64)>> = members
            .iter()
            .map(|s| s.ratings.iter().map(|r| (r.3, r.4)).collect())
            .filter(|g: &Vec<(f64, f64)>| !g.is_empty())
            .collect();
        let ratings: usize = groups.iter().map(Vec::len).sum();
        let (rho, ci) = correlation(&groups, study.seed ^ k as u64);
        table.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            condition.name,
            condition.arm,
            members.len(),
            finished.len(),
            shown(mean(&behaviors)),
            shown(mean(&commands)),
            shown(mean(&stops)),
            if finished.is_empty() {
                "–".into()
            } else {
                format!("{found} of {}", finished.len())
            },
            ratings,
            shown(rho),
            ci.map_or("–".into(), |(lo, hi)| format!("[{lo:.2}, {hi:.2}]")),
        ));
        conditions.push(json!({
            "condition": condition.name,
            "arm": condition.arm,
            "explanations": condition.explanations,
            "statements": condition.statements,
            "participants": members.len(),
            "finished": finished.len(),
            "behaviors_evaluated_mean": mean(&behaviors),
            "commands_mean": mean(&commands),
            "stops_mean": mean(&stops),
            "found_trustworthy": found,
            "ratings": ratings,
            "spearman_rating_estimate": rho,
            "spearman_ci95": ci.map(|(lo, hi)| vec![lo, hi]),
        }));
    }
    let summary = json!({
        "study": study.title,
        "domain": study.domain,
        "participants": everyone.len(),
        "bootstrap_resamples": BOOTSTRAP_RESAMPLES,
        "conditions": conditions,
    });
    let markdown = format!(
        "# {}\n\n{} participants, domain `{}`. Means per participant; \"finished\" counts the sessions whose episode ended (settled, or the study's limits). Spearman's rho ranks each rating against the robot's inverse trust estimate of the behavior just evaluated (the sum of its commands' weighted outcomes); its interval resamples participants ({BOOTSTRAP_RESAMPLES} resamples, percentile).\n\n{table}",
        study.title,
        everyone.len(),
        csv_field(&study.domain),
    );
    write_all(
        out,
        &[
            ("report.md", markdown),
            (
                "report.json",
                serde_json::to_string_pretty(&summary).expect("JSON") + "\n",
            ),
        ],
    )?;
    Ok(summary)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranks_share_ties() {
        assert_eq!(ranks(&[10.0, 20.0, 10.0, 30.0]), vec![1.5, 3.0, 1.5, 4.0]);
    }

    #[test]
    fn spearman_by_hand() {
        // Ranks x: 1 2 3 4; y: 1 3 2 4. d^2 = 0+1+1+0 = 2, rho = 1 - 6*2/(4*15) = 0.8.
        let rho = spearman(&[(1.0, 5.0), (2.0, 7.0), (3.0, 6.0), (4.0, 8.0)]).unwrap();
        assert!((rho - 0.8).abs() < 1e-12, "{rho}");
        assert_eq!(spearman(&[(1.0, 1.0), (2.0, 1.0), (3.0, 1.0)]), None);
        assert_eq!(spearman(&[(1.0, 1.0), (2.0, 2.0)]), None);
    }

    #[test]
    fn a_perfect_ranking_has_a_degenerate_interval_at_one() {
        let groups: Vec<Vec<(f64, f64)>> = (0..6)
            .map(|p| {
                (0..3)
                    .map(|k| (f64::from(p * 3 + k), f64::from(p * 3 + k) * 2.0))
                    .collect()
            })
            .collect();
        let (rho, ci) = correlation(&groups, 1);
        assert_eq!(rho, Some(1.0));
        let (lo, hi) = ci.unwrap();
        assert!((lo - 1.0).abs() < 1e-12 && (hi - 1.0).abs() < 1e-12);
    }
}
