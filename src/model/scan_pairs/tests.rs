use super::*;

fn scan(t: f64, readings: &[(&str, f64)]) -> WifiScan {
    WifiScan::from_readings(t, readings)
}

/// RSSI of access point `a` at `(x, y)`: log-distance path loss from its place.
fn field(a: usize, x: f64, y: f64) -> f64 {
    let (ax, ay) = [(0.0, 5.0), (20.0, -5.0), (40.0, 5.0), (60.0, -5.0)][a];
    let d = (x - ax).hypot(y - ay).max(1.0);
    -35.0 - 25.0 * d.log10()
}

/// A walk east along y = 0 and back (1 m steps, 1 s apart), a scan every 2 s with small
/// deterministic noise.
fn out_and_back() -> (Vec<Step>, Vec<WifiScan>, Vec<(f64, f64)>) {
    let mut steps = Vec::new();
    let mut truth = vec![(0.0, 0.0)];
    let (mut x, mut t) = (0.0, 0.0);
    for i in 0..120 {
        let back = i >= 60;
        t += 1.0;
        x += if back { -1.0 } else { 1.0 };
        let dheading = if i == 60 { std::f64::consts::PI } else { 0.0 };
        steps.push(Step {
            t,
            length: 1.0,
            dheading,
            dz: 0.0,
            heading: None,
        });
        truth.push((x, 0.0));
    }
    let names = ["a", "b", "c", "d"];
    let scans = (1..60)
        .map(|s| {
            let t = 2.0 * f64::from(s);
            let (x, y) = truth[t as usize];
            let noise = |a: usize| 3.0 * ((s as usize * 7 + a * 13) % 5) as f64 / 4.0 - 1.5;
            let readings: Vec<(&str, f64)> = (0..4)
                .map(|a| (names[a], field(a, x, y) + noise(a)))
                .collect();
            scan(t, &readings)
        })
        .collect();
    (steps, scans, truth)
}

#[test]
fn dissimilarity_counts_missing_access_points_at_the_floor() {
    let mut ids = FxHashMap::default();
    let a = CompactScan::new(&scan(0.0, &[("x", -50.0), ("y", -60.0)]), &mut ids, -100.0);
    let b = CompactScan::new(&scan(1.0, &[("x", -54.0)]), &mut ids, -100.0);
    assert_eq!(dissimilarity(&a, &a, -100.0), Some(0.0));
    // x differs by 4 dB, y is missing from b: 40 dB above the floor.
    let d = dissimilarity(&a, &b, -100.0).unwrap();
    assert!((d - ((16.0 + 1600.0) / 2.0_f64).sqrt()).abs() < 1e-9);
    let empty = CompactScan::new(&scan(2.0, &[]), &mut ids, -100.0);
    assert_eq!(dissimilarity(&empty, &empty, -100.0), None);
}

#[test]
fn calibration_finds_dissimilarity_growing_with_distance() {
    let (steps, scans, _) = out_and_back();
    let evidence = ScanEvidence::new(&scans, &steps, &ScanPairConfig::default()).unwrap();
    let l = &evidence.likelihood;
    assert!(l.mu.len() >= 3, "{l:?}");
    assert!(l.mu.windows(2).all(|w| w[1] >= w[0]), "{l:?}");
    assert!(l.mu.last().unwrap() > &(l.mu[0] + 5.0), "{l:?}");
    // A similar pair is more probable near than far; a dissimilar one far than near.
    assert!(l.log_density(l.mu[0], 0.5) > l.log_density(l.mu[0], 20.0));
    let far = *l.mu.last().unwrap();
    assert!(l.log_density(far, 20.0) > l.log_density(far, 0.5));
}

#[test]
fn a_scan_favours_particles_back_where_it_was_heard() {
    let (steps, scans, truth) = out_and_back();
    // Every pair in full (γ = 0), to see the pair term itself.
    let config = ScanPairConfig {
        pair_tempering: 0.0,
        ..Default::default()
    };
    let evidence = ScanEvidence::new(&scans, &steps, &config).unwrap();
    assert!(evidence.pairs() > 0);
    // The last scan (t = 118, x = 2 on the way back) against the true places of the
    // earlier scans, and against places shifted 6 m north (a particle that drifted).
    let k = scans.len() - 1;
    let place = |j: usize| {
        let (x, y) = truth[scans[j].t as usize];
        (x as f32, y as f32)
    };
    let at = place(k);
    let right = evidence.log_factor(k, at, place, |_| true);
    let off = evidence.log_factor(k, (at.0, at.1 + 6.0), place, |_| true);
    assert!(right > off + 3.0, "right {right}, off {off}");
    // Averaged (the default γ = 1), the same ordering, within one pair's reach.
    let averaged = ScanEvidence::new(&scans, &steps, &ScanPairConfig::default()).unwrap();
    let right = averaged.log_factor(k, at, place, |_| true);
    let off = averaged.log_factor(k, (at.0, at.1 + 6.0), place, |_| true);
    assert!(right > off, "right {right}, off {off}");
    // Pairs on another floor say nothing.
    assert_eq!(evidence.log_factor(k, at, place, |_| false), 0.0);
}

#[test]
fn walks_too_short_to_calibrate_are_refused_with_a_reason() {
    let (steps, scans, _) = out_and_back();
    let config = ScanPairConfig::default();
    assert_eq!(
        ScanEvidence::new(&scans[..1], &steps, &config).unwrap_err(),
        ScanPairsUnused::TooFewScans(1)
    );
    assert!(matches!(
        ScanEvidence::new(&scans[..4], &steps, &config),
        Err(ScanPairsUnused::TooFewPairs(_))
    ));
    let off = ScanPairConfig {
        enabled: false,
        ..config
    };
    assert_eq!(
        ScanEvidence::new(&scans, &steps, &off).unwrap_err(),
        ScanPairsUnused::Disabled
    );
}
