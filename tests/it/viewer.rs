//! `footslam view`: the layers a page gets from the runs' folders (a learn run, a track run on
//! the three-floor tower, a survey's radio map, a batch, a simulated campus), its errors, and the page itself
//! loaded in a real browser — headless Chromium — which must draw every layer with no error.
//!
//! The runs are made once per test binary by the command line, on simulated data, in
//! `target/tmp/viewer-runs/`, made afresh (seconds: few particles, short walks). The browser test saves
//! its screenshots in `target/tmp/viewer-screenshots/` for a person to look at. Without
//! Chromium it fails, saying how to install it, unless `FOOTSLAM_SKIP_BROWSER=1`.

use assert_cmd::Command;
use footslam::view::{LayerData, LayerKind, read_run};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::time::Duration;

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

/// The runs every test reads, made once.
struct Runs {
    root: PathBuf,
}

impl Runs {
    fn path(&self, name: &str) -> PathBuf {
        self.root.join(name)
    }
}

fn run_ok(args: &[&str]) {
    footslam().args(args).assert().success();
}

/// A learn run of the bundled office walk, a simulated tower walk tracked and surveyed, a
/// batch of two walks.
fn runs() -> &'static Runs {
    static RUNS: OnceLock<Runs> = OnceLock::new();
    RUNS.get_or_init(|| {
        let root = Path::new(env!("CARGO_TARGET_TMPDIR")).join("viewer-runs");
        let _ = std::fs::remove_dir_all(&root);
        std::fs::create_dir_all(&root).expect("dir");
        let p = |name: &str| root.join(name).display().to_string();
        let office = Path::new(env!("CARGO_MANIFEST_DIR")).join("datasets/office/steps.csv");
        let office = office.display().to_string();
        run_ok(&[
            "learn",
            "--steps",
            &office,
            "--particles",
            "300",
            "--out",
            &p("learn"),
        ]);
        run_ok(&[
            "simulate",
            "--building",
            "tower",
            "--minutes",
            "2",
            "--seed",
            "2",
            "--out",
            &p("sim"),
        ]);
        let (plan, steps, wifi) = (
            p("sim/floor.geojson"),
            p("sim/steps.csv"),
            p("sim/wifi.csv"),
        );
        run_ok(&[
            "track",
            "--plan",
            &plan,
            "--steps",
            &steps,
            "--out",
            &p("track"),
        ]);
        run_ok(&[
            "survey",
            "--plan",
            &plan,
            "--steps",
            &steps,
            "--wifi",
            &wifi,
            "--out",
            &p("survey"),
        ]);
        run_ok(&[
            "simulate",
            "--building",
            "campus",
            "--walks",
            "2",
            "--laps",
            "1",
            "--out",
            &p("campus"),
        ]);
        run_ok(&[
            "learn",
            "--steps",
            &office,
            "--steps",
            &office,
            "--particles",
            "200",
            "--out",
            &p("batch"),
        ]);
        Runs { root }
    })
}

fn kinds(run: &footslam::view::ViewRun) -> Vec<(String, LayerKind)> {
    run.layers
        .iter()
        .map(|l| (l.name.clone(), l.kind))
        .collect()
}

fn path_points(layer: &footslam::view::Layer) -> &[footslam::view::PathPoint] {
    match &layer.data {
        LayerData::Path(points) => points,
        LayerData::Geojson(_) => panic!("{} is not a path", layer.name),
    }
}

#[test]
fn a_learn_run_gives_its_map_plan_and_track_with_spread() {
    let run = read_run(&runs().path("learn")).expect("read");
    let names: Vec<(String, LayerKind)> = kinds(&run);
    let expected = [
        ("learned plan", LayerKind::Plan),
        ("learned map", LayerKind::HexMap),
        ("dead reckoning", LayerKind::DeadReckoning),
        ("track", LayerKind::Track),
    ];
    assert_eq!(names, expected.map(|(n, k)| (n.to_owned(), k)));
    let track = &run.layers[3];
    let points = path_points(track);
    assert_eq!(points.len(), 484, "one row per step");
    assert!(
        points
            .iter()
            .all(|p| p.spread.is_some() && p.level == Some(0)),
        "spread_m, levels from track.geojson"
    );
    assert_eq!(run.levels(), [0]);
    let LayerData::Geojson(map) = &run.layers[1].data else {
        panic!("geojson")
    };
    assert_eq!(map["hex_radius"], 0.5, "foreign members carried");
    assert!(run.layers[1].features > 50);
}

#[test]
fn a_track_run_shows_the_plan_it_was_given_and_its_three_floors() {
    let run = read_run(&runs().path("track")).expect("read");
    let names = kinds(&run);
    assert_eq!(
        names[0],
        ("floor plan".to_owned(), LayerKind::Plan),
        "from summary.json's plan_file"
    );
    assert!(names.contains(&("filtered track".to_owned(), LayerKind::FilteredTrack)));
    let track = run
        .layers
        .iter()
        .find(|l| l.kind == LayerKind::Track)
        .expect("track");
    assert!(
        path_points(track)
            .iter()
            .all(|p| p.spread.is_some() && p.certain.is_some())
    );
    assert_eq!(run.levels(), [0, 1, 2], "the tower's floors");
}

#[test]
fn a_batch_has_layers_per_walk_and_the_merged_map() {
    let run = read_run(&runs().path("batch")).expect("read");
    let names: Vec<String> = run.layers.iter().map(|l| l.name.clone()).collect();
    for name in [
        "merged map",
        "merged plan",
        "walk 1 · track",
        "walk 2 · track",
        "walk 2 · learned map",
    ] {
        assert!(names.iter().any(|n| n == name), "{name} in {names:?}");
    }
    let track = run
        .layers
        .iter()
        .find(|l| l.name == "walk 2 · track")
        .expect("track");
    assert_eq!(track.file, "walk-2/track.csv");
}

#[test]
fn a_simulated_campus_shows_its_outline_and_each_walk_s_truth_and_gps_fixes() {
    let run = read_run(&runs().path("campus")).expect("read");
    let names: Vec<(String, LayerKind)> = kinds(&run);
    for (name, kind) in [
        ("floor plan", LayerKind::Plan),
        ("outline", LayerKind::Outline),
        ("walk 1 · truth", LayerKind::Truth),
        ("walk 2 · GPS fixes", LayerKind::GpsFixes),
    ] {
        assert!(
            names.contains(&(name.to_owned(), kind)),
            "{name} in {names:?}"
        );
    }
    let gps = run
        .layers
        .iter()
        .find(|l| l.kind == LayerKind::GpsFixes)
        .expect("gps");
    assert!(
        path_points(gps)
            .iter()
            .all(|p| p.spread.is_some_and(|a| a > 0.0)),
        "accuracy as spread"
    );
}

#[test]
fn an_importer_s_trace_folders_are_parts_of_the_run() {
    let dir = tempfile::tempdir().expect("tempdir");
    let import = dir.path().join("import");
    for trace in ["trace-b", "trace-a", "empty"] {
        std::fs::create_dir_all(import.join(trace)).expect("dir");
    }
    std::fs::copy(
        runs().path("sim/floor.geojson"),
        import.join("floor.geojson"),
    )
    .expect("copy");
    for trace in ["trace-b", "trace-a"] {
        let waypoints = import.join(trace).join("waypoints.csv");
        std::fs::write(waypoints, "t,x,y\n1,2,3\n5,6,7\n").expect("write");
    }
    let run = read_run(&import).expect("read");
    let names: Vec<&str> = run.layers.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(
        names,
        ["floor plan", "trace-a · waypoints", "trace-b · waypoints"]
    );
    assert_eq!(run.layers[1].file, "trace-a/waypoints.csv");
}

#[test]
fn the_cli_writes_a_complete_page_with_given_truth_and_waypoints() {
    let runs = runs();
    let dir = tempfile::tempdir().expect("tempdir");
    let waypoints = dir.path().join("waypoints.csv");
    std::fs::write(&waypoints, "t,x,y,level\n2,19.9,-4.8,0\n60,10,5,1\n").expect("write");
    let out = dir.path().join("page");
    let (track, survey) = (runs.path("track"), runs.path("survey"));
    let truth = runs.path("sim/truth.csv");
    footslam()
        .arg("view")
        .args([&track, &survey])
        .arg("--truth")
        .arg(&truth)
        .arg("--waypoints")
        .arg(&waypoints)
        .arg("--out")
        .arg(&out)
        .assert()
        .success()
        .stdout(predicates::str::contains("index.html"));
    for file in [
        "index.html",
        "data.js",
        "viewer.js",
        "viewer.css",
        "leaflet/leaflet.js",
        "leaflet/leaflet.css",
        "leaflet/LICENSE",
        "summary.json",
    ] {
        assert!(out.join(file).is_file(), "{file}");
    }
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).expect("read"))
            .expect("json");
    let layers: Vec<&str> = summary["runs"][0]["layers"]
        .as_array()
        .expect("layers")
        .iter()
        .map(|l| l["name"].as_str().expect("name"))
        .collect();
    assert!(
        layers.contains(&"truth (sim/truth.csv)")
            && layers
                .iter()
                .any(|l| l.starts_with("waypoints (") && l.ends_with("/waypoints.csv)")),
        "{layers:?}"
    );
    assert_eq!(summary["runs"][1]["layers"][0]["kind"], "radio_map");
    let data = std::fs::read_to_string(out.join("data.js")).expect("read");
    assert!(data.starts_with("window.FOOTSLAM_VIEW = {"));
    assert!(
        data.contains("\"mean\"") && !data.contains("\"hist\""),
        "radio means kept, histograms dropped"
    );
    let html = std::fs::read_to_string(out.join("index.html")).expect("read");
    assert!(
        html.contains("<title>footslam view: track, survey</title>"),
        "{html}"
    );
    assert!(
        !html.contains("http://") && !html.contains("https://"),
        "nothing fetched"
    );
    // A second page into the same folder replaces the first whole.
    footslam()
        .arg("view")
        .arg(runs.path("learn"))
        .arg("--out")
        .arg(&out)
        .assert()
        .success();
    let data = std::fs::read_to_string(out.join("data.js")).expect("read");
    assert!(data.contains("learned map") && !data.contains("radio"));
}

#[test]
fn bad_folders_and_files_are_named_and_nothing_is_written() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("page");
    let fails = |folder: &Path, message: &str| {
        footslam()
            .arg("view")
            .arg(folder)
            .arg("--out")
            .arg(&out)
            .assert()
            .failure()
            .stderr(predicates::str::contains(message));
        assert!(!out.exists(), "nothing written for {}", folder.display());
    };
    fails(&dir.path().join("missing"), "no such run folder");
    let empty = dir.path().join("empty");
    std::fs::create_dir_all(&empty).expect("dir");
    std::fs::write(empty.join("notes.txt"), "x").expect("write");
    fails(&empty, "nothing to view: none of floor.geojson");
    let bad = dir.path().join("bad");
    std::fs::create_dir_all(&bad).expect("dir");
    std::fs::write(
        bad.join("map.geojson"),
        "{\"type\": \"FeatureCollection\",\n \"features\": [,]}",
    )
    .expect("write");
    fails(&bad, "map.geojson:2");
    std::fs::remove_file(bad.join("map.geojson")).expect("rm");
    std::fs::write(bad.join("track.csv"), "t,x,y\n1,0,0\n2,north,0\n").expect("write");
    fails(&bad, "track.csv:3");
    fails(&bad.join("track.csv"), "not a folder");
    // A page may not replace the run folder it shows.
    let learn = runs().path("learn");
    footslam()
        .arg("view")
        .arg(&learn)
        .arg("--out")
        .arg(&learn)
        .assert()
        .failure();
    assert!(learn.join("map.geojson").is_file() && !learn.join("index.html").exists());
}

// ---------- the page in a real browser ----------

/// Headless Chromium: `FOOTSLAM_CHROMIUM` (if it is a file), else the first of Debian's and
/// others' names on the PATH.
fn chromium() -> Option<PathBuf> {
    if let Some(path) = std::env::var_os("FOOTSLAM_CHROMIUM") {
        return Some(PathBuf::from(path)).filter(|p| p.is_file());
    }
    let names = [
        "chromium",
        "chromium-browser",
        "google-chrome",
        "google-chrome-stable",
    ];
    let dirs: Vec<PathBuf> = std::env::var_os("PATH")
        .map(|p| std::env::split_paths(&p).collect())
        .unwrap_or_default();
    names
        .iter()
        .flat_map(|n| dirs.iter().map(move |d| d.join(n)))
        .find(|p| p.is_file())
}

/// Runs Chromium headless on `page` (with `#fragment` when not empty) with `args`:
/// (stdout, stderr).
fn browse(chromium: &Path, page: &Path, fragment: &str, args: &[&str]) -> (String, String) {
    let profile = tempfile::tempdir().expect("tempdir");
    let url = format!(
        "file://{}{fragment}",
        page.canonicalize().expect("page").display()
    );
    let output = Command::new(chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--window-size=1280,900",
            "--virtual-time-budget=5000",
        ])
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .args(args)
        .arg(&url)
        .timeout(Duration::from_secs(90))
        .output()
        .expect("chromium runs");
    (
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

/// The page's own report (`<pre id="status">`) from a dumped DOM.
fn page_status(dom: &str) -> Value {
    let start = dom
        .find("<pre id=\"status\"")
        .unwrap_or_else(|| panic!("no #status in the DOM:\n{dom}"));
    let text = &dom[start..];
    let text = &text[text.find('>').expect("tag") + 1..text.find("</pre>").expect("end")];
    let text = text
        .replace("&quot;", "\"")
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&");
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("#status is not JSON ({e}): {text}"))
}

/// Loads `page` in the browser: every layer drawn, no error, the console clean; saves a
/// screenshot as `name.png`. Returns the page's report.
fn check_in_browser(chromium: &Path, page: &Path, name: &str, layers: usize) -> Value {
    let (dom, log) = browse(
        chromium,
        &page.join("index.html"),
        "#selftest",
        &["--dump-dom", "--enable-logging=stderr", "--v=0"],
    );
    let status = page_status(&dom);
    assert_eq!(
        status["errors"],
        Value::Array(Vec::new()),
        "{name}: errors on the page: {status}"
    );
    assert_eq!(
        status["ready"], true,
        "{name}: the viewer did not finish: {status}"
    );
    let drawn = status["layers"].as_array().expect("layers");
    assert_eq!(drawn.len(), layers, "{name}: {status}");
    for layer in drawn {
        assert!(
            layer["drawn"].as_u64().unwrap_or(0) > 0,
            "{name}: layer drew nothing: {layer}"
        );
    }
    // The self-test worked every control: levels, the time slider, access points, the
    // pointer's read-out.
    let exercised = &status["exercised"];
    assert_eq!(
        exercised["times"].as_array().map(Vec::len),
        Some(3),
        "{name}: {exercised}"
    );
    let readout = exercised["readout"].as_str().unwrap_or("");
    assert!(
        readout.contains('°') && readout.contains(" m"),
        "{name}: read-out {readout}"
    );
    let console: Vec<&str> = log
        .lines()
        .filter(|l| l.contains(":CONSOLE") && (l.contains("Uncaught") || l.contains("rror")))
        .collect();
    assert!(console.is_empty(), "{name}: console errors: {console:?}");
    let shots = Path::new(env!("CARGO_TARGET_TMPDIR")).join("viewer-screenshots");
    std::fs::create_dir_all(&shots).expect("dir");
    let shot = shots.join(format!("{name}.png"));
    let _ = std::fs::remove_file(&shot);
    browse(
        chromium,
        &page.join("index.html"),
        "",
        &[&format!("--screenshot={}", shot.display())],
    );
    let png = std::fs::read(&shot)
        .unwrap_or_else(|e| panic!("{name}: no screenshot {}: {e}", shot.display()));
    assert!(
        png.starts_with(b"\x89PNG") && png.len() > 20_000,
        "{name}: screenshot of {} bytes",
        png.len()
    );
    status
}

#[test]
fn the_page_draws_every_layer_in_headless_chromium() {
    if std::env::var("FOOTSLAM_SKIP_BROWSER").is_ok_and(|v| v == "1") {
        return;
    }
    let Some(chromium) = chromium() else {
        panic!(
            "the viewer's browser test needs headless Chromium: install it (Debian/Ubuntu: \
             `apt-get install chromium`; or set FOOTSLAM_CHROMIUM to a Chrome binary), or set \
             FOOTSLAM_SKIP_BROWSER=1 to skip this test"
        );
    };
    let runs = runs();
    let dir = tempfile::tempdir().expect("tempdir");
    let pages: [(&str, Vec<PathBuf>, usize); 4] = [
        ("learn", vec![runs.path("learn")], 4),
        ("campus", vec![runs.path("campus")], 6),
        (
            "tower",
            vec![runs.path("sim"), runs.path("track"), runs.path("survey")],
            6,
        ),
        ("batch", vec![runs.path("batch")], 10),
    ];
    for (name, folders, layers) in pages {
        let out = dir.path().join(name);
        footslam()
            .arg("view")
            .args(&folders)
            .arg("--out")
            .arg(&out)
            .assert()
            .success();
        let status = check_in_browser(&chromium, &out, name, layers);
        let exercised = &status["exercised"];
        match name {
            "learn" => assert!(
                exercised["arrow_groups"].as_u64() >= Some(1),
                "arrows: {exercised}"
            ),
            "tower" => {
                assert_eq!(status["levels"], serde_json::json!([0, 1, 2]), "{status}");
                assert!(
                    exercised["access_points"].as_u64() > Some(10),
                    "the BSSID picker: {exercised}"
                );
            }
            _ => {}
        }
    }
    // Web tiles under the layers: a local tile stands for every tile of the template.
    let tile = dir.path().join("tile.png");
    image::RgbaImage::from_pixel(256, 256, image::Rgba([200, 220, 240, 255]))
        .save(&tile)
        .expect("tile");
    let template = format!("file://{}?{{z}}/{{x}}/{{y}}", tile.display());
    let out = dir.path().join("basemap");
    footslam()
        .arg("view")
        .arg(runs.path("learn"))
        .args([
            "--basemap",
            &template,
            "--basemap-attribution",
            "test tiles",
        ])
        .arg("--out")
        .arg(&out)
        .assert()
        .success();
    let status = check_in_browser(&chromium, &out, "basemap", 4);
    let basemap = &status["basemap"];
    assert!(
        basemap["tiles_loaded"].as_u64() > Some(0) && basemap["tiles_failed"] == 0,
        "the basemap's tiles: {status}"
    );
}
