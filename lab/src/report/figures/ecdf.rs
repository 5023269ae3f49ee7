//! A scenario's benchmark as a distribution ([`crate::population::benchmark::Ecdf`]): for each arm, the
//! share of its (population, trial) pairs that settled on a trustworthy behavior within
//! `N` untrustworthy commands, as `N` grows; and, dashed, the probability that the
//! known-operator limit's agent settles within `N` ([`ScenarioBenchmark::limit_law`]).

use super::legend::{Key, LEGEND_WIDTH, legend};
use crate::experiment::arm_name::ArmName;
use crate::population::benchmark::ScenarioBenchmark;
use crate::reference::limit_law::UntrustworthyLaw;
use crate::report::plot::{Area, DrawResult, Overlay, arm_styles, drawing_order};
use plotters::prelude::*;

/// Places along each arm's curve its marker is drawn at.
const MARKERS: u64 = 8;

/// The share of what the limit's curve ever reaches that the figure shows at least.
const LIMIT_SHOWN: f64 = 0.999;

/// The curve through `steps` (each count where the curve steps up, with its level there,
/// ascending) as a line from `(0, 0)` to the right edge `right`: level between the counts,
/// up at each; steps past `right` are left out.
fn staircase(steps: &[(u64, f64)], right: u64) -> Vec<(f64, f64)> {
    let mut points = vec![(0.0, 0.0)];
    let mut share = 0.0;
    for &(n, next) in steps.iter().take_while(|(n, _)| *n <= right) {
        points.push((n as f64, share));
        points.push((n as f64, next));
        share = next;
    }
    points.push((right as f64, share));
    points
}

/// The count by which the limit's curve has reached [`LIMIT_SHOWN`] of its final level.
fn limit_reach(law: &UntrustworthyLaw) -> u64 {
    let steps = law.steps();
    let last = steps.last().map_or(0.0, |&(_, share)| share);
    steps
        .iter()
        .find(|&&(_, share)| share >= LIMIT_SHOWN * last)
        .map_or(0, |&(n, _)| n)
}

/// The ECDF figure of a scenario's benchmark.
pub(super) fn ecdf_figure(
    area: &Area<'_>,
    overlay: &mut Overlay,
    benchmark: &ScenarioBenchmark,
) -> DrawResult {
    let most = benchmark
        .arms
        .iter()
        .filter_map(|a| a.ecdf.settled.last().copied())
        .max()
        .unwrap_or(0);
    // Room for the limit's curve whatever the arms did.
    let right = most.max(limit_reach(&benchmark.limit_law)).max(1);
    let (width, _) = area.dim_in_pixel();
    let (plot, side) = area.split_horizontally(width.saturating_sub(LEGEND_WIDTH));
    let mut chart = ChartBuilder::on(&plot)
        .caption(
            format!(
                "{}: untrustworthy commands to settle, over {} populations",
                benchmark.scenario,
                benchmark.populations.len()
            ),
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0f64..right as f64, 0f64..1.02)?;
    chart
        .configure_mesh()
        .light_line_style(TRANSPARENT)
        .x_desc("untrustworthy commands N")
        .y_desc("share of (population, trial) pairs settled within N")
        .draw()?;
    chart.draw_series(DashedLineSeries::new(
        staircase(&benchmark.limit_law.steps(), right),
        6,
        4,
        BLACK.stroke_width(2),
    ))?;
    let names: Vec<&ArmName> = benchmark.arms.iter().map(|a| &a.arm).collect();
    let styles = arm_styles(&names);
    for index in drawing_order(&names) {
        let (ecdf, style) = (&benchmark.arms[index].ecdf, styles[index]);
        chart.draw_series(LineSeries::new(
            staircase(&ecdf.steps(), right),
            style.color.stroke_width(2),
        ))?;
        // The arm's marker on its curve at evenly spaced counts, staggered by arm so that
        // curves that run together do not hide each other's markers.
        let stagger = right / (MARKERS * names.len().max(1) as u64);
        overlay.markers(
            style.shape,
            Some((style.color, 1.0)),
            Some((WHITE, 1.0)),
            (0..MARKERS)
                .map(|k| k * right / MARKERS + index as u64 * stagger)
                .map(|n| {
                    let (x, y) = chart.backend_coord(&(n as f64, ecdf.share_within(n)));
                    ((f64::from(x), f64::from(y)), 4.5)
                }),
        );
    }
    let mut entries: Vec<(String, Key)> = names
        .iter()
        .zip(&styles)
        .map(|(name, &style)| (name.to_string(), Key::LineMarker(style)))
        .collect();
    entries.push(("known-operator limit (dashed)".to_owned(), Key::Line(BLACK)));
    legend(&side, overlay, &entries)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::population::benchmark::Ecdf;
    use crate::reference::limit_law::CountLaw;

    #[test]
    fn the_staircase_by_hand() {
        // Settled after 0, 3, 3 and 7 of five pairs: up to 0.2 at 0, 0.6 at 3 and 0.8 at
        // 7, level to the right edge.
        let ecdf = Ecdf::of([(true, 3), (false, 12), (true, 0), (true, 7), (true, 3)]);
        assert_eq!(
            staircase(&ecdf.steps(), 10),
            vec![
                (0.0, 0.0),
                (0.0, 0.0),
                (0.0, 0.2),
                (3.0, 0.2),
                (3.0, 0.6),
                (7.0, 0.6),
                (7.0, 0.8),
                (10.0, 0.8)
            ]
        );
    }

    #[test]
    fn the_limits_curve_by_hand() {
        // Settles at 0 with 1/2, at 2 with 1/2 - 1/1024, at 40 with 1/1024: 0.999 of it
        // by 2.
        let mut mass = vec![0.0; 41];
        (mass[0], mass[2], mass[40]) = (0.5, 0.5 - 1.0 / 1024.0, 1.0 / 1024.0);
        let law = UntrustworthyLaw {
            settled: CountLaw {
                mass,
                ..Default::default()
            },
            unsettled: CountLaw::default(),
        };
        assert_eq!(limit_reach(&law), 2);
        // Cut at the right edge: the step at 40 is past it.
        assert_eq!(
            staircase(&law.steps(), 5),
            vec![
                (0.0, 0.0),
                (0.0, 0.0),
                (0.0, 0.5),
                (2.0, 0.5),
                (2.0, 1.0 - 1.0 / 1024.0),
                (5.0, 1.0 - 1.0 / 1024.0)
            ]
        );
        assert_eq!(limit_reach(&UntrustworthyLaw::default()), 0);
    }
}
