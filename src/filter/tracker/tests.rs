//! Tests of the tracker.

use super::*;
use crate::filter::KldConfig;
use crate::filter::tracker_config::StartPose;
use crate::map::TopologyConfig;
use crate::sim::{SimConfig, simulate};

fn office() -> (crate::sim::Simulation, FloorTopology) {
    let mut config = SimConfig {
        seed: 7,
        ..Default::default()
    };
    config.walk.laps = 1;
    let sim = simulate(&config).expect("sim");
    let topology = FloorTopology::build(&sim.plan, &TopologyConfig::default()).expect("topo");
    (sim, topology)
}

fn small() -> TrackerConfig {
    TrackerConfig {
        kld: KldConfig {
            max_particles: 200_000,
            ..Default::default()
        },
        ..Default::default()
    }
}

/// [`small`] with a known start at the office's origin, on level 0.
fn at_origin(heading: f64) -> TrackerConfig {
    TrackerConfig {
        start: Some(StartPose {
            x: 0.0,
            y: 0.0,
            heading: Some(heading),
            level: Some(0),
        }),
        ..small()
    }
}

#[test]
fn particle_is_24_bytes_and_memory_is_at_most_64_bytes_per_particle() {
    assert_eq!(std::mem::size_of::<TrackParticle>(), 24);
    let (sim, topology) = office();
    let mut tracker = Tracker::new(&topology, &small()).expect("tracker");
    for s in &sim.steps.steps()[..3] {
        tracker.update(s).expect("update");
    }
    let b = tracker.bytes_per_particle();
    assert!(b <= 64.0, "{b} bytes per particle");
}

#[test]
fn known_start_tracks_a_walk_closely() {
    let (sim, topology) = office();
    let config = at_origin(0.0);
    let mut tracker = Tracker::new(&topology, &config).expect("tracker");
    assert!(tracker.initial_particles() < 50_000);
    let mut errors = Vec::new();
    for (s, p) in sim.steps.steps().iter().zip(&sim.truth.poses) {
        let r = tracker.update(s).expect("update");
        assert!(r.recovery.is_none(), "death at t = {}", s.t);
        let c = r.estimate.expect("clustered");
        errors.push((c.x - p.x).hypot(c.y - p.y));
    }
    errors.sort_by(f64::total_cmp);
    let p95 = errors[errors.len() * 95 / 100];
    assert!(p95 < 0.8, "p95 {p95} m");
}

#[test]
fn a_drift_rate_state_follows_a_drifting_gyro() {
    let mut config = SimConfig {
        seed: 9,
        ..Default::default()
    };
    config.walk.laps = 2;
    config.noise.drift_total = 120f64.to_radians();
    let sim = simulate(&config).expect("sim");
    let topology = FloorTopology::build(&sim.plan, &TopologyConfig::default()).expect("topo");
    let p95 = |drift_sigma: f64| {
        let config = TrackerConfig {
            drift_sigma,
            drift_walk_sigma: drift_sigma / 30.0,
            ..at_origin(0.0)
        };
        let mut tracker = Tracker::new(&topology, &config).expect("tracker");
        let mut errors: Vec<f64> = sim
            .steps
            .steps()
            .iter()
            .zip(&sim.truth.poses)
            .map(|(s, p)| {
                let c = tracker
                    .update(s)
                    .expect("update")
                    .estimate
                    .expect("cluster");
                (c.x - p.x).hypot(c.y - p.y)
            })
            .collect();
        errors.sort_by(f64::total_cmp);
        (
            errors[errors.len() * 95 / 100],
            tracker.particles()[0].drift,
        )
    };
    let (with, drift) = p95(0.05f64.to_radians());
    assert!(with < 1.0, "p95 {with} m with a drift state");
    // The walk drifts 120° over about 300 steps: about 0.4° a step, one sign.
    assert!(drift.abs() > 0.1f32.to_radians(), "drift {drift}");
}

#[test]
fn unknown_start_prior_covers_the_plan_and_shrinks() {
    let (sim, topology) = office();
    let mut tracker = Tracker::new(&topology, &small()).expect("tracker");
    let n0 = tracker.initial_particles();
    let bins = topology.total_area() * 36.0;
    assert!(n0 as f64 > bins, "{n0} particles for {bins} bins");
    assert!(tracker.particles().iter().all(|p| {
        sim.plan
            .is_walkable(f64::from(p.x), f64::from(p.y), Some(0))
    }));
    for s in &sim.steps.steps()[..60] {
        tracker.update(s).expect("update");
    }
    assert!(tracker.particles().len() < n0 / 4);
}

#[test]
fn results_do_not_depend_on_the_number_of_threads() {
    let (sim, topology) = office();
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        pool.install(|| {
            let mut tracker = Tracker::new(&topology, &small()).expect("tracker");
            let reports: Vec<TrackStep> = sim.steps.steps()[..40]
                .iter()
                .map(|s| tracker.update(s).expect("update"))
                .collect();
            (reports, tracker.particles().to_vec())
        })
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn a_walk_through_a_wall_is_recovered_not_a_crash() {
    let (_, topology) = office();
    let config = at_origin(-std::f64::consts::FRAC_PI_2);
    let mut tracker = Tracker::new(&topology, &config).expect("tracker");
    // Straight south from the corridor's centre line: through its south wall.
    let steps: Vec<Step> = (0..30)
        .map(|k| Step {
            t: f64::from(k) * 0.5 + 0.5,
            length: 0.7,
            dheading: 0.0,
            dz: 0.0,
            heading: None,
        })
        .collect();
    let mut deaths = 0;
    for s in &steps {
        let r = tracker.update(s).expect("update");
        deaths += usize::from(r.recovery.is_some());
        assert!(r.particles > 0);
        assert!(
            tracker
                .particles()
                .iter()
                .all(|p| p.x.is_finite() && p.y.is_finite())
        );
    }
    assert!(deaths > 0);
}

#[test]
fn an_unknown_start_heading_is_settled_by_step_headings() {
    let (sim, topology) = office();
    let unknown = |enabled: bool| TrackerConfig {
        start: Some(StartPose {
            heading: None,
            ..at_origin(0.0).start.expect("start")
        }),
        heading: crate::model::HeadingConfig {
            enabled,
            ..Default::default()
        },
        ..small()
    };
    // The mean resultant length of the particles' headings: 1 when all agree.
    let agreement = |t: &Tracker| {
        let (s, c) = t.particles().iter().fold((0.0, 0.0), |(s, c), p| {
            (
                s + f64::from(p.heading.sin()),
                c + f64::from(p.heading.cos()),
            )
        });
        s.hypot(c) / t.particles().len() as f64
    };
    let steps: Vec<Step> = sim
        .steps
        .steps()
        .iter()
        .zip(&sim.truth.poses)
        .map(|(s, p)| Step {
            heading: Some(p.heading),
            ..*s
        })
        .collect();
    let mut with = Tracker::new(&topology, &unknown(true)).expect("tracker");
    let mut without = Tracker::new(&topology, &unknown(false)).expect("tracker");
    assert!(agreement(&with) < 0.2, "a uniform prior heading");
    for s in &steps[..2] {
        with.update(s).expect("update");
        without.update(s).expect("update");
    }
    assert_eq!((with.headings_used(), without.headings_used()), (2, 0));
    // Two readings leave headings within about 20° (R = e^{−σ²/2} ≈ 0.94 for σ = 20°).
    assert!(agreement(&with) > 0.9, "{}", agreement(&with));
    assert!(agreement(&without) < agreement(&with));
    let mut errors: Vec<f64> = steps[2..]
        .iter()
        .zip(&sim.truth.poses[2..])
        .map(|(s, p)| {
            let c = with.update(s).expect("update").estimate.expect("cluster");
            (c.x - p.x).hypot(c.y - p.y)
        })
        .collect();
    errors.sort_by(f64::total_cmp);
    let p95 = errors[errors.len() * 95 / 100];
    assert!(p95 < 0.8, "p95 {p95} m");
}

#[test]
fn a_measurement_judges_each_particle_where_it_was_at_the_measurements_time() {
    use crate::map::{CellConfig, CellMap, CellRaster, RadioMap};
    use std::sync::Arc;
    let (sim, topology) = office();
    let cells = CellMap::build(
        &sim.plan,
        &topology,
        &CellConfig {
            granularity: 1.0,
            ..Default::default()
        },
    )
    .expect("cells");
    let raster =
        Arc::new(CellRaster::on_plan(&RadioMap::empty(&cells), &topology, 0.25).expect("raster"));
    // Inside: the 1 m cell the walker starts in, east along the corridor from (0, 0).
    let start = raster.cell_at(0, 0.0, 0.0).expect("a cell at the start");
    let values = (0..raster.cells())
        .map(|c| if c == start { 0.0 } else { f32::NEG_INFINITY })
        .collect();
    let region = CellField::new(raster, values, f32::NEG_INFINITY);
    let config = at_origin(0.0);
    // A 2 m step east leaves the start's cell: judged before the step (at = 0) every
    // particle is inside, after it (at = 1) none is, so that measurement is ignored.
    let step = Step {
        t: 1.0,
        length: 2.0,
        dheading: 0.0,
        dz: 0.0,
        heading: None,
    };
    let run = |at: f32| {
        let mut tracker = Tracker::new(&topology, &config).expect("tracker");
        let m = StepMeasurement { field: &region, at };
        let r = tracker.update_with(&step, Some(m)).expect("step");
        (
            tracker.measurements_ignored(),
            r.estimate.expect("estimate").x,
        )
    };
    let (ignored, x) = run(0.0);
    assert_eq!(ignored, 0);
    assert!((x - 2.0).abs() < 0.5, "{x}");
    assert_eq!(run(1.0).0, 1);
}

/// One open square room of `side` metres, in its own frame.
fn open_room(side: f64) -> FloorTopology {
    use crate::map::{FloorPlan, FloorPolygon};
    let ring = geo::LineString::from(vec![
        (0.0, 0.0),
        (side, 0.0),
        (side, side),
        (0.0, side),
        (0.0, 0.0),
    ]);
    let plan = FloorPlan {
        polygons: vec![FloorPolygon {
            polygon: geo::Polygon::new(ring, Vec::new()),
            level: 0,
            z: 0.0,
            name: None,
            room: None,
        }],
        ..FloorPlan::default()
    };
    FloorTopology::build(&plan, &TopologyConfig::default()).expect("topology")
}

#[test]
fn an_open_plan_keeps_each_step_within_its_bounds() {
    // An open room no wall narrows: the belief would keep the prior's particles and every
    // particle's path at every step.
    let topology = open_room(200.0);
    let config = TrackerConfig {
        kld: KldConfig {
            max_particles: 60_000,
            max_step_particles: 20_000,
            ..Default::default()
        },
        smoothing_max_nodes: 150_000,
        ..Default::default()
    };
    let (sim, _) = office();
    let mut tracker = Tracker::new(&topology, &config).expect("tracker");
    assert_eq!(
        tracker.initial_particles(),
        60_000,
        "the prior may use max_particles"
    );
    assert!(tracker.capped_draws() > 0);
    for s in &sim.steps.steps()[..20] {
        let r = tracker.update(s).expect("update");
        assert!(
            r.particles <= 20_000,
            "{} particles after a step",
            r.particles
        );
        let fit = r.fit.expect("fit");
        assert!(
            fit.survival > 0.9 && fit.unexplained_dz.abs() < 0.5,
            "{fit:?}"
        );
    }
    // 20 steps × 20,000 particles outgrow 150,000 path nodes: the ancestry is given up.
    let dropped = tracker.smoothing_dropped_at().expect("dropped");
    assert!((7..=9).contains(&dropped), "dropped at step {dropped}");
    assert!(tracker.take_smoothed().is_none());
    assert!(tracker.path_nodes_peak() > 150_000);
}
