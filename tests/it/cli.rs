//! The command line end to end: outputs, formats, reproducibility and clear errors.

use assert_cmd::Command;
use std::path::{Path, PathBuf};

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

/// Simulates a short walk (1 lap) into `dir` and returns the folder.
fn simulate_into(dir: &Path, seed: &str) -> PathBuf {
    simulate_with(dir, seed, &[])
}

/// As [`simulate_into`], with `extra` flags.
fn simulate_with(dir: &Path, seed: &str, extra: &[&str]) -> PathBuf {
    let out = dir.join(format!("sim-{seed}"));
    footslam()
        .args([
            "simulate",
            "--laps",
            "1",
            "--seed",
            seed,
            "--origin",
            "48.15,11.57",
        ])
        .args(extra)
        .arg("--out")
        .arg(&out)
        .assert()
        .success();
    out
}

/// Simulates a tower walk of `minutes` into `out`, with `extra` flags.
fn simulate_tower(out: &Path, minutes: &str, seed: &str, extra: &[&str]) {
    footslam()
        .args(["simulate", "--building", "tower", "--minutes", minutes])
        .args(["--seed", seed])
        .args(extra)
        .arg("--out")
        .arg(out)
        .assert()
        .success();
}

fn learn(steps: &Path, out: &Path, extra: &[&str]) -> assert_cmd::assert::Assert {
    let seed = if extra.contains(&"--seed") {
        &[][..]
    } else {
        &["--seed", "5"][..]
    };
    footslam()
        .args([
            "learn",
            "--particles",
            "2000",
            "--origin",
            "48.15,11.57",
            "--steps",
        ])
        .arg(steps)
        .arg("--out")
        .arg(out)
        .args(extra)
        .args(seed)
        .assert()
}

#[test]
fn simulate_writes_plan_steps_truth_and_picture() {
    let dir = tempfile::tempdir().expect("tempdir");
    let sim = simulate_into(dir.path(), "3");
    for f in [
        "floor.geojson",
        "steps.csv",
        "truth.csv",
        "truth.png",
        "config.json",
        "summary.json",
    ] {
        assert!(sim.join(f).is_file(), "missing {f}");
    }
    let truth = std::fs::read_to_string(sim.join("truth.csv")).expect("truth");
    assert!(truth.starts_with("t,x,y,z,level,heading\n"));
    let plan: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(sim.join("floor.geojson")).expect("plan"))
            .expect("json");
    assert_eq!(plan["type"], "FeatureCollection");
    assert!(plan.get("crs").is_none());
    assert!((plan["origin"]["lat"].as_f64().expect("lat") - 48.15).abs() < 1e-12);
}

#[test]
fn learn_writes_every_output_in_the_documented_formats() {
    let dir = tempfile::tempdir().expect("tempdir");
    let sim = simulate_into(dir.path(), "4");
    let out = dir.path().join("learn");
    learn(&sim.join("steps.csv"), &out, &[]).success();
    for f in [
        "map.geojson",
        "track.csv",
        "map.png",
        "summary.json",
        "config.json",
    ] {
        assert!(out.join(f).is_file(), "missing {f}");
    }
    // No staging folders are left behind.
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .expect("dir")
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().contains("staging"))
        .collect();
    assert!(leftovers.is_empty());

    let steps = std::fs::read_to_string(sim.join("steps.csv"))
        .expect("steps")
        .lines()
        .count()
        - 1;
    let track = std::fs::read_to_string(out.join("track.csv")).expect("track");
    assert!(track.starts_with("t,x,y,spread_m\n"));
    assert_eq!(track.lines().count() - 1, steps, "one track row per step");

    let map: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("map.geojson")).expect("map"))
            .expect("json");
    assert_eq!(map["type"], "FeatureCollection");
    assert!(map.get("crs").is_none());
    let features = map["features"].as_array().expect("features");
    assert!(features.len() > 20);
    for f in features {
        let p = &f["properties"];
        assert!(p["q"].is_i64() && p["r"].is_i64());
        assert_eq!(p["counts"].as_array().expect("counts").len(), 6);
        let probs: f64 = p["p"]
            .as_array()
            .expect("p")
            .iter()
            .map(|v| v.as_f64().expect("num"))
            .sum();
        assert!((probs - 1.0).abs() < 1e-3, "p sums to {probs}");
        assert!(p["visits"].as_u64().expect("visits") >= 1);
        let ring = f["geometry"]["coordinates"][0].as_array().expect("ring");
        assert_eq!(ring.len(), 7, "closed hexagon");
        let (lon, lat) = (
            ring[0][0].as_f64().expect("lon"),
            ring[0][1].as_f64().expect("lat"),
        );
        assert!(
            (lon - 11.57).abs() < 0.01 && (lat - 48.15).abs() < 0.01,
            "lon/lat order"
        );
    }

    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).expect("summary"))
            .expect("json");
    assert_eq!(summary["particles"], 2000);
    assert_eq!(summary["steps"].as_u64().expect("steps") as usize, steps);
    assert!(
        summary["final_effective_sample_size"]
            .as_f64()
            .expect("ess")
            > 0.0
    );
    assert!(summary["runtime_s"].as_f64().is_some());

    let png = std::fs::read(out.join("map.png")).expect("png");
    assert_eq!(&png[1..4], b"PNG");

    // config.json feeds back as --config and reproduces the run.
    let again = dir.path().join("again");
    footslam()
        .args(["learn", "--origin", "48.15,11.57", "--steps"])
        .arg(sim.join("steps.csv"))
        .arg("--config")
        .arg(out.join("config.json"))
        .arg("--out")
        .arg(&again)
        .assert()
        .success();
    assert_eq!(
        std::fs::read(out.join("map.geojson")).expect("a"),
        std::fs::read(again.join("map.geojson")).expect("b")
    );
}

#[test]
fn same_seed_same_output_whatever_the_thread_count() {
    let dir = tempfile::tempdir().expect("tempdir");
    let sim = simulate_into(dir.path(), "6");
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    learn(&sim.join("steps.csv"), &a, &["--threads", "1"]).success();
    learn(&sim.join("steps.csv"), &b, &["--threads", "2"]).success();
    for f in ["track.csv", "map.geojson"] {
        assert_eq!(
            std::fs::read(a.join(f)).expect("a"),
            std::fs::read(b.join(f)).expect("b"),
            "{f}"
        );
    }
    // An absurd thread count is capped with a warning, the result unchanged.
    let many = dir.path().join("many");
    let assert = learn(&sim.join("steps.csv"), &many, &["--threads", "100000"]).success();
    let stderr = String::from_utf8_lossy(&assert.get_output().stderr).to_string();
    assert!(stderr.contains("--threads 100000 capped"), "{stderr}");
    assert_eq!(
        std::fs::read(a.join("track.csv")).expect("a"),
        std::fs::read(many.join("track.csv")).expect("many")
    );
    // An --out that would replace an input (the simulator's summary.json and config.json
    // beside its steps) is refused, and nothing there changes.
    let before = std::fs::read(sim.join("summary.json")).expect("summary");
    let assert = learn(&sim.join("steps.csv"), &sim, &[]).failure();
    let stderr = String::from_utf8_lossy(&assert.get_output().stderr).to_string();
    assert!(stderr.contains("would replace the input"), "{stderr}");
    assert_eq!(
        std::fs::read(sim.join("summary.json")).expect("summary"),
        before
    );
    assert!(!sim.join("track.csv").exists());
    let c = dir.path().join("c");
    learn(&sim.join("steps.csv"), &c, &["--seed", "99"]).success();
    assert_ne!(
        std::fs::read(a.join("track.csv")).expect("a"),
        std::fs::read(c.join("track.csv")).expect("c")
    );
}

#[test]
fn learn_accepts_a_toml_config() {
    let dir = tempfile::tempdir().expect("tempdir");
    let sim = simulate_into(dir.path(), "7");
    let toml = dir.path().join("footslam.toml");
    std::fs::write(
        &toml,
        "particles = 500\nhex_radius = 0.6\n[motion]\ndheading_sigma = 0.02\n",
    )
    .expect("write");
    let out = dir.path().join("learn");
    footslam()
        .args(["learn", "--steps"])
        .arg(sim.join("steps.csv"))
        .arg("--config")
        .arg(&toml)
        .arg("--out")
        .arg(&out)
        .assert()
        .success();
    let config: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("config.json")).expect("config"))
            .expect("json");
    assert_eq!(config["particles"], 500);
    assert_eq!(config["hex_radius"], 0.6);
    assert_eq!(config["motion"]["dheading_sigma"], 0.02);
    assert_eq!(config["alpha"], 0.8, "unset fields keep their defaults");

    std::fs::write(&toml, "particles = 500\nhex_radiuss = 0.6\n").expect("write");
    let bad = footslam()
        .args(["learn", "--config"])
        .arg(&toml)
        .assert()
        .failure();
    let err = String::from_utf8_lossy(&bad.get_output().stderr).into_owned();
    assert!(
        err.contains("footslam.toml") && err.contains("hex_radiuss"),
        "{err}"
    );
}

#[test]
fn eval_prints_percentiles() {
    let dir = tempfile::tempdir().expect("tempdir");
    let sim = simulate_into(dir.path(), "8");
    let out = dir.path().join("learn");
    learn(&sim.join("steps.csv"), &out, &[]).success();
    let assert = footslam()
        .args(["eval", "--align", "rigid", "--truth"])
        .arg(sim.join("truth.csv"))
        .arg("--track")
        .arg(out.join("track.csv"))
        .arg("--steps")
        .arg(sim.join("steps.csv"))
        .arg("--map")
        .arg(out.join("map.geojson"))
        .arg("--plan")
        .arg(sim.join("floor.geojson"))
        .assert()
        .success();
    let text = String::from_utf8_lossy(&assert.get_output().stdout).into_owned();
    for key in ["p50", "p75", "p95", "max", "dead reckoning", "walkable"] {
        assert!(text.contains(key), "missing {key} in {text}");
    }
}

/// Runs `learn` on a steps file with `content` and returns stderr.
fn learn_error(content: &str) -> String {
    let dir = tempfile::tempdir().expect("tempdir");
    let steps = dir.path().join("bad_steps.csv");
    std::fs::write(&steps, content).expect("write");
    let out = dir.path().join("out");
    let assert = footslam()
        .args(["learn", "--particles", "10", "--steps"])
        .arg(&steps)
        .arg("--out")
        .arg(&out)
        .assert()
        .failure();
    assert!(!out.exists(), "no outputs on failure");
    String::from_utf8_lossy(&assert.get_output().stderr).into_owned()
}

#[test]
fn bad_step_traces_get_clear_errors() {
    let cases = [
        (
            "t,length,dheading\n0,0.7,0\n1,0.7,zero\n",
            "bad_steps.csv:3",
        ),
        ("t,length,dheading\n0,0.7,0\n1,NaN,0\n", "bad_steps.csv:3"),
        ("t,length,dheading\n1,0.7,0\n0.5,0.7,0\n", "increasing"),
        ("", "empty"),
        ("t,length,dheading\n", "no steps"),
        ("t,length\n0,0.7\n", "dheading"),
        ("t,length,dheading\n0,70,0\n", "bad_steps.csv:2"),
        ("t,length,dheading\n0,0.7,0,9\n", "bad_steps.csv:2"),
        (
            "t,length,dheading,field\n0,0.7,0,45\n1,0.7,0,NaN\n",
            "bad_steps.csv:3",
        ),
        (
            "t,length,dheading,field,field_up\n0,0.7,0,45,-60\n",
            "exceeds the magnitude",
        ),
    ];
    for (content, expect) in cases {
        let err = learn_error(content);
        assert!(err.contains(expect), "expected `{expect}` in: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}

#[test]
fn missing_files_and_bad_arguments_are_reported() {
    let a = footslam()
        .args(["learn", "--steps", "/nonexistent/steps.csv"])
        .assert()
        .failure();
    let err = String::from_utf8_lossy(&a.get_output().stderr).into_owned();
    assert!(err.contains("/nonexistent/steps.csv"), "{err}");
    let a = footslam()
        .args(["learn", "--origin", "100,5"])
        .assert()
        .failure();
    assert!(String::from_utf8_lossy(&a.get_output().stderr).contains("latitude"));
    let a = footslam()
        .args(["learn", "--particles", "0"])
        .assert()
        .failure();
    assert!(String::from_utf8_lossy(&a.get_output().stderr).contains("particles"));
}

/// A track from a run whose local frame sits elsewhere (learn --gps puts its origin at the
/// first fix) is compared in the truth's frame, using the origins in each run's summary.json.
#[test]
fn eval_moves_a_track_into_the_truths_frame() {
    use footslam::geometry::LocalFrame;
    let dir = tempfile::tempdir().expect("tempdir");
    let (truth_dir, track_dir) = (dir.path().join("sim"), dir.path().join("run"));
    std::fs::create_dir_all(&truth_dir).expect("dir");
    std::fs::create_dir_all(&track_dir).expect("dir");
    let truth_frame = LocalFrame::new(48.15, 11.57).expect("frame");
    let track_frame = LocalFrame::new(48.1502, 11.5705).expect("frame"); // ~37 m east, 22 m north
    let summary =
        |f: &LocalFrame| format!(r#"{{"origin": {{"lat": {}, "lon": {}}}}}"#, f.lat, f.lon);
    std::fs::write(truth_dir.join("summary.json"), summary(&truth_frame)).expect("write");
    let anchored =
        summary(&track_frame).replace("{\"origin\"", "{\"gps_file\": \"gps.csv\", \"origin\"");
    std::fs::write(track_dir.join("summary.json"), &anchored).expect("write");
    let (mut truth, mut track) = (String::from("t,x,y\n"), String::from("t,x,y\n"));
    for i in 0..20 {
        let (x, y) = (f64::from(i) * 0.7, 3.0 + (f64::from(i) * 0.3).sin());
        truth.push_str(&format!("{},{x},{y}\n", i + 1));
        let (lon, lat) = truth_frame.to_lon_lat(x, y);
        let (tx, ty) = track_frame.to_local(lon, lat);
        track.push_str(&format!("{},{tx},{ty}\n", i + 1));
    }
    std::fs::write(truth_dir.join("truth.csv"), truth).expect("write");
    std::fs::write(track_dir.join("track.csv"), track).expect("write");
    let eval_track = |track: &Path| -> serde_json::Value {
        let out = footslam()
            .arg("eval")
            .arg("--truth")
            .arg(truth_dir.join("truth.csv"))
            .arg("--track")
            .arg(track)
            .arg("--json")
            .assert()
            .success();
        serde_json::from_slice(&out.get_output().stdout).expect("json")
    };
    let eval = || eval_track(&track_dir.join("track.csv"));
    let value = eval();
    let p95 = value["track"]["p95"].as_f64().expect("p95");
    assert!(p95 < 0.01, "p95 {p95} m: the frames were not reconciled");
    assert!(value["track_reprojected_from"]["lat"].as_f64().is_some());
    // A walk learned from steps alone starts at (0, 0) whatever its origin: left as it is.
    std::fs::write(track_dir.join("summary.json"), summary(&track_frame)).expect("write");
    let value = eval();
    assert!(value["track_reprojected_from"].is_null());
    assert!(value["track"]["p95"].as_f64().expect("p95") > 10.0);
    // A walk of a batch (`walk-N/`): its record is `walks[N − 1]` of the batch's summary.
    let walk_dir = dir.path().join("batch").join("walk-2");
    std::fs::create_dir_all(&walk_dir).expect("dir");
    std::fs::copy(track_dir.join("track.csv"), walk_dir.join("track.csv")).expect("copy");
    let batch = summary(&track_frame).replace(
        "{\"origin\"",
        "{\"walks\": [{\"gps_file\": null}, {\"gps_file\": \"gps.csv\"}], \"origin\"",
    );
    std::fs::write(dir.path().join("batch").join("summary.json"), batch).expect("write");
    let value = eval_track(&walk_dir.join("track.csv"));
    let p95 = value["track"]["p95"].as_f64().expect("p95");
    assert!(
        p95 < 0.01,
        "batch walk: p95 {p95} m, the frames were not reconciled"
    );
}

#[test]
fn a_wifi_log_that_repeats_an_access_point_in_a_scan_is_read_and_counted() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    simulate_tower(&d.join("sim"), "2", "3", &[]);
    // Real logs list an access point twice in a scan now and then: repeat the first row.
    let wifi = std::fs::read_to_string(d.join("sim/wifi.csv")).expect("wifi");
    let mut lines: Vec<&str> = wifi.lines().collect();
    let first = lines[1];
    lines.insert(2, first);
    std::fs::write(d.join("twice.csv"), lines.join("\n") + "\n").expect("write");
    let assert = footslam()
        .args(["learn", "--particles", "300", "--steps"])
        .arg(d.join("sim/steps.csv"))
        .arg("--wifi")
        .arg(d.join("twice.csv"))
        .arg("--out")
        .arg(d.join("out"))
        .assert()
        .success();
    let stderr = String::from_utf8_lossy(&assert.get_output().stderr).into_owned();
    assert!(
        stderr.contains("1 row(s) repeated an access point"),
        "{stderr}"
    );
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(d.join("out/summary.json")).expect("summary"),
    )
    .expect("json");
    assert_eq!(summary["wifi_in_filter"]["duplicate_readings"], 1);
}

#[test]
fn learn_weighs_the_magnetic_field_when_the_steps_carry_it() {
    use footslam::io::read_steps_with_field;
    let dir = tempfile::tempdir().expect("tempdir");
    let sim = simulate_with(dir.path(), "8", &["--magnetometer"]);
    let steps = sim.join("steps.csv");
    let (trace, field) = read_steps_with_field(&steps).expect("steps");
    assert_eq!(field.expect("field columns").with_vertical(), trace.len());
    footslam()
        .args([
            "simulate",
            "--building",
            "campus",
            "--magnetometer",
            "--out",
        ])
        .arg(dir.path().join("campus"))
        .assert()
        .failure()
        .stderr(predicates::str::contains("campus"));
    // The tower's field has one map per floor; its walks read it on every floor.
    let tower = dir.path().join("tower");
    simulate_tower(&tower, "3", "2", &["--magnetometer"]);
    let (tower_steps, tower_field) =
        read_steps_with_field(&tower.join("steps.csv")).expect("steps");
    assert_eq!(
        tower_field.expect("field columns").observed(),
        tower_steps.len()
    );
    let out = dir.path().join("learned");
    learn(&steps, &out, &[])
        .success()
        .stdout(predicates::str::contains("magnetic field: "));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).expect("read"))
            .expect("json");
    let m = &summary["magnetic_field"];
    assert_eq!(m["steps_with_field"], trace.len());
    assert_eq!(m["steps_weighed"], trace.len(), "{m}");
    assert!(m["unused"].is_null());
    assert_eq!(m["calibration"]["components"], 2);
    // The learned field map: hexagons with readings and an Earth-like field.
    let fieldmap: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("fieldmap.geojson")).expect("read"))
            .expect("json");
    assert_eq!(fieldmap["quantity"], "magnetic field");
    assert!(out.join("fieldmap.png").is_file());
    let cells = fieldmap["features"].as_array().expect("features");
    assert!(cells.len() > 20, "{}", cells.len());
    for c in cells {
        let p = &c["properties"];
        assert!(p["readings"].as_u64().expect("readings") >= 1);
        assert!((20.0..90.0).contains(&p["magnitude_ut"].as_f64().expect("magnitude")));
        assert!(p["vertical_ut"].as_f64().expect("vertical") < 0.0);
    }
    // Switched off, the readings are counted and said unused.
    let config = dir.path().join("off.toml");
    std::fs::write(&config, "[field]\nenabled = false\n").expect("write");
    let off = dir.path().join("off");
    learn(&steps, &off, &["--config", config.to_str().expect("utf-8")]).success();
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(off.join("summary.json")).expect("read"))
            .expect("json");
    assert_eq!(summary["magnetic_field"]["unused"], "disabled");
    assert_eq!(summary["magnetic_field"]["steps_weighed"], 0);
    assert!(!off.join("fieldmap.geojson").exists());
}

#[test]
fn quiet_says_nothing_verbose_lists_the_files_and_every_run_ends_in_one_line() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("sim");
    let run = |flag: Option<&str>| {
        let mut cmd = footslam();
        if let Some(f) = flag {
            cmd.arg(f);
        }
        let done = cmd
            .args(["simulate", "--laps", "1", "--out"])
            .arg(&out)
            .assert()
            .success();
        String::from_utf8(done.get_output().stdout.clone()).expect("utf-8")
    };
    let normal = run(None);
    let last = normal.lines().last().expect("a closing line");
    assert!(
        last.starts_with(&format!("wrote {}", out.display())) && last.contains(" files) · "),
        "{last}"
    );
    assert!(run(Some("--quiet")).is_empty());
    let verbose = run(Some("-v"));
    assert!(
        verbose.contains("steps.csv (") && verbose.contains("truth.png ("),
        "{verbose}"
    );
    // Into an earlier run's folder: a notice on stderr, and it is replaced whole.
    footslam()
        .args(["simulate", "--laps", "1", "--out"])
        .arg(&out)
        .assert()
        .success()
        .stderr(predicates::str::contains("holds an earlier run"));
    // The flags go anywhere on the line, and not together.
    footslam()
        .args(["simulate", "--laps", "1", "-q", "--out"])
        .arg(&out)
        .assert()
        .success()
        .stdout("");
    footslam()
        .args(["-q", "-v", "simulate"])
        .assert()
        .failure()
        .stderr(predicates::str::contains("cannot be used with"));
}

#[test]
fn completions_and_manual_pages_come_from_the_command_line_itself() {
    let out = footslam().args(["completions", "bash"]).assert().success();
    let script = String::from_utf8(out.get_output().stdout.clone()).expect("utf-8");
    assert!(script.contains("_footslam") && script.contains("--map-weight"));
    let dir = tempfile::tempdir().expect("tempdir");
    footslam()
        .args(["man", "--out"])
        .arg(dir.path())
        .assert()
        .success();
    let learn = std::fs::read_to_string(dir.path().join("footslam-learn.1")).expect("page");
    assert!(
        learn.contains("\\-\\-map") || learn.contains("--map"),
        "{learn}"
    );
    assert!(dir.path().join("footslam.1").is_file());
    footslam().args(["completions", "tcsh"]).assert().failure();
}

#[test]
fn old_option_spellings_still_work_hidden() {
    // learn --prior-map (now --map), track --hexmap (now --map): hidden, not in --help.
    let help = footslam().args(["learn", "--help"]).assert().success();
    let help = String::from_utf8(help.get_output().stdout.clone()).expect("utf-8");
    assert!(
        help.contains("--map <FILE>") && !help.contains("prior-map"),
        "{help}"
    );
    footslam()
        .args(["learn", "--prior-map", "/no/such/map.geojson"])
        .assert()
        .failure()
        .stderr(predicates::str::contains("/no/such/map.geojson"));
    footslam()
        .args(["track", "--hexmap", "/no/such/map.geojson"])
        .assert()
        .failure()
        .stderr(predicates::str::contains("/no/such/map.geojson"));
}

#[test]
fn merge_writes_a_run_folder_with_a_picture_and_the_old_one_file_form_warns() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut maps = Vec::new();
    for seed in ["1", "2"] {
        let out = dir.path().join(format!("learn-{seed}"));
        footslam()
            .args(["-q", "learn", "--particles", "200", "--seed", seed, "--out"])
            .arg(&out)
            .assert()
            .success();
        maps.push(out.join("map.geojson"));
    }
    let merged = dir.path().join("merged");
    footslam()
        .arg("merge")
        .args(&maps)
        .arg("-o")
        .arg(&merged)
        .assert()
        .success();
    for file in [
        "merged.geojson",
        "merged_plan.geojson",
        "merged.png",
        "summary.json",
    ] {
        assert!(merged.join(file).is_file(), "{file}");
    }
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(merged.join("summary.json")).expect("summary"),
    )
    .expect("json");
    assert_eq!(summary["walks"], 2, "{summary}");
    let one = dir.path().join("one.geojson");
    footslam()
        .arg("merge")
        .args(&maps)
        .arg("--out")
        .arg(&one)
        .assert()
        .success()
        .stderr(predicates::str::contains("writes a folder"));
    assert!(one.is_file());
}

#[test]
fn eval_picture_draws_the_learned_plan_over_the_true_one() {
    let dir = tempfile::tempdir().expect("tempdir");
    let sim = simulate_into(dir.path(), "3");
    let run = dir.path().join("run");
    footslam()
        .args(["-q", "learn", "--particles", "300", "--steps"])
        .arg(sim.join("steps.csv"))
        .arg("--out")
        .arg(&run)
        .assert()
        .success();
    let png = dir.path().join("eval.png");
    footslam()
        .args(["eval", "--align", "rigid", "--truth"])
        .arg(sim.join("truth.csv"))
        .arg("--track")
        .arg(run.join("track.csv"))
        .arg("--learned-plan")
        .arg(run.join("plan.geojson"))
        .arg("--plan")
        .arg(sim.join("floor.geojson"))
        .arg("--picture")
        .arg(&png)
        .assert()
        .success();
    let img = image::open(&png).expect("a PNG").to_rgba8();
    let near = |rgb: [u8; 3]| {
        img.pixels()
            .filter(|p| (0..3).all(|i| p.0[i].abs_diff(rgb[i]) <= 30))
            .count()
    };
    assert!(near([166, 97, 26]) > 200, "no learned plan outline");
    assert!(near([178, 24, 43]) > 200, "no track");
}

#[test]
fn survey_pictures_show_the_picture_extent() {
    let dir = tempfile::tempdir().expect("tempdir");
    let tower = Path::new(env!("CARGO_MANIFEST_DIR")).join("datasets/tower");
    let survey = |out: &Path, extra: &[&str]| {
        footslam()
            .args(["-q", "survey", "--particles", "20000", "--plan"])
            .arg(tower.join("floor.geojson"))
            .arg("--steps")
            .arg(tower.join("steps.csv"))
            .arg("--wifi")
            .arg(tower.join("wifi.csv"))
            .args(extra)
            .arg("--out")
            .arg(out)
            .assert()
            .success();
        image::image_dimensions(out.join("radiomap.png")).expect("radiomap.png")
    };
    let (w, h) = survey(&dir.path().join("whole"), &[]);
    let (w2, h2) = survey(&dir.path().join("part"), &["--picture-extent", "0,0,10,10"]);
    // A 10 m square per floor is narrower than the cells' crop of a 40 m corridor.
    assert!(w2 < w && h2 != h, "{w}×{h} vs {w2}×{h2}");
}

#[test]
fn learn_pictures_show_the_picture_extent() {
    let dir = tempfile::tempdir().expect("tempdir");
    let learn = |out: &Path, extra: &[&str]| {
        footslam()
            .args(["-q", "learn", "--particles", "200"])
            .args(extra)
            .arg("--out")
            .arg(out)
            .assert()
            .success();
        image::image_dimensions(out.join("map.png")).expect("map.png")
    };
    let (w, h) = learn(&dir.path().join("whole"), &[]);
    let (w2, h2) = learn(&dir.path().join("part"), &["--picture-extent", "0,0,4,4"]);
    // A 4 m square is smaller than the whole walk's map at the same scale.
    assert!(w2 <= w && h2 < h, "{w}×{h} vs {w2}×{h2}");
    footslam()
        .args([
            "learn",
            "--particles",
            "200",
            "--picture-extent",
            "4,0,0,4",
            "--out",
        ])
        .arg(dir.path().join("bad"))
        .assert()
        .failure()
        .stderr(predicates::str::contains("picture.extent"));
}
