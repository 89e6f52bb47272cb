//! Tests of mean shift on hand-made beliefs: blobs, floors, stragglers, corridors and
//! opposite headings.

use super::*;
use rand::RngExt;
use rand_distr::StandardNormal;

fn blob(
    rng: &mut rand_pcg::Pcg64Mcg,
    n: usize,
    c: (f32, f32, f32),
    level: i32,
    spread: f32,
) -> Vec<ClusterPoint> {
    (0..n)
        .map(|_| ClusterPoint {
            x: c.0 + spread * rng.sample::<f32, _>(StandardNormal),
            y: c.1 + spread * rng.sample::<f32, _>(StandardNormal),
            z: c.2,
            level,
            heading: 0.3 + 0.05 * rng.sample::<f32, _>(StandardNormal),
            weight: 1.0,
        })
        .collect()
}

#[test]
fn one_blob_is_one_cluster_at_its_mean() {
    let mut rng = crate::random::stream(1, 0, 0);
    let points = blob(&mut rng, 2000, (10.0, -4.0, 3.0), 1, 1.0);
    let clusters = mean_shift(&points, &ClusterConfig::default());
    assert_eq!(clusters.len(), 1, "{clusters:?}");
    let c = clusters[0];
    assert!((c.x - 10.0).abs() < 0.1 && (c.y + 4.0).abs() < 0.1, "{c:?}");
    assert_eq!((c.level, c.particles), (1, 2000));
    assert!((c.weight - 1.0).abs() < 1e-9 && (c.z - 3.0).abs() < 1e-6);
    // Two axes of 1 m spread: an RMS radius of √2 m.
    assert!((c.spread - 2f64.sqrt()).abs() < 0.1, "{c:?}");
}

#[test]
fn distant_blobs_and_floors_are_separate_clusters() {
    let mut rng = crate::random::stream(2, 0, 0);
    let mut points = blob(&mut rng, 1500, (0.0, 0.0, 0.0), 0, 1.0);
    points.extend(blob(&mut rng, 500, (30.0, 0.0, 0.0), 0, 1.0));
    // Straight above the first blob, one floor up.
    points.extend(blob(&mut rng, 1000, (0.0, 0.0, 3.0), 1, 1.0));
    let clusters = mean_shift(&points, &ClusterConfig::default());
    assert_eq!(clusters.len(), 3, "{clusters:?}");
    assert!((clusters[0].weight - 0.5).abs() < 1e-9);
    assert_eq!(clusters[0].level, 0);
    assert_eq!(clusters[1].level, 1);
    assert!((clusters[2].x - 30.0).abs() < 0.2);
}

#[test]
fn stragglers_do_not_count_and_weights_matter() {
    let mut rng = crate::random::stream(3, 0, 0);
    let mut points = blob(&mut rng, 1000, (0.0, 0.0, 0.0), 0, 1.0);
    let mut far = blob(&mut rng, 1, (50.0, 50.0, 0.0), 0, 0.5);
    points.append(&mut far);
    let clusters = mean_shift(&points, &ClusterConfig::default());
    assert_eq!(clusters.len(), 1);
    // Reweighting the stragglers makes them the main cluster.
    for p in points.iter_mut().skip(1000) {
        p.weight = 2000.0;
    }
    let clusters = mean_shift(&points, &ClusterConfig::default());
    assert_eq!(clusters.len(), 2);
    assert!((clusters[0].x - 50.0).abs() < 1.0);
    assert!(mean_shift(&[], &ClusterConfig::default()).is_empty());
}

#[test]
fn elongated_corridor_cloud_stays_one_cluster() {
    // A 12 m strip along a corridor: within reach of one 7 m kernel's shifts.
    let points: Vec<ClusterPoint> = (0..1200)
        .map(|i| ClusterPoint {
            x: (i % 120) as f32 * 0.1,
            y: (i / 120) as f32 * 0.2,
            z: 0.0,
            level: 0,
            heading: std::f32::consts::PI * if i % 2 == 0 { 1.0 } else { -1.0 },
            weight: 1.0,
        })
        .collect();
    // Headings of ±π are one direction.
    assert_eq!(mean_shift(&points, &ClusterConfig::default()).len(), 1);
}

#[test]
fn groups_walking_towards_each_other_are_two_hypotheses() {
    // Two groups 6 m apart along a corridor (within one 7 m kernel), heading east and
    // west: a building's 180° symmetry, two poses, not one.
    let mut rng = crate::random::stream(4, 0, 0);
    let mut points = blob(&mut rng, 1000, (0.0, 0.0, 0.0), 0, 0.5);
    let mut west = blob(&mut rng, 1000, (6.0, 0.0, 0.0), 0, 0.5);
    west.iter_mut()
        .for_each(|p| p.heading -= std::f32::consts::PI);
    points.extend(west);
    let clusters = mean_shift(&points, &ClusterConfig::default());
    assert_eq!(clusters.len(), 2, "{clusters:?}");
    let mut xs: Vec<f64> = clusters.iter().map(|c| c.x).collect();
    xs.sort_by(f64::total_cmp);
    assert!(xs[0].abs() < 0.2 && (xs[1] - 6.0).abs() < 0.2, "{xs:?}");
    assert!(clusters.iter().all(|c| c.particles == 1000));
    // Ignoring headings, they are one place.
    let config = ClusterConfig {
        max_dheading: std::f64::consts::PI,
        ..Default::default()
    };
    assert_eq!(mean_shift(&points, &config).len(), 1);
}

#[test]
fn remembered_paths_end_where_each_seed_shifted_alone_ends() {
    let config = ClusterConfig::default();
    let mut rng = crate::random::stream(9, 0, 0);
    let mut remembered = 0;
    for spread in [0.3, 1.0, 3.0, 8.0] {
        let mut points = blob(&mut rng, 800, (0.0, 0.0, 0.0), 0, spread);
        points.extend(blob(&mut rng, 300, (9.0, 4.0, 0.0), 0, spread));
        let unit: Vec<Unit> = points.iter().map(Unit::of).collect();
        let mut grid = Grid::default();
        grid.build(&points, &unit, config.radius);
        let seeds = seeds(
            &points,
            &unit,
            config.radius / 2.0,
            config.max_dheading,
            &mut Vec::new(),
            &mut Vec::new(),
        );
        let mut shared = Shifts::default();
        for s in seeds {
            let alone = Shifts::default().shift(s, &grid, &config);
            let known = shared.known.len();
            let with_paths = shared.shift(s, &grid, &config);
            remembered += usize::from(shared.known.len() < known + 3);
            assert_eq!(with_paths.key(), alone.key(), "spread {spread}");
            assert_eq!(with_paths.density.to_bits(), alone.density.to_bits());
        }
    }
    // The seeds' paths do meet: most seeds end on a remembered path.
    assert!(remembered > 10, "{remembered}");
}
