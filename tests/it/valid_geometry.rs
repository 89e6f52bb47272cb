//! Every geometry the toolkit writes is valid by geo's OGC validation (what GEOS — hence
//! QGIS, PostGIS, shapely and geopandas — checks): maps, learned plans, radio maps, tracks,
//! simulated plans and outlines.

use assert_cmd::Command;
use geo::Validation;
use std::path::Path;

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

/// The invalid geometries of a GeoJSON file, as `feature index: reason`.
fn invalid_geometries(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).expect("read");
    let json: geojson::GeoJson = text.parse().expect("GeoJSON");
    let features = match json {
        geojson::GeoJson::FeatureCollection(c) => c.features,
        geojson::GeoJson::Feature(f) => vec![f],
        geojson::GeoJson::Geometry(g) => vec![geojson::Feature::from(g)],
    };
    let mut bad = Vec::new();
    for (i, feature) in features.into_iter().enumerate() {
        let Some(geometry) = feature.geometry else {
            continue;
        };
        let geometry: geo::Geometry<f64> = geometry.try_into().expect("geometry");
        if let Err(e) = geometry.check_validation() {
            bad.push(format!("feature {i}: {e}"));
        }
    }
    bad
}

#[test]
fn every_written_geometry_is_valid() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let tower = Path::new(env!("CARGO_MANIFEST_DIR")).join("datasets/tower");
    footslam()
        .args(["survey", "--plan"])
        .arg(tower.join("floor.geojson"))
        .arg("--steps")
        .arg(tower.join("steps.csv"))
        .arg("--wifi")
        .arg(tower.join("wifi.csv"))
        .arg("--out")
        .arg(d.join("survey"))
        .assert()
        .success();
    footslam()
        .args(["learn", "--particles", "2000", "--out"])
        .arg(d.join("learn"))
        .assert()
        .success();
    footslam()
        .args(["simulate", "--building", "campus", "--seed", "3", "--out"])
        .arg(d.join("campus"))
        .assert()
        .success();
    let files = [
        "survey/radiomap.geojson",
        "learn/map.geojson",
        "learn/plan.geojson",
        "learn/track.geojson",
        "campus/floor.geojson",
        "campus/outline.geojson",
    ];
    for file in files {
        let path = d.join(file);
        assert!(path.is_file(), "{file} written");
        let bad = invalid_geometries(&path);
        assert!(bad.is_empty(), "{file}: {bad:?}");
    }
}
