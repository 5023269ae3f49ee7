//! The UGV world as a stage for `console` (docs/studies.md): the map a participant sees,
//! each run as it unfolds, and the outcome report a participant's stop makes.
//!
//! A run is the simulator's own ([`UgvDomain::simulate`], drawn from the run's seed): the
//! people standing, the driven path, collisions, scans, the arrival. The page moves the
//! robot along the driven path; the trace times some of its positions (collisions, the
//! closest pass, the arrival), and between two timed positions the robot is placed by
//! distance travelled, so every event is drawn where and when the simulator put it
//! (docs/simulation.md, "Runs a person watches").
//!
//! The outcome report is what the robot knows, as a controller would send it to `serve`:
//! the outcome (interrupted when the participant stopped it; otherwise completed when it
//! arrived, failed when it was stuck or an explosive went off), the command's duration
//! (the moment of the stop, or the run's end), what the robot perceived until then
//! ([`domains::perceive`]), the reason the participant stated, and the weight the
//! scenario's paper operators give that outcome (movement: 1 for every outcome; patrol:
//! 1/3, a detonation 1).

use cbr_core::Behavior;
use console::{Ending, ShownRun, Stage};
use domains::geometry::{Shape, Vec2};
use domains::trace::EventKind;
use domains::world::ObstacleKind;
use domains::{Run, Scenario, UgvDomain, builtin_operators, perceive};
use lab::Domain;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};
use service::reply;
use trust::{Outcome, OutcomeWeights};

/// The UGV world of one scenario, as a person watches it.
pub struct UgvStage {
    domain: UgvDomain,
    weights: OutcomeWeights,
}

impl UgvStage {
    /// The stage of `scenario`, reporting outcomes with the weights of its paper
    /// operators (the same for each of a scenario's).
    pub fn new(scenario: Scenario) -> Self {
        let weights = builtin_operators(scenario)
            .first()
            .map(|o| o.weights.clone())
            .unwrap_or_default();
        Self {
            domain: UgvDomain::new(scenario),
            weights,
        }
    }

    fn run(&self, behavior: &Behavior, seed: u64) -> Run<'_> {
        self.domain
            .simulate(behavior, &mut ChaCha8Rng::seed_from_u64(seed), true)
    }
}

/// How a run ends by itself: the first arrival, getting stuck or a detonation.
fn run_end(run: &Run<'_>) -> (f64, &'static str) {
    run.trace
        .events
        .iter()
        .find_map(|e| match e.kind {
            EventKind::Arrived { .. } => Some((e.t, "arrived")),
            EventKind::Stuck => Some((e.t, "stuck")),
            EventKind::Detonation { .. } => Some((e.t, "detonation")),
            _ => None,
        })
        .unwrap_or((0.0, "stuck"))
}

fn point(p: Vec2) -> Value {
    json!([p.x, p.y])
}

fn shape(s: &Shape) -> (&'static str, Value) {
    match s {
        Shape::Circle { center, radius } => ("circle", json!([center.x, center.y, radius])),
        Shape::Polygon(points) => (
            "polygon",
            points.iter().copied().map(point).collect::<Vec<_>>().into(),
        ),
    }
}

fn obstacle_kind(kind: ObstacleKind) -> &'static str {
    match kind {
        ObstacleKind::House => "house",
        ObstacleKind::Vehicle => "vehicle",
        ObstacleKind::Barrier => "barrier",
        ObstacleKind::Cone => "cone",
        ObstacleKind::Human => "person",
    }
}

/// The driven path with a time at each position: the trace's timed positions are kept,
/// and between two of them time runs in proportion to distance travelled.
fn timed_path(run: &Run<'_>, end: f64, pause: f64) -> Vec<Value> {
    let driven = &run.driven;
    if driven.is_empty() {
        let start = run.plan.map_or(Vec2::new(0.0, 0.0), |p| p.points[0]);
        return vec![
            json!([0.0, start.x, start.y]),
            json!([end, start.x, start.y]),
        ];
    }
    // Distance along the driven path at each position.
    let mut along = vec![0.0];
    for pair in driven.windows(2) {
        along.push(along.last().copied().unwrap_or(0.0) + (pair[1] - pair[0]).norm());
    }
    // (index, time) anchors, in order along the path.
    let mut anchors: Vec<(usize, f64)> = vec![(0, 0.0)];
    let nearest_from = |from: usize, at: Vec2| {
        (from..driven.len())
            .min_by(|&a, &b| (driven[a] - at).norm().total_cmp(&(driven[b] - at).norm()))
            .unwrap_or(from)
    };
    for event in run.trace.events.iter().filter(|e| e.t <= end) {
        let at = match event.kind {
            EventKind::Collision { at } | EventKind::ClosestPass { at, .. } => at,
            EventKind::Arrived { at } => at,
            _ => continue,
        };
        let (last_index, last_t) = *anchors.last().expect("the start is an anchor");
        let index = nearest_from(last_index, at);
        if event.t >= last_t {
            anchors.push((index, event.t));
            if matches!(event.kind, EventKind::Collision { .. }) {
                anchors.push((index, (event.t + pause).min(end)));
            }
        }
    }
    let (last_index, last_t) = *anchors.last().expect("the start is an anchor");
    if last_index < driven.len() - 1 || last_t < end {
        anchors.push((driven.len() - 1, end.max(last_t)));
    }
    let mut path = Vec::with_capacity(driven.len() + anchors.len());
    for pair in anchors.windows(2) {
        let ((i0, t0), (i1, t1)) = (pair[0], pair[1]);
        let span = along[i1] - along[i0];
        for i in i0..=i1 {
            let share = if span > 0.0 {
                (along[i] - along[i0]) / span
            } else {
                (i - i0) as f64 / ((i1 - i0).max(1)) as f64
            };
            let t = t0 + share * (t1 - t0);
            if i == i0 && !path.is_empty() && t <= t0 && i0 != i1 {
                continue;
            }
            path.push(json!([t, driven[i].x, driven[i].y]));
        }
    }
    path.dedup();
    path
}

impl Stage for UgvStage {
    fn scene(&self) -> Value {
        let world = self.domain.world();
        json!({
            "size": point(world.size),
            "roads": world.roads.iter().map(|r| json!({"min": point(r.min), "max": point(r.max)})).collect::<Vec<_>>(),
            "obstacles": world.obstacles.iter().map(|o| {
                let (key, value) = shape(&o.shape);
                json!({"kind": obstacle_kind(o.kind), key: value})
            }).collect::<Vec<_>>(),
            "people": world.humans.iter().map(|h| {
                let (key, value) = shape(&h.shape);
                json!({"name": h.name, key: value})
            }).collect::<Vec<_>>(),
            "route": self.domain.route().iter().copied().map(point).collect::<Vec<_>>(),
            "robot_radius": world.robot.radius,
        })
    }

    fn show(&self, behavior: &Behavior, seed: u64) -> ShownRun {
        let run = self.run(behavior, seed);
        let (end, ends) = run_end(&run);
        let pause = self.domain.world().robot.collision_pause;
        let events: Vec<Value> = run
            .trace
            .events
            .iter()
            .filter(|e| e.t <= end)
            .filter_map(|e| match e.kind {
                EventKind::Collision { at } => {
                    Some(json!({"t": e.t, "kind": "collision", "at": point(at)}))
                }
                EventKind::Stuck => Some(json!({"t": e.t, "kind": "stuck"})),
                EventKind::Arrived { .. } => Some(json!({"t": e.t, "kind": "arrived"})),
                EventKind::Scanned { object, .. } => {
                    Some(json!({"t": e.t, "kind": "scanned", "object": object}))
                }
                EventKind::Labelled {
                    object,
                    labelled_explosive,
                    ..
                } => Some(json!({"t": e.t, "kind": "labelled", "object": object, "explosive_label": labelled_explosive})),
                EventKind::Detonation { object } => {
                    Some(json!({"t": e.t, "kind": "detonation", "object": object}))
                }
                _ => None,
            })
            .collect();
        let present: Vec<usize> = (0..self.domain.world().humans.len())
            .filter(|i| run.humans & (1 << i) != 0)
            .collect();
        let picture = json!({
            "duration_s": end,
            "ends": ends,
            "path": timed_path(&run, end, pause),
            "present": present,
            "objects": run.objects.iter().map(|o| json!({"at": point(o.object.at)})).collect::<Vec<_>>(),
            "events": events,
        });
        ShownRun {
            picture,
            duration_s: end,
        }
    }

    fn outcome(
        &self,
        behavior: &Behavior,
        seed: u64,
        ending: Ending,
        stated: Option<&str>,
    ) -> Value {
        let run = self.run(behavior, seed);
        let (end, ends) = run_end(&run);
        let stated = stated.and_then(|name| {
            self.domain
                .causes()
                .iter()
                .find(|c| c.name.as_str() == name)
                .map(|c| c.name)
        });
        let outcome = match ending {
            Ending::Stopped(at_s) => {
                let weight = stated.map_or(self.weights.default, |c| self.weights.of(c));
                Outcome::interrupted(weight, at_s)
            }
            Ending::RanOut => match ends {
                "arrived" => Outcome::completed(self.weights.completed, end),
                failure => {
                    let cause = if failure == "detonation" {
                        domains::causes::DETONATION
                    } else {
                        domains::causes::STUCK
                    };
                    Outcome::failed(self.weights.of(cause), end)
                }
            },
        };
        let until = outcome.duration_s;
        let outcome = outcome
            .observing(perceive(&run.trace, until, self.domain.observations()))
            .stating(stated);
        reply::outcome(&outcome, self.domain.observations())
    }

    fn cause_text(&self, cause: &str) -> String {
        match cause {
            "deadline" => "it was too slow",
            "collision" => "it hit something",
            "stuck" => "it got stuck",
            "too-fast-near-people" => "it drove too fast near people",
            "too-close" => "it came too close to something",
            "missed-object" => "it missed a suspicious object",
            "false-alarm" => "it called a harmless object dangerous",
            "detonation" => "an explosive went off",
            "poor-scan" => "it scanned an object poorly",
            other => other,
        }
        .to_owned()
    }
}
