//! `footslam plan`: a learned map as a walkable floor plan (`plan.geojson`, the contract
//! `track` and `survey` read) and a ROS occupancy grid (`map.pgm` + `map.yaml`).

use super::common::{output_dir, read_config, require_file};
use anyhow::Result;
use footslam::geometry::LocalFrame;
use footslam::io::floor_plan_geojson::write_floor_plan;
use footslam::io::map_geojson::read_stored_map;
use footslam::io::{RunFolder, write_ros_map};
use footslam::map::{LearnedPlan, OccupancyGrid};
use footslam::pipeline::{PlanRunConfig, Planned, plan};
use footslam::render::plan_png::{PlanPicture, PlanPictureConfig, write_plan_png};
use serde::Serialize;
use std::path::PathBuf;

/// Arguments of `footslam plan`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Learned map (map.geojson or merged.geojson of `learn`, or `merge`'s output).
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    map: PathBuf,
    /// Passes through a hexagon that make it walkable (overrides the config file; default
    /// 1; raise it for maps of many walks, where a stray step should not open a wall).
    #[arg(long, value_name = "N", help_heading = "Filter")]
    min_visits: Option<u32>,
    /// Side of an occupancy-grid square, metres (overrides the config file; default 0.05).
    #[arg(long, value_name = "METRES", help_heading = "Filter")]
    resolution: Option<f64>,
    /// Configuration (TOML or JSON with `plan` and `grid` tables; see config.json of a run).
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    config: Option<PathBuf>,
    /// Output folder (default: a new folder under `outputs/`).
    #[arg(short = 'o', long, value_name = "DIR", help_heading = "Outputs")]
    out: Option<PathBuf>,
}

#[derive(Debug, Serialize)]
struct Summary {
    map_file: String,
    map_hexagons: usize,
    map_walks: u32,
    hexagons_used: usize,
    hexagons_left_out: usize,
    polygons: usize,
    holes_filled: usize,
    pieces_dropped: usize,
    walkable_area_m2: f64,
    grid_width: usize,
    grid_height: usize,
    grid_free: usize,
    grid_occupied: usize,
    grid_unknown: usize,
    origin: LocalFrame,
}

/// Runs `footslam plan`.
pub fn run(args: Args) -> Result<()> {
    let mut config: PlanRunConfig = match &args.config {
        Some(p) => read_config(p)?,
        None => PlanRunConfig::default(),
    };
    if let Some(k) = args.min_visits {
        config.plan.min_visits = k;
    }
    if let Some(r) = args.resolution {
        config.grid.resolution = r;
    }
    require_file(&args.map, "map")?;
    let stored = read_stored_map(&args.map)?;
    // One occupancy grid per floor: `map.pgm` for the main floor, `map-level+N.pgm` others.
    let Planned { learned, grids } = plan(&stored.map, &config)?;
    let grid = &grids[0].1;
    let mut folder = super::common::create_run_folder(&output_dir(args.out, "plan"))?;
    folder.protect(std::iter::once(&args.map).chain(args.config.iter()));
    write_plan_files(&folder, "", &learned, &grids, &stored.frame)?;
    folder.write_json("config.json", &config)?;
    let (free, occupied, unknown) = grid.counts();
    let summary = Summary {
        map_file: args.map.display().to_string(),
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
    folder.write_json("summary.json", &summary)?;
    let out = folder.commit()?;
    info!(
        "walkable plan of {:.0} m² in {} polygon(s) from {} of {} hexagons ({} holes filled, {} stray pieces dropped); occupancy grid {} × {} at {} m",
        learned.area_m2,
        learned.plan.polygons.len(),
        learned.hexagons,
        stored.map.cells.len(),
        learned.holes_filled,
        learned.pieces_dropped,
        grid.width,
        grid.height,
        grid.resolution
    );
    super::verbosity::done(&out, None);
    Ok(())
}

/// Writes `plan.geojson`, `plan.png` and the occupancy grids under `prefix`: the first of
/// `grids` as `map.pgm` and `map.yaml`, the others as `map-level+N.pgm` and `.yaml`.
pub fn write_plan_files(
    folder: &RunFolder,
    prefix: &str,
    learned: &LearnedPlan,
    grids: &[(i32, OccupancyGrid)],
    frame: &LocalFrame,
) -> Result<()> {
    let at = |name: &str| folder.path(&format!("{prefix}{name}"));
    write_floor_plan(&at("plan.geojson"), &learned.plan, frame)?;
    for (i, (level, grid)) in grids.iter().enumerate() {
        let name = if i == 0 {
            "map".to_string()
        } else {
            format!("map-level{level:+}")
        };
        write_ros_map(
            &at(&format!("{name}.pgm")),
            &at(&format!("{name}.yaml")),
            grid,
        )?;
    }
    let picture = PlanPicture {
        plan: &learned.plan,
        title: Some(format!("learned plan, {:.0} m2", learned.area_m2)),
        paths: vec![],
        points: vec![],
        cells: vec![],
        markers: vec![],
        north_up: false,
        colour_bar: None,
    };
    write_plan_png(&at("plan.png"), &[picture], &PlanPictureConfig::default())?;
    Ok(())
}
