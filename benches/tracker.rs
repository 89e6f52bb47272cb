//! The known-map tracker's whole step (move, wall test through the floor polygons, height
//! weight, KLD bins and sample size, systematic resampling) at fixed particle counts on the
//! simulated three-floor building, from the uniform prior (the hardest phase: every particle
//! tests walls). Throughput is in particle-steps per second. Also the same step with a WiFi
//! containment region judged at the scan's time within the step (eqs. 12–13 of Woodman &
//! Harle 2009; a raster lookup per particle), the same step with an absolute heading on every
//! step (the compass likelihood: one wrapped difference, `exp` and `ln` per particle), and
//! the floor topology's `walk` on its own. The groups run without the path tree (causal,
//! `smoothing = false`), except `tracker_step_smoothing`, which keeps the belief's ancestry
//! for the whole-walk answer (the `track` default).

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use footslam::filter::{KldConfig, StepMeasurement, Tracker, TrackerConfig};
use footslam::map::{CellField, CellMap, CellRaster, FloorTopology, RadioMap, TopologyConfig};
use footslam::sensor::Step;
use footslam::sim::{TowerSimConfig, TowerSimulation, simulate_tower};
use rand::RngExt;
use std::hint::black_box;
use std::sync::Arc;
use std::time::Duration;

#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// The simulated tower's plan, as the tracker sees it, and its steps.
fn tower() -> (TowerSimulation, FloorTopology) {
    let sim = simulate_tower(&TowerSimConfig {
        seed: 1,
        ..Default::default()
    })
    .expect("simulation");
    let topology = FloorTopology::build(&sim.plan, &TopologyConfig::default()).expect("topology");
    (sim, topology)
}

/// Whole steps at fixed particle counts, each with `region` (if any) judged half-way
/// through the step; with `headings`, every step carries its true absolute heading.
fn step_group(
    c: &mut Criterion,
    name: &str,
    counts: &[usize],
    (sim, topology): &(TowerSimulation, FloorTopology),
    region: Option<&CellField>,
    headings: bool,
    smoothing: bool,
) {
    let steps: Vec<Step> = sim
        .steps
        .steps()
        .iter()
        .zip(&sim.truth.poses)
        .map(|(s, p)| Step {
            heading: headings.then_some(p.heading),
            ..*s
        })
        .collect();
    let mut g = c.benchmark_group(name);
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    for &n in counts {
        let config = TrackerConfig {
            kld: KldConfig {
                min_particles: n,
                max_particles: n,
                ..Default::default()
            },
            smoothing,
            ..Default::default()
        };
        let mut tracker = Tracker::new(topology, &config).expect("tracker");
        let mut k = 0;
        g.throughput(Throughput::Elements(n as u64));
        g.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            b.iter(|| {
                let m = region.map(|field| StepMeasurement { field, at: 0.5 });
                let report = tracker
                    .update_with(&steps[k % steps.len()], m)
                    .expect("step");
                k += 1;
                black_box(report.particles)
            })
        });
    }
    g.finish();
}

fn tracker_step(c: &mut Criterion) {
    step_group(
        c,
        "tracker_step",
        &[100_000, 1_000_000, 4_500_000],
        &tower(),
        None,
        false,
        false,
    );
}

fn tracker_step_with_smoothing(c: &mut Criterion) {
    step_group(
        c,
        "tracker_step_smoothing",
        &[100_000, 1_000_000],
        &tower(),
        None,
        false,
        true,
    );
}

fn tracker_step_with_heading(c: &mut Criterion) {
    step_group(
        c,
        "tracker_step_heading",
        &[1_000_000],
        &tower(),
        None,
        true,
        false,
    );
}

fn tracker_step_with_wifi(c: &mut Criterion) {
    let tower = tower();
    let (sim, topology) = &tower;
    let cells = CellMap::build(&sim.plan, topology, &Default::default()).expect("cells");
    let raster =
        Arc::new(CellRaster::on_plan(&RadioMap::empty(&cells), topology, 0.25).expect("raster"));
    // Every other cell inside: about half the particles outside at every step.
    let values = (0..raster.cells())
        .map(|c| if c % 2 == 0 { 0.0 } else { f32::NEG_INFINITY })
        .collect();
    let region = CellField::new(raster, values, 0.0);
    step_group(
        c,
        "tracker_step_wifi_containment",
        &[1_000_000],
        &tower,
        Some(&region),
        false,
        false,
    );
}

fn topology_walk(c: &mut Criterion) {
    let sim = simulate_tower(&TowerSimConfig::default()).expect("simulation");
    let topology = FloorTopology::build(&sim.plan, &TopologyConfig::default()).expect("topology");
    let mut rng = footslam::random::stream(1, 0, 0);
    let moves: Vec<(u32, [f32; 2], [f32; 2])> = (0..4096)
        .map(|_| {
            let (s, [x, y]) = topology.sample_uniform(&mut rng);
            let h: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let (x, y) = (x as f32, y as f32);
            let to = [x + 0.7 * h.cos() as f32, y + 0.7 * h.sin() as f32];
            (s, [x, y], to)
        })
        .collect();
    let mut i = 0;
    c.bench_function("floor_topology_walk_0.7m", |b| {
        b.iter(|| {
            let (s, from, to) = moves[i % moves.len()];
            i += 1;
            black_box(topology.walk(s, from, to))
        })
    });
}

criterion_group!(
    benches,
    tracker_step,
    tracker_step_with_smoothing,
    tracker_step_with_heading,
    tracker_step_with_wifi,
    topology_walk
);
criterion_main!(benches);
