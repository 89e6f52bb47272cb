//! FootSLAM with the magnetic field (MagSLAM): on simulated office walks whose heading
//! drifts far, each step's field reading against the particles' own field maps must find
//! the revisits that the steps alone miss, and must not hurt where there is nothing to find.

use crate::common::{Anchors, learn_walks, learned_track, recorded, truth_track, walk_of};
use footslam::eval::{Alignment, position_errors};
use footslam::filter::FootSlamConfig;
use footslam::pipeline::LearnWalk;
use footslam::sensor::{StepField, StepFields};
use footslam::sim::magnetic::{FieldSimConfig, MagneticWorld};
use footslam::sim::{SimConfig, StepNoiseConfig, simulate};

/// The learned path's p95 error (rigid fit) on a simulated office walk with a phone's step
/// errors and 60° of heading drift, learned by 1,000 particles from the steps with the
/// `field` readings (or without any).
fn p95(seed: u64, field: impl Fn(&StepFields) -> Option<StepFields>) -> f64 {
    let mut config = SimConfig {
        seed,
        ..Default::default()
    };
    config.noise = StepNoiseConfig::phone();
    config.noise.drift_total = 60f64.to_radians();
    let sim = simulate(&config).expect("simulate");
    let steps = recorded(&sim.steps);
    let world = MagneticWorld::around(&sim.truth, FieldSimConfig::default(), seed + 1000);
    let readings = world
        .readings_along(&sim.truth, seed + 2000)
        .expect("readings");
    let walk = LearnWalk {
        field: field(&readings),
        ..walk_of(&steps)
    };
    let learn = FootSlamConfig {
        particles: 1_000,
        ..Default::default()
    };
    let run = learn_walks(&[walk], Anchors::default(), &learn)
        .walks
        .remove(0);
    let truth = truth_track(&sim.truth.poses);
    position_errors(&truth, &learned_track(&steps, &run), Alignment::Rigid)
        .expect("errors")
        .p95
}

#[test]
#[allow(clippy::print_stderr)] // reports the figures with --nocapture
fn the_field_finds_revisits_the_steps_miss() {
    let (mut sum_without, mut sum_with) = (0.0, 0.0);
    for seed in [3, 4, 5, 6] {
        let without = p95(seed, |_| None);
        let with = p95(seed, |f| Some(f.clone()));
        eprintln!("seed {seed}: p95 {without:.2} m without the field, {with:.2} m with it");
        assert!(
            with <= without + 0.5,
            "seed {seed}: {with:.2} m with the field, {without:.2} m without"
        );
        sum_without += without;
        sum_with += with;
    }
    assert!(
        sum_with < 0.8 * sum_without,
        "mean p95 {:.2} m with the field, {:.2} m without",
        sum_with / 4.0,
        sum_without / 4.0
    );
}

#[test]
fn a_field_that_tells_nothing_changes_nothing() {
    // A uniform field (outdoors, or a hall without steel) is found uninformative and left
    // out, so the answer is exactly the one without readings.
    let flat = |f: &StepFields| {
        let readings = vec![
            Some(StepField {
                magnitude: 48.0,
                vertical: Some(-43.0),
            });
            f.len()
        ];
        Some(StepFields::new(readings).expect("valid"))
    };
    assert_eq!(p95(5, |_| None), p95(5, flat));
}
