//! The legend strip below the map: scale bar (left), colour bar and north arrow (right).

use super::{Layout, PictureConfig, Shading};
use crate::render::canvas::{INK, WHITE, fill, push_ring, rect, stroke, viridis};
use crate::render::glyphs::{self, GLYPH_HEIGHT};
use tiny_skia::{FillRule, PathBuilder, Pixmap};

/// Colour bar length, pixels.
const COLOUR_BAR_WIDTH: f32 = 200.0;

/// Height of the legend strip, pixels: caption, colour bar, labels.
pub fn legend_height(text_scale: u32) -> f64 {
    f64::from(2 * GLYPH_HEIGHT * text_scale) + 24.0
}

/// Rows of the legend strip, pixels.
struct Strip {
    /// Top of the captions.
    top: f32,
    /// Centre line of the bars.
    mid: f32,
    /// Height of a line of text.
    text_h: f32,
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

/// Draws the legend; `labels` are the colour bar's (low, high) ends, `None` for a
/// picture without hexagons (no colour bar then).
pub fn draw_legend(
    pixmap: &mut Pixmap,
    layout: &Layout,
    config: &PictureConfig,
    labels: Option<(String, String)>,
) {
    let ts = config.text_scale;
    let text_h = (GLYPH_HEIGHT * ts) as f32;
    let top = layout.legend_top as f32;
    let strip = Strip {
        top,
        mid: top + text_h + 12.0,
        text_h,
        ts,
    };
    let margin = config.margin_px as f32;
    // Room for a third of the map, at most 150 pixels.
    let room = 150.0f64.min(layout.map_width.max(60.0) / 3.0) / layout.scale;
    draw_scale_bar(pixmap, &strip, margin, scale_bar_length(room), layout.scale);
    let arrow_x = layout.width as f32 - margin - 10.0;
    let caption = match config.shading {
        Shading::Visits => "visits (log scale)",
        Shading::Probability => "max transition p",
    };
    if let Some(labels) = labels {
        draw_colour_bar(
            pixmap,
            &strip,
            arrow_x - 50.0 - COLOUR_BAR_WIDTH,
            caption,
            labels,
        );
    }
    draw_north_arrow(pixmap, &strip, arrow_x);
}

/// The longest 1-2-5 length (metres, 1 cm to 500 km) not exceeding `room` metres.
fn scale_bar_length(room: f64) -> f64 {
    (-2..6)
        .flat_map(|k| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(k)))
        .take_while(|&m| m <= room)
        .last()
        .unwrap_or(0.01)
}

/// A two-tone bar `metres` long starting at `x0`, labelled on its right.
fn draw_scale_bar(pixmap: &mut Pixmap, strip: &Strip, x0: f32, metres: f64, scale: f64) {
    let bar = (metres * scale) as f32;
    for (i, colour) in [INK, WHITE].into_iter().enumerate() {
        if let Some(half) = rect(x0 + i as f32 * bar / 2.0, strip.mid - 4.0, bar / 2.0, 8.0) {
            fill(pixmap, &half, colour, FillRule::Winding);
            stroke(pixmap, &half, INK, 1.0, None);
        }
    }
    let label = if metres >= 1.0 {
        format!("{metres} m")
    } else {
        format!("{metres:.2} m")
    };
    let at = (x0 + bar + 8.0, strip.mid - strip.text_h / 2.0);
    glyphs::draw_text(pixmap, &label, at, strip.ts, INK);
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

/// An upward arrow centred on `x` under the letter N.
fn draw_north_arrow(pixmap: &mut Pixmap, strip: &Strip, x: f32) {
    let (tip, base) = (strip.mid - 8.0, strip.mid + strip.text_h + 6.0);
    let mut pb = PathBuilder::new();
    push_ring(
        &mut pb,
        [(x, tip), (x + 9.0, base), (x, base - 7.0), (x - 9.0, base)],
    );
    if let Some(arrow) = pb.finish() {
        fill(pixmap, &arrow, INK, FillRule::Winding);
    }
    strip.centred_text(pixmap, "N", x, strip.top);
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
}
