//! Every GeoJSON footslam writes validates as RFC 7946: a `FeatureCollection` without a `crs`
//! member, positions `[lon, lat]` in range (longitude first), closed polygon rings of at least
//! four positions, exterior rings counter-clockwise and holes clockwise (sec. 3.1.6).
//!
//! The outputs come from a short campus walk (GPS, outline, batch of two walks, merge), with
//! the origin in Munich so that swapped coordinates are caught (lat 48 is not lon 11).

use assert_cmd::Command;
use serde_json::Value;
use std::path::Path;

const LAT: f64 = 48.15;
const LON: f64 = 11.57;

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

/// Twice the signed area of a ring in (lon, lat): positive when counter-clockwise.
fn signed_area(ring: &[Value]) -> f64 {
    ring.windows(2)
        .map(|w| {
            let (a, b) = (&w[0], &w[1]);
            a[0].as_f64().unwrap_or(0.0) * b[1].as_f64().unwrap_or(0.0)
                - b[0].as_f64().unwrap_or(0.0) * a[1].as_f64().unwrap_or(0.0)
        })
        .sum()
}

fn check_position(p: &Value, file: &str) {
    let p = p
        .as_array()
        .unwrap_or_else(|| panic!("{file}: position {p} is not an array"));
    assert!(p.len() >= 2, "{file}: position with {} numbers", p.len());
    let (lon, lat) = (p[0].as_f64().expect("lon"), p[1].as_f64().expect("lat"));
    assert!(
        lon.abs() <= 180.0 && lat.abs() <= 90.0,
        "{file}: [{lon}, {lat}] out of range"
    );
    // Longitude first: near the origin's longitude, not its latitude.
    assert!(
        (lon - LON).abs() < 0.01 && (lat - LAT).abs() < 0.01,
        "{file}: [{lon}, {lat}]"
    );
}

fn check_ring(ring: &Value, exterior: bool, file: &str) {
    let ring = ring.as_array().expect("ring");
    assert!(ring.len() >= 4, "{file}: ring of {} positions", ring.len());
    assert_eq!(ring.first(), ring.last(), "{file}: ring not closed");
    ring.iter().for_each(|p| check_position(p, file));
    let area = signed_area(ring);
    if exterior {
        assert!(area > 0.0, "{file}: exterior ring is clockwise");
    } else {
        assert!(area < 0.0, "{file}: hole is counter-clockwise");
    }
}

fn check_geometry(g: &Value, file: &str) {
    let c = &g["coordinates"];
    match g["type"].as_str().expect("geometry type") {
        "Point" => check_position(c, file),
        "LineString" => c
            .as_array()
            .expect("line")
            .iter()
            .for_each(|p| check_position(p, file)),
        "Polygon" => {
            for (i, ring) in c.as_array().expect("rings").iter().enumerate() {
                check_ring(ring, i == 0, file);
            }
        }
        "MultiPolygon" => {
            for poly in c.as_array().expect("polygons") {
                for (i, ring) in poly.as_array().expect("rings").iter().enumerate() {
                    check_ring(ring, i == 0, file);
                }
            }
        }
        other => panic!("{file}: unexpected geometry {other}"),
    }
}

fn validate(path: &Path) -> usize {
    let file = path.display().to_string();
    let v: Value =
        serde_json::from_str(&std::fs::read_to_string(path).expect("read")).expect("json");
    assert_eq!(v["type"], "FeatureCollection", "{file}");
    assert!(v.get("crs").is_none(), "{file}: has a crs member");
    let features = v["features"].as_array().expect("features");
    for f in features {
        assert_eq!(f["type"], "Feature", "{file}");
        assert!(f.get("crs").is_none());
        check_geometry(&f["geometry"], &file);
    }
    features.len()
}

#[test]
fn every_geojson_output_is_rfc_7946() {
    let dir = tempfile::tempdir().expect("tempdir");
    let sim = dir.path().join("sim");
    footslam()
        .args([
            "simulate",
            "--building",
            "campus",
            "--walks",
            "2",
            "--laps",
            "1",
            "--seed",
            "4",
        ])
        .args(["--origin", &format!("{LAT},{LON}"), "--out"])
        .arg(&sim)
        .assert()
        .success();
    let learn = dir.path().join("learn");
    footslam()
        .args(["learn", "--particles", "500", "--steps"])
        .arg(&sim)
        .arg("--outline")
        .arg(sim.join("outline.geojson"))
        .arg("--out")
        .arg(&learn)
        .assert()
        .success();
    let merged = dir.path().join("merged.geojson");
    footslam()
        .arg("merge")
        .arg(learn.join("walk-1/map.geojson"))
        .arg(learn.join("walk-2/map.geojson"))
        .arg("--out")
        .arg(&merged)
        .assert()
        .success();
    let files = [
        sim.join("floor.geojson"),
        sim.join("outline.geojson"),
        learn.join("walk-1/map.geojson"),
        learn.join("walk-2/track.geojson"),
        learn.join("merged.geojson"),
        merged.clone(),
    ];
    for f in &files {
        assert!(validate(f) > 0, "{} is empty", f.display());
    }
    // The batch's own merge and `footslam merge` agree, and hold two walks.
    let a: Value =
        serde_json::from_str(&std::fs::read_to_string(&files[4]).expect("r")).expect("j");
    let b: Value = serde_json::from_str(&std::fs::read_to_string(&merged).expect("r")).expect("j");
    assert_eq!(a["features"], b["features"]);
    assert_eq!(b["walks"], 2);
    // With GPS and no --origin the frame's origin is the first fix.
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(learn.join("summary.json")).expect("r"))
            .expect("j");
    let gps = std::fs::read_to_string(sim.join("walk-1/gps.csv")).expect("gps");
    let first: Vec<f64> = gps
        .lines()
        .nth(1)
        .expect("fix")
        .split(',')
        .map(|v| v.parse().expect("n"))
        .collect();
    assert!((summary["origin"]["lat"].as_f64().expect("lat") - first[1]).abs() < 1e-12);
    assert!((summary["origin"]["lon"].as_f64().expect("lon") - first[2]).abs() < 1e-12);
}
