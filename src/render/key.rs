//! What every picture's legend strip is made of: a key (a swatch and a label for each line,
//! dot, square, marker and area drawn), a scale bar and a north arrow.
//!
//! The key wraps into as many rows as the picture's width needs; [`key_height`] says how
//! tall it will be before anything is drawn, so that the pictures can size their strips.

use super::canvas::{INK, WHITE, fill, polyline, rect, stroke};
use super::glyphs::{self, GLYPH_HEIGHT};
use tiny_skia::{ColorU8, FillRule, PathBuilder, Pixmap, StrokeDash};

/// How a key entry is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Swatch {
    /// A solid line.
    Line(ColorU8),
    /// A solid line with a white halo (the estimated path of map pictures).
    HaloLine(ColorU8),
    /// A dashed line.
    Dashed(ColorU8),
    /// A filled dot with a white ring.
    Dot(ColorU8),
    /// A small cloud of dots (particles, uncertain steps).
    Dots(ColorU8),
    /// A filled square with a white ring.
    Square(ColorU8),
    /// A filled area with an outline (floor, cells).
    Area(ColorU8),
    /// A ring with a cross (a labelled place).
    Marker,
}

/// One entry of a key.
#[derive(Debug, Clone, PartialEq)]
pub struct KeyEntry {
    /// Its symbol.
    pub swatch: Swatch,
    /// What it is.
    pub label: String,
}

impl KeyEntry {
    /// An entry `label` drawn as `swatch`.
    pub fn new(swatch: Swatch, label: impl Into<String>) -> Self {
        Self {
            swatch,
            label: label.into(),
        }
    }
}

/// Width of a swatch, pixels.
const SWATCH_W: f32 = 26.0;
/// Gap between a swatch and its label, and between entries, pixels.
const GAP: f32 = 6.0;
const ENTRY_GAP: f32 = 22.0;

fn text_h(ts: u32) -> f32 {
    (GLYPH_HEIGHT * ts) as f32
}

/// Height of one key row, pixels.
fn row_h(ts: u32) -> f32 {
    text_h(ts) + 10.0
}

fn entry_w(e: &KeyEntry, ts: u32) -> f32 {
    SWATCH_W + GAP + glyphs::text_width(&e.label, ts) as f32
}

/// The entries of each row when `entries` wrap within `width` pixels.
fn rows(entries: &[KeyEntry], width: f32, ts: u32) -> Vec<&[KeyEntry]> {
    let mut out = Vec::new();
    let (mut start, mut used) = (0, 0.0f32);
    for (i, e) in entries.iter().enumerate() {
        let w = entry_w(e, ts);
        if i > start && used + ENTRY_GAP + w > width {
            out.push(&entries[start..i]);
            (start, used) = (i, w);
        } else {
            used += if i > start { ENTRY_GAP + w } else { w };
        }
    }
    if start < entries.len() {
        out.push(&entries[start..]);
    }
    out
}

/// Height in pixels of the key of `entries` wrapped within `width` pixels (0 without
/// entries).
pub fn key_height(entries: &[KeyEntry], width: f32, ts: u32) -> f32 {
    rows(entries, width, ts).len() as f32 * row_h(ts)
}

/// Draws the key of `entries` from `(left, top)`, wrapped within `width` pixels.
pub fn draw_key(
    pixmap: &mut Pixmap,
    entries: &[KeyEntry],
    (left, top): (f32, f32),
    width: f32,
    ts: u32,
) {
    for (r, row) in rows(entries, width, ts).into_iter().enumerate() {
        let y = top + r as f32 * row_h(ts);
        let mid = y + text_h(ts) / 2.0;
        let mut x = left;
        for e in row {
            draw_swatch(pixmap, e.swatch, x, mid);
            glyphs::draw_text(pixmap, &e.label, (x + SWATCH_W + GAP, y), ts, INK);
            x += entry_w(e, ts) + ENTRY_GAP;
        }
    }
}

fn draw_swatch(pixmap: &mut Pixmap, swatch: Swatch, x: f32, mid: f32) {
    let line = |pixmap: &mut Pixmap, colour, width, dash| {
        if let Some(l) = polyline([(x + 2.0, mid), (x + SWATCH_W - 2.0, mid)]) {
            stroke(pixmap, &l, colour, width, dash);
        }
    };
    let centre = x + SWATCH_W / 2.0;
    let dot = |pixmap: &mut Pixmap, cx: f32, r: f32, colour, ring: bool| {
        if let Some(d) = PathBuilder::from_circle(cx, mid, r) {
            fill(pixmap, &d, colour, FillRule::Winding);
            if ring {
                stroke(pixmap, &d, WHITE, 1.5, None);
            }
        }
    };
    match swatch {
        Swatch::Line(c) => line(pixmap, c, 3.0, None),
        Swatch::HaloLine(c) => {
            line(pixmap, ColorU8::from_rgba(200, 200, 200, 255), 5.0, None);
            line(pixmap, c, 2.5, None);
        }
        Swatch::Dashed(c) => line(pixmap, c, 2.0, StrokeDash::new(vec![6.0, 3.0], 0.0)),
        Swatch::Dot(c) => dot(pixmap, centre, 6.0, c, true),
        Swatch::Dots(c) => {
            for (dx, dy) in [
                (-7.0, -3.0),
                (-2.0, 3.0),
                (3.0, -2.0),
                (8.0, 2.0),
                (1.0, 0.0),
            ] {
                if let Some(d) = PathBuilder::from_circle(centre + dx, mid + dy, 2.0) {
                    fill(pixmap, &d, c, FillRule::Winding);
                }
            }
        }
        Swatch::Square(c) => {
            if let Some(s) = rect(centre - 6.0, mid - 6.0, 12.0, 12.0) {
                fill(pixmap, &s, c, FillRule::Winding);
                stroke(pixmap, &s, WHITE, 1.5, None);
            }
        }
        Swatch::Area(c) => {
            if let Some(s) = rect(x + 2.0, mid - 7.0, SWATCH_W - 4.0, 14.0) {
                fill(pixmap, &s, c, FillRule::Winding);
                stroke(pixmap, &s, INK, 1.0, None);
            }
        }
        Swatch::Marker => super::plan_marks::draw_marker(pixmap, (centre, mid), "", 1),
    }
}

/// The longest 1-2-5 length (metres, 1 cm to 500 km) not exceeding `room` metres.
pub fn scale_bar_length(room: f64) -> f64 {
    (-2..6)
        .flat_map(|k| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(k)))
        .take_while(|&m| m <= room)
        .last()
        .unwrap_or(0.01)
}

/// A two-tone scale bar from `x0` centred on row `mid`, as long as the longest 1-2-5 length
/// that fits in `room_px` pixels at `scale` pixels per metre, labelled on its right.
/// Returns the pixel just right of its label.
pub fn draw_scale_bar(
    pixmap: &mut Pixmap,
    (x0, mid): (f32, f32),
    room_px: f64,
    scale: f64,
    ts: u32,
) -> f32 {
    let metres = scale_bar_length(room_px / scale);
    let bar = (metres * scale) as f32;
    for (i, colour) in [INK, WHITE].into_iter().enumerate() {
        if let Some(half) = rect(x0 + i as f32 * bar / 2.0, mid - 4.0, bar / 2.0, 8.0) {
            fill(pixmap, &half, colour, FillRule::Winding);
            stroke(pixmap, &half, INK, 1.0, None);
        }
    }
    let label = if metres >= 1.0 {
        format!("{metres} m")
    } else {
        format!("{metres:.2} m")
    };
    let x = x0 + bar + 8.0;
    glyphs::draw_text(pixmap, &label, (x, mid - text_h(ts) / 2.0), ts, INK);
    x + glyphs::text_width(&label, ts) as f32
}

/// An upward arrow centred on `x` under the letter N, the letter's top at `top`.
pub fn draw_north_arrow(pixmap: &mut Pixmap, x: f32, top: f32, ts: u32) {
    let th = text_h(ts);
    let (tip, base) = (top + th + 4.0, top + 2.0 * th + 18.0);
    let mut pb = PathBuilder::new();
    super::canvas::push_ring(
        &mut pb,
        [(x, tip), (x + 9.0, base), (x, base - 7.0), (x - 9.0, base)],
    );
    if let Some(arrow) = pb.finish() {
        fill(pixmap, &arrow, INK, FillRule::Winding);
    }
    let left = x - glyphs::text_width("N", ts) as f32 / 2.0;
    glyphs::draw_text(pixmap, "N", (left, top), ts, INK);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_bar_lengths_are_one_two_five() {
        assert_eq!(scale_bar_length(7.5), 5.0);
        assert_eq!(scale_bar_length(20.0), 20.0);
        assert_eq!(scale_bar_length(0.3), 0.2);
        assert_eq!(scale_bar_length(0.001), 0.01);
    }

    #[test]
    fn the_key_wraps_into_rows_that_fit() {
        let entries: Vec<KeyEntry> = (0..6)
            .map(|i| KeyEntry::new(Swatch::Line(INK), format!("entry number {i}")))
            .collect();
        let one = entry_w(&entries[0], 2);
        assert_eq!(key_height(&[], 500.0, 2), 0.0);
        assert_eq!(key_height(&entries, 10_000.0, 2), row_h(2));
        // Two entries a row.
        let width = 2.0 * one + ENTRY_GAP + 1.0;
        assert_eq!(rows(&entries, width, 2).len(), 3);
        // Narrower than one entry: one a row, never an empty row.
        assert_eq!(rows(&entries, 10.0, 2).len(), 6);
    }

    #[test]
    fn every_swatch_draws_something() {
        for swatch in [
            Swatch::Line(INK),
            Swatch::HaloLine(INK),
            Swatch::Dashed(INK),
            Swatch::Dot(INK),
            Swatch::Dots(INK),
            Swatch::Square(INK),
            Swatch::Area(INK),
            Swatch::Marker,
        ] {
            let mut pixmap = Pixmap::new(40, 20).expect("pixmap");
            pixmap.fill(tiny_skia::Color::WHITE);
            draw_swatch(&mut pixmap, swatch, 4.0, 10.0);
            let inked = pixmap.pixels().iter().filter(|p| p.red() < 200).count();
            assert!(inked > 5, "{swatch:?} drew {inked} pixels");
        }
    }
}
