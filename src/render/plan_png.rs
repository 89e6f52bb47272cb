//! Pictures (PNG) of multi-floor plans with paths and particle clouds over them, as in Woodman
//! & Harle 2008, Fig. 4: one panel per floor level side by side at one scale, surfaces shaded
//! by height (so stair treads show as a ramp), outlines as walls, barriers in black, paths as
//! lines and point clouds as density-blended dots. Several pictures (snapshots at chosen
//! steps) stack top to bottom in one image, each under its title. North is up.

use super::canvas::{INK, PLAN_WALL, fill, polyline, polyline_pieces, push_ring, rgb, stroke};
use super::glyphs::{self, GLYPH_HEIGHT};
pub use super::plan_marks::{ColourBar, PlanMarker};
use crate::error::{Error, Result};
use crate::map::FloorPlan;
use geo::Area;
use serde::{Deserialize, Serialize};
use std::path::Path;
use tiny_skia::{Color, ColorU8, FillRule, PathBuilder, Pixmap};

/// One picture: a plan with paths and point clouds in its local frame.
#[derive(Debug, Clone)]
pub struct PlanPicture<'a> {
    /// The building.
    pub plan: &'a FloorPlan,
    /// Title above the picture.
    pub title: Option<String>,
    /// Lines through `(x, y, level)` points; a line is drawn on the panel of each point's level.
    pub paths: Vec<PlanPath<'a>>,
    /// Point clouds (e.g. particles).
    pub points: Vec<PlanPoints<'a>>,
    /// Filled areas over the floor (e.g. radio-map cells coloured by mean RSSI).
    pub cells: Vec<PlanCell<'a>>,
    /// Labelled markers (e.g. where an access point is heard strongest).
    pub markers: Vec<PlanMarker>,
    /// A colour bar in the title row, explaining the cells' colours.
    pub colour_bar: Option<ColourBar>,
}

/// A filled area over the plan.
#[derive(Debug, Clone, Copy)]
pub struct PlanCell<'a> {
    /// The area, local metres.
    pub area: &'a geo::MultiPolygon<f64>,
    /// Its level.
    pub level: i32,
    /// Fill colour.
    pub colour: [u8; 3],
}

/// A path over the plan.
#[derive(Debug, Clone, Copy)]
pub struct PlanPath<'a> {
    /// `(x, y, level)` in order.
    pub points: &'a [(f64, f64, i32)],
    /// Line colour.
    pub colour: [u8; 3],
    /// What it is (for documentation; the picture has no legend for it).
    pub label: &'a str,
}

/// A point cloud over the plan.
#[derive(Debug, Clone, Copy)]
pub struct PlanPoints<'a> {
    /// `(x, y, level)`.
    pub points: &'a [(f32, f32, i32)],
    /// Dot colour.
    pub colour: [u8; 3],
    /// What it is.
    pub label: &'a str,
}

/// Settings of [`render_plan_png`]; every default in one place.
///
/// | field              | default | meaning                                           |
/// |--------------------|---------|---------------------------------------------------|
/// | `pixels_per_metre` | 8       | scale, lowered to fit `max_width_px`              |
/// | `margin_px`        | 24      | border around and between panels                  |
/// | `max_width_px`     | 4000    | widest picture                                    |
/// | `min_width_px`     | 900     | narrowest picture: a small plan is drawn larger, so its titles and labels fit |
/// | `text_scale`       | 2       | image pixels per font pixel                       |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PlanPictureConfig {
    /// Image pixels per metre.
    pub pixels_per_metre: f64,
    /// Border, pixels.
    pub margin_px: u32,
    /// Widest picture, pixels.
    pub max_width_px: u32,
    /// Narrowest picture, pixels (the scale is raised for a small plan).
    pub min_width_px: u32,
    /// Font scale.
    pub text_scale: u32,
}

impl Default for PlanPictureConfig {
    fn default() -> Self {
        Self {
            pixels_per_metre: 8.0,
            margin_px: 24,
            max_width_px: 4000,
            min_width_px: 900,
            text_scale: 2,
        }
    }
}

impl PlanPictureConfig {
    /// Checks every field against its documented range.
    pub fn validate(&self) -> Result<()> {
        let ppm = self.pixels_per_metre;
        if !(ppm.is_finite() && ppm > 0.0 && ppm <= 500.0) {
            return Err(crate::error::Error::config(
                "picture.pixels_per_metre",
                ppm.to_string(),
                "must be in (0, 500]",
            ));
        }
        if self.margin_px > 200 {
            return Err(crate::error::Error::config(
                "picture.margin_px",
                self.margin_px.to_string(),
                "must be at most 200",
            ));
        }
        if !(400..=16384).contains(&self.max_width_px) {
            return Err(crate::error::Error::config(
                "picture.max_width_px",
                self.max_width_px.to_string(),
                "must be in 400..=16384",
            ));
        }
        if self.min_width_px > 16384 {
            return Err(crate::error::Error::config(
                "picture.min_width_px",
                self.min_width_px.to_string(),
                "must be at most 16384",
            ));
        }
        if !(1..=4).contains(&self.text_scale) {
            return Err(crate::error::Error::config(
                "picture.text_scale",
                self.text_scale.to_string(),
                "must be in 1..=4",
            ));
        }
        Ok(())
    }
}

/// Panel geometry shared by every picture of one image.
struct Layout {
    levels: Vec<i32>,
    min_x: f64,
    max_y: f64,
    scale: f64,
    panel_w: f64,
    margin: f64,
    title_h: f64,
    width: u32,
    row_h: f64,
}

impl Layout {
    fn new(pictures: &[PlanPicture], config: &PlanPictureConfig) -> Result<Self> {
        let mut levels: Vec<i32> = pictures
            .iter()
            .flat_map(|p| p.plan.polygons.iter().map(|f| f.level))
            .collect();
        levels.sort_unstable();
        levels.dedup();
        if levels.is_empty() {
            levels.push(0);
        }
        let (x0, y0, x1, y1) = pictures
            .iter()
            .filter_map(|p| p.plan.bounds())
            .reduce(|a, b| (a.0.min(b.0), a.1.min(b.1), a.2.max(b.2), a.3.max(b.3)))
            .unwrap_or((-5.0, -5.0, 5.0, 5.0));
        if ![x0, y0, x1, y1].iter().all(|v| v.is_finite()) {
            return Err(Error::invalid(
                "the floor plan",
                "has non-finite coordinates",
            ));
        }
        let (w_m, h_m) = ((x1 - x0).max(1.0), (y1 - y0).max(1.0));
        let margin = f64::from(config.margin_px);
        let n = levels.len() as f64;
        let fit = (f64::from(config.max_width_px) - margin * (n + 1.0)) / (n * w_m);
        // Raised for a narrow plan, but never taller than the widest picture allowed.
        let least = ((f64::from(config.min_width_px.min(config.max_width_px))
            - margin * (n + 1.0))
            / (n * w_m))
            .min(f64::from(config.max_width_px) / h_m);
        let scale = config.pixels_per_metre.max(least).min(fit).max(0.05);
        let (panel_w, panel_h) = (w_m * scale, h_m * scale);
        let title_h = f64::from(2 * GLYPH_HEIGHT * config.text_scale) + 12.0;
        let width = (margin * (n + 1.0) + n * panel_w).ceil();
        let row_h = title_h + panel_h + margin;
        Ok(Self {
            levels,
            min_x: x0,
            max_y: y1,
            scale,
            panel_w,
            margin,
            title_h,
            width: width as u32,
            row_h,
        })
    }

    /// Pixel of local `(x, y)` on the panel of level index `li` in row `row`.
    fn pixel(&self, row: usize, li: usize, x: f64, y: f64) -> (f32, f32) {
        let left = self.margin + li as f64 * (self.panel_w + self.margin);
        let top = self.margin + row as f64 * self.row_h + self.title_h;
        (
            (left + (x - self.min_x) * self.scale) as f32,
            (top + (self.max_y - y) * self.scale) as f32,
        )
    }

    fn level_index(&self, level: i32) -> Option<usize> {
        self.levels.binary_search(&level).ok()
    }
}

/// Renders `pictures` stacked top to bottom into one PNG.
pub fn render_plan_png(pictures: &[PlanPicture], config: &PlanPictureConfig) -> Result<Vec<u8>> {
    config.validate()?;
    if pictures.is_empty() {
        return Err(Error::not_enough("no picture to draw", ""));
    }
    let layout = Layout::new(pictures, config)?;
    let height = (layout.margin + layout.row_h * pictures.len() as f64).ceil() as u32;
    if u64::from(layout.width) * u64::from(height) > 400_000_000 {
        return Err(Error::too_large(
            "a picture",
            format!("{}×{height} pixels", layout.width),
            "4×10⁸ pixels",
            "draw fewer snapshots",
        ));
    }
    let mut pixmap = Pixmap::new(layout.width, height).ok_or_else(|| {
        Error::encode(
            format!("allocate a {}×{height} picture", layout.width),
            "out of memory",
        )
    })?;
    pixmap.fill(Color::WHITE);
    let ts = config.text_scale;
    for (row, picture) in pictures.iter().enumerate() {
        let top = (layout.margin + row as f64 * layout.row_h) as f32;
        if let Some(title) = &picture.title {
            glyphs::draw_text(&mut pixmap, title, (layout.margin as f32, top), ts, INK);
        }
        for (li, level) in layout.levels.iter().enumerate() {
            let (x, _) = layout.pixel(row, li, layout.min_x, layout.max_y);
            let label = format!("level {level}");
            let y = top + (GLYPH_HEIGHT * ts) as f32 + 4.0;
            glyphs::draw_text(&mut pixmap, &label, (x, y), ts, PLAN_WALL);
        }
        draw_plan(&mut pixmap, &layout, row, picture.plan);
        for cell in &picture.cells {
            draw_cell(&mut pixmap, &layout, row, cell);
        }
        for cloud in &picture.points {
            draw_points(&mut pixmap, &layout, row, cloud);
        }
        for path in &picture.paths {
            draw_path(&mut pixmap, &layout, row, path);
        }
        for m in &picture.markers {
            if let Some(li) = layout.level_index(m.level) {
                let at = layout.pixel(row, li, m.x, m.y);
                super::plan_marks::draw_marker(&mut pixmap, at, &m.label, ts);
            }
        }
        if let Some(bar) = &picture.colour_bar {
            let right = layout.width as f32 - layout.margin as f32;
            super::plan_marks::draw_colour_bar(&mut pixmap, bar, right, top, ts);
        }
    }
    pixmap
        .encode_png()
        .map_err(|e| Error::encode("encode the picture as PNG", e))
}

/// Renders `pictures` and writes them to `path` atomically.
pub fn write_plan_png(
    path: &Path,
    pictures: &[PlanPicture],
    config: &PlanPictureConfig,
) -> Result<()> {
    crate::io::write_atomically(path, &render_plan_png(pictures, config)?)
}

/// Surfaces shaded by their height off their level's floor (light grey on the floor, blue
/// 1.5 m up or down a stair), outlined as walls; barriers as thick black lines.
fn draw_plan(pixmap: &mut Pixmap, layout: &Layout, row: usize, plan: &FloorPlan) {
    // Each level's floor height: that of its largest surface.
    let floors: Vec<f64> = layout
        .levels
        .iter()
        .map(|&l| {
            plan.polygons
                .iter()
                .filter(|f| f.level == l)
                .max_by(|a, b| {
                    a.polygon
                        .unsigned_area()
                        .total_cmp(&b.polygon.unsigned_area())
                })
                .map_or(0.0, |f| f.z)
        })
        .collect();
    for stage in 0..2 {
        for f in &plan.polygons {
            let Some(li) = layout.level_index(f.level) else {
                continue;
            };
            let mut pb = PathBuilder::new();
            for ring in std::iter::once(f.polygon.exterior()).chain(f.polygon.interiors()) {
                push_ring(
                    &mut pb,
                    ring.coords().map(|c| layout.pixel(row, li, c.x, c.y)),
                );
            }
            let Some(path) = pb.finish() else { continue };
            if stage == 0 {
                let t = ((f.z - floors[li]).abs() / STAIR_SHADE_HEIGHT).clamp(0.0, 1.0);
                fill(pixmap, &path, height_shade(t), FillRule::EvenOdd);
            } else {
                stroke(pixmap, &path, PLAN_WALL, 1.0, None);
            }
        }
    }
    for b in &plan.barriers {
        let Some(li) = layout.level_index(b.level) else {
            continue;
        };
        if let Some(line) = polyline(b.line.coords().map(|c| layout.pixel(row, li, c.x, c.y))) {
            stroke(pixmap, &line, INK, 2.5, None);
        }
    }
}

/// Viridis (perceptually uniform, dark blue to yellow) at `t` in [0, 1], for cell colours.
pub fn viridis_rgb(t: f64) -> [u8; 3] {
    let c = super::canvas::viridis(t);
    [c.red(), c.green(), c.blue()]
}

/// Surfaces this far above or below their level's floor are shaded fully blue, metres.
const STAIR_SHADE_HEIGHT: f64 = 1.5;

/// Light grey (t = 0) to light blue (t = 1).
fn height_shade(t: f64) -> ColorU8 {
    let mix = |a: f64, b: f64| (a + t * (b - a)).round() as u8;
    rgb(mix(232.0, 170.0), mix(232.0, 200.0), mix(232.0, 235.0))
}

/// Dots blended into the pixels: each point adds a third of its colour, so dense clouds are
/// saturated and sparse ones faint.
fn draw_points(pixmap: &mut Pixmap, layout: &Layout, row: usize, cloud: &PlanPoints) {
    let (w, h) = (pixmap.width() as i64, pixmap.height() as i64);
    let [r, g, b] = cloud.colour.map(f32::from);
    let alpha = 0.35f32;
    let pixels = pixmap.pixels_mut();
    for &(x, y, level) in cloud.points {
        let Some(li) = layout.level_index(level) else {
            continue;
        };
        if !(x.is_finite() && y.is_finite()) {
            continue;
        }
        let (px, py) = layout.pixel(row, li, f64::from(x), f64::from(y));
        let (cx, cy) = (px.floor() as i64, py.floor() as i64);
        for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            let (qx, qy) = (cx + dx, cy + dy);
            if qx < 0 || qy < 0 || qx >= w || qy >= h {
                continue;
            }
            let p = &mut pixels[(qy * w + qx) as usize];
            let blend = |c: u8, t: f32| (f32::from(c) * (1.0 - alpha) + t * alpha).round() as u8;
            if let Some(c) = tiny_skia::PremultipliedColorU8::from_rgba(
                blend(p.red(), r),
                blend(p.green(), g),
                blend(p.blue(), b),
                255,
            ) {
                *p = c;
            }
        }
    }
}

/// A filled area with a thin outline.
fn draw_cell(pixmap: &mut Pixmap, layout: &Layout, row: usize, cell: &PlanCell) {
    let Some(li) = layout.level_index(cell.level) else {
        return;
    };
    let mut pb = PathBuilder::new();
    for polygon in &cell.area.0 {
        for ring in std::iter::once(polygon.exterior()).chain(polygon.interiors()) {
            push_ring(
                &mut pb,
                ring.coords().map(|c| layout.pixel(row, li, c.x, c.y)),
            );
        }
    }
    if let Some(path) = pb.finish() {
        let [r, g, b] = cell.colour;
        fill(pixmap, &path, rgb(r, g, b), FillRule::EvenOdd);
        stroke(
            pixmap,
            &path,
            ColorU8::from_rgba(255, 255, 255, 160),
            0.5,
            None,
        );
    }
}

/// The path, split where it changes level, on each level's panel.
fn draw_path(pixmap: &mut Pixmap, layout: &Layout, row: usize, path: &PlanPath) {
    let colour = rgb(path.colour[0], path.colour[1], path.colour[2]);
    let halo = ColorU8::from_rgba(255, 255, 255, 200);
    let mut start = 0;
    while start < path.points.len() {
        let level = path.points[start].2;
        let end = path.points[start..]
            .iter()
            .position(|p| p.2 != level)
            .map_or(path.points.len(), |k| start + k);
        if let Some(li) = layout.level_index(level) {
            let pixels: Vec<(f32, f32)> = path.points[start..end]
                .iter()
                .filter(|p| p.0.is_finite() && p.1.is_finite())
                .map(|p| layout.pixel(row, li, p.0, p.1))
                .collect();
            for line in polyline_pieces(&pixels) {
                stroke(pixmap, &line, halo, 3.5, None);
                stroke(pixmap, &line, colour, 2.0, None);
            }
        }
        start = end;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::FloorPolygon;
    use geo::Rect;

    fn two_floors() -> FloorPlan {
        let floor = |level: i32| FloorPolygon {
            polygon: Rect::new((0.0, 0.0), (20.0, 10.0)).to_polygon(),
            level,
            z: 3.0 * f64::from(level),
            name: None,
            room: None,
        };
        FloorPlan {
            polygons: vec![floor(0), floor(1)],
            ..Default::default()
        }
    }

    #[test]
    fn panels_per_level_and_rows_per_picture() {
        let plan = two_floors();
        let path = [(1.0, 1.0, 0), (5.0, 5.0, 0), (5.0, 5.0, 1), (9.0, 1.0, 1)];
        let cell = geo::MultiPolygon::new(vec![Rect::new((2.0, 2.0), (4.0, 4.0)).to_polygon()]);
        let points: Vec<(f32, f32, i32)> = (0..10_000)
            .map(|i| ((i % 200) as f32 * 0.1, (i / 200) as f32 * 0.2, 0))
            .collect();
        let picture = PlanPicture {
            plan: &plan,
            title: Some("step 5: 10000 particles".into()),
            paths: vec![PlanPath {
                points: &path,
                colour: [20, 60, 200],
                label: "track",
            }],
            points: vec![PlanPoints {
                points: &points,
                colour: [200, 30, 30],
                label: "particles",
            }],
            cells: vec![PlanCell {
                area: &cell,
                level: 1,
                colour: [0, 160, 0],
            }],
            markers: vec![PlanMarker {
                x: 3.0,
                y: 3.0,
                level: 1,
                label: "strongest".into(),
            }],
            colour_bar: Some(ColourBar {
                low: "-96 dBm".into(),
                high: "-30 dBm".into(),
                colour: viridis_rgb,
            }),
        };
        // The default widens a small plan to 900 px.
        let wide = render_plan_png(
            std::slice::from_ref(&picture),
            &PlanPictureConfig::default(),
        )
        .expect("png");
        let wide = image::load_from_memory(&wide).expect("decodes");
        assert_eq!(wide.width(), 900);
        let config = PlanPictureConfig {
            min_width_px: 0,
            ..Default::default()
        };
        let png = render_plan_png(&[picture.clone(), picture], &config).expect("png");
        let image = image::load_from_memory(&png).expect("decodes").to_rgb8();
        // Two 20 m panels at 8 px/m with 24 px margins: 3 × 24 + 2 × 160 = 392 wide.
        assert_eq!(image.width(), 392);
        assert!(image.height() > 2 * 80);
        // Red dots land on the first panel.
        let (x, y) = (24 + 40, 24 + 40);
        let p = image.get_pixel(x, (y + 28) as u32);
        assert!(p[0] > p[2], "{p:?}");
        // The green cell fills its place on the second panel (level 1), left of the dots.
        let (cx, cy) = (24 + 160 + 24 + 24, 24 + 40 + 7 * 8);
        let q = image.get_pixel(cx, cy);
        assert!(q[1] > q[0] && q[1] > q[2], "{q:?}");
        assert!(render_plan_png(&[], &config).is_err());
    }
}
