//! Tests of the FootSLAM filter.
use super::*;
use crate::map::HexTransitionMap;
use crate::model::GpsObservation;
use crate::model::ScanEvidence;
use crate::sensor::WifiScan;

fn square_walk(laps: usize) -> Vec<Step> {
    let mut steps = Vec::new();
    let mut t = 0.0;
    for _ in 0..laps {
        for side in 0..4 {
            for s in 0..10 {
                t += 0.5;
                let turn = if s == 0 && (side > 0 || t > 1.0) {
                    std::f64::consts::FRAC_PI_2
                } else {
                    0.0
                };
                steps.push(Step {
                    t,
                    length: 0.7,
                    dheading: turn,
                    dz: 0.0,
                    heading: None,
                });
            }
        }
    }
    steps
}

/// A filter of `particles` seeded with `seed` after two laps of the square walk.
fn after_square_walk(particles: usize, seed: u64) -> FootSlam {
    let mut f = FootSlam::new(FootSlamConfig {
        particles,
        seed,
        ..Default::default()
    })
    .expect("valid");
    for s in square_walk(2) {
        f.update(&s);
    }
    f
}

#[test]
fn replayed_path_ends_at_the_particle() {
    let f = after_square_walk(300, 7);
    assert!(f.resamplings() > 0, "revisits must trigger resampling");
    for i in [0, 17, 299] {
        let path = f.replay_path(i);
        let end = path.last().expect("non-empty");
        assert_eq!(*end, f.particles[i].pose);
    }
    let e = f.estimate();
    assert_eq!(e.path.len(), 80);
    assert!(!e.map.cells.is_empty());
}

#[test]
fn estimate_maximises_the_whole_path_likelihood() {
    let f = after_square_walk(400, 9);
    let e = f.estimate();
    let max = f
        .particles
        .iter()
        .map(|p| p.path_log_likelihood)
        .fold(f64::NEG_INFINITY, f64::max);
    assert_eq!(e.path_log_likelihood, max);
    assert_eq!(f.particles[e.index].path_log_likelihood, max);
}

#[test]
fn results_do_not_depend_on_thread_count() {
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        pool.install(|| after_square_walk(500, 3).estimate().path)
    };
    assert_eq!(run(1), run(3));
}

/// Fixes at the true positions of a square walk started at (10, 5) facing north.
fn anchored(laps: usize) -> (Vec<Step>, Vec<Pose2>, Anchors) {
    let steps = square_walk(laps);
    let mut pose = Pose2::new(10.0, 5.0, std::f64::consts::FRAC_PI_2);
    let truth: Vec<Pose2> = steps
        .iter()
        .map(|s| {
            pose = pose.step(s.length, s.dheading);
            pose
        })
        .collect();
    let gps = steps
        .iter()
        .zip(&truth)
        .step_by(2)
        .map(|(s, p)| GpsObservation {
            t: s.t,
            x: p.x,
            y: p.y,
            sigma: 2.0,
        })
        .collect();
    let anchors = Anchors {
        gps,
        ..Default::default()
    };
    (steps, truth, anchors)
}

#[test]
fn gps_fixes_find_an_unknown_start_and_heading() {
    let (steps, truth, anchors) = anchored(2);
    let config = FootSlamConfig {
        particles: 2000,
        seed: 4,
        start: Pose2::new(11.0, 4.0, 0.0),
        start_position_sigma: 2.0,
        start_heading_sigma: std::f64::consts::PI,
        ..Default::default()
    };
    let mut f = FootSlam::with_anchors(config, anchors).expect("valid");
    for s in &steps {
        f.update(s);
    }
    assert_eq!(f.gps_fixes_used(), 40);
    let path = f.estimate().path;
    let worst = path
        .iter()
        .zip(&truth)
        .skip(10)
        .map(|(p, q)| (p.x - q.x).hypot(p.y - q.y))
        .fold(0.0, f64::max);
    assert!(
        worst < 1.5,
        "worst error {worst} m after the first 10 steps"
    );
}

#[test]
fn anchored_results_do_not_depend_on_thread_count() {
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        pool.install(|| {
            let (steps, _, mut anchors) = anchored(2);
            let mut prior = EdgePrior::uniform(0.8);
            let outline = geo::Rect::new((8.0, 3.0), (19.0, 14.0)).to_polygon();
            prior.add_outline(&HexGrid::new(0.5), &outline, 0.05);
            anchors.prior = Some(prior);
            let config = FootSlamConfig {
                particles: 500,
                seed: 3,
                start: Pose2::new(10.0, 5.0, 1.5),
                start_position_sigma: 1.0,
                start_heading_sigma: 0.2,
                ..Default::default()
            };
            let mut f = FootSlam::with_anchors(config, anchors).expect("valid");
            for s in &steps {
                f.update(s);
            }
            let e = f.estimate();
            (e.path, e.prior_offset)
        })
    };
    assert_eq!(run(1), run(3));
}

#[test]
fn revisiting_particles_gain_weight() {
    // Two edges: one crossed before (count 1), one never; the known one is likelier.
    let grid = HexGrid::new(0.5);
    let mut map = HexTransitionMap::new();
    let uniform = MapPrior {
        alpha: 0.8,
        prior: None,
        offset: Hex::ZERO,
        level: 0,
    };
    let a = Pose2::new(0.0, 0.0, 0.0);
    let b = Pose2::new(0.866, 0.0, 0.0);
    let first = log_map_factor(
        &grid,
        |h, e| map.record_crossing(h, e),
        uniform,
        false,
        a,
        b,
    );
    assert!(
        (first - (0.8f64 / 4.8).ln()).abs() < 1e-12,
        "an unknown hexagon gives 1/6"
    );
    let back = log_map_factor(
        &grid,
        |h, e| map.record_crossing(h, e),
        uniform,
        false,
        b,
        a,
    );
    // Leaving b through the edge entered: (1 + 0.8) / (1 + 4.8).
    assert!((back - (1.8f64 / 5.8).ln()).abs() < 1e-12);
    let c = Pose2::new(0.2, 0.2, 0.0);
    assert_eq!(
        log_map_factor(
            &grid,
            |h, e| map.record_crossing(h, e),
            uniform,
            false,
            a,
            c
        ),
        0.0,
        "no crossing, no update"
    );
}

#[test]
fn rejects_bad_configuration() {
    assert!(
        FootSlam::new(FootSlamConfig {
            particles: 0,
            ..Default::default()
        })
        .is_err()
    );
    assert!(
        FootSlam::new(FootSlamConfig {
            hex_radius: f64::NAN,
            ..Default::default()
        })
        .is_err()
    );
    assert!(
        FootSlam::new(FootSlamConfig {
            alpha: -1.0,
            ..Default::default()
        })
        .is_err()
    );
}

#[test]
fn compass_headings_pick_the_start_heading_and_count() {
    // The square walk in a world turned by 0.5 rad, its steps read by an exact compass.
    let rotation = 0.5;
    let mut heading = 0.0;
    let steps: Vec<Step> = square_walk(1)
        .into_iter()
        .map(|s| {
            heading += s.dheading;
            Step {
                heading: Some(heading + rotation),
                ..s
            }
        })
        .collect();
    let run = |enabled: bool| {
        let mut f = FootSlam::new(FootSlamConfig {
            particles: 500,
            seed: 3,
            start_heading_sigma: std::f64::consts::PI,
            heading: crate::model::HeadingConfig {
                enabled,
                ..Default::default()
            },
            ..Default::default()
        })
        .expect("valid");
        for s in &steps {
            f.update(s);
        }
        f
    };
    let with = run(true);
    assert_eq!(with.headings_used(), steps.len());
    let end = with.estimate().path.last().copied().expect("a path");
    let error = (end.heading - heading - rotation).sin().asin().abs();
    assert!(error < 10f64.to_radians(), "{}°", error.to_degrees());
    assert_eq!(run(false).headings_used(), 0);
}

#[test]
fn each_floor_has_its_own_map() {
    // Two laps of the square on the ground floor, a straight flight of 10 treads up 3 m,
    // then two laps of the same square (in plan) on the floor above: the same hexagons in
    // plan, counted on two levels.
    let mut steps = square_walk(2);
    let mut t = steps.last().expect("steps").t;
    for _ in 0..10 {
        t += 0.5;
        steps.push(Step {
            t,
            length: 0.3,
            dheading: 0.0,
            dz: 0.3,
            heading: None,
        });
    }
    for mut s in square_walk(2) {
        s.t += t + 0.5;
        steps.push(s);
    }
    let mut f = FootSlam::new(FootSlamConfig {
        particles: 200,
        seed: 3,
        ..Default::default()
    })
    .expect("valid");
    for s in &steps {
        f.update(s);
    }
    let e = f.estimate();
    assert_eq!(e.levels.len(), steps.len());
    assert_eq!(e.levels[..80], [0; 80]);
    assert_eq!(*e.levels.last().expect("steps"), 1);
    assert_eq!(e.map.cell_levels(), vec![0, 1]);
    assert!(
        (e.map.level_height(1) - 3.0).abs() < 0.1,
        "{:?}",
        e.map.levels
    );
    let on = |l: i32| e.map.cells.iter().filter(|c| c.level == l).count();
    // Each floor holds the square's hexagons (about 40 each), not their sum.
    assert!(
        (20..80).contains(&on(0)) && (20..80).contains(&on(1)),
        "{} {}",
        on(0),
        on(1)
    );
    // Without levels the two squares pile onto one plane.
    let mut flat = FootSlam::new(FootSlamConfig {
        particles: 200,
        seed: 3,
        levels: crate::model::LevelConfig {
            enabled: false,
            ..Default::default()
        },
        ..Default::default()
    })
    .expect("valid");
    for s in &steps {
        flat.update(s);
    }
    assert_eq!(flat.estimate().map.cell_levels(), vec![0]);
    assert!(flat.estimate().map.levels.is_empty());
}

/// Three laps of a 7 m square (10 steps a side, 0.5 s apart) whose measured heading
/// changes drift by `drift` radians a step, its true positions, and a WiFi scan every
/// second step from four access points at the corners (log-distance path loss, ±1.5 dB of
/// deterministic noise).
fn drifting_square_with_scans(drift: f64) -> (Vec<Step>, Vec<(f64, f64)>, Vec<WifiScan>) {
    let truth_steps = square_walk(3);
    let mut pose = Pose2::default();
    let mut truth = Vec::new();
    let steps: Vec<Step> = truth_steps
        .iter()
        .map(|s| {
            pose = pose.step(s.length, s.dheading);
            truth.push((pose.x, pose.y));
            Step {
                dheading: s.dheading + drift,
                ..*s
            }
        })
        .collect();
    let corners = [(-1.0, -1.0), (8.0, -1.0), (8.0, 8.0), (-1.0, 8.0)];
    let names = ["ap0", "ap1", "ap2", "ap3"];
    let scans = steps
        .iter()
        .zip(&truth)
        .enumerate()
        .filter(|(i, _)| i % 2 == 1)
        .map(|(i, (s, &(x, y)))| {
            let readings: Vec<(&str, f64)> = corners
                .iter()
                .zip(names)
                .enumerate()
                .map(|(a, (&(ax, ay), name))| {
                    let d = (x - ax).hypot(y - ay).max(1.0);
                    let noise = 0.75 * ((i * 7 + a * 13) % 5) as f64 - 1.5;
                    (name, -30.0 - 30.0 * d.log10() + noise)
                })
                .collect();
            WifiScan::from_readings(s.t, &readings)
        })
        .collect();
    (steps, truth, scans)
}

/// Mean distance of the answer's path from the truth.
fn mean_error(f: &FootSlam, truth: &[(f64, f64)]) -> f64 {
    let e = f.estimate();
    e.path
        .iter()
        .zip(truth)
        .map(|(p, t)| (p.x - t.0).hypot(p.y - t.1))
        .sum::<f64>()
        / truth.len() as f64
}

#[test]
fn wifi_scans_correct_a_drift_the_map_does_not_see() {
    // α so large that eq. (6) is flat: only the scans can tell the laps apart.
    let (steps, truth, scans) = drifting_square_with_scans(0.02);
    let config = FootSlamConfig {
        particles: 2000,
        seed: 3,
        alpha: 1000.0,
        motion: crate::model::StepMotionConfig {
            drift_rate_sigma0: 0.02,
            ..Default::default()
        },
        ..Default::default()
    };
    let evidence = ScanEvidence::new(&scans, &steps, &config.wifi).expect("calibrates");
    let run = |wifi: Option<Arc<ScanEvidence>>| {
        let anchors = Anchors {
            wifi,
            ..Default::default()
        };
        let mut f = FootSlam::with_anchors(config.clone(), anchors).expect("valid");
        for s in &steps {
            f.update(s);
        }
        f
    };
    let without = run(None);
    let with = run(Some(Arc::new(evidence)));
    assert_eq!(with.scans_used(), scans.len());
    assert_eq!(without.scans_used(), 0);
    let (e_with, e_without) = (mean_error(&with, &truth), mean_error(&without, &truth));
    assert!(
        e_with < 0.6 * e_without,
        "mean error with scans {e_with:.2} m, without {e_without:.2} m"
    );
    assert!(with.estimate().wifi_log_likelihood > 0.0);
}

#[test]
fn building_axes_correct_a_drift_the_map_does_not_see() {
    // A staircase of 14 m legs turning left and right in turn (it never comes back, so
    // eq. 6 has nothing to say), its heading drifting 0.6° a step.
    let mut pose = Pose2::default();
    let (mut steps, mut truth) = (Vec::new(), Vec::new());
    for k in 0..160 {
        let turn = match (k % 20, k / 20 % 2) {
            (0, _) if k == 0 => 0.0,
            (0, 1) => std::f64::consts::FRAC_PI_2,
            (0, _) => -std::f64::consts::FRAC_PI_2,
            _ => 0.0,
        };
        pose = pose.step(0.7, turn);
        truth.push((pose.x, pose.y));
        steps.push(Step {
            t: 1.7e9 + 0.5 * f64::from(k),
            length: 0.7,
            dheading: turn + 0.01,
            dz: 0.0,
            heading: None,
        });
    }
    let config = FootSlamConfig {
        particles: 2000,
        seed: 5,
        alpha: 1000.0,
        hex_radius: 10.0,
        motion: crate::model::StepMotionConfig {
            drift_rate_sigma0: 0.02,
            ..Default::default()
        },
        axes: crate::model::AxesConfig {
            enabled: true,
            ..Default::default()
        },
        ..Default::default()
    };
    let evidence = Arc::new(crate::model::AxisEvidence::new(&steps, &config.axes));
    assert!(evidence.active && evidence.directions == 4, "{evidence:?}");
    let run = |config: &FootSlamConfig| {
        let anchors = Anchors {
            axes: Some(Arc::clone(&evidence)),
            ..Default::default()
        };
        let mut f = FootSlam::with_anchors(config.clone(), anchors).expect("valid");
        for s in &steps {
            f.update(s);
        }
        f
    };
    let with = run(&config);
    let mut off = config.clone();
    off.axes.enabled = false;
    let without = run(&off);
    assert!(with.axis_steps() > steps.len() / 3, "{}", with.axis_steps());
    assert_eq!(without.axis_steps(), 0);
    let (e_with, e_without) = (mean_error(&with, &truth), mean_error(&without, &truth));
    let mut dr = Pose2::default();
    let e_dr = steps
        .iter()
        .zip(&truth)
        .map(|(s, t)| {
            dr = dr.step(s.length, s.dheading);
            (dr.x - t.0).hypot(dr.y - t.1)
        })
        .sum::<f64>()
        / truth.len() as f64;
    assert!(
        e_with < 0.2 * e_dr && e_with < 0.6 * e_without,
        "mean error with axes {e_with:.2} m, dead reckoning {e_dr:.2} m, without {e_without:.2} m"
    );
}

#[test]
fn smoothing_averages_the_final_paths_near_the_best() {
    let steps = square_walk(2);
    let mut truth = Vec::new();
    let mut pose = Pose2::default();
    for s in &steps {
        pose = pose.step(s.length, s.dheading);
        truth.push((pose.x, pose.y));
    }
    let run = |draws: usize| {
        let mut config = FootSlamConfig {
            particles: 3000,
            seed: 11,
            ..Default::default()
        };
        config.smoothing.draws = draws;
        let mut f = FootSlam::new(config).expect("valid");
        for s in &steps {
            f.update(s);
        }
        f
    };
    let alone = run(0);
    let e = alone.estimate();
    assert_eq!(e.smoothed_paths, (1, 1));
    assert!(e.spread_m.iter().all(|&s| s == 0.0));
    let replayed = alone.replay_path(e.index);
    assert!(e.path.iter().zip(&replayed).all(|(a, b)| a == b));
    let smoothed = run(256);
    let s = smoothed.estimate();
    assert_eq!(s.path.len(), steps.len());
    assert_eq!(s.spread_m.len(), steps.len());
    assert!(s.smoothed_paths.1 >= 1 && s.smoothed_paths.1 <= s.smoothed_paths.0);
    assert!(s.spread_m.iter().any(|&v| v > 0.0));
    // The spread grows towards the end, where the final particles' ancestries part.
    assert!(s.spread_m[s.spread_m.len() - 1] >= s.spread_m[0]);
    let (e_mean, e_best) = (mean_error(&smoothed, &truth), mean_error(&alone, &truth));
    assert!(
        e_mean <= 1.05 * e_best + 0.02,
        "smoothed {e_mean:.3} m, best {e_best:.3} m"
    );
}
