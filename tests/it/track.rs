//! `footslam track` end to end: outputs, reproducibility, recovery and clear errors, on
//! simulated multi-floor walks.

use assert_cmd::Command;
use image::GenericImageView;
use predicates::prelude::*;
use std::path::{Path, PathBuf};

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

/// Simulates a short tower walk into `dir`.
pub(crate) fn simulate_tower(dir: &Path, seed: &str, minutes: &str) -> PathBuf {
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
        "track_filtered.csv",
        "track.geojson",
        "track.png",
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
    // The filtered track: one row per step from localisation on, on the truth's clock.
    let text = std::fs::read_to_string(out.join("track_filtered.csv")).expect("filtered");
    assert!(text.starts_with("t,x,y,z,level\n"));
    assert_eq!(
        text.lines().count() as u64 - 1,
        steps - localised + 1,
        "rows from localisation on"
    );
    // The smoothed answer: one row per step, those before localisation included, each
    // saying whether the walk settles it; here the whole walk does.
    let text = std::fs::read_to_string(out.join("track.csv")).expect("track");
    assert!(text.starts_with("t,x,y,z,level,certain,hypotheses,spread,share\n"));
    assert_eq!(text.lines().count() as u64 - 1, steps, "a row per step");
    let smoothing = &summary["smoothing"];
    assert_eq!(smoothing["steps_certain"].as_u64(), Some(steps));
    assert!(smoothing["path_nodes_peak"].as_u64().expect("nodes") > 0);
    // --online: no ancestry, track.csv is the filtered track.
    let online = dir.path().join("online");
    track(&sim, &online, &["--seed", "4", "--online"]).success();
    assert_eq!(
        std::fs::read(online.join("track.csv")).expect("online"),
        std::fs::read(out.join("track_filtered.csv")).expect("filtered"),
        "the filter does not depend on the ancestry"
    );
    assert!(!online.join("track_filtered.csv").exists());
    assert!(json(&online.join("summary.json"))["smoothing"].is_null());
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
    // The pictures show the walk, not the whole building; or the part asked for.
    let whole = image::open(one.join("particles.png")).expect("png");
    let walk = image::open(known.join("particles.png")).expect("png");
    assert!(walk.height() <= 4000 && walk.width() <= 4000);
    let corner = dir.path().join("corner");
    track(
        &sim,
        &corner,
        &["--start", &arg, "--picture-extent", "0,0,10,10"],
    )
    .success();
    let small = image::open(corner.join("track.png")).expect("png");
    let large = image::open(known.join("track.png")).expect("png");
    assert!(
        small.height() < large.height() || small.width() < large.width(),
        "{:?} {:?} {:?}",
        small.dimensions(),
        large.dimensions(),
        whole.dimensions()
    );
    track(
        &sim,
        &dir.path().join("bad"),
        &["--picture-extent", "5,0,1,10"],
    )
    .failure()
    .stderr(predicate::str::contains("picture.extent"));
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
        .args(["track", "--start", "1"])
        .assert()
        .failure()
        .stderr(predicate::str::contains("X,Y[,HEADING[,LEVEL]]"));
    footslam()
        .args(["track", "--start", "1,2,east"])
        .assert()
        .failure()
        .stderr(predicate::str::contains(
            "HEADING `east` is not a finite number",
        ));
}

#[test]
fn simulate_tower_writes_wifi_scans_and_the_radio_truth() {
    let dir = tempfile::tempdir().expect("tempdir");
    let sim = simulate_tower(dir.path(), "8", "2");
    let scans = footslam::io::read_wifi(&sim.join("wifi.csv")).expect("wifi.csv parses");
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
    let (map, _) = footslam::io::radio_map_geojson::read_radio_map_geojson(
        &out.join("radiomap.geojson"),
        None,
    )
    .expect("radiomap.geojson reads back");
    assert!(map.cells.iter().any(|c| c.radio.scans > 0));
    assert!(out.join("radiomap.csv").is_file() && out.join("radiomap.png").is_file());
    let bssid = map.access_points()[0].replace(':', "-");
    assert!(
        out.join(format!("heatmap-{bssid}.png")).is_file(),
        "{bssid}"
    );
    // `--heatmaps 2`: the two access points heard in the most cells (then most readings,
    // then by BSSID); the same map on one thread as on two (walks run in parallel).
    let mut widest: Vec<(usize, u32, String)> = map
        .access_points()
        .into_iter()
        .map(|b| {
            let stats = map.cells.iter().filter_map(|c| c.radio.aps.get(b));
            let (cells, readings) = stats.fold((0, 0), |(c, n), s| (c + 1, n + s.n));
            (cells, readings, b.to_string())
        })
        .collect();
    widest.sort_by(|a, b| b.0.cmp(&a.0).then(b.1.cmp(&a.1)).then(a.2.cmp(&b.2)));
    assert!(widest.len() > 2, "{widest:?}");
    let two = dir.path().join("survey-two");
    let mut survey = footslam();
    survey
        .arg("survey")
        .arg("--plan")
        .arg(a.join("floor.geojson"));
    for walk in [&a, &b] {
        survey.arg("--steps").arg(walk.join("steps.csv"));
        survey.arg("--wifi").arg(walk.join("wifi.csv"));
    }
    survey
        .args(["--heatmaps", "2", "--threads", "1", "--out"])
        .arg(&two)
        .assert()
        .success()
        .stdout(predicate::str::contains(format!(
            "heatmaps: 2 of the {} access points",
            widest.len()
        )));
    let mut drawn: Vec<String> = std::fs::read_dir(&two)
        .expect("survey folder")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("heatmap-"))
        .collect();
    drawn.sort();
    let mut want: Vec<String> = widest[..2]
        .iter()
        .map(|(_, _, b)| format!("heatmap-{}.png", b.replace(':', "-")))
        .collect();
    want.sort();
    assert_eq!(drawn, want);
    assert_eq!(
        std::fs::read(two.join("radiomap.geojson")).expect("map"),
        std::fs::read(out.join("radiomap.geojson")).expect("map"),
        "one thread and all threads survey the same map"
    );
    footslam()
        .args(["survey", "--heatmaps", "some"])
        .assert()
        .failure()
        .stderr(predicate::str::contains(
            "a number of access points or `all`",
        ));
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

/// Position errors of `out`'s track.csv against `sim`'s truth.csv, unaligned.
fn track_errors(sim: &Path, out: &Path) -> footslam::eval::ErrorReport {
    let truth = footslam::io::read_trajectory(&sim.join("truth.csv")).expect("truth");
    let track = footslam::io::read_trajectory(&out.join("track.csv")).expect("track");
    footslam::eval::position_errors(&truth, &track, footslam::eval::Alignment::None)
        .expect("errors")
}

#[test]
fn a_start_without_a_heading_localises_at_the_known_place() {
    let dir = tempfile::tempdir().expect("tempdir");
    let sim = simulate_tower(dir.path(), "4", "3");
    let s = json(&sim.join("summary.json"))["start"].clone();
    // X,Y (the lowest surface there) and X,Y,,LEVEL: position known, heading not.
    for (name, arg) in [
        ("xy", format!("{},{}", s["x"], s["y"])),
        ("xyl", format!("{},{},,{}", s["x"], s["y"], s["level"])),
    ] {
        let out = dir.path().join(name);
        track(&sim, &out, &[&format!("--start={arg}")]).success();
        let config = json(&out.join("config.json"));
        assert!(config["start"]["heading"].is_null(), "{name}");
        let summary = json(&out.join("summary.json"));
        let localised = summary["steps_to_localise"].as_u64().expect("localised");
        assert!(localised <= 15, "{name}: localised after {localised} steps");
        let errors = track_errors(&sim, &out);
        assert!(errors.p95 < 1.0, "{name}: p95 {:.2} m", errors.p95);
    }
    // An old config.json with a numeric heading still reads.
    let out = dir.path().join("numeric");
    let config = dir.path().join("config.json");
    let text = format!(
        r#"{{"start": {{"x": {}, "y": {}, "heading": {}, "level": {}}}}}"#,
        s["x"], s["y"], s["heading"], s["level"]
    );
    std::fs::write(&config, text).expect("write");
    track(&sim, &out, &["--config", config.to_str().expect("utf-8")]).success();
    assert_eq!(json(&out.join("summary.json"))["steps_to_localise"], 1);
}

/// `sim`'s steps with absolute headings: the true heading plus 10° of noise, a fifth of
/// them a further 60° off either way (a disturbed compass), drawn from `seed`.
fn with_headings(sim: &Path, seed: u64) -> PathBuf {
    use footslam::random::{gauss, stream};
    use rand::RngExt;
    let trace = footslam::io::read_steps(&sim.join("steps.csv")).expect("steps");
    let truth = footslam::io::truth_csv::read_truth(&sim.join("truth.csv")).expect("truth");
    let mut rng = stream(seed, 0, 0x4EAD);
    let steps: Vec<footslam::sensor::Step> = trace
        .steps()
        .iter()
        .zip(&truth.poses)
        .map(|(s, p)| {
            let mut h = p.heading + 10f64.to_radians() * gauss(&mut rng);
            if rng.random::<f64>() < 0.2 {
                h += 60f64.to_radians() * if rng.random::<bool>() { 1.0 } else { -1.0 };
            }
            footslam::sensor::Step {
                heading: Some(h.sin().atan2(h.cos())),
                ..*s
            }
        })
        .collect();
    let path = sim.join("steps-heading.csv");
    let trace = footslam::sensor::StepTrace::new(steps).expect("valid");
    footslam::io::steps_csv::write_steps(&path, &trace).expect("write");
    path
}

#[test]
#[allow(clippy::print_stderr)] // reports the figures with --nocapture
fn noisy_compass_headings_localise_sooner_than_ignoring_them() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (mut with, mut without) = (0, 0);
    for seed in ["4", "5", "6"] {
        // One floor: no identical floor for a heading to leave ambiguous.
        let sim = dir.path().join(format!("one-floor-{seed}"));
        footslam()
            .args(["simulate", "--building", "tower", "--floors", "1"])
            .args(["--minutes", "3", "--seed", seed, "--out"])
            .arg(&sim)
            .assert()
            .success();
        let steps = with_headings(&sim, seed.parse().expect("seed"));
        let run = |name: &str, extra: &[&str]| {
            let out = dir.path().join(format!("{name}-{seed}"));
            footslam()
                .arg("track")
                .arg("--plan")
                .arg(sim.join("floor.geojson"))
                .arg("--steps")
                .arg(&steps)
                .args(["--seed", seed, "--out"])
                .arg(&out)
                .args(extra)
                .assert()
                .success();
            let summary = json(&out.join("summary.json"));
            let n = summary["steps_to_localise"].as_u64().expect("localised");
            let p95 = track_errors(&sim, &out).p95;
            (summary, n, p95)
        };
        let (used, n_with, p95_with) = run("with", &[]);
        let (ignored, n_without, p95_without) = run("without", &["--ignore-heading"]);
        eprintln!(
            "seed {seed}: localised after {n_with} steps with headings (p95 {p95_with:.2} m), {n_without} without (p95 {p95_without:.2} m)"
        );
        assert_eq!(used["headings_used"], true);
        assert_eq!(ignored["headings_used"], false);
        assert_eq!(used["steps_with_heading"], used["steps"]);
        assert_eq!(ignored["steps_with_heading"], used["steps"]);
        assert!(
            n_with <= n_without + 5,
            "seed {seed}: {n_with} vs {n_without}"
        );
        assert!(p95_with < 1.5, "seed {seed}: p95 {p95_with:.2} m");
        with += n_with;
        without += n_without;
    }
    // Measured: 49 + 34 + 54 = 137 steps with headings, 63 + 79 + 63 = 205 without.
    assert!(
        with * 5 <= without * 4,
        "{with} steps to localise with headings, {without} without"
    );
}
