//! `footslam learn`: FootSLAM on a step trace.

use super::common::{
    Progress, bundled, output_dir, parse_origin, peak_memory_bytes, read_config, require_file,
};
use anyhow::{Context, Result};
use footslam::dataset::{TimedPoint, read_steps, write_trajectory};
use footslam::export::RunFolder;
use footslam::export::map_geojson::write_map_geojson;
use footslam::export::map_png::{MapPicture, PictureConfig, write_map_png};
use footslam::filter::{FootSlam, FootSlamConfig};
use footslam::geometry::LocalFrame;
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;

/// The bundled sample walk, used when `--steps` is not given.
const DEFAULT_STEPS: &str = "datasets/office/steps.csv";

/// Arguments of `footslam learn`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Step trace CSV (`t,length,dheading[,dz][,heading]`). Default: the bundled sample walk.
    #[arg(long)]
    steps: Option<PathBuf>,
    /// Number of particles (overrides the config file).
    #[arg(long)]
    particles: Option<usize>,
    /// Random seed (overrides the config file).
    #[arg(long)]
    seed: Option<u64>,
    /// Hexagon circumradius in metres (overrides the config file; default 0.5).
    #[arg(long)]
    hex_radius: Option<f64>,
    /// WGS84 origin of the local frame, `LAT,LON` in degrees (default 0,0).
    #[arg(long, value_parser = parse_origin, allow_hyphen_values = true)]
    origin: Option<LocalFrame>,
    /// FootSLAM configuration (TOML, or JSON such as a previous run's config.json).
    #[arg(long)]
    config: Option<PathBuf>,
    /// Output folder (default: a new folder under `outputs/`).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Worker threads (default: all cores). Results do not depend on it.
    #[arg(long)]
    threads: Option<usize>,
}

#[derive(Debug, Serialize)]
struct Summary {
    steps_file: String,
    particles: usize,
    steps: usize,
    seed: u64,
    threads: usize,
    runtime_s: f64,
    filter_runtime_s: f64,
    particle_steps_per_s: f64,
    final_effective_sample_size: f64,
    min_effective_sample_size: f64,
    resamplings: usize,
    best_particle: usize,
    best_particle_weight: f64,
    best_path_log_likelihood: f64,
    hexagons: usize,
    map_area_m2: f64,
    path_length_m: f64,
    peak_memory_bytes: Option<u64>,
    origin: LocalFrame,
    version: &'static str,
}

/// Runs `footslam learn`.
pub fn run(args: Args) -> Result<()> {
    let started = Instant::now();
    let mut config: FootSlamConfig = match &args.config {
        Some(p) => read_config(p)?,
        None => FootSlamConfig::default(),
    };
    if let Some(n) = args.particles {
        config.particles = n;
    }
    if let Some(s) = args.seed {
        config.seed = s;
    }
    if let Some(r) = args.hex_radius {
        config.hex_radius = r;
    }
    config.validate()?;
    let origin = args.origin.unwrap_or_default();
    let steps_path = args.steps.clone().unwrap_or_else(|| bundled(DEFAULT_STEPS));
    require_file(&steps_path, "step trace")?;
    let trace = read_steps(&steps_path)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .context("cannot start worker threads")?;
    let threads = pool.current_num_threads();

    let filter_started = Instant::now();
    let filter = pool.install(|| -> Result<FootSlam> {
        let mut filter = FootSlam::new(config.clone())?;
        let mut progress = Progress::new(trace.len() as u64, "learning");
        for step in trace.steps() {
            filter.update(step);
            progress.inc();
        }
        progress.finish();
        Ok(filter)
    })?;
    let filter_runtime = filter_started.elapsed().as_secs_f64();
    let estimate = filter.estimate();

    let out = output_dir(args.out, "learn");
    let folder = RunFolder::create(&out)?;
    let track: Vec<TimedPoint> = trace
        .steps()
        .iter()
        .zip(&estimate.path)
        .map(|(s, p)| TimedPoint {
            t: s.t,
            x: p.x,
            y: p.y,
        })
        .collect();
    write_trajectory(&folder.path("track.csv"), &track)?;
    write_map_geojson(&folder.path("map.geojson"), &estimate.map, &origin)?;
    let path: Vec<(f64, f64)> = track.iter().map(|p| (p.x, p.y)).collect();
    let picture = MapPicture {
        map: &estimate.map,
        path: &path,
        truth: None,
        plan: None,
    };
    write_map_png(&folder.path("map.png"), &picture, &PictureConfig::default())?;
    folder.write_json("config.json", &config)?;

    let ess = filter.ess_history();
    let summary = Summary {
        steps_file: steps_path.display().to_string(),
        particles: config.particles,
        steps: trace.len(),
        seed: config.seed,
        threads,
        runtime_s: started.elapsed().as_secs_f64(),
        filter_runtime_s: filter_runtime,
        particle_steps_per_s: (config.particles * trace.len()) as f64 / filter_runtime.max(1e-9),
        final_effective_sample_size: filter.effective_sample_size(),
        min_effective_sample_size: ess.iter().copied().fold(f64::INFINITY, f64::min),
        resamplings: filter.resamplings(),
        best_particle: estimate.index,
        best_particle_weight: estimate.weight,
        best_path_log_likelihood: estimate.path_log_likelihood,
        hexagons: estimate.map.cells.len(),
        map_area_m2: estimate.map.cells.len() as f64
            * footslam::geometry::HexGrid::new(config.hex_radius).cell_area(),
        path_length_m: path
            .windows(2)
            .map(|w| (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1))
            .sum(),
        peak_memory_bytes: peak_memory_bytes(),
        origin,
        version: env!("CARGO_PKG_VERSION"),
    };
    folder.write_json("summary.json", &summary)?;
    let out = folder.commit()?;
    {
        outln!(
            "learned {} hexagons from {} steps with {} particles in {:.2} s ({:.2e} particle-steps/s); final ESS {:.0}",
            summary.hexagons,
            summary.steps,
            summary.particles,
            summary.filter_runtime_s,
            summary.particle_steps_per_s,
            summary.final_effective_sample_size
        );
        outln!("outputs: {}", out.display());
    }
    Ok(())
}
