//! The legend strip below the map: scale bar (left), colour bar and north arrow (right), and
//! the key of the lines and marks drawn (below them).

use super::{Layout, PictureConfig, Shading};
use crate::render::canvas::{INK, fill, rect, stroke, viridis};
use crate::render::glyphs::{self, GLYPH_HEIGHT};
use crate::render::key::{self, KeyEntry};
use tiny_skia::{FillRule, Pixmap};

/// Colour bar length, pixels.
const COLOUR_BAR_WIDTH: f32 = 200.0;

/// Height of the legend strip's first row, pixels: caption, colour bar, labels.
pub fn legend_height(text_scale: u32) -> f64 {
    f64::from(2 * GLYPH_HEIGHT * text_scale) + 24.0
}

/// Rows of the legend strip, pixels.
struct Strip {
    /// Top of the captions.
    top: f32,
    /// Centre line of the bars.
    mid: f32,
    /// Font scale.
    ts: u32,
}

impl Strip {
    /// Draws `text` centred horizontally on `x` with its top at `y`.
    fn centred_text(&self, pixmap: &mut Pixmap, text: &str, x: f32, y: f32) {
        let left = x - glyphs::text_width(text, self.ts) as f32 / 2.0;
        glyphs::draw_text(pixmap, text, (left, y), self.ts, INK);
    }
}

/// The colour bar of a picture's hexagons: its (low, high) labels, or one label when every
/// hexagon has the same value (no bar then: a bar from 1 to 1 explains nothing).
#[derive(Debug, Clone, PartialEq)]
pub enum ColourScale {
    /// A ramp from low to high.
    Ramp(String, String),
    /// Every hexagon alike: what they all are.
    Uniform(String),
}

/// Draws the legend; `scale` is the hexagons' colour scale, `None` for a picture without
/// hexagons; `north` draws the north arrow (only where the frame's heading is absolute).
pub fn draw_legend(
    pixmap: &mut Pixmap,
    layout: &Layout,
    config: &PictureConfig,
    scale: Option<ColourScale>,
    (north, entries): (bool, &[KeyEntry]),
) {
    let ts = config.text_scale;
    let text_h = (GLYPH_HEIGHT * ts) as f32;
    let top = layout.legend_top as f32;
    let strip = Strip {
        top,
        mid: top + text_h + 12.0,
        ts,
    };
    let margin = config.margin_px as f32;
    // Room for a third of the picture, at most 150 pixels.
    let room = 150.0f64.min(f64::from(layout.width) / 3.0);
    key::draw_scale_bar(pixmap, (margin, strip.mid), room, layout.scale, ts);
    let arrow_x = layout.width as f32 - margin - 10.0;
    let caption = match config.shading {
        Shading::Visits => "visits (log scale)",
        Shading::Probability => "max transition p",
    };
    match scale {
        Some(ColourScale::Ramp(low, high)) => draw_colour_bar(
            pixmap,
            &strip,
            arrow_x - 50.0 - COLOUR_BAR_WIDTH,
            caption,
            (low, high),
        ),
        Some(ColourScale::Uniform(what)) => {
            let right = arrow_x - 50.0;
            let w = glyphs::text_width(&what, ts) as f32;
            if let Some(swatch) = rect(right - w - 24.0, strip.mid - 6.0, 16.0, 12.0) {
                fill(pixmap, &swatch, viridis(1.0), FillRule::Winding);
                stroke(pixmap, &swatch, INK, 1.0, None);
            }
            glyphs::draw_text(
                pixmap,
                &what,
                (right - w, strip.mid - text_h / 2.0),
                ts,
                INK,
            );
        }
        None => {}
    }
    if north {
        key::draw_north_arrow(pixmap, arrow_x, strip.top, ts);
    }
    let key_top = top + legend_height(ts) as f32;
    let width = layout.width as f32 - 2.0 * margin;
    key::draw_key(pixmap, entries, (margin, key_top), width, ts);
}

/// The viridis ramp from `left`, its caption above and its end labels below.
fn draw_colour_bar(
    pixmap: &mut Pixmap,
    strip: &Strip,
    left: f32,
    caption: &str,
    (low, high): (String, String),
) {
    let (y, h, w) = (strip.mid - 6.0, 12.0, COLOUR_BAR_WIDTH);
    let steps = w as u32;
    for i in 0..steps {
        if let Some(slice) = rect(left + i as f32, y, 1.0, h) {
            let t = f64::from(i) / f64::from(steps - 1);
            fill(pixmap, &slice, viridis(t), FillRule::Winding);
        }
    }
    if let Some(frame) = rect(left, y, w, h) {
        stroke(pixmap, &frame, INK, 1.0, None);
    }
    strip.centred_text(pixmap, caption, left + w / 2.0, strip.top);
    strip.centred_text(pixmap, &low, left, y + h + 4.0);
    strip.centred_text(pixmap, &high, left + w, y + h + 4.0);
}
