//! No floor plan needed (issue 14, part 2): a radio map from the walks alone. Three walks of
//! a one-floor simulated building, each from its known start, learned by FootSLAM; their
//! scans placed on the learned paths and cut by the plan learned from the merged map
//! ([`survey_paths`], what `learn --wifi` runs). Its per-cell mean RSSI against the
//! simulator's expected field, after the walks' rigid alignment, is within 1 dB (RMS) of a
//! radio map surveyed on the true plan with the same walks (the tracker from the same known
//! starts, `survey`'s way).
//!
//! Then new walkers, each from an unknown start, are tracked twice with their WiFi: on the
//! true plan with the surveyed radio map, and on the learned plan (grown by the tracking
//! margin, `track --plan-margin 0.25`) with the learned radio map. On the learned map each
//! localises on the right place in at most twice the steps, and tracks with p95 ≤ 1.5 m in
//! the learned map's frame (the truth moved into it by the rigid alignment).

use footslam::eval::rf_localisation::{radio_map_rms, radio_map_rms_in, survey_simulations};
use footslam::eval::tracking::{TrackingScore, score_tracking};
use footslam::filter::{
    EPSILON_MISS, FootSlam, FootSlamConfig, RfConfig, RfLocaliser, RfTracker, TrackerConfig,
    path_points, survey_paths,
};
use footslam::geometry::{Pose2, RigidTransform};
use footslam::map::{
    CellConfig, CellMap, FloorTopology, PlanConfig, RadioMap, TopologyConfig, grow_plan,
    merge_maps, walkable_plan,
};
use footslam::sensor::TruePose;
use footslam::sim::{TowerSimConfig, TowerSimulation, simulate_tower};

/// Grid spacing of the expected field, metres.
const SPACING: f64 = 0.5;
/// Readings a (cell, access point) pair needs to be scored.
const MIN_READINGS: u32 = 3;
/// How far a learned plan is grown for tracking (`track --plan-margin`), metres.
const TRACKING_MARGIN: f64 = 0.25;

/// `walker` tracked from an unknown start on `topology` with `map` and its scans, scored
/// against `truth` (its true poses, in the frame of the map).
fn track_unknown_start(
    walker: &TowerSimulation,
    topology: &FloorTopology,
    map: &RadioMap,
    truth: &[TruePose],
    seed: u64,
) -> TrackingScore {
    let rf = RfLocaliser::new(map, topology, &RfConfig::default()).expect("localiser");
    let config = TrackerConfig {
        seed,
        ..Default::default()
    };
    let mut tracker = RfTracker::new(topology, &config, &rf, &walker.wifi).expect("tracker");
    let reports: Vec<_> = walker
        .steps
        .steps()
        .iter()
        .map(|s| tracker.update(s).expect("step"))
        .collect();
    score_tracking(truth, &reports)
}

fn one_floor_walk(seed: u64) -> TowerSimulation {
    let mut config = TowerSimConfig {
        seed,
        ..Default::default()
    };
    config.building.floors = 1;
    simulate_tower(&config).expect("simulation")
}

#[test]
#[allow(clippy::print_stderr)] // reports the figures with --nocapture
fn a_radio_map_from_the_walks_alone_matches_one_surveyed_on_the_true_plan_and_localises_new_walkers()
 {
    let sims: Vec<TowerSimulation> = [21u64, 22, 23].into_iter().map(one_floor_walk).collect();
    // FootSLAM from each walk's known start (the crowdsourced case: each walk starts at a
    // known point), so the three maps share one frame.
    let estimates: Vec<_> = sims
        .iter()
        .enumerate()
        .map(|(i, sim)| {
            let config = FootSlamConfig {
                particles: 5_000,
                seed: 7 + i as u64,
                start: Pose2::new(sim.start.x, sim.start.y, sim.start.heading),
                ..Default::default()
            };
            let mut filter = FootSlam::new(config).expect("filter");
            for step in sim.steps.steps() {
                filter.update(step);
            }
            filter.estimate()
        })
        .collect();
    let maps: Vec<_> = estimates.iter().map(|e| (&e.map, 1.0)).collect();
    let merged = merge_maps(&maps).expect("merge");
    let learned = walkable_plan(&merged, &PlanConfig::default()).expect("plan");
    let paths: Vec<_> = sims
        .iter()
        .zip(&estimates)
        .map(|(sim, e)| {
            (
                path_points(sim.steps.steps(), &e.path, 0),
                sim.wifi.as_slice(),
            )
        })
        .collect();
    let survey = survey_paths(
        &learned.plan,
        &paths,
        &CellConfig::default(),
        RfConfig::default().missing_rssi,
        EPSILON_MISS,
    )
    .expect("survey on the learned plan");
    let added: usize = survey.counts.iter().map(|c| c.added).sum();
    let scans: usize = sims.iter().map(|s| s.wifi.len()).sum();
    assert!(added * 10 >= scans * 9, "{added} of {scans} scans placed");
    assert!(survey.map.epsilon.is_some(), "ε calibrated");

    // The learned frame against the truth's: the rigid fit of every learned step position to
    // its true one.
    let (from, to): (Vec<_>, Vec<_>) = sims
        .iter()
        .zip(&estimates)
        .flat_map(|(sim, e)| {
            e.path
                .iter()
                .zip(&sim.truth.poses)
                .map(|(p, t)| ((p.x, p.y), (t.x, t.y)))
        })
        .unzip();
    let to_truth = RigidTransform::fit(&from, &to).expect("alignment");
    let truth_topology =
        FloorTopology::build(&sims[0].plan, &TopologyConfig::default()).expect("topology");
    let learned_topology =
        FloorTopology::build(&learned.plan, &TopologyConfig::default()).expect("topology");
    let (learned_rms, learned_pairs) = radio_map_rms_in(
        &survey.map,
        &survey.cells,
        &learned_topology,
        &sims[0].radio,
        &truth_topology,
        Some(&to_truth.inverse()),
        SPACING,
        MIN_READINGS,
    );

    // The same walks surveyed on the true plan.
    let cells =
        CellMap::build(&sims[0].plan, &truth_topology, &CellConfig::default()).expect("cells");
    let surveyed = survey_simulations(
        &sims,
        &truth_topology,
        &cells,
        &Default::default(),
        RfConfig::default().missing_rssi,
        EPSILON_MISS,
    )
    .expect("survey on the true plan");
    let (true_rms, true_pairs) = radio_map_rms(
        &surveyed,
        &cells,
        &truth_topology,
        &sims[0].radio,
        SPACING,
        MIN_READINGS,
    );
    eprintln!(
        "learned plan: {} cells, {added}/{scans} scans, RMS {learned_rms:.2} dB over \
         {learned_pairs} pairs; true plan: {} cells, RMS {true_rms:.2} dB over {true_pairs} pairs",
        survey.cells.cells().len(),
        cells.cells().len()
    );
    assert!(learned_pairs >= 100 && true_pairs >= 100);
    assert!(
        learned_rms <= true_rms + 1.0,
        "learned {learned_rms:.2} dB against surveyed {true_rms:.2} dB"
    );

    // New walkers from unknown starts: the true plan and surveyed map, against the learned
    // plan (grown for tracking) and learned map.
    let tracking_plan = grow_plan(&learned.plan, TRACKING_MARGIN).expect("grown plan");
    let tracking_topology =
        FloorTopology::build(&tracking_plan, &TopologyConfig::default()).expect("topology");
    let from_truth = to_truth.inverse();
    for seed in 30..36 {
        let walker = one_floor_walk(seed);
        let surveyed_run = track_unknown_start(
            &walker,
            &truth_topology,
            &surveyed,
            &walker.truth.poses,
            seed,
        );
        let moved: Vec<TruePose> = walker
            .truth
            .poses
            .iter()
            .map(|p| {
                let (x, y) = from_truth.apply((p.x, p.y));
                TruePose { x, y, ..*p }
            })
            .collect();
        let learned_run =
            track_unknown_start(&walker, &tracking_topology, &survey.map, &moved, seed);
        let steps = |r: &TrackingScore| r.steps_to_localise.expect("localised");
        let p95 = |r: &TrackingScore| r.errors.as_ref().expect("errors").p95;
        eprintln!(
            "walker {seed}: true plan + surveyed map localised in {} steps, p95 {:.2} m; \
             learned plan + map in {} steps, p95 {:.2} m",
            steps(&surveyed_run),
            p95(&surveyed_run),
            steps(&learned_run),
            p95(&learned_run)
        );
        assert!(learned_run.right_cluster, "walker {seed}: wrong first fix");
        assert!(
            steps(&learned_run) <= 2 * steps(&surveyed_run),
            "walker {seed}: {} steps against {}",
            steps(&learned_run),
            steps(&surveyed_run)
        );
        assert!(
            p95(&learned_run) <= 1.5,
            "walker {seed}: p95 {}",
            p95(&learned_run)
        );
    }
}

fn footslam() -> assert_cmd::Command {
    assert_cmd::Command::cargo_bin("footslam").expect("binary")
}

#[test]
fn learn_wifi_writes_a_radio_map_on_the_learned_plan_and_refuses_a_log_on_another_clock() {
    use footslam::io::radio_map_geojson::read_radio_map_geojson;
    use predicates::prelude::*;
    let dir = tempfile::tempdir().expect("tempdir");
    let sim = dir.path().join("sim");
    footslam()
        .args(["simulate", "--building", "tower", "--floors", "1"])
        .args(["--minutes", "4", "--seed", "5", "--origin", "52.21,0.091"])
        .arg("--out")
        .arg(&sim)
        .assert()
        .success();
    // The walk's folder: `wifi.csv` beside `steps.csv` is found without `--wifi`.
    let out = dir.path().join("learn");
    footslam()
        .args(["learn", "--particles", "2000", "--cell", "2", "--steps"])
        .arg(&sim)
        .arg("--out")
        .arg(&out)
        .assert()
        .success();
    for file in [
        "radiomap.geojson",
        "radiomap.csv",
        "radiomap.png",
        "plan.geojson",
    ] {
        assert!(out.join(file).is_file(), "{file}");
    }
    // One heatmap per access point, named by its BSSID.
    let heatmaps: Vec<String> = std::fs::read_dir(&out)
        .expect("outputs")
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.starts_with("heatmap-") && n.ends_with(".png"))
        .collect();
    assert!(!heatmaps.is_empty(), "no heatmap");
    assert!(heatmaps.iter().all(|n| !n.contains(':')), "{heatmaps:?}");
    let (map, _) = read_radio_map_geojson(&out.join("radiomap.geojson"), None).expect("map");
    assert!(map.epsilon.is_some(), "ε calibrated");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).expect("summary"))
            .expect("json");
    let radio = &summary["radio"];
    assert_eq!(radio["granularity_m"], 2.0);
    assert_eq!(radio["cells"].as_u64(), Some(map.cells.len() as u64));
    let (read, added) = (&radio["scans"][0], &radio["scans_added"][0]);
    assert!(
        added.as_u64() > Some(0) && added.as_u64() <= read.as_u64(),
        "{radio}"
    );

    // A walker tracked on the learned plan, grown for tracking, with the learned radio map
    // (the same walk: the CLI end to end, not the figures).
    footslam()
        .args(["track", "--plan-margin", "0.25", "--plan"])
        .arg(out.join("plan.geojson"))
        .arg("--radiomap")
        .arg(out.join("radiomap.geojson"))
        .arg("--steps")
        .arg(sim.join("steps.csv"))
        .arg("--wifi")
        .arg(sim.join("wifi.csv"))
        .arg("--out")
        .arg(dir.path().join("track"))
        .assert()
        .success()
        .stdout(predicate::str::contains("localised after"));
    footslam()
        .args(["track", "--plan-margin=-1", "--plan"])
        .arg(out.join("plan.geojson"))
        .arg("--out")
        .arg(dir.path().join("bad-margin"))
        .assert()
        .failure()
        .stderr(predicate::str::contains("--plan-margin"));

    // The same log on another clock places no scan: an error naming the file.
    let shifted = dir.path().join("shifted.csv");
    let text = std::fs::read_to_string(sim.join("wifi.csv")).expect("wifi");
    let mut lines = text.lines();
    let mut moved = format!("{}\n", lines.next().expect("header"));
    for line in lines {
        let (t, rest) = line.split_once(',').expect("row");
        let t: f64 = t.parse().expect("time");
        moved.push_str(&format!("{},{rest}\n", t + 1e5));
    }
    std::fs::write(&shifted, moved).expect("write");
    footslam()
        .args(["learn", "--particles", "500", "--steps"])
        .arg(sim.join("steps.csv"))
        .arg("--wifi")
        .arg(&shifted)
        .arg("--out")
        .arg(dir.path().join("shifted-run"))
        .assert()
        .failure()
        .stderr(
            predicate::str::contains("shifted.csv")
                .and(predicate::str::contains("no scan falls within")),
        );
    assert!(!dir.path().join("shifted-run").exists());
}
