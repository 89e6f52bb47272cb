//! The library's pipelines are the toolkit's work; the CLI and the batch runners are faces.
//!
//! * A batch of walks fanned out walk by walk and pass by pass (`learn_one`, `others_map`,
//!   `combine`: what a cluster runs as tasks) learns exactly what `learn` does in one call.
//! * The CLI writes what the pipelines compute: `learn`, `track`, `survey` and `steps` run
//!   through the binary give byte-identical files to the library's results written by the
//!   library's writers, for the same inputs and seeds.

use assert_cmd::Command;
use footslam::filter::{FootSlamConfig, FootSlamEstimate, StartPose, TrackerConfig};
use footslam::geometry::LocalFrame;
use footslam::inertial::{Mount, StepsConfig};
use footslam::io::floor_plan_geojson::read_floor_plan;
use footslam::io::map_geojson::write_map_geojson;
use footslam::io::radio_map_geojson::write_radio_map_geojson;
use footslam::io::steps_csv::write_steps_with_field;
use footslam::io::{read_imu, read_steps, read_wifi, write_track};
use footslam::map::FloorTopology;
use footslam::pipeline::{
    LearnConfig, LearnInput, LearnWalk, Silent, SnapshotSteps, SurveyConfig, SurveyInput,
    SurveyWalk, TrackInput, combine, feetslam_passes, learn, learn_one, others_map, steps, survey,
    track,
};
use footslam::sim::{SimConfig, simulate};
use std::path::Path;

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// `walks` to learn in the local frame, with no outline or prior map.
fn in_local_frame(walks: &[LearnWalk]) -> LearnInput<'_> {
    LearnInput {
        walks,
        frame: LocalFrame::default(),
        outline: None,
        prior_map: None,
    }
}

#[test]
fn a_batch_fanned_out_walk_by_walk_learns_what_learn_does() {
    // Three one-lap office walks from the known start (the origin, facing east).
    let walks: Vec<LearnWalk> = [41u64, 42, 43]
        .iter()
        .map(|&seed| {
            let mut config = SimConfig {
                seed,
                ..Default::default()
            };
            config.walk.laps = 1;
            LearnWalk {
                trace: simulate(&config).expect("simulate").steps,
                start: Some(StartPose {
                    x: 0.0,
                    y: 0.0,
                    heading: Some(0.0),
                    level: None,
                }),
                ..Default::default()
            }
        })
        .collect();
    let config = LearnConfig {
        footslam: FootSlamConfig {
            particles: 300,
            ..Default::default()
        },
        ..Default::default()
    };
    let input = in_local_frame(&walks);
    let together = learn(&input, &config, &Silent).expect("learn");
    assert_eq!(together.iterations, config.iterations);
    assert!(together.iterations > 0);

    // The same batch as tasks: pass 0 alone, then each pass against the others' maps.
    let passes = feetslam_passes(&walks, &config);
    assert_eq!(passes, together.iterations);
    let mut answers: Vec<FootSlamEstimate> = walks
        .iter()
        .enumerate()
        .map(|(i, w)| {
            learn_one(&input, w, i, None, &config, None)
                .expect("pass 0")
                .estimate
        })
        .collect();
    for _ in 0..passes {
        let maps: Vec<_> = answers.iter().map(|e| &e.map).collect();
        let others: Vec<_> = (0..walks.len())
            .map(|i| others_map(&maps, i).expect("others"))
            .collect();
        answers = walks
            .iter()
            .enumerate()
            .map(|(i, w)| {
                learn_one(&input, w, i, Some(&others[i]), &config, None)
                    .expect("pass")
                    .estimate
            })
            .collect();
    }
    for (i, (apart, run)) in answers.iter().zip(&together.walks).enumerate() {
        assert_eq!(apart.path, run.estimate.path, "walk {i}: path");
        assert_eq!(apart.map, run.estimate.map, "walk {i}: map");
    }
    let refs: Vec<&FootSlamEstimate> = answers.iter().collect();
    let combined = combine(&input, &refs, &config.cells).expect("combine");
    let merged = combined.merged.expect("a batch's merged map");
    assert_eq!(Some(&merged), together.combined.merged.as_ref());
    assert!(merged.cells.len() > 50, "{} hexagons", merged.cells.len());
    // A task's index must name a walk of the batch, and combine wants one answer a walk.
    assert!(combine(&input, &refs[..2], &config.cells).is_err());
}

#[test]
fn the_cli_writes_what_the_pipelines_compute() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    footslam()
        .args([
            "simulate",
            "--building",
            "tower",
            "--minutes",
            "2",
            "--seed",
            "4",
        ])
        .arg("--out")
        .arg(d.join("sim"))
        .assert()
        .success();
    let (plan_path, steps_path, wifi_path) = (
        d.join("sim/floor.geojson"),
        d.join("sim/steps.csv"),
        d.join("sim/wifi.csv"),
    );
    let trace = read_steps(&steps_path).expect("steps");
    let (plan, frame) = read_floor_plan(&plan_path, None).expect("plan");

    // learn: one walk, 400 particles, seed 3.
    footslam()
        .args(["learn", "--particles", "400", "--seed", "3", "--steps"])
        .arg(&steps_path)
        .arg("--out")
        .arg(d.join("learn"))
        .assert()
        .success();
    let config = FootSlamConfig {
        particles: 400,
        seed: 3,
        ..Default::default()
    };
    let walks = [LearnWalk {
        trace: trace.clone(),
        ..Default::default()
    }];
    let input = in_local_frame(&walks);
    let learned = learn(&input, &LearnConfig::from(config), &Silent).expect("learn");
    let map = d.join("lib-map.geojson");
    write_map_geojson(&map, &learned.walks[0].estimate.map, &input.frame).expect("write");
    assert_eq!(read(&map), read(&d.join("learn/map.geojson")), "learn");

    // track: the filtered track, seed 2.
    footslam()
        .args(["track", "--seed", "2", "--plan"])
        .arg(&plan_path)
        .arg("--steps")
        .arg(&steps_path)
        .arg("--out")
        .arg(d.join("track"))
        .assert()
        .success();
    let tracker = TrackerConfig {
        seed: 2,
        ..Default::default()
    };
    let topology = FloorTopology::build(&plan, &tracker.topology).expect("topology");
    let input = TrackInput {
        topology: &topology,
        transitions: None,
        radio: None,
    };
    let run = track(&input, &trace, &tracker, &SnapshotSteps::Never, &Silent).expect("track");
    let filtered = d.join("lib-track.csv");
    write_track(&filtered, &run.filtered).expect("write");
    assert_eq!(
        read(&filtered),
        read(&d.join("track/track_filtered.csv")),
        "track"
    );

    // survey: the walk's WiFi into a radio map, seed 5.
    footslam()
        .args(["survey", "--seed", "5", "--plan"])
        .arg(&plan_path)
        .arg("--steps")
        .arg(&steps_path)
        .arg("--wifi")
        .arg(&wifi_path)
        .arg("--out")
        .arg(d.join("survey"))
        .assert()
        .success();
    let mut survey_config = SurveyConfig::default();
    survey_config.tracker.seed = 5;
    let walks = [SurveyWalk {
        trace: trace.clone(),
        scans: read_wifi(&wifi_path).expect("wifi"),
        start: None,
    }];
    let input = SurveyInput {
        plan: &plan,
        topology: &topology,
        walks: &walks,
        earlier: &[],
    };
    let surveyed = survey(&input, &survey_config, &Silent).expect("survey");
    let radio = d.join("lib-radiomap.geojson");
    write_radio_map_geojson(&radio, &surveyed.map, &frame).expect("write");
    assert_eq!(
        read(&radio),
        read(&d.join("survey/radiomap.geojson")),
        "survey"
    );

    // steps: a phone recording's step events.
    let imu = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/phone_excerpt.csv");
    footslam()
        .args(["steps", "--mount", "phone", "--imu"])
        .arg(&imu)
        .arg("--out")
        .arg(d.join("steps"))
        .assert()
        .success();
    let recording = read_imu(&imu).expect("imu");
    let events = steps(&recording, Mount::Phone, &StepsConfig::default()).expect("steps");
    let written = d.join("lib-steps.csv");
    write_steps_with_field(&written, &events.trace, events.field.as_ref()).expect("write");
    assert_eq!(read(&written), read(&d.join("steps/steps.csv")), "steps");
}

#[test]
fn cross_walk_scans_weigh_in_the_feetslam_passes_when_asked() {
    use footslam::sim::{TowerSimConfig, simulate_tower};
    // Two 3-minute tower walks with their WiFi, each from its true start.
    let walks: Vec<LearnWalk> = [7u64, 8]
        .iter()
        .map(|&seed| {
            let mut config = TowerSimConfig {
                seed,
                ..Default::default()
            };
            config.walk.minutes = 3.0;
            let sim = simulate_tower(&config).expect("simulate");
            LearnWalk {
                trace: sim.steps,
                scans: sim.wifi,
                start: Some(StartPose {
                    x: sim.start.x,
                    y: sim.start.y,
                    heading: Some(sim.start.heading),
                    level: Some(sim.start.level),
                }),
                ..Default::default()
            }
        })
        .collect();
    let input = in_local_frame(&walks);
    let mut config = LearnConfig {
        footslam: FootSlamConfig {
            particles: 300,
            ..Default::default()
        },
        iterations: 1,
        ..Default::default()
    };
    let without = learn(&input, &config, &Silent).expect("learn");
    assert!(without.walks.iter().all(|r| r.wifi_references.is_none()));
    config.footslam.wifi.cross_walk = true;
    let with = learn(&input, &config, &Silent).expect("learn");
    for (i, run) in with.walks.iter().enumerate() {
        let refs = run
            .wifi_references
            .as_ref()
            .expect("references in the pass");
        assert!(
            refs.references() > 0 && refs.calibration_pairs > 0,
            "walk {i}"
        );
    }
    assert_ne!(
        with.walks[0].estimate.path, without.walks[0].estimate.path,
        "the other walk's scans weigh"
    );
}
