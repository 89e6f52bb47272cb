//! `footslam import` end to end: a real Indoor Location Competition excerpt
//! (`tests/data/ilc_excerpt.txt`) on a synthetic floor, a synthetic IPIN logfile, and bad
//! inputs that must fail with the file and line named, never a panic.

use assert_cmd::Command;
use footslam::io::floor_plan_geojson::read_floor_plan;
use footslam::io::import::ipin_log::synthetic_ipin_log;
use footslam::io::{read_gps_csv, read_imu, read_waypoints, read_wifi};
use footslam::map::{FloorTopology, TopologyConfig};
use std::path::{Path, PathBuf};

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

fn excerpt() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/ilc_excerpt.txt")
}

/// A 200 m × 150 m floor (as ILC writes it: bbox in degrees, size in `floor_info.json`) with
/// one 30 m × 30 m shop at (10..40, 10..40) m.
fn write_floor(dir: &Path) {
    std::fs::create_dir_all(dir).expect("mkdir");
    let lon = |x: f64| 120.0 + x / 200.0 * 0.002;
    let lat = |y: f64| 30.0 + y / 150.0 * 0.0015;
    let rect = |x0: f64, y0: f64, x1: f64, y1: f64| {
        format!(
            "[[[{},{}],[{},{}],[{},{}],[{},{}],[{},{}]]]",
            lon(x0),
            lat(y0),
            lon(x1),
            lat(y0),
            lon(x1),
            lat(y1),
            lon(x0),
            lat(y1),
            lon(x0),
            lat(y0)
        )
    };
    let map = format!(
        r#"{{"type":"FeatureCollection","features":[
        {{"type":"Feature","properties":{{"name":"F1"}},"geometry":{{"type":"MultiPolygon","coordinates":[{}]}}}},
        {{"type":"Feature","properties":{{"name":"shop"}},"geometry":{{"type":"Polygon","coordinates":{}}}}}]}}"#,
        rect(0.0, 0.0, 200.0, 150.0),
        rect(10.0, 10.0, 40.0, 40.0)
    );
    std::fs::write(dir.join("geojson_map.json"), map).expect("write");
    std::fs::write(
        dir.join("floor_info.json"),
        r#"{"map_info": {"width": 200.0, "height": 150.0}}"#,
    )
    .expect("write");
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).expect("summary"))
        .expect("json")
}

#[test]
fn ilc_trace_and_floor_convert_to_footslam_files() {
    let dir = tempfile::tempdir().expect("tempdir");
    let floor = dir.path().join("floor");
    write_floor(&floor);
    let out = dir.path().join("out");
    let assert = footslam()
        .args(["import", "ilc", "--trace"])
        .arg(excerpt())
        .arg("--floor")
        .arg(&floor)
        .arg("--out")
        .arg(&out)
        .assert()
        .success();
    let stdout = String::from_utf8_lossy(&assert.get_output().stdout).into_owned();
    assert!(
        stdout.contains("9 stale readings of 30 dropped"),
        "{stdout}"
    );
    assert!(stdout.contains("corridors 100.0 % (2/2)"), "{stdout}");

    let imu = read_imu(&out.join("imu.csv")).expect("imu.csv");
    assert_eq!(imu.samples().len(), 21);
    assert!(imu.has_magnetometer() && imu.has_orientation());
    assert!((imu.samples()[0].t - 1_574_559_495.401).abs() < 1e-6);
    let wifi = read_wifi(&out.join("wifi.csv")).expect("wifi.csv");
    assert_eq!(wifi.len(), 1);
    assert_eq!(wifi[0].readings.len(), 21);
    let waypoints = read_waypoints(&out.join("waypoints.csv")).expect("waypoints.csv");
    assert_eq!(waypoints.len(), 2);
    assert!((waypoints[0].x - 81.317215).abs() < 1e-3);
    // The known start: the first waypoint, as `--start` takes it.
    let start = std::fs::read_to_string(out.join("start.txt")).expect("start.txt");
    let start: footslam::filter::StartPose = start.trim().parse().expect("X,Y");
    assert!((start.x - waypoints[0].x).abs() < 1e-3 && (start.y - waypoints[0].y).abs() < 1e-3);
    assert!(!out.join("walks.csv").exists(), "one trace: no manifest");

    // The plan reads back in the waypoints' metres and the tracker accepts it.
    let (plan, frame) = read_floor_plan(&out.join("floor.geojson"), None).expect("plan");
    FloorTopology::build(&plan, &TopologyConfig::default()).expect("topology");
    assert!((frame.lat - 30.0).abs() < 1e-9 && (frame.lon - 120.0).abs() < 1e-9);
    let (x0, y0, x1, y1) = plan.bounds().expect("bounds");
    for (got, want) in [(x0, 0.0), (y0, 0.0), (x1, 200.0), (y1, 150.0)] {
        assert!((got - want).abs() < 0.03, "bounds {x0} {y0} {x1} {y1}");
    }
    assert!(
        !plan.is_walkable(25.0, 25.0, Some(0)),
        "the shop is cut out"
    );
    assert!(plan.is_walkable(waypoints[0].x, waypoints[0].y, Some(0)));

    let s = summary(&out);
    let t = &s["traces"][0]["summary"];
    assert_eq!(t["stale_readings_dropped"], 9);
    assert_eq!(t["imu_sources"]["gyroscope"], "TYPE_GYROSCOPE");
    assert_eq!(t["not_converted"]["TYPE_DIST1"], 1);
    assert_eq!(s["walkable"], "corridors");
    assert_eq!(s["floor"]["waypoints_on_walkable"]["outline"]["on"], 2);

    // The whole floor as the outline.
    let out2 = dir.path().join("outline");
    footslam()
        .args(["import", "ilc", "--walkable", "outline", "--floor"])
        .arg(&floor)
        .arg("--out")
        .arg(&out2)
        .assert()
        .success();
    let (plan, _) = read_floor_plan(&out2.join("floor.geojson"), None).expect("plan");
    assert!(plan.is_walkable(25.0, 25.0, Some(0)));
    assert!(!out2.join("imu.csv").exists());
}

#[test]
fn a_folder_of_traces_gives_one_folder_per_trace_and_one_floor() {
    let dir = tempfile::tempdir().expect("tempdir");
    let traces = dir.path().join("path_data_files");
    std::fs::create_dir_all(&traces).expect("mkdir");
    for name in ["a.txt", "b.txt"] {
        std::fs::copy(excerpt(), traces.join(name)).expect("copy");
    }
    std::fs::write(traces.join("notes.md"), "not a trace").expect("write");
    let floor = dir.path().join("floor");
    write_floor(&floor);
    let out = dir.path().join("out");
    footslam()
        .args(["import", "ilc", "--trace"])
        .arg(&traces)
        .arg("--floor")
        .arg(&floor)
        .arg("--out")
        .arg(&out)
        .assert()
        .success();
    for name in ["a", "b"] {
        for f in ["imu.csv", "wifi.csv", "waypoints.csv"] {
            assert!(out.join(name).join(f).is_file(), "{name}/{f}");
        }
    }
    assert!(out.join("floor.geojson").is_file() && !out.join("imu.csv").exists());
    assert_eq!(summary(&out)["traces"].as_array().map(Vec::len), Some(2));
    // The manifest names each walk's steps-to-be, its WiFi log and its start.
    let walks = footslam::io::read_walk_manifest(&out.join("walks.csv"), true).expect("walks.csv");
    assert_eq!(walks.len(), 2);
    for (walk, name) in walks.iter().zip(["a", "b"]) {
        assert_eq!(walk.steps, out.join(name).join("steps/steps.csv"));
        assert_eq!(
            walk.wifi.as_deref(),
            Some(out.join(name).join("wifi.csv").as_path())
        );
        assert!(walk.start.is_some_and(|s| (s.x - 81.317).abs() < 1e-3));
    }
    assert_eq!(summary(&out)["manifest"], "walks.csv");
}

#[test]
fn ipin_logfile_converts_to_footslam_files() {
    let dir = tempfile::tempdir().expect("tempdir");
    let log = dir.path().join("logfile.txt");
    std::fs::write(&log, synthetic_ipin_log(5, 40.313, -3.483)).expect("write");
    let out = dir.path().join("out");
    let assert = footslam()
        .args(["import", "ipin", "--log"])
        .arg(&log)
        .arg("--out")
        .arg(&out)
        .assert()
        .success();
    let stdout = String::from_utf8_lossy(&assert.get_output().stdout).into_owned();
    assert!(
        stdout.contains("5 stale readings of 15 dropped"),
        "{stdout}"
    );
    let imu = read_imu(&out.join("imu.csv")).expect("imu.csv");
    assert_eq!(imu.samples().len(), 250);
    assert!(imu.has_pressure() && imu.has_orientation() && imu.has_magnetometer());
    assert_eq!(read_wifi(&out.join("wifi.csv")).expect("wifi").len(), 5);
    let gps = read_gps_csv(&out.join("gps.csv")).expect("gps.csv");
    assert_eq!(gps.len(), 5);
    assert_eq!(gps[0].accuracy, 12.0);
    let w = read_waypoints(&out.join("waypoints.csv")).expect("waypoints.csv");
    assert_eq!(w.len(), 3);
    assert!(w[0].x.abs() < 1e-6 && (w[2].x - 4.0).abs() < 0.03, "{w:?}");
    assert_eq!(w[0].level, Some(0));
    assert_eq!(summary(&out)["summary"]["skipped_tags"]["LIGH"], 50);

    // An origin 10 m south of the track moves the waypoints 10 m north.
    let out2 = dir.path().join("out2");
    footslam()
        .args(["import", "ipin", "--origin", "40.31291,-3.483", "--log"])
        .arg(&log)
        .arg("--out")
        .arg(&out2)
        .assert()
        .success();
    let w = read_waypoints(&out2.join("waypoints.csv")).expect("waypoints.csv");
    assert!((w[0].y - 10.0).abs() < 0.05, "{w:?}");
}

/// Runs `import` on a file holding `content` and returns stderr; the run must fail
/// cleanly (no panic) and leave no output folder.
fn import_fails(source: &str, content: &str) -> String {
    let dir = tempfile::tempdir().expect("tempdir");
    let file = dir.path().join("input.txt");
    std::fs::write(&file, content).expect("write");
    let out = dir.path().join("out");
    let flag = if source == "ilc" { "--trace" } else { "--log" };
    let assert = footslam()
        .args(["import", source, flag])
        .arg(&file)
        .arg("--out")
        .arg(&out)
        .assert()
        .failure();
    let err = String::from_utf8_lossy(&assert.get_output().stderr).into_owned();
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.contains("input.txt"), "{err}");
    assert!(!out.exists(), "a failed import leaves no output");
    err
}

#[test]
fn bad_ilc_traces_fail_with_file_and_line() {
    let text = std::fs::read_to_string(excerpt()).expect("excerpt");
    let lines: Vec<&str> = text.lines().collect();
    let with_line = |n: usize, replacement: &str| {
        let mut l = lines.clone();
        l[n - 1] = replacement;
        l.join("\n") + "\n"
    };
    // Line 22 is the second TYPE_ACCELEROMETER row.
    assert!(lines[21].contains("TYPE_ACCELEROMETER\t"), "{}", lines[21]);
    let err = import_fails("ilc", "");
    assert!(err.contains("no data rows"), "{err}");
    let err = import_fails(
        "ilc",
        &with_line(22, "1574559495421\tTYPE_ACCELEROMETER\t-0.67"),
    );
    assert!(
        err.contains("input.txt:22") && err.contains("expected 3 or 4"),
        "{err}"
    );
    let err = import_fails(
        "ilc",
        &with_line(22, "1574559495421\tTYPE_ACCELEROMETER\tNaN\t1.8\t9.9\t2"),
    );
    assert!(
        err.contains("input.txt:22") && err.contains("finite"),
        "{err}"
    );
    let err = import_fails(
        "ilc",
        &with_line(22, "1574559490000\tTYPE_ACCELEROMETER\t0.1\t1.8\t9.9\t2"),
    );
    assert!(
        err.contains("input.txt:22") && err.contains("before the same sensor's row"),
        "{err}"
    );
    let no_gyro: String = lines
        .iter()
        .filter(|l| !l.contains("TYPE_GYROSCOPE"))
        .map(|l| format!("{l}\n"))
        .collect();
    let err = import_fails("ilc", &no_gyro);
    assert!(err.contains("no gyroscope rows"), "{err}");

    // A cut-off last line (no newline) is skipped and reported, not an error.
    let dir = tempfile::tempdir().expect("tempdir");
    let file = dir.path().join("cut.txt");
    std::fs::write(
        &file,
        format!("{text}1574559504999\tTYPE_ACCELEROMETER\t0.1"),
    )
    .expect("write");
    let assert = footslam()
        .args(["import", "ilc", "--trace"])
        .arg(&file)
        .arg("--out")
        .arg(dir.path().join("out"))
        .assert()
        .success();
    let stdout = String::from_utf8_lossy(&assert.get_output().stdout).into_owned();
    assert!(
        stdout.contains(&format!("last line {}", lines.len() + 1)),
        "{stdout}"
    );
}

#[test]
fn bad_ipin_logs_fail_with_file_and_line() {
    let good = synthetic_ipin_log(1, 40.313, -3.483);
    let n = good.lines().count() + 1;
    let err = import_fails("ipin", "");
    assert!(err.contains("no data lines"), "{err}");
    let err = import_fails("ipin", &format!("{good}GYRO;1.000;1.0;0.1;NaN;0.2;3\n"));
    assert!(
        err.contains(&format!("input.txt:{n}")) && err.contains("finite"),
        "{err}"
    );
    // A bare tag (found by the fuzzer: the fields were taken from the end before counting).
    let err = import_fails("ipin", &format!("{good}WIFI;\n"));
    assert!(
        err.contains(&format!("input.txt:{n}")) && err.contains("WIFI line has 1 fields"),
        "{err}"
    );
    let err = import_fails("ipin", &format!("{good}WIFI;1.000;1.0;lab\n"));
    assert!(
        err.contains(&format!("input.txt:{n}")) && err.contains("WIFI"),
        "{err}"
    );
    let err = import_fails("ipin", &format!("{good}ACCE;0.1;0.1;0.1;0.2;9.8;3\n"));
    assert!(
        err.contains(&format!("input.txt:{n}")) && err.contains("before"),
        "{err}"
    );
    // AppTimestamp in milliseconds: 50 Hz would read as a 0.05 Hz, 16.7-hour recording.
    let ms: String = synthetic_ipin_log(2, 40.313, -3.483)
        .lines()
        .map(|l| {
            let mut f: Vec<String> = l.split(';').map(str::to_owned).collect();
            if !l.starts_with('%') && f.len() > 2 {
                f[1] = format!("{:.0}", f[1].parse::<f64>().expect("t") * 1000.0);
            }
            f.join(";") + "\n"
        })
        .collect();
    let err = import_fails("ipin", &ms);
    assert!(
        err.contains("input.txt") && err.contains("milliseconds"),
        "{err}"
    );
}
