//! `footslam simulate`: a building, a walk through it and its step trace: the single-floor
//! office of the FootSLAM experiments, or the multi-floor tower for known-map tracking.

use super::common::{output_dir, read_config, write_truth_png};
use super::simulate_args::{Args, Building, Tour};
use anyhow::Result;
use footslam::geometry::LocalFrame;
use footslam::geometry::path_length;
use footslam::io::RunFolder;
use footslam::io::floor_plan_geojson::write_floor_plan;
use footslam::io::radio_truth_csv::{write_access_points, write_radio_field};
use footslam::io::steps_csv::write_steps_with_field;
use footslam::io::truth_csv::write_truth;
use footslam::io::write_wifi;
use footslam::render::plan_png::{PlanPath, PlanPicture, PlanPictureConfig, write_plan_png};
use footslam::sensor::TruePose;
use footslam::sim::{
    SimConfig, TourKind, TowerSimConfig, TowerSimulation, floor_changes, floor_resolved_at,
    simulate, simulate_tower,
};
use serde::Serialize;
use std::path::Path;

/// Spacing of the expected-RSSI grid written to `wifi_field.csv`, metres.
const FIELD_SPACING: f64 = 1.0;

/// `--tour survey` without `--minutes` (or a config file) walks the whole tour, up to this
/// long.
const SURVEY_MINUTES_CAP: f64 = 600.0;

#[derive(Debug, Serialize)]
struct Summary {
    steps: usize,
    duration_s: f64,
    path_length_m: f64,
    floor_polygons: usize,
    seed: u64,
    origin: LocalFrame,
}

#[derive(Debug, Serialize)]
struct TowerSummary {
    steps: usize,
    duration_s: f64,
    path_length_m: f64,
    floor_polygons: usize,
    floors: usize,
    identical_floors: bool,
    start: TruePose,
    floor_changes: Vec<usize>,
    floor_resolved_at: Option<usize>,
    access_points: usize,
    wifi_scans: usize,
    seed: u64,
    origin: LocalFrame,
}

/// Runs `footslam simulate`.
pub fn run(args: Args) -> Result<()> {
    args.check_flags_apply()?;
    match args.building {
        Building::Office => run_office(args),
        Building::Tower => run_tower(args),
        Building::Campus => super::simulate_campus::run(args),
    }
}

/// `simulate --building tower`.
fn run_tower(args: Args) -> Result<()> {
    let config = tower_config(&args)?;
    let origin = args.origin.unwrap_or_default();
    let sim = simulate_tower(&config)?;
    let folder = super::common::create_run_folder(&output_dir(args.out, "simulate"))?;
    let truth = write_tower_files(&folder, &sim, &origin)?;
    folder.write_json("config.json", &config)?;
    let summary = tower_summary(&config, &sim, &truth, origin);
    folder.write_json("summary.json", &summary)?;
    let out = folder.commit()?;
    info!(
        "simulated {} steps ({:.0} m, {:.0} s) through {} floors, {} changes of floor, {} WiFi scans of {} access points",
        summary.steps,
        summary.path_length_m,
        summary.duration_s,
        summary.floors,
        summary.floor_changes.len(),
        summary.wifi_scans,
        summary.access_points
    );
    super::verbosity::done(&out, None);
    Ok(())
}

/// The tower's configuration: the config file's (or the default) with the flags applied.
fn tower_config(args: &Args) -> Result<TowerSimConfig> {
    let mut config: TowerSimConfig = match &args.config {
        Some(p) => read_config(p)?,
        None => TowerSimConfig::default(),
    };
    if let Some(sensor) = args.sensor {
        config.noise = sensor.noise();
    }
    if args.magnetometer {
        config.field.enabled = true;
    }
    if let Some(s) = args.seed {
        config.seed = s;
    }
    if let Some(f) = args.floors {
        config.building.floors = f;
    }
    if args.identical_floors {
        config.building.identical_floors = true;
    }
    if let Some(m) = args.minutes {
        config.walk.minutes = m;
    }
    if let Some(t) = args.tour {
        config.walk.tour = match t {
            Tour::Random => TourKind::Random,
            Tour::Survey => TourKind::Survey,
        };
        if t == Tour::Survey && args.minutes.is_none() && args.config.is_none() {
            // The whole tour: a survey walk ends where it has covered the building (a
            // config file's `walk.minutes` is kept).
            config.walk.minutes = SURVEY_MINUTES_CAP;
        }
    }
    Ok(config)
}

/// Writes the tower's plan, steps, truth, WiFi scans, access points, expected RSSI field and
/// truth picture; returns the true path `(x, y, level)` from the start.
fn write_tower_files(
    folder: &RunFolder,
    sim: &TowerSimulation,
    origin: &LocalFrame,
) -> Result<Vec<(f64, f64, i32)>> {
    write_floor_plan(&folder.path("floor.geojson"), &sim.plan, origin)?;
    write_steps_with_field(&folder.path("steps.csv"), &sim.steps, sim.field.as_ref())?;
    write_truth(&folder.path("truth.csv"), &sim.truth)?;
    write_wifi(&folder.path("wifi.csv"), &sim.wifi)?;
    let aps = sim.radio.access_points();
    write_access_points(&folder.path("wifi_aps.csv"), aps)?;
    let field = sim.expected_field(FIELD_SPACING)?;
    write_radio_field(&folder.path("wifi_field.csv"), aps, &field)?;
    let truth = sim.true_points();
    write_tower_png(&folder.path("truth.png"), sim, &truth)?;
    Ok(truth)
}

/// `truth.png` of the tower: the true walk over every floor.
fn write_tower_png(path: &Path, sim: &TowerSimulation, truth: &[(f64, f64, i32)]) -> Result<()> {
    let picture = PlanPicture {
        plan: &sim.plan,
        title: Some(format!("true walk: {} steps", sim.truth.len())),
        paths: vec![PlanPath {
            points: truth,
            colour: [33, 102, 172],
            label: "true path",
        }],
        points: Vec::new(),
        cells: Vec::new(),
        markers: Vec::new(),
        north_up: true,
        colour_bar: None,
    };
    write_plan_png(path, &[picture], &PlanPictureConfig::default())?;
    Ok(())
}

/// The tower run's `summary.json`.
fn tower_summary(
    config: &TowerSimConfig,
    sim: &TowerSimulation,
    truth: &[(f64, f64, i32)],
    origin: LocalFrame,
) -> TowerSummary {
    let levels = (0, config.building.level_count() - 1);
    TowerSummary {
        steps: sim.steps.len(),
        duration_s: sim.truth.poses.last().map_or(0.0, |p| p.t),
        path_length_m: path_length(truth.iter().map(|p| (p.0, p.1))),
        floor_polygons: sim.plan.polygons.len(),
        floors: config.building.floors,
        identical_floors: config.building.identical_floors,
        start: sim.start,
        floor_changes: floor_changes(&sim.start, &sim.truth),
        floor_resolved_at: floor_resolved_at(&sim.start, &sim.truth, levels),
        access_points: sim.radio.access_points().len(),
        wifi_scans: sim.wifi.len(),
        seed: config.seed,
        origin,
    }
}

/// `simulate --building office`.
fn run_office(args: Args) -> Result<()> {
    let mut config: SimConfig = match &args.config {
        Some(p) => read_config(p)?,
        None => SimConfig::default(),
    };
    if let Some(sensor) = args.sensor {
        config.noise = sensor.noise();
    }
    if let Some(s) = args.seed {
        config.seed = s;
    }
    if let Some(l) = args.laps {
        config.walk.laps = l;
    }
    if args.magnetometer {
        config.field.enabled = true;
    }
    let origin = args.origin.unwrap_or_default();
    let sim = simulate(&config)?;
    let folder = super::common::create_run_folder(&output_dir(args.out, "simulate"))?;
    write_floor_plan(&folder.path("floor.geojson"), &sim.plan, &origin)?;
    write_steps_with_field(&folder.path("steps.csv"), &sim.steps, sim.field.as_ref())?;
    write_truth(&folder.path("truth.csv"), &sim.truth)?;
    let truth: Vec<(f64, f64)> = sim.truth.poses.iter().map(|p| (p.x, p.y)).collect();
    write_truth_png(&folder.path("truth.png"), &sim.plan, &truth)?;
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
        info!(
            "simulated {} steps ({:.0} m, {:.0} s) through {} floor polygons",
            summary.steps, summary.path_length_m, summary.duration_s, summary.floor_polygons
        );
        super::verbosity::done(&out, None);
    }
    Ok(())
}
