//! The hexagon transition map's hot paths: counting a crossing in a private map and in a
//! map shared with another particle (copy on write), and walking a step through the grid.

use criterion::{Criterion, criterion_group, criterion_main};
use footslam::geometry::Hex;
use footslam::geometry::HexGrid;
use footslam::map::HexTransitionMap;
use std::hint::black_box;

#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn corridor_map() -> HexTransitionMap {
    let mut m = HexTransitionMap::new();
    for q in -40..40 {
        for r in [-1, 0, 1] {
            m.record_crossing(Hex::new(q, r), 0);
        }
    }
    m
}

fn crossings(c: &mut Criterion) {
    let mut g = c.benchmark_group("hex_map");
    let mut private = corridor_map();
    let mut q = 0;
    g.bench_function("record_crossing_private", |b| {
        b.iter(|| {
            q = (q + 7) % 80 - 40;
            black_box(private.record_crossing(Hex::new(q, 0), 0))
        })
    });
    let shared = corridor_map();
    g.bench_function("record_crossing_shared_copy_on_write", |b| {
        b.iter_batched(
            || shared.clone(),
            |mut m| black_box(m.record_crossing(Hex::new(3, 0), 1)),
            criterion::BatchSize::SmallInput,
        )
    });
    g.bench_function("clone_map", |b| b.iter(|| black_box(shared.clone())));
    let grid = HexGrid::new(0.5);
    let mut k = 0.0f64;
    g.bench_function("for_each_crossing_0.7m_step", |b| {
        b.iter(|| {
            k += 0.37;
            let (x, y) = (k.sin() * 10.0, k.cos() * 10.0);
            let mut n = 0;
            grid.for_each_crossing((x, y), (x + 0.7 * k.cos(), y + 0.7 * k.sin()), |_| n += 1);
            black_box(n)
        })
    });
    g.finish();
}

/// A learned map of a 100 m × 60 m floor walked everywhere but a 60 m × 20 m atrium
/// (about 7,400 hexagons of 0.5 m): `walkable_plan` (union, grow, fill, simplify) and its
/// 5 cm occupancy grid — the work of `footslam plan` on a large building.
fn plan(c: &mut Criterion) {
    let grid = HexGrid::new(0.5);
    let mut cells = Vec::new();
    for q in -150..150 {
        for r in -150..150 {
            let hex = Hex::new(q, r);
            let (x, y) = grid.center(hex);
            let floor = (0.0..100.0).contains(&x) && (0.0..60.0).contains(&y);
            let atrium = (20.0..80.0).contains(&x) && (20.0..40.0).contains(&y);
            if floor && !atrium {
                cells.push(footslam::map::HexCell {
                    hex,
                    counts: [1, 1, 0, 0, 0, 0],
                    level: 0,
                });
            }
        }
    }
    let map = footslam::map::HexMapSnapshot {
        radius: 0.5,
        alpha: 0.8,
        cells,
        levels: Vec::new(),
    };
    let config = footslam::map::PlanConfig::default();
    let mut g = c.benchmark_group("plan");
    g.sample_size(10);
    g.bench_function("walkable_plan_7k_hexagons", |b| {
        b.iter(|| black_box(footslam::map::walkable_plan(&map, &config).expect("plan")))
    });
    let learned = footslam::map::walkable_plan(&map, &config).expect("plan");
    let grid_config = footslam::map::OccupancyConfig::default();
    g.bench_function("occupancy_grid_100x60m_5cm", |b| {
        b.iter(|| {
            black_box(
                footslam::map::OccupancyGrid::from_plan(&learned.plan, 0, &grid_config)
                    .expect("grid"),
            )
        })
    });
    g.finish();
}

criterion_group!(benches, crossings, plan);
criterion_main!(benches);
