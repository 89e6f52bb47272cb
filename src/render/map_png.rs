//! A publication-quality raster picture (PNG) of a learned hexagon map.
//!
//! Layers, bottom to top: white background, the floor plan's walkable surfaces (light grey),
//! the hexagons coloured by a perceptual colour map (viridis) with thin outlines, the floor
//! plan's walls, the ground-truth path (blue, dashed), the estimated path (dark red, with a
//! white halo), a start (green dot) and an end marker (black square). Below the map, a legend
//! strip holds a scale bar, a colour bar with its range, a north arrow where the frame's
//! heading is absolute, and a key naming every line and mark drawn. The local frame's y
//! axis is flipped into image rows (north is up when the frame is absolute).

mod legend;

use super::canvas::{
    INK, PATH_RED, PLAN_FILL, PLAN_WALL, START_GREEN, TRUTH_BLUE, WHITE, fill, polyline_pieces,
    push_ring, rect, stroke, viridis,
};
use super::key::{KeyEntry, Swatch, key_height};
use crate::error::{Error, Result};
use crate::geometry::HexGrid;
use crate::map::hex_transitions::{transition_probabilities, visits};
use crate::map::{FloorPlan, HexMapSnapshot};
use legend::{ColourScale, draw_legend, legend_height};
use serde::{Deserialize, Serialize};
use std::path::Path;
use tiny_skia::{Color, ColorU8, FillRule, PathBuilder, Pixmap, StrokeDash};

/// What the hexagon colours show.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Shading {
    /// Passes through each hexagon, on a log scale from 1 to the most visited hexagon.
    #[default]
    Visits,
    /// Each hexagon's largest posterior-mean transition probability (1/6: no preferred
    /// direction; 1: one edge only), from the map's smallest to its largest.
    Probability,
}

/// Settings of [`render_map_png`]; validated by [`PictureConfig::validate`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct PictureConfig {
    /// Scale, image pixels per metre, (0, 1000]; lowered when the picture would exceed
    /// `max_side_px`. Default 20.
    pub pixels_per_metre: f64,
    /// Blank border around the map, pixels, at most 100. Default 40.
    pub margin_px: u32,
    /// Largest width or height of the picture, pixels, 1000..=16384. Default 4000.
    pub max_side_px: u32,
    /// What the hexagon colours show. Default [`Shading::Visits`].
    pub shading: Shading,
    /// Width of the estimated path, pixels, (0, 20]. Default 2.
    pub line_width_px: f32,
    /// Image pixels per font pixel of the labels (glyphs are 7 font pixels tall), 1..=4.
    /// Default 2.
    pub text_scale: u32,
    /// The part of the map to show, `[x0, y0, x1, y1]` local metres (`--picture-extent`);
    /// `None`: everything drawn, with a building outline cut to
    /// [`PictureConfig::outline_margin_m`] around the rest. Default `None`.
    pub extent: Option<[f64; 4]>,
    /// How far around the map, the path and the truth a building outline is shown, metres,
    /// [0, 1000]: a 40 m walk in a 240 m mall fills its picture. Default 10.
    pub outline_margin_m: f64,
}

impl Default for PictureConfig {
    fn default() -> Self {
        Self {
            pixels_per_metre: 20.0,
            margin_px: 40,
            max_side_px: 4000,
            shading: Shading::Visits,
            line_width_px: 2.0,
            text_scale: 2,
            extent: None,
            outline_margin_m: 10.0,
        }
    }
}

impl PictureConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `pixels_per_metre` is outside (0, 1000], `margin_px` above 100,
    /// `max_side_px` outside 1000..=16384, `line_width_px` outside (0, 20], `text_scale` outside
    /// 1..=4, `outline_margin_m` outside [0, 1000] m, or an `extent` is not `x0 < x1, y0 < y1`
    /// within 1000 km of the origin.
    pub fn validate(&self) -> Result<()> {
        let (ppm, w) = (self.pixels_per_metre, self.line_width_px);
        require(
            ppm.is_finite() && ppm > 0.0 && ppm <= 1000.0,
            "picture.pixels_per_metre",
            ppm,
            "must be in (0, 1000]",
        )?;
        require(
            self.margin_px <= 100,
            "picture.margin_px",
            self.margin_px,
            "must be at most 100",
        )?;
        let side = self.max_side_px;
        require(
            (1000..=16384).contains(&side),
            "picture.max_side_px",
            side,
            "must be in 1000..=16384",
        )?;
        require(
            w.is_finite() && w > 0.0 && w <= 20.0,
            "picture.line_width_px",
            w,
            "must be in (0, 20]",
        )?;
        let ts = self.text_scale;
        require(
            (1..=4).contains(&ts),
            "picture.text_scale",
            ts,
            "must be in 1..=4",
        )?;
        let m = self.outline_margin_m;
        require(
            m.is_finite() && (0.0..=1000.0).contains(&m),
            "picture.outline_margin_m",
            m,
            "must be in [0, 1000] m",
        )?;
        if let Some([x0, y0, x1, y1]) = self.extent {
            let finite = [x0, y0, x1, y1]
                .iter()
                .all(|v| v.is_finite() && v.abs() <= 1e6);
            require(
                finite && x0 < x1 && y0 < y1,
                "picture.extent",
                format!("[{x0}, {y0}, {x1}, {y1}]"),
                "must be x0 < x1, y0 < y1, local metres within 1000 km of the origin",
            )?;
        }
        Ok(())
    }
}

/// `Ok` when `ok`, else a configuration error on `field`.
fn require(
    ok: bool,
    field: &'static str,
    value: impl ToString,
    reason: &'static str,
) -> Result<()> {
    if ok {
        Ok(())
    } else {
        Err(crate::error::Error::config(
            field,
            value.to_string(),
            reason,
        ))
    }
}

/// What to draw: a map and the path that built it, with optional references. All
/// coordinates are in the map's local frame (x east, y north, metres).
///
/// A map and its walk drawn into memory:
///
/// ```
/// use footslam::geometry::Pose2;
/// use footslam::map::map_of_path;
/// use footslam::render::map_png::{MapPicture, PictureConfig, render_map_png};
///
/// let path: Vec<Pose2> = (1..=20).map(|i| Pose2::new(0.5 * f64::from(i), 0.0, 0.0)).collect();
/// let map = map_of_path(Pose2::default(), &path, &[0; 20], 0.5, 0.8);
/// let points: Vec<(f64, f64)> = path.iter().map(|p| (p.x, p.y)).collect();
///
/// let picture = MapPicture { path_label: "walk", ..MapPicture::new(&map, &points) };
/// let png = render_map_png(&picture, &PictureConfig::default())?;
/// let image = image::load_from_memory(&png).expect("a PNG").to_rgb8();
/// // 20 pixels a metre over the 10 m walk, 40 of margin each side; the path in dark red.
/// assert!(image.width() >= 10 * 20 + 2 * 40);
/// assert!(image.pixels().any(|p| p.0 == [178, 24, 43]));
///
/// let config = PictureConfig { pixels_per_metre: 5000.0, ..Default::default() };
/// let err = render_map_png(&picture, &config).unwrap_err();
/// assert!(err.to_string().contains("picture.pixels_per_metre"));
/// # Ok::<(), footslam::Error>(())
/// ```
#[derive(Debug, Clone, Copy)]
pub struct MapPicture<'a> {
    /// The learned map.
    pub map: &'a HexMapSnapshot,
    /// The estimated path.
    pub path: &'a [(f64, f64)],
    /// Indices `i` where `path` is broken: no line from point `i − 1` to point `i` (the
    /// walk left the floor drawn and came back elsewhere). Sorted; empty: one line.
    pub path_breaks: &'a [usize],
    /// The true path, drawn dashed beneath the estimate.
    pub truth: Option<&'a [(f64, f64)]>,
    /// A floor plan in the same frame, drawn beneath the map.
    pub plan: Option<&'a FloorPlan>,
    /// A building outline in the same frame, drawn dashed over the map.
    pub outline: Option<&'a geo::Polygon<f64>>,
    /// What `path` is, for the key (e.g. "most probable path", "true path").
    pub path_label: &'a str,
    /// What `truth` is, for the key (e.g. "true path", "waypoints").
    pub truth_label: &'a str,
    /// The frame's y axis points north (GPS, an absolute heading, an outline or a plan
    /// placed it): draw a north arrow. Otherwise the frame turns with the walker's unknown
    /// first heading, and no arrow is drawn.
    pub north_up: bool,
}

impl<'a> MapPicture<'a> {
    /// A picture of `map` and `path` without references.
    #[must_use]
    pub fn new(map: &'a HexMapSnapshot, path: &'a [(f64, f64)]) -> Self {
        Self {
            map,
            path,
            path_breaks: &[],
            truth: None,
            plan: None,
            outline: None,
            path_label: "estimated path",
            truth_label: "true path",
            north_up: false,
        }
    }

    /// The key: every line and mark this picture draws.
    fn key(&self) -> Vec<KeyEntry> {
        let mut entries = Vec::new();
        if !self.path.is_empty() {
            entries.push(KeyEntry::new(Swatch::HaloLine(PATH_RED), self.path_label));
        }
        if self.truth.is_some_and(|t| !t.is_empty()) {
            entries.push(KeyEntry::new(Swatch::Dashed(TRUTH_BLUE), self.truth_label));
        }
        if !self.path.is_empty() {
            entries.push(KeyEntry::new(Swatch::Dot(START_GREEN), "start"));
            entries.push(KeyEntry::new(Swatch::Square(INK), "end"));
        }
        if self.plan.is_some() {
            entries.push(KeyEntry::new(Swatch::Area(PLAN_FILL), "floor plan"));
        }
        if self.outline.is_some() {
            entries.push(KeyEntry::new(
                Swatch::Dashed(OUTLINE_GREY),
                "building outline",
            ));
        }
        entries
    }
}

/// The building outline.
const OUTLINE_GREY: ColorU8 = ColorU8::from_rgba(90, 90, 90, 255);

/// Renders `picture` as PNG bytes.
///
/// # Errors
///
/// [`Error::Config`] when `config` fails [`PictureConfig::validate`]; [`Error::InvalidData`] when a
/// point of the path or the truth is not finite or the map's hexagon radius is not positive;
/// [`Error::Encode`] when the picture cannot be allocated or encoded.
pub fn render_map_png(picture: &MapPicture, config: &PictureConfig) -> Result<Vec<u8>> {
    let pixmap = render(picture, config)?;
    pixmap
        .encode_png()
        .map_err(|e| Error::encode("encode the map picture as PNG", e))
}

/// Renders `picture` and writes it to `path` atomically.
///
/// # Errors
///
/// As [`render_map_png`], and [`Error::Io`] when `path` cannot be written (its folder missing or
/// read-only).
pub fn write_map_png(path: &Path, picture: &MapPicture, config: &PictureConfig) -> Result<()> {
    crate::io::write_atomically(path, &render_map_png(picture, config)?)
}

/// Where the map lies in the image.
#[derive(Debug, Clone, Copy)]
struct Layout {
    /// West and north edges of the drawn extent, metres.
    min_x: f64,
    max_y: f64,
    /// Pixels per metre actually used.
    scale: f64,
    /// Pixel position of (`min_x`, `max_y`).
    left: f64,
    top: f64,
    /// Top of the legend strip, pixels.
    legend_top: f64,
    width: u32,
    height: u32,
    /// Pixel size of the part of the map shown.
    map_width: f64,
    map_height: f64,
    /// Something drawn lies outside the part shown: cut it at the map's edges.
    cropped: bool,
}

impl Layout {
    fn new(picture: &MapPicture, config: &PictureConfig, key: &[KeyEntry]) -> Self {
        let given = config.extent.map(|[x0, y0, x1, y1]| (x0, y0, x1, y1));
        let shown = given.or_else(|| extent(picture, config.outline_margin_m));
        let cropped = match (extent(picture, f64::INFINITY), shown) {
            (Some(all), Some(s)) => all.0 < s.0 || all.1 < s.1 || all.2 > s.2 || all.3 > s.3,
            _ => false,
        };
        let (mut x0, mut y0, mut x1, mut y1) = shown.unwrap_or((-5.0, -5.0, 5.0, 5.0));
        // At least a metre each way, so a single point still gets a picture.
        let grow = |lo: &mut f64, hi: &mut f64| {
            let pad = (1.0 - (*hi - *lo)).max(0.0) / 2.0;
            *lo -= pad;
            *hi += pad;
        };
        grow(&mut x0, &mut x1);
        grow(&mut y0, &mut y1);
        let ts = f64::from(config.text_scale);
        let margin = f64::from(config.margin_px);
        let side = f64::from(config.max_side_px);
        // The key wraps within the narrowest picture: its height is known before the scale.
        let min_width = 2.0 * margin + 420.0 + 60.0 * ts;
        let legend = legend_height(config.text_scale)
            + f64::from(key_height(
                key,
                min_width as f32 - 2.0 * margin as f32,
                config.text_scale,
            ));
        let scale = config
            .pixels_per_metre
            .min((side - 2.0 * margin) / (x1 - x0))
            .min((side - 2.0 * margin - legend) / (y1 - y0));
        let (map_width, map_height) = ((x1 - x0) * scale, (y1 - y0) * scale);
        let width = (map_width.ceil() + 2.0 * margin).max(min_width).min(side);
        let legend_top = margin + map_height + margin / 2.0;
        let height = (legend_top + legend + margin / 2.0).ceil().min(side);
        Self {
            min_x: x0,
            max_y: y1,
            scale,
            left: ((width - map_width) / 2.0).floor(),
            top: margin,
            legend_top,
            width: width as u32,
            height: height as u32,
            map_width,
            map_height,
            cropped,
        }
    }

    /// Paints white over everything outside the part of the map shown (the legend is drawn
    /// after).
    fn blank_outside_map(&self, pixmap: &mut Pixmap) {
        let (left, top) = (self.left as f32, self.top as f32);
        let (right, bottom) = (
            (self.left + self.map_width) as f32,
            (self.top + self.map_height) as f32,
        );
        let (width, height) = (self.width as f32, self.height as f32);
        let bands = [
            rect(0.0, 0.0, width, top),
            rect(0.0, bottom, width, height - bottom),
            rect(0.0, top, left, bottom - top),
            rect(right, top, width - right, bottom - top),
        ];
        for band in bands.into_iter().flatten() {
            fill(pixmap, &band, WHITE, FillRule::Winding);
        }
        // A thin frame says that the map goes on beyond it.
        if let Some(frame) = rect(left, top, right - left, bottom - top) {
            stroke(pixmap, &frame, OUTLINE_GREY, 1.0, None);
        }
    }

    /// Image position of local point `(x, y)`; y is flipped so that north is up.
    fn pixel(&self, (x, y): (f64, f64)) -> (f32, f32) {
        (
            (self.left + (x - self.min_x) * self.scale) as f32,
            (self.top + (self.max_y - y) * self.scale) as f32,
        )
    }
}

/// Bounding box of everything drawn, metres, the building outline only within
/// `outline_margin` of the rest (all of it when there is nothing else); `None` when there is
/// nothing.
fn extent(picture: &MapPicture, outline_margin: f64) -> Option<(f64, f64, f64, f64)> {
    let grid = HexGrid::new(picture.map.radius);
    let r = picture.map.radius;
    let hexes = picture.map.cells.iter().map(|c| {
        let (x, y) = grid.center(c.hex);
        (x - r, y - r, x + r, y + r)
    });
    let lines = picture.path.iter().chain(picture.truth.unwrap_or_default());
    let points = lines.map(|&(x, y)| (x, y, x, y));
    let plan = picture.plan.and_then(FloorPlan::bounds);
    let outline = picture
        .outline
        .and_then(geo::BoundingRect::bounding_rect)
        .map(|r| (r.min().x, r.min().y, r.max().x, r.max().y));
    let union = |a: Bounds, b: Bounds| (a.0.min(b.0), a.1.min(b.1), a.2.max(b.2), a.3.max(b.3));
    let Some(rest) = hexes.chain(points).chain(plan).reduce(union) else {
        return outline;
    };
    let m = outline_margin;
    let near = outline.and_then(|o| {
        let cut = (
            o.0.max(rest.0 - m),
            o.1.max(rest.1 - m),
            o.2.min(rest.2 + m),
            o.3.min(rest.3 + m),
        );
        (cut.0 <= cut.2 && cut.1 <= cut.3).then_some(cut)
    });
    Some(near.map_or(rest, |n| union(rest, n)))
}

/// `(x0, y0, x1, y1)`, metres.
type Bounds = (f64, f64, f64, f64);

fn render(picture: &MapPicture, config: &PictureConfig) -> Result<Pixmap> {
    config.validate()?;
    check_finite(picture)?;
    let key = picture.key();
    let layout = Layout::new(picture, config, &key);
    let mut pixmap = Pixmap::new(layout.width, layout.height).ok_or_else(|| {
        Error::encode(
            format!("allocate a {}×{} picture", layout.width, layout.height),
            "out of memory",
        )
    })?;
    pixmap.fill(Color::WHITE);
    if let Some(plan) = picture.plan {
        draw_plan(&mut pixmap, &layout, plan, true);
    }
    let labels = draw_hexagons(&mut pixmap, &layout, picture.map, config.shading);
    if let Some(plan) = picture.plan {
        draw_plan(&mut pixmap, &layout, plan, false);
    }
    let w = config.line_width_px;
    if let Some(truth) = picture.truth {
        let dash = StrokeDash::new(vec![7.0, 4.0], 0.0);
        draw_line(&mut pixmap, &layout, truth, (TRUTH_BLUE, 0.75 * w), dash);
    }
    let halo = ColorU8::from_rgba(255, 255, 255, 220);
    let mut starts = vec![0];
    starts.extend(
        picture
            .path_breaks
            .iter()
            .copied()
            .filter(|&b| b > 0 && b < picture.path.len()),
    );
    starts.push(picture.path.len());
    for run in starts.windows(2).filter(|w| w[0] < w[1]) {
        let piece = &picture.path[run[0]..run[1]];
        draw_line(&mut pixmap, &layout, piece, (halo, w + 2.0), None);
        draw_line(&mut pixmap, &layout, piece, (PATH_RED, w), None);
    }
    if let Some(outline) = picture.outline {
        let dash = StrokeDash::new(vec![10.0, 5.0], 0.0);
        let ring: Vec<(f64, f64)> = outline.exterior().coords().map(|c| (c.x, c.y)).collect();
        draw_line(&mut pixmap, &layout, &ring, (OUTLINE_GREY, 1.5), dash);
    }
    draw_markers(&mut pixmap, &layout, picture.path, w);
    if layout.cropped {
        layout.blank_outside_map(&mut pixmap);
    }
    let scale = (!picture.map.cells.is_empty()).then_some(labels);
    draw_legend(
        &mut pixmap,
        &layout,
        config,
        scale,
        (picture.north_up, &key),
    );
    Ok(pixmap)
}

fn check_finite(picture: &MapPicture) -> Result<()> {
    let named = [("path", Some(picture.path)), ("truth", picture.truth)];
    for (name, points) in named {
        if let Some(i) = points
            .unwrap_or_default()
            .iter()
            .position(|p| !(p.0.is_finite() && p.1.is_finite()))
        {
            return Err(Error::invalid(format!("{name} point {i}"), "is not finite"));
        }
    }
    let r = picture.map.radius;
    if !(r.is_finite() && r > 0.0) {
        return Err(Error::invalid(
            "the map's hexagon radius",
            format!("{r} m is not a positive number"),
        ));
    }
    Ok(())
}

/// The plan's surfaces (`surfaces`) or its walls (outlines of all rings).
fn draw_plan(pixmap: &mut Pixmap, layout: &Layout, plan: &FloorPlan, surfaces: bool) {
    for floor in &plan.polygons {
        let mut pb = PathBuilder::new();
        let rings = std::iter::once(floor.polygon.exterior()).chain(floor.polygon.interiors());
        for ring in rings {
            push_ring(&mut pb, ring.coords().map(|c| layout.pixel((c.x, c.y))));
        }
        if let Some(path) = pb.finish() {
            if surfaces {
                fill(pixmap, &path, PLAN_FILL, FillRule::EvenOdd);
            } else {
                stroke(pixmap, &path, PLAN_WALL, 1.5, None);
            }
        }
    }
}

/// Fills each hexagon by its shading value; returns the colour bar's scale.
fn draw_hexagons(
    pixmap: &mut Pixmap,
    layout: &Layout,
    map: &HexMapSnapshot,
    shading: Shading,
) -> ColourScale {
    let (values, (lo, hi), labels) = shading_values(map, shading);
    let grid = HexGrid::new(map.radius);
    let mut outlines = PathBuilder::new();
    for (cell, v) in map.cells.iter().zip(values) {
        let t = if hi - lo > 1e-12 {
            (v - lo) / (hi - lo)
        } else {
            1.0
        };
        let corners = grid.corners(cell.hex).map(|p| layout.pixel(p));
        let mut pb = PathBuilder::new();
        push_ring(&mut pb, corners);
        if let Some(hexagon) = pb.finish() {
            fill(pixmap, &hexagon, viridis(t), FillRule::Winding);
        }
        push_ring(&mut outlines, corners);
    }
    if let Some(outlines) = outlines.finish() {
        stroke(
            pixmap,
            &outlines,
            ColorU8::from_rgba(0, 0, 0, 60),
            0.75,
            None,
        );
    }
    labels
}

/// Each cell's value on the colour scale, the scale's range and its labels.
fn shading_values(map: &HexMapSnapshot, shading: Shading) -> (Vec<f64>, (f64, f64), ColourScale) {
    match shading {
        Shading::Visits => {
            let n: Vec<u64> = map.cells.iter().map(|c| visits(&c.counts).max(1)).collect();
            let max = n.iter().copied().max().unwrap_or(1);
            let values = n.iter().map(|&v| (v as f64).ln()).collect();
            let scale = if max > 1 {
                ColourScale::Ramp("1".into(), max.to_string())
            } else {
                ColourScale::Uniform("1 visit each".into())
            };
            (values, (0.0, (max as f64).ln()), scale)
        }
        Shading::Probability => {
            let values: Vec<f64> = map
                .cells
                .iter()
                .map(|c| {
                    transition_probabilities(&c.counts, map.alpha)
                        .iter()
                        .copied()
                        .fold(0.0, f64::max)
                })
                .collect();
            let lo = values.iter().copied().reduce(f64::min).unwrap_or(1.0 / 6.0);
            let hi = values.iter().copied().reduce(f64::max).unwrap_or(1.0);
            let (low, high) = (format!("{lo:.2}"), format!("{hi:.2}"));
            let scale = if low == high {
                ColourScale::Uniform(format!("max transition p {low}"))
            } else {
                ColourScale::Ramp(low, high)
            };
            (values, (lo, hi), scale)
        }
    }
}

/// Strokes the polyline through `points` (metres).
fn draw_line(
    pixmap: &mut Pixmap,
    layout: &Layout,
    points: &[(f64, f64)],
    (color, width): (ColorU8, f32),
    dash: Option<StrokeDash>,
) {
    let pixels: Vec<(f32, f32)> = points.iter().map(|&p| layout.pixel(p)).collect();
    for line in polyline_pieces(&pixels) {
        stroke(pixmap, &line, color, width, dash.clone());
    }
}

/// A green dot at the start and a black square at the end of `path`.
fn draw_markers(pixmap: &mut Pixmap, layout: &Layout, path: &[(f64, f64)], line_width: f32) {
    let size = 2.5 * line_width + 2.0;
    if let Some(&last) = path.last() {
        let (x, y) = layout.pixel(last);
        if let Some(square) = rect(x - size, y - size, 2.0 * size, 2.0 * size) {
            fill(pixmap, &square, INK, FillRule::Winding);
            stroke(pixmap, &square, WHITE, 1.5, None);
        }
    }
    if let Some(&first) = path.first() {
        let (x, y) = layout.pixel(first);
        if let Some(dot) = PathBuilder::from_circle(x, y, size) {
            fill(pixmap, &dot, START_GREEN, FillRule::Winding);
            stroke(pixmap, &dot, WHITE, 1.5, None);
        }
    }
}

#[cfg(test)]
mod tests;
