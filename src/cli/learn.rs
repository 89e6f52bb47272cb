//! `footslam learn`: FootSLAM on one walk or a batch of walks, optionally anchored to the
//! world by GPS fixes, a rough building outline and a map learned on earlier walks.
//!
//! [`run`] reads the walks and the anchors ([`super::learn_inputs`]), learns the walks
//! ([`super::learn_walks`]), writes each walk's outputs ([`super::learn_outputs`]), the merged
//! maps and the radio map of their WiFi logs ([`super::learn_radio`]), and the run's summary.

use super::common::{
    bundled, output_dir, parse_origin, peak_memory_bytes, read_config, require_file, walk_prefix,
};
use super::learn_inputs::{WalkArgs, check_same_grid, read_walks};
use super::learn_outputs::{Summary, write_learned_plan, write_walk};
use super::learn_radio::{RadioSummary, learn_radio_map};
use super::learn_walks::{Shared, learn_batch};
use anyhow::Result;
use footslam::filter::{FootSlamConfig, StartPose};
use footslam::geometry::{HexGrid, LocalFrame};
use footslam::io::RunFolder;
use footslam::io::map_geojson::{read_stored_map, write_walks_map_geojson};
use footslam::io::{parse_utc_time, read_outline};
use footslam::map::{CellConfig, EdgePrior, merge_maps, shift_map};
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;

/// The bundled sample walk, used when `--steps` is not given.
const DEFAULT_STEPS: &str = "datasets/office/steps.csv";

/// Arguments of `footslam learn`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Step trace CSV (`t,length,dheading[,dz][,heading]`; an absolute `heading` column sets
    /// the start heading and weights the particles, see `--ignore-heading`), or a folder holding `steps.csv`
    /// or sub-folders that do (one walk each, with `gps.csv` or `gps.gpx` beside it when
    /// there is one). Repeat for a batch of walks, learned in parallel (walk i has seed
    /// `seed + i`). Default: the bundled sample walk.
    #[arg(long)]
    steps: Vec<PathBuf>,
    /// GPS fixes: CSV `t,lat,lon[,accuracy]` on the steps' clock, or GPX 1.1 (by the `.gpx`
    /// extension). Repeat once per walk, in the order of the walks.
    #[arg(long)]
    gps: Vec<PathBuf>,
    /// UTC time of the steps' `t = 0` for GPX files (RFC 3339, e.g. 2024-05-01T10:00:00Z,
    /// or Unix seconds). Default: the steps' `t` are Unix seconds.
    #[arg(long, value_parser = parse_utc_time)]
    gps_t0: Option<f64>,
    /// WiFi log CSV (`t,bssid,rssi[,ssid,freq]`) of a walk, on the steps' clock: its scans
    /// are placed on the learned path and make a radio map on the plan learned from the
    /// run's map (`radiomap.geojson`, `radiomap.csv`, heatmaps and ε, as `footslam survey`
    /// writes them). Repeat once per walk, in the order of the walks; a walk folder's
    /// `wifi.csv` is found without it.
    #[arg(long)]
    wifi: Vec<PathBuf>,
    /// Radio-map cell granularity with WiFi, metres (default 3).
    #[arg(long)]
    cell: Option<f64>,
    /// Building outline (GeoJSON Polygon, Feature or FeatureCollection of one), known to a
    /// few metres: crossing it becomes improbable (low Dirichlet prior `outline_alpha`).
    #[arg(long)]
    outline: Option<PathBuf>,
    /// A map learned earlier (map.geojson, a `footslam merge` of several, or the
    /// merged.geojson of a walk learned with a prior map): its counts become prior
    /// pseudo-counts. Its origin becomes the default origin. The run then also writes
    /// merged.geojson: the prior and this walk's map in this walk's frame (the next walk's
    /// prior; with GPS the frame averages the walks' GPS biases).
    #[arg(long)]
    prior_map: Option<PathBuf>,
    /// Weight of the prior map's counts (overrides the config file; default 1).
    #[arg(long)]
    prior_weight: Option<f64>,
    /// Number of particles (overrides the config file).
    #[arg(long)]
    particles: Option<usize>,
    /// Random seed (overrides the config file).
    #[arg(long)]
    seed: Option<u64>,
    /// Hexagon circumradius in metres (overrides the config file; default 0.5).
    #[arg(long)]
    hex_radius: Option<f64>,
    /// WGS84 origin of the local frame, `LAT,LON` in degrees. Default: the prior map's
    /// origin, else the first GPS fix, else 0,0.
    #[arg(long, value_parser = parse_origin, allow_hyphen_values = true)]
    origin: Option<LocalFrame>,
    /// FootSLAM configuration (TOML, or JSON such as a previous run's config.json).
    #[arg(long)]
    config: Option<PathBuf>,
    /// Output folder (default: a new folder under `outputs/`).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Worker threads (default: all cores; at most 4 per core). Results do not depend on it.
    #[arg(long)]
    threads: Option<usize>,
    /// The walk's known start, `X,Y[,HEADING[,LEVEL]]` (metres in the local frame, radians
    /// counter-clockwise from east, the floor level; `X,Y,,LEVEL` for a level without a
    /// heading). Without HEADING the start heading is unknown (the step headings set it
    /// where the trace has them). Repeat once per walk, in the order of the walks: walks
    /// with known starts are learned into one frame. A given start wins over the first GPS
    /// fix.
    #[arg(long, value_parser = super::track::parse_start, allow_hyphen_values = true)]
    start: Vec<StartPose>,
    /// Walk manifest CSV instead of `--steps`/`--gps`/`--wifi`/`--start`: a header naming
    /// `steps` and optionally `gps`, `wifi` and `start` (as `--start`, quoted), one walk a
    /// row, paths relative to the manifest.
    #[arg(long)]
    walks: Option<PathBuf>,
    /// Ignore the step traces' absolute `heading` column (same as `heading.enabled = false`
    /// in the config): the walk then starts at `start.heading` (default 0, east).
    #[arg(long)]
    ignore_heading: bool,
}

/// `summary.json`: one walk's figures at the top level, or a batch's under `walks`.
#[derive(Debug, Serialize)]
struct RunSummary {
    #[serde(flatten)]
    single: Option<Summary>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    walks: Vec<Summary>,
    runtime_s: f64,
    threads: usize,
    outline_edges: usize,
    prior_map_hexagons: usize,
    prior_map_walks: u32,
    /// FeetSLAM iterations run over the batch (`iterations` in the configuration; 0 for
    /// one walk, or for walks in frames of their own).
    iterations: u32,
    peak_memory_bytes: Option<u64>,
    origin: LocalFrame,
    /// The radio map made from the walks' WiFi logs (`--wifi`).
    #[serde(skip_serializing_if = "Option::is_none")]
    radio: Option<RadioSummary>,
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
    if let Some(w) = args.prior_weight {
        config.prior_weight = w;
    }
    if args.ignore_heading {
        config.heading.enabled = false;
    }
    config.validate()?;
    let walk_args = WalkArgs {
        steps: &args.steps,
        gps: &args.gps,
        wifi: &args.wifi,
        starts: &args.start,
        manifest: args.walks.as_deref(),
        gps_t0: args.gps_t0,
    };
    let walks = read_walks(&walk_args, &bundled(DEFAULT_STEPS))?;
    let cells = CellConfig {
        granularity: args.cell.unwrap_or(CellConfig::default().granularity),
        ..CellConfig::default()
    };
    cells.validate()?;
    let prior_map = match &args.prior_map {
        Some(p) => {
            require_file(p, "prior map")?;
            Some(read_stored_map(p)?)
        }
        None => None,
    };
    let first_fix = walks.iter().find_map(|w| w.fixes.first());
    let frame = args
        .origin
        .or(prior_map.as_ref().map(|m| m.frame))
        .or(first_fix.and_then(|f| LocalFrame::new(f.lat, f.lon)))
        .unwrap_or_default();

    let grid = HexGrid::new(config.hex_radius);
    let mut prior = EdgePrior::uniform(config.alpha);
    let mut outline_edges = 0;
    if let Some(path) = &args.outline {
        require_file(path, "outline")?;
        let outline = read_outline(path, &frame)?;
        outline_edges = prior.add_outline(&grid, &outline, config.outline_alpha);
    }
    let (mut prior_map_hexagons, mut prior_walks) = (0, 0);
    if let (Some(stored), Some(path)) = (&prior_map, &args.prior_map) {
        check_same_grid(
            path,
            stored.map.radius,
            &stored.frame,
            config.hex_radius,
            &frame,
        )?;
        prior.add_counts(&stored.map, config.prior_weight);
        prior_map_hexagons = stored.map.cells.len();
        prior_walks = stored.walks;
    }

    let pool = super::common::worker_pool(args.threads)?;
    let threads = pool.current_num_threads();
    let batch = walks.len() > 1;
    let stored = prior_map.as_ref().map(|m| &m.map);
    let shared = Shared {
        config: &config,
        frame: &frame,
        prior: &prior,
        prior_map: stored,
        prior_walks,
    };
    let (runs, iterations) = pool.install(|| learn_batch(&walks, &shared))?;

    let out = output_dir(args.out, "learn");
    let mut folder = RunFolder::create(&out)?;
    folder.protect(
        walks
            .iter()
            .flat_map(|w| {
                [
                    Some(&w.steps_path),
                    w.gps_path.as_ref(),
                    w.wifi_path.as_ref(),
                ]
            })
            .flatten()
            .chain(args.prior_map.iter())
            .chain(args.outline.iter())
            .chain(args.config.iter())
            .chain(args.walks.iter()),
    );
    let mut summaries = Vec::with_capacity(runs.len());
    for (i, (walk, run)) in walks.iter().zip(&runs).enumerate() {
        let prefix = walk_prefix(&folder, i, batch)?;
        summaries.push(write_walk(&folder, &prefix, walk, run, &frame)?);
        if let Some(stored) = &prior_map {
            // The prior and this walk, in this walk's frame: the next walk's prior.
            let prior = shift_map(&stored.map, run.estimate.prior_shift);
            let merged = merge_maps(&[(&prior, 1.0), (&run.estimate.map, 1.0)])?;
            let path = folder.path(&format!("{prefix}merged.geojson"));
            write_walks_map_geojson(&path, &merged, &frame, stored.walks + 1)?;
            let plan = folder.path(&format!("{prefix}merged_plan.geojson"));
            write_learned_plan(&plan, &merged, &frame)?;
        }
    }
    let batch_merged = if batch && prior_map.is_none() {
        let maps: Vec<_> = runs.iter().map(|r| (&r.estimate.map, 1.0)).collect();
        let walks = maps.len() as u32;
        let merged = merge_maps(&maps)?;
        write_walks_map_geojson(&folder.path("merged.geojson"), &merged, &frame, walks)?;
        write_learned_plan(&folder.path("merged_plan.geojson"), &merged, &frame)?;
        Some(merged)
    } else {
        None
    };
    // The radio map: every walk's scans on the plan of everything the run learned (the
    // batch's merged map, or the walks' maps with the prior moved into the first's frame).
    let radio = if walks.iter().any(|w| w.wifi_path.is_some()) {
        let run_map = match batch_merged {
            Some(merged) => merged,
            None => {
                let prior = prior_map
                    .as_ref()
                    .zip(runs.first())
                    .map(|(stored, first)| shift_map(&stored.map, first.estimate.prior_shift));
                let mut all: Vec<_> = runs.iter().map(|r| (&r.estimate.map, 1.0)).collect();
                all.extend(prior.as_ref().map(|p| (p, 1.0)));
                merge_maps(&all)?
            }
        };
        let estimates: Vec<_> = runs.iter().map(|r| &r.estimate).collect();
        Some(learn_radio_map(
            &folder, &walks, &estimates, &run_map, &cells, &frame,
        )?)
    } else {
        None
    };
    let (single, summaries) = if batch {
        (None, summaries)
    } else {
        (summaries.pop(), Vec::new())
    };
    let summary = RunSummary {
        single,
        walks: summaries,
        runtime_s: started.elapsed().as_secs_f64(),
        threads,
        outline_edges,
        prior_map_hexagons,
        prior_map_walks: prior_walks,
        iterations,
        peak_memory_bytes: peak_memory_bytes(),
        origin: frame,
        radio,
        version: env!("CARGO_PKG_VERSION"),
    };
    // One walk: the configuration it ran with (start from its fixes included); a batch: the
    // shared one (each walk's own is in its folder).
    match (batch, runs.first()) {
        (false, Some(run)) => folder.write_json("config.json", &run.config)?,
        _ => folder.write_json("config.json", &config)?,
    }
    folder.write_json("summary.json", &summary)?;
    let out = folder.commit()?;
    for (i, s) in summary.single.iter().chain(&summary.walks).enumerate() {
        let walk = if batch {
            format!("walk {}: ", i + 1)
        } else {
            String::new()
        };
        let gps = if s.gps_fixes > 0 {
            format!(" and {} GPS fixes", s.gps_fixes_used)
        } else {
            String::new()
        };
        outln!(
            "{walk}learned {} hexagons from {} steps{gps} with {} particles in {:.2} s ({:.2e} particle-steps/s); final ESS {:.0}",
            s.hexagons,
            s.steps,
            s.particles,
            s.filter_runtime_s,
            s.particle_steps_per_s,
            s.final_effective_sample_size
        );
    }
    outln!("outputs: {}", out.display());
    Ok(())
}
