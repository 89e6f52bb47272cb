//! FootSLAM accuracy on simulated office walks (issue: "What it must show").
//!
//! Each case simulates an office floor and a 3-lap walk with room visits under
//! foot-mounted-grade noise (0.5° white heading noise per step, 15° heading drift over the
//! walk), runs `footslam learn` end to end with its default particle count, and checks:
//! p95 error after rigid alignment ≤ 1.5 m and ≤ a third of dead reckoning's, and at
//! least 90 % of the visit-weighted learned hexagons in walkable space.

use assert_cmd::Command;
use footslam::dataset::{TimedPoint, read_trajectory};
use footslam::eval::{Alignment, position_errors, walkable_fraction};
use footslam::export::map_geojson::read_map_geojson;
use footslam::sim::{SimConfig, simulate};

#[allow(clippy::print_stderr)] // reports the figures with --nocapture
fn check_seed(seed: u64, drift_deg: f64) {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut config = SimConfig {
        seed,
        ..Default::default()
    };
    config.noise.drift_total = drift_deg.to_radians();
    let sim = simulate(&config).expect("simulate");
    let steps = dir.path().join("steps.csv");
    footslam::dataset::steps_csv::write_steps(&steps, &sim.steps).expect("write steps");
    let out = dir.path().join("run");
    Command::cargo_bin("footslam")
        .expect("binary")
        .args(["learn", "--steps"])
        .arg(&steps)
        .arg("--out")
        .arg(&out)
        .assert()
        .success();

    let truth: Vec<TimedPoint> = sim
        .truth
        .poses
        .iter()
        .map(|p| TimedPoint {
            t: p.t,
            x: p.x,
            y: p.y,
        })
        .collect();
    let track = read_trajectory(&out.join("track.csv")).expect("track");
    assert_eq!(track.len(), sim.steps.len(), "one row per step");
    let learned = position_errors(&truth, &track, Alignment::Rigid).expect("errors");
    let dr: Vec<TimedPoint> = sim
        .steps
        .steps()
        .iter()
        .zip(sim.steps.dead_reckon(Default::default()))
        .map(|(s, p)| TimedPoint {
            t: s.t,
            x: p.x,
            y: p.y,
        })
        .collect();
    let dead_reckoning = position_errors(&truth, &dr, Alignment::Rigid).expect("errors");
    let (map, _) = read_map_geojson(&out.join("map.geojson")).expect("map");
    let walkable = walkable_fraction(&map, &sim.plan, learned.transform.as_ref());
    eprintln!(
        "seed {seed} drift {drift_deg}°: learned p95 {:.2} m, dead reckoning p95 {:.2} m, walkable {:.1} %",
        learned.p95,
        dead_reckoning.p95,
        100.0 * walkable
    );
    assert!(
        learned.p95 <= 1.5,
        "seed {seed}: p95 {:.2} m > 1.5 m",
        learned.p95
    );
    assert!(
        learned.p95 <= dead_reckoning.p95 / 3.0,
        "seed {seed}: p95 {:.2} m is not a third of dead reckoning's {:.2} m",
        learned.p95,
        dead_reckoning.p95
    );
    assert!(
        walkable >= 0.9,
        "seed {seed}: only {:.1} % walkable",
        100.0 * walkable
    );
}

#[test]
fn learns_office_walks_with_moderate_drift() {
    for seed in [101, 202] {
        check_seed(seed, 10.0);
    }
}

#[test]
fn learns_office_walks_with_strong_drift() {
    for seed in [303, 404] {
        check_seed(seed, 20.0);
    }
}
