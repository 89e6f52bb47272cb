//! FootSLAM filter throughput: how time grows with particles and with walk length, and the
//! headline size (100,000 particles over a 700-step walk).
//!
//! `cargo bench --bench footslam` (the headline group alone: `-- headline`; the answer's
//! cost, one path or the whole-walk mean: `-- answer`; the magnetic field's cost per step:
//! `-- signals`).
//! Memory is measured by `examples/scaling.rs` (criterion measures time only).

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use footslam::filter::{Anchors, FootSlam, FootSlamConfig};
use footslam::model::FieldEvidence;
use footslam::sensor::{Step, StepTrace, TruePath, TruePose};
use footslam::sim::magnetic::{FieldSimConfig, MagneticWorld};
use footslam::sim::office_walk_steps;
use std::hint::black_box;
use std::sync::Arc;

#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn run(particles: usize, steps: &[Step]) -> usize {
    let mut f = FootSlam::new(FootSlamConfig {
        particles,
        seed: 1,
        ..Default::default()
    })
    .expect("config");
    for s in steps {
        f.update(s);
    }
    f.estimate().map.cells.len()
}

fn particles(c: &mut Criterion) {
    let steps = office_walk_steps(200, 1).expect("walk");
    let mut g = c.benchmark_group("particles");
    g.sample_size(10);
    for n in [1_000usize, 10_000, 30_000, 100_000] {
        g.throughput(Throughput::Elements((n * steps.len()) as u64));
        g.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, &n| {
            b.iter(|| black_box(run(n, &steps)))
        });
    }
    g.finish();
}

fn walk_length(c: &mut Criterion) {
    let all = office_walk_steps(700, 1).expect("walk");
    let mut g = c.benchmark_group("walk_length");
    g.sample_size(10);
    let n = 10_000;
    for len in [100usize, 300, 700] {
        g.throughput(Throughput::Elements((n * len) as u64));
        g.bench_with_input(BenchmarkId::from_parameter(len), &len, |b, &len| {
            b.iter(|| black_box(run(n, &all[..len])))
        });
    }
    g.finish();
}

fn headline(c: &mut Criterion) {
    let steps = office_walk_steps(700, 1).expect("walk");
    let mut g = c.benchmark_group("headline");
    g.sample_size(10);
    g.measurement_time(std::time::Duration::from_secs(300));
    let n = 100_000;
    g.throughput(Throughput::Elements((n * steps.len()) as u64));
    g.bench_function("100000x700", |b| b.iter(|| black_box(run(n, &steps))));
    g.finish();
}

/// The answer after the walk: the most probable particle's path replayed alone
/// (`smoothing.draws = 0`) against the whole-walk answer (256 final paths replayed and
/// averaged), 10,000 particles after 700 steps.
fn answer(c: &mut Criterion) {
    let steps = office_walk_steps(700, 1).expect("walk");
    let mut g = c.benchmark_group("answer");
    g.sample_size(10);
    for draws in [0usize, 256] {
        let mut config = FootSlamConfig {
            particles: 10_000,
            seed: 1,
            ..Default::default()
        };
        config.smoothing.draws = draws;
        let mut f = FootSlam::new(config).expect("config");
        for s in &steps {
            f.update(s);
        }
        g.bench_with_input(BenchmarkId::new("draws", draws), &draws, |b, _| {
            b.iter(|| black_box(f.estimate().path.len()))
        });
    }
    g.finish();
}

/// The steps alone against the steps with each one's magnetic field reading (a simulated
/// field along the dead-reckoned walk), 10,000 particles over 700 steps.
fn signals(c: &mut Criterion) {
    let steps = office_walk_steps(700, 1).expect("walk");
    let trace = StepTrace::new(steps.clone()).expect("valid");
    let poses = steps
        .iter()
        .zip(trace.dead_reckon(Default::default()))
        .map(|(s, p)| TruePose {
            t: s.t,
            x: p.x,
            y: p.y,
            z: 0.0,
            level: 0,
            heading: p.heading,
        })
        .collect();
    let truth = TruePath { poses };
    let world = MagneticWorld::around(&truth, FieldSimConfig::default(), 1);
    let config = FootSlamConfig {
        particles: 10_000,
        seed: 1,
        ..Default::default()
    };
    let field = Arc::new(FieldEvidence::new(
        &config.field,
        &steps,
        &world.readings_along(&truth, 2).expect("readings"),
    ));
    assert!(field.active(), "the simulated field tells places apart");
    let mut g = c.benchmark_group("signals");
    g.sample_size(10);
    g.throughput(Throughput::Elements(
        (config.particles * steps.len()) as u64,
    ));
    for (name, evidence) in [("steps", None), ("field", Some(field))] {
        g.bench_function(name, |b| {
            b.iter(|| {
                let anchors = Anchors {
                    field: evidence.clone(),
                    ..Default::default()
                };
                let mut f = FootSlam::with_anchors(config.clone(), anchors).expect("config");
                for s in &steps {
                    f.update(s);
                }
                black_box(f.field_steps())
            })
        });
    }
    g.finish();
}

criterion_group!(benches, particles, walk_length, headline, answer, signals);
criterion_main!(benches);
