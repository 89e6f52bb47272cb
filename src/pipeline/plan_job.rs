//! The `plan` job, request in, report out: a learned map as a walkable floor plan and one
//! occupancy grid per floor ([`plan`](super::plan())).

use super::named::Named;
use super::plan::{PlanRunConfig, Planned, plan};
use crate::error::{Error, Result};
use crate::geometry::LocalFrame;
use crate::io::map_geojson::StoredMap;
use serde::Serialize;

/// The options of `plan` that change its configuration; `None` leaves the configuration's.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PlanOverrides {
    /// `plan.min_visits`: passes through a hexagon that make it walkable.
    pub min_visits: Option<u32>,
    /// `grid.resolution`: the side of an occupancy-grid square, metres.
    pub resolution: Option<f64>,
}

impl PlanOverrides {
    /// `config` with these overrides.
    ///
    /// ```
    /// use footslam::pipeline::{PlanOverrides, PlanRunConfig};
    /// let o = PlanOverrides { min_visits: Some(3), resolution: None };
    /// let config = o.apply(PlanRunConfig::default());
    /// assert_eq!(config.plan.min_visits, 3);
    /// assert_eq!(config.grid.resolution, PlanRunConfig::default().grid.resolution);
    /// ```
    #[must_use]
    pub fn apply(&self, mut config: PlanRunConfig) -> PlanRunConfig {
        if let Some(k) = self.min_visits {
            config.plan.min_visits = k;
        }
        if let Some(r) = self.resolution {
            config.grid.resolution = r;
        }
        config
    }
}

/// Everything `plan` runs on, read and parsed by a face.
#[derive(Debug, Clone)]
pub struct PlanRequest {
    /// The learned map.
    pub map: Named<StoredMap>,
    /// The configuration file's (or the defaults).
    pub config: PlanRunConfig,
    /// The face's options over it.
    pub overrides: PlanOverrides,
}

/// `summary.json` of `plan`.
#[derive(Debug, Clone, Serialize)]
pub struct PlanReport {
    /// The map's name.
    pub map_file: String,
    /// Hexagons of the map.
    pub map_hexagons: usize,
    /// Walks whose counts the map holds.
    pub map_walks: u32,
    /// Hexagons walked often enough to be walkable.
    pub hexagons_used: usize,
    /// Hexagons left out.
    pub hexagons_left_out: usize,
    /// Polygons of the plan.
    pub polygons: usize,
    /// Small holes filled.
    pub holes_filled: usize,
    /// Stray pieces dropped.
    pub pieces_dropped: usize,
    /// Walkable area, m².
    pub walkable_area_m2: f64,
    /// The main floor's grid: width and height in squares.
    pub grid_width: usize,
    /// Its height.
    pub grid_height: usize,
    /// Its free squares.
    pub grid_free: usize,
    /// Its occupied squares.
    pub grid_occupied: usize,
    /// Its unknown squares.
    pub grid_unknown: usize,
    /// The map's frame.
    pub origin: LocalFrame,
}

/// What [`run_plan`] gives.
#[derive(Debug, Clone)]
pub struct PlanJob {
    /// The configuration run.
    pub config: PlanRunConfig,
    /// The map's frame.
    pub frame: LocalFrame,
    /// The plan and its grids.
    pub planned: Planned,
    /// Its report.
    pub report: PlanReport,
}

/// The walkable plan and grids of the request's map, and the report.
///
/// # Errors
///
/// As [`plan`](super::plan()): the configuration with its overrides out of range, a map with no
/// hexagon visited `min_visits` times or no walkable piece of `min_area`, or a grid beyond 2²⁸
/// squares.
pub fn run_plan(request: PlanRequest) -> Result<PlanJob> {
    let config = request.overrides.apply(request.config);
    let stored = &request.map.value;
    let planned = plan(&stored.map, &config)?;
    let learned = &planned.learned;
    let (_, grid) = planned.grids.first().ok_or_else(|| {
        Error::not_enough(format!("{}: the plan has no floor", request.map.label), "")
    })?;
    let (free, occupied, unknown) = grid.counts();
    let report = PlanReport {
        map_file: request.map.label.clone(),
        map_hexagons: stored.map.cells.len(),
        map_walks: stored.walks,
        hexagons_used: learned.hexagons,
        hexagons_left_out: learned.hexagons_left_out,
        polygons: learned.plan.polygons.len(),
        holes_filled: learned.holes_filled,
        pieces_dropped: learned.pieces_dropped,
        walkable_area_m2: learned.area_m2,
        grid_width: grid.width,
        grid_height: grid.height,
        grid_free: free,
        grid_occupied: occupied,
        grid_unknown: unknown,
        origin: stored.frame,
    };
    Ok(PlanJob {
        config,
        frame: stored.frame,
        planned,
        report,
    })
}
