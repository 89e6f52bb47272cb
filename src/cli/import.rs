//! `footslam import`: convert public dataset recordings (Indoor Location Competition 2.0,
//! IPIN competition logfiles) into footslam's CSV and GeoJSON files.

use super::common::parse_origin;
use anyhow::{Context, Result, bail};
use footslam::filter::StartPose;
use footslam::geometry::LocalFrame;
use footslam::io::RunFolder;
use footslam::io::floor_plan_geojson::{read_floor_plan, write_floor_plan};
use footslam::io::import::ilc_floor::{IlcFloor, PlanReport, Walkable, read_ilc_floor};
use footslam::io::import::ilc_trace::{IlcImportConfig, IlcTrace, read_ilc_trace};
use footslam::io::import::ipin_log::{IpinImportConfig, IpinLog, IpinLogSummary, read_ipin_log};
use footslam::io::import::walkable_share::{WalkableShare, walkable_shares};
use footslam::io::{
    ManifestWalk, Waypoint, write_gps_csv, write_imu, write_walk_manifest, write_waypoints,
    write_wifi,
};
use footslam::map::{FloorPlan, FloorTopology, TopologyConfig};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `footslam import`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(subcommand)]
    source: Source,
}

#[derive(Debug, clap::Subcommand)]
enum Source {
    /// Microsoft Indoor Location Competition 2.0: trace files (`path_data_files`/*.txt) and
    /// a floor folder (`geojson_map.json` + `floor_info.json`).
    Ilc(IlcArgs),
    /// IPIN competition smartphone logfile (`GetSensorData` app, `TAG;AppTimestamp;...`).
    Ipin(IpinArgs),
}

/// The walkable area of an ILC floor plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum WalkableArg {
    /// The whole floor outline, shops included (a walker entering a shop stays on the plan).
    Outline,
    /// The outline minus shops and rooms (public corridors only).
    Corridors,
}

impl From<WalkableArg> for Walkable {
    fn from(w: WalkableArg) -> Self {
        match w {
            WalkableArg::Outline => Walkable::Outline,
            WalkableArg::Corridors => Walkable::Corridors,
        }
    }
}

#[derive(Debug, clap::Args)]
struct IlcArgs {
    /// Trace files (*.txt) or folders of them; repeat or list several. One trace file
    /// writes into --out itself; several (or a folder) write one sub-folder per trace,
    /// named after the file stem.
    #[arg(long, num_args = 1.., value_name = "FILE", help_heading = "Inputs")]
    trace: Vec<PathBuf>,
    /// Floor folder holding `geojson_map.json` and `floor_info.json`: writes floor.geojson.
    #[arg(long, value_name = "DIR", help_heading = "Inputs")]
    floor: Option<PathBuf>,
    /// The plan's walkable area. `corridors` (default): in the sample site's F1 all 237
    /// waypoints of 36 traces lie in the corridors (none in a shop), and the corridors are a
    /// third of the floor, a far stronger constraint for the tracker. The import reports
    /// the share for both choices; use `outline` where walkers enter shops.
    #[arg(long, value_enum, default_value_t = WalkableArg::Corridors, help_heading = "Inputs")]
    walkable: WalkableArg,
    /// WiFi readings last seen longer than this before their scan are stale and dropped,
    /// seconds.
    #[arg(long, default_value_t = IlcImportConfig::default().max_wifi_age_s, value_name = "SECONDS", help_heading = "Inputs")]
    max_wifi_age: f64,
    /// Output folder (written completely or not at all).
    #[arg(short = 'o', long, value_name = "DIR", help_heading = "Outputs")]
    out: PathBuf,
}

#[derive(Debug, clap::Args)]
struct IpinArgs {
    /// The logfile.
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    log: PathBuf,
    /// Origin LAT,LON of the local frame of waypoints.csv (default: the first POSI point).
    #[arg(long, value_parser = parse_origin, value_name = "LAT,LON", help_heading = "Inputs")]
    origin: Option<LocalFrame>,
    /// WiFi readings last seen longer than this before the newest of their scan are stale
    /// and dropped, seconds.
    #[arg(long, default_value_t = IpinImportConfig::default().max_wifi_age_s, value_name = "SECONDS", help_heading = "Inputs")]
    max_wifi_age: f64,
    /// Output folder (written completely or not at all).
    #[arg(short = 'o', long, value_name = "DIR", help_heading = "Outputs")]
    out: PathBuf,
}

/// Runs `footslam import`.
pub fn run(args: Args) -> Result<()> {
    match args.source {
        Source::Ilc(a) => run_ilc(a),
        Source::Ipin(a) => run_ipin(a),
    }
}

/// The trace files named: files as given, folders' `*.txt` in name order.
fn trace_files(paths: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for path in paths {
        if path.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(path)
                .with_context(|| format!("{}", path.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_file() && p.extension().is_some_and(|e| e == "txt"))
                .collect();
            if found.is_empty() {
                bail!("{}: no trace files (*.txt) in this folder", path.display());
            }
            found.sort();
            files.extend(found);
        } else if path.is_file() {
            files.push(path.clone());
        } else {
            bail!("{}: no such trace file or folder", path.display());
        }
    }
    Ok(files)
}

fn stem(path: &Path) -> String {
    path.file_stem()
        .map_or_else(|| "trace".into(), |s| s.to_string_lossy().into_owned())
}

/// A share of waypoints as a percentage and a count.
fn percent(share: WalkableShare) -> String {
    let WalkableShare { on, total } = share;
    if total == 0 {
        "n/a".into()
    } else {
        format!("{:.1} % ({on}/{total})", 100.0 * on as f64 / total as f64)
    }
}

/// The name `--walkable` gives a choice (`outline`, `corridors`).
fn walkable_name(choice: Walkable) -> String {
    format!("{choice:?}").to_lowercase()
}

/// `import ilc`: traces and a floor into one folder.
fn run_ilc(args: IlcArgs) -> Result<()> {
    let started = Instant::now();
    if args.trace.is_empty() && args.floor.is_none() {
        bail!("nothing to import: give --trace (files or folders) and/or --floor");
    }
    let config = IlcImportConfig {
        max_wifi_age_s: args.max_wifi_age,
    };
    let files = trace_files(&args.trace)?;
    let nested = files.len() > 1 || args.trace.iter().any(|p| p.is_dir());
    let traces = read_traces(&files, &config)?;
    let floor = match &args.floor {
        Some(dir) => Some(read_ilc_floor(dir)?),
        None => None,
    };
    let folder = super::common::create_run_folder(&args.out)?;
    let walkable = Walkable::from(args.walkable);
    let (floor_json, plan) = match &floor {
        Some(floor) => {
            let (json, plan) = import_floor(&folder, floor, walkable, &traces)?;
            (json, Some(plan))
        }
        None => (Value::Null, None),
    };
    let mut traces_json = Vec::with_capacity(traces.len());
    for (name, trace) in &traces {
        traces_json.push(write_trace(&folder, name, trace, nested, plan.as_ref())?);
    }
    let manifest = nested && write_manifest(&folder, &traces)?;
    let summary = json!({
        "source": "Microsoft Indoor Location Competition 2.0 (MIT licence, XYZ10 Inc.)",
        "walkable": walkable,
        "max_wifi_age_s": config.max_wifi_age_s,
        "floor": floor_json,
        "traces": traces_json,
        "manifest": manifest.then_some("walks.csv"),
        "seconds": started.elapsed().as_secs_f64(),
    });
    folder.write_json("summary.json", &summary)?;
    let out = folder.commit()?;
    info!(
        "wrote {} trace(s){} to {} in {:.1} s",
        traces.len(),
        if floor.is_some() {
            " and floor.geojson"
        } else {
            ""
        },
        out.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Reads the trace files, each named after its file stem (names must differ: each may get
/// its own folder).
fn read_traces(files: &[PathBuf], config: &IlcImportConfig) -> Result<Vec<(String, IlcTrace)>> {
    let mut names = std::collections::BTreeSet::new();
    for f in files {
        if !names.insert(stem(f)) {
            bail!(
                "two traces are named {}: their folders would clash",
                stem(f)
            );
        }
    }
    let mut traces = Vec::with_capacity(files.len());
    for f in files {
        traces.push((stem(f), read_ilc_trace(f, config)?));
    }
    Ok(traces)
}

/// Writes floor.geojson (checked by reading it back) and says how many of the traces'
/// waypoints lie on each choice of walkable area: the summary's `floor` and the plan.
fn import_floor(
    folder: &RunFolder,
    floor: &IlcFloor,
    walkable: Walkable,
    traces: &[(String, IlcTrace)],
) -> Result<(Value, FloorPlan)> {
    let all_waypoints: Vec<Waypoint> = traces
        .iter()
        .flat_map(|(_, t)| t.waypoints.iter().copied())
        .collect();
    let (plan, report) = floor.plan(walkable)?;
    write_floor_plan(&folder.path("floor.geojson"), &plan, &floor.frame)?;
    check_written_plan(&folder.path("floor.geojson"), &plan)?;
    let shares = walkable_shares(floor, walkable, &plan, &all_waypoints)?;
    print_floor(floor, &report);
    if !all_waypoints.is_empty() {
        print_shares(&shares, walkable);
    }
    let shares_json: serde_json::Map<String, Value> = shares
        .iter()
        .map(|&(choice, share)| (walkable_name(choice), json!(share)))
        .collect();
    let json = json!({
        "file": "floor.geojson",
        "origin": {"lat": floor.frame.lat, "lon": floor.frame.lon},
        "floor": floor.summary,
        "plan": report,
        "waypoints_on_walkable": shares_json,
    });
    Ok((json, plan))
}

/// Writes one trace's files (into its own folder when `nested`), prints its line and
/// returns its entry of the summary's `traces`.
fn write_trace(
    folder: &RunFolder,
    name: &str,
    trace: &IlcTrace,
    nested: bool,
    plan: Option<&FloorPlan>,
) -> Result<Value> {
    let prefix = if nested {
        folder.create_dir(name)?;
        format!("{name}/")
    } else {
        String::new()
    };
    let at = |file: &str| folder.path(&format!("{prefix}{file}"));
    let mut written = vec!["imu.csv"];
    write_imu(&at("imu.csv"), &trace.imu)?;
    if !trace.wifi.is_empty() {
        write_wifi(&at("wifi.csv"), &trace.wifi)?;
        written.push("wifi.csv");
    }
    if let Some(start) = known_start(trace) {
        write_waypoints(&at("waypoints.csv"), &trace.waypoints)?;
        let text = format!("{:.3},{:.3}\n", start.x, start.y);
        folder.write(&format!("{prefix}start.txt"), text.as_bytes())?;
        written.extend(["waypoints.csv", "start.txt"]);
    }
    let share = plan.map(|p| WalkableShare::of(p, &trace.waypoints));
    print_trace(name, trace, share);
    Ok(json!({
        "name": name,
        "folder": if nested { name } else { "." },
        "written": written,
        "summary": trace.summary,
        "waypoints_on_walkable": share,
    }))
}

/// Where a trace starts: its first waypoint (the walker marked it on the floor plan),
/// heading unknown.
fn known_start(trace: &IlcTrace) -> Option<StartPose> {
    trace.waypoints.first().map(|w| StartPose {
        x: w.x,
        y: w.y,
        heading: None,
        level: None,
    })
}

/// `walks.csv`: the manifest of `learn --walks` and `survey --walks` for the traces with a
/// known start, each walk's steps at `NAME/steps/steps.csv` (where `footslam steps --imu
/// NAME/imu.csv --out NAME/steps` writes them), its WiFi log and its start. Returns whether
/// it was written (no trace with waypoints: no manifest).
fn write_manifest(folder: &RunFolder, traces: &[(String, IlcTrace)]) -> Result<bool> {
    let walks: Vec<ManifestWalk> = traces
        .iter()
        .filter_map(|(name, trace)| {
            Some(ManifestWalk {
                steps: PathBuf::from(format!("{name}/steps/steps.csv")),
                gps: None,
                wifi: (!trace.wifi.is_empty()).then(|| format!("{name}/wifi.csv").into()),
                start: Some(known_start(trace)?),
                name: Some(name.clone()),
            })
        })
        .collect();
    if walks.is_empty() {
        return Ok(false);
    }
    write_walk_manifest(&folder.path("walks.csv"), &walks)?;
    info!(
        "walks.csv: {} walks with their starts, for `learn --walks` and `survey --walks` once \
         each has its steps (footslam steps --imu NAME/imu.csv --out NAME/steps)",
        walks.len()
    );
    Ok(true)
}

/// Reads the written plan back: the tracker's topology must accept it and its metres must
/// equal the plan's within 5 cm.
fn check_written_plan(path: &Path, plan: &FloorPlan) -> Result<()> {
    let (back, _) = read_floor_plan(path, None)?;
    FloorTopology::build(&back, &TopologyConfig::default())
        .context("the written floor plan is not accepted by the tracker's topology")?;
    let worst = plan
        .polygons
        .iter()
        .zip(&back.polygons)
        .flat_map(|(a, b)| {
            let (mut a, mut b) = (
                a.polygon.exterior().0.clone(),
                b.polygon.exterior().0.clone(),
            );
            // The writer may turn a ring around (RFC 7946 winding): compare as sets of corners.
            a.sort_by(|p, q| p.x.total_cmp(&q.x).then(p.y.total_cmp(&q.y)));
            b.sort_by(|p, q| p.x.total_cmp(&q.x).then(p.y.total_cmp(&q.y)));
            a.into_iter()
                .zip(b)
                .map(|(p, q)| (p.x - q.x).hypot(p.y - q.y))
                .collect::<Vec<_>>()
        })
        .fold(0.0, f64::max);
    if back.polygons.len() != plan.polygons.len() || worst > 0.05 {
        bail!(
            "{}: the plan read back differs from the plan written ({} vs {} surfaces, corners up to {worst:.3} m apart)",
            path.display(),
            back.polygons.len(),
            plan.polygons.len()
        );
    }
    Ok(())
}

fn print_floor(floor: &IlcFloor, report: &PlanReport) {
    let s = &floor.summary;
    info!(
        "floor.geojson: {} {:.0} m × {:.0} m (the bounding box spans {:.0} m × {:.0} m on the globe), \
         {} shops; walkable = {}: {} surface(s), {:.0} m² of {:.0} m² ({} slivers dropped)",
        s.floor_name.as_deref().unwrap_or("floor"),
        s.width_m,
        s.height_m,
        s.geodesic_width_m,
        s.geodesic_height_m,
        s.shops,
        format!("{:?}", report.walkable).to_lowercase(),
        report.surfaces,
        report.walkable_area_m2,
        s.outline_area_m2,
        report.slivers_dropped
    );
}

/// The share of waypoints on each choice of walkable area, and a warning when too few lie
/// on the chosen one.
fn print_shares(shares: &[(Walkable, WalkableShare)], walkable: Walkable) {
    let text: Vec<String> = shares
        .iter()
        .map(|&(choice, share)| format!("{} {}", walkable_name(choice), percent(share)))
        .collect();
    info!("  waypoints on the walkable area: {}", text.join(", "));
    let chosen = shares.iter().find(|(choice, _)| *choice == walkable);
    if let Some(&(_, share)) = chosen.filter(|(_, share)| share.suspect()) {
        info!(
            "  warning: {} of {} waypoints lie off the walkable area{}",
            share.off(),
            share.total,
            if walkable == Walkable::Corridors {
                " (walkers entered shops?): consider --walkable outline"
            } else {
                ""
            }
        );
    }
}

fn print_trace(name: &str, trace: &IlcTrace, share: Option<WalkableShare>) {
    let s = &trace.summary;
    let total_wifi = s.wifi_readings + s.stale_readings_dropped + s.duplicate_bssids_dropped;
    info!(
        "{name}: {} IMU samples ({:.0} Hz, {:.1} s), {} WiFi scans ({} stale readings of {} dropped), {} waypoints{}",
        s.imu.samples,
        s.imu.rate_hz,
        s.imu.duration_s,
        s.wifi_scans,
        s.stale_readings_dropped,
        total_wifi,
        s.waypoints,
        share.map_or(String::new(), |p| format!(
            ", on the walkable area {}",
            percent(p)
        ))
    );
    print_log_notes(
        s.truncated_last_line,
        "skipped unknown row types",
        &s.unknown_types,
    );
}

/// A log's cut-off last line (skipped) and the kinds of lines it counted but did not convert.
fn print_log_notes(
    truncated_last_line: Option<usize>,
    what: &str,
    counts: &std::collections::BTreeMap<String, usize>,
) {
    if let Some(line) = truncated_last_line {
        info!(
            "  warning: the last line {line} is unterminated (the log was cut off) and was \
             skipped"
        );
    }
    if !counts.is_empty() {
        let list: Vec<String> = counts.iter().map(|(k, v)| format!("{k} ×{v}")).collect();
        info!("  {what}: {}", list.join(", "));
    }
}

/// `import ipin`: one logfile into a folder.
fn run_ipin(args: IpinArgs) -> Result<()> {
    let started = Instant::now();
    let config = IpinImportConfig {
        max_wifi_age_s: args.max_wifi_age,
    };
    let log = read_ipin_log(&args.log, &config)?;
    let frame = log.waypoint_frame(args.origin);
    let folder = super::common::create_run_folder(&args.out)?;
    let written = write_ipin_files(&folder, &log, frame.as_ref())?;
    folder.write_json(
        "summary.json",
        &json!({
            "source": "IPIN competition logfile (GetSensorData format)",
            "log": args.log,
            "origin": frame.map(|f| json!({"lat": f.lat, "lon": f.lon})),
            "written": written,
            "summary": log.summary,
            "seconds": started.elapsed().as_secs_f64(),
        }),
    )?;
    let out = folder.commit()?;
    print_ipin(&args.log, &log.summary);
    if let Some(f) = frame {
        info!("  waypoints.csv frame origin: {:.7},{:.7}", f.lat, f.lon);
    }
    info!("wrote {} to {}", written.join(", "), out.display());
    Ok(())
}

/// Writes the log's files (imu.csv, and wifi.csv, gps.csv and waypoints.csv when it has
/// their data) and returns their names.
fn write_ipin_files(
    folder: &RunFolder,
    log: &IpinLog,
    frame: Option<&LocalFrame>,
) -> Result<Vec<&'static str>> {
    let mut written = vec!["imu.csv"];
    write_imu(&folder.path("imu.csv"), &log.imu)?;
    if !log.wifi.is_empty() {
        write_wifi(&folder.path("wifi.csv"), &log.wifi)?;
        written.push("wifi.csv");
    }
    if !log.gnss.is_empty() {
        write_gps_csv(&folder.path("gps.csv"), &log.gnss)?;
        written.push("gps.csv");
    }
    if let Some(waypoints) = log.waypoints(frame) {
        write_waypoints(&folder.path("waypoints.csv"), &waypoints)?;
        written.push("waypoints.csv");
    }
    Ok(written)
}

/// The logfile's counts and notes.
fn print_ipin(path: &Path, s: &IpinLogSummary) {
    let total_wifi = s.wifi_readings + s.stale_readings_dropped + s.duplicate_bssids_dropped;
    info!(
        "{}: {} IMU samples ({:.0} Hz, {:.1} s{}), {} WiFi scans ({} stale readings of {} dropped), \
         {} GNSS fixes, {} positions",
        path.display(),
        s.imu.samples,
        s.imu.rate_hz,
        s.imu.duration_s,
        if s.imu_channels.is_empty() {
            String::new()
        } else {
            format!("; with {}", s.imu_channels.join(", "))
        },
        s.wifi_scans,
        s.stale_readings_dropped,
        total_wifi,
        s.gnss_fixes,
        s.positions
    );
    print_log_notes(
        s.lines.truncated_last_line,
        "not converted",
        &s.skipped_tags,
    );
}
