//! A minimal SVG writer for the drawings of this crate (a run, a landscape): shapes and
//! text appended to a string, with text escaped. Coordinates are in pixels.

use std::fmt::Write;

/// An SVG document under construction.
pub struct Svg {
    body: String,
    width: f64,
    height: f64,
}

/// Escapes text for use in SVG content and attributes.
pub fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

impl Svg {
    /// An empty drawing of `width` x `height` pixels on a white background.
    pub fn new(width: f64, height: f64) -> Self {
        let mut svg = Self {
            body: String::new(),
            width,
            height,
        };
        svg.rect(0.0, 0.0, width, height, "fill=\"white\"");
        svg
    }

    /// A rectangle; `style` holds extra attributes such as `fill="red"`.
    pub fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, style: &str) {
        writeln!(
            self.body,
            r#"<rect x="{x:.2}" y="{y:.2}" width="{w:.2}" height="{h:.2}" {style}/>"#
        )
        .ok();
    }

    /// A circle.
    pub fn circle(&mut self, cx: f64, cy: f64, r: f64, style: &str) {
        writeln!(
            self.body,
            r#"<circle cx="{cx:.2}" cy="{cy:.2}" r="{r:.2}" {style}/>"#
        )
        .ok();
    }

    /// A closed polygon or an open polyline through `points`.
    pub fn poly(&mut self, points: &[(f64, f64)], closed: bool, style: &str) {
        let tag = if closed { "polygon" } else { "polyline" };
        let mut coords = String::new();
        for (x, y) in points {
            write!(coords, "{x:.2},{y:.2} ").ok();
        }
        writeln!(
            self.body,
            r#"<{tag} points="{}" {style}/>"#,
            coords.trim_end()
        )
        .ok();
    }

    /// A line segment.
    pub fn line(&mut self, a: (f64, f64), b: (f64, f64), style: &str) {
        writeln!(
            self.body,
            r#"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" {style}/>"#,
            a.0, a.1, b.0, b.1
        )
        .ok();
    }

    /// Text at `(x, y)`; the text is escaped.
    pub fn text(&mut self, x: f64, y: f64, size: f64, text: &str, style: &str) {
        writeln!(
            self.body,
            r#"<text x="{x:.2}" y="{y:.2}" font-family="sans-serif" font-size="{size}" {style}>{}</text>"#,
            escape(text)
        )
        .ok();
    }

    /// The finished document.
    pub fn finish(self) -> String {
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">\n{}</svg>\n",
            self.body,
            w = self.width,
            h = self.height
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_escaped_elements() {
        let mut svg = Svg::new(10.0, 20.0);
        svg.circle(1.0, 2.0, 3.0, "fill=\"red\"");
        svg.text(0.0, 5.0, 12.0, "a<b & c", "");
        let out = svg.finish();
        assert!(out.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"10\""));
        assert!(out.contains(r#"<circle cx="1.00" cy="2.00" r="3.00" fill="red"/>"#));
        assert!(out.contains("a&lt;b &amp; c</text>"));
        assert!(out.trim_end().ends_with("</svg>"));
    }
}
