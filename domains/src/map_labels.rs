//! Where the words of a run's picture go. Every label of the map (landmarks, street
//! names, start and goal, the patrol's objects) is set on the first side of its point
//! where it covers no label placed before it and no marked point, so that labels never
//! overlap one another. Street names are fixed inside their street; the rest try eight
//! sides in turn, then rows above and below joined by a leader line, and where all are
//! taken, the place that covers least.

use crate::geometry::Vec2;
use lab::report::plot::text_width;

/// How a label's text is anchored at its point, horizontally.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Horizontal {
    /// The text starts at the point.
    Left,
    /// The text is centred on the point.
    Center,
    /// The text ends at the point.
    Right,
}

/// How a label's text is anchored at its point, vertically (the map's north is up).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Vertical {
    /// The text's top is at the point: it hangs below it.
    Top,
    /// The text is centred on the point.
    Center,
    /// The text's bottom is at the point: it stands above it.
    Bottom,
}

/// A rectangle of the map (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapRect {
    /// South-west corner.
    pub min: Vec2,
    /// North-east corner.
    pub max: Vec2,
}

impl MapRect {
    /// The square of half-side `half` m around `at`.
    pub fn around(at: Vec2, half: f64) -> Self {
        Self {
            min: Vec2::new(at.x - half, at.y - half),
            max: Vec2::new(at.x + half, at.y + half),
        }
    }

    /// The area (m²) this rectangle shares with `other`; 0 when they only touch.
    pub fn overlap(&self, other: &MapRect) -> f64 {
        let w = self.max.x.min(other.max.x) - self.min.x.max(other.min.x);
        let h = self.max.y.min(other.max.y) - self.min.y.max(other.min.y);
        if w > 0.0 && h > 0.0 { w * h } else { 0.0 }
    }
}

/// What a label names, which sets how it is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// A street's name, inside the street.
    Street,
    /// A landmark's name.
    Place,
    /// The route's start or goal.
    Route,
    /// A patrol object's truth and assigned label.
    Object,
}

/// A placed label: its text, font size (plotters' size, px), what it names, the point its
/// text is anchored at (m), the anchor and the area it covers.
#[derive(Clone, Debug, PartialEq)]
pub struct Label {
    /// The words.
    pub text: String,
    /// Font size as plotters takes it (px).
    pub font: u32,
    /// What it names.
    pub role: Role,
    /// Where the text is anchored (m).
    pub at: Vec2,
    /// Horizontal anchor.
    pub horizontal: Horizontal,
    /// Vertical anchor.
    pub vertical: Vertical,
    /// What the text covers (m).
    pub covers: MapRect,
    /// The point a leader line joins the label to, when the label is not beside it.
    pub leader_from: Option<Vec2>,
}

/// Sets labels one at a time so that no label covers another or a marked point.
pub struct LabelPlacer {
    /// Pixels per metre of the drawing.
    scale: f64,
    /// Where labels may go (m): the map and the room right of it.
    bounds: MapRect,
    /// Marked points and placed labels.
    taken: Vec<MapRect>,
    /// The labels placed so far, in order.
    labels: Vec<Label>,
}

/// Gap between a point and a label beside it, left or right (px): clear of the point's
/// marker (the route's squares and the objects' discs reach 5 px from their point).
const GAP_PX: f64 = 7.0;
/// Gap between a point and a label above or below it (px): more than half the height of
/// the map's tallest label (14 px fonts are drawn 11.3 px tall), so that a label above or
/// below a point clears a label centred beside the same point.
const GAP_ABOVE_PX: f64 = 6.0;
/// Space between rows of labels moved up or down from their point (px).
const ROW_GAP_PX: f64 = 2.0;

impl LabelPlacer {
    /// A placer for a drawing of `scale` px per metre whose labels must stay in `bounds`.
    pub fn new(scale: f64, bounds: MapRect) -> Self {
        Self {
            scale,
            bounds,
            taken: Vec::new(),
            labels: Vec::new(),
        }
    }

    /// Marks `area` as taken by something drawn (a marker), which no label may cover.
    pub fn mark(&mut self, area: MapRect) {
        self.taken.push(area);
    }

    /// Width and height (m) of `text` at `font`.
    fn extent(&self, text: &str, font: u32) -> (f64, f64) {
        let width = f64::from(text_width(text, font)) / self.scale;
        // plotters draws a font of size s at s / 1.24 px, as `text_width` assumes.
        let height = f64::from(font) / 1.24 / self.scale;
        (width, height)
    }

    /// The area `text` covers when anchored at `at` as given.
    fn covers(&self, text: &str, font: u32, at: Vec2, h: Horizontal, v: Vertical) -> MapRect {
        let (width, height) = self.extent(text, font);
        let left = match h {
            Horizontal::Left => at.x,
            Horizontal::Center => at.x - width / 2.0,
            Horizontal::Right => at.x - width,
        };
        let bottom = match v {
            Vertical::Bottom => at.y,
            Vertical::Center => at.y - height / 2.0,
            Vertical::Top => at.y - height,
        };
        MapRect {
            min: Vec2::new(left, bottom),
            max: Vec2::new(left + width, bottom + height),
        }
    }

    fn push(&mut self, label: Label) {
        self.taken.push(label.covers);
        self.labels.push(label);
    }

    /// Places a street's name exactly where given, inside its street.
    pub fn fixed(&mut self, text: &str, font: u32, at: Vec2, h: Horizontal, v: Vertical) {
        let covers = self.covers(text, font, at, h, v);
        self.push(Label {
            text: text.to_owned(),
            font,
            role: Role::Street,
            at,
            horizontal: h,
            vertical: v,
            covers,
            leader_from: None,
        });
    }

    /// Places `text` beside `point`: right, left, above, below, then the four corners,
    /// the first side that covers nothing taken and stays in bounds. Where all eight are
    /// taken, the label moves up or down by one to three rows, right or left, and a
    /// leader line joins it to its point. Where every place covers something, the place
    /// that covers least.
    pub fn beside(&mut self, text: &str, font: u32, role: Role, point: Vec2) {
        let (gx, gy) = (GAP_PX / self.scale, GAP_ABOVE_PX / self.scale);
        let row = self.extent(text, font).1 + ROW_GAP_PX / self.scale;
        let (x, y) = (point.x, point.y);
        let mut places = vec![
            (Vec2::new(x + gx, y), Horizontal::Left, Vertical::Center),
            (Vec2::new(x - gx, y), Horizontal::Right, Vertical::Center),
            (Vec2::new(x, y + gy), Horizontal::Center, Vertical::Bottom),
            (Vec2::new(x, y - gy), Horizontal::Center, Vertical::Top),
            (
                Vec2::new(x + gx, y + gy),
                Horizontal::Left,
                Vertical::Bottom,
            ),
            (Vec2::new(x + gx, y - gy), Horizontal::Left, Vertical::Top),
            (
                Vec2::new(x - gx, y + gy),
                Horizontal::Right,
                Vertical::Bottom,
            ),
            (Vec2::new(x - gx, y - gy), Horizontal::Right, Vertical::Top),
        ];
        let adjacent = places.len();
        for rows in 1..=3 {
            for dy in [rows as f64 * row, -(rows as f64) * row] {
                places.push((
                    Vec2::new(x + gx, y + dy),
                    Horizontal::Left,
                    Vertical::Center,
                ));
                places.push((
                    Vec2::new(x - gx, y + dy),
                    Horizontal::Right,
                    Vertical::Center,
                ));
            }
        }
        let outside = |a: &MapRect| {
            let inside = a.overlap(&self.bounds);
            (a.max.x - a.min.x) * (a.max.y - a.min.y) - inside
        };
        let cost = |a: &MapRect| -> f64 {
            self.taken.iter().map(|t| t.overlap(a)).sum::<f64>() + outside(a)
        };
        let (k, (at, h, v, covers)) = places
            .iter()
            .map(|&(at, h, v)| (at, h, v, self.covers(text, font, at, h, v)))
            .enumerate()
            .min_by(|a, b| cost(&a.1.3).total_cmp(&cost(&b.1.3)))
            .expect("places to try");
        self.push(Label {
            text: text.to_owned(),
            font,
            role,
            at,
            horizontal: h,
            vertical: v,
            covers,
            leader_from: (k >= adjacent).then_some(point),
        });
    }

    /// The labels, in the order they were placed.
    pub fn into_labels(self) -> Vec<Label> {
        self.labels
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn placer() -> LabelPlacer {
        LabelPlacer::new(
            10.0,
            MapRect {
                min: Vec2::new(0.0, 0.0),
                max: Vec2::new(100.0, 100.0),
            },
        )
    }

    #[test]
    fn overlap_by_hand() {
        let a = MapRect::around(Vec2::new(0.0, 0.0), 1.0);
        let b = MapRect::around(Vec2::new(1.0, 1.0), 1.0);
        assert_eq!(a.overlap(&b), 1.0);
        assert_eq!(a.overlap(&MapRect::around(Vec2::new(2.0, 0.0), 1.0)), 0.0);
    }

    #[test]
    fn a_free_point_is_labelled_on_its_right() {
        let mut p = placer();
        p.beside("goal", 13, Role::Route, Vec2::new(50.0, 50.0));
        let label = &p.into_labels()[0];
        assert_eq!(
            (label.horizontal, label.vertical),
            (Horizontal::Left, Vertical::Center)
        );
        // 4 characters at 13 px: ceil(4 x 0.6 x 13 / 1.24) = 26 px, 2.6 m, from 0.7 m right.
        assert!((label.covers.min.x - 50.7).abs() < 1e-9);
        assert!((label.covers.max.x - 53.3).abs() < 1e-9);
    }

    #[test]
    fn two_labels_of_one_point_take_two_sides() {
        let mut p = placer();
        p.beside("goal", 13, Role::Route, Vec2::new(50.0, 50.0));
        p.beside("north gate", 13, Role::Place, Vec2::new(50.0, 50.0));
        let labels = p.into_labels();
        assert_eq!(labels[0].horizontal, Horizontal::Left);
        assert_eq!(labels[1].horizontal, Horizontal::Right);
        assert_eq!(labels[0].covers.overlap(&labels[1].covers), 0.0);
    }

    #[test]
    fn a_label_at_the_east_edge_goes_west_and_never_over_a_mark() {
        let mut p = placer();
        p.mark(MapRect::around(Vec2::new(97.0, 50.0), 0.4));
        p.beside("harmless/harmless", 12, Role::Object, Vec2::new(99.0, 50.0));
        let label = &p.into_labels()[0];
        assert!(
            label.covers.max.x <= 100.0 && label.covers.min.y >= 50.0,
            "{label:?}"
        );
    }
}
