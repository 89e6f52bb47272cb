//! `footslam learn`: FootSLAM on one walk or a batch of walks, optionally anchored to the
//! world by GPS fixes, a rough building outline and a map learned on earlier walks.

use super::common::{
    Progress, bundled, output_dir, parse_origin, path_length, peak_memory_bytes, read_config,
    require_file, walk_prefix,
};
use super::learn_inputs::{Walk, WalkArgs, check_same_grid, read_walks};
use super::learn_radio::{RadioSummary, learn_radio_map};
use anyhow::Result;
use footslam::filter::gps_start::heading_from_fixes;
use footslam::filter::{Anchors, FootSlam, FootSlamConfig, FootSlamEstimate, StartPose};
use footslam::geometry::Hex;
use footslam::geometry::{HexGrid, LocalFrame};
use footslam::io::RunFolder;
use footslam::io::floor_plan_geojson::write_floor_plan;
use footslam::io::map_geojson::{read_stored_map, write_map_geojson, write_walks_map_geojson};
use footslam::io::track_geojson::write_track_geojson;
use footslam::io::{TimedPoint, TrackPoint, parse_utc_time, read_outline, write_trajectory};
use footslam::map::{
    CellConfig, EdgePrior, HexMapSnapshot, PlanConfig, merge_maps, register_maps, shift_map,
    walkable_plan,
};
use footslam::model::{GpsObservation, HeadingLikelihood, find_levels};
use footslam::render::map_png::{MapPicture, PictureConfig, write_map_png};
use rayon::prelude::*;
use serde::Serialize;
use std::path::PathBuf;
use std::sync::Mutex;
use std::time::Instant;

/// The bundled sample walk, used when `--steps` is not given.
const DEFAULT_STEPS: &str = "datasets/office/steps.csv";
/// The widest shift searched when registering a walk's map onto a prior map, metres.
const MAX_REGISTRATION: f64 = 25.0;
/// Step headings that set a walk's start heading (the most probable under the heading
/// model, so disturbed ones among them do not pull it).
const START_HEADING_READINGS: usize = 10;

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

#[derive(Debug, Serialize)]
struct Summary {
    steps_file: String,
    gps_file: Option<String>,
    /// Steps of the trace that carry an absolute heading.
    steps_with_heading: usize,
    /// Steps whose absolute heading weighted the particles.
    headings_used: usize,
    particles: usize,
    steps: usize,
    seed: u64,
    filter_runtime_s: f64,
    particle_steps_per_s: f64,
    final_effective_sample_size: f64,
    min_effective_sample_size: f64,
    resamplings: usize,
    best_particle: usize,
    best_particle_weight: f64,
    best_path_log_likelihood: f64,
    hexagons: usize,
    /// Floors found from the steps' height changes (1 for a walk on one floor).
    levels: usize,
    map_area_m2: f64,
    path_length_m: f64,
    gps_fixes: usize,
    gps_fixes_used: usize,
    /// How far path and map were moved towards the prior map's frame, metres.
    prior_offset_m: (f64, f64),
    /// Where the walk's orientation came from and how well it is known.
    heading: HeadingSummary,
    /// Walkable area of `plan.geojson`, m² (`None`: the map had too little to make a plan
    /// of, and no file was written).
    walkable_plan_m2: Option<f64>,
}

/// Where a walk's start heading came from and how uncertain the map's orientation is.
#[derive(Debug, Clone, Copy, Serialize)]
struct HeadingSummary {
    /// `gps fixes` (the first fixes' track), `compass` (the steps' `heading` column),
    /// `config` (`start.heading` with `start_heading_sigma`), `assumed` (`start.heading`,
    /// exact: a map in the walk's own frame) or `unknown` (uniform over the circle).
    start_source: &'static str,
    /// The start heading, degrees counter-clockwise from east.
    start_deg: f64,
    /// Its spread before the walk, degrees (1σ; 0 when assumed exact).
    start_sigma_deg: f64,
    /// The spread of the particles' headings after the last step, degrees (1σ,
    /// [`FootSlam::heading_spread`]): the map's orientation as the whole walk pins it.
    final_sigma_deg: f64,
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

/// What every walk of a run shares.
struct Shared<'a> {
    config: &'a FootSlamConfig,
    frame: &'a LocalFrame,
    /// `α` with the outline and the `--prior-map` counts.
    prior: &'a EdgePrior,
    prior_map: Option<&'a HexMapSnapshot>,
    prior_walks: u32,
}

/// Learns the walks, each with seed `seed + i`: alone, then — for a batch in one frame —
/// `config.iterations` FeetSLAM passes in which each walk is learned again with the merged
/// map of the other walks' previous pass as prior pseudo-counts (weight `prior_weight`).
/// Each pass reads only the pass before, so the result does not depend on the order in
/// which walks finish or on the thread count. Returns the last pass and the passes run.
fn learn_batch(walks: &[Walk], shared: &Shared) -> Result<(Vec<WalkRun>, u32)> {
    let batch = walks.len() > 1;
    // Walks share a frame when each starts at a known place. (Walks placed by GPS alone
    // carry each its own GPS bias: they meet through `--prior-map`'s registration instead.)
    let one_frame = walks.iter().all(|w| w.start.is_some());
    let iterations = if batch && one_frame {
        shared.config.iterations
    } else {
        0
    };
    let bar = (batch && iterations > 0).then(|| {
        let passes = u64::from(iterations) + 1;
        Mutex::new(Progress::new(passes * walks.len() as u64, "learning walks"))
    });
    let pass = |priors: Option<&[EdgePrior]>| {
        walks
            .par_iter()
            .enumerate()
            .map(|(i, walk)| {
                let mut config = shared.config.clone();
                config.seed = config.seed.wrapping_add(i as u64);
                let prior = priors.map_or(shared.prior, |p| &p[i]);
                let run = learn_walk(walk, config, shared, prior, !batch);
                if let Some(bar) = &bar
                    && let Ok(mut bar) = bar.lock()
                {
                    bar.inc();
                }
                run
            })
            .collect::<Result<Vec<_>>>()
    };
    let mut runs = pass(None)?;
    for _ in 0..iterations {
        let priors = (0..runs.len())
            .map(|i| {
                let others: Vec<_> = runs
                    .iter()
                    .enumerate()
                    .filter(|&(j, _)| j != i)
                    .map(|(_, r)| (&r.estimate.map, 1.0))
                    .collect();
                let mut prior = shared.prior.clone();
                prior.add_counts(&merge_maps(&others)?, shared.config.prior_weight);
                Ok(prior)
            })
            .collect::<Result<Vec<_>>>()?;
        runs = pass(Some(&priors))?;
    }
    if let Some(bar) = bar
        && let Ok(bar) = bar.into_inner()
    {
        bar.finish();
    }
    Ok((runs, iterations))
}

/// The result of learning one walk.
struct WalkRun {
    config: FootSlamConfig,
    start_source: &'static str,
    filter: FootSlam,
    estimate: FootSlamEstimate,
    runtime_s: f64,
}

/// Learns one walk: with GPS it starts at the first fix (spread by its accuracy), heading
/// from the first fixes ([`heading_from_fixes`]) or, when they do not tell, unknown
/// (uniform) — unless the configuration gives a heading spread. Steps with absolute
/// headings set the start heading instead (the heading before the first step that best
/// explains the first readings, [`HeadingLikelihood::start_heading`]), so the learned map
/// keeps its orientation (x east, y north).
fn learn_walk(
    walk: &Walk,
    mut config: FootSlamConfig,
    shared: &Shared,
    prior: &EdgePrior,
    progress: bool,
) -> Result<WalkRun> {
    let (frame, prior_map, prior_walks) = (shared.frame, shared.prior_map, shared.prior_walks);
    let gps: Vec<GpsObservation> = walk
        .fixes
        .iter()
        .map(|f| GpsObservation::from_fix(f, frame))
        .collect();
    let mut heading_given = config.start_heading_sigma != 0.0;
    let mut start_source = match config.start_heading_sigma {
        s if s >= std::f64::consts::PI => "unknown",
        s if s != 0.0 => "config",
        _ => "assumed",
    };
    // A given start (`--start`, a manifest's) places the walk; its heading, when given,
    // is known; without one it is unknown unless GPS fixes or step headings tell.
    if let Some(start) = walk.start {
        config.start.x = start.x;
        config.start.y = start.y;
        if let Some(level) = start.level {
            config.start_level = level;
        }
        if let Some(heading) = start.heading {
            config.start.heading = heading;
            heading_given = true;
            start_source = "given";
        } else if !heading_given {
            config.start_heading_sigma = std::f64::consts::PI;
            start_source = "unknown";
        }
    }
    if let Some(first) = gps.first() {
        if walk.start.is_none() {
            config.start.x = first.x;
            config.start.y = first.y;
            config.start_position_sigma = config.start_position_sigma.max(first.sigma);
        }
        if !heading_given {
            match heading_from_fixes(&gps, walk.trace.steps()) {
                Some((heading, sigma)) => {
                    config.start.heading = heading;
                    config.start_heading_sigma = sigma;
                    start_source = "gps fixes";
                }
                None => {
                    config.start_heading_sigma = std::f64::consts::PI;
                    start_source = "unknown";
                }
            }
        }
    }
    let compass = HeadingLikelihood::new(config.heading);
    if !heading_given
        && compass.enabled()
        && let Some((heading, sigma)) =
            compass.start_heading(walk.trace.steps(), START_HEADING_READINGS)
    {
        config.start.heading = heading;
        config.start_heading_sigma = sigma;
        start_source = "compass";
    }
    let started = Instant::now();
    // The walk's floors from its height changes, known before the first step so that a
    // stair climbed the first time already splits at half height.
    let levels = find_levels(walk.trace.steps(), config.levels, config.start_level)?;
    // With GPS and a prior map: first learn the walk alone, in its own GPS frame, and
    // register its map onto the prior to find where the two frames meet.
    let mut prior_offset = Hex::ZERO;
    if let (Some(map), false) = (prior_map, gps.is_empty()) {
        let alone = Anchors {
            gps: gps.clone(),
            levels: levels.clone(),
            ..Default::default()
        };
        let mut first = FootSlam::with_anchors(config.clone(), alone)?;
        for step in walk.trace.steps() {
            first.update(step);
        }
        let n = f64::from(prior_walks.max(1));
        let reach = (3.0 * config.gps.bias_sigma * (1.0 + 1.0 / n).sqrt()).min(MAX_REGISTRATION);
        prior_offset = register_maps(&first.estimate().map, map, reach).0;
    }
    let anchors = Anchors {
        gps,
        prior: Some(prior.clone()),
        prior_walks,
        prior_offset,
        levels,
    };
    let mut filter = FootSlam::with_anchors(config.clone(), anchors)?;
    let mut bar = progress.then(|| Progress::new(walk.trace.len() as u64, "learning"));
    for step in walk.trace.steps() {
        filter.update(step);
        if let Some(b) = bar.as_mut() {
            b.inc();
        }
    }
    if let Some(b) = bar {
        b.finish();
    }
    let runtime_s = started.elapsed().as_secs_f64();
    let estimate = filter.estimate();
    Ok(WalkRun {
        config,
        start_source,
        filter,
        estimate,
        runtime_s,
    })
}

/// Writes one walk's outputs under `prefix` and returns its summary.
fn write_walk(
    folder: &RunFolder,
    prefix: &str,
    walk: &Walk,
    run: &WalkRun,
    frame: &LocalFrame,
) -> Result<Summary> {
    let (config, estimate, filter) = (&run.config, &run.estimate, &run.filter);
    let at = |name: &str| folder.path(&format!("{prefix}{name}"));
    // Built one at a time from the trace and the path (a long walk's per-step outputs are
    // the largest things a run holds).
    let steps_and_path = || walk.trace.steps().iter().zip(&estimate.path);
    write_trajectory(
        &at("track.csv"),
        steps_and_path().map(|(s, p)| TimedPoint {
            t: s.t,
            x: p.x,
            y: p.y,
        }),
    )?;
    let points: Vec<TrackPoint> = steps_and_path()
        .zip(&estimate.levels)
        .map(|((s, p), &level)| TrackPoint {
            t: s.t,
            x: p.x,
            y: p.y,
            z: estimate.map.level_height(level),
            level,
        })
        .collect();
    write_track_geojson(&at("track.geojson"), &points, frame)?;
    drop(points);
    write_map_geojson(&at("map.geojson"), &estimate.map, frame)?;
    let walkable_plan_m2 = write_learned_plan(&at("plan.geojson"), &estimate.map, frame)?;
    let path: Vec<(f64, f64)> = estimate.path.iter().map(|p| (p.x, p.y)).collect();
    // One picture per floor: `map.png` the first (level 0), `map-level+N.png` the others.
    let mut levels = estimate.map.cell_levels();
    if !levels.contains(&0) {
        levels.insert(0, 0);
    }
    for level in levels {
        let on_level = HexMapSnapshot {
            cells: estimate
                .map
                .cells
                .iter()
                .filter(|c| c.level == level)
                .cloned()
                .collect(),
            levels: Vec::new(),
            ..estimate.map
        };
        // The path on this floor, broken where the walk left it.
        let (mut walked, mut breaks) = (Vec::new(), Vec::new());
        let mut previous = None;
        for (i, (p, &l)) in path.iter().zip(&estimate.levels).enumerate() {
            if l == level {
                if previous.is_some_and(|j| j + 1 != i) {
                    breaks.push(walked.len());
                }
                walked.push(*p);
                previous = Some(i);
            }
        }
        let picture = MapPicture {
            map: &on_level,
            path: &walked,
            path_breaks: &breaks,
            truth: None,
            plan: None,
        };
        let name = match level {
            0 => "map.png".to_string(),
            l => format!("map-level{l:+}.png"),
        };
        write_map_png(&at(&name), &picture, &PictureConfig::default())?;
    }
    if !prefix.is_empty() {
        folder.write_json(&format!("{prefix}config.json"), config)?;
    }
    let ess = filter.ess_history();
    let steps = walk.trace.len();
    Ok(Summary {
        steps_file: walk.steps_path.display().to_string(),
        gps_file: walk.gps_path.as_ref().map(|p| p.display().to_string()),
        steps_with_heading: walk.trace.with_heading(),
        headings_used: filter.headings_used(),
        particles: config.particles,
        steps,
        seed: config.seed,
        filter_runtime_s: run.runtime_s,
        particle_steps_per_s: (config.particles * steps) as f64 / run.runtime_s.max(1e-9),
        final_effective_sample_size: filter.effective_sample_size(),
        min_effective_sample_size: ess.iter().copied().fold(f64::INFINITY, f64::min),
        resamplings: filter.resamplings(),
        best_particle: estimate.index,
        best_particle_weight: estimate.weight,
        best_path_log_likelihood: estimate.path_log_likelihood,
        hexagons: estimate.map.cells.len(),
        levels: estimate.map.levels.len().max(1),
        map_area_m2: estimate.map.cells.len() as f64 * HexGrid::new(config.hex_radius).cell_area(),
        path_length_m: path_length(path.iter().copied()),
        gps_fixes: walk.fixes.len(),
        gps_fixes_used: filter.gps_fixes_used(),
        prior_offset_m: estimate.prior_offset,
        walkable_plan_m2,
        heading: HeadingSummary {
            start_source: run.start_source,
            start_deg: config.start.heading.to_degrees(),
            start_sigma_deg: config
                .start_heading_sigma
                .min(std::f64::consts::PI)
                .to_degrees(),
            final_sigma_deg: filter.heading_spread().to_degrees(),
        },
    })
}

/// Writes the walkable plan of `map` ([`walkable_plan`], default settings) to `path` and
/// returns its area; writes nothing and returns `None` when the map is too small to make
/// one (`footslam plan` gives the reason and the settings to change).
fn write_learned_plan(
    path: &std::path::Path,
    map: &HexMapSnapshot,
    frame: &LocalFrame,
) -> Result<Option<f64>> {
    match walkable_plan(map, &PlanConfig::default()) {
        Ok(learned) => {
            write_floor_plan(path, &learned.plan, frame)?;
            Ok(Some(learned.area_m2))
        }
        Err(_) => Ok(None),
    }
}
