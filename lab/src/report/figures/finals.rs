//! Where each arm's final behaviors land over a pair of components, over the operator's
//! landscape: the pairs drawn, the landscapes estimated for them, the figure and its
//! caption.

use crate::Domain;
use crate::reference::landscape::{self, Grid, Landscape};
use crate::report::entry::ReportEntry;
use crate::report::heatmap::{self, KEY_WIDTH};
use crate::report::page::escape;
use crate::report::plot::{Area, DrawResult, Overlay, Shape, wrap};
use crate::seeds::{Purpose, stream_seed};
use cbr_core::BehaviorSpace;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Runs per cell of the landscapes behind the final behaviors, by default: the standard
/// error of a completion share is at most 0.035.
pub const FINALS_LANDSCAPE_RUNS: u32 = 200;

/// The pairs of components the final behaviors are drawn over, across then up: the first
/// two, the next two, ..., the last two when their number is odd (none for a space of one
/// component).
pub fn component_pairs(space: &BehaviorSpace) -> Vec<(usize, usize)> {
    let n = space.components().len();
    (0..n / 2)
        .map(|k| (2 * k, 2 * k + 1))
        .chain((n % 2 == 1 && n > 1).then(|| (n - 2, n - 1)))
        .collect()
}

/// The landscapes of experiment number `experiment` (its place in the report) for its
/// [`ReportEntry::landscapes`]: one per pair of [`component_pairs`], the other components
/// drawn at random, `runs` per cell (at least 1), each run judged by one of
/// `operators` (those the experiment's trials draw from; one per run when there are
/// several, so the landscape is their mean). Pair `p` draws from the seed
/// `stream_seed(seed, experiment, p, Landscape)`. `progress()` is called after each cell.
pub fn finals_landscapes<D: Domain>(
    domain: &D,
    operators: &[&D::Operator],
    experiment: u64,
    seed: u64,
    runs: u32,
    progress: &(dyn Fn() + Sync),
) -> Result<Vec<Landscape>, landscape::LandscapeError> {
    component_pairs(domain.space())
        .into_iter()
        .enumerate()
        .map(|(p, (x, y))| {
            let seed = stream_seed(seed, experiment, p as u64, Purpose::Landscape);
            landscape::estimate(domain, operators, &[x, y], runs, seed, progress)
        })
        .collect()
}

/// The layout of a final-behaviors figure: a title band with the subtitle's lines, then
/// up to four arms' panels a row and the keys.
pub(super) struct FinalsLayout {
    subtitle: Vec<String>,
    rows: usize,
    columns: usize,
}

impl FinalsLayout {
    /// Size of one arm's panel (px).
    const PANEL: (u32, u32) = (330, 320);
    /// Font size of the subtitle.
    const SUBTITLE_FONT: u32 = 15;

    pub(super) fn new(arms: usize, subtitle: &str) -> Self {
        let columns = arms.clamp(1, 4);
        let width = Self::PANEL.0 * columns as u32 + KEY_WIDTH - 20;
        Self {
            subtitle: wrap(subtitle, Self::SUBTITLE_FONT, width),
            rows: arms.div_ceil(columns).max(1),
            columns,
        }
    }

    /// Height of the title band (px).
    fn header(&self) -> u32 {
        40 + 18 * self.subtitle.len() as u32 + 8
    }

    pub(super) fn size(&self) -> (u32, u32) {
        (
            Self::PANEL.0 * self.columns as u32 + KEY_WIDTH,
            self.header() + Self::PANEL.1 * self.rows as u32,
        )
    }
}

/// How to read a final-behaviors figure over components `x` and `y`, and why it is empty
/// of trustworthy cells when it is.
pub(super) fn finals_caption(
    e: &ReportEntry<'_>,
    (x, y): (usize, usize),
    grid: Option<&Grid>,
) -> String {
    let components = e.space.components();
    let mut caption = format!(
        "Where each arm's trials ended: one panel per arm, each cell a setting of {} \
         (across) and {} (up){}. ",
        escape(&components[x].name),
        escape(&components[y].name),
        if components.len() > 2 {
            ", the other components pooled"
        } else {
            ""
        }
    );
    match grid {
        Some(grid) => {
            caption.push_str(
                "The colour is the chance that the operator lets a command with that setting \
                 complete (dark: rarely, yellow: almost always); the outlined cells are the \
                 trustworthy region, where the trust estimate is expected to climb. ",
            );
            if !grid.tallies.iter().any(|t| t.trusted_on_average()) {
                caption.push_str(
                    "No cell of this pair is trustworthy on average over the other \
                     components: whether a setting of these two is trusted depends on the \
                     others, so the panels show where trials ended, not a region to find. ",
                );
            }
        }
        None => caption.push_str("No landscape of the operator was estimated. "),
    }
    caption.push_str(
        "A marker's area is in proportion to the trials that ended in its cell (the key at \
         the right gives sizes); a good arm ends its trials inside the outline.",
    );
    caption
}

/// What the colour and the circles of a final-behaviors figure show.
pub(super) fn finals_subtitle(e: &ReportEntry<'_>, grid: Option<&Grid>) -> String {
    let background = match (grid, e.landscapes.first()) {
        (Some(grid), Some(landscape)) => {
            let runs = grid.tallies.first().map_or(0, |t| t.runs);
            let others = if e.space.components().len() > 2 {
                ", the other components drawn at random"
            } else {
                ""
            };
            let judged = if landscape.operators > 1 {
                format!(
                    "the mean over its {} operators (one drawn per run, as each trial draws one)",
                    landscape.operators
                )
            } else {
                format!("operator {}", e.operator)
            };
            let region = if grid.tallies.iter().any(|t| t.trusted_on_average()) {
                ""
            } else {
                " No cell is in the trustworthy region: on average over the other components none is trusted."
            };
            format!("Colour: P(complete) under {judged}; {runs} runs per cell{others}.{region}")
        }
        _ => "No landscape of the operator was estimated.".to_owned(),
    };
    format!("{background} Circles: trials whose final behavior lies in the cell.")
}

/// Up to three counts for the key of marker sizes: 1, a round number near a quarter of
/// `most`, and `most` (each once).
fn count_key(most: u32) -> Vec<u32> {
    let quarter = f64::from(most) / 4.0;
    let round = if quarter < 1.0 {
        1
    } else {
        let magnitude = 10f64.powf(quarter.log10().floor());
        let nice = [1.0, 2.0, 5.0, 10.0]
            .into_iter()
            .map(|m| m * magnitude)
            .filter(|&v| v <= quarter)
            .fold(magnitude, f64::max);
        nice as u32
    };
    let mut key = vec![1, round, most];
    key.dedup();
    key
}

/// The smallest marker's radius (px), so that one trial shows.
const SMALLEST_MARKER: f64 = 1.0;

/// The radius (px) of the marker of `count` trials when the most in one cell is `most`
/// and the largest marker has radius `largest`: area in proportion to the count, at
/// least [`SMALLEST_MARKER`].
fn marker_radius(count: u32, most: u32, largest: f64) -> f64 {
    (largest * (f64::from(count) / f64::from(most.max(1))).sqrt()).max(SMALLEST_MARKER)
}

/// Where each arm's final behaviors land over components `x` and `y`: one panel per arm,
/// circles sized by the trials ending in each cell (one size scale for the figure), over
/// the operator's landscape `grid` (one colour scale) with its trustworthy region
/// outlined; the colour bar and both keys right of the panels.
pub(super) fn final_behaviors(
    area: &Area<'_>,
    overlay: &mut Overlay,
    e: &ReportEntry<'_>,
    (x, y): (usize, usize),
    grid: Option<&Grid>,
    layout: &FinalsLayout,
    id: &str,
) -> DrawResult {
    let components = e.space.components();
    let (nx, ny) = (components[x].len(), components[y].len());
    let all_counts: Vec<Vec<u32>> = e
        .result
        .arms
        .iter()
        .map(|s| {
            let mut counts = vec![0u32; nx * ny];
            for t in &s.trials {
                let b = t.report.settled;
                counts[usize::from(b.get(x)) * ny + usize::from(b.get(y))] += 1;
            }
            counts
        })
        .collect();
    let most = all_counts
        .iter()
        .flatten()
        .copied()
        .max()
        .unwrap_or(0)
        .max(1);
    let title = format!(
        "{}: final behaviors of every arm by {} and {} ({} trials each)",
        e.result.name,
        components[x].name,
        components[y].name,
        e.result.trials()
    );
    area.draw(&Text::new(title, (10, 8), ("sans-serif", 21).into_font()))?;
    let subtitle = ("sans-serif", FinalsLayout::SUBTITLE_FONT)
        .into_font()
        .color(&RGBColor(60, 60, 60));
    for (k, line) in layout.subtitle.iter().enumerate() {
        area.draw(&Text::new(
            line.as_str(),
            (10, 38 + 18 * k as i32),
            subtitle.clone(),
        ))?;
    }
    let (_, body) = area.split_vertically(layout.header());
    let (panels_area, key_area) =
        body.split_horizontally(FinalsLayout::PANEL.0 * layout.columns as u32);
    let panels = panels_area.split_evenly((layout.rows, layout.columns));
    let mut largest = 0.0;
    let arms = e.result.arms.len();
    for (k, (panel, (arm, counts))) in panels
        .iter()
        .zip(e.result.arms.iter().zip(&all_counts))
        .enumerate()
    {
        // Ticks on the outer axes only: the bottom panel of each column, the first column.
        let style = heatmap::PanelStyle {
            caption: arm.name.as_str(),
            write_values: false,
            id,
            ticks: (k + layout.columns >= arms, k % layout.columns == 0),
        };
        let chart = heatmap::panel(panel, overlay, e.space, (x, y), grid, style)?;
        let (width, height) = chart.plotting_area().dim_in_pixel();
        let cell = (f64::from(width) / nx as f64).min(f64::from(height) / ny as f64);
        largest = 0.48 * cell;
        // A light disc in a dark ring, readable on every colour of the scale.
        overlay.markers(
            Shape::Circle,
            Some((WHITE, 0.85)),
            Some((BLACK, 1.0)),
            (0..nx)
                .flat_map(|i| (0..ny).map(move |j| (i, j)))
                .filter(|&(i, j)| counts[i * ny + j] > 0)
                .map(|(i, j)| {
                    let (px, py) = chart.backend_coord(&(i as f64, j as f64));
                    (
                        (f64::from(px), f64::from(py)),
                        marker_radius(counts[i * ny + j], most, largest),
                    )
                }),
        );
    }
    let mut top = 10;
    if grid.is_some() {
        heatmap::color_key(&key_area, top)?;
        top += heatmap::color_key_height() + 20;
    }
    key_area.draw(&Text::new(
        "trials ending there",
        (10, top),
        ("sans-serif", 14).into_font(),
    ))?;
    key_area.draw(&Text::new(
        "(marker area in proportion)",
        (10, top + 17),
        ("sans-serif", 12).into_font(),
    ))?;
    top += 40;
    let (left, base) = key_area.get_base_pixel();
    for count in count_key(most) {
        let r = marker_radius(count, most, largest);
        let cy = top + r.ceil() as i32;
        overlay.markers(
            Shape::Circle,
            Some((WHITE, 1.0)),
            Some((BLACK, 1.0)),
            [((f64::from(left + 19), f64::from(base + cy)), r)],
        );
        let label = if count == 1 {
            "1 trial".to_owned()
        } else {
            format!("{count} trials")
        };
        key_area.draw(&Text::new(
            label,
            (36, cy),
            TextStyle::from(("sans-serif", 13).into_font()).pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
        top = cy + r.ceil() as i32 + 8;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn count_keys_are_round_integers() {
        assert_eq!(count_key(1), [1]);
        assert_eq!(count_key(3), [1, 3]);
        assert_eq!(count_key(37), [1, 5, 37]);
        assert_eq!(count_key(120), [1, 20, 120]);
        assert_eq!(count_key(500), [1, 100, 500]);
        // Area in proportion to the count, never below 1 px; 1 and 20 trials differ.
        assert_eq!(marker_radius(100, 100, 7.0), 7.0);
        assert_eq!(marker_radius(25, 100, 8.0), 4.0);
        assert_eq!(marker_radius(1, 500, 7.0), 1.0);
        assert!(marker_radius(20, 300, 6.0) > marker_radius(1, 300, 6.0) + 0.5);
    }

    #[test]
    fn components_pair_up() {
        let space = |n: usize| {
            let c = |i: usize| {
                cbr_core::NamedComponent::numeric(&format!("c{i}"), "m", 0.0, 1.0, 2).unwrap()
            };
            BehaviorSpace::new((0..n).map(c).collect()).unwrap()
        };
        assert_eq!(component_pairs(&space(1)), []);
        assert_eq!(component_pairs(&space(2)), [(0, 1)]);
        assert_eq!(component_pairs(&space(3)), [(0, 1), (1, 2)]);
        assert_eq!(component_pairs(&space(4)), [(0, 1), (2, 3)]);
    }
}
