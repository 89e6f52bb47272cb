//! `footslam eval`: position error of a track against the truth.

use super::common::{SAME_ORIGIN, parse_origin, read_config, require_file};
use anyhow::Result;
use footslam::dataset::floor_plan_geojson::read_floor_plan;
use footslam::dataset::{TimedPoint, read_steps, read_track, read_trajectory};
use footslam::eval::{Alignment, ErrorReport, floor_accuracy, position_errors, walkable_fraction};
use footslam::export::map_geojson::read_map_geojson;
use footslam::geometry::LocalFrame;
use std::path::{Path, PathBuf};

/// Arguments of `footslam eval`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Ground truth CSV with `t,x,y` columns (e.g. the simulator's truth.csv).
    #[arg(long)]
    truth: PathBuf,
    /// Estimated track CSV with `t,x,y` columns (e.g. learn's or track's track.csv); with
    /// `z` and `level` columns in both files, the share on the right floor is reported too.
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
    /// Floor plan GeoJSON of the building, in the truth's frame (e.g. simulate's floor.geojson).
    #[arg(long, requires = "map")]
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

/// Picks one figure out of an error report.
type Statistic = fn(&ErrorReport) -> f64;

/// Runs `footslam eval`.
pub fn run(args: Args) -> Result<()> {
    require_file(&args.truth, "truth file")?;
    require_file(&args.track, "track file")?;
    let truth = read_trajectory(&args.truth)?;
    let mut track = read_trajectory(&args.track)?;
    // Runs anchored to the world (learn --gps) put their local frame's origin at the first
    // fix, not where the simulator put the truth's: compare in the truth's frame.
    let reprojected = match (
        run_origin(&args.truth, false),
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
    let alignment = match args.align {
        AlignArg::None => Alignment::None,
        AlignArg::Rigid => Alignment::Rigid,
    };
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
    let floors = match (read_track(&args.truth), read_track(&args.track)) {
        (Ok(truth), Ok(track)) => {
            let levels = |v: &[footslam::dataset::TrackPoint]| -> Vec<(f64, i32)> {
                v.iter().map(|p| (p.t, p.level)).collect()
            };
            floor_accuracy(&levels(&truth), &levels(&track))
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
            "floor_accuracy": floors,
            "track_reprojected_from": reprojected.map(|(from, _)| from),
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
        let rows: [(&str, Statistic); 6] = [
            ("p50", |r| r.p50),
            ("p75", |r| r.p75),
            ("p95", |r| r.p95),
            ("max", |r| r.max),
            ("mean", |r| r.mean),
            ("rmse", |r| r.rmse),
        ];
        match &dead_reckoning {
            Some(dr) => {
                outln!("{:<6} {:>10} {:>15}", "", "track", "dead reckoning");
                outln!("{:<6} {:>10} {:>15}", "points", report.n, dr.n);
                for (name, f) in rows {
                    outln!("{name:<6} {:>8.3} m {:>13.3} m", f(&report), f(dr));
                }
            }
            None => {
                outln!("{:<6} {:>10}", "points", report.n);
                for (name, f) in rows {
                    outln!("{name:<6} {:>8.3} m", f(&report));
                }
            }
        }
        if let Some(f) = floors {
            outln!("right floor {:.1} % of track points", 100.0 * f);
        }
        if let Some(w) = walkable {
            outln!("walkable {:.1} % of visit-weighted map hexagons", 100.0 * w);
        }
    }
    Ok(())
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
    footslam::dataset::geojson_file::read_origin(value.get("origin")?).ok()
}
