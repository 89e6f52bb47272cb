//! `footslam simulate`: a building, a walk through it and its step trace: the single-floor
//! office of the FootSLAM experiments, or the multi-floor tower for known-map tracking.

use super::common::{output_dir, parse_origin, path_length, read_config, write_truth_png};
use anyhow::Result;
use footslam::dataset::floor_plan_geojson::write_floor_plan;
use footslam::dataset::radio_truth_csv::{write_access_points, write_radio_field};
use footslam::dataset::steps_csv::write_steps;
use footslam::dataset::truth_csv::write_truth;
use footslam::dataset::write_wifi;
use footslam::export::RunFolder;
use footslam::export::plan_png::{PlanPath, PlanPicture, PlanPictureConfig, write_plan_png};
use footslam::geometry::LocalFrame;
use footslam::map::{FloorTopology, TopologyConfig};
use footslam::sim::{
    SimConfig, StepNoiseConfig, TourKind, TowerSimConfig, TruePose, expected_field, floor_changes,
    floor_resolved_at, simulate, simulate_tower,
};

/// Spacing of the expected-RSSI grid written to `wifi_field.csv`, metres.
const FIELD_SPACING: f64 = 1.0;
use serde::Serialize;
use std::path::PathBuf;

/// Which building to simulate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Building {
    /// One office floor: a corridor loop with rooms (the FootSLAM walks).
    Office,
    /// A multi-floor building with two stairwells of treads (known-map tracking).
    Tower,
    /// The office in a yard with a front door: outdoor–indoor–outdoor walks with GPS fixes
    /// outdoors, and the building's rough outline.
    Campus,
}

/// `--tour survey` without `--minutes` (or a config file) walks the whole tour, up to this
/// long.
const SURVEY_MINUTES_CAP: f64 = 600.0;

/// Which tour the tower's walker takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Tour {
    /// Room after random room from a random start.
    Random,
    /// A radio survey: every room swept lane by lane, both stairwells between every pair of
    /// floors (ends where the tour ends — about 23 minutes on the default building — or
    /// after `--minutes` when given).
    Survey,
}

/// Arguments of `footslam simulate`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The building.
    #[arg(long, value_enum, default_value = "office")]
    building: Building,
    /// Tower: number of floors (overrides the config file).
    #[arg(long)]
    floors: Option<usize>,
    /// Tower: every floor with the same layout (overrides the config file).
    #[arg(long)]
    identical_floors: bool,
    /// Tower: length of the walk in minutes (overrides the config file).
    #[arg(long)]
    minutes: Option<f64>,
    /// Tower: the kind of tour (overrides the config file; default random).
    #[arg(long, value_enum)]
    tour: Option<Tour>,
    /// Random seed (overrides the config file).
    #[arg(long)]
    pub(super) seed: Option<u64>,
    /// Office, campus: laps of the corridor loop (overrides the config file).
    #[arg(long)]
    pub(super) laps: Option<usize>,
    /// Campus: number of walks of the building, written to walk-1/ … walk-N/ when more
    /// than one (overrides the config file).
    #[arg(long)]
    pub(super) walks: Option<usize>,
    /// Campus: the walks end indoors after the tour, so GPS sees only the way in
    /// (overrides the config file's `walk_out`).
    #[arg(long)]
    pub(super) entrance_only: bool,
    /// Campus: the steps carry a compass's absolute `heading` (overrides the config file's
    /// `compass.enabled`).
    #[arg(long)]
    pub(super) compass: bool,
    /// Step-sensor errors: `foot` (a foot-mounted IMU, the default) or `phone` (a hand-held
    /// phone's PDR; on the campus also its compass), both measured on real recordings
    /// (docs/error-models.md). Overrides the config file's `noise` (and `compass`).
    #[arg(long, value_enum)]
    pub(super) sensor: Option<Sensor>,
    /// Simulation configuration (TOML, or JSON such as a previous run's config.json).
    #[arg(long)]
    pub(super) config: Option<PathBuf>,
    /// WGS84 origin of the local frame for the floor plan GeoJSON, `LAT,LON` (default 0,0).
    #[arg(long, value_parser = parse_origin, allow_hyphen_values = true)]
    pub(super) origin: Option<LocalFrame>,
    /// Output folder (default: a new folder under `outputs/`).
    #[arg(long)]
    pub(super) out: Option<PathBuf>,
}

/// Step-sensor error presets of `--sensor`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(super) enum Sensor {
    /// A foot-mounted IMU's strides.
    Foot,
    /// A hand-held phone's steps.
    Phone,
}

impl Sensor {
    /// The preset's step errors.
    pub(super) fn noise(self) -> StepNoiseConfig {
        match self {
            Self::Foot => StepNoiseConfig::foot(),
            Self::Phone => StepNoiseConfig::phone(),
        }
    }
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
    match args.building {
        Building::Office => run_office(args),
        Building::Tower => run_tower(args),
        Building::Campus => super::simulate_campus::run(args),
    }
}

fn run_tower(args: Args) -> Result<()> {
    let mut config: TowerSimConfig = match &args.config {
        Some(p) => read_config(p)?,
        None => TowerSimConfig::default(),
    };
    if let Some(sensor) = args.sensor {
        config.noise = sensor.noise();
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
    let origin = args.origin.unwrap_or_default();
    let sim = simulate_tower(&config)?;
    let folder = RunFolder::create(&output_dir(args.out, "simulate"))?;
    write_floor_plan(&folder.path("floor.geojson"), &sim.plan, &origin)?;
    write_steps(&folder.path("steps.csv"), &sim.steps)?;
    write_truth(&folder.path("truth.csv"), &sim.truth)?;
    write_wifi(&folder.path("wifi.csv"), &sim.wifi)?;
    let aps = sim.radio.access_points();
    write_access_points(&folder.path("wifi_aps.csv"), aps)?;
    let topology = FloorTopology::build(&sim.plan, &TopologyConfig::default())?;
    let field = expected_field(&sim.radio, &topology, FIELD_SPACING);
    write_radio_field(&folder.path("wifi_field.csv"), aps, &field)?;
    let truth: Vec<(f64, f64, i32)> = std::iter::once(&sim.start)
        .chain(&sim.truth.poses)
        .map(|p| (p.x, p.y, p.level))
        .collect();
    let picture = PlanPicture {
        plan: &sim.plan,
        title: Some(format!("true walk: {} steps", sim.truth.len())),
        paths: vec![PlanPath {
            points: &truth,
            colour: [33, 102, 172],
            label: "truth",
        }],
        points: Vec::new(),
        cells: Vec::new(),
        markers: Vec::new(),
        colour_bar: None,
    };
    write_plan_png(
        &folder.path("truth.png"),
        &[picture],
        &PlanPictureConfig::default(),
    )?;
    folder.write_json("config.json", &config)?;
    let levels = (0, config.building.floors as i32 - 1);
    let summary = TowerSummary {
        steps: sim.steps.len(),
        duration_s: sim.truth.poses.last().map_or(0.0, |p| p.t),
        path_length_m: path_length(truth.iter().map(|p| (p.0, p.1))),
        floor_polygons: sim.plan.polygons.len(),
        floors: config.building.floors,
        identical_floors: config.building.identical_floors,
        start: sim.start,
        floor_changes: floor_changes(&sim.start, &sim.truth),
        floor_resolved_at: floor_resolved_at(&sim.start, &sim.truth, levels),
        access_points: aps.len(),
        wifi_scans: sim.wifi.len(),
        seed: config.seed,
        origin,
    };
    folder.write_json("summary.json", &summary)?;
    let out = folder.commit()?;
    outln!(
        "simulated {} steps ({:.0} m, {:.0} s) through {} floors, {} changes of floor, {} WiFi scans of {} access points",
        summary.steps,
        summary.path_length_m,
        summary.duration_s,
        summary.floors,
        summary.floor_changes.len(),
        summary.wifi_scans,
        summary.access_points
    );
    outln!("outputs: {}", out.display());
    Ok(())
}

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
    let origin = args.origin.unwrap_or_default();
    let sim = simulate(&config)?;
    let folder = RunFolder::create(&output_dir(args.out, "simulate"))?;
    write_floor_plan(&folder.path("floor.geojson"), &sim.plan, &origin)?;
    write_steps(&folder.path("steps.csv"), &sim.steps)?;
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
