//! `footslam survey`: build a cell-based WiFi radio map from ordinary walks, tracking each
//! walker on the known plan and adding its scans where it was (Woodman & Harle 2009).

use super::batch_table::walks_table;
use super::common::{
    check_height_changes, output_dir, parse_origin, read_config, read_scans, require_file,
};
use super::progress_bars::Bars;
use super::radio_outputs::write_radio_map_files;
use anyhow::{Context, Result, bail};
use footslam::filter::StartPose;
use footslam::geometry::LocalFrame;
use footslam::io::floor_plan_geojson::read_floor_plan;
use footslam::io::radio_map_geojson::read_radio_map_geojson;
use footslam::io::{read_steps, read_walk_manifest};
use footslam::map::{FloorPlan, FloorTopology, RadioMap};
use footslam::model::wifi_distance::held_out_quantiles;
use footslam::pipeline::{Quality, SurveyConfig, SurveyInput, SurveyWalk, Surveyed, survey};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `footslam survey`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Floor plan GeoJSON.
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    plan: PathBuf,
    /// Step trace CSV of a walk; repeat with `--wifi` for several walks (paired in order).
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    steps: Vec<PathBuf>,
    /// WiFi log CSV (`t,bssid,rssi[,ssid,freq]`) of the walk given by the `--steps` at the
    /// same position.
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    wifi: Vec<PathBuf>,
    /// Manifest of walks: a CSV with columns `steps,wifi` (paths relative to the manifest)
    /// and optionally `start` — the walk's known start `X,Y[,HEADING[,LEVEL]]` as `--start`
    /// takes it, quoted since it holds commas (e.g. `"12.5,3,,1"`); empty = the start of
    /// `--start` or the config, else unknown — one walk a row; added to any
    /// `--steps`/`--wifi` pairs.
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    walks: Option<PathBuf>,
    /// Every walk stays on its start floor: allows step traces without a `dz` column on a
    /// plan of several levels (otherwise an error).
    #[arg(long, help_heading = "Inputs")]
    one_floor: bool,
    /// A radio map surveyed before on this plan at this granularity (`radiomap.geojson`),
    /// merged into the new one; repeat to merge several (with no walk: just merge them).
    #[arg(
        long = "radiomap",
        alias = "merge",
        value_name = "FILE",
        help_heading = "Inputs"
    )]
    merge: Vec<PathBuf>,
    /// Cell granularity, metres (default 3).
    #[arg(long, value_name = "METRES", help_heading = "Filter")]
    cell: Option<f64>,
    /// Known start `X,Y[,HEADING[,LEVEL]]` of the walk of the `--steps` at the same position
    /// (`X,Y,,LEVEL`: a level without a heading), as in `learn`; a manifest's walks take
    /// theirs from its `start` column (default: unknown).
    #[arg(long, value_parser = super::track::parse_start, allow_hyphen_values = true, value_name = "X,Y[,HEADING[,LEVEL]]", help_heading = "Inputs")]
    start: Vec<StartPose>,
    /// WGS84 origin `LAT,LON`; overrides the plan's `origin`.
    #[arg(long, value_parser = parse_origin, allow_hyphen_values = true, value_name = "LAT,LON", help_heading = "Inputs")]
    origin: Option<footslam::geometry::LocalFrame>,
    /// Most particles: KLD-sampling's cap (overrides `kld.max_particles` of the config file,
    /// and `kld.max_step_particles` where lower; default 8,000,000 at the prior, 1,000,000
    /// after a step).
    #[arg(long, value_name = "N", help_heading = "Filter")]
    particles: Option<usize>,
    /// Random seed (overrides the config file).
    #[arg(long, value_name = "N", help_heading = "Filter")]
    seed: Option<u64>,
    /// Survey configuration (TOML or JSON with `tracker` and `cells`).
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    config: Option<PathBuf>,
    /// The part of the plan `radiomap.png` and the heatmaps show, `X0,Y0,X1,Y1` local
    /// metres (default: the cells drawn, with 10 m around them, within the plan).
    #[arg(long, value_parser = super::common::parse_extent, allow_hyphen_values = true, value_name = "X0,Y0,X1,Y1", help_heading = "Outputs")]
    picture_extent: Option<[f64; 4]>,
    /// Output folder (default: a new folder under `outputs/`).
    #[arg(short = 'o', long, value_name = "DIR", help_heading = "Outputs")]
    out: Option<PathBuf>,
    /// Worker threads (default: all cores; at most 4 per core). Results do not depend on it.
    #[arg(long, value_name = "N", help_heading = "Filter")]
    threads: Option<usize>,
}

#[derive(Debug, Serialize)]
struct WalkSummary {
    steps_file: String,
    wifi_file: String,
    /// The walk's known start (its own from the manifest, else the shared one).
    start: Option<StartPose>,
    steps: usize,
    scans: usize,
    /// Rows of the WiFi log that repeated an access point within a scan (the later kept).
    duplicate_readings: usize,
    steps_to_localise: Option<usize>,
    /// Steps whose place the survey knew (the whole-walk answer's certain steps, or the
    /// filtered estimates from localisation on with `tracker.smoothing = false`).
    steps_placed: usize,
    scans_added: usize,
    scans_skipped: usize,
    /// How well the walk fitted the plan; a `poor` walk's scans are left out of the map.
    quality: Quality,
}

#[derive(Debug, Serialize)]
struct Summary {
    /// The survey's verdict and its reasons (docs/robustness.md).
    quality: Quality,
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

/// The radio maps of `--radiomap`, to merge into the new one.
fn read_earlier_maps(args: &Args, frame: LocalFrame) -> Result<Vec<RadioMap>> {
    args.merge
        .iter()
        .map(|path| {
            require_file(path, "radio map")?;
            Ok(read_radio_map_geojson(path, Some(frame))?.0)
        })
        .collect()
}

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
    let config = survey_config(&args)?;
    require_file(&args.plan, "floor plan")?;
    let (plan, frame) = read_floor_plan(&args.plan, args.origin)?;
    let topology = FloorTopology::build(&plan, &config.tracker.topology)
        .with_context(|| format!("{}: not a usable floor plan", args.plan.display()))?;
    let (files, walks) = read_walks(&args, &plan)?;
    let earlier = read_earlier_maps(&args, frame)?;
    let input = SurveyInput {
        plan: &plan,
        topology: &topology,
        walks: &walks,
        earlier: &earlier,
    };
    let pool = super::common::worker_pool(args.threads)?;
    let surveyed = pool
        .install(|| survey(&input, &config, &Bars::default()))
        .with_context(|| format!("{}: cannot survey on this plan", args.plan.display()))?;
    warn_left_out(&files, &surveyed);

    let mut folder = super::common::create_run_folder(&output_dir(args.out.clone(), "survey"))?;
    folder.protect(
        [&args.plan]
            .into_iter()
            .chain(&args.steps)
            .chain(&args.wifi)
            .chain(&args.merge)
            .chain(args.walks.iter())
            .chain(args.config.iter()),
    );
    let pictures = (&frame, true, args.picture_extent);
    write_radio_map_files(&folder, "", &plan, &surveyed.map, pictures)?;
    let mut coverage = String::from("granularity_m,cells,coverage_percent,mean_scans_per_cell\n");
    for c in &surveyed.coverage {
        let (g, n, share, mean) = (c.granularity, c.cells, 100.0 * c.share, c.mean_scans);
        coverage.push_str(&format!("{g},{n},{share:.1},{mean:.2}\n"));
    }
    folder.write("coverage.csv", coverage.as_bytes())?;
    folder.write_json("config.json", &config)?;
    let summary = Summary::new(&files, &walks, &surveyed, &config, started);
    folder.write("walks.csv", &walks_table(&summary.walks)?)?;
    folder.write_json("summary.json", &summary)?;
    let out = folder.commit()?;
    summary.print(&out);
    Ok(())
}

/// Warns of each walk whose scans were left out of the map (it does not fit the plan).
fn warn_left_out(files: &[WalkFiles], surveyed: &Surveyed) {
    for (f, w) in files.iter().zip(&surveyed.walks) {
        if w.left_out() {
            super::common::warn(&format!(
                "{}: {}; its scans were left out of the radio map",
                f.steps.display(),
                w.quality.line()
            ));
        }
    }
}

/// The survey's configuration: the config file's (or the defaults) with the flags'
/// overrides, validated.
fn survey_config(args: &Args) -> Result<SurveyConfig> {
    let mut config: SurveyConfig = match &args.config {
        Some(p) => read_config(p)?,
        None => SurveyConfig::default(),
    };
    if let Some(s) = args.seed {
        config.tracker.seed = s;
    }
    if let Some(n) = args.particles {
        config.tracker.kld.cap_particles(n);
    }
    if let Some(g) = args.cell {
        config.cells.granularity = g;
    }
    config.tracker.validate()?;
    config.cells.validate()?;
    if !(config.epsilon_miss.is_finite() && (0.0..=0.5).contains(&config.epsilon_miss)) {
        bail!("epsilon_miss = {} must be in [0, 0.5]", config.epsilon_miss);
    }
    Ok(config)
}

/// The walks of the `--steps`/`--wifi` pairs and the manifest: their files and contents.
fn read_walks(args: &Args, plan: &FloorPlan) -> Result<(Vec<WalkFiles>, Vec<SurveyWalk>)> {
    let mut files: Vec<WalkFiles> = args
        .steps
        .iter()
        .cloned()
        .zip(args.wifi.iter().cloned())
        .enumerate()
        .map(|(i, (steps, wifi))| WalkFiles {
            steps,
            wifi,
            start: args.start.get(i).copied(),
            duplicate_readings: 0,
        })
        .collect();
    if !args.start.is_empty() && args.start.len() != args.steps.len() {
        bail!(
            "{} --start poses for {} --steps files: give one --start per --steps (paired in \
             order), a `start` column in the --walks manifest, or `tracker.start` in --config \
             for every walk",
            args.start.len(),
            args.steps.len()
        );
    }
    if let Some(manifest) = &args.walks {
        files.extend(read_manifest(manifest)?);
    }
    if files.is_empty() && args.merge.is_empty() {
        bail!("nothing to survey: give --steps/--wifi pairs, --walks or --radiomap");
    }
    let mut walks = Vec::with_capacity(files.len());
    for w in &mut files {
        require_file(&w.steps, "step trace")?;
        require_file(&w.wifi, "WiFi log")?;
        let trace = read_steps(&w.steps)?;
        check_height_changes(&w.steps, &args.plan, plan, args.one_floor)?;
        let (scans, duplicate_readings) = read_scans(&w.wifi, &trace)?;
        w.duplicate_readings = duplicate_readings;
        walks.push(SurveyWalk {
            trace,
            scans,
            start: w.start,
        });
    }
    Ok((files, walks))
}

impl Summary {
    /// The run's summary from what the survey did.
    fn new(
        files: &[WalkFiles],
        walks: &[SurveyWalk],
        surveyed: &Surveyed,
        config: &SurveyConfig,
        started: Instant,
    ) -> Self {
        let map = &surveyed.map;
        let (share, mean) = map.coverage();
        let duration: f64 = walks
            .iter()
            .map(|w| {
                let st = w.trace.steps();
                st.last().map_or(0.0, |l| l.t - st[0].t)
            })
            .sum();
        let runtime = started.elapsed().as_secs_f64();
        Summary {
            walks: files
                .iter()
                .zip(walks)
                .zip(&surveyed.walks)
                .map(|((files, walk), done)| WalkSummary {
                    steps_file: files.steps.display().to_string(),
                    wifi_file: files.wifi.display().to_string(),
                    start: done.start,
                    steps: walk.trace.len(),
                    scans: walk.scans.len(),
                    duplicate_readings: files.duplicate_readings,
                    steps_to_localise: done.steps_to_localise,
                    steps_placed: done.steps_placed,
                    scans_added: done.scans_added,
                    scans_skipped: done.scans_skipped,
                    quality: done.quality.clone(),
                })
                .collect(),
            quality: surveyed.quality.clone(),
            cells: surveyed.cells.cells().len(),
            rooms: surveyed.cells.rooms().len(),
            granularity_m: config.cells.granularity,
            coverage: share,
            mean_scans_per_covered_cell: mean,
            epsilon: map.epsilon,
            epsilon_sqrt: map.epsilon_sqrt,
            ndist_leave_one_out_p50_p90_p99_max: held_out_quantiles(&surveyed.held),
            access_points: map.access_points().len(),
            runtime_s: runtime,
            walk_duration_s: duration,
            speed_vs_real_time: duration / runtime.max(1e-9),
            peak_memory_bytes: footslam::memory::peak_bytes(),
        }
    }

    /// Prints the outcome and the output folder.
    fn print(&self, out: &std::path::Path) {
        let speed = if self.walks.is_empty() {
            String::new()
        } else {
            format!(" ({:.0}× real time)", self.speed_vs_real_time)
        };
        info!(
            "surveyed {} walk(s) into {} cells: {:.1} % covered, {:.1} scans per covered cell, {} access points{speed}",
            self.walks.len(),
            self.cells,
            100.0 * self.coverage,
            self.mean_scans_per_covered_cell,
            self.access_points,
        );
        super::verbosity::done(out, Some(&self.quality.line()));
    }
}

/// One walk to survey: its files and, when known, its own start.
#[derive(Debug, Clone)]
struct WalkFiles {
    steps: PathBuf,
    wifi: PathBuf,
    start: Option<StartPose>,
    /// Rows of the WiFi log that repeated an access point within a scan (known once read).
    duplicate_readings: usize,
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
            duplicate_readings: 0,
        })
        .collect())
}
