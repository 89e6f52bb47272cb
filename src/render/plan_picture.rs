//! What a plan picture holds (the plan, paths, point clouds, cells, markers) and its
//! settings ([`PlanPictureConfig`]); drawn by [`super::plan_png`], laid out by
//! `plan_layout`.

pub use super::plan_marks::{ColourBar, PlanMarker};
use crate::error::Result;
use crate::map::FloorPlan;
use serde::{Deserialize, Serialize};

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
    /// The frame's y axis points north (a GeoJSON plan's frame does; a learned plan's only
    /// where GPS, a compass, an outline or a prior map placed it): the legend draws a north
    /// arrow when every picture of the image says so.
    pub north_up: bool,
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

/// Settings of [`super::plan_png::render_plan_png`]; every default in one place.
///
/// | field              | default | meaning                                           |
/// |--------------------|---------|---------------------------------------------------|
/// | `pixels_per_metre` | 8       | scale, lowered to fit `max_width_px`              |
/// | `margin_px`        | 24      | border around and between panels                  |
/// | `max_width_px`     | 4000    | widest picture                                    |
/// | `min_width_px`     | 900     | narrowest picture: a small plan is drawn larger, so its titles and labels fit |
/// | `max_height_px`    | 4000    | tallest picture (all its snapshots): the scale is lowered to fit |
/// | `text_scale`       | 2       | image pixels per font pixel                       |
/// | `crop_to_content`  | true    | show what is drawn over the plan, not the whole plan |
/// | `crop_margin_m`    | 10      | floor shown around what is drawn, metres          |
/// | `extent`           | none    | `[x0, y0, x1, y1]` local metres to show instead (`--picture-extent`) |
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
    /// Tallest picture, pixels (the scale is lowered to fit).
    pub max_height_px: u32,
    /// Show the part of the plan that paths, points, cells and markers cover (with
    /// `crop_margin_m` around), not the whole plan.
    pub crop_to_content: bool,
    /// Floor shown around what is drawn, metres.
    pub crop_margin_m: f64,
    /// The part of the floor to show, `[x0, y0, x1, y1]` local metres, instead of the crop.
    pub extent: Option<[f64; 4]>,
}

impl Default for PlanPictureConfig {
    fn default() -> Self {
        Self {
            pixels_per_metre: 8.0,
            margin_px: 24,
            max_width_px: 4000,
            min_width_px: 900,
            text_scale: 2,
            max_height_px: 4000,
            crop_to_content: true,
            crop_margin_m: 10.0,
            extent: None,
        }
    }
}

impl PlanPictureConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) when `pixels_per_metre` is outside (0, 500],
    /// `margin_px` above 200, `max_width_px` or `max_height_px` outside 400..=16384, `min_width_px`
    /// above 16384, `crop_margin_m` outside [0, 1000] m, `text_scale` outside 1..=4, or an `extent`
    /// is not `x0 < x1, y0 < y1` within 1000 km of the origin.
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
        if !(400..=16384).contains(&self.max_height_px) {
            return Err(crate::error::Error::config(
                "picture.max_height_px",
                self.max_height_px.to_string(),
                "must be in 400..=16384",
            ));
        }
        crate::error::check_range(
            "picture.crop_margin_m",
            self.crop_margin_m,
            0.0..=1000.0,
            "m",
        )?;
        if let Some([x0, y0, x1, y1]) = self.extent
            && !([x0, y0, x1, y1]
                .iter()
                .all(|v| v.is_finite() && v.abs() <= 1e6)
                && x0 < x1
                && y0 < y1)
        {
            return Err(crate::error::Error::config(
                "picture.extent",
                format!("[{x0}, {y0}, {x1}, {y1}]"),
                "must be x0 < x1, y0 < y1, local metres within 1000 km of the origin",
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
