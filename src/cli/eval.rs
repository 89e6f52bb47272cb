//! `footslam eval`: position error of a track against the truth.

use super::common::{SAME_ORIGIN, parse_origin, read_config, require_file};
use anyhow::{Context, Result};
use footslam::eval::{
    Alignment, ErrorReport, floor_accuracy, plan_overlap, position_errors, walkable_fraction,
    waypoint_errors,
};
use footslam::geometry::LocalFrame;
use footslam::io::floor_plan_geojson::read_floor_plan;
use footslam::io::map_geojson::read_map_geojson;
use footslam::io::{
    TimedPoint, read_certain_trajectory, read_steps, read_track, read_trajectory, read_waypoints,
};
use std::path::{Path, PathBuf};

/// Arguments of `footslam eval`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Ground truth CSV with `t,x,y` columns (e.g. the simulator's truth.csv).
    #[arg(
        long,
        required_unless_present = "waypoints",
        conflicts_with = "waypoints"
    )]
    truth: Option<PathBuf>,
    /// Sparse ground truth `t,x,y[,level]` (e.g. an importer's waypoints.csv): the error at
    /// each waypoint, the track interpolated at its time. With `--steps`, dead reckoning
    /// starts at the first waypoint (with the steps' absolute heading when they carry one,
    /// else rigidly aligned).
    #[arg(long)]
    waypoints: Option<PathBuf>,
    /// Estimated track CSV with `t,x,y` columns (e.g. learn's or track's track.csv); with
    /// `z` and `level` columns in both files, the share on the right floor is reported too.
    /// Rows a `certain` column marks 0 (track's smoothed steps whose place the walk leaves
    /// ambiguous) are left out and counted.
    #[arg(long)]
    track: PathBuf,
    /// Alignment before measuring: `none` (absolute) or `rigid` (best rotation and
    /// translation, for maps learned without absolute anchors).
    #[arg(long, value_enum, default_value = "none")]
    align: AlignArg,
    /// Step trace of the walk: also report dead reckoning's error, for comparison.
    #[arg(long)]
    steps: Option<PathBuf>,
    /// Learned map (map.geojson): with `--plan`, also report the visit-weighted fraction of
    /// its hexagons in walkable space (after the track's alignment).
    #[arg(long, requires = "plan")]
    map: Option<PathBuf>,
    /// Learned walkable plan (learn's plan.geojson or merged_plan.geojson, or plan's): with
    /// `--plan`, also report its precision and its recall of the space the walk visited
    /// (the true walkable area within 0.75 m of the truth), by area, after the track's
    /// alignment.
    #[arg(long, requires = "plan")]
    learned_plan: Option<PathBuf>,
    /// Floor plan GeoJSON of the building, in the truth's frame (e.g. simulate's
    /// floor.geojson), for `--map` or `--learned-plan`.
    #[arg(long)]
    plan: Option<PathBuf>,
    /// WGS84 origin of the local frame, `LAT,LON`; overrides the `--plan`'s own `origin`.
    #[arg(long, value_parser = parse_origin, allow_hyphen_values = true)]
    origin: Option<LocalFrame>,
    /// Print JSON instead of a table.
    #[arg(long)]
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
    let (mut track, uncertain) = read_certain_trajectory(&args.track)?;
    // Runs anchored to the world (learn --gps) put their local frame's origin at the first
    // fix, not where the simulator put the truth's: compare in the truth's frame.
    let reprojected = match (
        run_origin(&truth_path, false),
        run_origin(&args.track, true),
    ) {
        (Some(truth_frame), Some(track_frame))
            if truth_frame.distance_to(&track_frame) > SAME_ORIGIN =>
        {
            for p in &mut track {
                let (lon, lat) = track_frame.to_lon_lat(p.x, p.y);
                (p.x, p.y) = truth_frame.to_local(lon, lat);
            }
            Some((track_frame, truth_frame))
        }
        _ => None,
    };
    let alignment = Alignment::from(args.align);
    let report = position_errors(&truth, &track, alignment)?;
    let dead_reckoning = match &args.steps {
        Some(path) => {
            require_file(path, "step trace")?;
            let trace = read_steps(path)?;
            let poses = trace.dead_reckon(Default::default());
            let dr: Vec<TimedPoint> = trace
                .steps()
                .iter()
                .zip(poses)
                .map(|(s, p)| TimedPoint {
                    t: s.t,
                    x: p.x,
                    y: p.y,
                })
                .collect();
            Some(position_errors(&truth, &dr, alignment)?)
        }
        None => None,
    };
    // Both files with `z` and `level` columns (truth.csv, track's track.csv): floor accuracy.
    let floors = match (read_track(&truth_path), read_track(&args.track)) {
        (Ok(truth), Ok(track)) => {
            let levels = |v: &[footslam::io::TrackPoint]| -> Vec<(f64, i32)> {
                v.iter().map(|p| (p.t, p.level)).collect()
            };
            floor_accuracy(&levels(&truth), &levels(&track))
        }
        _ => None,
    };
    if args.plan.is_some() && args.map.is_none() && args.learned_plan.is_none() {
        anyhow::bail!("--plan is for --map or --learned-plan: give one of them");
    }
    let overlap = match (&args.learned_plan, &args.plan) {
        (Some(learned), Some(plan)) => {
            require_file(learned, "learned plan")?;
            require_file(plan, "floor plan")?;
            let (learned, _) = read_floor_plan(learned, args.origin)?;
            let (plan, _) = read_floor_plan(plan, args.origin)?;
            // Levels from the truth's `level` column when it has one, compared by number:
            // a learned plan numbers its floors from the walks' start levels (`learn
            // --start X,Y,HEADING,LEVEL`; 0 when not given).
            let visited: Vec<(f64, f64, i32)> = match read_track(&truth_path) {
                Ok(t) => t.iter().map(|p| (p.x, p.y, p.level)).collect(),
                Err(_) => truth.iter().map(|p| (p.x, p.y, 0)).collect(),
            };
            Some(plan_overlap(
                &learned,
                &plan,
                &visited,
                0,
                report.transform.as_ref(),
                VISITED_REACH,
                OVERLAP_RESOLUTION,
            )?)
        }
        _ => None,
    };
    let walkable = match (&args.map, &args.plan) {
        (Some(map), Some(plan)) => {
            require_file(map, "map")?;
            require_file(plan, "floor plan")?;
            let (map, _) = read_map_geojson(map)?;
            let (plan, _) = read_floor_plan(plan, args.origin)?;
            Some(walkable_fraction(&map, &plan, report.transform.as_ref()))
        }
        _ => None,
    };
    if args.json {
        let value = serde_json::json!({
            "track": report,
            "dead_reckoning": dead_reckoning,
            "walkable_fraction": walkable,
            "plan_overlap": overlap,
            "floor_accuracy": floors,
            "track_reprojected_from": reprojected.map(|(from, _)| from),
            "uncertain_rows_left_out": uncertain,
        });
        outln!("{}", serde_json::to_string_pretty(&value)?);
    } else {
        if let Some((from, to)) = reprojected {
            outln!(
                "track moved from its run's origin ({:.6}, {:.6}) to the truth's ({:.6}, {:.6})",
                from.lat,
                from.lon,
                to.lat,
                to.lon
            );
        }
        note_uncertain(uncertain);
        print_table(&report, dead_reckoning.as_ref());
        if let Some(f) = floors {
            outln!("right floor {:.1} % of track points", 100.0 * f);
        }
        if let Some(w) = walkable {
            outln!("walkable {:.1} % of visit-weighted map hexagons", 100.0 * w);
        }
        if let Some(o) = overlap {
            outln!(
                "learned plan: precision {:.3}, recall of visited space {:.3} ({:.0} m² learned, {:.0} m² visited)",
                o.precision,
                o.recall,
                o.learned_m2,
                o.visited_m2
            );
        }
    }
    Ok(())
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
        anyhow::bail!("give --truth or --waypoints");
    };
    if args.map.is_some() || args.learned_plan.is_some() || args.plan.is_some() {
        anyhow::bail!(
            "--map, --learned-plan and --plan need a dense --truth (the visited space); \
             with --waypoints give the waypoints file as --truth instead"
        );
    }
    require_file(path, "waypoints file")?;
    let waypoints = read_waypoints(path)?;
    let (track, uncertain) = read_certain_trajectory(&args.track)?;
    let alignment = Alignment::from(args.align);
    let errors = waypoint_errors(&waypoints, &track, alignment)
        .with_context(|| format!("{} against {}", args.track.display(), path.display()))?;
    let dead_reckoning = match &args.steps {
        Some(steps) => {
            require_file(steps, "step trace")?;
            let trace = read_steps(steps)?;
            let absolute = trace.steps().first().and_then(|s| s.heading).is_some();
            let dr = dead_reckoning_from(&trace, &waypoints[0], absolute);
            let align = if absolute {
                alignment
            } else {
                Alignment::Rigid
            };
            Some((waypoint_errors(&waypoints, &dr, align)?, absolute))
        }
        None => None,
    };
    if args.json {
        let value = serde_json::json!({
            "track": errors.report,
            "waypoints": errors.points,
            "held": errors.held,
            "dead_reckoning": dead_reckoning.as_ref().map(|(d, _)| &d.report),
            "dead_reckoning_waypoints": dead_reckoning.as_ref().map(|(d, _)| &d.points),
            "dead_reckoning_heading": dead_reckoning.as_ref().map(|(_, a)| if *a { "absolute" } else { "rigidly aligned" }),
            "uncertain_rows_left_out": uncertain,
        });
        outln!("{}", serde_json::to_string_pretty(&value)?);
    } else {
        note_uncertain(uncertain);
        print_table(
            &errors.report,
            dead_reckoning.as_ref().map(|(d, _)| &d.report),
        );
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
        if let Some((_, false)) = dead_reckoning {
            outln!("dead reckoning rigidly aligned: the steps carry no absolute heading");
        }
    }
    Ok(())
}

/// Dead reckoning placed at the first waypoint at its time: the walker stands at the start
/// until the first step; with `absolute`, the heading before the first step is the first
/// step's measured heading less its turn, so the path follows the measured headings.
fn dead_reckoning_from(
    trace: &footslam::sensor::StepTrace,
    first: &footslam::io::Waypoint,
    absolute: bool,
) -> Vec<TimedPoint> {
    let steps = trace.steps();
    let heading = match steps.first() {
        Some(s) if absolute => s.heading.unwrap_or(0.0) - s.dheading,
        _ => 0.0,
    };
    let start = footslam::geometry::Pose2 {
        x: 0.0,
        y: 0.0,
        heading,
    };
    let t0 = steps.first().map_or(first.t, |s| first.t.min(s.t - 1e-3));
    let mut points = vec![TimedPoint {
        t: t0,
        x: 0.0,
        y: 0.0,
    }];
    points.extend(
        steps
            .iter()
            .zip(trace.dead_reckon(start))
            .map(|(s, p)| TimedPoint {
                t: s.t,
                x: p.x,
                y: p.y,
            }),
    );
    // Shift so that the path passes the first waypoint at its time.
    if let Some((x, y)) = footslam::eval::position_error::interpolate_at(&points, first.t) {
        for p in &mut points {
            p.x += first.x - x;
            p.y += first.y - y;
        }
    }
    points
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
