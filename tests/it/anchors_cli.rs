//! `learn` with GPS (CSV and GPX), outline and prior map, and `merge`: inputs in every
//! accepted form, and clear errors for bad ones.

use assert_cmd::Command;
use std::path::{Path, PathBuf};

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

fn simulate(dir: &Path) -> PathBuf {
    let sim = dir.join("sim");
    footslam()
        .args([
            "simulate",
            "--building",
            "campus",
            "--laps",
            "1",
            "--seed",
            "8",
        ])
        .args(["--origin", "48.15,11.57", "--out"])
        .arg(&sim)
        .assert()
        .success();
    sim
}

fn learn(sim: &Path, out: &Path, extra: &[&str]) -> assert_cmd::assert::Assert {
    footslam()
        .args(["learn", "--particles", "300", "--steps"])
        .arg(sim.join("steps.csv"))
        .arg("--out")
        .arg(out)
        .args(extra)
        .assert()
}

fn stderr(a: assert_cmd::assert::Assert) -> String {
    String::from_utf8_lossy(&a.failure().get_output().stderr).into_owned()
}

/// The simulated fixes as GPX 1.1, with UTC times `t0 + t`.
fn write_gpx(gps_csv: &Path, path: &Path) {
    let text = std::fs::read_to_string(gps_csv).expect("gps");
    let mut gpx = String::from(
        "<?xml version=\"1.0\"?>\n<gpx version=\"1.1\" creator=\"test\" xmlns=\"http://www.topografix.com/GPX/1/1\"><trk><trkseg>\n",
    );
    for line in text.lines().skip(1) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().expect("n")).collect();
        let (m, s) = ((v[0] / 60.0).floor(), v[0] % 60.0);
        gpx.push_str(&format!(
            "<trkpt lat=\"{}\" lon=\"{}\"><time>2024-05-01T10:{m:02}:{s:06.3}Z</time><hdop>0.7</hdop></trkpt>\n",
            v[1], v[2]
        ));
    }
    gpx.push_str("</trkseg></trk></gpx>\n");
    std::fs::write(path, gpx).expect("write gpx");
}

#[test]
fn gpx_needs_its_clock_and_then_anchors_like_csv() {
    let dir = tempfile::tempdir().expect("tempdir");
    let sim = simulate(dir.path());
    let gpx = dir.path().join("walk.gpx");
    write_gpx(&sim.join("gps.csv"), &gpx);
    let gpx_arg = gpx.to_str().expect("utf-8");
    let err = stderr(learn(&sim, &dir.path().join("a"), &["--gps", gpx_arg]));
    assert!(
        err.contains("walk.gpx") && err.contains("--gps-t0"),
        "{err}"
    );
    let out = dir.path().join("b");
    learn(
        &sim,
        &out,
        &["--gps", gpx_arg, "--gps-t0", "2024-05-01T10:00:00Z"],
    )
    .success();
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).expect("r"))
            .expect("json");
    let fixes = std::fs::read_to_string(sim.join("gps.csv"))
        .expect("gps")
        .lines()
        .count()
        - 1;
    assert_eq!(summary["gps_fixes"].as_u64(), Some(fixes as u64));
    assert_eq!(summary["gps_fixes_used"].as_u64(), Some(fixes as u64));
    assert!(out.join("track.geojson").is_file() && out.join("map.geojson").is_file());
}

#[test]
fn bad_gps_outline_and_prior_maps_are_explained() {
    let dir = tempfile::tempdir().expect("tempdir");
    let sim = simulate(dir.path());
    let bad = dir.path().join("gps.csv");
    std::fs::write(&bad, "t,lat,lon\n0,48.15,11.57\n1,48.15,NaN\n").expect("write");
    let err = stderr(learn(
        &sim,
        &dir.path().join("a"),
        &["--gps", bad.to_str().expect("p")],
    ));
    assert!(err.contains("gps.csv:3"), "{err}");
    let gps = sim.join("gps.csv");
    let gps = gps.to_str().expect("p");
    let err = stderr(learn(
        &sim,
        &dir.path().join("a"),
        &["--gps", gps, "--gps", gps],
    ));
    assert!(err.contains("one per walk"), "{err}");
    let outline = dir.path().join("outline.geojson");
    std::fs::write(
        &outline,
        r#"{"type": "LineString", "coordinates": [[11.57, 48.15], [11.58, 48.15]]}"#,
    )
    .expect("write");
    let err = stderr(learn(
        &sim,
        &dir.path().join("a"),
        &["--outline", outline.to_str().expect("p")],
    ));
    assert!(
        err.contains("outline.geojson") && err.contains("LineString"),
        "{err}"
    );

    // A map learned at one origin cannot seed a walk at another, nor merge with its maps.
    let first = dir.path().join("first");
    learn(&sim, &first, &["--origin", "48.15,11.57"]).success();
    let map = first.join("map.geojson");
    let map_arg = map.to_str().expect("p");
    let err = stderr(learn(
        &sim,
        &dir.path().join("a"),
        &["--prior-map", map_arg, "--origin", "48.16,11.57"],
    ));
    assert!(
        err.contains("map.geojson") && err.contains("--origin 48.15,11.57"),
        "{err}"
    );
    let err = stderr(learn(
        &sim,
        &dir.path().join("a"),
        &["--prior-map", map_arg, "--hex-radius", "0.6"],
    ));
    assert!(
        err.contains("hexagons of radius")
            && err.contains("this run uses 0.6 m, or pass --hex-radius 0.5"),
        "{err}"
    );
    let other = dir.path().join("other");
    learn(&sim, &other, &["--origin", "48.2,11.57"]).success();
    let err = stderr(
        footslam()
            .arg("merge")
            .arg(&map)
            .arg(other.join("map.geojson"))
            .arg("--out")
            .arg(dir.path().join("m.geojson"))
            .assert(),
    );
    assert!(err.contains("other") && err.contains("origin"), "{err}");
    assert!(
        !dir.path().join("m.geojson").exists(),
        "nothing written on error"
    );

    // Without --origin the prior map's origin is used, and the walk learns from it.
    let second = dir.path().join("second");
    learn(
        &sim,
        &second,
        &["--prior-map", map_arg, "--prior-weight", "0.5"],
    )
    .success();
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(second.join("summary.json")).expect("r"))
            .expect("json");
    assert_eq!(summary["origin"]["lat"], 48.15);
    assert!(summary["prior_map_hexagons"].as_u64().expect("n") > 50);
    let config: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(second.join("config.json")).expect("r"))
            .expect("json");
    assert_eq!(config["prior_weight"], 0.5);
}

/// `gps.csv` of `sim` with each row's `(t, lat, lon)` changed by `edit`.
fn edited_fixes(sim: &Path, to: &Path, edit: impl Fn(f64, f64, f64) -> (f64, f64, f64)) {
    let text = std::fs::read_to_string(sim.join("gps.csv")).expect("gps");
    let mut lines = text.lines();
    let header = lines.next().expect("header");
    let cols: Vec<&str> = header.split(',').collect();
    let at = |name: &str| cols.iter().position(|c| *c == name).expect(name);
    let (it, ilat, ilon) = (at("t"), at("lat"), at("lon"));
    let mut out = format!("{header}\n");
    for line in lines {
        let mut f: Vec<String> = line.split(',').map(str::to_owned).collect();
        let num = |i: usize| f[i].parse::<f64>().expect("number");
        let (t, lat, lon) = edit(num(it), num(ilat), num(ilon));
        f[it] = t.to_string();
        f[ilat] = lat.to_string();
        f[ilon] = lon.to_string();
        out.push_str(&f.join(","));
        out.push('\n');
    }
    std::fs::write(to, out).expect("write");
}

#[test]
fn fixes_and_outlines_of_another_place_or_clock_are_said() {
    let dir = tempfile::tempdir().expect("tempdir");
    let sim = simulate(dir.path());
    let d = dir.path();
    // The same fixes 500 km away (another city than --origin).
    let far = d.join("far.csv");
    edited_fixes(&sim, &far, |t, lat, lon| (t, lat - 4.5, lon));
    let err = stderr(learn(
        &sim,
        &d.join("a"),
        &["--gps", far.to_str().expect("p"), "--origin", "48.15,11.57"],
    ));
    assert!(
        err.contains("far.csv") && err.contains("km from the run's origin"),
        "{err}"
    );
    // A receiver's "no fix" rows at 0°, 0°.
    let null = d.join("null.csv");
    edited_fixes(&sim, &null, |t, lat, lon| {
        if t < 5.0 {
            (t, 0.0, 0.0)
        } else {
            (t, lat, lon)
        }
    });
    let err = stderr(learn(
        &sim,
        &d.join("a"),
        &["--gps", null.to_str().expect("p")],
    ));
    assert!(err.contains("null.csv:") && err.contains("no fix"), "{err}");
    // The fixes on a clock running a third of the walk late: they still overlap the walk,
    // so the run goes on, but says so.
    let fixes = std::fs::read_to_string(sim.join("gps.csv")).expect("gps");
    let last_t: f64 = fixes
        .lines()
        .last()
        .and_then(|l| l.split(',').next())
        .and_then(|t| t.parse().ok())
        .expect("t");
    let late = d.join("late.csv");
    edited_fixes(&sim, &late, |t, lat, lon| (t + 0.4 * last_t, lat, lon));
    let out = learn(&sim, &d.join("late"), &["--gps", late.to_str().expect("p")]).success();
    let err = String::from_utf8_lossy(&out.get_output().stderr).into_owned();
    assert!(
        err.contains("late.csv") && err.contains("outside the walk's time span"),
        "{err}"
    );
    // An outline 20 km from the walk, and one of a few square millimetres.
    let outline = |name: &str, lat: f64, size: f64| {
        let path = d.join(name);
        let ring = format!(
            "[[11.57,{lat}],[{},{lat}],[{},{}],[11.57,{}],[11.57,{lat}]]",
            11.57 + size,
            11.57 + size,
            lat + size,
            lat + size
        );
        std::fs::write(
            &path,
            format!(r#"{{"type":"Polygon","coordinates":[{ring}]}}"#),
        )
        .expect("outline");
        path
    };
    let away = outline("away.geojson", 48.33, 0.001);
    let err = stderr(learn(
        &sim,
        &d.join("a"),
        &[
            "--outline",
            away.to_str().expect("p"),
            "--origin",
            "48.15,11.57",
        ],
    ));
    assert!(
        err.contains("away.geojson") && err.contains("from the walk's start"),
        "{err}"
    );
    let tiny = outline("tiny.geojson", 48.15, 1e-8);
    let err = stderr(learn(
        &sim,
        &d.join("a"),
        &[
            "--outline",
            tiny.to_str().expect("p"),
            "--origin",
            "48.15,11.57",
        ],
    ));
    assert!(err.contains("tiny.geojson") && err.contains("m²"), "{err}");
}
