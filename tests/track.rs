//! `footslam track` end to end: outputs, reproducibility, recovery and clear errors, on
//! simulated multi-floor walks.

use assert_cmd::Command;
use predicates::prelude::*;
use std::path::{Path, PathBuf};

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

/// Simulates a short tower walk into `dir`.
fn simulate_tower(dir: &Path, seed: &str, minutes: &str) -> PathBuf {
    let out = dir.join(format!("tower-{seed}"));
    footslam()
        .args([
            "simulate",
            "--building",
            "tower",
            "--minutes",
            minutes,
            "--seed",
            seed,
            "--origin",
            "52.21,0.091",
            "--out",
        ])
        .arg(&out)
        .assert()
        .success()
        .stdout(predicate::str::contains("3 floors"));
    out
}

fn track(sim: &Path, out: &Path, extra: &[&str]) -> assert_cmd::assert::Assert {
    footslam()
        .arg("track")
        .arg("--plan")
        .arg(sim.join("floor.geojson"))
        .arg("--steps")
        .arg(sim.join("steps.csv"))
        .arg("--out")
        .arg(out)
        .args(extra)
        .assert()
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("read")).expect("json")
}

#[test]
fn track_writes_every_output_and_localises() {
    let dir = tempfile::tempdir().expect("tempdir");
    let sim = simulate_tower(dir.path(), "4", "6");
    let out = dir.path().join("run");
    track(&sim, &out, &["--seed", "4"])
        .success()
        .stdout(predicate::str::contains("localised after"));
    for f in [
        "track.csv",
        "track.geojson",
        "summary.json",
        "particles.png",
        "config.json",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let summary = json(&out.join("summary.json"));
    let steps = summary["steps"].as_u64().expect("steps");
    let localised = summary["steps_to_localise"].as_u64().expect("localised");
    assert!(localised < steps);
    assert!(summary["particles_initial"].as_u64().expect("n0") > 100_000);
    assert_eq!(
        summary["particles_per_step"]
            .as_array()
            .expect("array")
            .len() as u64,
        steps
    );
    assert_eq!(
        summary["clusters_per_step"]
            .as_array()
            .expect("array")
            .len() as u64,
        steps
    );
    assert!(summary["bytes_per_particle"].as_f64().expect("bytes") <= 64.0);
    // One row per step from localisation on, on the truth's clock; the floor is right.
    let text = std::fs::read_to_string(out.join("track.csv")).expect("track");
    assert!(text.starts_with("t,x,y,z,level\n"));
    assert_eq!(
        text.lines().count() as u64 - 1,
        steps - localised + 1,
        "rows from localisation on"
    );
    footslam()
        .args(["eval", "--json", "--truth"])
        .arg(sim.join("truth.csv"))
        .arg("--track")
        .arg(out.join("track.csv"))
        .assert()
        .success()
        .stdout(
            predicate::str::contains("\"floor_accuracy\": 1.0")
                .or(predicate::str::contains("\"floor_accuracy\": 0.99")),
        );
    // RFC 7946: lon/lat order near the origin, no crs member.
    let geojson = std::fs::read_to_string(out.join("track.geojson")).expect("geojson");
    assert!(!geojson.contains("\"crs\""));
    let value: serde_json::Value = serde_json::from_str(&geojson).expect("json");
    let first = &value["features"][1]["geometry"]["coordinates"];
    assert!((first[0].as_f64().expect("lon") - 0.091).abs() < 0.01);
    assert!((first[1].as_f64().expect("lat") - 52.21).abs() < 0.01);
    let png = image::open(out.join("particles.png")).expect("png");
    assert!(png.width() > 600 && png.height() > 600);
    // The run's configuration reproduces it.
    let again = dir.path().join("again");
    track(
        &sim,
        &again,
        &["--config", out.join("config.json").to_str().expect("utf-8")],
    )
    .success();
    assert_eq!(
        std::fs::read(out.join("track.csv")).expect("a"),
        std::fs::read(again.join("track.csv")).expect("b")
    );
}

#[test]
fn results_do_not_depend_on_threads_and_a_known_start_localises_at_once() {
    let dir = tempfile::tempdir().expect("tempdir");
    let sim = simulate_tower(dir.path(), "6", "2");
    let (one, two) = (dir.path().join("one"), dir.path().join("two"));
    track(&sim, &one, &["--threads", "1"]).success();
    track(&sim, &two, &["--threads", "2"]).success();
    for f in ["track.csv", "track.geojson"] {
        assert_eq!(
            std::fs::read(one.join(f)).expect("one"),
            std::fs::read(two.join(f)).expect("two"),
            "{f}"
        );
    }
    let start = json(&sim.join("summary.json"))["start"].clone();
    let arg = format!(
        "{},{},{},{}",
        start["x"], start["y"], start["heading"], start["level"]
    );
    let known = dir.path().join("known");
    track(&sim, &known, &["--start", &arg]).success();
    let summary = json(&known.join("summary.json"));
    assert_eq!(summary["steps_to_localise"], 1);
    assert!(summary["particles_initial"].as_u64().expect("n0") < 20_000);
}

#[test]
fn a_door_missing_from_the_map_is_recovered_and_reported() {
    let dir = tempfile::tempdir().expect("tempdir");
    let sim = simulate_tower(dir.path(), "5", "6");
    // Remove every door from the plan: the walker walks through walls.
    let mut plan = json(&sim.join("floor.geojson"));
    let features = plan["features"].as_array_mut().expect("features");
    features.retain(|f| {
        !f["properties"]["name"]
            .as_str()
            .is_some_and(|n| n.starts_with("door"))
    });
    let broken = dir.path().join("no-doors.geojson");
    std::fs::write(&broken, serde_json::to_string(&plan).expect("json")).expect("write");
    let out = dir.path().join("run");
    footslam()
        .arg("track")
        .arg("--plan")
        .arg(&broken)
        .arg("--steps")
        .arg(sim.join("steps.csv"))
        .arg("--out")
        .arg(&out)
        .assert()
        .success();
    let summary = json(&out.join("summary.json"));
    let deaths = summary["deaths"].as_u64().expect("deaths");
    assert!(deaths > 0, "no death recorded");
    let recoveries = summary["recoveries"].as_array().expect("recoveries");
    assert_eq!(recoveries.len() as u64, deaths);
    assert!(recoveries.iter().all(|r| r["method"].is_string()));
    let text = std::fs::read_to_string(out.join("track.csv")).expect("track");
    assert!(!text.contains("NaN") && !text.contains("inf"));
}

#[test]
fn bad_inputs_get_clear_errors() {
    let dir = tempfile::tempdir().expect("tempdir");
    let sim = simulate_tower(dir.path(), "7", "1");
    let run = |plan: &Path, steps: &Path, extra: &[&str], expected: &str| {
        footslam()
            .arg("track")
            .arg("--plan")
            .arg(plan)
            .arg("--steps")
            .arg(steps)
            .arg("--out")
            .arg(dir.path().join("bad"))
            .args(extra)
            .assert()
            .failure()
            .stderr(predicate::str::contains(expected));
        assert!(!dir.path().join("bad").exists(), "partial outputs left");
    };
    let plan = sim.join("floor.geojson");
    let steps = sim.join("steps.csv");
    let nan = dir.path().join("nan.geojson");
    let text = std::fs::read_to_string(&plan).expect("plan");
    let first = text.find("[[[").expect("a polygon") + 3;
    std::fs::write(
        &nan,
        format!("{}NaN,{}", &text[..first], &text[first + 1..]),
    )
    .expect("write");
    run(&nan, &steps, &[], "nan.geojson");
    let bow = dir.path().join("bow.geojson");
    std::fs::write(
        &bow,
        r#"{"type":"FeatureCollection","origin":{"lat":52.2,"lon":0.09},"features":[{"type":"Feature","properties":{"name":"lobby"},"geometry":{"type":"Polygon","coordinates":[[[0.09,52.2],[0.0901,52.2001],[0.0901,52.2],[0.09,52.2001],[0.09,52.2]]]}}]}"#,
    )
    .expect("write");
    run(&bow, &steps, &[], "not a valid polygon");
    run(
        &dir.path().join("none.geojson"),
        &steps,
        &[],
        "does not exist",
    );
    let unsorted = dir.path().join("unsorted.csv");
    std::fs::write(&unsorted, "t,length,dheading,dz\n1,0.7,0,0\n0.5,0.7,0,0\n").expect("write");
    run(&plan, &unsorted, &[], "unsorted.csv:3");
    run(
        &plan,
        &steps,
        &["--start", "500,500,0"],
        "not on a walkable surface",
    );
    footslam()
        .args(["track", "--start", "1,2"])
        .assert()
        .failure()
        .stderr(predicate::str::contains("X,Y,HEADING"));
}

#[test]
fn simulate_tower_writes_wifi_scans_and_the_radio_truth() {
    let dir = tempfile::tempdir().expect("tempdir");
    let sim = simulate_tower(dir.path(), "8", "2");
    let scans = footslam::dataset::read_wifi(&sim.join("wifi.csv")).expect("wifi.csv parses");
    // A scan about every 2 s of the 2-minute walk, each hearing several access points.
    assert!((50..=70).contains(&scans.len()), "{} scans", scans.len());
    assert!(
        scans
            .iter()
            .all(|s| s.readings.iter().all(|r| r.rssi >= -96.0))
    );
    let aps = std::fs::read_to_string(sim.join("wifi_aps.csv")).expect("aps");
    assert_eq!(aps.lines().count(), 1 + 24);
    let field = std::fs::read_to_string(sim.join("wifi_field.csv")).expect("field");
    let header = field.lines().next().expect("header");
    assert_eq!(header.split(',').count(), 3 + 24);
    assert!(field.lines().count() > 1000);
    let summary = json(&sim.join("summary.json"));
    assert_eq!(summary["access_points"], 24);
    assert_eq!(summary["wifi_scans"].as_u64(), Some(scans.len() as u64));
}

#[test]
fn survey_builds_a_radio_map_from_tracked_walks() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (a, b) = (
        simulate_tower(dir.path(), "9", "3"),
        simulate_tower(dir.path(), "10", "3"),
    );
    let out = dir.path().join("survey");
    footslam()
        .arg("survey")
        .arg("--plan")
        .arg(a.join("floor.geojson"))
        .arg("--steps")
        .arg(a.join("steps.csv"))
        .arg("--wifi")
        .arg(a.join("wifi.csv"))
        .arg("--steps")
        .arg(b.join("steps.csv"))
        .arg("--wifi")
        .arg(b.join("wifi.csv"))
        .arg("--out")
        .arg(&out)
        .assert()
        .success()
        .stdout(predicate::str::contains("surveyed 2 walk(s)"));
    let summary = json(&out.join("summary.json"));
    assert_eq!(summary["walks"].as_array().expect("walks").len(), 2);
    assert!(summary["coverage"].as_f64().expect("coverage") > 0.0);
    assert!(summary["speed_vs_real_time"].as_f64().expect("speed") > 0.0);
    let coverage = std::fs::read_to_string(out.join("coverage.csv")).expect("coverage");
    assert_eq!(coverage.lines().count(), 6);
    let (map, _) = footslam::export::radio_map_geojson::read_radio_map_geojson(
        &out.join("radiomap.geojson"),
        None,
    )
    .expect("radiomap.geojson reads back");
    assert!(map.cells.iter().any(|c| c.radio.scans > 0));
    assert!(out.join("radiomap.csv").is_file() && out.join("heatmap-000.png").is_file());
    // One WiFi log per step trace.
    footslam()
        .arg("survey")
        .arg("--plan")
        .arg(a.join("floor.geojson"))
        .arg("--steps")
        .arg(a.join("steps.csv"))
        .arg("--steps")
        .arg(b.join("steps.csv"))
        .arg("--wifi")
        .arg(a.join("wifi.csv"))
        .arg("--out")
        .arg(dir.path().join("bad"))
        .assert()
        .failure()
        .stderr(predicate::str::contains("one --wifi per --steps"));
}
