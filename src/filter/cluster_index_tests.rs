//! Tests of the grid-indexed mode merging and nearest-mode search: the same answers as
//! comparing every pair.

use super::*;
use rand::RngExt;

/// Random modes over several floors and headings, some at equal places.
fn random_modes(rng: &mut rand_pcg::Pcg64Mcg, n: usize, extent: f64) -> Vec<Mode> {
    let mut modes: Vec<Mode> = (0..n)
        .map(|_| Mode {
            x: rng.random_range(-extent..extent),
            y: rng.random_range(-extent..extent),
            z: 3.0 * f64::from(rng.random_range(0..3u8)),
            heading: rng.random_range(-3.0..3.0),
            density: rng.random_range(0.0..10.0),
        })
        .collect();
    let copy = modes[0];
    modes.push(copy); // a tie: the lower index must win
    modes
}

#[test]
fn the_mode_index_finds_what_comparing_every_mode_finds() {
    let mut rng = crate::random::stream(11, 0, 0);
    let config = ClusterConfig::default();
    for extent in [5.0, 60.0, 2000.0] {
        let modes = random_modes(&mut rng, 300, extent);
        let index = ModeIndex::new(&modes, config.radius);
        for _ in 0..2000 {
            let p = ClusterPoint {
                x: rng.random_range(-1.2 * extent..1.2 * extent) as f32,
                y: rng.random_range(-1.2 * extent..1.2 * extent) as f32,
                z: 3.0 * f32::from(rng.random_range(0..4u8)),
                level: 0,
                heading: rng.random_range(-3.0..3.0),
                weight: 1.0,
            };
            // Every mode compared, first minimum kept (the definition).
            let brute = modes
                .iter()
                .enumerate()
                .map(|(i, m)| {
                    let dz = (f64::from(p.z) - m.z).abs();
                    let dh = heading_gap(f64::from(p.heading), m.heading);
                    let mut penalty = if dz < config.max_dz { 0.0 } else { 1e6 * dz };
                    if dh > config.max_dheading {
                        penalty += 1e3 * dh;
                    }
                    let d = (f64::from(p.x) - m.x).hypot(f64::from(p.y) - m.y);
                    (i, d + penalty)
                })
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map(|(i, _)| i);
            assert_eq!(index.nearest(&p, &modes, &config), brute);
        }
    }
}

#[test]
fn merging_by_cells_keeps_what_comparing_every_pair_keeps() {
    let mut rng = crate::random::stream(12, 0, 0);
    let config = ClusterConfig::default();
    for extent in [10.0, 100.0] {
        let modes = random_modes(&mut rng, 500, extent);
        let merged = merge_modes(modes.clone(), &config);
        let mut sorted = modes;
        sorted.sort_by(|a, b| b.density.total_cmp(&a.density));
        let mut brute: Vec<Mode> = Vec::new();
        for m in sorted {
            if !brute.iter().any(|k| {
                (k.x - m.x).hypot(k.y - m.y) < config.radius
                    && (k.z - m.z).abs() < config.max_dz
                    && heading_gap(k.heading, m.heading) < config.max_dheading
            }) {
                brute.push(m);
            }
        }
        let key = |m: &Mode| (m.x.to_bits(), m.y.to_bits(), m.z.to_bits());
        assert_eq!(
            merged.iter().map(key).collect::<Vec<_>>(),
            brute.iter().map(key).collect::<Vec<_>>()
        );
    }
}

#[test]
fn a_cloud_over_a_kilometre_clusters_quickly() {
    // 10,000 points spread over 1 km² (a belief on a large open plan): every point its
    // own mode, which comparing every mode with every point took minutes over a walk.
    let mut rng = crate::random::stream(13, 0, 0);
    let points: Vec<ClusterPoint> = (0..10_000)
        .map(|_| ClusterPoint {
            x: rng.random_range(0.0..1000.0),
            y: rng.random_range(0.0..1000.0),
            z: 0.0,
            level: 0,
            heading: rng.random_range(-3.0..3.0),
            weight: 1.0,
        })
        .collect();
    let config = ClusterConfig {
        min_weight: 0.0,
        ..ClusterConfig::default()
    };
    let clusters = mean_shift(&points, &config);
    let total: usize = clusters.iter().map(|c| c.particles).sum();
    assert!(clusters.len() > 1000, "{}", clusters.len());
    assert_eq!(total, points.len(), "every point joins a cluster");
}
