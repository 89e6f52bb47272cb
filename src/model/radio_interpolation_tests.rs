use super::*;
use crate::map::{CellRadio, RadioMapCell};
use geo::Rect;

/// A corridor of 2 m cells at `xs`; the cells at `surveyed` hold two scans each of an access
/// point at x = 0 whose RSSI falls 1 dB a metre (−40 dBm at the wall), and of one at the far
/// end rising 1 dB a metre.
fn corridor(xs: &[f64], surveyed: &[usize]) -> RadioMap {
    let cells = xs
        .iter()
        .enumerate()
        .map(|(i, &x)| {
            let mut radio = CellRadio::default();
            if surveyed.contains(&i) {
                for d in [-0.5, 0.5] {
                    let readings = [("west", -40.0 - x + d), ("east", -90.0 + 0.5 * x - d)];
                    radio.add_scan(&WifiScan::from_readings(0.0, &readings));
                }
            }
            RadioMapCell {
                id: format!("0-{i}-0"),
                level: 0,
                area: Rect::new((x - 1.0, 0.0), (x + 1.0, 2.0))
                    .to_polygon()
                    .into(),
                radio,
            }
        })
        .collect();
    RadioMap {
        cells,
        ..Default::default()
    }
}

fn fixed() -> InterpolationConfig {
    InterpolationConfig {
        length_scale: Some(10.0),
        noise_ratio: Some(0.05),
        ..Default::default()
    }
}

#[test]
fn between_surveyed_cells_the_mean_lies_between_and_the_variance_grows_away_from_data() {
    // Cells every 2 m from 1 to 39 m; surveyed 1–9 m and 31–39 m.
    let xs: Vec<f64> = (0..20).map(|i| 1.0 + 2.0 * f64::from(i)).collect();
    let surveyed: Vec<usize> = (0..5).chain(15..20).collect();
    let map = corridor(&xs, &surveyed);
    let gp = RadioInterpolation::new(&map, -96.0, 1, &fixed()).expect("interpolation");
    let west = |c: usize| gp.predict(c, "west").expect("known access point");
    // At the surveyed cells the mean follows the data (−41 dBm at x = 1 m).
    assert!((west(0).0 + 41.0).abs() < 1.5, "{:?}", west(0));
    // Between the last surveyed cell of the west (x = 9 m, −49 dBm) and the first of the
    // east (x = 31 m, −71 dBm), the mean lies between the two.
    for c in 5..15 {
        let (m, _) = west(c);
        assert!((-71.5..=-48.5).contains(&m), "cell {c}: {m}");
    }
    // The variance grows away from the data: the gap's middle is the least certain.
    let share: Vec<f64> = (0..20).map(|c| gp.variance_share(c)).collect();
    assert!(share[5] < share[7] && share[7] < share[9], "{share:?}");
    assert!(share[0] < share[9] && west(0).1 < west(9).1);
    assert!(gp.is_known(0) && gp.predict(0, "nobody").is_none());
}

#[test]
fn far_from_any_survey_a_cell_gets_the_prior_and_is_unknown() {
    let xs = [1.0, 3.0, 5.0, 7.0, 400.0];
    let map = corridor(&xs, &[0, 1, 2, 3]);
    let gp = RadioInterpolation::new(&map, -96.0, 1, &fixed()).expect("interpolation");
    let (m, v) = gp.predict(4, "west").expect("known access point");
    // The prior: the mean of the survey's values, and all of its variance.
    let prior = (-41.0 - 43.0 - 45.0 - 47.0) / 4.0;
    assert!((m - prior).abs() < 1e-3, "{m}");
    assert!(gp.variance_share(4) > 0.999 && !gp.is_known(4));
    assert!(v > gp.predict(0, "west").expect("known").1);
    // An unknown cell has no likelihood; known ones do, highest where the scan was taken.
    let scan = WifiScan::from_readings(0.0, &[("west", -45.0), ("east", -87.5)]);
    let ll = gp.log_likelihoods(&scan);
    assert!(ll[4].is_none());
    let best = (0..4)
        .max_by(|&a, &b| ll[a].expect("known").total_cmp(&ll[b].expect("known")))
        .expect("cells");
    assert_eq!(best, 2);
}

#[test]
fn the_kernel_is_fitted_on_the_survey() {
    // A long corridor surveyed every 2 m: the variogram rises with distance, so a finite
    // length scale comes out; the noise is the scans' spread within cells (±0.5 dB), small
    // against the field's.
    let xs: Vec<f64> = (0..40).map(|i| 1.0 + 2.0 * f64::from(i)).collect();
    let all: Vec<usize> = (0..40).collect();
    let map = corridor(&xs, &all);
    let gp = RadioInterpolation::new(&map, -96.0, 1, &InterpolationConfig::default())
        .expect("interpolation");
    let fit = gp.fit();
    assert!(fit.pairs > 0, "{fit:?}");
    assert!(
        fit.length_scale > 3.0 && fit.length_scale < 600.0,
        "{fit:?}"
    );
    assert!(
        fit.noise_ratio < 0.01 + 1e-12 && fit.noise_within_cells,
        "{fit:?}"
    );
    // Given values win over the fit.
    let gp = RadioInterpolation::new(&map, -96.0, 1, &fixed()).expect("interpolation");
    assert_eq!((gp.fit().length_scale, gp.fit().noise_ratio), (10.0, 0.05));
}

#[test]
fn configs_are_validated_and_an_empty_map_refused() {
    let bad = InterpolationConfig {
        max_share: 0.0,
        ..Default::default()
    };
    assert!(bad.validate().is_err());
    let bad = InterpolationConfig {
        length_scale: Some(-1.0),
        ..Default::default()
    };
    assert!(bad.validate().is_err());
    assert!(InterpolationConfig::default().validate().is_ok());
    let empty = corridor(&[1.0, 3.0], &[]);
    assert!(RadioInterpolation::new(&empty, -96.0, 1, &fixed()).is_err());
}

#[test]
fn log_ratios_are_the_log_likelihoods_less_one_constant_and_held_out_cells_predict_themselves() {
    let xs: Vec<f64> = (0..20).map(|i| 1.0 + 2.0 * f64::from(i)).collect();
    let map = corridor(&xs, &(0..20).step_by(2).collect::<Vec<_>>());
    let gp = RadioInterpolation::new(&map, -96.0, 1, &fixed()).expect("interpolation");
    let scan = WifiScan::from_readings(0.0, &[("west", -52.0), ("east", -84.0)]);
    let ll = gp.log_likelihoods(&scan);
    let lr = gp.log_ratios(&gp.readings(&scan));
    let offsets: Vec<f64> = ll
        .iter()
        .zip(&lr)
        .filter_map(|(a, b)| Some(a.as_ref()? - b.as_ref()?))
        .collect();
    assert_eq!(offsets.len(), 20);
    assert!(
        offsets.iter().all(|o| (o - offsets[0]).abs() < 1e-6),
        "{offsets:?}"
    );
    // Each surveyed cell, left out, is still predicted from its neighbours better than by
    // the prior; its fingerprint as a scan holds both access points.
    let held = gp.held_out_scans();
    assert_eq!(held.len(), 10);
    for h in &held[1..9] {
        assert_eq!((h.scans, h.readings.len()), (2, 2));
        let own = h.own_log_ratio.expect("predicted by its neighbours");
        assert!(own > 0.0, "cell {}: {own}", h.cell);
    }
}
