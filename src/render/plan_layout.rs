//! Where a plan picture's panels lie and which part of the floor they show.
//!
//! A picture shows what is drawn over the plan (paths, point clouds, cells, markers) with a
//! margin around it, within the plan: a 40 m walk in a 240 m mall fills its picture rather
//! than a sliver of it. The part shown can be given instead
//! ([`PlanPictureConfig::extent`]); without anything drawn over it, the whole plan is shown.
//! The scale is the configured one, lowered so that the picture fits the widest and tallest
//! allowed, raised for a small extent so that titles and labels fit.

use super::glyphs::GLYPH_HEIGHT;
use super::key::{KeyEntry, key_height};
use super::plan_picture::{PlanPicture, PlanPictureConfig};
use crate::error::{Error, Result};
use geo::BoundingRect;

/// `(x0, y0, x1, y1)`, local metres.
type Bounds = (f64, f64, f64, f64);

fn union(a: Bounds, b: Bounds) -> Bounds {
    (a.0.min(b.0), a.1.min(b.1), a.2.max(b.2), a.3.max(b.3))
}

/// The bounds of the finite points `(x, y)` of `points`.
fn bounds_of(points: impl Iterator<Item = (f64, f64)>) -> Option<Bounds> {
    points
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .map(|(x, y)| (x, y, x, y))
        .reduce(union)
}

/// What the pictures draw over their plans, bounded.
fn content_bounds(pictures: &[PlanPicture]) -> Option<Bounds> {
    let mut all: Vec<Bounds> = Vec::new();
    for p in pictures {
        all.extend(
            p.paths
                .iter()
                .filter_map(|path| bounds_of(path.points.iter().map(|&(x, y, _)| (x, y)))),
        );
        all.extend(p.points.iter().filter_map(|cloud| {
            bounds_of(
                cloud
                    .points
                    .iter()
                    .map(|&(x, y, _)| (f64::from(x), f64::from(y))),
            )
        }));
        all.extend(p.cells.iter().filter_map(|c| {
            c.area
                .bounding_rect()
                .map(|r| (r.min().x, r.min().y, r.max().x, r.max().y))
        }));
        all.extend(bounds_of(p.markers.iter().map(|m| (m.x, m.y))));
    }
    all.into_iter().reduce(union)
}

/// The part of the floor the pictures show: [`PlanPictureConfig::extent`], else what they
/// draw with [`PlanPictureConfig::crop_margin_m`] around it, within the plan, else the plan.
pub(super) fn extent(pictures: &[PlanPicture], config: &PlanPictureConfig) -> Bounds {
    if let Some([x0, y0, x1, y1]) = config.extent {
        return (x0, y0, x1, y1);
    }
    let plan = pictures
        .iter()
        .filter_map(|p| p.plan.bounds())
        .reduce(union);
    let m = config.crop_margin_m;
    let content = content_bounds(pictures)
        .filter(|_| config.crop_to_content)
        .map(|c| (c.0 - m, c.1 - m, c.2 + m, c.3 + m));
    match (plan, content) {
        (Some(p), Some(c)) => {
            let cut = (p.0.max(c.0), p.1.max(c.1), p.2.min(c.2), p.3.min(c.3));
            if cut.0 < cut.2 && cut.1 < cut.3 {
                cut
            } else {
                p
            }
        }
        (Some(p), None) => p,
        (None, Some(c)) => c,
        (None, None) => (-5.0, -5.0, 5.0, 5.0),
    }
}

/// Panel geometry shared by every picture of one image.
#[derive(Debug, Clone)]
pub(super) struct Layout {
    pub(super) levels: Vec<i32>,
    pub(super) min_x: f64,
    pub(super) max_y: f64,
    pub(super) scale: f64,
    pub(super) panel_w: f64,
    pub(super) panel_h: f64,
    pub(super) margin: f64,
    pub(super) title_h: f64,
    pub(super) width: u32,
    pub(super) row_h: f64,
    /// Height of the legend strip below the last picture, pixels.
    pub(super) legend_h: f64,
    /// Width the key wraps within, pixels.
    pub(super) key_w: f32,
}

impl Layout {
    pub(super) fn new(
        pictures: &[PlanPicture],
        config: &PlanPictureConfig,
        key: &[KeyEntry],
    ) -> Result<Self> {
        let mut levels: Vec<i32> = pictures
            .iter()
            .flat_map(|p| p.plan.polygons.iter().map(|f| f.level))
            .collect();
        levels.sort_unstable();
        levels.dedup();
        if levels.is_empty() {
            levels.push(0);
        }
        let (x0, y0, x1, y1) = extent(pictures, config);
        if ![x0, y0, x1, y1].iter().all(|v| v.is_finite()) {
            return Err(Error::invalid(
                "the floor plan",
                "has non-finite coordinates",
            ));
        }
        let (w_m, h_m) = ((x1 - x0).max(1.0), (y1 - y0).max(1.0));
        let margin = f64::from(config.margin_px);
        let n = levels.len() as f64;
        let rows = pictures.len().max(1) as f64;
        let title_h = f64::from(2 * GLYPH_HEIGHT * config.text_scale) + 12.0;
        let fit = (f64::from(config.max_width_px) - margin * (n + 1.0)) / (n * w_m);
        // The legend strip: scale bar and north arrow, then the key wrapped within the
        // narrowest picture.
        let ts = config.text_scale;
        let key_w = (f64::from(config.min_width_px.min(config.max_width_px)) - 2.0 * margin)
            .max(100.0) as f32;
        let legend_h = f64::from(2 * GLYPH_HEIGHT * ts)
            + 18.0
            + f64::from(key_height(key, key_w, ts))
            + margin;
        let fit_h =
            (f64::from(config.max_height_px) - margin - legend_h - rows * (title_h + margin))
                / (rows * h_m);
        // Raised for a narrow plan, but never taller than the widest picture allowed.
        let least = ((f64::from(config.min_width_px.min(config.max_width_px))
            - margin * (n + 1.0))
            / (n * w_m))
            .min(f64::from(config.max_width_px) / h_m);
        let scale = config
            .pixels_per_metre
            .max(least)
            .min(fit)
            .min(fit_h)
            .max(0.05);
        let (panel_w, panel_h) = (w_m * scale, h_m * scale);
        let width = (margin * (n + 1.0) + n * panel_w).ceil();
        let row_h = title_h + panel_h + margin;
        Ok(Self {
            levels,
            min_x: x0,
            max_y: y1,
            scale,
            panel_w,
            panel_h,
            margin,
            title_h,
            width: width as u32,
            row_h,
            legend_h,
            key_w,
        })
    }

    /// Pixel of local `(x, y)` on the panel of level index `li` in row `row`.
    pub(super) fn pixel(&self, row: usize, li: usize, x: f64, y: f64) -> (f32, f32) {
        let left = self.margin + li as f64 * (self.panel_w + self.margin);
        let top = self.margin + row as f64 * self.row_h + self.title_h;
        (
            (left + (x - self.min_x) * self.scale) as f32,
            (top + (self.max_y - y) * self.scale) as f32,
        )
    }

    pub(super) fn level_index(&self, level: i32) -> Option<usize> {
        self.levels.binary_search(&level).ok()
    }

    /// The layout of one panel drawn on its own: level `level` alone, its top left corner at
    /// pixel (0, 0).
    pub(super) fn panel(&self, level: i32) -> Self {
        Self {
            levels: vec![level],
            margin: 0.0,
            title_h: 0.0,
            ..self.clone()
        }
    }

    /// Whether local `(x, y)` lies within the part of the floor shown.
    pub(super) fn shows(&self, x: f64, y: f64) -> bool {
        (0.0..=self.panel_w).contains(&((x - self.min_x) * self.scale))
            && (0.0..=self.panel_h).contains(&((self.max_y - y) * self.scale))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::{FloorPlan, FloorPolygon};
    use crate::render::plan_picture::PlanPath;
    use geo::Rect;

    fn mall() -> FloorPlan {
        FloorPlan {
            polygons: vec![FloorPolygon {
                polygon: Rect::new((0.0, 0.0), (240.0, 200.0)).to_polygon(),
                level: 0,
                z: 0.0,
                name: None,
                room: None,
            }],
            ..Default::default()
        }
    }

    fn picture<'a>(plan: &'a FloorPlan, path: &'a [(f64, f64, i32)]) -> PlanPicture<'a> {
        PlanPicture {
            plan,
            title: None,
            paths: vec![PlanPath {
                points: path,
                colour: [0, 0, 0],
                label: "walk",
            }],
            points: Vec::new(),
            cells: Vec::new(),
            markers: Vec::new(),
            north_up: true,
            colour_bar: None,
        }
    }

    #[test]
    fn a_walk_is_shown_with_its_margin_within_the_plan() {
        let plan = mall();
        let walk = [(5.0, 20.0, 0), (45.0, 30.0, 0), (f64::NAN, 0.0, 0)];
        let config = PlanPictureConfig::default();
        let one = [picture(&plan, &walk)];
        // 10 m around the walk, cut by the plan's edge at x = 0.
        assert_eq!(extent(&one, &config), (0.0, 10.0, 55.0, 40.0));
        let whole = PlanPictureConfig {
            crop_to_content: false,
            ..config
        };
        assert_eq!(extent(&one, &whole), (0.0, 0.0, 240.0, 200.0));
        let given = PlanPictureConfig {
            extent: Some([100.0, 100.0, 120.0, 150.0]),
            ..config
        };
        assert_eq!(extent(&one, &given), (100.0, 100.0, 120.0, 150.0));
        let nothing = [picture(&plan, &[])];
        assert_eq!(extent(&nothing, &config), (0.0, 0.0, 240.0, 200.0));
        // Many snapshots stay within the tallest picture allowed.
        let many: Vec<_> = (0..12).map(|_| picture(&plan, &[])).collect();
        let layout = Layout::new(&many, &config, &[]).expect("layout");
        let height = layout.margin + layout.row_h * many.len() as f64 + layout.legend_h;
        assert!(height <= f64::from(config.max_height_px) + 1.0, "{height}");
        // Inside and outside what is shown.
        let layout = Layout::new(&one, &config, &[]).expect("layout");
        assert!(layout.shows(30.0, 25.0) && !layout.shows(100.0, 25.0));
    }
}
