//! A learned map as a walkable floor plan and occupancy grids, as stages:
//!
//! 1. **plan** — the hexagons walked at least `min_visits` times, joined into polygons per
//!    floor, small holes filled and stray pieces dropped ([`walkable_plan`]);
//! 2. **grids** — one occupancy grid per floor, the plan's own `level` first (or, when the
//!    walks never stood on it, the lowest).

use crate::Result;
use crate::map::{
    HexMapSnapshot, LearnedPlan, OccupancyConfig, OccupancyGrid, PlanConfig, walkable_plan,
};
use serde::{Deserialize, Serialize};

/// Everything [`plan`] needs; every default in its component.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PlanRunConfig {
    /// The walkable plan ([`PlanConfig`]).
    pub plan: PlanConfig,
    /// The occupancy grid ([`OccupancyConfig`]).
    pub grid: OccupancyConfig,
}

/// What [`plan`] gives.
#[derive(Debug, Clone)]
pub struct Planned {
    /// The walkable plan.
    pub learned: LearnedPlan,
    /// One grid per floor, `(level, grid)`, the main floor first.
    pub grids: Vec<(i32, OccupancyGrid)>,
}

/// The walkable plan and occupancy grids of `map`, in the stages of the [module](self).
///
/// # Errors
///
/// As [`walkable_plan`]: `config.plan` out of range, or no hexagon with `min_visits` visits or no
/// piece of `min_area`; as [`OccupancyGrid::from_plan`](crate::map::OccupancyGrid::from_plan):
/// `config.grid` out of range, or a grid beyond 2²⁸ squares.
pub fn plan(map: &HexMapSnapshot, config: &PlanRunConfig) -> Result<Planned> {
    let learned = walkable_plan(map, &config.plan)?;
    let mut levels = learned.plan.levels();
    let main = if levels.contains(&config.plan.level) {
        config.plan.level
    } else {
        levels[0]
    };
    levels.retain(|&l| l != main);
    levels.insert(0, main);
    let grids = levels
        .iter()
        .map(|&l| OccupancyGrid::from_plan(&learned.plan, l, &config.grid).map(|g| (l, g)))
        .collect::<Result<Vec<_>>>()?;
    Ok(Planned { learned, grids })
}
