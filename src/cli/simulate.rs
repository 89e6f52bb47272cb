//! `footslam simulate`: an office floor, a walk through it and its step trace.

use super::common::{output_dir, parse_origin, read_config};
use anyhow::Result;
use footslam::dataset::floor_plan_geojson::write_floor_plan;
use footslam::dataset::steps_csv::write_steps;
use footslam::dataset::truth_csv::write_truth;
use footslam::export::RunFolder;
use footslam::export::map_png::{MapPicture, PictureConfig, write_map_png};
use footslam::geometry::LocalFrame;
use footslam::map::HexMapSnapshot;
use footslam::sim::{SimConfig, simulate};
use serde::Serialize;
use std::path::PathBuf;

/// Arguments of `footslam simulate`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Random seed (overrides the config file).
    #[arg(long)]
    seed: Option<u64>,
    /// Laps of the corridor loop (overrides the config file).
    #[arg(long)]
    laps: Option<usize>,
    /// Simulation configuration (TOML, or JSON such as a previous run's config.json).
    #[arg(long)]
    config: Option<PathBuf>,
    /// WGS84 origin of the local frame for the floor plan GeoJSON, `LAT,LON` (default 0,0).
    #[arg(long, value_parser = parse_origin, allow_hyphen_values = true)]
    origin: Option<LocalFrame>,
    /// Output folder (default: a new folder under `outputs/`).
    #[arg(long)]
    out: Option<PathBuf>,
}

#[derive(Debug, Serialize)]
struct Summary {
    steps: usize,
    duration_s: f64,
    path_length_m: f64,
    floor_polygons: usize,
    seed: u64,
    origin: LocalFrame,
}

/// Runs `footslam simulate`.
pub fn run(args: Args) -> Result<()> {
    let mut config: SimConfig = match &args.config {
        Some(p) => read_config(p)?,
        None => SimConfig::default(),
    };
    if let Some(s) = args.seed {
        config.seed = s;
    }
    if let Some(l) = args.laps {
        config.walk.laps = l;
    }
    let origin = args.origin.unwrap_or_default();
    let sim = simulate(&config)?;
    let folder = RunFolder::create(&output_dir(args.out, "simulate"))?;
    write_floor_plan(&folder.path("floor.geojson"), &sim.plan, &origin)?;
    write_steps(&folder.path("steps.csv"), &sim.steps)?;
    write_truth(&folder.path("truth.csv"), &sim.truth)?;
    let truth: Vec<(f64, f64)> = sim.truth.poses.iter().map(|p| (p.x, p.y)).collect();
    let empty = HexMapSnapshot {
        radius: 0.5,
        alpha: 0.8,
        cells: Vec::new(),
    };
    let picture = MapPicture {
        map: &empty,
        path: &truth,
        truth: None,
        plan: Some(&sim.plan),
    };
    write_map_png(
        &folder.path("truth.png"),
        &picture,
        &PictureConfig::default(),
    )?;
    folder.write_json("config.json", &config)?;
    let summary = Summary {
        steps: sim.steps.len(),
        duration_s: sim.truth.poses.last().map_or(0.0, |p| p.t),
        path_length_m: sim.truth.length(),
        floor_polygons: sim.plan.polygons.len(),
        seed: config.seed,
        origin,
    };
    folder.write_json("summary.json", &summary)?;
    let out = folder.commit()?;
    {
        outln!(
            "simulated {} steps ({:.0} m, {:.0} s) through {} floor polygons",
            summary.steps,
            summary.path_length_m,
            summary.duration_s,
            summary.floor_polygons
        );
        outln!("outputs: {}", out.display());
    }
    Ok(())
}
