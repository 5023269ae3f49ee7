//! One proposal of every search strategy on the 16,000-behavior patrol space, after an
//! episode of 200 command outcomes, with the cross-episode knowledge of 50 earlier
//! episodes: `search/<strategy>/<distinct behaviors>`. 200 outcomes over 40 distinct
//! behaviors is an episode's usual shape (about 5 commands each); over 200 distinct
//! behaviors it is the model-based search's worst case at that size (one observation per
//! behavior, the largest kernel matrix). `search-served/<strategy>/<distinct>` is the same
//! with every other earlier episode ending on a trusted behavior (one the episode did not
//! reject), so that searches that look near what earlier operators trusted (`nested`) have
//! something to look near. The proposal timed is an episode's 200th-behavior one, made
//! right after the untimed proposal at 199 behaviors, as in a run (the conditioned family
//! keeps its profiles' likelihoods from one proposal to the next); an extra untimed
//! proposal every other iteration shifts the timed ones' parity, so that they fall on both
//! of `nested`'s alternating turns (its nested search and its fallback) and its figure is
//! their mean. `vouch/nested/<distinct>` is what vouching for case reuse adds to a
//! selection of `case-based+nested` in the served setting: the searcher asked whether it
//! doubts a remembered trusted behavior at the 200th behavior's evidence, right after the
//! same question at 199 (the first question of a selection; later ones on the same evidence
//! reuse its scores).
#![allow(missing_docs)] // criterion's macros generate undocumented items

use cbr_core::{Behavior, BehaviorSpace, Searcher};
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use std::time::{Duration, Instant};
use trust::{Evaluated, Outcome, SearchKind, TrustSearcher};

/// Outcomes of a synthetic operator that dislikes slow and careless behaviors.
fn outcome(space: &BehaviorSpace, b: &Behavior, rng: &mut ChaCha8Rng) -> Outcome {
    let speed = b.get(0) as f64 / (space.components()[0].len() - 1) as f64;
    let padding = b.get(1) as f64 / (space.components()[1].len() - 1) as f64;
    if rng.random_bool((1.0 - speed).powi(2) * 0.8) {
        Outcome::interrupted(1.0 / 3.0, 120.0)
    } else if rng.random_bool((1.0 - padding) * speed * 0.5) {
        Outcome::interrupted(1.0 / 3.0, 40.0).observing(trust::Observations::NONE.with(0))
    } else {
        Outcome::completed(1.0 / 3.0, 90.0)
    }
}

/// Feeds `searcher` one episode of `outcomes` commands over `distinct` behaviors and
/// returns its evidence.
fn episode(
    searcher: &mut dyn Searcher<Evidence = Evaluated, Feedback = Outcome>,
    space: &BehaviorSpace,
    outcomes: usize,
    distinct: usize,
    rng: &mut ChaCha8Rng,
) -> Vec<Evaluated> {
    let behaviors: Vec<Behavior> = (0..distinct).map(|_| space.draw(rng)).collect();
    searcher.begin_episode(space, &behaviors[0]);
    let mut evaluated = Vec::new();
    for (i, b) in behaviors.iter().enumerate() {
        let commands = outcomes / distinct + usize::from(i < outcomes % distinct);
        for _ in 0..commands {
            searcher.observe(b, &outcome(space, b, rng));
        }
        evaluated.push(Evaluated {
            behavior: *b,
            time: rng.random_range(10.0..2000.0),
        });
    }
    evaluated
}

/// A searcher in the middle of an episode, and what made it.
struct AfterEarlier {
    searcher: Box<TrustSearcher>,
    /// The behaviors the earlier episodes settled on, in order.
    settled_on: Vec<Behavior>,
    /// The episode's evidence.
    evaluated: Vec<Evaluated>,
    /// The randomness left.
    rng: ChaCha8Rng,
}

/// A searcher of `kind` after 50 earlier episodes of 200 outcomes over 40 behaviors, of
/// which every other one settled on a trusted behavior when `served` (none otherwise),
/// then fed an episode of 200 outcomes over `distinct` behaviors.
fn after_earlier(
    kind: SearchKind,
    space: &BehaviorSpace,
    served: bool,
    distinct: usize,
) -> AfterEarlier {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut searcher = kind.build();
    let mut settled_on = Vec::new();
    for earlier in 0..50 {
        let evaluated = episode(searcher.as_mut(), space, 200, 40, &mut rng);
        let settled = (served && earlier % 2 == 0)
            .then(|| space.draw(&mut rng))
            .filter(|t| !evaluated.iter().any(|e| e.behavior == *t));
        settled_on.extend(settled);
        searcher.end_episode(&evaluated, settled.as_ref());
    }
    let evaluated = episode(searcher.as_mut(), space, 200, distinct, &mut rng);
    AfterEarlier {
        searcher,
        settled_on,
        evaluated,
        rng,
    }
}

/// One proposal of every strategy after 50 earlier episodes, of which every other one
/// settled on a trusted behavior when `served`, none otherwise.
fn propose_after(c: &mut Criterion, group: &str, served: bool) {
    let space = domains::spaces::patrol_space();
    let mut group = c.benchmark_group(group);
    for kind in SearchKind::all() {
        for distinct in [40usize, 200] {
            let AfterEarlier {
                mut searcher,
                evaluated,
                mut rng,
                ..
            } = after_earlier(kind, &space, served, distinct);
            let before = &evaluated[..evaluated.len() - 1];
            group.bench_with_input(
                BenchmarkId::new(kind.name(), distinct),
                &distinct,
                |b, _| {
                    b.iter_custom(|iterations| {
                        timed_after(
                            iterations,
                            (&mut searcher, &mut rng),
                            |(searcher, rng), i| {
                                for _ in 0..1 + i % 2 {
                                    black_box(searcher.propose(&space, before, rng));
                                }
                            },
                            |(searcher, rng)| {
                                black_box(searcher.propose(&space, black_box(&evaluated), rng));
                            },
                        )
                    })
                },
            );
        }
    }
    group.finish();
}

/// One question of `nested`'s vouching for case reuse after 50 earlier episodes, every
/// other one settled on a trusted behavior: does it doubt the first of them?
fn vouch(c: &mut Criterion) {
    let space = domains::spaces::patrol_space();
    let kind = SearchKind::all()
        .find(|k| k.name() == "nested")
        .expect("the nested strategy is built in");
    let mut group = c.benchmark_group("vouch");
    for distinct in [40usize, 200] {
        let AfterEarlier {
            mut searcher,
            settled_on,
            evaluated,
            ..
        } = after_earlier(kind, &space, true, distinct);
        let asked = settled_on[0];
        let before = &evaluated[..evaluated.len() - 1];
        group.bench_with_input(
            BenchmarkId::new(kind.name(), distinct),
            &distinct,
            |b, _| {
                b.iter_custom(|iterations| {
                    timed_after(
                        iterations,
                        &mut searcher,
                        |searcher, _| {
                            black_box(searcher.doubts(&space, before, &asked));
                        },
                        |searcher| {
                            black_box(searcher.doubts(&space, black_box(&evaluated), &asked));
                        },
                    )
                })
            },
        );
    }
    group.finish();
}

/// The time `measured` takes over `iterations` runs, each after an untimed `prepare` (given
/// the iteration's index) that brings `state` to where the measured call starts.
fn timed_after<S>(
    iterations: u64,
    mut state: S,
    mut prepare: impl FnMut(&mut S, u64),
    mut measured: impl FnMut(&mut S),
) -> Duration {
    let mut timed = Duration::ZERO;
    for i in 0..iterations {
        prepare(&mut state, i);
        let start = Instant::now();
        measured(&mut state);
        timed += start.elapsed();
    }
    timed
}

fn propose(c: &mut Criterion) {
    propose_after(c, "search", false);
    propose_after(c, "search-served", true);
    vouch(c);
}

criterion_group!(benches, propose);
criterion_main!(benches);
