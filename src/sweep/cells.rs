//! A checked sweep: its base suite, its cells (one parameter at a time or a grid), each
//! checked as a suite, its runs (a cell and a seed) and their shards, within the limits
//! ([`crate::limits::SWEEP_RUNS`], [`crate::limits::SWEEP_TRIALS`]).

use super::{Design, Parameter, SuiteSource, SweepConfig, SweepError};
use crate::catalog::{Catalog, resolve_readings};
use crate::config_file::ConfigFileError;
use crate::limits::{SWEEP_RUNS, SWEEP_TRIALS};
use crate::suite::{EMBEDDED_ORIGIN, SuiteConfig};
use files::{parse_ron, read_text};
use lab::report::file_stems;
use std::path::{Path, PathBuf};

/// One cell: a label and its suite.
#[derive(Clone, Debug)]
pub struct Cell {
    /// e.g. `base` or `lambda=0.9`.
    pub label: String,
    /// The suite this cell runs.
    pub suite: SuiteConfig,
}

/// One run: a cell and a seed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RunId {
    /// The cell's index.
    pub cell: usize,
    /// The seed's index.
    pub seed: usize,
}

/// A checked sweep: its cells and runs.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// The config as read.
    pub config: SweepConfig,
    /// Where the base suite's operator files are found from.
    pub origin: PathBuf,
    /// The cells, in report order.
    pub cells: Vec<Cell>,
    /// Each cell's folder name under `runs/` ([`file_stems`] of the labels).
    pub(super) folders: Vec<String>,
}

impl Sweep {
    /// Reads and checks a sweep file against `catalog`.
    pub fn load<C: Catalog>(catalog: &C, path: &Path) -> Result<Self, SweepError> {
        let text = read_text(path)?;
        let config: SweepConfig = parse_ron(&text, path)?;
        Self::new(catalog, config, path)
    }

    /// Checks `config` (read from `path`) against `catalog` and forms its cells.
    pub fn new<C: Catalog>(
        catalog: &C,
        config: SweepConfig,
        path: &Path,
    ) -> Result<Self, SweepError> {
        let invalid = |field: &str, message: String| {
            SweepError::from(ConfigFileError::invalid(path, field.to_owned(), message))
        };
        if config.seeds.is_empty() {
            return Err(invalid("seeds", "at least one seed is needed".into()));
        }
        if let Some(j) =
            (1..config.seeds.len()).find(|&j| config.seeds[..j].contains(&config.seeds[j]))
        {
            return Err(invalid(
                "seeds",
                format!(
                    "seed {} is listed twice; each seed runs every cell once",
                    config.seeds[j]
                ),
            ));
        }
        for (i, p) in config.parameters.iter().enumerate() {
            if p.len() == 0 {
                return Err(invalid(
                    &format!("parameters[{i}]"),
                    format!("{} lists no value", p.name()),
                ));
            }
            if let Some(j) = p.repeated() {
                return Err(invalid(
                    &format!("parameters[{i}]"),
                    format!("{} lists {} twice", p.name(), p.value(j)),
                ));
            }
        }
        let (base, origin) = match &config.suite {
            SuiteSource::Embedded => (
                SuiteConfig::embedded(catalog),
                PathBuf::from(EMBEDDED_ORIGIN),
            ),
            SuiteSource::File(file) => {
                let file = path.parent().unwrap_or(Path::new(".")).join(file);
                (SuiteConfig::load(catalog, &file), file)
            }
        };
        let mut base = base.map_err(|reason| SweepError::Suite {
            cell: "base".into(),
            reason,
        })?;
        // Every reading spelled out, so a cell setting a reading to its default is the
        // base cell.
        base.readings = resolve_readings(catalog, &base.readings)
            .map_err(|e| invalid("suite", e.to_string()))?;
        if let Some(trials) = config.trials {
            base.trials = trials;
        }
        if let Some(arms) = &config.arms {
            base.arms.clone_from(arms);
        }
        // Counted before any cell is built: a grid of a few long lists has more cells than
        // memory holds.
        let cells = match config.design {
            Design::OneAtATime => config.parameters.iter().fold(1usize, |n, p| {
                n.saturating_add((0..p.len()).filter(|&i| !p.is_in(i, &base)).count())
            }),
            Design::Grid => config
                .parameters
                .iter()
                .fold(1usize, |n, p| n.saturating_mul(p.len())),
        };
        let runs = cells.saturating_mul(config.seeds.len());
        let design = match config.design {
            Design::OneAtATime => "the base and each value it does not have",
            Design::Grid => "every combination of the values",
        };
        SWEEP_RUNS
            .check_total(
                "parameters",
                runs as u64,
                format!(" ({cells} cells, {design}, x {} seeds)", config.seeds.len()),
            )
            .map_err(|e| invalid(e.field(), e.problem()))?;
        let cells = match config.design {
            Design::OneAtATime => one_at_a_time(&base, &config.parameters),
            Design::Grid => grid(&base, &config.parameters),
        };
        let trials = cells.iter().fold(0u64, |sum, cell| {
            let suite = &cell.suite;
            sum.saturating_add(
                suite.experiments.len() as u64
                    * suite.arms.len() as u64
                    * u64::from(suite.trials.get())
                    * config.seeds.len() as u64,
            )
        });
        SWEEP_TRIALS
            .check_total(
                "parameters",
                trials,
                format!(
                    " in all (per cell: experiments x arms x trials, x {} seeds)",
                    config.seeds.len()
                ),
            )
            .map_err(|e| invalid(e.field(), e.problem()))?;
        for cell in &cells {
            cell.suite
                .validate(catalog, &origin)
                .map_err(|reason| SweepError::Suite {
                    cell: cell.label.clone(),
                    reason,
                })?;
        }
        let folders = file_stems(cells.iter().map(|c| &c.label));
        Ok(Self {
            config,
            origin,
            cells,
            folders,
        })
    }

    /// Every run, cells in order and seeds in order within a cell.
    pub fn runs(&self) -> Vec<RunId> {
        (0..self.cells.len())
            .flat_map(|cell| (0..self.config.seeds.len()).map(move |seed| RunId { cell, seed }))
            .collect()
    }

    /// The runs of shard `index` (from 1) of `count`: every `count`-th run.
    pub fn shard(&self, index: usize, count: usize) -> Vec<RunId> {
        self.runs()
            .into_iter()
            .enumerate()
            .filter(|(i, _)| i % count == index - 1)
            .map(|(_, r)| r)
            .collect()
    }

    /// Trials per run, for progress: experiments x arms x trials, summed over `runs`.
    pub fn trials_in(&self, runs: &[RunId]) -> u64 {
        runs.iter()
            .map(|r| {
                let s = &self.cells[r.cell].suite;
                (s.experiments.len() * s.arms.len()) as u64 * u64::from(s.trials.get())
            })
            .sum()
    }
}

fn one_at_a_time(base: &SuiteConfig, parameters: &[Parameter]) -> Vec<Cell> {
    let mut cells = vec![Cell {
        label: "base".into(),
        suite: base.clone(),
    }];
    for p in parameters {
        // A value equal to the base's is the base cell itself.
        for i in (0..p.len()).filter(|&i| !p.is_in(i, base)) {
            let mut suite = base.clone();
            let label = p.apply(i, &mut suite);
            cells.push(Cell { label, suite });
        }
    }
    cells
}

fn grid(base: &SuiteConfig, parameters: &[Parameter]) -> Vec<Cell> {
    let mut cells = vec![Cell {
        label: String::new(),
        suite: base.clone(),
    }];
    for p in parameters {
        cells = cells
            .into_iter()
            .flat_map(|cell| {
                (0..p.len()).map(move |i| {
                    let mut suite = cell.suite.clone();
                    let label = p.apply(i, &mut suite);
                    Cell {
                        label: if cell.label.is_empty() {
                            label
                        } else {
                            format!("{},{label}", cell.label)
                        },
                        suite,
                    }
                })
            })
            .collect();
    }
    if parameters.is_empty() {
        cells[0].label = "base".into();
    }
    cells
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::UgvCatalog;
    use trust::TimeUnit;

    fn sweep(text: &str) -> Sweep {
        Sweep::new(
            &UgvCatalog,
            parse_ron(text, Path::new("s.ron")).unwrap(),
            Path::new("s.ron"),
        )
        .unwrap()
    }

    #[test]
    fn cells_one_at_a_time_and_as_a_grid() {
        let s = sweep(
            "(suite: embedded, seeds: [1, 2], parameters: [lambda([0.9, 0.95]), retention([any_search, final_from_search])])",
        );
        // 0.95 and any_search are the paper's: the base cell.
        let labels: Vec<&str> = s.cells.iter().map(|c| c.label.as_str()).collect();
        assert_eq!(
            labels,
            ["base", "lambda=0.9", "retention=final_from_search"]
        );
        assert_eq!(s.runs().len(), 6);
        assert_eq!(s.cells[1].suite.adapter.lambda, 0.9);
        let g = sweep(
            "(suite: embedded, seeds: [1], design: grid, parameters: [lambda([0.9, 0.95]), time_unit([task_seconds, commands])])",
        );
        assert_eq!(g.cells.len(), 4);
        assert_eq!(g.cells[3].label, "lambda=0.95,time_unit=commands");
        assert_eq!(g.cells[3].suite.adapter.time_unit, TimeUnit::Commands);
    }

    #[test]
    fn shards_partition_the_runs() {
        let s = sweep("(suite: embedded, seeds: [1, 2, 3], parameters: [lambda([0.9, 0.8])])");
        let mut all: Vec<RunId> = (1..=4).flat_map(|i| s.shard(i, 4)).collect();
        all.sort_by_key(|r| (r.cell, r.seed));
        assert_eq!(all, s.runs());
        assert_eq!(s.shard(1, 4)[0], RunId { cell: 0, seed: 0 });
    }

    #[test]
    fn bad_sweeps_are_named() {
        let err = Sweep::new(
            &UgvCatalog,
            parse_ron(
                "(suite: embedded, seeds: [], parameters: [])",
                Path::new("s.ron"),
            )
            .unwrap(),
            Path::new("s.ron"),
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("seeds"), "{err}");
        let err = Sweep::new(
            &UgvCatalog,
            parse_ron(
                "(suite: embedded, seeds: [1], parameters: [lambda([1.5])])",
                Path::new("s.ron"),
            )
            .unwrap(),
            Path::new("s.ron"),
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("lambda=1.5"), "{err}");
    }
}
