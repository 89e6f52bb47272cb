//! `track --hexmap` (issue 14, part 3): a learned map's transition probabilities as the
//! tracker's motion prior, through the library (`footslam::pipeline::learn` and `track`, as
//! `footslam learn` and `footslam track` run them).
//!
//! Three walks of a one-floor simulated building are learned from their known starts with
//! their WiFi (so the learned frame is the truth's); new walkers are then tracked from an
//! unknown start on the learned plan (grown by `--plan-margin 0.25`) with the learned radio
//! map, with and without the learned map's transitions. The prior must make every walker's
//! median error smaller (it pulls particles onto the lanes the mapping walks trod) and must
//! not slow localisation by more than a few steps. The command line refuses a learned map
//! in another frame than the plan's.

use crate::common::{
    Anchors, in_own_pool, learn_walks, recorded, recorded_plan, recorded_radio_map, recorded_scans,
    recorded_truth, smoothed_track, truth_track,
};
use assert_cmd::Command;
use footslam::eval::{Alignment, position_errors};
use footslam::filter::{FootSlamConfig, RfLocaliser, StartPose, TrackerConfig};
use footslam::geometry::LocalFrame;
use footslam::map::{FloorTopology, grow_plan};
use footslam::model::TransitionPrior;
use footslam::pipeline::{
    LearnWalk, PlanRunConfig, RadioInput, Silent, SnapshotSteps, TrackInput, plan, track,
};
use footslam::sim::{TowerSimConfig, TowerSimulation, simulate_tower};

/// A walk of the one-floor building (`footslam simulate --building tower --floors 1`).
fn simulate(seed: u64) -> TowerSimulation {
    let mut config = TowerSimConfig {
        seed,
        ..Default::default()
    };
    config.building.floors = 1;
    simulate_tower(&config).expect("simulate")
}

#[test]
#[allow(clippy::print_stderr)] // reports the figures with --nocapture
fn a_learned_maps_transitions_sharpen_tracking_on_its_plan() {
    // The mapping walks, each with its WiFi and its known start (a `learn --walks`
    // manifest), learned with 5,000 particles into the default frame.
    let walks: Vec<LearnWalk> = [21u64, 22, 23]
        .into_iter()
        .map(|seed| {
            let sim = simulate(seed);
            LearnWalk {
                trace: recorded(&sim.steps),
                scans: recorded_scans(&sim.wifi),
                start: Some(StartPose::from(sim.start)),
                ..Default::default()
            }
        })
        .collect();
    // The maps are learned from the steps alone (the scans make the radio map only), so that
    // this test follows the transition prior; the scans inside the filter are tested in
    // filter::footslam's and model::scan_pairs' tests.
    let mut config = FootSlamConfig {
        particles: 5000,
        ..Default::default()
    };
    config.wifi.enabled = false;
    let learned = learn_walks(&walks, Anchors::default(), &config).combined;
    let merged = learned.merged.expect("merged map");
    let radio = learned.radio.expect("radio map");
    // What `track` reads of `learn`'s files: `merged_plan.geojson` (the plan of the merged
    // map) grown by `--plan-margin 0.25`, `radiomap.geojson` and, with `--hexmap`,
    // `merged.geojson`.
    let frame = LocalFrame::default();
    let tracker = TrackerConfig::default();
    let merged_plan = plan(&merged, &PlanRunConfig::default())
        .expect("plan")
        .learned
        .plan;
    let plan = grow_plan(&recorded_plan(&merged_plan, frame), 0.25).expect("grown plan");
    let topology = FloorTopology::build(&plan, &tracker.topology).expect("topology");
    let radio_map = recorded_radio_map(&radio.survey.map, frame);
    let localiser = RfLocaliser::new(&radio_map, &topology, &tracker.rf).expect("localiser");
    let transitions = TransitionPrior::new(&merged, tracker.transitions).expect("transitions");
    for seed in [30u64, 32] {
        let sim = simulate(seed);
        let (steps, scans) = (recorded(&sim.steps), recorded_scans(&sim.wifi));
        let truth = truth_track(&recorded_truth(&sim.truth).poses);
        let run = |hexmap: bool| {
            let input = TrackInput {
                topology: &topology,
                transitions: hexmap.then_some(&transitions),
                radio: Some(RadioInput {
                    localiser: &localiser,
                    scans: &scans,
                }),
            };
            let run =
                in_own_pool(|| track(&input, &steps, &tracker, &SnapshotSteps::Never, &Silent))
                    .expect("track");
            let errors = position_errors(&truth, &smoothed_track(&steps, &run), Alignment::None)
                .expect("errors");
            let localised = run.records.first_localised().expect("localised") + 1;
            (errors.p50, errors.p95, localised)
        };
        let (plain, hex) = (run(false), run(true));
        eprintln!("walker {seed}: plain (p50, p95, steps) {plain:?}, with --hexmap {hex:?}");
        assert!(hex.0 < plain.0, "walker {seed}: {hex:?} against {plain:?}");
        assert!(hex.1 < 1.2, "walker {seed}: {hex:?}");
        assert!(
            hex.2 <= plain.2 + 3,
            "walker {seed}: {hex:?} against {plain:?}"
        );
    }
}

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

#[test]
fn a_learned_map_in_another_frame_than_the_plan_is_refused() {
    // A map and its plan from one `learn` run (few particles: only the files matter), the
    // plan then placed elsewhere by `--origin`: the map is refused, named.
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    footslam()
        .args(["simulate", "--building", "tower", "--floors", "1", "--seed"])
        .args(["21", "--out"])
        .arg(d.join("sim"))
        .assert()
        .success();
    let learned = d.join("learn");
    footslam()
        .args(["learn", "--particles", "200", "--steps"])
        .arg(d.join("sim/steps.csv"))
        .arg("--out")
        .arg(&learned)
        .assert()
        .success();
    let assert = footslam()
        .arg("track")
        .arg("--plan")
        .arg(learned.join("plan.geojson"))
        .arg("--steps")
        .arg(d.join("sim/steps.csv"))
        .args(["--origin", "0.001,0"])
        .arg("--hexmap")
        .arg(learned.join("map.geojson"))
        .arg("--out")
        .arg(d.join("refused"))
        .assert()
        .failure();
    let stderr = String::from_utf8_lossy(&assert.get_output().stderr).to_string();
    assert!(
        stderr.contains("map.geojson") && stderr.contains("frame"),
        "{stderr}"
    );
}
