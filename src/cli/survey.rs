//! `footslam survey`: build a cell-based WiFi radio map from ordinary walks, tracking each
//! walker on the known plan and adding its scans where it was (Woodman & Harle 2009).

use super::common::{
    Progress, check_height_changes, output_dir, parse_origin, peak_memory_bytes, read_config,
    read_scans, require_file,
};
use super::radio_outputs::{held_out_quantiles, write_radio_map_files};
use anyhow::{Context, Result, bail};
use footslam::filter::{
    Assignments, StartPose, TrackStep, Tracker, TrackerConfig, calibrate_map, placed_steps,
    survey_assignments, survey_walk,
};
use footslam::io::RunFolder;
use footslam::io::floor_plan_geojson::read_floor_plan;
use footslam::io::radio_map_geojson::read_radio_map_geojson;
use footslam::io::{read_steps, read_walk_manifest};
use footslam::map::{CellConfig, CellMap, FloorTopology, RadioMap};
use footslam::sensor::WifiScan;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Instant;

/// Granularities of the coverage table (the paper's Table 1), metres.
const COVERAGE_GRANULARITIES: [f64; 5] = [1.0, 2.0, 3.0, 4.0, 5.0];

/// Arguments of `footslam survey`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Floor plan GeoJSON.
    #[arg(long)]
    plan: PathBuf,
    /// Step trace CSV of a walk; repeat with `--wifi` for several walks (paired in order).
    #[arg(long)]
    steps: Vec<PathBuf>,
    /// WiFi log CSV (`t,bssid,rssi[,ssid,freq]`) of the walk given by the `--steps` at the
    /// same position.
    #[arg(long)]
    wifi: Vec<PathBuf>,
    /// Manifest of walks: a CSV with columns `steps,wifi` (paths relative to the manifest)
    /// and optionally `start` — the walk's known start `X,Y[,HEADING[,LEVEL]]` as `--start`
    /// takes it, quoted since it holds commas (e.g. `"12.5,3,,1"`); empty = the start of
    /// `--start` or the config, else unknown — one walk a row; added to any
    /// `--steps`/`--wifi` pairs.
    #[arg(long)]
    walks: Option<PathBuf>,
    /// Every walk stays on its start floor: allows step traces without a `dz` column on a
    /// plan of several levels (otherwise an error).
    #[arg(long)]
    one_floor: bool,
    /// A radio map surveyed before on this plan at this granularity (`radiomap.geojson`),
    /// merged into the new one; repeat to merge several (with no walk: just merge them).
    #[arg(long)]
    merge: Vec<PathBuf>,
    /// Cell granularity, metres (default 3).
    #[arg(long)]
    cell: Option<f64>,
    /// Known start `X,Y[,HEADING[,LEVEL]]` of every walk (`X,Y,,LEVEL`: a level without a
    /// heading), unless the manifest gives the walk its own (default: unknown).
    #[arg(long, value_parser = super::track::parse_start, allow_hyphen_values = true)]
    start: Option<StartPose>,
    /// WGS84 origin `LAT,LON`; overrides the plan's `origin`.
    #[arg(long, value_parser = parse_origin, allow_hyphen_values = true)]
    origin: Option<footslam::geometry::LocalFrame>,
    /// Random seed (overrides the config file).
    #[arg(long)]
    seed: Option<u64>,
    /// Survey configuration (TOML or JSON with `tracker` and `cells`).
    #[arg(long)]
    config: Option<PathBuf>,
    /// Output folder (default: a new folder under `outputs/`).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Worker threads (default: all cores; at most 4 per core). Results do not depend on it.
    #[arg(long)]
    threads: Option<usize>,
}

/// The survey's configuration, written as `config.json`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SurveyConfig {
    /// The tracker of every walk (its seed is the first walk's; walk `k` uses seed + k).
    pub tracker: TrackerConfig,
    /// Rooms and cells.
    pub cells: CellConfig,
    /// Share of surveyed scans allowed outside their own cell's region when calibrating the
    /// map's `ε` (default 0.001; the paper's ε gave 0.00028 per step on its building).
    pub epsilon_miss: f64,
}

impl Default for SurveyConfig {
    fn default() -> Self {
        Self {
            tracker: TrackerConfig::default(),
            cells: CellConfig::default(),
            epsilon_miss: footslam::filter::EPSILON_MISS,
        }
    }
}

#[derive(Debug, Serialize)]
struct WalkSummary {
    steps_file: String,
    wifi_file: String,
    /// The walk's known start (its own from the manifest, else the shared one).
    start: Option<StartPose>,
    steps: usize,
    scans: usize,
    steps_to_localise: Option<usize>,
    /// Steps whose place the survey knew (the whole-walk answer's certain steps, or the
    /// filtered estimates from localisation on with `tracker.smoothing = false`).
    steps_placed: usize,
    scans_added: usize,
    scans_skipped: usize,
}

#[derive(Debug, Serialize)]
struct Summary {
    walks: Vec<WalkSummary>,
    cells: usize,
    rooms: usize,
    granularity_m: f64,
    coverage: f64,
    mean_scans_per_covered_cell: f64,
    epsilon: Option<f64>,
    epsilon_sqrt: Option<f64>,
    /// Per distance (`paper`, `sqrt`): quantiles of the held-out distances ε is chosen from.
    ndist_leave_one_out_p50_p90_p99_max: BTreeMap<&'static str, [Option<f64>; 4]>,
    access_points: usize,
    runtime_s: f64,
    walk_duration_s: f64,
    speed_vs_real_time: f64,
    peak_memory_bytes: Option<u64>,
}

/// A survey at one granularity: its cells, the map, each walk's scans (added, skipped) and
/// where they went.
type Surveyed = (CellMap, RadioMap, Vec<(usize, usize)>, Vec<Assignments>);

/// Runs `footslam survey`.
pub fn run(args: Args) -> Result<()> {
    let started = Instant::now();
    if args.steps.len() != args.wifi.len() {
        bail!(
            "give one --wifi per --steps (got {} step traces and {} WiFi logs)",
            args.steps.len(),
            args.wifi.len()
        );
    }
    let mut config: SurveyConfig = match &args.config {
        Some(p) => read_config(p)?,
        None => SurveyConfig::default(),
    };
    if let Some(s) = args.seed {
        config.tracker.seed = s;
    }
    if args.start.is_some() {
        config.tracker.start = args.start;
    }
    if let Some(g) = args.cell {
        config.cells.granularity = g;
    }
    config.tracker.validate()?;
    config.cells.validate()?;
    if !(config.epsilon_miss.is_finite() && (0.0..=0.5).contains(&config.epsilon_miss)) {
        bail!("epsilon_miss = {} must be in [0, 0.5]", config.epsilon_miss);
    }
    require_file(&args.plan, "floor plan")?;
    let (plan, frame) = read_floor_plan(&args.plan, args.origin)?;
    let topology = FloorTopology::build(&plan, &config.tracker.topology)
        .with_context(|| format!("{}: not a usable floor plan", args.plan.display()))?;
    let mut pairs: Vec<WalkFiles> = args
        .steps
        .iter()
        .cloned()
        .zip(args.wifi.iter().cloned())
        .map(|(steps, wifi)| WalkFiles {
            steps,
            wifi,
            start: None,
        })
        .collect();
    if let Some(manifest) = &args.walks {
        pairs.extend(read_manifest(manifest)?);
    }
    if pairs.is_empty() && args.merge.is_empty() {
        bail!("nothing to survey: give --steps/--wifi pairs, --walks or --merge");
    }
    let mut walks = Vec::with_capacity(pairs.len());
    for w in &pairs {
        require_file(&w.steps, "step trace")?;
        require_file(&w.wifi, "WiFi log")?;
        let trace = read_steps(&w.steps)?;
        check_height_changes(&w.steps, &args.plan, &plan, args.one_floor)?;
        let scans = read_scans(&w.wifi, &trace)?;
        walks.push((trace, scans));
    }
    // A walk's own start overrides the shared one.
    let starts: Vec<Option<StartPose>> = pairs
        .iter()
        .map(|w| w.start.or(config.tracker.start))
        .collect();
    let pool = super::common::worker_pool(args.threads)?;
    let total: u64 = walks.iter().map(|(s, _)| s.len() as u64).sum();
    // Per walk: the filter's reports, and the steps its scans are placed by.
    let runs: Vec<(Vec<TrackStep>, Vec<TrackStep>)> = pool.install(|| -> Result<_> {
        let mut progress = Progress::new(total, "surveying");
        let mut runs = Vec::with_capacity(walks.len());
        for (k, (trace, _)) in walks.iter().enumerate() {
            let tracker_config = TrackerConfig {
                seed: config.tracker.seed.wrapping_add(k as u64),
                start: starts[k],
                ..config.tracker.clone()
            };
            let mut tracker = Tracker::new(&topology, &tracker_config)
                .with_context(|| format!("walk {} ({})", k + 1, pairs[k].steps.display()))?;
            let mut reports = Vec::with_capacity(trace.len());
            for step in trace.steps() {
                reports.push(tracker.update(step)?);
                progress.inc();
            }
            let placed = placed_steps(&tracker, reports.clone());
            runs.push((reports, placed));
        }
        progress.finish();
        Ok(runs)
    })?;
    let scans: Vec<&[WifiScan]> = walks.iter().map(|(_, w)| w.as_slice()).collect();
    let build = |granularity: f64| -> Result<Surveyed> {
        let cells = CellMap::build(
            &plan,
            &topology,
            &CellConfig {
                granularity,
                ..config.cells
            },
        )?;
        let mut map = RadioMap::empty(&cells);
        let assignments: Vec<Assignments> = runs
            .iter()
            .zip(&scans)
            .map(|((_, placed), scans)| survey_assignments(&cells, &topology, placed, scans))
            .collect();
        let counts = assignments
            .iter()
            .zip(&scans)
            .map(|(a, scans)| {
                let c = survey_walk(&mut map, a, scans);
                (c.added, c.skipped)
            })
            .collect();
        Ok((cells, map, counts, assignments))
    };
    let (cells, mut map, counts, assignments) = build(config.cells.granularity)?;
    for path in &args.merge {
        require_file(path, "radio map")?;
        let (earlier, _) = read_radio_map_geojson(path, Some(frame))?;
        map.merge(&earlier).with_context(|| {
            format!(
                "{}: not a map of this plan at {} m cells",
                path.display(),
                config.cells.granularity
            )
        })?;
    }
    let calibration: Vec<(Assignments, &[WifiScan])> =
        assignments.into_iter().zip(scans.iter().copied()).collect();
    let held = calibrate_map(
        &mut map,
        &calibration,
        config.tracker.rf.missing_rssi,
        config.epsilon_miss,
    );
    let quantiles = held_out_quantiles(&held);

    let mut folder = RunFolder::create(&output_dir(args.out, "survey"))?;
    folder.protect(
        [&args.plan]
            .into_iter()
            .chain(&args.steps)
            .chain(&args.wifi)
            .chain(&args.merge)
            .chain(args.walks.iter())
            .chain(args.config.iter()),
    );
    write_radio_map_files(&folder, "", &plan, &map, &frame)?;
    let mut coverage = String::from("granularity_m,cells,coverage_percent,mean_scans_per_cell\n");
    for g in COVERAGE_GRANULARITIES {
        let (_, m, ..) = build(g)?;
        let (share, mean) = m.coverage();
        coverage.push_str(&format!(
            "{g},{},{:.1},{:.2}\n",
            m.cells.len(),
            100.0 * share,
            mean
        ));
    }
    folder.write("coverage.csv", coverage.as_bytes())?;
    folder.write_json("config.json", &config)?;
    let (share, mean) = map.coverage();
    let duration: f64 = walks
        .iter()
        .map(|(s, _)| {
            let st = s.steps();
            st.last().map_or(0.0, |l| l.t - st[0].t)
        })
        .sum();
    let runtime = started.elapsed().as_secs_f64();
    let summary = Summary {
        walks: walks
            .iter()
            .zip(&runs)
            .zip(&counts)
            .zip(pairs.iter().zip(&starts))
            .map(
                |((((trace, wifi), (reports, placed)), &(added, skipped)), (files, start))| {
                    WalkSummary {
                        steps_file: files.steps.display().to_string(),
                        wifi_file: files.wifi.display().to_string(),
                        start: *start,
                        steps: trace.len(),
                        scans: wifi.len(),
                        steps_to_localise: reports.iter().position(|r| r.localised).map(|i| i + 1),
                        steps_placed: placed.iter().filter(|r| r.estimate.is_some()).count(),
                        scans_added: added,
                        scans_skipped: skipped,
                    }
                },
            )
            .collect(),
        cells: cells.cells().len(),
        rooms: cells.rooms().len(),
        granularity_m: config.cells.granularity,
        coverage: share,
        mean_scans_per_covered_cell: mean,
        epsilon: map.epsilon,
        epsilon_sqrt: map.epsilon_sqrt,
        ndist_leave_one_out_p50_p90_p99_max: quantiles,
        access_points: map.access_points().len(),
        runtime_s: runtime,
        walk_duration_s: duration,
        speed_vs_real_time: duration / runtime.max(1e-9),
        peak_memory_bytes: peak_memory_bytes(),
    };
    folder.write_json("summary.json", &summary)?;
    let out = folder.commit()?;
    let speed = if summary.walks.is_empty() {
        String::new()
    } else {
        format!(" ({:.0}× real time)", summary.speed_vs_real_time)
    };
    outln!(
        "surveyed {} walk(s) into {} cells: {:.1} % covered, {:.1} scans per covered cell, {} access points{speed}",
        summary.walks.len(),
        summary.cells,
        100.0 * share,
        mean,
        summary.access_points,
    );
    outln!("outputs: {}", out.display());
    Ok(())
}

/// One walk to survey: its files and, when known, its own start.
#[derive(Debug, Clone)]
struct WalkFiles {
    steps: PathBuf,
    wifi: PathBuf,
    start: Option<StartPose>,
}

/// The walks of a manifest CSV ([`read_walk_manifest`] with a WiFi log each).
fn read_manifest(path: &std::path::Path) -> Result<Vec<WalkFiles>> {
    require_file(path, "walk manifest")?;
    Ok(read_walk_manifest(path, true)?
        .into_iter()
        .map(|w| WalkFiles {
            steps: w.steps,
            wifi: w.wifi.unwrap_or_default(),
            start: w.start,
        })
        .collect())
}
