//! The radio survey on a simulated survey walk of the three-floor building (20–30 minutes),
//! through the library (`footslam::pipeline::survey` and `track`, as `footslam survey` and
//! `footslam track --radiomap` run them): coverage of 3 m cells (the paper's Table 1: 96 %
//! after 2.5 hours of walking), per-cell mean RSSI against the simulator's expected field,
//! speed against real time, and tracking with the map; and the command line's files, flags
//! and messages on short walks.

use crate::common::{
    in_own_pool, recorded, recorded_plan, recorded_radio_map, recorded_scans, smoothed_track,
};
use assert_cmd::Command;
use footslam::eval::rf_localisation::{SimulatedSurvey, radio_map_rms, simulate_survey};
use footslam::filter::{EpsilonSource, RfConfig, RfLocaliser, RfMode, StartPose, TrackerConfig};
use footslam::geometry::LocalFrame;
use footslam::map::{FloorPlan, FloorTopology, RadioMap};
use footslam::model::wifi_distance::Normalisation;
use footslam::pipeline::{
    RadioInput, Silent, SnapshotSteps, SurveyConfig, SurveyInput, SurveyWalk, TrackInput, TrackRun,
    survey, track,
};
use footslam::sensor::{StepTrace, WifiScan};
use footslam::sim::{TourKind, TowerSimConfig};
use predicates::prelude::*;
use std::path::{Path, PathBuf};
use std::time::Instant;

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

/// The origin the survey's walks are placed by.
const ORIGIN: &str = "52.21,0.091";

fn origin() -> LocalFrame {
    LocalFrame::new(52.21, 0.091).expect("origin")
}

/// `footslam simulate --building tower` of `minutes` with `seed` and `origin` (plus `extra`
/// arguments) into `dir/name`.
fn simulate_tower(
    dir: &Path,
    name: &str,
    minutes: u32,
    seed: u64,
    origin: &str,
    extra: &[&str],
) -> PathBuf {
    let out = dir.join(name);
    footslam()
        .args(["simulate", "--building", "tower", "--minutes"])
        .arg(minutes.to_string())
        .arg("--seed")
        .arg(seed.to_string())
        .args(["--origin", origin])
        .args(extra)
        .arg("--out")
        .arg(&out)
        .assert()
        .success();
    out
}

/// `footslam track` of the simulated walk in `walk` with the radio map `radiomap`, into `out`.
fn track_with_map(walk: &Path, radiomap: &Path, out: &Path) -> Command {
    let mut cmd = footslam();
    cmd.arg("track")
        .arg("--plan")
        .arg(walk.join("floor.geojson"))
        .arg("--steps")
        .arg(walk.join("steps.csv"))
        .arg("--radiomap")
        .arg(radiomap)
        .arg("--out")
        .arg(out);
    cmd
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("read")).expect("json")
}

/// A tower walk of `minutes` with `seed` and `tour` (`footslam simulate --building tower`
/// placed at [`ORIGIN`]): its plan, steps and scans as its files record them.
struct Walk {
    plan: FloorPlan,
    steps: StepTrace,
    scans: Vec<WifiScan>,
    start: StartPose,
    duration_s: f64,
}

fn walk(minutes: f64, seed: u64, tour: TourKind) -> Walk {
    let mut config = TowerSimConfig {
        seed,
        ..Default::default()
    };
    config.walk.minutes = minutes;
    config.walk.tour = tour;
    let sim = footslam::sim::simulate_tower(&config).expect("simulate");
    Walk {
        plan: recorded_plan(&sim.plan, origin()),
        steps: recorded(&sim.steps),
        scans: recorded_scans(&sim.wifi),
        start: StartPose::from(sim.start),
        duration_s: sim.truth.poses.last().map_or(0.0, |p| p.t),
    }
}

/// `footslam track --radiomap` of `walk` on `topology` with `localiser` (its configuration
/// the tracker's `rf`), on the calling thread's pool.
fn track_with<'a>(
    walk: &'a Walk,
    topology: &'a FloorTopology,
    localiser: &'a RfLocaliser,
) -> TrackRun<'a> {
    let input = TrackInput {
        topology,
        transitions: None,
        radio: Some(RadioInput {
            localiser,
            scans: &walk.scans,
        }),
    };
    let config = TrackerConfig {
        rf: *localiser.config(),
        ..Default::default()
    };
    track(&input, &walk.steps, &config, &SnapshotSteps::Never, &Silent).expect("track")
}

#[test]
#[allow(clippy::print_stderr)] // reports the figures with --nocapture
fn a_survey_walk_covers_the_building_fast_and_the_map_localises_a_walker() {
    let survey_walk = walk(30.0, 31, TourKind::Survey);
    let minutes = survey_walk.duration_s / 60.0;
    assert!((20.0..=30.0).contains(&minutes), "{minutes} min");
    let config = SurveyConfig::default();
    let topology =
        FloorTopology::build(&survey_walk.plan, &config.tracker.topology).expect("topology");
    let walks = [SurveyWalk {
        trace: survey_walk.steps.clone(),
        scans: survey_walk.scans.clone(),
        start: Some(survey_walk.start),
    }];
    let input = SurveyInput {
        plan: &survey_walk.plan,
        topology: &topology,
        walks: &walks,
        earlier: &[],
    };
    let started = Instant::now();
    let surveyed = in_own_pool(|| survey(&input, &config, &Silent)).expect("survey");
    let steps = survey_walk.steps.steps();
    let duration = steps[steps.len() - 1].t - steps[0].t;
    let speed = duration / started.elapsed().as_secs_f64();
    let (coverage, _) = surveyed.map.coverage();
    eprintln!(
        "survey of {minutes:.1} min: coverage {:.1} %, {speed:.0}× real time, ε {:?} (√k {:?})",
        100.0 * coverage,
        surveyed.map.epsilon,
        surveyed.map.epsilon_sqrt
    );
    assert!(coverage >= 0.96, "coverage {coverage}");
    assert!(speed >= 100.0, "{speed}× real time");
    let epsilon = surveyed.map.epsilon.expect("calibrated epsilon");
    assert!(epsilon > 0.0 && epsilon < 20.0, "{epsilon}");
    let epsilon_sqrt = surveyed.map.epsilon_sqrt.expect("calibrated for √k");
    // The same held-out distances times √k ≥ 1: a larger threshold.
    assert!(
        epsilon_sqrt > epsilon && epsilon_sqrt < 60.0,
        "{epsilon_sqrt}"
    );
    let three = surveyed
        .coverage
        .iter()
        .find(|c| c.granularity == 3.0)
        .expect("3 m row");
    assert!((100.0 * three.share - 100.0 * coverage).abs() < 0.06);

    // Another walk in the same building, localised with the map (as `radiomap.geojson`
    // records it) in each mode.
    let other = walk(3.0, 32, TourKind::Random);
    let topology = FloorTopology::build(&other.plan, &Default::default()).expect("topology");
    let radiomap = recorded_radio_map(&surveyed.map, origin());
    let localiser = |map: &RadioMap, rf: RfConfig| RfLocaliser::new(map, &topology, &rf);
    for mode in [
        RfMode::Containment,
        RfMode::Probabilistic,
        RfMode::PriorOnly,
    ] {
        let rf = RfConfig {
            mode,
            ..Default::default()
        };
        let localiser = localiser(&radiomap, rf).expect("localiser");
        let run = in_own_pool(|| track_with(&other, &topology, &localiser));
        let steps = run.records.first_localised().map(|i| i + 1);
        eprintln!("{mode:?}: localised after {steps:?} steps");
        assert!(steps.is_some(), "{mode:?}: not localised");
        assert_eq!(run.measurements_ignored, 0, "{mode:?}");
        // The map is calibrated for √k, so that is the default distance.
        assert_eq!(localiser.distance(), Normalisation::Sqrt);
        assert!((localiser.epsilon() - epsilon_sqrt).abs() < 0.01);
    }
    // The paper's distance on request, with its own calibrated threshold.
    let paper = RfConfig {
        distance: Some(Normalisation::Paper),
        ..Default::default()
    };
    let localiser_paper = localiser(&radiomap, paper).expect("localiser");
    let run = in_own_pool(|| track_with(&other, &topology, &localiser_paper));
    assert!(run.records.first_localised().is_some());
    assert_eq!(localiser_paper.distance(), Normalisation::Paper);
    assert!((localiser_paper.epsilon() - epsilon).abs() < 0.01);
    // Another tool's map without thresholds: √k with a threshold derived from the map's
    // histograms; near the survey's own calibration.
    let foreign = RadioMap {
        epsilon: None,
        epsilon_sqrt: None,
        ..radiomap.clone()
    };
    let derived = localiser(&foreign, RfConfig::default()).expect("localiser");
    in_own_pool(|| track_with(&other, &topology, &derived));
    assert_eq!(derived.distance(), Normalisation::Sqrt);
    assert_eq!(derived.epsilon_source(), EpsilonSource::Derived);
    let e = derived.epsilon();
    assert!(
        e > 0.5 * epsilon_sqrt && e < 2.0 * epsilon_sqrt,
        "derived {e} vs calibrated {epsilon_sqrt}"
    );
    // The same run on one thread and on two.
    let tracks: Vec<_> = [1, 2]
        .iter()
        .map(|&threads| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("pool");
            let localiser = localiser(&radiomap, RfConfig::default()).expect("localiser");
            let run = pool.install(|| track_with(&other, &topology, &localiser));
            (run.filtered.clone(), smoothed_track(&other.steps, &run))
        })
        .collect();
    assert!(tracks[0] == tracks[1], "the thread count changed the track");
}

#[test]
fn survey_and_track_write_the_radio_figures_and_refuse_what_they_cannot_use() {
    // `footslam survey` of a short survey walk from its known start, and `footslam track`
    // of another walk with the map: the files, the flags and the messages.
    let dir = tempfile::tempdir().expect("tempdir");
    let sim = simulate_tower(
        dir.path(),
        "survey-walk",
        SURVEY_MINUTES,
        31,
        ORIGIN,
        &["--tour", "survey"],
    );
    let s = &json(&sim.join("summary.json"))["start"];
    let start = format!("{},{},{},{}", s["x"], s["y"], s["heading"], s["level"]);
    let out = dir.path().join("survey");
    footslam()
        .arg("survey")
        .arg("--plan")
        .arg(sim.join("floor.geojson"))
        .arg("--steps")
        .arg(sim.join("steps.csv"))
        .arg("--wifi")
        .arg(sim.join("wifi.csv"))
        .arg(format!("--start={start}"))
        .arg("--out")
        .arg(&out)
        .assert()
        .success()
        .stdout(predicate::str::contains("surveyed 1 walk(s)"));
    let summary = json(&out.join("summary.json"));
    let radiomap = out.join("radiomap.geojson");
    let coverage = summary["coverage"].as_f64().expect("coverage");
    let epsilon = summary["epsilon"].as_f64().expect("calibrated epsilon");
    let epsilon_sqrt = summary["epsilon_sqrt"].as_f64().expect("calibrated for √k");
    let walks = std::fs::read_to_string(out.join("walks.csv")).expect("walks.csv");
    assert!(
        walks.starts_with("walk,") && walks.contains("steps_to_localise"),
        "{walks}"
    );
    let table = std::fs::read_to_string(out.join("coverage.csv")).expect("coverage.csv");
    let three: Vec<&str> = table
        .lines()
        .find(|l| l.starts_with("3,"))
        .expect("3 m row")
        .split(',')
        .collect();
    assert!((three[2].parse::<f64>().expect("percent") - 100.0 * coverage).abs() < 0.06);

    let other = simulate_tower(dir.path(), "walk", 3, 32, ORIGIN, &[]);
    let run = dir.path().join("track-prior-only");
    track_with_map(&other, &radiomap, &run)
        .arg("--wifi")
        .arg(other.join("wifi.csv"))
        .args(["--rf-mode", "prior-only"])
        .assert()
        .success();
    assert_eq!(json(&run.join("config.json"))["rf"]["mode"], "prior_only");
    let rf = &json(&run.join("summary.json"))["rf"];
    assert_eq!(rf["distance"], "sqrt");
    assert!((rf["epsilon_dbm"].as_f64().expect("epsilon") - epsilon_sqrt).abs() < 0.01);
    let run = dir.path().join("track-paper");
    track_with_map(&other, &radiomap, &run)
        .arg("--wifi")
        .arg(other.join("wifi.csv"))
        .args(["--rf-distance", "paper"])
        .assert()
        .success();
    let rf = &json(&run.join("summary.json"))["rf"];
    assert_eq!(rf["distance"], "paper");
    assert!((rf["epsilon_dbm"].as_f64().expect("epsilon") - epsilon).abs() < 0.01);
    // Another tool's map without thresholds: the summary and the output say where the
    // threshold came from.
    let mut foreign = json(&radiomap);
    let members = foreign.as_object_mut().expect("collection");
    members.remove("epsilon");
    members.remove("epsilon_sqrt");
    let foreign_path = dir.path().join("foreign.geojson");
    std::fs::write(&foreign_path, foreign.to_string()).expect("write");
    let run = dir.path().join("track-foreign");
    track_with_map(&other, &foreign_path, &run)
        .arg("--wifi")
        .arg(other.join("wifi.csv"))
        .assert()
        .success()
        .stdout(predicate::str::contains(
            "derived from the map's histograms",
        ));
    assert_eq!(
        json(&run.join("summary.json"))["rf"]["epsilon_source"],
        "derived"
    );
    // A map of single scans shows no spread: the error names the ways out.
    let mut single = foreign.clone();
    for feature in single["features"].as_array_mut().expect("features") {
        let properties = feature["properties"].as_object_mut().expect("properties");
        properties.insert("scans".into(), serde_json::json!(1));
        for (_, ap) in properties["aps"].as_object_mut().expect("aps").iter_mut() {
            let mean = ap["mean"].as_f64().expect("mean");
            let bin = format!("{}", mean.round() as i64);
            *ap = serde_json::json!({"n": 1, "mean": mean, "hist": {bin: 1}});
        }
    }
    let single_path = dir.path().join("single.geojson");
    std::fs::write(&single_path, single.to_string()).expect("write");
    track_with_map(&other, &single_path, &dir.path().join("track-single"))
        .arg("--wifi")
        .arg(other.join("wifi.csv"))
        .assert()
        .failure()
        .stderr(
            predicate::str::contains("--rf-epsilon")
                .and(predicate::str::contains("footslam survey")),
        );
    // A sparse map (the survey's cells on the start floor only): radio evidence by default,
    // an answer at every step with its spread and share, scored every row by eval.
    let mut sparse = json(&radiomap);
    for feature in sparse["features"].as_array_mut().expect("features") {
        let properties = feature["properties"].as_object_mut().expect("properties");
        if properties["level"].as_i64() != Some(0) {
            properties.insert("scans".into(), serde_json::json!(0));
            properties.insert("aps".into(), serde_json::json!({}));
        }
    }
    let sparse_path = dir.path().join("sparse.geojson");
    std::fs::write(&sparse_path, sparse.to_string()).expect("write");
    let run = dir.path().join("track-sparse");
    track_with_map(&other, &sparse_path, &run)
        .arg("--wifi")
        .arg(other.join("wifi.csv"))
        .assert()
        .success()
        .stdout(predicate::str::contains("evidence measurements"));
    let rf = &json(&run.join("summary.json"))["rf"];
    assert_eq!(rf["mode"], "evidence", "{rf}");
    // The default evidence: the nearest fingerprint within reach of the survey, the
    // path-loss model everywhere.
    let evidence = &rf["evidence"];
    assert_eq!(evidence["source"], "combined", "{evidence}");
    let ndist = &evidence["ndist"];
    assert!(
        ndist["bands_used"].as_u64().expect("bands") >= 1,
        "{evidence}"
    );
    assert!(
        ndist["cells_in_reach"].as_u64() < ndist["cells"].as_u64(),
        "{evidence}"
    );
    let pathloss = &evidence["pathloss"];
    assert!(
        pathloss["model"]["access_points"].as_u64().expect("APs") > 0,
        "{evidence}"
    );
    assert!(
        pathloss["median_here"].as_f64() > pathloss["median_elsewhere"].as_f64(),
        "{evidence}"
    );
    let steps = std::fs::read_to_string(other.join("steps.csv"))
        .expect("steps")
        .lines()
        .count();
    let track = std::fs::read_to_string(run.join("track.csv")).expect("track");
    assert_eq!(track.lines().count(), steps, "a row per step");
    for row in track.lines().skip(1) {
        let cols: Vec<f64> = row.split(',').map(|c| c.parse().expect("number")).collect();
        let (spread, share) = (cols[7], cols[8]);
        assert!(spread >= 0.0 && share > 0.0 && share <= 1.0, "{row}");
    }
    footslam()
        .args(["eval", "--all-rows", "--truth"])
        .arg(other.join("truth.csv"))
        .arg("--track")
        .arg(run.join("track.csv"))
        .assert()
        .success()
        .stdout(predicate::str::contains("uncertain").not());
    // A radio map needs its scans, and a map of another place is refused.
    track_with_map(&other, &radiomap, &dir.path().join("no-wifi"))
        .assert()
        .failure()
        .stderr(predicate::str::contains("--wifi"));
    let elsewhere = simulate_tower(dir.path(), "elsewhere", 1, 32, "10,10", &[]);
    track_with_map(&elsewhere, &radiomap, &dir.path().join("elsewhere-run"))
        .arg("--wifi")
        .arg(elsewhere.join("wifi.csv"))
        .assert()
        .failure()
        .stderr(predicate::str::contains(
            "no radio-map cell lies on the floor plan",
        ));
}

/// Minutes of the survey walk of the command-line test: enough for a calibrated map.
const SURVEY_MINUTES: u32 = 6;

#[test]
fn surveyed_cell_means_are_within_3_db_rms_of_the_expected_field() {
    let SimulatedSurvey {
        tours,
        topology,
        cells,
        map,
    } = simulate_survey(&TowerSimConfig::default(), 33, 1).expect("survey");
    let (coverage, _) = map.coverage();
    assert!(coverage >= 0.96, "coverage {coverage}");
    // Cells with a few readings of an access point heard in every scan there.
    let (rms, pairs) = radio_map_rms(&map, &cells, &topology, &tours[0].radio, 0.5, 3);
    assert!(pairs > 300, "{pairs} cell/AP pairs");
    assert!(rms <= 3.0, "RMS {rms:.2} dB over {pairs} pairs");
}

#[test]
fn manifest_starts_place_each_walk_and_override_the_shared_start() {
    let dir = tempfile::tempdir().expect("tempdir");
    let walks: Vec<PathBuf> = [41, 42, 43]
        .iter()
        .map(|&seed| simulate_tower(dir.path(), &format!("walk-{seed}"), 2, seed, ORIGIN, &[]))
        .collect();
    // Each walk's true start (the pose before its first step, as truth.csv's path begins).
    let starts: Vec<serde_json::Value> = walks
        .iter()
        .map(|w| json(&w.join("summary.json"))["start"].clone())
        .collect();
    let full =
        |s: &serde_json::Value| format!("{},{},{},{}", s["x"], s["y"], s["heading"], s["level"]);
    let no_heading = |s: &serde_json::Value| format!("{},{},,{}", s["x"], s["y"], s["level"]);
    let manifest = |name: &str, column: Option<[String; 3]>| {
        let mut text = String::from(if column.is_some() {
            "steps,wifi,start\n"
        } else {
            "steps,wifi\n"
        });
        for (i, w) in walks.iter().enumerate() {
            let name = w.file_name().expect("name").to_string_lossy();
            text.push_str(&format!("{name}/steps.csv,{name}/wifi.csv"));
            if let Some(c) = &column {
                text.push_str(&format!(",\"{}\"", c[i]));
            }
            text.push('\n');
        }
        let path = dir.path().join(name);
        std::fs::write(&path, text).expect("write");
        path
    };
    let survey = |manifest: &Path, out: &str, extra: &[String]| {
        let out = dir.path().join(out);
        footslam()
            .arg("survey")
            .arg("--plan")
            .arg(walks[0].join("floor.geojson"))
            .arg("--walks")
            .arg(manifest)
            .args(extra)
            .arg("--out")
            .arg(&out)
            .assert()
            .success()
            .stdout(predicate::str::contains("surveyed 3 walk(s)"));
        json(&out.join("summary.json"))["walks"]
            .as_array()
            .expect("walks")
            .clone()
    };
    let localised = |w: &serde_json::Value| w["steps_to_localise"].as_u64();
    // Known starts: the first walk's full pose, the second's place without a heading, the
    // third unknown.
    let known = manifest(
        "known.csv",
        Some([full(&starts[0]), no_heading(&starts[1]), String::new()]),
    );
    let with_starts = survey(&known, "known", &[]);
    let unknown = survey(&manifest("plain.csv", None), "unknown", &[]);
    assert_eq!(localised(&with_starts[0]), Some(1));
    let second = localised(&with_starts[1]).expect("localised");
    assert!(second <= 15, "localised after {second} steps");
    assert!(with_starts[1]["start"]["heading"].is_null());
    assert!(with_starts[2]["start"].is_null());
    // Unknown starts in three identical floors take far longer, when they localise at all.
    for (i, w) in unknown.iter().enumerate().take(2) {
        let steps = localised(w).unwrap_or(u64::MAX);
        assert!(
            steps > 15,
            "walk {i}: localised after {steps} steps without a start"
        );
    }
    assert_eq!(localised(&with_starts[2]), localised(&unknown[2]));
    assert!(with_starts[2]["scans_added"].as_u64() == unknown[2]["scans_added"].as_u64());
    assert!(
        with_starts[0]["scans_added"].as_u64() > unknown[0]["scans_added"].as_u64(),
        "a known start surveys the walk's scans from its first step"
    );
    // A shared start (`tracker.start` of --config) applies to the walks without their own.
    let s = &starts[2];
    let config = dir.path().join("shared.toml");
    std::fs::write(
        &config,
        format!(
            "[tracker.start]\nx = {}\ny = {}\nheading = {}\nlevel = {}\n",
            s["x"], s["y"], s["heading"], s["level"]
        ),
    )
    .expect("write");
    let shared = survey(
        &known,
        "shared",
        &["--config".into(), config.display().to_string()],
    );
    assert_eq!(localised(&shared[2]), Some(1));
    assert_eq!(shared[0]["start"], with_starts[0]["start"]);
    // A --start belongs to the --steps at its position: with a manifest alone it is refused,
    // naming the ways to give a shared start.
    footslam()
        .arg("survey")
        .arg("--plan")
        .arg(walks[0].join("floor.geojson"))
        .arg("--walks")
        .arg(&known)
        .arg(format!("--start={}", full(&starts[2])))
        .assert()
        .failure()
        .stderr(predicate::str::contains("tracker.start"));
    // A malformed start names the manifest's line.
    let bad = manifest(
        "bad.csv",
        Some([full(&starts[0]), "1,2,north".into(), String::new()]),
    );
    footslam()
        .arg("survey")
        .arg("--plan")
        .arg(walks[0].join("floor.geojson"))
        .arg("--walks")
        .arg(&bad)
        .arg("--out")
        .arg(dir.path().join("bad"))
        .assert()
        .failure()
        .stderr(
            predicate::str::contains("bad.csv:3").and(predicate::str::contains("HEADING `north`")),
        );
}

/// Surveys from an unknown start keep the scans taken before the filter's first fix: the
/// whole-walk answer places every scan whose place the walk settles. On survey walks from
/// unknown starts, coverage of 3 m cells within 3 points of the same walk surveyed at its
/// true positions, and per-cell mean RSSI no worse than the filtered survey's (+0.1 dB).
#[test]
#[allow(clippy::print_stderr)] // reports the figures with --nocapture
fn surveys_from_an_unknown_start_place_the_scans_before_the_fix() {
    use footslam::eval::rf_localisation::radio_map_rms;
    use footslam::filter::{
        Cluster, TrackStep, Tracker, TrackerConfig, placed_steps, survey_assignments, survey_walk,
    };
    use footslam::map::{CellMap, FloorTopology, RadioMap, TopologyConfig};
    use footslam::sim::{TourKind, simulate_tower};
    for seed in [41, 42] {
        let mut config = TowerSimConfig {
            seed,
            ..Default::default()
        };
        config.walk.tour = TourKind::Survey;
        config.walk.minutes = 8.0;
        let sim = simulate_tower(&config).expect("survey walk");
        let topology = FloorTopology::build(&sim.plan, &TopologyConfig::default()).expect("topo");
        let cells = CellMap::build(&sim.plan, &topology, &Default::default()).expect("cells");
        let survey = |reports: &[TrackStep]| {
            let mut map = RadioMap::empty(&cells);
            let assignments = survey_assignments(&cells, &topology, reports, &sim.wifi);
            survey_walk(&mut map, &assignments, &sim.wifi);
            let (coverage, _) = map.coverage();
            let (rms, _) = radio_map_rms(&map, &cells, &topology, &sim.radio, 0.5, 3);
            (coverage, rms)
        };
        let truth: Vec<TrackStep> = sim
            .truth
            .poses
            .iter()
            .map(|p| TrackStep {
                t: p.t,
                particles: 1,
                clusters: Some(1),
                estimate: Some(Cluster {
                    x: p.x,
                    y: p.y,
                    z: p.z,
                    level: p.level,
                    heading: p.heading,
                    spread: 0.0,
                    weight: 1.0,
                    particles: 1,
                }),
                localised: true,
                recovery: None,
                fit: None,
            })
            .collect();
        let run = |smoothing: bool| {
            let config = TrackerConfig {
                seed,
                smoothing,
                ..Default::default()
            };
            let mut tracker = Tracker::new(&topology, &config).expect("tracker");
            let reports: Vec<TrackStep> = sim
                .steps
                .steps()
                .iter()
                .map(|s| tracker.update(s).expect("step"))
                .collect();
            let fix = reports.iter().position(|r| r.localised);
            (survey(&placed_steps(&tracker, reports)), fix)
        };
        let (true_coverage, _) = survey(&truth);
        let ((filtered_coverage, filtered_rms), fix) = run(false);
        let ((coverage, rms), _) = run(true);
        eprintln!(
            "seed {seed}: fix at step {fix:?}; coverage {:.1} % (filtered {:.1} %, true positions {:.1} %); RMS {rms:.2} dB (filtered {filtered_rms:.2} dB)",
            100.0 * coverage,
            100.0 * filtered_coverage,
            100.0 * true_coverage
        );
        assert!(
            fix.is_some_and(|f| f > 5),
            "seed {seed}: the walk must start ambiguous"
        );
        assert!(
            coverage >= true_coverage - 0.03,
            "seed {seed}: coverage {coverage} vs {true_coverage} at true positions"
        );
        assert!(
            rms <= filtered_rms + 0.1,
            "seed {seed}: RMS {rms} vs {filtered_rms}"
        );
    }
}
