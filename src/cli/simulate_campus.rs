//! `footslam simulate --building campus`: outdoor–indoor–outdoor walks of the office in its
//! yard, with GPS fixes outdoors and the building's rough outline.

use super::common::{output_dir, read_config, walk_prefix, write_truth_png};
use super::simulate_args::{Args, Sensor};
use anyhow::Result;
use footslam::geometry::path_length;
use footslam::io::RunFolder;
use footslam::io::floor_plan_geojson::write_floor_plan;
use footslam::io::steps_csv::write_steps;
use footslam::io::truth_csv::write_truth;
use footslam::io::{write_gps_csv, write_outline};
use footslam::sim::{CampusSimConfig, CampusWalk, CompassSimConfig, simulate_campus};
use serde::Serialize;

#[derive(Debug, Serialize)]
struct WalkSummary {
    folder: String,
    steps: usize,
    duration_s: f64,
    path_length_m: f64,
    gps_fixes: usize,
    gps_error_mean_m: f64,
    gps_error_rms_m: f64,
    gps_error_p95_m: f64,
}

#[derive(Debug, Serialize)]
struct Summary {
    walks: Vec<WalkSummary>,
    floor_polygons: usize,
    seed: u64,
    origin: footslam::geometry::LocalFrame,
}

/// Runs the campus simulation.
pub fn run(args: Args) -> Result<()> {
    let config = campus_config(&args)?;
    let origin = args.origin.unwrap_or_default();
    let sim = simulate_campus(&config, &origin)?;
    let folder = super::common::create_run_folder(&output_dir(args.out, "simulate"))?;
    write_floor_plan(&folder.path("floor.geojson"), &sim.plan, &origin)?;
    write_outline(&folder.path("outline.geojson"), &sim.outline, &origin)?;
    let several = sim.walks.len() > 1;
    let mut walks = Vec::new();
    for (i, walk) in sim.walks.iter().enumerate() {
        let prefix = walk_prefix(&folder, i, several)?;
        walks.push(write_walk(&folder, &prefix, walk, &sim.plan)?);
    }
    folder.write_json("config.json", &config)?;
    let summary = Summary {
        walks,
        floor_polygons: sim.plan.polygons.len(),
        seed: config.seed,
        origin,
    };
    folder.write_json("summary.json", &summary)?;
    let out = folder.commit()?;
    for w in &summary.walks {
        print_walk(w);
    }
    super::verbosity::done(&out, None);
    Ok(())
}

/// The campus's configuration: the config file's (or the default) with the flags applied.
fn campus_config(args: &Args) -> Result<CampusSimConfig> {
    let mut config: CampusSimConfig = match &args.config {
        Some(p) => read_config(p)?,
        None => CampusSimConfig::default(),
    };
    if let Some(s) = args.seed {
        config.seed = s;
    }
    if let Some(l) = args.laps {
        config.walk.laps = l;
    }
    if let Some(w) = args.walks {
        config.walks = w;
    }
    if args.entrance_only {
        config.walk_out = false;
    }
    if let Some(sensor) = args.sensor {
        config.noise = sensor.noise();
        if sensor == Sensor::Phone {
            config.compass = CompassSimConfig::phone();
        }
    }
    if args.compass {
        config.compass.enabled = true;
    }
    Ok(config)
}

/// One walk's line.
fn print_walk(w: &WalkSummary) {
    info!(
        "simulated {} steps ({:.0} m, {:.0} s) with {} GPS fixes outdoors (error mean {:.1} m, p95 {:.1} m){}",
        w.steps,
        w.path_length_m,
        w.duration_s,
        w.gps_fixes,
        w.gps_error_mean_m,
        w.gps_error_p95_m,
        if w.folder.is_empty() {
            String::new()
        } else {
            format!(" in {}", w.folder)
        }
    );
}

/// Writes one walk's steps, truth, GPS fixes and truth picture; returns its summary.
fn write_walk(
    folder: &RunFolder,
    prefix: &str,
    walk: &CampusWalk,
    plan: &footslam::map::FloorPlan,
) -> Result<WalkSummary> {
    let at = |name: &str| folder.path(&format!("{prefix}{name}"));
    write_steps(&at("steps.csv"), &walk.steps)?;
    write_truth(&at("truth.csv"), &walk.truth)?;
    write_gps_csv(&at("gps.csv"), &walk.gps.fixes)?;
    let truth: Vec<(f64, f64)> = std::iter::once((walk.start.x, walk.start.y))
        .chain(walk.truth.poses.iter().map(|p| (p.x, p.y)))
        .collect();
    write_truth_png(&at("truth.png"), plan, &truth)?;
    let errors = walk.gps.error_summary();
    Ok(WalkSummary {
        folder: prefix.trim_end_matches('/').to_string(),
        steps: walk.steps.len(),
        duration_s: walk.truth.poses.last().map_or(0.0, |p| p.t),
        path_length_m: path_length(truth.iter().copied()),
        gps_fixes: walk.gps.fixes.len(),
        gps_error_mean_m: errors.mean,
        gps_error_rms_m: errors.rms,
        gps_error_p95_m: errors.p95,
    })
}
