//! `footslam track`: locate and track a walker on a known 2.5D floor plan from step events.

use super::common::{
    bundled, check_height_changes, check_scans_match, output_dir, parse_extent, parse_origin,
    peak_memory_bytes, read_config, read_scans, require_file,
};
use super::progress_bars::Bars;
use super::track_pictures::write_track_pictures;
use super::track_summary::{PlanStats, RfSummary, SmoothedStats, SmoothingSummary, Summary};
use anyhow::{Context, Result, bail};
use footslam::filter::{RfLocaliser, RfMode, SmoothedWalk, StartPose, TrackerConfig};
use footslam::geometry::LocalFrame;
use footslam::io::RunFolder;
use footslam::io::floor_plan_geojson::read_floor_plan;
use footslam::io::map_geojson::read_map_geojson;
use footslam::io::radio_map_geojson::read_radio_map_geojson;
use footslam::io::track_geojson::write_track_geojson;
use footslam::io::{SmoothedPoint, TrackPoint, read_steps, write_smoothed_track, write_track};
use footslam::map::{FloorPlan, FloorTopology, grow_plan};
use footslam::model::TransitionPrior;
use footslam::model::wifi_distance::Normalisation;
use footslam::pipeline::{
    QualityConfig, RadioInput, SAME_ORIGIN_M, SnapshotSteps, TrackInput, TrackRun, track,
};
use footslam::sensor::{StepTrace, WifiScan};
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
    config: Option<PathBuf>,
    /// Output folder (default: a new folder under `outputs/`).
    #[arg(short = 'o', long, value_name = "DIR", help_heading = "Outputs")]
    out: Option<PathBuf>,
    /// Worker threads (default: all cores; at most 4 per core). Results do not depend on it.
    #[arg(long, value_name = "N", help_heading = "Filter")]
    threads: Option<usize>,
    /// Radio map (`radiomap.geojson` as `footslam survey` writes it, or another tool's with
    /// the same properties) for RF-assisted localisation; needs `--wifi`.
    #[arg(long, requires = "wifi", value_name = "FILE", help_heading = "Inputs")]
    radiomap: Option<PathBuf>,
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
    picture_extent: Option<[f64; 4]>,
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
    let started = Instant::now();
    let config = tracker_config(&args)?;
    let mut inputs = read_inputs(&args, &config)?;
    let input = TrackInput {
        topology: &inputs.topology,
        transitions: inputs.transitions.as_ref(),
        radio: inputs.radio.as_ref().map(|r| RadioInput {
            localiser: &r.localiser,
            scans: &r.scans,
        }),
    };
    let snapshots = match &args.snapshots {
        Some(list) => SnapshotSteps::At(list.clone()),
        None => SnapshotSteps::Auto,
    };
    let pool = super::common::worker_pool(args.threads)?;
    let threads = pool.current_num_threads();
    let bars = Bars::default();
    let mut run = pool.install(|| track(&input, &inputs.trace, &config, &snapshots, &bars))?;

    let mut folder = super::common::create_run_folder(&output_dir(args.out.clone(), "track"))?;
    folder.protect(
        [&inputs.plan_path, &inputs.steps_path]
            .into_iter()
            .chain(args.radiomap.iter())
            .chain(args.wifi.iter())
            .chain(args.hexmap.iter())
            .chain(args.config.iter()),
    );
    // The trace's times are all the outputs need of it now.
    let times: Vec<f64> = inputs.trace.steps().iter().map(|s| s.t).collect();
    inputs.steps_with_heading = inputs.trace.with_heading();
    inputs.trace = StepTrace::default();
    // The answer: the smoothed track's certain steps, else (online) the filtered track.
    let smoothed = write_tracks(&folder, &times, run.smoothed.take(), &run)?;
    let answer = smoothed
        .as_ref()
        .map_or(&run.filtered[..], |(_, a, _)| &a[..]);
    write_track_geojson(&folder.path("track.geojson"), answer, &inputs.frame)?;
    let parts = smoothed.as_ref().map(|(_, a, u)| (&a[..], &u[..]));
    let extent = args.picture_extent;
    write_track_pictures(&folder, &inputs.plan, &run, parts, times.len(), extent)?;
    folder.write_json("config.json", &config)?;
    let stats = smoothed.as_ref().map(|(s, ..)| s);
    let summary = summary(&args, &inputs, &run, &times, stats, threads, started);
    folder.write_json("summary.json", &summary)?;
    let out = folder.commit()?;
    summary.print(&out);
    Ok(())
}

/// What `track` read: the plan, the walk and, when given, the learned map and the radio map
/// with the walk's scans.
struct Inputs {
    plan_path: PathBuf,
    steps_path: PathBuf,
    plan: FloorPlan,
    frame: LocalFrame,
    topology: FloorTopology,
    transitions: Option<TransitionPrior>,
    trace: StepTrace,
    /// Steps of the trace with an absolute heading (kept when the trace is dropped).
    steps_with_heading: usize,
    radio: Option<RadioFiles>,
}

/// The radio map (as a localiser) and the walk's scans, with their files.
struct RadioFiles {
    map_path: PathBuf,
    wifi_path: PathBuf,
    localiser: RfLocaliser,
    scans: Vec<WifiScan>,
    /// Scans that hear an access point of the map.
    matched: usize,
    /// Rows of the log that repeated an access point within a scan (the later kept).
    duplicate_readings: usize,
}

/// Reads and checks `track`'s inputs.
fn read_inputs(args: &Args, config: &TrackerConfig) -> Result<Inputs> {
    let plan_path = args.plan.clone().unwrap_or_else(|| bundled(DEFAULT_PLAN));
    let steps_path = args.steps.clone().unwrap_or_else(|| bundled(DEFAULT_STEPS));
    require_file(&plan_path, "floor plan")?;
    require_file(&steps_path, "step trace")?;
    let (plan, frame) = read_floor_plan(&plan_path, args.origin)?;
    let plan = match args.plan_margin {
        Some(margin) => grow_plan(&plan, margin)
            .with_context(|| format!("{}: --plan-margin {margin}", plan_path.display()))?,
        None => plan,
    };
    let transitions = match &args.hexmap {
        Some(path) => {
            require_file(path, "learned map")?;
            let (map, map_frame) = read_map_geojson(path)?;
            let off = frame.distance_to(&map_frame);
            if off > SAME_ORIGIN_M {
                bail!(
                    "{}: its origin lies {off:.3} m from the plan's ({}): the learned map \
                     must be in the plan's frame (the map and the plan.geojson of one learn run)",
                    path.display(),
                    plan_path.display()
                );
            }
            Some(TransitionPrior::new(&map, config.transitions)?)
        }
        None => None,
    };
    let trace = read_steps(&steps_path)?;
    check_height_changes(&steps_path, &plan_path, &plan, args.one_floor)?;
    if let Some(late) = args.snapshots.iter().flatten().find(|&&k| k > trace.len()) {
        bail!(
            "--snapshots asks for step {late}, but {} has only {} steps",
            steps_path.display(),
            trace.len()
        );
    }
    let topology = FloorTopology::build(&plan, &config.topology)
        .with_context(|| format!("{}: not a usable floor plan", plan_path.display()))?;
    let radio = match (&args.radiomap, &args.wifi) {
        (Some(map_path), Some(wifi_path)) => {
            require_file(map_path, "radio map")?;
            require_file(wifi_path, "WiFi log")?;
            let (map, _) = read_radio_map_geojson(map_path, Some(frame))?;
            let (scans, duplicate_readings) = read_scans(wifi_path, &trace)?;
            let matched = check_scans_match(&map, &scans, map_path, wifi_path)?;
            let localiser = RfLocaliser::new(&map, &topology, &config.rf).with_context(|| {
                format!(
                    "{}: cannot localise with this radio map",
                    map_path.display()
                )
            })?;
            if let Some(why) = localiser.fallback() {
                super::common::warn(&format!(
                    "{}: {why}; containment regions are used instead of radio evidence",
                    map_path.display()
                ));
            }
            Some(RadioFiles {
                map_path: map_path.clone(),
                wifi_path: wifi_path.clone(),
                localiser,
                scans,
                matched,
                duplicate_readings,
            })
        }
        _ => None,
    };
    Ok(Inputs {
        plan_path,
        steps_path,
        plan,
        frame,
        topology,
        transitions,
        steps_with_heading: trace.with_heading(),
        trace,
        radio,
    })
}

/// `summary.json` of a run: its inputs, the filter's figures and the smoother's.
fn summary<'r>(
    args: &Args,
    inputs: &Inputs,
    run: &'r TrackRun,
    times: &[f64],
    smoothed: Option<&SmoothedStats>,
    threads: usize,
    started: Instant,
) -> Summary<'r> {
    let records = &run.records;
    let first = records.first_localised();
    let initial = run.initial_particles;
    Summary {
        quality: run.quality(smoothed.map_or(0, |s| s.certain), &QualityConfig::default()),
        rf: inputs.radio.as_ref().map(|r| RfSummary {
            radiomap_file: r.map_path.display().to_string(),
            wifi_file: r.wifi_path.display().to_string(),
            scans: r.scans.len(),
            scans_matched: r.matched,
            duplicate_readings: r.duplicate_readings,
            mode: r.localiser.config().mode,
            distance: r.localiser.distance(),
            epsilon_dbm: r.localiser.epsilon(),
            epsilon_source: r.localiser.epsilon_source(),
            started_at_step: records
                .steps
                .iter()
                .position(|r| r.particles() > 0)
                .map(|i| i + 1),
            measurements_ignored: run.measurements_ignored,
            evidence: r.localiser.evidence().cloned(),
            evidence_fallback: r.localiser.fallback().map(str::to_owned),
        }),
        headings_used: run.headings_used > 0,
        steps_with_heading: inputs.steps_with_heading,
        plan_file: inputs.plan_path.display().to_string(),
        hexmap_file: args.hexmap.as_ref().map(|p| p.display().to_string()),
        hexmap_hexagons: inputs.transitions.as_ref().map(TransitionPrior::len),
        steps_file: inputs.steps_path.display().to_string(),
        steps: times.len(),
        steps_to_localise: first.map(|i| i + 1),
        localised_at_t: first.map(|i| times[i]),
        track_rows: run.filtered.len(),
        smoothing: smoothed.map(|s| SmoothingSummary {
            steps_estimated: s.estimated,
            steps_certain: s.certain,
            first_certain_step: s.first_certain,
            path_nodes_peak: s.path_nodes_peak,
            runtime_s: s.runtime_s,
        }),
        particles_initial: initial,
        particles_max: records
            .steps
            .iter()
            .map(|r| r.particles())
            .max()
            .unwrap_or(initial)
            .max(initial),
        particles_final: records.steps.last().map_or(initial, |r| r.particles()),
        particles_per_step: &records.steps,
        clusters_per_step: &records.steps,
        deaths: records.recoveries.len(),
        recoveries: &records.recoveries,
        plan_fit: records.fit,
        seed: run.seed,
        threads,
        runtime_s: started.elapsed().as_secs_f64(),
        filter_runtime_s: run.filter_runtime_s,
        particle_steps_per_s: records.particle_steps() as f64 / run.filter_runtime_s.max(1e-9),
        bytes_per_particle: run.bytes_per_particle,
        peak_memory_bytes: peak_memory_bytes(),
        plan: PlanStats {
            surfaces: inputs.topology.len(),
            walkable_area_m2: inputs.topology.total_area(),
            levels: inputs.topology.levels(),
        },
        origin: inputs.frame,
        version: env!("CARGO_PKG_VERSION"),
    }
}

/// The tracker's configuration: the config file's (or the defaults), with the flags'
/// overrides, validated.
fn tracker_config(args: &Args) -> Result<TrackerConfig> {
    let mut config: TrackerConfig = match &args.config {
        Some(p) => read_config(p)?,
        None => TrackerConfig::default(),
    };
    if let Some(s) = args.seed {
        config.seed = s;
    }
    if let Some(n) = args.particles {
        config.kld.cap_particles(n);
    }
    if args.start.is_some() {
        config.start = args.start;
    }
    if args.ignore_heading {
        config.heading.enabled = false;
    }
    if let Some(m) = args.rf_mode {
        config.rf.mode = match m {
            RfModeArg::Containment => RfMode::Containment,
            RfModeArg::Probabilistic => RfMode::Probabilistic,
            RfModeArg::PriorOnly => RfMode::PriorOnly,
            RfModeArg::Evidence => RfMode::Evidence,
            RfModeArg::Auto => RfMode::Auto,
        };
    }
    if args.rf_epsilon.is_some() {
        config.rf.epsilon = args.rf_epsilon;
    }
    if let Some(d) = args.rf_distance {
        config.rf.distance = Some(match d {
            RfDistanceArg::Paper => Normalisation::Paper,
            RfDistanceArg::Sqrt => Normalisation::Sqrt,
        });
    }
    if args.rf_every_step {
        config.rf.every_step = true;
    }
    if args.online {
        config.smoothing = false;
    }
    if let Some(w) = args.hexmap_weight {
        config.transitions.weight = w;
    }
    config.validate()?;
    Ok(config)
}

/// Writes `track.csv` (and, with smoothing, `track_filtered.csv`) and returns, with
/// smoothing, what the smoother gave, the answer (the smoothed track's certain steps) and
/// the uncertain steps' estimates; `None` online, where the answer is the filtered `track`.
/// The smoothed walk is read once, into track.csv and the answer, then dropped.
fn write_tracks(
    folder: &RunFolder,
    times: &[f64],
    smoothed: Option<SmoothedWalk>,
    run: &TrackRun,
) -> Result<Option<SmoothedTracks>> {
    let smoothing_started = Instant::now();
    let track = &run.filtered;
    Ok(match smoothed {
        Some(walk) => {
            let mut stats = SmoothedStats::default();
            let mut answer = Vec::new();
            let mut uncertain = Vec::new();
            let points = times
                .iter()
                .zip(walk.iter())
                .enumerate()
                .filter_map(|(i, (&t, k))| {
                    let k = k?;
                    stats.certain += usize::from(k.certain);
                    if k.certain && stats.first_certain.is_none() {
                        stats.first_certain = Some(i + 1);
                    }
                    let c = k.estimate?;
                    stats.estimated += 1;
                    let point = TrackPoint {
                        t,
                        x: c.x,
                        y: c.y,
                        z: c.z,
                        level: c.level,
                    };
                    if k.certain {
                        answer.push(point);
                    } else {
                        uncertain.push((c.x as f32, c.y as f32, c.level));
                    }
                    Some(SmoothedPoint {
                        point,
                        certain: k.certain,
                        hypotheses: k.hypotheses,
                        spread: c.spread,
                        share: c.weight,
                    })
                });
            write_smoothed_track(&folder.path("track.csv"), points)?;
            write_track(&folder.path("track_filtered.csv"), track)?;
            stats.path_nodes_peak = run.path_nodes_peak;
            stats.runtime_s = smoothing_started.elapsed().as_secs_f64();
            Some((stats, answer, uncertain))
        }
        None => {
            write_track(&folder.path("track.csv"), track)?;
            None
        }
    })
}

/// What [`write_tracks`] gives with smoothing: the smoother's counts, the answer (certain
/// steps) and the uncertain steps' estimates as `(x, y, level)`.
type SmoothedTracks = (SmoothedStats, Vec<TrackPoint>, Vec<(f32, f32, i32)>);

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
