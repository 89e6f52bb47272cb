//! `footslam survey`: build a cell-based WiFi radio map from ordinary walks, tracking each
//! walker on the known plan and adding its scans where it was (Woodman & Harle 2009).

use super::batch_table::walks_table;
use super::common::{output_dir, parse_origin, read_config, require_file};
use super::progress_bars::Bars;
use super::radio_outputs::{Heatmaps, parse_heatmaps, write_radio_map_files};
use anyhow::{Result, bail};
use footslam::filter::StartPose;
use footslam::geometry::LocalFrame;
use footslam::io::floor_plan_geojson::read_floor_plan;
use footslam::io::radio_map_geojson::read_radio_map_geojson;
use footslam::io::steps_csv::has_dz_column;
use footslam::io::{read_steps, read_walk_manifest, read_wifi_log};
use footslam::map::{FloorPlan, RadioMap};
use footslam::pipeline::{
    Named, SurveyConfig, SurveyOverrides, SurveyReport, SurveyRequest, SurveyWalkRequest, Surveyed,
    prepare_survey,
};
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
    /// Heatmaps for the N access points heard in the most cells, or `all` (a real floor
    /// hears hundreds to thousands) [default: 24].
    #[arg(long, value_parser = parse_heatmaps, value_name = "N|all", help_heading = "Outputs")]
    heatmaps: Option<Heatmaps>,
    /// Output folder (default: a new folder under `outputs/`).
    #[arg(short = 'o', long, value_name = "DIR", help_heading = "Outputs")]
    out: Option<PathBuf>,
    /// Worker threads (default: all cores; at most 4 per core). Results do not depend on it.
    #[arg(long, value_name = "N", help_heading = "Filter")]
    threads: Option<usize>,
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
    let bars = Bars::default();
    let prepared = prepare_survey(read_request(&args)?, &bars)?;
    let pool = super::common::worker_pool(args.threads)?;
    let surveyed = pool.install(|| prepared.run(&bars))?;
    warn_left_out(&prepared.labels, &surveyed);

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
    let heatmaps = args.heatmaps.unwrap_or(Heatmaps::DEFAULT);
    let pictures = (&prepared.frame, true, args.picture_extent, heatmaps);
    let plan = &prepared.plan.value;
    let drawn =
        pool.install(|| write_radio_map_files(&folder, "", plan, &surveyed.map, pictures))?;
    let mut coverage = String::from("granularity_m,cells,coverage_percent,mean_scans_per_cell\n");
    for c in &surveyed.coverage {
        let (g, n, share, mean) = (c.granularity, c.cells, 100.0 * c.share, c.mean_scans);
        coverage.push_str(&format!("{g},{n},{share:.1},{mean:.2}\n"));
    }
    folder.write("coverage.csv", coverage.as_bytes())?;
    folder.write_json("config.json", &prepared.config)?;
    let report = SurveyReport::new(&prepared, &surveyed, started);
    folder.write("walks.csv", &walks_table(&report.walks)?)?;
    folder.write_json("summary.json", &report)?;
    let out = folder.commit()?;
    super::radio_outputs::print_heatmaps(drawn, &surveyed.map);
    print_report(&report, &out);
    Ok(())
}

/// Warns of each walk whose scans were left out of the map (it does not fit the plan).
fn warn_left_out(labels: &[footslam::pipeline::SurveyWalkLabels], surveyed: &Surveyed) {
    for (f, w) in labels.iter().zip(&surveyed.walks) {
        if w.left_out() {
            super::common::warn(&format!(
                "{}: {}; its scans were left out of the radio map",
                f.steps,
                w.quality.line()
            ));
        }
    }
}

/// The request of `survey`: the plan, the walks and the radio maps to merge read, the
/// configuration file's and the flags over it.
fn read_request(args: &Args) -> Result<SurveyRequest> {
    if args.steps.len() != args.wifi.len() {
        bail!(
            "give one --wifi per --steps (got {} step traces and {} WiFi logs)",
            args.steps.len(),
            args.wifi.len()
        );
    }
    let config: SurveyConfig = match &args.config {
        Some(p) => read_config(p)?,
        None => SurveyConfig::default(),
    };
    require_file(&args.plan, "floor plan")?;
    let (plan, frame) = read_floor_plan(&args.plan, args.origin)?;
    let walks = read_walks(args, &plan)?;
    Ok(SurveyRequest {
        plan: Named::new(plan, args.plan.display().to_string()),
        frame,
        walks,
        one_floor: args.one_floor,
        earlier: read_earlier_maps(args, frame)?,
        config,
        overrides: SurveyOverrides {
            seed: args.seed,
            particles: args.particles,
            start: None,
            cell: args.cell,
        },
    })
}

/// The walks of the `--steps`/`--wifi` pairs and the manifest, read.
fn read_walks(args: &Args, plan: &FloorPlan) -> Result<Vec<SurveyWalkRequest>> {
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
    let label = |p: &PathBuf| p.display().to_string();
    files
        .iter()
        .map(|w| {
            require_file(&w.steps, "step trace")?;
            require_file(&w.wifi, "WiFi log")?;
            let log = read_wifi_log(&w.wifi)?;
            // Only a plan of several levels needs the steps' header read again.
            let several = plan.levels().len() > 1 && !args.one_floor;
            Ok(SurveyWalkRequest {
                steps: Named::new(read_steps(&w.steps)?, label(&w.steps)),
                steps_have_dz: !several || has_dz_column(&w.steps)?,
                wifi: Named::new(log.scans, label(&w.wifi)),
                duplicate_readings: log.duplicate_readings,
                start: w.start,
            })
        })
        .collect()
}

/// Prints the outcome and the output folder.
fn print_report(report: &SurveyReport, out: &std::path::Path) {
    let speed = if report.walks.is_empty() {
        String::new()
    } else {
        format!(" ({:.0}× real time)", report.speed_vs_real_time)
    };
    info!(
        "surveyed {} walk(s) into {} cells: {:.1} % covered, {:.1} scans per covered cell, {} access points{speed}",
        report.walks.len(),
        report.cells,
        100.0 * report.coverage,
        report.mean_scans_per_covered_cell,
        report.access_points,
    );
    super::verbosity::done(out, Some(&report.quality.line()));
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
