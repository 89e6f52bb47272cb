//! `footslam plan`: a learned map as a walkable floor plan (`plan.geojson`, the contract
//! `track` and `survey` read) and a ROS occupancy grid (`map.pgm` + `map.yaml`).

use super::common::{output_dir, read_config, require_file};
use anyhow::Result;
use footslam::geometry::LocalFrame;
use footslam::io::floor_plan_geojson::write_floor_plan;
use footslam::io::map_geojson::read_stored_map;
use footslam::io::{RunFolder, write_ros_map};
use footslam::map::{LearnedPlan, OccupancyGrid};
use footslam::pipeline::{Named, PlanOverrides, PlanRequest, PlanRunConfig, run_plan};
use footslam::render::plan_png::{PlanPicture, PlanPictureConfig, write_plan_png};
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

/// Runs `footslam plan`.
pub fn run(args: Args) -> Result<()> {
    let config: PlanRunConfig = match &args.config {
        Some(p) => read_config(p)?,
        None => PlanRunConfig::default(),
    };
    require_file(&args.map, "map")?;
    let request = PlanRequest {
        map: Named::new(read_stored_map(&args.map)?, args.map.display().to_string()),
        config,
        overrides: PlanOverrides {
            min_visits: args.min_visits,
            resolution: args.resolution,
        },
    };
    let job = run_plan(request)?;
    let (learned, grids) = (&job.planned.learned, &job.planned.grids);
    let mut folder = super::common::create_run_folder(&output_dir(args.out, "plan"))?;
    folder.protect(std::iter::once(&args.map).chain(args.config.iter()));
    write_plan_files(&folder, "", learned, grids, &job.frame)?;
    folder.write_json("config.json", &job.config)?;
    folder.write_json("summary.json", &job.report)?;
    let out = folder.commit()?;
    let r = &job.report;
    info!(
        "walkable plan of {:.0} m² in {} polygon(s) from {} of {} hexagons ({} holes filled, {} stray pieces dropped); occupancy grid {} × {} at {} m",
        r.walkable_area_m2,
        r.polygons,
        r.hexagons_used,
        r.map_hexagons,
        r.holes_filled,
        r.pieces_dropped,
        r.grid_width,
        r.grid_height,
        job.config.grid.resolution
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
