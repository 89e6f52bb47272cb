//! Pictures (PNG) of multi-floor plans with paths and particle clouds over them, as in Woodman
//! & Harle 2008, Fig. 4: one panel per floor level side by side at one scale, surfaces shaded
//! by height (so stair treads show as a ramp), outlines as walls, barriers in black, paths as
//! lines and point clouds as density-blended dots. Several pictures (snapshots at chosen
//! steps) stack top to bottom in one image, each under its title, above one legend strip:
//! scale bar, north arrow (north is up) and the key of every line, cloud and marker drawn.

use super::canvas::{INK, PLAN_WALL, fill, polyline, polyline_pieces, push_ring, rgb, stroke};
use super::glyphs::{self, GLYPH_HEIGHT};
use super::key::{KeyEntry, Swatch};
use super::plan_layout::Layout;
pub use super::plan_picture::{
    ColourBar, PlanCell, PlanMarker, PlanPath, PlanPicture, PlanPictureConfig, PlanPoints,
};
use crate::error::{Error, Result};
use crate::map::FloorPlan;
use geo::Area;
use rayon::prelude::*;
use std::path::Path;
use tiny_skia::{Color, ColorU8, FillRule, PathBuilder, Pixmap, PixmapPaint, Transform};

/// Renders `pictures` stacked top to bottom into one PNG.
///
/// # Errors
///
/// - [`Error::Config`] when `config` fails [`PlanPictureConfig::validate`].
/// - [`Error::NotEnough`] when `pictures` is empty.
/// - [`Error::InvalidData`] when the plans' extent is not finite.
/// - [`Error::TooLarge`] beyond 4×10⁸ pixels (too many snapshots).
/// - [`Error::Encode`] when the picture or a panel cannot be allocated, or the PNG cannot be
///   encoded.
pub fn render_plan_png(pictures: &[PlanPicture], config: &PlanPictureConfig) -> Result<Vec<u8>> {
    config.validate()?;
    if pictures.is_empty() {
        return Err(Error::not_enough("no picture to draw", ""));
    }
    let key = key_of(pictures);
    let layout = Layout::new(pictures, config, &key)?;
    let rows_bottom = layout.margin + layout.row_h * pictures.len() as f64;
    let height = (rows_bottom + layout.legend_h).ceil() as u32;
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
    // Every panel drawn on its own, in parallel (a particle cloud of a million points per
    // picture), then placed in order.
    let levels = layout.levels.len();
    let panels: Vec<Pixmap> = (0..pictures.len() * levels)
        .into_par_iter()
        .map(|k| draw_panel(&layout, layout.levels[k % levels], &pictures[k / levels]))
        .collect::<Result<_>>()?;
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
        for li in 0..levels {
            let panel = &panels[row * levels + li];
            let (x, y) = layout.pixel(row, li, layout.min_x, layout.max_y);
            pixmap.draw_pixmap(
                x.round() as i32,
                y.round() as i32,
                panel.as_ref(),
                &PixmapPaint::default(),
                Transform::identity(),
                None,
            );
        }
        for m in &picture.markers {
            if let Some(li) = layout.level_index(m.level)
                && layout.shows(m.x, m.y)
            {
                // Its label is in the key: beside the marker it would hide the cells.
                let at = layout.pixel(row, li, m.x, m.y);
                super::plan_marks::draw_marker(&mut pixmap, at, "", ts);
            }
        }
        if let Some(bar) = &picture.colour_bar {
            let right = layout.width as f32 - layout.margin as f32;
            super::plan_marks::draw_colour_bar(&mut pixmap, bar, right, top, ts);
        }
    }
    let north_up = pictures.iter().all(|p| p.north_up);
    draw_legend(
        &mut pixmap,
        &layout,
        rows_bottom as f32,
        (&key, north_up),
        ts,
    );
    pixmap
        .encode_png()
        .map_err(|e| Error::encode("encode the picture as PNG", e))
}

/// The key of `pictures`: each path, point cloud and marker label once, in the order drawn.
fn key_of(pictures: &[PlanPicture]) -> Vec<KeyEntry> {
    let mut key: Vec<KeyEntry> = Vec::new();
    let mut add = |entry: KeyEntry| {
        if !entry.label.is_empty() && !key.contains(&entry) {
            key.push(entry);
        }
    };
    for p in pictures {
        // What a picture holds nothing of is not in the key.
        for path in p.paths.iter().filter(|p| !p.points.is_empty()) {
            let [r, g, b] = path.colour;
            add(KeyEntry::new(Swatch::Line(rgb(r, g, b)), path.label));
        }
        for cloud in p.points.iter().filter(|c| !c.points.is_empty()) {
            let [r, g, b] = cloud.colour;
            add(KeyEntry::new(Swatch::Dots(rgb(r, g, b)), cloud.label));
        }
        for m in &p.markers {
            add(KeyEntry::new(Swatch::Marker, m.label.clone()));
        }
    }
    key
}

/// The strip below the pictures from `top`: a scale bar and, where the frame is absolute
/// (`north_up`), a north arrow; then the key.
fn draw_legend(
    pixmap: &mut Pixmap,
    layout: &Layout,
    top: f32,
    (key, north_up): (&[KeyEntry], bool),
    ts: u32,
) {
    let margin = layout.margin as f32;
    let text_h = (GLYPH_HEIGHT * ts) as f32;
    let room = (layout.panel_w / 3.0).clamp(40.0, 200.0);
    super::key::draw_scale_bar(pixmap, (margin, top + text_h), room, layout.scale, ts);
    if north_up {
        super::key::draw_north_arrow(pixmap, layout.width as f32 - margin - 10.0, top, ts);
    }
    let key_top = top + 2.0 * text_h + 18.0;
    super::key::draw_key(pixmap, key, (margin, key_top), layout.key_w, ts);
}

/// The panel of `level` of `picture` on its own (white, the size of a panel): the plan,
/// cells, point clouds and paths, clipped to the part of the floor shown.
fn draw_panel(layout: &Layout, level: i32, picture: &PlanPicture) -> Result<Pixmap> {
    let (w, h) = (
        (layout.panel_w.ceil() as u32).max(1),
        (layout.panel_h.ceil() as u32).max(1),
    );
    let mut panel = Pixmap::new(w, h)
        .ok_or_else(|| Error::encode(format!("allocate a {w}×{h} panel"), "out of memory"))?;
    panel.fill(Color::WHITE);
    let own = layout.panel(level);
    draw_plan(&mut panel, &own, 0, picture.plan);
    for cell in &picture.cells {
        draw_cell(&mut panel, &own, 0, cell);
    }
    for cloud in &picture.points {
        draw_points(&mut panel, &own, 0, cloud);
    }
    for path in &picture.paths {
        draw_path(&mut panel, &own, 0, path);
    }
    Ok(panel)
}

/// Renders `pictures` and writes them to `path` atomically.
///
/// # Errors
///
/// As [`render_plan_png`], and [`Error::Io`] when `path` cannot be written (its folder missing or
/// read-only).
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
#[must_use]
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
    let (w, h) = (i64::from(pixmap.width()), i64::from(pixmap.height()));
    let [r, g, b] = cloud.colour.map(f32::from);
    let alpha = 0.35f32;
    // The blend of every channel value with the cloud's colour, once (a million-point
    // cloud blends four pixels a point).
    let blend = |c: u8, t: f32| (f32::from(c) * (1.0 - alpha) + t * alpha).round() as u8;
    let table = |t: f32| -> [u8; 256] { std::array::from_fn(|c| blend(c as u8, t)) };
    let (tr, tg, tb) = (table(r), table(g), table(b));
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
            if let Some(c) = tiny_skia::PremultipliedColorU8::from_rgba(
                tr[usize::from(p.red())],
                tg[usize::from(p.green())],
                tb[usize::from(p.blue())],
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
            north_up: true,
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
