//! What the accuracy tests share: walks learned and tracked through the library
//! (`footslam::pipeline`), as the command line runs them, read back as the rows its track
//! files hold, and scored against the simulator's truth (`footslam::eval`).
//!
//! The filters run on what the simulator's files record (`recorded*`): the steps as
//! `steps.csv` holds them (millimetres, microradians), GPS fixes, WiFi scans, floor plans
//! and radio maps as their files do, scored against the truth as `truth.csv` holds it. The
//! tests' figures and thresholds were measured on that data when they ran the command line
//! on the files, and a particle filter's run moves when its input moves by a millimetre.
//!
//! A module of the accuracy tests' binary (`tests/accuracy/main.rs`): each test module uses
//! some of it.
#![allow(dead_code)]

/// The allocator the binary runs with: the filters allocate and free many small map nodes
/// from all threads, which the system allocator serves slower.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

use footslam::eval::{Alignment, position_errors};
use footslam::filter::FootSlamConfig;
use footslam::geometry::LocalFrame;
use footslam::io::floor_plan_geojson::{read_floor_plan, write_floor_plan};
use footslam::io::map_geojson::StoredMap;
use footslam::io::radio_map_geojson::{read_radio_map_geojson, write_radio_map_geojson};
use footslam::io::steps_csv::write_steps;
use footslam::io::truth_csv::{read_truth, write_truth};
use footslam::io::{TimedPoint, read_gps_csv, read_steps, read_wifi, write_gps_csv, write_wifi};
use footslam::map::{FloorPlan, HexMapSnapshot, RadioMap};
use footslam::pipeline::LearnConfig;
use footslam::pipeline::{LearnInput, LearnWalk, Learned, Silent, TrackRun, WalkRun, learn};
use footslam::sensor::{GpsFix, StepTrace, TruePath, TruePose, WifiScan};
use geo::Polygon;
use std::path::Path;

/// What `write` puts in a file named `name`, as `read` reads it back.
pub fn through_file<T>(
    name: &str,
    write: impl FnOnce(&Path) -> footslam::Result<()>,
    read: impl FnOnce(&Path) -> footslam::Result<T>,
) -> T {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join(name);
    write(&path).unwrap_or_else(|e| panic!("write {name}: {e}"));
    read(&path).unwrap_or_else(|e| panic!("read {name}: {e}"))
}

/// `trace` as its `steps.csv` records it.
pub fn recorded(trace: &StepTrace) -> StepTrace {
    through_file("steps.csv", |p| write_steps(p, trace), read_steps)
}

/// `fixes` as their `gps.csv` records them.
pub fn recorded_fixes(fixes: &[GpsFix]) -> Vec<GpsFix> {
    through_file("gps.csv", |p| write_gps_csv(p, fixes), read_gps_csv)
}

/// `scans` as their `wifi.csv` records them.
pub fn recorded_scans(scans: &[WifiScan]) -> Vec<WifiScan> {
    through_file("wifi.csv", |p| write_wifi(p, scans), read_wifi)
}

/// A true path as its `truth.csv` records it (to 0.1 mm, times to the millisecond as the
/// recorded steps' are: a track at the steps' times lies within the truth's time span).
pub fn recorded_truth(truth: &TruePath) -> TruePath {
    through_file("truth.csv", |p| write_truth(p, truth), read_truth)
}

/// `plan` as its GeoJSON file in `frame` records it (corners in degrees, to about a
/// millimetre).
pub fn recorded_plan(plan: &FloorPlan, frame: LocalFrame) -> FloorPlan {
    through_file(
        "plan.geojson",
        |p| write_floor_plan(p, plan, &frame),
        |p| read_floor_plan(p, None).map(|(plan, _)| plan),
    )
}

/// `map` as its `radiomap.geojson` in `frame` records it.
pub fn recorded_radio_map(map: &RadioMap, frame: LocalFrame) -> RadioMap {
    through_file(
        "radiomap.geojson",
        |p| write_radio_map_geojson(p, map, &frame),
        |p| read_radio_map_geojson(p, Some(frame)).map(|(map, _)| map),
    )
}

/// `learn`'s configuration with `particles` particles and seed `seed` (`--particles`,
/// `--seed`), the rest the defaults.
pub fn footslam_config(particles: usize, seed: u64) -> FootSlamConfig {
    FootSlamConfig {
        particles,
        seed,
        ..Default::default()
    }
}

/// What `learn` reads besides the walks: the frame (`--origin`, else the default), the
/// outline (`--outline`) and a map learned before (`--prior-map`).
#[derive(Clone, Copy, Default)]
pub struct Anchors<'a> {
    pub frame: LocalFrame,
    pub outline: Option<&'a Polygon<f64>>,
    pub prior_map: Option<&'a StoredMap>,
}

/// `work` run as the command line runs a command: on the threads of a worker pool of its
/// own (all cores), so that the pipeline's parallel loops run on the thread that calls them
/// rather than wait on a pool from outside it. Results do not depend on the pool.
pub fn in_own_pool<T: Send>(work: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .build()
        .expect("worker pool")
        .install(work)
}

/// The walks learned with `config`, as `footslam learn` learns them (walk `i` with seed
/// `seed + i`).
pub fn learn_walks(walks: &[LearnWalk], anchors: Anchors, config: &FootSlamConfig) -> Learned {
    learn_walks_with(walks, anchors, &LearnConfig::from(config.clone()))
}

/// The walks learned with the whole job's `config`, as [`learn_walks`].
pub fn learn_walks_with(walks: &[LearnWalk], anchors: Anchors, config: &LearnConfig) -> Learned {
    let input = LearnInput {
        walks,
        frame: anchors.frame,
        outline: anchors.outline,
        prior_map: anchors.prior_map,
    };
    in_own_pool(|| learn(&input, config, &Silent)).expect("learn")
}

/// One walk of steps alone (no GPS, WiFi or start).
pub fn walk_of(trace: &StepTrace) -> LearnWalk {
    LearnWalk {
        trace: trace.clone(),
        ..Default::default()
    }
}

/// A learned walk's path as the rows of its `track.csv`: each step's time and place.
pub fn learned_track(trace: &StepTrace, run: &WalkRun) -> Vec<TimedPoint> {
    trace
        .steps()
        .iter()
        .zip(&run.estimate.path)
        .map(|(s, p)| TimedPoint {
            t: s.t,
            x: p.x,
            y: p.y,
        })
        .collect()
}

/// A tracking run's whole-walk answer as the rows of its `track.csv`: every step the
/// smoother placed, certain or not, at its time.
pub fn smoothed_track(trace: &StepTrace, run: &TrackRun) -> Vec<TimedPoint> {
    let walk = run.smoothed.as_ref().expect("smoothing on");
    trace
        .steps()
        .iter()
        .zip(walk.iter())
        .filter_map(|(s, k)| {
            let c = k?.estimate?;
            Some(TimedPoint {
                t: s.t,
                x: c.x,
                y: c.y,
            })
        })
        .collect()
}

/// True poses as `truth.csv`'s rows are read by the evaluation: time and place.
pub fn truth_track(poses: &[TruePose]) -> Vec<TimedPoint> {
    poses
        .iter()
        .map(|p| TimedPoint {
            t: p.t,
            x: p.x,
            y: p.y,
        })
        .collect()
}

/// The p95 error of `track` against `truth` with `alignment`, metres.
pub fn p95(truth: &[TimedPoint], track: &[TimedPoint], alignment: Alignment) -> f64 {
    position_errors(truth, track, alignment)
        .expect("errors")
        .p95
}

/// The nearest-rank p95 of `errors` (0 for none), as `footslam simulate` reports a walk's
/// GPS error (`gps_error_p95_m`).
pub fn nearest_rank_p95(errors: &[f64]) -> f64 {
    let mut sorted = errors.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted
        .get(((sorted.len() as f64 * 0.95).ceil() as usize).saturating_sub(1))
        .copied()
        .unwrap_or(0.0)
}

/// A learned map as `--prior-map` reads it: `map` holding the counts of `walks` walks,
/// in `frame`.
pub fn stored(map: &HexMapSnapshot, frame: LocalFrame, walks: u32) -> StoredMap {
    StoredMap {
        map: map.clone(),
        frame,
        walks,
    }
}
