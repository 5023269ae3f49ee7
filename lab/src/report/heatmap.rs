//! Heatmaps of a [`Landscape`] over two components: cells coloured by the completion
//! probability on one 0-to-1 colour scale (so panels of one figure compare), the
//! trustworthy region outlined (the cells whose expected trust estimate climbs; see
//! [`crate::reference::landscape`]), axes in the components' real values and units, and the colour
//! bar with the outline's key. `landscape` draws one heatmap; the report draws the final
//! behaviors of every arm over one each.

use crate::reference::landscape::{Grid, Landscape, LandscapeError};
use crate::report::plot::{
    Area, Overlay, PlotError, axis_title, category_label, probability_color, sparse_labels,
    svg_with, text_width, value_labels, wrap,
};
use cbr_core::BehaviorSpace;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;

/// A chart whose cell `(i, j)` is centred on `(i, j)`.
pub type CellChart<'a, 'b> =
    ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Font size of tick labels (px).
const TICK_FONT: u32 = 13;
/// Font size of axis titles (px).
const TITLE_FONT: u32 = 14;
/// Margin of a heatmap panel (px), and below it, where the axis title's descenders go.
const MARGIN: u32 = 6;
const MARGIN_BOTTOM: u32 = 14;
/// Height of the colour bar (px).
const BAR_HEIGHT: i32 = 150;
/// The key of the trustworthy region's outline.
const OUTLINE_KEY: &str = "outlined: the trustworthy region (the expected trust estimate climbs: mean weighted outcome > 0)";
/// Width of the strip right of the heatmaps holding the colour bar and the keys (px).
pub const KEY_WIDTH: u32 = 190;

/// Room the axes of a heatmap with component `y` up need: (left label area, bottom label
/// area), in pixels: tick labels, their gap and the axis title.
pub fn label_areas(space: &BehaviorSpace, y: usize) -> (u32, u32) {
    let widest = value_labels(&space.components()[y])
        .iter()
        .map(|l| text_width(l, TICK_FONT))
        .max()
        .unwrap_or(0);
    (
        widest + 12 + TITLE_FONT + 10,
        TICK_FONT + 12 + TITLE_FONT + 12,
    )
}

/// How a heatmap panel is drawn.
#[derive(Clone, Copy, Debug)]
pub struct PanelStyle<'s> {
    /// The title on top (none when empty).
    pub caption: &'s str,
    /// Whether each cell's completion probability is written in it.
    pub write_values: bool,
    /// The id of the group of cells and outline in the overlay: drawn once, referred to
    /// by the next panels of the same id (they must show the same grid).
    pub id: &'s str,
    /// Whether the axes across and up have ticks and tick labels (panels of one figure
    /// label only the outer ones).
    pub ticks: (bool, bool),
}

/// Draws the heatmap panel of components `x` (across) and `y` (up) on `area`: the
/// caption on top, the cells of `grid` coloured (none without one), the trustworthy
/// region outlined, the values written in when the style says so; the cells, the outline
/// and the values go into `overlay`. Returns the chart, to place what goes on top of it.
pub fn panel<'a, 'b>(
    area: &'a Area<'b>,
    overlay: &mut Overlay,
    space: &BehaviorSpace,
    (x, y): (usize, usize),
    grid: Option<&Grid>,
    style: PanelStyle<'_>,
) -> Result<CellChart<'a, 'b>, Box<dyn std::error::Error + 'static>> {
    let PanelStyle {
        caption,
        write_values,
        id,
        ticks,
    } = style;
    let components = space.components();
    let (nx, ny) = (components[x].len(), components[y].len());
    let (left, bottom) = label_areas(space, y);
    let mut builder = ChartBuilder::on(area);
    if !caption.is_empty() {
        builder.caption(caption, ("sans-serif", 17));
    }
    let mut chart = builder
        .margin(MARGIN)
        // Plotters puts the axis title's top one font size above the bottom: room for its
        // descenders.
        .margin_bottom(MARGIN_BOTTOM)
        .x_label_area_size(bottom)
        .y_label_area_size(left)
        .build_cartesian_2d(-0.5..nx as f64 - 0.5, -0.5..ny as f64 - 0.5)?;
    let (x_labels, y_labels) = (value_labels(&components[x]), value_labels(&components[y]));
    // Across, every `step`-th value is labelled so that labels never touch.
    let (width, _) = chart.plotting_area().dim_in_pixel();
    let cell_width = f64::from(width) / nx as f64;
    let sparse_x = sparse_labels(&x_labels, TICK_FONT, 4.0, cell_width);
    let (x_label, y_label) = (category_label(&sparse_x), category_label(&y_labels));
    let (x_title, y_title) = (axis_title(&components[x]), axis_title(&components[y]));
    chart
        .configure_mesh()
        .disable_mesh()
        .x_labels(if ticks.0 { nx + 1 } else { 0 })
        .y_labels(if ticks.1 { ny + 1 } else { 0 })
        .x_desc(x_title)
        .y_desc(y_title)
        .x_label_formatter(&x_label)
        .y_label_formatter(&y_label)
        .label_style(("sans-serif", TICK_FONT))
        .axis_desc_style(("sans-serif", TITLE_FONT))
        .draw()?;
    let Some(grid) = grid else {
        return Ok(chart);
    };
    let cells = (0..nx).flat_map(|i| (0..ny).map(move |j| (i, j)));
    let at = |x: f64, y: f64| {
        let (px, py) = chart.backend_coord(&(x, y));
        (f64::from(px), f64::from(py))
    };
    overlay.group(id, at(-0.5, -0.5), |overlay| {
        overlay.rects(cells.clone().map(|(i, j)| {
            let (cx, cy) = (i as f64, j as f64);
            (
                probability_color(grid.at(i, j).p_complete()),
                at(cx - 0.5, cy - 0.5),
                at(cx + 0.5, cy + 0.5),
            )
        }));
        if write_values {
            overlay.texts(
                12,
                cells.map(|(i, j)| {
                    let p = grid.at(i, j).p_complete();
                    let ink = if p > 0.6 { BLACK } else { WHITE };
                    (at(i as f64, j as f64), ink, format!("{p:.2}"))
                }),
            );
        }
        let edges = region_outline(grid);
        // A cased line (dark under light) reads on every colour of the scale.
        for (color, width) in [(BLACK, 4.0), (WHITE, 2.0)] {
            overlay.segments(
                color,
                width,
                edges.iter().map(|&(a, b)| (at(a.0, a.1), at(b.0, b.1))),
            );
        }
    });
    Ok(chart)
}

/// The edges between the trustworthy region and the rest (or the grid's border), as
/// segments in cell coordinates.
pub fn region_outline(grid: &Grid) -> Vec<((f64, f64), (f64, f64))> {
    let inside = |i: isize, j: isize| {
        i >= 0
            && j >= 0
            && (i as usize) < grid.nx
            && (j as usize) < grid.ny
            && grid.at(i as usize, j as usize).trusted_on_average()
    };
    let mut edges = Vec::new();
    for i in 0..grid.nx as isize {
        for j in 0..grid.ny as isize {
            if !inside(i, j) {
                continue;
            }
            let (l, r) = (i as f64 - 0.5, i as f64 + 0.5);
            let (b, t) = (j as f64 - 0.5, j as f64 + 0.5);
            if !inside(i - 1, j) {
                edges.push(((l, b), (l, t)));
            }
            if !inside(i + 1, j) {
                edges.push(((r, b), (r, t)));
            }
            if !inside(i, j - 1) {
                edges.push(((l, b), (r, b)));
            }
            if !inside(i, j + 1) {
                edges.push(((l, t), (r, t)));
            }
        }
    }
    edges
}

/// Width of the text of the keys right of a colour bar or marker (px).
const KEY_TEXT_WIDTH: u32 = KEY_WIDTH - 42;

/// The height (px) [`color_key`] draws.
pub fn color_key_height() -> i32 {
    22 + BAR_HEIGHT + 22 + 15 * wrap(OUTLINE_KEY, TICK_FONT, KEY_TEXT_WIDTH).len() as i32 + 4
}

/// Draws the colour bar of the completion probability and the key of the outline into
/// `area` from `top` down (pixels), [`color_key_height`] high.
pub fn color_key(area: &Area<'_>, top: i32) -> Result<(), Box<dyn std::error::Error + 'static>> {
    let title = ("sans-serif", TITLE_FONT).into_font();
    let ticks = TextStyle::from(("sans-serif", TICK_FONT).into_font())
        .pos(Pos::new(HPos::Left, VPos::Center));
    area.draw(&Text::new("P(complete)", (10, top), title.clone()))?;
    let (bar_top, bar_left) = (top + 22, 10);
    let steps = 50;
    for k in 0..steps {
        // Top of the bar is 1.
        let y0 = bar_top + BAR_HEIGHT * k / steps;
        let y1 = bar_top + BAR_HEIGHT * (k + 1) / steps;
        let p = 1.0 - (f64::from(k) + 0.5) / f64::from(steps);
        area.draw(&Rectangle::new(
            [(bar_left, y0), (bar_left + 18, y1)],
            probability_color(p).filled(),
        ))?;
    }
    area.draw(&Rectangle::new(
        [(bar_left, bar_top), (bar_left + 18, bar_top + BAR_HEIGHT)],
        BLACK.stroke_width(1),
    ))?;
    for k in 0..=5 {
        let y = bar_top + BAR_HEIGHT * (5 - k) / 5;
        area.draw(&PathElement::new(
            vec![(bar_left + 18, y), (bar_left + 23, y)],
            BLACK.stroke_width(1),
        ))?;
        area.draw(&Text::new(
            format!("{:.1}", f64::from(k) / 5.0),
            (bar_left + 26, y),
            ticks.clone(),
        ))?;
    }
    let key_top = bar_top + BAR_HEIGHT + 22;
    for (color, width) in [(BLACK, 4), (WHITE, 2)] {
        area.draw(&Rectangle::new(
            [(bar_left, key_top), (bar_left + 18, key_top + 14)],
            color.stroke_width(width),
        ))?;
    }
    let lines = wrap(OUTLINE_KEY, TICK_FONT, KEY_TEXT_WIDTH);
    for (k, line) in lines.iter().enumerate() {
        area.draw(&Text::new(
            line.as_str(),
            (bar_left + 26, key_top + 7 + 15 * k as i32),
            ticks.clone(),
        ))?;
    }
    Ok(())
}

/// Pixels per cell of a landscape figure.
const CELL: u32 = 34;

/// The `landscape` figure: the heatmap of `landscape` over components `x` and `y` with
/// every cell's completion probability written in it, `title` and `subtitle` on top, the
/// colour bar and key right of it. `path` names the figure in errors.
pub fn landscape_svg(
    space: &BehaviorSpace,
    landscape: &Landscape,
    (x, y): (usize, usize),
    title: &str,
    subtitle: &str,
    path: &Path,
) -> Result<String, LandscapeSvgError> {
    let grid = landscape.grid(space, x, y)?;
    let (left, bottom) = label_areas(space, y);
    let header = 56;
    // The colour key starts this far below the header.
    let caption = 24;
    let chart_width = 2 * MARGIN + left + grid.nx as u32 * CELL;
    let chart_height = MARGIN + MARGIN_BOTTOM + bottom + grid.ny as u32 * CELL;
    let key_height = color_key_height() as u32 + 10;
    let titles = text_width(title, 20).max(text_width(subtitle, 15)) + 20;
    let width = (chart_width + KEY_WIDTH).max(titles);
    let height = header + chart_height.max(key_height + caption);
    Ok(svg_with(path, (width, height), |root, overlay| {
        root.draw(&Text::new(title, (10, 8), ("sans-serif", 20).into_font()))?;
        root.draw(&Text::new(
            subtitle,
            (10, 34),
            ("sans-serif", 15).into_font().color(&RGBColor(60, 60, 60)),
        ))?;
        let (_, body) = root.split_vertically(header);
        let (chart_area, key_area) = body.split_horizontally(chart_width);
        let (chart_area, _) = chart_area.split_vertically(chart_height);
        let style = PanelStyle {
            caption: "",
            write_values: true,
            id: "landscape",
            ticks: (true, true),
        };
        panel(&chart_area, overlay, space, (x, y), Some(&grid), style)?;
        color_key(&key_area, caption as i32)?;
        Ok(())
    })?)
}

/// Why a landscape figure could not be made.
#[derive(Debug, thiserror::Error)]
pub enum LandscapeSvgError {
    /// The components do not fit the landscape.
    #[error(transparent)]
    Landscape(#[from] LandscapeError),
    /// The figure could not be drawn.
    #[error(transparent)]
    Plot(#[from] PlotError),
}
