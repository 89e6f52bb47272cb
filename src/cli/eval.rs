//! `footslam eval`: position error of a track against the truth.

use super::common::{parse_origin, read_config, require_file};
use super::eval_picture::{EvalPicture, Reference};
use anyhow::{Context, Result, bail};
use footslam::eval::{
    Alignment, ErrorReport, PlanOverlap, WaypointDeadReckoning, WaypointErrors,
    dead_reckoning_track, plan_overlap, position_errors, reproject, track_floor_accuracy,
    walkable_fraction, waypoint_dead_reckoning, waypoint_errors,
};
use footslam::geometry::LocalFrame;
use footslam::io::floor_plan_geojson::read_floor_plan;
use footslam::io::map_geojson::read_map_geojson;
use footslam::io::{
    TimedPoint, read_certain_trajectory, read_steps, read_track, read_trajectory, read_waypoints,
};
use footslam::pipeline::SAME_ORIGIN_M;
use footslam::sensor::StepTrace;
use std::path::{Path, PathBuf};

/// Arguments of `footslam eval`: one reference, `--truth` or `--waypoints`.
#[derive(Debug, clap::Args)]
#[command(group(
    clap::ArgGroup::new("reference")
        .required(true)
        .args(["truth", "waypoints"])
))]
pub struct Args {
    /// Ground truth CSV with `t,x,y` columns (e.g. the simulator's truth.csv).
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    truth: Option<PathBuf>,
    /// Sparse ground truth `t,x,y[,level]` (e.g. an importer's waypoints.csv): the error at
    /// each waypoint, the track interpolated at its time. With `--steps`, dead reckoning
    /// starts at the first waypoint (with the steps' absolute heading when they carry one,
    /// else rigidly aligned).
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    waypoints: Option<PathBuf>,
    /// Estimated track CSV with `t,x,y` columns (e.g. learn's or track's track.csv); with
    /// `z` and `level` columns in both files, the share on the right floor is reported too.
    /// Rows a `certain` column marks 0 (track's smoothed steps whose place the walk leaves
    /// ambiguous) are left out and counted, unless `--all-rows`.
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    track: PathBuf,
    /// Score every row of the track, uncertain ones (`certain = 0`) too: the answer a user
    /// gets at every step, however sure.
    #[arg(long, help_heading = "Filter")]
    all_rows: bool,
    /// Alignment before measuring: `none` (absolute) or `rigid` (best rotation and
    /// translation, for maps learned without absolute anchors).
    #[arg(long, value_enum, default_value = "none", help_heading = "Filter")]
    align: AlignArg,
    /// Step trace of the walk: also report dead reckoning's error, for comparison.
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    steps: Option<PathBuf>,
    /// Learned map (map.geojson): with `--plan`, also report the visit-weighted fraction of
    /// its hexagons in walkable space (after the track's alignment).
    #[arg(long, requires = "plan", value_name = "FILE", help_heading = "Inputs")]
    map: Option<PathBuf>,
    /// Learned walkable plan (learn's plan.geojson or `merged_plan.geojson`, or plan's): with
    /// `--plan`, also report its precision and its recall of the space the walk visited
    /// (the true walkable area within 0.75 m of the truth), by area, after the track's
    /// alignment.
    #[arg(long, requires = "plan", value_name = "FILE", help_heading = "Inputs")]
    learned_plan: Option<PathBuf>,
    /// Floor plan GeoJSON of the building, in the truth's frame (e.g. simulate's
    /// floor.geojson), for `--map` or `--learned-plan`.
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    plan: Option<PathBuf>,
    /// WGS84 origin of the local frame, `LAT,LON`; overrides the `--plan`'s own `origin`.
    #[arg(long, value_parser = parse_origin, allow_hyphen_values = true, value_name = "LAT,LON", help_heading = "Inputs")]
    origin: Option<LocalFrame>,
    /// Also draw the track (after the alignment) over the truth or the waypoints into this
    /// PNG, on the `--plan` when given (one panel per floor), with the `--learned-plan`'s
    /// outlines aligned as the track is.
    #[arg(long, value_name = "FILE", help_heading = "Outputs")]
    picture: Option<PathBuf>,
    /// Print JSON instead of a table.
    #[arg(long, help_heading = "Outputs")]
    json: bool,
}

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
enum AlignArg {
    None,
    Rigid,
}

impl From<AlignArg> for Alignment {
    fn from(a: AlignArg) -> Self {
        match a {
            AlignArg::None => Alignment::None,
            AlignArg::Rigid => Alignment::Rigid,
        }
    }
}

/// Picks one figure out of an error report.
type Statistic = fn(&ErrorReport) -> f64;

/// "Visited space" for `--learned-plan`: the true walkable area within this many metres of
/// the truth — the hexagon radius (0.5 m, where the feet went) plus the plan's grow
/// (0.25 m, the body's half-width).
const VISITED_REACH: f64 = 0.75;
/// Side of the squares `--learned-plan` measures areas on, metres.
const OVERLAP_RESOLUTION: f64 = 0.05;

/// Runs `footslam eval`.
pub fn run(args: Args) -> Result<()> {
    require_file(&args.track, "track file")?;
    let Some(truth_path) = args.truth.clone() else {
        return run_waypoints(args);
    };
    require_file(&truth_path, "truth file")?;
    let truth = read_trajectory(&truth_path)?;
    let (mut track, uncertain) = read_scored_rows(&args)?;
    let reprojected = reproject_to_truth(&truth_path, &args.track, &mut track);
    let alignment = Alignment::from(args.align);
    let report = position_errors(&truth, &track, alignment)?;
    let dead_reckoning = match &args.steps {
        Some(path) => {
            let dr = dead_reckoning_track(&read_step_trace(path)?);
            Some(position_errors(&truth, &dr, alignment)?)
        }
        None => None,
    };
    // Both files with `z` and `level` columns (truth.csv, track's track.csv): floor accuracy.
    let (truth_rows, track_rows) = (read_track(&truth_path).ok(), read_track(&args.track).ok());
    let floors = match (&truth_rows, &track_rows) {
        (Some(truth), Some(track)) => track_floor_accuracy(truth, track),
        _ => None,
    };
    if args.plan.is_some()
        && args.map.is_none()
        && args.learned_plan.is_none()
        && args.picture.is_none()
    {
        bail!("--plan is for --map, --learned-plan or --picture: give one of them");
    }
    // The truth with its levels when it has a `level` column (0 otherwise).
    let reference: Vec<(f64, f64, i32)> = match &truth_rows {
        Some(t) => t.iter().map(|p| (p.x, p.y, p.level)).collect(),
        None => truth.iter().map(|p| (p.x, p.y, 0)).collect(),
    };
    let picture = Reference {
        points: &reference,
        label: "true path",
        track_rows: track_rows.as_deref(),
    };
    write_picture(&args, &track, picture, &report)?;
    let overlap = learned_plan_overlap(&args, &reference, &report)?;
    let walkable = map_walkable_fraction(&args, &report)?;
    let outcome = Outcome {
        report,
        dead_reckoning,
        walkable,
        overlap,
        floors,
        reprojected,
        uncertain,
    };
    if args.json {
        print_json(&outcome)
    } else {
        print_summary(&outcome);
        Ok(())
    }
}

/// `--picture`: the track over `reference`, after the alignment of `report`.
fn write_picture(
    args: &Args,
    track: &[TimedPoint],
    reference: Reference,
    report: &ErrorReport,
) -> Result<()> {
    let Some(out) = &args.picture else {
        return Ok(());
    };
    if let Some(plan) = &args.plan {
        require_file(plan, "floor plan")?;
    }
    EvalPicture {
        track,
        reference,
        report,
        plan: args.plan.as_deref(),
        origin: args.origin,
        learned_plan: args.learned_plan.as_deref(),
    }
    .write(out)
    .with_context(|| format!("writing --picture {}", out.display()))
}

/// What `eval --truth` found, to print.
struct Outcome {
    /// The track's errors.
    report: ErrorReport,
    /// Dead reckoning's errors, with `--steps`.
    dead_reckoning: Option<ErrorReport>,
    /// The map's visit-weighted walkable fraction, with `--map`.
    walkable: Option<f64>,
    /// The learned plan's overlap with the true one, with `--learned-plan`.
    overlap: Option<PlanOverlap>,
    /// The share of track points on the right floor, when both files have levels.
    floors: Option<f64>,
    /// The track's run origin and the truth's, when the track was moved between them.
    reprojected: Option<(LocalFrame, LocalFrame)>,
    /// Uncertain track rows left out.
    uncertain: usize,
}

/// Runs anchored to the world (learn --gps) put their local frame's origin at the first fix,
/// not where the simulator put the truth's: moves `track` into the truth's frame when their
/// origins differ, and returns (the track's origin, the truth's).
fn reproject_to_truth(
    truth: &Path,
    track_path: &Path,
    track: &mut [TimedPoint],
) -> Option<(LocalFrame, LocalFrame)> {
    let truth_frame = run_origin(truth, false)?;
    let track_frame = run_origin(track_path, true)?;
    if truth_frame.distance_to(&track_frame) <= SAME_ORIGIN_M {
        return None;
    }
    reproject(track, &track_frame, &truth_frame);
    Some((track_frame, truth_frame))
}

/// The step trace of `--steps`.
fn read_step_trace(path: &Path) -> Result<StepTrace> {
    require_file(path, "step trace")?;
    Ok(read_steps(path)?)
}

/// `--learned-plan` with `--plan`: the learned plan's overlap with the true one, after the
/// track's alignment.
fn learned_plan_overlap(
    args: &Args,
    visited: &[(f64, f64, i32)],
    report: &ErrorReport,
) -> Result<Option<PlanOverlap>> {
    let (Some(learned), Some(plan)) = (&args.learned_plan, &args.plan) else {
        return Ok(None);
    };
    require_file(learned, "learned plan")?;
    require_file(plan, "floor plan")?;
    let (learned, _) = read_floor_plan(learned, args.origin)?;
    let (plan, _) = read_floor_plan(plan, args.origin)?;
    // Levels from the truth's `level` column when it has one, compared by number: a learned
    // plan numbers its floors from the walks' start levels (`learn --start X,Y,HEADING,LEVEL`;
    // 0 when not given).
    let transform = report.transform.as_ref();
    Ok(Some(plan_overlap(
        &learned,
        &plan,
        visited,
        0,
        transform,
        VISITED_REACH,
        OVERLAP_RESOLUTION,
    )?))
}

/// `--map` with `--plan`: the map's visit-weighted fraction in walkable space, after the
/// track's alignment.
fn map_walkable_fraction(args: &Args, report: &ErrorReport) -> Result<Option<f64>> {
    let (Some(map), Some(plan)) = (&args.map, &args.plan) else {
        return Ok(None);
    };
    require_file(map, "map")?;
    require_file(plan, "floor plan")?;
    let (map, _) = read_map_geojson(map)?;
    let (plan, _) = read_floor_plan(plan, args.origin)?;
    Ok(Some(walkable_fraction(
        &map,
        &plan,
        report.transform.as_ref(),
    )))
}

/// Prints `eval --truth --json`.
fn print_json(o: &Outcome) -> Result<()> {
    let value = serde_json::json!({
        "track": o.report,
        "dead_reckoning": o.dead_reckoning,
        "walkable_fraction": o.walkable,
        "plan_overlap": o.overlap,
        "floor_accuracy": o.floors,
        "track_reprojected_from": o.reprojected.map(|(from, _)| from),
        "uncertain_rows_left_out": o.uncertain,
    });
    outln!("{}", serde_json::to_string_pretty(&value)?);
    Ok(())
}

/// Prints `eval --truth` as a table and lines.
fn print_summary(o: &Outcome) {
    if let Some((from, to)) = o.reprojected {
        outln!(
            "track moved from its run's origin ({:.6}, {:.6}) to the truth's ({:.6}, {:.6})",
            from.lat,
            from.lon,
            to.lat,
            to.lon
        );
    }
    note_uncertain(o.uncertain);
    print_table(&o.report, o.dead_reckoning.as_ref());
    if let Some(f) = o.floors {
        outln!("right floor {:.1} % of track points", 100.0 * f);
    }
    if let Some(w) = o.walkable {
        outln!("walkable {:.1} % of visit-weighted map hexagons", 100.0 * w);
    }
    if let Some(o) = o.overlap {
        outln!(
            "learned plan: precision {:.3}, recall of visited space {:.3} ({:.0} m² learned, {:.0} m² visited)",
            o.precision,
            o.recall,
            o.learned_m2,
            o.visited_m2
        );
    }
}

/// The track's rows to score (all with `--all-rows`, else the certain ones) and the number
/// of uncertain rows left out.
fn read_scored_rows(args: &Args) -> Result<(Vec<TimedPoint>, usize)> {
    Ok(if args.all_rows {
        (read_trajectory(&args.track)?, 0)
    } else {
        read_certain_trajectory(&args.track)?
    })
}

/// Says how many smoothed rows were left out as uncertain (none said when none).
fn note_uncertain(rows: usize) {
    if rows > 0 {
        outln!("{rows} uncertain track rows (certain = 0) left out");
    }
}

/// Prints the error table, with dead reckoning's beside the track's when given.
fn print_table(report: &ErrorReport, dead_reckoning: Option<&ErrorReport>) {
    let rows: [(&str, Statistic); 7] = [
        ("p50", |r| r.p50),
        ("p75", |r| r.p75),
        ("p90", |r| r.p90),
        ("p95", |r| r.p95),
        ("max", |r| r.max),
        ("mean", |r| r.mean),
        ("rmse", |r| r.rmse),
    ];
    match dead_reckoning {
        Some(dr) => {
            outln!("{:<6} {:>10} {:>15}", "", "track", "dead reckoning");
            outln!("{:<6} {:>10} {:>15}", "points", report.n, dr.n);
            for (name, f) in rows {
                outln!("{name:<6} {:>8.3} m {:>13.3} m", f(report), f(dr));
            }
        }
        None => {
            outln!("{:<6} {:>10}", "points", report.n);
            for (name, f) in rows {
                outln!("{name:<6} {:>8.3} m", f(report));
            }
        }
    }
}

/// `eval --waypoints`: errors at sparse ground-truth points.
fn run_waypoints(args: Args) -> Result<()> {
    let Some(path) = &args.waypoints else {
        bail!("give --truth or --waypoints");
    };
    if args.map.is_some() || args.learned_plan.is_some() {
        bail!(
            "--map and --learned-plan need a dense --truth (the visited space); \
             with --waypoints give the waypoints file as --truth instead"
        );
    }
    if args.plan.is_some() && args.picture.is_none() {
        bail!("--plan with --waypoints is for --picture: give --picture FILE");
    }
    require_file(path, "waypoints file")?;
    let waypoints = read_waypoints(path)?;
    let (track, uncertain) = read_scored_rows(&args)?;
    let alignment = Alignment::from(args.align);
    let errors = waypoint_errors(&waypoints, &track, alignment)
        .with_context(|| format!("{} against {}", args.track.display(), path.display()))?;
    let reference: Vec<(f64, f64, i32)> = waypoints
        .iter()
        .map(|w| (w.x, w.y, w.level.unwrap_or(0)))
        .collect();
    let track_rows = args
        .picture
        .as_ref()
        .and_then(|_| read_track(&args.track).ok());
    let picture = Reference {
        points: &reference,
        label: "waypoints",
        track_rows: track_rows.as_deref(),
    };
    write_picture(&args, &track, picture, &errors.report)?;
    let dead_reckoning = match &args.steps {
        Some(steps) => {
            let trace = read_step_trace(steps)?;
            Some(waypoint_dead_reckoning(&waypoints, &trace, alignment)?)
        }
        None => None,
    };
    if args.json {
        print_waypoints_json(&errors, dead_reckoning.as_ref(), uncertain)
    } else {
        print_waypoints_summary(&errors, dead_reckoning.as_ref(), uncertain);
        Ok(())
    }
}

/// Prints `eval --waypoints --json`.
fn print_waypoints_json(
    errors: &WaypointErrors,
    dead_reckoning: Option<&WaypointDeadReckoning>,
    uncertain: usize,
) -> Result<()> {
    let heading = |d: &WaypointDeadReckoning| match d.absolute_heading {
        true => "absolute",
        false => "rigidly aligned",
    };
    let value = serde_json::json!({
        "track": errors.report,
        "waypoints": errors.points,
        "held": errors.held,
        "dead_reckoning": dead_reckoning.map(|d| &d.errors.report),
        "dead_reckoning_waypoints": dead_reckoning.map(|d| &d.errors.points),
        "dead_reckoning_heading": dead_reckoning.map(heading),
        "uncertain_rows_left_out": uncertain,
    });
    outln!("{}", serde_json::to_string_pretty(&value)?);
    Ok(())
}

/// Prints `eval --waypoints` as a table and lines.
fn print_waypoints_summary(
    errors: &WaypointErrors,
    dead_reckoning: Option<&WaypointDeadReckoning>,
    uncertain: usize,
) {
    note_uncertain(uncertain);
    print_table(&errors.report, dead_reckoning.map(|d| &d.errors.report));
    if errors.held > 0 {
        outln!(
            "{} waypoints after the track's last step compared with its end (the walker stands)",
            errors.held
        );
    }
    if errors.report.skipped > 0 {
        outln!(
            "{} waypoints outside the track's time span were skipped",
            errors.report.skipped
        );
    }
    if dead_reckoning.is_some_and(|d| !d.absolute_heading) {
        outln!("dead reckoning rigidly aligned: the steps carry no absolute heading");
    }
}

/// The WGS84 origin recorded in the `summary.json` beside a run's CSV file (simulate, learn,
/// track and survey write one), or for a walk of a batch (`walk-N/`) in the batch's
/// `summary.json` one folder up, if there is one. With `anchored`, only for runs whose local
/// frame is tied to the world — `learn --gps` or a floor plan (`track`) — and not for a walk
/// learned from steps alone, which starts at (0, 0) whatever its origin.
fn run_origin(csv: &Path, anchored: bool) -> Option<LocalFrame> {
    let read = |folder: &Path| read_config::<serde_json::Value>(&folder.join("summary.json")).ok();
    let folder = csv.parent()?;
    let (value, walk) = match read(folder) {
        Some(value) => (value, None),
        None => {
            // A batch's walk: `walks[N − 1]` of the batch's summary holds its own figures.
            let n: usize = folder
                .file_name()?
                .to_str()?
                .strip_prefix("walk-")?
                .parse()
                .ok()?;
            (read(folder.parent()?)?, Some(n.checked_sub(1)?))
        }
    };
    let record = match walk {
        Some(i) => value.get("walks")?.get(i)?,
        None => &value,
    };
    let tied = |key: &str| record.get(key).is_some_and(|v| !v.is_null());
    if anchored && !(tied("gps_file") || tied("plan_file")) {
        return None;
    }
    footslam::io::geojson_file::read_origin(value.get("origin")?).ok()
}
