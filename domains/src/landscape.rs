//! The landscape of an operator: for every behavior, the estimated probability that the
//! operator lets a run complete, with the causes of the other endings. A domain author
//! reads it to see what each operator rewards; the heatmap shows two components and
//! averages over the others.
//!
//! Each behavior's runs draw from their own ChaCha8 stream (the seed, stream = the
//! behavior's rank), so the estimate does not depend on the number of threads.

use crate::causes;
use crate::svg::Svg;
use cbr_core::{Behavior, BehaviorSpace};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::fmt::Write;
use trust::{Domain, OutcomeKind};

/// The runs of one behavior, counted.
#[derive(Clone, Debug, PartialEq)]
pub struct Tally {
    /// The behavior.
    pub behavior: Behavior,
    /// Runs made.
    pub runs: u32,
    /// Runs the operator let complete.
    pub completed: u32,
    /// Runs that failed or were interrupted, by cause (in [`causes::ALL`] order).
    pub causes: [u32; 6],
}

impl Tally {
    /// Fraction of runs completed.
    pub fn p_complete(&self) -> f64 {
        f64::from(self.completed) / f64::from(self.runs.max(1))
    }
}

/// Completion estimates over a whole behavior space.
#[derive(Clone, Debug)]
pub struct Landscape {
    /// One tally per behavior, in the space's order.
    pub tallies: Vec<Tally>,
}

/// Why a landscape cannot be drawn.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
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
}

/// Runs every behavior of `domain` `runs` times under `operator`, in parallel.
/// `progress()` is called after each behavior's runs.
pub fn estimate<D: Domain>(
    domain: &D,
    operator: &D::Operator,
    runs: u32,
    seed: u64,
    progress: &(dyn Fn() + Sync),
) -> Landscape {
    let space = domain.space();
    let tallies = (0..space.size())
        .into_par_iter()
        .map(|rank| {
            let behavior = space.unrank(rank);
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            rng.set_stream(rank);
            let mut tally = Tally {
                behavior,
                runs,
                completed: 0,
                causes: [0; 6],
            };
            for _ in 0..runs {
                let outcome = domain.run(&behavior, operator, &mut rng);
                if outcome.kind == OutcomeKind::Completed {
                    tally.completed += 1;
                } else if let Some(cause) = outcome.cause {
                    let index = causes::ALL.iter().position(|&c| c == cause);
                    tally.causes[index.expect("a UGV run ends with a UGV cause")] += 1;
                }
            }
            progress();
            tally
        })
        .collect();
    Landscape { tallies }
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

/// The heatmap's two components from `"a,b"`: both known, and different.
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

impl Landscape {
    /// One line per behavior: its component values, the runs, completions, the completion
    /// probability and the count of each cause.
    pub fn csv(&self, space: &BehaviorSpace) -> String {
        let mut out = String::new();
        for c in space.components() {
            write!(out, "{},", c.name).ok();
        }
        out.push_str("runs,completed,p_complete");
        for cause in causes::ALL {
            write!(out, ",{cause}").ok();
        }
        out.push('\n');
        for t in &self.tallies {
            for (i, c) in space.components().iter().enumerate() {
                write!(out, "{},", c.display_value(t.behavior.get(i))).ok();
            }
            write!(out, "{},{},{:.4}", t.runs, t.completed, t.p_complete()).ok();
            for n in t.causes {
                write!(out, ",{n}").ok();
            }
            out.push('\n');
        }
        out
    }

    /// Mean completion probability for every pair of values of components `x` and `y`,
    /// averaged over all the other components: `grid[i][j]` for value `i` of `x`, `j` of `y`.
    pub fn marginal(&self, space: &BehaviorSpace, x: usize, y: usize) -> Vec<Vec<f64>> {
        let (nx, ny) = (space.components()[x].len(), space.components()[y].len());
        let mut sum = vec![vec![0.0; ny]; nx];
        let mut count = vec![vec![0u32; ny]; nx];
        for t in &self.tallies {
            let (i, j) = (
                usize::from(t.behavior.get(x)),
                usize::from(t.behavior.get(y)),
            );
            sum[i][j] += t.p_complete();
            count[i][j] += 1;
        }
        for (row, counts) in sum.iter_mut().zip(&count) {
            for (cell, &n) in row.iter_mut().zip(counts) {
                *cell /= f64::from(n.max(1));
            }
        }
        sum
    }

    /// A heatmap of [`Landscape::marginal`]: `x` across, `y` up, one cell per value pair,
    /// labelled with its probability.
    pub fn heatmap_svg(
        &self,
        space: &BehaviorSpace,
        x: usize,
        y: usize,
        title: &str,
    ) -> Result<String, LandscapeError> {
        if x == y {
            return Err(LandscapeError::SameComponent(
                space.components()[x].name.clone(),
            ));
        }
        let grid = self.marginal(space, x, y);
        let (cx, cy) = (&space.components()[x], &space.components()[y]);
        let (nx, ny) = (cx.len(), cy.len());
        let cell = 34.0;
        let (left, top) = (70.0, 80.0);
        let width = (left + nx as f64 * cell + 110.0).max(600.0);
        let height = top + ny as f64 * cell + 60.0;
        let mut svg = Svg::new(width, height);
        svg.text(left, 25.0, 14.0, title, r##"font-weight="bold""##);
        let others: Vec<&str> = space
            .components()
            .iter()
            .enumerate()
            .filter(|(i, _)| *i != x && *i != y)
            .map(|(_, c)| c.name.as_str())
            .collect();
        if !others.is_empty() {
            let note = format!("P(complete), mean over {}", others.join(", "));
            svg.text(left, 45.0, 11.0, &note, r##"fill="#333""##);
        } else {
            svg.text(left, 45.0, 11.0, "P(complete)", r##"fill="#333""##);
        }
        for (i, column) in grid.iter().enumerate() {
            for (j, &p) in column.iter().enumerate() {
                let px = left + i as f64 * cell;
                let py = top + (ny - 1 - j) as f64 * cell;
                svg.rect(px, py, cell, cell, &format!(r##"fill="{}""##, color(p)));
                let ink = if p > 0.6 { "#000" } else { "#fff" };
                svg.text(
                    px + 4.0,
                    py + cell / 2.0 + 4.0,
                    10.0,
                    &format!("{p:.2}"),
                    &format!(r##"fill="{ink}""##),
                );
            }
        }
        for i in 0..nx {
            let label = cx.display_value(i as u16).to_string();
            let px = left + i as f64 * cell + 4.0;
            svg.text(px, top + ny as f64 * cell + 14.0, 10.0, &label, "");
        }
        for j in 0..ny {
            let label = cy.display_value(j as u16).to_string();
            let py = top + (ny - 1 - j) as f64 * cell + cell / 2.0 + 4.0;
            svg.text(left - 40.0, py, 10.0, &label, "");
        }
        let axis_x = format!("{} ({})", cx.name, cx.unit);
        svg.text(left, top + ny as f64 * cell + 34.0, 12.0, &axis_x, "");
        let axis_y = format!("{} ({})", cy.name, cy.unit);
        svg.text(5.0, top - 10.0, 12.0, &axis_y, "");
        // Colour bar.
        let bar_x = left + nx as f64 * cell + 30.0;
        for k in 0..=10 {
            let p = f64::from(k) / 10.0;
            let py = top + (10 - k) as f64 * 20.0;
            svg.rect(bar_x, py, 20.0, 20.0, &format!(r##"fill="{}""##, color(p)));
            svg.text(bar_x + 25.0, py + 14.0, 10.0, &format!("{p:.1}"), "");
        }
        Ok(svg.finish())
    }
}

/// A perceptually ordered colour for a probability: dark blue (0) through teal to
/// yellow (1).
fn color(p: f64) -> String {
    const STOPS: [(f64, [f64; 3]); 5] = [
        (0.0, [68.0, 1.0, 84.0]),
        (0.25, [59.0, 82.0, 139.0]),
        (0.5, [33.0, 145.0, 140.0]),
        (0.75, [94.0, 201.0, 98.0]),
        (1.0, [253.0, 231.0, 37.0]),
    ];
    let p = p.clamp(0.0, 1.0);
    let k = STOPS
        .iter()
        .rposition(|(at, _)| *at <= p)
        .unwrap_or(0)
        .min(3);
    let ((a, ca), (b, cb)) = (STOPS[k], STOPS[k + 1]);
    let f = (p - a) / (b - a);
    let mix = |i: usize| (ca[i] + (cb[i] - ca[i]) * f).round() as u8;
    format!("#{:02x}{:02x}{:02x}", mix(0), mix(1), mix(2))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ugv::UgvDomain;
    use crate::{Scenario, builtin_operators};

    #[test]
    fn colors_at_the_ends_and_between() {
        assert_eq!(color(0.0), "#440154");
        assert_eq!(color(1.0), "#fde725");
        assert_eq!(color(0.5), "#21918c");
    }

    #[test]
    fn the_marginal_averages_over_the_other_components() {
        let space = Scenario::Patrol.space();
        let mut tallies = Vec::new();
        for b in space.iter() {
            // Completed when scan_time index is even: half the scan times.
            let completed = u32::from(b.get(2) % 2 == 0);
            tallies.push(Tally {
                behavior: b,
                runs: 1,
                completed,
                causes: [0; 6],
            });
        }
        let grid = Landscape { tallies }.marginal(&space, 0, 1);
        assert_eq!(grid.len(), 20);
        assert!(grid.iter().flatten().all(|&p| (p - 0.5).abs() < 1e-12));
    }

    #[test]
    fn a_small_landscape_is_deterministic_and_drawable() {
        let domain = UgvDomain::new(Scenario::Movement);
        let op = &builtin_operators(Scenario::Movement)[1];
        let a = estimate(&domain, op, 3, 9, &|| {});
        let b = estimate(&domain, op, 3, 9, &|| {});
        assert_eq!(a.tallies, b.tallies);
        assert_eq!(a.tallies.len(), 400);
        for t in &a.tallies {
            assert_eq!(t.completed + t.causes.iter().sum::<u32>(), 3);
        }
        let space = domain.space();
        let csv = a.csv(space);
        assert!(csv.starts_with("speed,padding,runs,completed,p_complete,deadline,"));
        assert_eq!(csv.lines().count(), 401);
        let svg = a.heatmap_svg(space, 0, 1, "t").unwrap();
        assert_eq!(svg.matches("<rect").count(), 1 + 400 + 11);
        assert!(a.heatmap_svg(space, 1, 1, "t").is_err());
        assert!(component(space, "scan_time").is_err());
        assert_eq!(axes(space, "padding, speed"), Ok((1, 0)));
        assert!(axes(space, "speed").is_err());
        assert!(axes(space, "speed,speed").is_err());
    }
}
