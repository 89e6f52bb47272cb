//! Marks on plan pictures: labelled markers (e.g. where an access point is strongest) and a
//! colour bar explaining a heatmap's colours, drawn by [`super::plan_png`].

use super::canvas::{INK, WHITE, fill, rect, rgb, stroke};
use super::glyphs::{self, GLYPH_HEIGHT};
use tiny_skia::{FillRule, PathBuilder, Pixmap};

/// A labelled marker over the plan.
#[derive(Debug, Clone)]
pub struct PlanMarker {
    /// East, metres.
    pub x: f64,
    /// North, metres.
    pub y: f64,
    /// Level of the panel it is drawn on.
    pub level: i32,
    /// Text beside it.
    pub label: String,
}

/// A horizontal colour bar in a picture's title row: `colour(t)` for `t` from 0 (left,
/// labelled `low`) to 1 (right, labelled `high`).
#[derive(Debug, Clone)]
pub struct ColourBar {
    /// Label of the left end.
    pub low: String,
    /// Label of the right end.
    pub high: String,
    /// Colour of a value's position `t` in [0, 1].
    pub colour: fn(f64) -> [u8; 3],
}

/// Width of the bar itself, pixels.
const BAR_WIDTH: f32 = 160.0;
/// Radius of a marker's ring, pixels.
const MARKER_RADIUS: f32 = 6.0;

/// Draws a ring with a cross at pixel `(px, py)` and its label to the right.
pub(super) fn draw_marker(pixmap: &mut Pixmap, (px, py): (f32, f32), label: &str, scale: u32) {
    let mut pb = PathBuilder::new();
    pb.push_circle(px, py, MARKER_RADIUS);
    if let Some(ring) = pb.finish() {
        stroke(pixmap, &ring, WHITE, 4.0, None);
        stroke(pixmap, &ring, INK, 2.0, None);
    }
    let mut pb = PathBuilder::new();
    pb.move_to(px - MARKER_RADIUS, py);
    pb.line_to(px + MARKER_RADIUS, py);
    pb.move_to(px, py - MARKER_RADIUS);
    pb.line_to(px, py + MARKER_RADIUS);
    if let Some(cross) = pb.finish() {
        stroke(pixmap, &cross, INK, 1.5, None);
    }
    let y = py - (GLYPH_HEIGHT * scale) as f32 / 2.0;
    // Right of the marker, or left of it where the label would leave the picture.
    let w = glyphs::text_width(label, scale) as f32;
    let right = px + MARKER_RADIUS + 4.0;
    let x = if right + w > pixmap.width() as f32 {
        (px - MARKER_RADIUS - 4.0 - w).max(0.0)
    } else {
        right
    };
    glyphs::draw_text(pixmap, label, (x, y), scale, INK);
}

/// Draws `bar` ending at `right` pixels from the left, its top at `top`: `low`, the bar,
/// `high`.
pub(super) fn draw_colour_bar(
    pixmap: &mut Pixmap,
    bar: &ColourBar,
    right: f32,
    top: f32,
    scale: u32,
) {
    let h = (GLYPH_HEIGHT * scale) as f32;
    let high_w = glyphs::text_width(&bar.high, scale) as f32;
    let low_w = glyphs::text_width(&bar.low, scale) as f32;
    let x_high = right - high_w;
    let x1 = x_high - 6.0;
    let x0 = x1 - BAR_WIDTH;
    glyphs::draw_text(pixmap, &bar.low, (x0 - 6.0 - low_w, top), scale, INK);
    glyphs::draw_text(pixmap, &bar.high, (x_high, top), scale, INK);
    let steps = 64;
    let w = BAR_WIDTH / steps as f32;
    for i in 0..steps {
        let [r, g, b] = (bar.colour)((f64::from(i) + 0.5) / f64::from(steps));
        let x = x0 + i as f32 * w;
        if let Some(p) = rect(x, top, w + 0.5, h) {
            fill(pixmap, &p, rgb(r, g, b), FillRule::Winding);
        }
    }
    if let Some(p) = rect(x0, top, x1 - x0, h) {
        stroke(pixmap, &p, INK, 1.0, None);
    }
}
