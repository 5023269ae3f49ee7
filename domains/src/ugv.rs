//! `UgvDomain`: the movement and patrol tasks over the urban block, behind the trust
//! crate's `Domain` contract.
//!
//! A run draws which people are standing around, looks up the plan for the behavior's
//! padding (planned once per padding and set of people, then cached), drives it, and for
//! patrol places, spots, scans and labels the suspicious objects. The result is a
//! [`Trace`]; the operator model turns it into a [`Judgement`].

use crate::detector::Detector;
use crate::drive::{Mark, drive};
use crate::geometry::{Shape, Vec2};
use crate::operator::OperatorModel;
use crate::patrol::{PatrolGround, PatrolSetup, SuspiciousObject};
use crate::perception;
use crate::planner::{Plan, Problem, VisibilityGraph};
use crate::profile::point_to_point;
use crate::scenario::Scenario;
use crate::self_competence;
use crate::trace::{EventKind, Trace};
use crate::world::World;
use cbr_core::{Behavior, BehaviorSpace, Context, ContextSpace};
use lab::{Attentive, Domain, GoalChanging, Judgement, SelfJudging};
use rand::{Rng, RngCore};
use std::sync::{Arc, OnceLock};
use trust::{Cause, CompetencePart, DeclaredCause, Hint};

/// The behavior's settings in physical units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Commanded speed (m/s).
    pub speed: f64,
    /// Obstacle padding (m).
    pub padding: f64,
    /// Scan time (s); patrol only.
    pub scan_time: f64,
    /// Scan distance (m); patrol only.
    pub scan_distance: f64,
}

/// What happened to one suspicious object.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectFate {
    /// The object.
    pub object: SuspiciousObject,
    /// Where the robot scanned it from, if it spotted it.
    pub scanned_from: Option<Vec2>,
    /// The label it gave (`true`: explosive), if it scanned it.
    pub labelled_explosive: Option<bool>,
}

/// Everything about one simulated run (the trace, and what a drawing needs).
#[derive(Clone, Debug)]
pub struct Run<'a> {
    /// The behavior's settings.
    pub settings: Settings,
    /// Which human spots were occupied (bit per spot).
    pub humans: u32,
    /// The plan followed, or `None` when the robot was stuck.
    pub plan: Option<&'a Plan>,
    /// The events.
    pub trace: Trace,
    /// Driven positions, when recorded.
    pub driven: Vec<Vec2>,
    /// Patrol objects and what became of them (empty for movement).
    pub objects: Vec<ObjectFate>,
}

/// Where a plan passes each spot where people stand: per spot (sorted along the path) the
/// arc length, the spot and the body-to-body gap; and the arc lengths alone.
#[derive(Debug, Default)]
struct Passes {
    spots: Vec<(f64, usize, f64)>,
    at: Vec<f64>,
}

/// The UGV world as a trust domain for one scenario.
pub struct UgvDomain {
    scenario: Scenario,
    space: Arc<BehaviorSpace>,
    world: World,
    detector: Detector,
    patrol: PatrolSetup,
    /// Where the patrol's objects may lie, measured once.
    ground: PatrolGround,
    /// Per padding: the visibility graph for every set of people.
    visibility: Box<[OnceLock<VisibilityGraph>]>,
    /// Per padding and set of people: the plan.
    plans: Box<[OnceLock<Option<Plan>>]>,
    /// Per padding and set of people: where the plan passes each spot where people stand
    /// ([`UgvDomain::people_along`]), and those arc lengths alone.
    passes: Box<[OnceLock<Passes>]>,
    /// Component index of speed, padding, scan time, scan distance (the last two only for
    /// patrol).
    components: [Option<usize>; 4],
}

impl UgvDomain {
    /// The domain for `scenario` over the urban block. Plans are computed on first use.
    pub fn new(scenario: Scenario) -> Self {
        let space = scenario.space();
        let world = World::urban_block();
        let patrol = PatrolSetup::default();
        let ground = PatrolGround::new(&world, patrol.free_space);
        let paddings = space
            .component_index("padding")
            .map_or(1, |i| space.components()[i].len());
        let plans = (0..paddings << world.humans.len())
            .map(|_| OnceLock::new())
            .collect();
        let passes = (0..paddings << world.humans.len())
            .map(|_| OnceLock::new())
            .collect();
        let visibility = (0..paddings).map(|_| OnceLock::new()).collect();
        let components = ["speed", "padding", "scan_time", "scan_distance"]
            .map(|name| space.component_index(name));
        Self {
            scenario,
            space,
            world,
            detector: Detector::default(),
            patrol,
            ground,
            visibility,
            plans,
            passes,
            components,
        }
    }

    /// The scenario.
    pub fn scenario(&self) -> Scenario {
        self.scenario
    }

    /// The map.
    pub fn world(&self) -> &World {
        &self.world
    }

    /// The explosives detector.
    pub fn detector(&self) -> &Detector {
        &self.detector
    }

    /// The patrol's objects and camera.
    pub fn patrol_setup(&self) -> &PatrolSetup {
        &self.patrol
    }

    /// The way-points of this scenario's route, start first and goal last.
    pub fn route(&self) -> &[Vec2] {
        match self.scenario {
            Scenario::Movement => &self.world.movement_route,
            Scenario::Patrol => &self.world.patrol_route,
        }
    }

    /// The behavior's settings in physical units.
    pub fn settings(&self, behavior: &Behavior) -> Settings {
        let value = |slot: usize, fallback: f64| {
            self.components[slot].map_or(fallback, |i| {
                self.space.components()[i].numeric_value(behavior.get(i))
            })
        };
        Settings {
            speed: value(0, 1.0),
            padding: value(1, 0.0),
            scan_time: value(2, 0.0),
            scan_distance: value(3, 0.0),
        }
    }

    /// The plan for `behavior`'s padding with the people in `humans` standing, or `None`
    /// when there is no way through. Computed once, then shared.
    pub fn plan(&self, behavior: &Behavior, humans: u32) -> Option<&Plan> {
        let padding_index = self.components[1].map_or(0, |i| usize::from(behavior.get(i)));
        let slot = (padding_index << self.world.humans.len()) | humans as usize;
        self.plans[slot]
            .get_or_init(|| {
                let points = self.visibility[padding_index]
                    .get_or_init(|| self.problem(behavior).visibility(self.route()))
                    .route(humans)?;
                let obstacles: Vec<&Shape> = self.world.obstacles_with(humans).collect();
                Some(Plan::new(
                    points,
                    &obstacles,
                    &self.world.robot,
                    self.world.size,
                ))
            })
            .as_ref()
    }

    /// The cache slot of `behavior`'s padding with the people in `humans` standing.
    fn plan_slot(&self, behavior: &Behavior, humans: u32) -> usize {
        let padding_index = self.components[1].map_or(0, |i| usize::from(behavior.get(i)));
        (padding_index << self.world.humans.len()) | humans as usize
    }

    /// The planning problem for `behavior`'s padding: the map's obstacles fixed, the
    /// people optional.
    fn problem(&self, behavior: &Behavior) -> Problem<'_> {
        Problem {
            size: self.world.size,
            fixed: self.world.obstacles.iter().map(|o| &o.shape).collect(),
            optional: self.world.humans.iter().map(|h| &h.shape).collect(),
            clearance: self.world.robot.radius + self.settings(behavior).padding,
        }
    }

    /// One command judged by an operator at `attention` (1: [`Domain::run`]) whose goals
    /// change `goal_change_at` seconds in (infinity: never): the run, the operator's
    /// judgement of its trace ([`OperatorModel::judge_attending`]), cut by the goal change
    /// if the command has not ended by then (weighed as the operator weighs an
    /// interruption the robot cannot attribute, its default weight), then what the robot
    /// perceived and its self-assessment up to the judgement's end.
    fn run_at(
        &self,
        behavior: &Behavior,
        operator: &OperatorModel,
        attention: f64,
        goal_change_at: f64,
        rng: &mut dyn RngCore,
    ) -> Judgement {
        let run = self.simulate(behavior, rng, false);
        let mut judgement = operator.judge_attending(&run.trace, attention, rng);
        if goal_change_at < judgement.outcome.duration_s {
            judgement = Judgement::redirected(operator.weights.default, goal_change_at);
        }
        let until = judgement.outcome.duration_s;
        let observed = perception::perceive(&run.trace, until, self.observations());
        judgement
            .observing(observed)
            .assessing(perception::self_assessment(
                &run.trace,
                until,
                &self.detector,
            ))
    }

    /// Simulates one run of `behavior`, drawing all randomness from `rng`. With `record`,
    /// the driven path is kept for drawing.
    pub fn simulate(&self, behavior: &Behavior, rng: &mut dyn RngCore, record: bool) -> Run<'_> {
        let settings = self.settings(behavior);
        let mut humans = 0;
        for (i, spot) in self.world.humans.iter().enumerate() {
            if rng.random::<f64>() < spot.occupied {
                humans |= 1 << i;
            }
        }
        let objects = match self.scenario {
            Scenario::Movement => Vec::new(),
            Scenario::Patrol => self.patrol.place(&self.ground, rng),
        };
        let plan = self.plan(behavior, humans);
        let mut run = Run {
            settings,
            humans,
            plan,
            // Room for three events per object (scan, label, detonation), a pass per spot
            // where people stand, a few collisions, the closest pass, falling behind plan
            // and the arrival.
            trace: Trace {
                events: Vec::with_capacity(3 * objects.len() + self.world.humans.len() + 6),
            },
            driven: Vec::new(),
            objects: objects
                .iter()
                .map(|&object| ObjectFate {
                    object,
                    scanned_from: None,
                    labelled_explosive: None,
                })
                .collect(),
        };
        let Some(plan) = plan else {
            run.trace
                .push(self.world.robot.replan_timeout, EventKind::Stuck);
            return run;
        };
        let track = record.then_some(&mut run.driven);
        let passes = self.passes[self.plan_slot(behavior, humans)].get_or_init(|| {
            let spots = self.people_along(plan);
            let at = spots.iter().map(|p| p.0).collect();
            Passes { spots, at }
        });
        let people = &passes.spots;
        match self.scenario {
            Scenario::Movement => {
                let driven = drive(
                    plan,
                    &self.world.robot,
                    settings.speed,
                    &[],
                    &passes.at,
                    rng,
                    &mut run.trace,
                    track,
                );
                for (&(_, person, gap), &(t, speed)) in people.iter().zip(&driven.watched) {
                    let present = humans & (1 << person) != 0;
                    run.trace.insert_sorted(
                        t,
                        EventKind::PassedPerson {
                            person,
                            present,
                            gap,
                            speed,
                        },
                    );
                }
            }
            Scenario::Patrol => {
                self.patrol_run(
                    plan,
                    settings,
                    passes,
                    humans,
                    rng,
                    &mut run.trace,
                    &mut run.objects,
                    track,
                );
            }
        }
        run
    }

    /// Where the plan passes closest to each spot where people stand: arc length, the
    /// spot, and the body-to-body gap to a person there (m); sorted along the path. Which
    /// spots are occupied is `humans`. Geometry only: no random draw.
    fn people_along(&self, plan: &Plan) -> Vec<(f64, usize, f64)> {
        let radius = self.world.robot.radius;
        let mut people: Vec<(f64, usize, f64)> = self
            .world
            .humans
            .iter()
            .enumerate()
            .map(|(i, spot)| {
                let centre = match spot.shape {
                    Shape::Circle { center, .. } => center,
                    _ => spot.shape.nearest_point(plan.points[0]),
                };
                let (s, _) = plan.nearest(centre);
                let gap = spot.shape.distance_to_point(plan.point_at(s).0) - radius;
                (s, i, gap)
            })
            .collect();
        people.sort_by(|a, b| a.0.total_cmp(&b.0));
        people
    }

    /// The patrol part of a run: spot objects while driving, stop, approach, scan, label.
    #[allow(clippy::too_many_arguments)]
    fn patrol_run(
        &self,
        plan: &Plan,
        settings: Settings,
        passes: &Passes,
        humans: u32,
        rng: &mut dyn RngCore,
        trace: &mut Trace,
        fates: &mut [ObjectFate],
        track: Option<&mut Vec<Vec2>>,
    ) {
        let robot = &self.world.robot;
        // Gap between body and object the robot keeps while scanning: its scan distance,
        // unless its padding asks for more.
        let standoff = settings.scan_distance.max(settings.padding);
        // Per object: where the path passes it, which it is, whether the camera spots it
        // and, if so, the time to drive out to the scan position (or back).
        let mut visits: Vec<(f64, usize, bool, f64)> = fates
            .iter()
            .enumerate()
            .map(|(i, fate)| {
                let (s, distance) = plan.nearest(fate.object.at);
                let spotted = rng.random::<f64>() < self.patrol.p_spot(distance, settings.speed);
                let approach = if spotted {
                    let spur = (distance - robot.radius - standoff).abs();
                    point_to_point(spur, settings.speed, robot.accel, robot.decel)
                } else {
                    0.0
                };
                (s, i, spotted, approach)
            })
            .collect();
        visits.sort_by(|a, b| a.0.total_cmp(&b.0));
        let marks: Vec<Mark> = visits
            .iter()
            .map(|&(s, _, spotted, approach)| Mark {
                s,
                dwell: if spotted {
                    2.0 * approach + settings.scan_time
                } else {
                    0.0
                },
            })
            .collect();
        let driven = drive(
            plan,
            robot,
            settings.speed,
            &marks,
            &passes.at,
            rng,
            trace,
            track,
        );
        let arrived = trace.events.pop().expect("a drive ends with its arrival");
        for (&(_, person, gap), &(t, speed)) in passes.spots.iter().zip(&driven.watched) {
            let present = humans & (1 << person) != 0;
            trace.push(
                t,
                EventKind::PassedPerson {
                    person,
                    present,
                    gap,
                    speed,
                },
            );
        }
        for (&(s, i, spotted, approach), &t) in visits.iter().zip(&driven.mark_times) {
            let fate = &mut fates[i];
            if !spotted {
                trace.push(t, EventKind::MissedObject { object: i });
                continue;
            }
            let (on_path, _) = plan.point_at(s);
            let toward = (fate.object.at - on_path).unit();
            fate.scanned_from = Some(fate.object.at - toward * (robot.radius + standoff));
            let explosive = fate.object.explosive;
            let correct = rng.random::<f64>()
                < self
                    .detector
                    .accuracy(explosive, settings.scan_time, standoff);
            let labelled_explosive = explosive == correct;
            fate.labelled_explosive = Some(labelled_explosive);
            let t_label = t + approach + settings.scan_time;
            trace.push(
                t_label,
                EventKind::Scanned {
                    object: i,
                    distance: standoff,
                    duration: settings.scan_time,
                },
            );
            trace.push(
                t_label,
                EventKind::Labelled {
                    object: i,
                    explosive,
                    labelled_explosive,
                },
            );
            if explosive && !labelled_explosive {
                let t_boom = (t_label + self.patrol.fuse).min(arrived.t);
                trace.push(t_boom, EventKind::Detonation { object: i });
            }
        }
        trace.events.push(arrived);
        trace.sort();
    }
}

impl Domain for UgvDomain {
    type Operator = OperatorModel;

    fn name(&self) -> &str {
        self.scenario.as_str()
    }

    fn space(&self) -> &Arc<BehaviorSpace> {
        &self.space
    }

    fn causes(&self) -> &[DeclaredCause] {
        self.scenario.causes()
    }

    fn observations(&self) -> &[Cause] {
        perception::observations(self.scenario)
    }

    fn hints(&self) -> &[Hint] {
        perception::hints(self.scenario)
    }

    fn contexts(&self) -> &ContextSpace {
        crate::job_context::contexts()
    }

    fn statements(&self) -> &[String] {
        crate::statements::names(self.scenario)
    }

    fn true_statements(&self, operator: &OperatorModel) -> Vec<cbr_core::Statement> {
        crate::statements::truth(self.scenario, operator)
    }

    fn operator_in_context(
        &self,
        operator: &OperatorModel,
        context: &Context,
    ) -> Option<OperatorModel> {
        (!operator.contexts.is_empty()).then(|| operator.in_context(context))
    }

    fn run(
        &self,
        behavior: &Behavior,
        operator: &OperatorModel,
        rng: &mut dyn RngCore,
    ) -> Judgement {
        self.run_at(behavior, operator, 1.0, f64::INFINITY, rng)
    }

    fn attentive(&self) -> Option<&dyn Attentive<Operator = OperatorModel>> {
        Some(self)
    }

    fn goal_changing(&self) -> Option<&dyn GoalChanging<Operator = OperatorModel>> {
        Some(self)
    }

    fn self_judging(&self) -> Option<&dyn SelfJudging<Operator = OperatorModel>> {
        Some(self)
    }
}

impl Attentive for UgvDomain {
    fn run_attending(
        &self,
        behavior: &Behavior,
        operator: &OperatorModel,
        attention: f64,
        rng: &mut dyn RngCore,
    ) -> Judgement {
        self.run_at(behavior, operator, attention, f64::INFINITY, rng)
    }
}

impl GoalChanging for UgvDomain {
    fn run_redirected(
        &self,
        behavior: &Behavior,
        operator: &OperatorModel,
        attention: f64,
        at_s: f64,
        rng: &mut dyn RngCore,
    ) -> Judgement {
        self.run_at(behavior, operator, attention, at_s, rng)
    }
}

impl SelfJudging for UgvDomain {
    fn competence_parts(&self) -> &[CompetencePart] {
        self_competence::parts(self.scenario)
    }

    fn predict_competence(&self, behavior: &Behavior) -> Vec<Option<f64>> {
        self_competence::predict(
            self.scenario,
            &self.settings(behavior),
            &self.patrol,
            &self.detector,
        )
    }

    fn competence_truth(&self, behavior: &Behavior, rng: &mut dyn RngCore) -> Vec<Option<bool>> {
        self_competence::truth(self.scenario, &self.simulate(behavior, rng, false))
    }
}
