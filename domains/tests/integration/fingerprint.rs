//! The paper's operators judge exactly as before the operator preferences and the
//! perception were added: a fingerprint over 2,000 seeded runs per builtin operator
//! (behavior drawn from the run's seed, then simulated and judged), computed on the code
//! before the change and asserted after it. A new preference that is off must draw no
//! extra random number and change no outcome.

use domains::{Scenario, UgvDomain, builtin_operators};
use lab::{Domain, Judgement};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use trust::OutcomeKind;

/// FNV-1a over the bytes of each judgement: kind, weight, true cause, duration.
fn fold(hash: &mut u64, bytes: &[u8]) {
    for &b in bytes {
        *hash ^= u64::from(b);
        *hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
    }
}

fn fingerprint(judgements: impl Iterator<Item = Judgement>) -> u64 {
    let mut hash = 0xcbf2_9ce4_8422_2325;
    for j in judgements {
        let o = j.outcome;
        let kind = match o.kind {
            OutcomeKind::Completed => 0u8,
            OutcomeKind::Failed => 1,
            OutcomeKind::Interrupted => 2,
        };
        fold(&mut hash, &[kind]);
        fold(&mut hash, &o.weight.to_bits().to_le_bytes());
        let cause = j.truth.map(|c| c.to_string()).unwrap_or_default();
        fold(&mut hash, cause.as_bytes());
        fold(&mut hash, &o.duration_s.to_bits().to_le_bytes());
    }
    hash
}

fn outcomes<'a>(
    domain: &'a UgvDomain,
    operator: &'a domains::OperatorModel,
) -> impl Iterator<Item = Judgement> + 'a {
    (0..2_000u64).map(move |seed| {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let behavior = domain.space().draw(&mut rng);
        domain.run(&behavior, operator, &mut rng)
    })
}

#[test]
fn the_paper_operators_judge_as_before() {
    let mut found = Vec::new();
    for scenario in Scenario::ALL {
        let domain = UgvDomain::new(scenario);
        for operator in builtin_operators(scenario) {
            let print = fingerprint(outcomes(&domain, &operator));
            found.push((scenario.as_str(), operator.name.clone(), print));
        }
    }
    let expected: [(&str, &str, u64); 5] = [
        ("movement", "speed-focused", 13169304524885064539),
        ("movement", "safety-focused", 6958178685098041679),
        ("movement", "balanced", 3506146241908088748),
        ("patrol", "speed-focused", 1228565568871286956),
        ("patrol", "detection-focused", 7950344923981678100),
    ];
    let found: Vec<(&str, &str, u64)> =
        found.iter().map(|(s, n, p)| (*s, n.as_str(), *p)).collect();
    assert_eq!(found, expected);
}
