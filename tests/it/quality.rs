//! Every command's quality verdict end to end (issue: answers a user can trust): walks on
//! their own building's plan come out `ok`, walks on another building's plan `poor` with
//! the reason, in `summary.json` and on the terminal; a survey leaves such a walk's scans
//! out of its radio map, and refuses when no walk fits.

use assert_cmd::Command;
use predicates::prelude::*;
use std::path::{Path, PathBuf};

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

fn datasets() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("datasets")
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("read")).expect("json")
}

fn codes(quality: &serde_json::Value) -> Vec<String> {
    quality["reasons"]
        .as_array()
        .expect("reasons")
        .iter()
        .map(|r| r["code"].as_str().expect("code").to_string())
        .collect()
}

fn track(steps: &str, plan: &str, out: &Path) -> assert_cmd::assert::Assert {
    footslam()
        .arg("track")
        .arg("--steps")
        .arg(datasets().join(steps).join("steps.csv"))
        .arg("--plan")
        .arg(datasets().join(plan).join("floor.geojson"))
        .arg("--out")
        .arg(out)
        .assert()
}

#[test]
fn track_says_when_the_walk_is_not_on_this_plan() {
    let dir = tempfile::tempdir().expect("tempdir");
    // The bundled tower walk on its own plan.
    let right = dir.path().join("right");
    track("tower", "tower", &right)
        .success()
        .stdout(predicate::str::contains("quality: ok"));
    let q = &json(&right.join("summary.json"))["quality"];
    assert_eq!(q["verdict"], "ok");
    assert!(q["reasons"].as_array().expect("reasons").is_empty());
    // The same walk (three floors, 3 m of stairs) on the one-floor office plan: the climb
    // the plan cannot explain, and the walls it keeps running into.
    let storeys = dir.path().join("storeys");
    track("tower", "office", &storeys)
        .success()
        .stdout(predicate::str::contains(
            "quality: poor: the walk climbs or descends",
        ));
    let summary = json(&storeys.join("summary.json"));
    assert_eq!(summary["quality"]["verdict"], "poor");
    assert!(codes(&summary["quality"]).contains(&"unexplained_climb".to_string()));
    assert!(
        summary["plan_fit"]["unexplained_climb_m"]
            .as_f64()
            .expect("climb")
            > 3.0
    );
    // The office walk (one floor) on the tower plan: it localises somewhere, but the walls
    // refuse its steps again and again.
    let walls = dir.path().join("walls");
    track("office", "tower", &walls).success();
    let summary = json(&walls.join("summary.json"));
    assert_eq!(
        summary["quality"]["verdict"], "poor",
        "{}",
        summary["quality"]
    );
    assert!(codes(&summary["quality"]).contains(&"repeated_restarts".to_string()));
    let fit = &summary["plan_fit"];
    assert!(fit["survival_mean"].as_f64().expect("survival") < 0.8);
    assert_eq!(fit["steps"], summary["steps"]);
}

#[test]
fn survey_leaves_out_a_walk_that_does_not_fit_and_refuses_when_none_does() {
    let dir = tempfile::tempdir().expect("tempdir");
    let tower = datasets().join("tower");
    let office = datasets().join("office");
    // The tower walk fits; the office walk (its steps heard the same WiFi log, on the
    // same clock) does not: its scans would land in the wrong cells.
    let out = dir.path().join("mixed");
    footslam()
        .args(["survey", "--plan"])
        .arg(tower.join("floor.geojson"))
        .arg("--steps")
        .arg(tower.join("steps.csv"))
        .arg("--wifi")
        .arg(tower.join("wifi.csv"))
        .arg("--steps")
        .arg(office.join("steps.csv"))
        .arg("--wifi")
        .arg(tower.join("wifi.csv"))
        .arg("--out")
        .arg(&out)
        .assert()
        .success()
        .stderr(predicate::str::contains(
            "its scans were left out of the radio map",
        ))
        .stdout(predicate::str::contains("quality: doubtful: walk 2:"));
    let summary = json(&out.join("summary.json"));
    assert_eq!(summary["quality"]["verdict"], "doubtful");
    let walks = summary["walks"].as_array().expect("walks");
    assert_eq!(walks[0]["quality"]["verdict"], "ok");
    assert!(walks[0]["scans_added"].as_u64().expect("added") > 0);
    assert_eq!(walks[1]["quality"]["verdict"], "poor");
    assert_eq!(walks[1]["scans_added"], 0);
    // Only the walk on another building's plan: nothing to survey, nothing written.
    let none = dir.path().join("none");
    footslam()
        .args(["survey", "--plan"])
        .arg(office.join("floor.geojson"))
        .arg("--steps")
        .arg(tower.join("steps.csv"))
        .arg("--wifi")
        .arg(tower.join("wifi.csv"))
        .arg("--out")
        .arg(&none)
        .assert()
        .failure()
        .stderr(
            predicate::str::contains("office/floor.geojson")
                .and(predicate::str::contains("no walk fits the floor plan"))
                .and(predicate::str::contains("climbs or descends")),
        );
    assert!(!none.exists());
}

#[test]
fn learn_reports_its_verdict() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("learn");
    footslam()
        .args(["learn", "--particles", "2000", "--seed", "3", "--steps"])
        .arg(datasets().join("office/steps.csv"))
        .arg("--out")
        .arg(&out)
        .assert()
        .success()
        .stdout(predicate::str::contains("quality: ok"));
    let q = &json(&out.join("summary.json"))["quality"];
    assert_eq!(q["verdict"], "ok", "{q}");
}

#[test]
fn an_open_plan_finishes_within_its_bounds_and_says_so() {
    // One open room 1 km square: nothing narrows an unknown start, so the belief would keep
    // every particle and every path. The documented bounds (particles per step, path nodes)
    // keep the run short; the verdict says what the answer is worth.
    let dir = tempfile::tempdir().expect("tempdir");
    let (lat, lon): (f64, f64) = (48.1491, 11.5681);
    let (dlat, dlon) = (
        1000.0 / 111_320.0,
        1000.0 / (111_320.0 * lat.to_radians().cos()),
    );
    let ring = serde_json::json!([
        [lon, lat],
        [lon + dlon, lat],
        [lon + dlon, lat + dlat],
        [lon, lat + dlat],
        [lon, lat]
    ]);
    let plan = serde_json::json!({"type": "FeatureCollection", "origin": {"lat": lat, "lon": lon},
        "features": [{"type": "Feature", "properties": {"level": 0, "z": 0.0},
            "geometry": {"type": "Polygon", "coordinates": [ring]}}]});
    let plan_path = dir.path().join("room.geojson");
    std::fs::write(&plan_path, plan.to_string()).expect("plan");
    let config = dir.path().join("bounds.toml");
    std::fs::write(
        &config,
        "smoothing_max_nodes = 200000\n[kld]\nmax_particles = 40000\nmax_step_particles = 5000\n",
    )
    .expect("config");
    let out = dir.path().join("run");
    footslam()
        .arg("track")
        .arg("--plan")
        .arg(&plan_path)
        .arg("--steps")
        .arg(datasets().join("office/steps.csv"))
        .arg("--config")
        .arg(&config)
        .arg("--out")
        .arg(&out)
        .assert()
        .success()
        .stdout(predicate::str::contains("quality: doubtful"));
    let summary = json(&out.join("summary.json"));
    let reasons = codes(&summary["quality"]);
    for code in ["not_settled", "smoothing_dropped", "thin_prior"] {
        assert!(reasons.contains(&code.to_string()), "{reasons:?}");
    }
    assert!(summary["particles_max"].as_u64().expect("max") <= 40_000);
    let per_step = summary["particles_per_step"].as_array().expect("per step");
    assert!(per_step.iter().all(|n| n.as_u64().expect("n") <= 5_000));
    // Without the ancestry the answer is the filter's own: track.csv in that format.
    let track = std::fs::read_to_string(out.join("track.csv")).expect("track");
    assert!(track.starts_with("t,x,y,z,level\n"));
    assert!(summary["smoothing"].is_null());
}
