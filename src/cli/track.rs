//! `footslam track`: locate and track a walker on a known 2.5D floor plan from step events.

use super::common::{
    Progress, SAME_ORIGIN, bundled, check_height_changes, check_scans_match, output_dir,
    parse_origin, peak_memory_bytes, read_config, read_scans, require_file, warn,
};
use super::track_pictures::{snapshot, write_particles_png, write_track_png};
use super::track_summary::{
    PlanStats, RfSummary, SmoothedStats, SmoothingSummary, StepRecords, Summary,
};
use anyhow::{Context, Result, bail};
use footslam::filter::{
    RfLocaliser, RfMode, RfTracker, SmoothedWalk, StartPose, TrackStep, Tracker, TrackerConfig,
};
use footslam::geometry::LocalFrame;
use footslam::io::RunFolder;
use footslam::io::floor_plan_geojson::read_floor_plan;
use footslam::io::map_geojson::read_map_geojson;
use footslam::io::radio_map_geojson::read_radio_map_geojson;
use footslam::io::track_geojson::write_track_geojson;
use footslam::io::{SmoothedPoint, TrackPoint, read_steps, write_smoothed_track, write_track};
use footslam::map::{FloorTopology, grow_plan};
use footslam::model::TransitionPrior;
use footslam::model::wifi_distance::Normalisation;
use std::path::PathBuf;
use std::time::Instant;

/// The bundled sample building and walk, used when `--plan` / `--steps` are not given.
const DEFAULT_PLAN: &str = "datasets/tower/floor.geojson";
const DEFAULT_STEPS: &str = "datasets/tower/steps.csv";
/// Automatic snapshots: the prior, these steps, the step of localisation and the last step.
const AUTO_SNAPSHOTS: [usize; 2] = [5, 25];

/// Arguments of `footslam track`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Floor plan GeoJSON (walkable polygons with `level` and `z`). Default: the bundled
    /// three-floor building.
    #[arg(long)]
    plan: Option<PathBuf>,
    /// Grow the plan by this many metres before tracking (default 0). For a plan learned
    /// from walks (`learn`'s `plan.geojson`), whose edges are where the walks stopped rather
    /// than walls: 0.25 gives a new walker room past them. Only for plans with one height
    /// per level.
    #[arg(long)]
    plan_margin: Option<f64>,
    /// The walk stays on its start floor: allows a step trace without a `dz` column on a
    /// plan of several levels (without this flag that is an error, since `dz = 0` would
    /// pin the walk to one floor silently).
    #[arg(long)]
    one_floor: bool,
    /// A map learned by `learn` in the plan's frame (its `map.geojson` or `merged.geojson`
    /// beside the `plan.geojson` it made): its transition probabilities become a motion
    /// prior — a particle moving along a well-trodden hexagon edge is likelier than one
    /// crossing an edge nobody crossed (FeetSLAM's reuse of a FootSLAM map).
    #[arg(long)]
    hexmap: Option<PathBuf>,
    /// Exponent of the learned map's transition factors (default 1; 0 switches them off).
    #[arg(long, requires = "hexmap")]
    hexmap_weight: Option<f64>,
    /// Step trace CSV (`t,length,dheading[,dz][,heading]`). An absolute `heading` column
    /// (radians counter-clockwise from east, e.g. from a compass) weights the particles
    /// (see `--ignore-heading`). Default: the bundled walk.
    #[arg(long)]
    steps: Option<PathBuf>,
    /// Known start `X,Y[,HEADING[,LEVEL]]` (local metres; HEADING = heading before the first
    /// step, radians counter-clockwise from east). Without HEADING the heading is unknown
    /// (uniform at the known position); `X,Y,,LEVEL` gives a level without a heading.
    /// Default: unknown (uniform over the whole plan).
    #[arg(long, value_parser = parse_start, allow_hyphen_values = true)]
    start: Option<StartPose>,
    /// Ignore the step trace's absolute `heading` column (same as `heading.enabled = false`
    /// in the config).
    #[arg(long)]
    ignore_heading: bool,
    /// WGS84 origin of the local frame, `LAT,LON`; overrides the plan's `origin` member.
    #[arg(long, value_parser = parse_origin, allow_hyphen_values = true)]
    origin: Option<LocalFrame>,
    /// Random seed (overrides the config file).
    #[arg(long)]
    seed: Option<u64>,
    /// Steps after which to draw the particle cloud in particles.png (0 = the prior),
    /// e.g. `0,5,50`. Default: the prior, steps 5 and 25, localisation and the last step.
    #[arg(long, value_delimiter = ',')]
    snapshots: Option<Vec<usize>>,
    /// Tracker configuration (TOML, or JSON such as a previous run's config.json).
    #[arg(long)]
    config: Option<PathBuf>,
    /// Output folder (default: a new folder under `outputs/`).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Worker threads (default: all cores; at most 4 per core). Results do not depend on it.
    #[arg(long)]
    threads: Option<usize>,
    /// Radio map (`radiomap.geojson` as `footslam survey` writes it, or another tool's with
    /// the same properties) for RF-assisted localisation; needs `--wifi`.
    #[arg(long, requires = "wifi")]
    radiomap: Option<PathBuf>,
    /// WiFi log CSV (`t,bssid,rssi[,ssid,freq]`) of the walk, on the step trace's clock.
    #[arg(long, requires = "radiomap")]
    wifi: Option<PathBuf>,
    /// How scans weight particles after the prior region: `containment` (eqs. 12–13, the
    /// default), `probabilistic` (eq. 14) or `prior-only`.
    #[arg(long, value_enum)]
    rf_mode: Option<RfModeArg>,
    /// The scan-to-cell distance's divisor: `paper` (the number k of access points a cell
    /// hears, eqs. 8 and 11) or `sqrt` (√k). Default: `sqrt`, unless the radio map holds a
    /// threshold calibrated for the paper's distance only.
    #[arg(long, value_enum, requires = "radiomap")]
    rf_distance: Option<RfDistanceArg>,
    /// Region threshold ε, dBm (default: the radio map's calibration for the distance, else
    /// one derived from the map's histograms; the paper used 9.5 with `--rf-distance paper`).
    #[arg(long, requires = "radiomap")]
    rf_epsilon: Option<f64>,
    /// Apply the latest scan at every step where the particles are then (eq. 12 read
    /// literally), instead of once, where they were when the scan was taken.
    #[arg(long, requires = "radiomap")]
    rf_every_step: bool,
    /// Causal answers only: `track.csv` holds each step's estimate as the filter saw it
    /// (from localisation on) and no ancestry is kept. By default `track.csv` is the
    /// smoothed whole-walk answer for every step, and the filtered one is
    /// `track_filtered.csv`.
    #[arg(long)]
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
}

/// Parses `X,Y[,HEADING[,LEVEL]]` ([`StartPose`]'s `FromStr`), for clap.
pub(super) fn parse_start(s: &str) -> Result<StartPose, String> {
    s.parse()
}

/// Runs `footslam track`.
pub fn run(args: Args) -> Result<()> {
    let started = Instant::now();
    let config = tracker_config(&args)?;
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
            if off > SAME_ORIGIN {
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
            let scans = read_scans(wifi_path, &trace)?;
            let matched = check_scans_match(&map, &scans, map_path, wifi_path)?;
            let rf = RfLocaliser::new(&map, &topology, &config.rf).with_context(|| {
                format!(
                    "{}: cannot localise with this radio map",
                    map_path.display()
                )
            })?;
            Some((rf, scans, map_path, wifi_path, matched))
        }
        _ => None,
    };
    let pool = super::common::worker_pool(args.threads)?;
    let threads = pool.current_num_threads();
    let wanted = |step: usize, last: bool| match &args.snapshots {
        Some(list) => list.contains(&step),
        None => step == 0 || AUTO_SNAPSHOTS.contains(&step) || last,
    };

    let filter_started = Instant::now();
    let (reports, snapshots, initial, bytes_per_particle, track, ignored, headings_used, smoothing) =
        pool.install(|| -> Result<_> {
            let mut walker = match &radio {
                Some((rf, scans, ..)) => {
                    let mut t = RfTracker::new(&topology, &config, rf, scans)?;
                    t.set_transition_prior(transitions.as_ref());
                    Walker::Rf(Box::new(t))
                }
                None => {
                    let mut t = Tracker::new(&topology, &config)?;
                    t.set_transition_prior(transitions.as_ref());
                    Walker::Plain(Box::new(t))
                }
            };
            if let Some(tracker) = walker.tracker()
                && tracker.capped_draws() > 0
            {
                warn(&format!(
                    "the prior over {} stopped at kld.max_particles = {} before the KLD bound \
                     was met: the plan is large for an unknown start (each step will be slow \
                     and the prior thin); give --start, a radio map, or raise the cap",
                    plan_path.display(),
                    config.kld.max_particles
                ));
            }
            let mut snapshots = Vec::new();
            if let Some(tracker) = walker.tracker()
                && wanted(0, trace.is_empty())
            {
                snapshots.push(snapshot(tracker, 0, "prior", 0));
            }
            let mut progress = Progress::new(trace.len() as u64, "tracking");
            let mut reports = StepRecords::default();
            let mut track: Vec<TrackPoint> = Vec::new();
            let mut localised_before = false;
            for (i, step) in trace.steps().iter().enumerate() {
                let report = walker.update(step)?;
                let first_fix = report.localised && !localised_before;
                localised_before |= report.localised;
                if localised_before && let Some(c) = report.estimate {
                    track.push(TrackPoint {
                        t: step.t,
                        x: c.x,
                        y: c.y,
                        z: c.z,
                        level: c.level,
                    });
                }
                let k = i + 1;
                let auto_fix = args.snapshots.is_none() && first_fix;
                if (wanted(k, k == trace.len()) || auto_fix)
                    && let Some(tracker) = walker.tracker()
                {
                    let what = if first_fix { "localised" } else { "step" };
                    snapshots.push(snapshot(tracker, k, what, track.len()));
                }
                reports.push(i, step.t, &report);
                progress.inc();
            }
            progress.finish();
            let smoothing = walker.take_smoothed(trace.len()).map(|walk| Smoothing {
                walk,
                path_nodes_peak: walker.tracker().map_or(0, Tracker::path_nodes_peak),
            });
            Ok((
                reports,
                snapshots,
                // The prior's particles: an RF tracker starts at the first scan.
                walker.tracker().map_or(0, Tracker::initial_particles),
                walker.tracker().map_or(0.0, Tracker::bytes_per_particle),
                track,
                walker.tracker().map_or(0, Tracker::measurements_ignored),
                walker.tracker().map_or(0, Tracker::headings_used),
                smoothing,
            ))
        })?;
    let filter_runtime = filter_started.elapsed().as_secs_f64();

    let out = output_dir(args.out, "track");
    let mut folder = RunFolder::create(&out)?;
    folder.protect(
        [&plan_path, &steps_path]
            .into_iter()
            .chain(args.radiomap.iter())
            .chain(args.wifi.iter())
            .chain(args.hexmap.iter())
            .chain(args.config.iter()),
    );
    // The trace's times are all the outputs need of it now.
    let (steps_total, steps_with_heading) = (trace.len(), trace.with_heading());
    let times: Vec<f64> = trace.steps().iter().map(|s| s.t).collect();
    drop(trace);
    // The answer: the smoothed track's certain steps, else (online) the filtered track.
    let smoothed = write_tracks(&folder, &times, smoothing, &track)?;
    let answer = smoothed.as_ref().map_or(&track[..], |(_, a, _)| &a[..]);
    write_track_geojson(&folder.path("track.geojson"), answer, &frame)?;
    let track_points: Vec<(f64, f64, i32)> = track.iter().map(|p| (p.x, p.y, p.level)).collect();
    write_particles_png(
        &folder.path("particles.png"),
        &plan,
        &snapshots,
        &track_points,
    )?;
    if let Some((_, answer, uncertain)) = &smoothed {
        write_track_png(
            &folder.path("track.png"),
            &plan,
            &track_points,
            answer,
            uncertain,
            steps_total,
        )?;
    }
    folder.write_json("config.json", &config)?;

    let first = reports.steps.iter().position(|r| r.localised());
    let particle_steps: usize = reports.steps.iter().map(|r| r.particles()).sum();
    let summary = Summary {
        rf: radio
            .as_ref()
            .map(|(rf, scans, map_path, wifi_path, matched)| RfSummary {
                radiomap_file: map_path.display().to_string(),
                wifi_file: wifi_path.display().to_string(),
                scans: scans.len(),
                scans_matched: *matched,
                mode: rf.config().mode,
                distance: rf.distance(),
                epsilon_dbm: rf.epsilon(),
                epsilon_source: rf.epsilon_source(),
                started_at_step: reports
                    .steps
                    .iter()
                    .position(|r| r.particles() > 0)
                    .map(|i| i + 1),
                measurements_ignored: ignored,
            }),
        headings_used: headings_used > 0,
        steps_with_heading,
        plan_file: plan_path.display().to_string(),
        hexmap_file: args.hexmap.as_ref().map(|p| p.display().to_string()),
        hexmap_hexagons: transitions.as_ref().map(TransitionPrior::len),
        steps_file: steps_path.display().to_string(),
        steps: steps_total,
        steps_to_localise: first.map(|i| i + 1),
        localised_at_t: first.map(|i| times[i]),
        track_rows: track.len(),
        smoothing: smoothed.as_ref().map(|(s, ..)| SmoothingSummary {
            steps_estimated: s.estimated,
            steps_certain: s.certain,
            first_certain_step: s.first_certain,
            path_nodes_peak: s.path_nodes_peak,
            runtime_s: s.runtime_s,
        }),
        particles_initial: initial,
        particles_max: reports
            .steps
            .iter()
            .map(|r| r.particles())
            .max()
            .unwrap_or(initial)
            .max(initial),
        particles_final: reports.steps.last().map_or(initial, |r| r.particles()),
        particles_per_step: &reports.steps,
        clusters_per_step: &reports.steps,
        deaths: reports.recoveries.len(),
        recoveries: &reports.recoveries,
        seed: config.seed,
        threads,
        runtime_s: started.elapsed().as_secs_f64(),
        filter_runtime_s: filter_runtime,
        particle_steps_per_s: particle_steps as f64 / filter_runtime.max(1e-9),
        bytes_per_particle,
        peak_memory_bytes: peak_memory_bytes(),
        plan: PlanStats {
            surfaces: topology.len(),
            walkable_area_m2: topology.total_area(),
            levels: topology.levels(),
        },
        origin: frame,
        version: env!("CARGO_PKG_VERSION"),
    };
    folder.write_json("summary.json", &summary)?;
    let out = folder.commit()?;
    summary.print(&out);
    Ok(())
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

/// The smoothed belief per step of the walk, computed as it is read.
struct Smoothing<'a> {
    walk: SmoothedWalk<'a>,
    path_nodes_peak: usize,
}

/// Writes `track.csv` (and, with smoothing, `track_filtered.csv`) and returns, with
/// smoothing, what the smoother gave, the answer (the smoothed track's certain steps) and
/// the uncertain steps' estimates; `None` online, where the answer is the filtered `track`.
/// The smoothed walk is read once, into track.csv and the answer, then dropped.
fn write_tracks(
    folder: &RunFolder,
    times: &[f64],
    smoothing: Option<Smoothing>,
    track: &[TrackPoint],
) -> Result<Option<SmoothedTracks>> {
    let smoothing_started = Instant::now();
    Ok(match smoothing {
        Some(s) => {
            let mut stats = SmoothedStats::default();
            let mut answer = Vec::new();
            let mut uncertain = Vec::new();
            let points = times
                .iter()
                .zip(s.walk.iter())
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
                    })
                });
            write_smoothed_track(&folder.path("track.csv"), points)?;
            write_track(&folder.path("track_filtered.csv"), track)?;
            stats.path_nodes_peak = s.path_nodes_peak;
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

/// The tracker with or without a radio map.
enum Walker<'a> {
    Plain(Box<Tracker<'a>>),
    Rf(Box<RfTracker<'a>>),
}

impl<'a> Walker<'a> {
    fn tracker(&self) -> Option<&Tracker<'a>> {
        match self {
            Walker::Plain(t) => Some(t),
            Walker::Rf(t) => t.tracker(),
        }
    }

    /// The smoothed belief after each of the walk's `steps` steps (`None` without
    /// smoothing), computed as it is read.
    fn take_smoothed(&mut self, steps: usize) -> Option<SmoothedWalk<'a>> {
        match self {
            // Tracker step k + 1 stands after the walk's step k; step 0 is the prior.
            Walker::Plain(t) => Some(t.take_smoothed()?.on_walk(0, steps)),
            Walker::Rf(t) => t.take_smoothed(),
        }
    }

    fn update(&mut self, step: &footslam::sensor::Step) -> footslam::Result<TrackStep> {
        match self {
            Walker::Plain(t) => t.update(step),
            Walker::Rf(t) => t.update(step),
        }
    }
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
