//! The landscape of an operator, for any [`Domain`]: how often a behavior completes under
//! the operator, per *cell*. A cell fixes some components (all of them: one cell per
//! behavior; two of them: one cell per pair of values, the other components drawn
//! uniformly at random for every run). A domain author reads it to see what each operator
//! rewards; the report draws every arm's final behaviors over it.
//!
//! Every run of cell `k` draws from one ChaCha8 stream: seeded with the landscape's seed,
//! stream number `k` (the behavior's rank when every component is fixed). A run draws, in
//! order, the operator (only when there are several: one uniformly, as an experiment
//! drawing its operator per trial does), the free components (only when there are
//! some), then whatever the domain's run draws. Cells run in parallel and are collected in
//! order, so the estimate does not depend on the number of threads.
//!
//! **The trustworthy region.** The trust estimate of a behavior is the sum of its
//! commands' contributions `w * cmd` (+w for a completion, -w otherwise), starting at 0.
//! After `n` commands its expected value is `n * drift`, where `drift` is the mean
//! contribution of one command. With a positive drift the expected estimate climbs to the
//! trustworthy threshold (after `tau_T / drift` commands) and never reaches the
//! untrustworthy one; with a negative drift it falls to the untrustworthy threshold. A cell
//! is in the trustworthy region when its estimated drift is positive
//! ([`Tally::trusted_on_average`]). With one weight for every outcome (the movement
//! operators) that is `P(complete) > 1/2`; with symmetric thresholds and one weight it is
//! also exactly the cells more likely than not to reach `tau_T` before `tau_UT` (gambler's
//! ruin); with cause-dependent weights (the patrol operators weigh a detonation three times
//! the rest) the boundary moves with the causes of the failures.

use crate::{Domain, Judgement};
use cbr_core::{Behavior, BehaviorSpace};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::fmt::Write;
use trust::{Cause, DeclaredCause, OutcomeKind};

/// The runs of one cell, counted.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tally {
    /// Runs made.
    pub runs: u32,
    /// Runs the operator let complete.
    pub completed: u32,
    /// The sum of the runs' contributions `w * cmd` to the trust estimate.
    pub contribution: f64,
    /// Runs that failed or were interrupted, by the operator's true reason (evaluation
    /// reads the truth; no searcher does).
    pub causes: BTreeMap<Cause, u32>,
    /// Runs by their contribution to the estimate (each distinct contribution once, in
    /// the order first met): the step law of the estimate's walk, from which the
    /// known-operator limit is solved ([`crate::reference::known_operator`]).
    pub steps: Vec<StepTally>,
}

/// Runs that contributed the same to the estimate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepTally {
    /// The contribution `w * cmd` of each.
    pub contribution: f64,
    /// Whether they failed or were interrupted (a completion of weight 0 contributes 0
    /// too, and is not untrustworthy).
    pub untrustworthy: bool,
    /// How many runs.
    pub runs: u32,
}

impl Tally {
    /// Fraction of runs completed.
    pub fn p_complete(&self) -> f64 {
        f64::from(self.completed) / f64::from(self.runs.max(1))
    }

    /// The mean contribution of one command to the trust estimate: its expected change
    /// per command.
    pub fn drift(&self) -> f64 {
        self.contribution / f64::from(self.runs.max(1))
    }

    /// Whether the expected trust estimate climbs (positive drift): the cell is in the
    /// trustworthy region (see the module documentation).
    pub fn trusted_on_average(&self) -> bool {
        self.drift() > 0.0
    }

    /// Adds the runs of `other`.
    fn add(&mut self, other: &Tally) {
        self.runs += other.runs;
        self.completed += other.completed;
        self.contribution += other.contribution;
        for (&cause, &n) in &other.causes {
            *self.causes.entry(cause).or_default() += n;
        }
        for step in &other.steps {
            self.count_step(step.contribution, step.untrustworthy, step.runs);
        }
    }

    /// Counts one run judged `judgement`.
    pub fn record(&mut self, judgement: &Judgement) {
        let outcome = &judgement.outcome;
        self.runs += 1;
        self.contribution += outcome.contribution();
        self.count_step(outcome.contribution(), outcome.is_untrustworthy(), 1);
        if outcome.kind == OutcomeKind::Completed {
            self.completed += 1;
        } else if let Some(cause) = judgement.truth {
            *self.causes.entry(cause).or_default() += 1;
        }
    }

    /// Counts `runs` runs that contributed `contribution`.
    fn count_step(&mut self, contribution: f64, untrustworthy: bool, runs: u32) {
        match self
            .steps
            .iter_mut()
            .find(|s| s.contribution == contribution && s.untrustworthy == untrustworthy)
        {
            Some(step) => step.runs += runs,
            None => self.steps.push(StepTally {
                contribution,
                untrustworthy,
                runs,
            }),
        }
    }
}

/// Completion estimates per cell.
#[derive(Clone, Debug, PartialEq)]
pub struct Landscape {
    /// The components each cell fixes, in the space's order.
    pub fixed: Vec<usize>,
    /// The number of values of each fixed component.
    pub lengths: Vec<usize>,
    /// Operators the runs drew from (1: a fixed operator).
    pub operators: usize,
    /// One tally per cell, in mixed-radix order of the fixed components' values, the last
    /// fastest (with every component fixed: the space's rank order).
    pub cells: Vec<Tally>,
}

/// Why a landscape cannot be estimated or drawn.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum LandscapeError {
    /// A component name is not in the space.
    #[error("unknown component `{name}`; the space has: {known}")]
    UnknownComponent {
        /// The name given.
        name: String,
        /// The names available.
        known: String,
    },
    /// The axes are not given as two names separated by a comma.
    #[error("expected two component names separated by a comma (e.g. `speed,padding`), got `{0}`")]
    Axes(String),
    /// The two axes are the same component.
    #[error("the heatmap needs two different components, got `{0}` twice")]
    SameComponent(String),
    /// The fixed components are not distinct indices of the space, in increasing order.
    #[error(
        "the fixed components must be distinct component indices below {components}, in increasing order, got {fixed:?}"
    )]
    Fixed {
        /// The indices given.
        fixed: Vec<usize>,
        /// The space's number of components.
        components: usize,
    },
    /// No operator to judge the runs.
    #[error("a landscape needs at least one operator")]
    NoOperator,
    /// No run per cell.
    #[error("a landscape needs at least one run per cell")]
    NoRuns,
    /// A heatmap asks for a component the landscape does not fix.
    #[error("the landscape does not fix component `{0}`: it averaged over it")]
    NotFixed(String),
    /// A stop was requested ([`crate::interrupt`]) before every cell was estimated.
    #[error(transparent)]
    Interrupted(#[from] crate::Interrupted),
}

/// Runs every cell of `domain` that fixes the components `fixed` (indices, increasing;
/// all of them for one cell per behavior) `runs` times, each run under one of `operators`
/// (drawn uniformly per run when there are several), in parallel on the current rayon
/// pool. `progress()` is called after each cell.
pub fn estimate<D: Domain>(
    domain: &D,
    operators: &[&D::Operator],
    fixed: &[usize],
    runs: u32,
    seed: u64,
    progress: &(dyn Fn() + Sync),
) -> Result<Landscape, LandscapeError> {
    let space = domain.space();
    let n = space.components().len();
    if fixed.windows(2).any(|w| w[0] >= w[1]) || fixed.iter().any(|&c| c >= n) {
        return Err(LandscapeError::Fixed {
            fixed: fixed.to_vec(),
            components: n,
        });
    }
    if operators.is_empty() {
        return Err(LandscapeError::NoOperator);
    }
    if runs == 0 {
        return Err(LandscapeError::NoRuns);
    }
    let lengths: Vec<usize> = fixed.iter().map(|&c| space.components()[c].len()).collect();
    let count: usize = lengths.iter().product();
    let every_component = fixed.len() == n;
    let cells = (0..count)
        .into_par_iter()
        .map(|cell| {
            crate::interrupt::check()?;
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            rng.set_stream(cell as u64);
            let mut tally = Tally::default();
            // Every component fixed: the behavior of rank `cell`; otherwise the fixed values.
            let (whole, values) = if every_component {
                (Some(space.unrank(cell as u64)), Vec::new())
            } else {
                (None, cell_values(&lengths, cell))
            };
            for _ in 0..runs {
                let operator = match operators.len() {
                    1 => operators[0],
                    k => operators[rng.random_range(0..k)],
                };
                let behavior = match whole {
                    Some(behavior) => behavior,
                    None => with_values(space.draw(&mut rng), fixed, &values),
                };
                tally.record(&domain.run(&behavior, operator, &mut rng));
            }
            progress();
            Ok(tally)
        })
        .collect::<Result<_, crate::Interrupted>>()?;
    Ok(Landscape {
        fixed: fixed.to_vec(),
        lengths,
        operators: operators.len(),
        cells,
    })
}

/// The values of the fixed components in cell `cell` (mixed radix, the last fastest).
fn cell_values(lengths: &[usize], mut cell: usize) -> Vec<u16> {
    let mut values = vec![0u16; lengths.len()];
    for (value, &len) in values.iter_mut().zip(lengths).rev() {
        *value = (cell % len) as u16;
        cell /= len;
    }
    values
}

/// `behavior` with component `fixed[i]` set to `values[i]`.
fn with_values(behavior: Behavior, fixed: &[usize], values: &[u16]) -> Behavior {
    fixed
        .iter()
        .zip(values)
        .fold(behavior, |b, (&component, &value)| b.with(component, value))
}

/// The index of component `name`, or an error listing the names available.
pub fn component(space: &BehaviorSpace, name: &str) -> Result<usize, LandscapeError> {
    space
        .component_index(name)
        .ok_or_else(|| LandscapeError::UnknownComponent {
            name: name.to_owned(),
            known: space
                .components()
                .iter()
                .map(|c| c.name.as_str())
                .collect::<Vec<_>>()
                .join(", "),
        })
}

/// A heatmap's two components from `"a,b"` (across, then up): both known, and different.
pub fn axes(space: &BehaviorSpace, names: &str) -> Result<(usize, usize), LandscapeError> {
    let (a, b) = names
        .split_once(',')
        .ok_or_else(|| LandscapeError::Axes(names.to_owned()))?;
    let (x, y) = (component(space, a.trim())?, component(space, b.trim())?);
    if x == y {
        return Err(LandscapeError::SameComponent(a.trim().to_owned()));
    }
    Ok((x, y))
}

/// The cells of a landscape over two of its fixed components, the others pooled.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// The component across.
    pub x: usize,
    /// The component up.
    pub y: usize,
    /// Values of `x`.
    pub nx: usize,
    /// Values of `y`.
    pub ny: usize,
    /// The tally of values `(i, j)` at `i * ny + j`: the runs of every cell with those
    /// values, pooled (every cell has as many runs, so its completion share is the mean
    /// of theirs).
    pub tallies: Vec<Tally>,
}

impl Grid {
    /// The tally of value `i` of `x` and `j` of `y`.
    pub fn at(&self, i: usize, j: usize) -> &Tally {
        &self.tallies[i * self.ny + j]
    }
}

/// The columns every landscape's CSV has after those of its fixed components
/// ([`Landscape::csv`]).
pub const CSV_COLUMNS: &str = "runs,completed,p_complete";

/// Whether `bytes` are a landscape's CSV ([`Landscape::csv`]): its header line holds
/// [`CSV_COLUMNS`].
pub fn is_landscape_csv(bytes: &[u8]) -> bool {
    let header = bytes.split(|&b| b == b'\n').next().unwrap_or_default();
    header
        .windows(CSV_COLUMNS.len())
        .any(|w| w == CSV_COLUMNS.as_bytes())
}

impl Landscape {
    /// The cells over components `x` (across) and `y` (up), both fixed by the landscape,
    /// pooled over the other fixed components.
    pub fn grid(&self, space: &BehaviorSpace, x: usize, y: usize) -> Result<Grid, LandscapeError> {
        let name = |c: usize| space.components()[c].name.clone();
        if x == y {
            return Err(LandscapeError::SameComponent(name(x)));
        }
        let position = |c: usize| {
            self.fixed
                .iter()
                .position(|&f| f == c)
                .ok_or_else(|| LandscapeError::NotFixed(name(c)))
        };
        let (px, py) = (position(x)?, position(y)?);
        let (nx, ny) = (self.lengths[px], self.lengths[py]);
        let mut tallies = vec![Tally::default(); nx * ny];
        for (cell, tally) in self.cells.iter().enumerate() {
            let values = cell_values(&self.lengths, cell);
            tallies[usize::from(values[px]) * ny + usize::from(values[py])].add(tally);
        }
        Ok(Grid {
            x,
            y,
            nx,
            ny,
            tallies,
        })
    }

    /// One line per cell: the fixed components' values, the runs, completions, the
    /// completion probability and the count of each of the domain's declared `causes`.
    pub fn csv(&self, space: &BehaviorSpace, causes: &[DeclaredCause]) -> String {
        let mut out = String::new();
        for &c in &self.fixed {
            write!(out, "{},", space.components()[c].name).ok();
        }
        out.push_str(CSV_COLUMNS);
        for cause in causes {
            write!(out, ",{}", cause.name).ok();
        }
        out.push('\n');
        for (cell, t) in self.cells.iter().enumerate() {
            for (&c, value) in self.fixed.iter().zip(cell_values(&self.lengths, cell)) {
                write!(out, "{},", space.components()[c].display_value(value)).ok();
            }
            write!(out, "{},{},{:.4}", t.runs, t.completed, t.p_complete()).ok();
            for cause in causes {
                write!(out, ",{}", t.causes.get(&cause.name).copied().unwrap_or(0)).ok();
            }
            out.push('\n');
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Judgement;
    use cbr_core::NamedComponent;
    use rand::RngCore;
    use std::sync::Arc;

    /// Two components `a` (3 values) and `b` (2 values). An operator is a table of
    /// completion probabilities by value of `a` (the run completes when a uniform draw
    /// falls below it); `b` changes nothing. Failures are dropped items of weight 2,
    /// completions weigh 1.
    struct Dice {
        space: Arc<BehaviorSpace>,
    }

    const DROPPED: Cause = Cause::from_static("dropped-item");

    const DICE_CAUSES: [DeclaredCause; 2] = [
        DeclaredCause {
            name: Cause::from_static("too-slow"),
            default_weight: None,
        },
        DeclaredCause {
            name: DROPPED,
            default_weight: None,
        },
    ];

    impl Dice {
        fn new() -> Self {
            let a = NamedComponent::numeric("a", "m", 0.0, 1.0, 3).unwrap();
            let b = NamedComponent::numeric("b", "s", 0.0, 1.0, 2).unwrap();
            Self {
                space: Arc::new(BehaviorSpace::new(vec![a, b]).unwrap()),
            }
        }
    }

    impl crate::SimulatedOperator for [f64; 3] {}

    impl Domain for Dice {
        type Operator = [f64; 3];

        fn name(&self) -> &str {
            "dice"
        }

        fn space(&self) -> &Arc<BehaviorSpace> {
            &self.space
        }

        fn causes(&self) -> &[DeclaredCause] {
            &DICE_CAUSES
        }

        fn run(
            &self,
            behavior: &Behavior,
            operator: &[f64; 3],
            rng: &mut dyn RngCore,
        ) -> Judgement {
            let p = operator[usize::from(behavior.get(0))];
            if rng.random::<f64>() < p {
                Judgement::completed(1.0, 1.0)
            } else {
                Judgement::failed(2.0, DROPPED, 1.0)
            }
        }
    }

    #[test]
    fn certain_operators_give_exact_counts_per_behavior() {
        // Completion is certain for a = 0 and a = 2, impossible for a = 1.
        let dice = Dice::new();
        let land = estimate(&dice, &[&[1.0, 0.0, 1.0]], &[0, 1], 10, 7, &|| {}).unwrap();
        assert_eq!(land.lengths, [3, 2]);
        // Rank order: (a, b) = (0,0), (0,1), (1,0), (1,1), (2,0), (2,1).
        let completed: Vec<u32> = land.cells.iter().map(|t| t.completed).collect();
        assert_eq!(completed, [10, 10, 0, 0, 10, 10]);
        // Drift: +1 per completion; -2 per failure.
        assert_eq!(land.cells[0].drift(), 1.0);
        assert_eq!(land.cells[2].drift(), -2.0);
        assert_eq!(land.cells[2].causes[&DROPPED], 10);
        // The step law: ten +1 steps where it completes, ten -2 steps where it does not.
        let step = |contribution, untrustworthy| StepTally {
            contribution,
            untrustworthy,
            runs: 10,
        };
        assert_eq!(land.cells[0].steps, [step(1.0, false)]);
        assert_eq!(land.cells[2].steps, [step(-2.0, true)]);
        assert!(land.cells[0].trusted_on_average());
        assert!(!land.cells[2].trusted_on_average());
        let csv = land.csv(&dice.space, dice.causes());
        assert!(csv.starts_with("a,b,runs,completed,p_complete,too-slow,dropped-item\n"));
        assert!(csv.contains("\n1,0,10,0,0.0000,0,10\n"), "{csv}");
    }

    #[test]
    fn a_pair_with_the_others_drawn_averages_over_them() {
        // Fixing only `b`, every run draws `a` uniformly: with completion certain for two
        // of the three values of `a`, P(complete) is 2/3 in every cell of `b`.
        let dice = Dice::new();
        let land = estimate(&dice, &[&[1.0, 0.0, 1.0]], &[1], 3000, 1, &|| {}).unwrap();
        assert_eq!(land.cells.len(), 2);
        for t in &land.cells {
            assert_eq!(t.runs, 3000);
            assert!(
                (t.p_complete() - 2.0 / 3.0).abs() < 0.03,
                "{}",
                t.p_complete()
            );
            // Drift 2/3 * 1 - 1/3 * 2 = 0: on the boundary of the region.
            assert!(t.drift().abs() < 0.1);
        }
    }

    #[test]
    fn several_operators_are_drawn_per_run() {
        // One operator always completes, the other never: the mixture completes half the
        // time, as the mean of the two landscapes.
        let dice = Dice::new();
        let (yes, no) = ([1.0; 3], [0.0; 3]);
        let land = estimate(&dice, &[&yes, &no], &[0, 1], 4000, 3, &|| {}).unwrap();
        assert_eq!(land.operators, 2);
        for t in &land.cells {
            assert!((t.p_complete() - 0.5).abs() < 0.03, "{}", t.p_complete());
        }
    }

    #[test]
    fn the_grid_pools_the_other_fixed_components() {
        let dice = Dice::new();
        let land = estimate(&dice, &[&[1.0, 0.0, 1.0]], &[0, 1], 5, 2, &|| {}).unwrap();
        let grid = land.grid(&dice.space, 1, 0).unwrap();
        assert_eq!((grid.nx, grid.ny), (2, 3));
        assert_eq!(grid.at(0, 1).runs, 5);
        assert_eq!(grid.at(1, 2).completed, 5);
        let pair = estimate(&dice, &[&[1.0, 0.0, 1.0]], &[0], 5, 2, &|| {}).unwrap();
        assert_eq!(
            pair.grid(&dice.space, 0, 1),
            Err(LandscapeError::NotFixed("b".into()))
        );
        // Pooled over `b`: 10 runs per value of `a`.
        let landscape_a = estimate(&dice, &[&[1.0, 0.0, 1.0]], &[0, 1], 5, 2, &|| {}).unwrap();
        let mut pooled = Tally::default();
        pooled.add(&landscape_a.cells[0]);
        pooled.add(&landscape_a.cells[1]);
        assert_eq!(pooled.runs, 10);
        assert_eq!(pooled.contribution, 10.0);
    }

    #[test]
    fn the_estimate_is_deterministic_and_checks_its_inputs() {
        let dice = Dice::new();
        let op = [0.3, 0.5, 0.9];
        let a = estimate(&dice, &[&op], &[0, 1], 50, 11, &|| {}).unwrap();
        let b = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| estimate(&dice, &[&op], &[0, 1], 50, 11, &|| {}).unwrap());
        assert_eq!(a, b);
        let fixed_err = |fixed: &[usize]| estimate(&dice, &[&op], fixed, 1, 0, &|| {}).unwrap_err();
        assert!(matches!(fixed_err(&[1, 0]), LandscapeError::Fixed { .. }));
        assert!(matches!(fixed_err(&[2]), LandscapeError::Fixed { .. }));
        assert!(matches!(fixed_err(&[0, 0]), LandscapeError::Fixed { .. }));
        assert_eq!(
            estimate(&dice, &[], &[0], 1, 0, &|| {}),
            Err(LandscapeError::NoOperator)
        );
        assert_eq!(
            estimate(&dice, &[&op], &[0], 0, 0, &|| {}),
            Err(LandscapeError::NoRuns)
        );
    }

    #[test]
    fn the_trustworthy_region_is_where_the_estimate_climbs() {
        let tally = |runs, completed, contribution| Tally {
            runs,
            completed,
            contribution,
            causes: BTreeMap::new(),
            steps: Vec::new(),
        };
        // Weights 1: 6 of 10 complete, drift (6 - 4) / 10 = 0.2 > 0; 5 of 10 is a walk
        // without drift, which does not climb.
        assert!(tally(10, 6, 2.0).trusted_on_average());
        assert!(!tally(10, 5, 0.0).trusted_on_average());
        // Patrol-like weights (completion 1/3, detonation 1): 7 of 10 complete, 3
        // detonate: drift (7/3 - 3) / 10 < 0, outside the region despite P(complete) 0.7.
        let patrol = tally(10, 7, 7.0 / 3.0 - 3.0);
        assert_eq!(patrol.p_complete(), 0.7);
        assert!(!patrol.trusted_on_average());
        // Gambler's ruin with steps of 1 between thresholds +5 and -5: P(+5 first) is
        // 1 / (1 + (q/p)^5), above 1/2 exactly when p > 1/2, i.e. when the drift is > 0.
        for p in [0.3f64, 0.49, 0.51, 0.8] {
            let ruin: f64 = 1.0 / (1.0 + ((1.0 - p) / p).powi(5));
            let drift = p - (1.0 - p);
            assert_eq!(ruin > 0.5, drift > 0.0, "p = {p}");
        }
    }

    #[test]
    fn axes_are_two_different_known_components() {
        let space = Dice::new().space;
        assert_eq!(axes(&space, "b, a"), Ok((1, 0)));
        assert!(matches!(axes(&space, "a"), Err(LandscapeError::Axes(_))));
        assert!(matches!(
            axes(&space, "a,a"),
            Err(LandscapeError::SameComponent(_))
        ));
        let err = axes(&space, "a,c").unwrap_err().to_string();
        assert_eq!(err, "unknown component `c`; the space has: a, b");
    }
}
