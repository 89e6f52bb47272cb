//! `footslam track`: locate and track a walker on a known 2.5D floor plan from step events.

use super::common::{bundled, output_dir, parse_extent, parse_origin, read_config, require_file};
use super::progress_bars::Bars;
use super::track_pictures::write_track_pictures;
use super::track_summary::print_report;
use anyhow::{Result, bail};
use footslam::filter::{RfMode, StartPose, TrackerConfig};
use footslam::geometry::LocalFrame;
use footslam::io::RunFolder;
use footslam::io::floor_plan_geojson::read_floor_plan;
use footslam::io::map_geojson::read_stored_map;
use footslam::io::radio_map_geojson::read_radio_map_geojson;
use footslam::io::steps_csv::has_dz_column;
use footslam::io::track_geojson::write_track_geojson;
use footslam::io::{ManifestWalk, read_steps, read_wifi_log, write_smoothed_track, write_track};
use footslam::model::wifi_distance::Normalisation;
use footslam::pipeline::{
    Named, PreparedTrack, Progress, SnapshotSteps, TrackAnswer, TrackOverrides, TrackRadioRequest,
    TrackReport, TrackRequest, TrackRun, prepare,
};
use std::path::PathBuf;
use std::time::Instant;

/// The bundled sample building and walk, used when `--plan` / `--steps` are not given.
const DEFAULT_PLAN: &str = "datasets/tower/floor.geojson";
const DEFAULT_STEPS: &str = "datasets/tower/steps.csv";

/// Arguments of `footslam track`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Floor plan GeoJSON (walkable polygons with `level` and `z`). Default: the bundled
    /// three-floor building.
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    plan: Option<PathBuf>,
    /// Grow the plan by this many metres before tracking (default 0). For a plan learned
    /// from walks (`learn`'s `plan.geojson`), whose edges are where the walks stopped rather
    /// than walls: 0.25 gives a new walker room past them. Only for plans with one height
    /// per level.
    #[arg(long, value_name = "METRES", help_heading = "Filter")]
    plan_margin: Option<f64>,
    /// The walk stays on its start floor: allows a step trace without a `dz` column on a
    /// plan of several levels (without this flag that is an error, since `dz = 0` would
    /// pin the walk to one floor silently).
    #[arg(long, help_heading = "Inputs")]
    one_floor: bool,
    /// A map learned by `learn` in the plan's frame (its `map.geojson` or `merged.geojson`
    /// beside the `plan.geojson` it made): its transition probabilities become a motion
    /// prior — a particle moving along a well-trodden hexagon edge is likelier than one
    /// crossing an edge nobody crossed (FeetSLAM's reuse of a FootSLAM map).
    #[arg(
        long = "map",
        alias = "hexmap",
        value_name = "FILE",
        help_heading = "Inputs"
    )]
    hexmap: Option<PathBuf>,
    /// Exponent of the learned map's transition factors (default 1; 0 switches them off).
    #[arg(
        long = "map-weight",
        alias = "hexmap-weight",
        requires = "hexmap",
        value_name = "WEIGHT",
        help_heading = "Filter"
    )]
    hexmap_weight: Option<f64>,
    /// Step trace CSV (`t,length,dheading[,dz][,heading]`). An absolute `heading` column
    /// (radians counter-clockwise from east, e.g. from a compass) weights the particles
    /// (see `--ignore-heading`). Default: the bundled walk.
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    steps: Option<PathBuf>,
    /// Manifest of walks to track on the same plan (and radio map), up to 4 at once: a CSV
    /// with columns `steps[,wifi][,start][,name]` (paths relative to the manifest; `wifi`
    /// required with `--radiomap`; an empty `start` is unknown). The plan and the radio map
    /// are prepared once; each walk's outputs go into a folder named by its `name` (default
    /// `walk-1`, `walk-2`, … as in `learn`), with `walks.csv` (one row per walk) beside them.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["steps", "wifi", "start"], help_heading = "Inputs")]
    pub(super) walks: Option<PathBuf>,
    /// Known start `X,Y[,HEADING[,LEVEL]]` (local metres; HEADING = heading before the first
    /// step, radians counter-clockwise from east). Without HEADING the heading is unknown
    /// (uniform at the known position); `X,Y,,LEVEL` gives a level without a heading.
    /// Default: unknown (uniform over the whole plan).
    #[arg(long, value_parser = parse_start, allow_hyphen_values = true, value_name = "X,Y[,HEADING[,LEVEL]]", help_heading = "Inputs")]
    start: Option<StartPose>,
    /// Ignore the step trace's absolute `heading` column (same as `heading.enabled = false`
    /// in the config).
    #[arg(long, help_heading = "Inputs")]
    ignore_heading: bool,
    /// WGS84 origin of the local frame, `LAT,LON`; overrides the plan's `origin` member.
    #[arg(long, value_parser = parse_origin, allow_hyphen_values = true, value_name = "LAT,LON", help_heading = "Inputs")]
    origin: Option<LocalFrame>,
    /// Most particles: KLD-sampling's cap (overrides `kld.max_particles` of the config file,
    /// and `kld.max_step_particles` where lower; default 8,000,000 at the prior, 1,000,000
    /// after a step).
    #[arg(long, value_name = "N", help_heading = "Filter")]
    particles: Option<usize>,
    /// Random seed (overrides the config file).
    #[arg(long, value_name = "N", help_heading = "Filter")]
    seed: Option<u64>,
    /// Steps after which to draw the particle cloud in particles.png (0 = the prior),
    /// e.g. `0,5,50`. Default: the prior, steps 5 and 25, localisation and the last step.
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "STEPS",
        help_heading = "Outputs"
    )]
    snapshots: Option<Vec<usize>>,
    /// Tracker configuration (TOML, or JSON such as a previous run's config.json).
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    pub(super) config: Option<PathBuf>,
    /// Output folder (default: a new folder under `outputs/`).
    #[arg(short = 'o', long, value_name = "DIR", help_heading = "Outputs")]
    pub(super) out: Option<PathBuf>,
    /// Worker threads (default: all cores; at most 4 per core). Results do not depend on it.
    #[arg(long, value_name = "N", help_heading = "Filter")]
    pub(super) threads: Option<usize>,
    /// Radio map (`radiomap.geojson` as `footslam survey` writes it, or another tool's with
    /// the same properties) for RF-assisted localisation; needs `--wifi` (or a `wifi` column
    /// in `--walks`).
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    pub(super) radiomap: Option<PathBuf>,
    /// WiFi log CSV (`t,bssid,rssi[,ssid,freq]`) of the walk, on the step trace's clock.
    #[arg(
        long,
        requires = "radiomap",
        value_name = "FILE",
        help_heading = "Inputs"
    )]
    wifi: Option<PathBuf>,
    /// How scans weigh the particles: `auto` (the default: `evidence` on a radio map that
    /// covers less than 60 % of its cells, else `containment`), `evidence` (likelihood ratios
    /// calibrated on the radio map, which rule out no place the map does not know;
    /// containment regions where the map is too sparse to calibrate them), `containment`
    /// (eqs. 12–13), `probabilistic` (eq. 14) or `prior-only`.
    #[arg(long, value_enum, help_heading = "Filter")]
    rf_mode: Option<RfModeArg>,
    /// The scan-to-cell distance's divisor: `paper` (the number k of access points a cell
    /// hears, eqs. 8 and 11) or `sqrt` (√k). Default: `sqrt`, unless the radio map holds a
    /// threshold calibrated for the paper's distance only.
    #[arg(long, value_enum, requires = "radiomap", help_heading = "Filter")]
    rf_distance: Option<RfDistanceArg>,
    /// Region threshold ε, dBm (default: the radio map's calibration for the distance, else
    /// one derived from the map's histograms; the paper used 9.5 with `--rf-distance paper`).
    #[arg(
        long,
        requires = "radiomap",
        value_name = "EPSILON",
        help_heading = "Filter"
    )]
    rf_epsilon: Option<f64>,
    /// Apply the latest scan at every step where the particles are then (eq. 12 read
    /// literally), instead of once, where they were when the scan was taken.
    #[arg(long, requires = "radiomap", help_heading = "Filter")]
    rf_every_step: bool,
    /// The part of the plan `track.png` and `particles.png` show, `X0,Y0,X1,Y1` local
    /// metres (default: what they draw, with 10 m around it, within the plan).
    #[arg(long, value_parser = parse_extent, allow_hyphen_values = true, value_name = "X0,Y0,X1,Y1", help_heading = "Outputs")]
    pub(super) picture_extent: Option<[f64; 4]>,
    /// Causal answers only: `track.csv` holds each step's estimate as the filter saw it
    /// (from localisation on) and no ancestry is kept. By default `track.csv` is the
    /// smoothed whole-walk answer for every step, and the filtered one is
    /// `track_filtered.csv`.
    #[arg(long, help_heading = "Filter")]
    online: bool,
}

/// `--rf-distance` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum RfDistanceArg {
    Paper,
    Sqrt,
}

/// `--rf-mode` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum RfModeArg {
    Containment,
    Probabilistic,
    PriorOnly,
    Evidence,
    Auto,
}

/// Parses `X,Y[,HEADING[,LEVEL]]` ([`StartPose`]'s `FromStr`), for clap.
pub(super) fn parse_start(s: &str) -> Result<StartPose, String> {
    s.parse()
}

/// Runs `footslam track`.
pub fn run(args: Args) -> Result<()> {
    if args.radiomap.is_some() && args.wifi.is_none() {
        bail!(
            "--radiomap needs the walk's WiFi log: give --wifi (or --walks with a `wifi` column)"
        );
    }
    let started = Instant::now();
    let (request, inputs) = read_request(&args, None)?;
    let pool = super::common::worker_pool(args.threads)?;
    let bars = Bars::default();
    let prepared = pool.install(|| prepare(request, &bars))?;
    let mut folder = super::common::create_run_folder(&output_dir(args.out.clone(), "track"))?;
    folder.protect(inputs.iter().chain(args.config.iter()));
    let report =
        pool.install(|| track_into(&folder, &prepared, &bars, args.picture_extent, started))?;
    let out = folder.commit()?;
    print_report(&report, &out);
    Ok(())
}

/// Tracks a prepared walk and writes its outputs into `folder`: `track.csv` (and
/// `track_filtered.csv`), `track.geojson`, the pictures, `config.json` and `summary.json`,
/// whose report it returns.
pub(super) fn track_into(
    folder: &RunFolder,
    prepared: &PreparedTrack,
    progress: &dyn Progress,
    extent: Option<[f64; 4]>,
    started: Instant,
) -> Result<TrackReport> {
    let mut run = prepared.run(progress)?;
    let times: Vec<f64> = prepared.trace.steps().iter().map(|s| s.t).collect();
    let answer = TrackAnswer::read(&mut run, &times);
    write_tracks(folder, &answer, &run)?;
    // The answer: the smoothed track's certain steps, else (online) the filtered track.
    let (certain, uncertain) = (answer.certain(), answer.uncertain());
    let smoothed = answer.smoothing.is_some();
    let track = if smoothed { &certain } else { &run.filtered };
    write_track_geojson(&folder.path("track.geojson"), track, &prepared.frame)?;
    let parts = smoothed.then_some((&certain[..], &uncertain[..]));
    write_track_pictures(folder, &prepared.plan, &run, parts, times.len(), extent)?;
    folder.write_json("config.json", &prepared.config)?;
    let report = TrackReport::new(prepared, &run, &answer, started);
    folder.write_json("summary.json", &report)?;
    Ok(report)
}

/// Reads `track`'s inputs into its request, with the steps, WiFi log and start of `walk`
/// where given (a manifest's first walk) instead of `--steps`, `--wifi` and `--start`; with
/// the files read (kept from the output).
pub(super) fn read_request(
    args: &Args,
    walk: Option<&ManifestWalk>,
) -> Result<(TrackRequest, Vec<PathBuf>)> {
    let plan_path = args.plan.clone().unwrap_or_else(|| bundled(DEFAULT_PLAN));
    let steps_path = match walk {
        Some(w) => w.steps.clone(),
        None => args.steps.clone().unwrap_or_else(|| bundled(DEFAULT_STEPS)),
    };
    let wifi_path = walk.map_or(args.wifi.clone(), |w| w.wifi.clone());
    require_file(&plan_path, "floor plan")?;
    require_file(&steps_path, "step trace")?;
    let config: TrackerConfig = match &args.config {
        Some(p) => read_config(p)?,
        None => TrackerConfig::default(),
    };
    let (plan, frame) = read_floor_plan(&plan_path, args.origin)?;
    // Only a plan of several levels needs the steps' file read again for its header.
    let steps_have_dz = plan.levels().len() <= 1 || args.one_floor || has_dz_column(&steps_path)?;
    let map = match &args.hexmap {
        Some(path) => {
            require_file(path, "learned map")?;
            Some(Named::new(
                read_stored_map(path)?,
                path.display().to_string(),
            ))
        }
        None => None,
    };
    let radio = match (&args.radiomap, &wifi_path) {
        (Some(map_path), Some(wifi_path)) => {
            require_file(map_path, "radio map")?;
            require_file(wifi_path, "WiFi log")?;
            let (map, _) = read_radio_map_geojson(map_path, Some(frame))?;
            let log = read_wifi_log(wifi_path)?;
            Some(TrackRadioRequest {
                map: Named::new(map, map_path.display().to_string()),
                scans: Named::new(log.scans, wifi_path.display().to_string()),
                duplicate_readings: log.duplicate_readings,
            })
        }
        _ => None,
    };
    let request = TrackRequest {
        plan: Named::new(plan, plan_path.display().to_string()),
        frame,
        plan_margin: args.plan_margin,
        steps: Named::new(read_steps(&steps_path)?, steps_path.display().to_string()),
        steps_have_dz,
        one_floor: args.one_floor,
        map,
        radio,
        snapshots: match &args.snapshots {
            Some(list) => SnapshotSteps::At(list.clone()),
            None => SnapshotSteps::Auto,
        },
        config,
        overrides: TrackOverrides {
            start: walk.map_or(args.start, |w| w.start),
            ..overrides(args)
        },
    };
    let files = [plan_path, steps_path]
        .into_iter()
        .chain(args.radiomap.iter().cloned())
        .chain(wifi_path.iter().cloned())
        .chain(args.hexmap.iter().cloned())
        .collect();
    Ok((request, files))
}

/// The flags that override the tracker's configuration.
fn overrides(args: &Args) -> TrackOverrides {
    TrackOverrides {
        seed: args.seed,
        particles: args.particles,
        start: args.start,
        ignore_heading: args.ignore_heading,
        rf_mode: args.rf_mode.map(|m| match m {
            RfModeArg::Containment => RfMode::Containment,
            RfModeArg::Probabilistic => RfMode::Probabilistic,
            RfModeArg::PriorOnly => RfMode::PriorOnly,
            RfModeArg::Evidence => RfMode::Evidence,
            RfModeArg::Auto => RfMode::Auto,
        }),
        rf_epsilon: args.rf_epsilon,
        rf_distance: args.rf_distance.map(|d| match d {
            RfDistanceArg::Paper => Normalisation::Paper,
            RfDistanceArg::Sqrt => Normalisation::Sqrt,
        }),
        rf_every_step: args.rf_every_step,
        online: args.online,
        map_weight: args.hexmap_weight,
    }
}

/// Writes `track.csv`: the smoothed answer (and the filtered track as
/// `track_filtered.csv`), or online the filtered track.
fn write_tracks(folder: &RunFolder, answer: &TrackAnswer, run: &TrackRun) -> Result<()> {
    if answer.smoothing.is_some() {
        write_smoothed_track(&folder.path("track.csv"), answer.rows.iter().copied())?;
        write_track(&folder.path("track_filtered.csv"), &run.filtered)?;
    } else {
        write_track(&folder.path("track.csv"), &run.filtered)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn starts_parse_or_explain() {
        let s = parse_start("1.5,-2,0.5").expect("start");
        assert_eq!((s.x, s.y, s.heading, s.level), (1.5, -2.0, Some(0.5), None));
        let s = parse_start("1.5, -2").expect("no heading");
        assert_eq!((s.x, s.y, s.heading, s.level), (1.5, -2.0, None, None));
        let s = parse_start("1,2,3,2").expect("level");
        assert_eq!((s.heading, s.level), (Some(3.0), Some(2)));
        let s = parse_start("1,2,,-1").expect("level without heading");
        assert_eq!((s.x, s.y, s.heading, s.level), (1.0, 2.0, None, Some(-1)));
        assert_eq!(parse_start("1,2,").expect("trailing comma").heading, None);
        let err = |s: &str| parse_start(s).expect_err(s);
        assert!(err("1").contains("expected X,Y[,HEADING[,LEVEL]]"));
        assert!(err("1,2,3,4,5").contains("X,Y,,LEVEL"));
        assert!(err("1,2,x").contains("HEADING `x` is not a finite number"));
        assert!(err("1,2,NaN").contains("HEADING `NaN`"));
        assert!(err("x,2").contains("X `x`"));
        assert!(err(",2").contains("X ``"));
        assert!(err("1,2,3,1.5").contains("level `1.5` is not an integer"));
        assert!(err("1,2,,").contains("level ``"));
    }
}
