//! What each fuzz target does with one input: hand the bytes to a reader of the toolkit
//! (through a file, as users give them) and, where it accepts them, to what runs on its
//! output. A panic, hang or runaway allocation anywhere is a finding; an `Err` is the
//! right answer to a malformed file.
//!
//! Shared by the fuzz targets (`fuzz/fuzz_targets/*.rs`, nightly, `cargo fuzz run NAME`)
//! and by `tests/it/fuzz_replay.rs`, which replays the committed corpora
//! (`fuzz/corpus/NAME/`) on the stable toolchain in CI.

#![allow(dead_code)]

use footslam::geometry::LocalFrame;
use footslam::io;
use footslam::io::map_geojson::{read_map_geojson, read_stored_map};
use footslam::io::radio_map_geojson::read_radio_map_geojson;
use std::path::{Path, PathBuf};

/// What a target does with one input.
pub type Target = fn(&[u8]);

/// Every target by name, as `fuzz/fuzz_targets/NAME.rs` and `fuzz/corpus/NAME/` call it.
pub const TARGETS: &[(&str, Target)] = &[
    ("steps_csv", steps_csv),
    ("imu_csv", imu_csv),
    ("wifi_csv", wifi_csv),
    ("gps_csv", gps_csv),
    ("gpx", gpx),
    ("eval_csv", eval_csv),
    ("floor_plan", floor_plan),
    ("outline", outline),
    ("radio_map", radio_map),
    ("hex_map", hex_map),
    ("manifest", manifest),
    ("config", config),
    ("ilc_trace", ilc_trace),
    ("ilc_floor", ilc_floor),
    ("ipin_log", ipin_log),
];

/// A scratch folder of this process and thread (the replay test runs targets in
/// parallel), made once.
fn scratch() -> PathBuf {
    thread_local! {
        static DIR: PathBuf = {
            let dir = std::env::temp_dir().join(format!(
                "footslam-fuzz-{}-{:?}",
                std::process::id(),
                std::thread::current().id()
            ));
            std::fs::create_dir_all(&dir).expect("scratch folder");
            dir
        };
    }
    DIR.with(PathBuf::clone)
}

/// Writes `data` to `name` in the scratch folder and returns its path.
fn file(name: &str, data: &[u8]) -> PathBuf {
    let path = scratch().join(name);
    std::fs::write(&path, data).expect("scratch file");
    path
}

/// Asserts that an accepted value is finite: readers must refuse NaN and infinities.
fn finite(values: impl IntoIterator<Item = f64>, what: &str) {
    for v in values {
        assert!(v.is_finite(), "{what}: accepted a non-finite value {v}");
    }
}

/// A step trace (`steps.csv`); an accepted one is written back and read again unchanged in
/// length.
pub fn steps_csv(data: &[u8]) {
    let path = file("steps.csv", data);
    if let Ok(trace) = io::read_steps(&path) {
        for s in trace.steps() {
            finite([s.t, s.length, s.dheading, s.dz], "steps");
        }
        let _ = io::steps_csv::has_dz_column(&path);
        let again = file("steps-again.csv", b"");
        io::steps_csv::write_steps(&again, &trace).expect("write steps");
        let back = io::read_steps(&again).expect("a written trace reads back");
        assert_eq!(back.len(), trace.len());
    }
}

/// An IMU recording (`imu.csv`), then both step detectors on what it accepts.
pub fn imu_csv(data: &[u8]) {
    let path = file("imu.csv", data);
    if let Ok(recording) = io::read_imu(&path) {
        let config = footslam::inertial::StepsConfig::default();
        let _ = footslam::inertial::detect_strides(&recording, &config.foot);
        let _ = footslam::inertial::detect_steps(&recording, &config.phone);
    }
}

/// A WiFi log (`wifi.csv`).
pub fn wifi_csv(data: &[u8]) {
    let path = file("wifi.csv", data);
    if let Ok(scans) = io::read_wifi(&path) {
        finite(scans.iter().map(|s| s.t), "wifi");
    }
}

/// GPS fixes as CSV (`gps.csv`).
pub fn gps_csv(data: &[u8]) {
    let path = file("gps.csv", data);
    if let Ok(fixes) = io::read_gps_csv(&path) {
        finite(fixes.iter().flat_map(|f| [f.t, f.lat, f.lon]), "gps");
    }
}

/// GPS fixes as GPX.
pub fn gpx(data: &[u8]) {
    let path = file("gps.gpx", data);
    let _ = io::read_gpx(&path, 0.0);
}

/// The CSVs `eval` reads: a ground truth, a track, a trajectory and waypoints (the same
/// bytes to each).
pub fn eval_csv(data: &[u8]) {
    let path = file("eval.csv", data);
    let _ = io::truth_csv::read_truth(&path);
    let _ = io::read_track(&path);
    let _ = io::read_trajectory(&path);
    let _ = io::read_certain_trajectory(&path);
    let _ = io::read_waypoints(&path);
}

/// A floor plan (GeoJSON), then the topology built on what it accepts (bounded loops on
/// any valid plan).
pub fn floor_plan(data: &[u8]) {
    let path = file("plan.geojson", data);
    if let Ok((plan, _)) = io::floor_plan_geojson::read_floor_plan(&path, None) {
        let _ =
            footslam::map::FloorTopology::build(&plan, &footslam::map::TopologyConfig::default());
    }
}

/// A building outline (GeoJSON).
pub fn outline(data: &[u8]) {
    let path = file("outline.geojson", data);
    let frame = LocalFrame::new(52.0, 0.1).expect("frame");
    let _ = io::read_outline(&path, &frame);
}

/// A radio map (GeoJSON).
pub fn radio_map(data: &[u8]) {
    let path = file("radiomap.geojson", data);
    let _ = read_radio_map_geojson(&path, None);
}

/// A learned hexagon map (GeoJSON), as `track --hexmap` and `learn --prior-map` read it.
pub fn hex_map(data: &[u8]) {
    let path = file("map.geojson", data);
    let _ = read_map_geojson(&path);
    let _ = read_stored_map(&path);
}

/// A walk manifest, as `learn --walks` and `survey --walks` read it.
pub fn manifest(data: &[u8]) {
    let path = file("walks.csv", data);
    let _ = io::read_walk_manifest(&path, false);
    let _ = io::read_walk_manifest(&path, true);
}

/// A component configuration, as JSON and as TOML, into each configuration type and its
/// range checks.
pub fn config(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    macro_rules! each {
        ($($t:ty),*) => {$(
            if let Ok(c) = serde_json::from_str::<$t>(text) {
                let _ = c.validate();
            }
            if let Ok(c) = toml::from_str::<$t>(text) {
                let _ = c.validate();
            }
        )*};
    }
    each!(
        footslam::filter::FootSlamConfig,
        footslam::pipeline::LearnConfig,
        footslam::pipeline::SurveyConfig,
        footslam::filter::TrackerConfig,
        footslam::inertial::StepsConfig,
        footslam::sim::SimConfig,
        footslam::map::CellConfig,
        footslam::filter::FingerprintConfig,
        footslam::io::import::ilc_trace::IlcImportConfig
    );
}

/// An Indoor Location Competition 2.0 trace file.
pub fn ilc_trace(data: &[u8]) {
    let path = file("trace.txt", data);
    let config = io::import::ilc_trace::IlcImportConfig::default();
    let _ = io::import::ilc_trace::read_ilc_trace(&path, &config);
}

/// An Indoor Location Competition 2.0 floor: `floor_info.json` and `geojson_map.json`,
/// the input split at its first NUL byte (all of it the map when there is none).
pub fn ilc_floor(data: &[u8]) {
    let (info, map) = match data.iter().position(|&b| b == 0) {
        Some(i) => (&data[..i], &data[i + 1..]),
        None => (&b"{\"map_info\":{\"height\":100,\"width\":100}}"[..], data),
    };
    let dir = scratch().join("floor");
    std::fs::create_dir_all(&dir).expect("floor folder");
    std::fs::write(dir.join("floor_info.json"), info).expect("info");
    std::fs::write(dir.join("geojson_map.json"), map).expect("map");
    let _ = io::import::ilc_floor::read_ilc_floor(&dir);
}

/// An IPIN competition logfile.
pub fn ipin_log(data: &[u8]) {
    let path = file("log.txt", data);
    let config = io::import::ipin_log::IpinImportConfig::default();
    let _ = io::import::ipin_log::read_ipin_log(&path, &config);
}

/// Runs every input of `fuzz/corpus/NAME/` through target `NAME`; returns the number run.
pub fn replay(corpus: &Path, name: &str, target: Target) -> usize {
    let dir = corpus.join(name);
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return 0;
    };
    let mut inputs: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    inputs.sort();
    for input in &inputs {
        let data = std::fs::read(input).expect("corpus file");
        target(&data);
    }
    inputs.len()
}
