//! Tests of the path-loss model.
use super::fit::monotone_shares;
use super::*;
use crate::map::radio_map::{CellRadio, RadioMapCell};
use geo::{MultiPolygon, Rect};

/// A 20 × 20 grid of 2 m cells; access points at (5, 5), (35, 30) and (12, 36) with
/// exponent 3, surveyed only in the grid's western half (x < 20), one scan per cell.
fn half_surveyed() -> RadioMap {
    let aps = [
        ("west", 5.0, 5.0),
        ("east", 35.0, 30.0),
        ("north", 12.0, 36.0),
    ];
    let mut cells = Vec::new();
    for i in 0..20 {
        for j in 0..20 {
            let (x, y) = (2.0 * f64::from(i) + 1.0, 2.0 * f64::from(j) + 1.0);
            let mut radio = CellRadio::default();
            if x < 20.0 {
                let readings: Vec<(&str, f64)> = aps
                    .iter()
                    .map(|&(b, ax, ay)| {
                        let d = (x - ax).hypot(y - ay).max(1.0);
                        (b, -35.0 - 30.0 * d.log10())
                    })
                    .filter(|&(_, r)| r > -90.0)
                    .collect();
                radio.add_scan(&WifiScan::from_readings(0.0, &readings));
            }
            let area = Rect::new((x - 1.0, y - 1.0), (x + 1.0, y + 1.0)).to_polygon();
            cells.push(RadioMapCell {
                id: format!("0-{i}-{j}"),
                level: 0,
                area: MultiPolygon(vec![area]),
                radio,
            });
        }
    }
    RadioMap {
        cells,
        ..Default::default()
    }
}

fn likeliest(map: &PathLossMap, scan: &WifiScan) -> (f64, f64) {
    let ll = map.log_likelihoods(scan).expect("modelled");
    let best = ll
        .iter()
        .enumerate()
        .filter_map(|(c, l)| l.map(|l| (c, l)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .expect("a cell")
        .0;
    (map.centres[best].0, map.centres[best].1)
}

#[test]
fn access_points_are_found_beyond_the_survey() {
    let map = PathLossMap::fit(&half_surveyed(), &PathLossConfig::default()).expect("fit");
    assert_eq!(map.access_points(), 3);
    let east = map.models[map.columns["east"]];
    // The eastern access point lies 15 m beyond the surveyed half: found within a cell or two.
    assert!((east.x - 35.0).hypot(east.y - 30.0) < 4.0, "{east:?}");
    assert!((east.slope + 30.0).abs() < 3.0, "{east:?}");
    let west = map.models[map.columns["west"]];
    assert!((west.x - 5.0).hypot(west.y - 5.0) < 2.0, "{west:?}");
}

#[test]
fn a_scan_where_nobody_surveyed_is_placed_there() {
    let map = PathLossMap::fit(&half_surveyed(), &PathLossConfig::default()).expect("fit");
    // A scan at (31, 27), in the unsurveyed half, near the eastern access point.
    let (x, y) = (31.0f64, 27.0f64);
    let rssi = |ax: f64, ay: f64| -35.0 - 30.0 * (x - ax).hypot(y - ay).log10();
    let scan =
        WifiScan::from_readings(0.0, &[("west", rssi(5.0, 5.0)), ("east", rssi(35.0, 30.0))]);
    let (px, py) = likeliest(&map, &scan);
    assert!((px - x).hypot(py - y) < 6.0, "placed at ({px}, {py})");
    // A scan of access points nobody modelled: no likelihood.
    assert!(
        map.log_likelihoods(&WifiScan::from_readings(0.0, &[("x", -50.0)]))
            .is_none()
    );
}

#[test]
fn a_device_reading_low_everywhere_is_placed_by_the_differences() {
    // A phone that reads 9 dB below the survey's at (13, 11): the absolute levels say
    // "farther from every access point", their differences say where.
    let (x, y) = (13.0f64, 11.0f64);
    let rssi = |ax: f64, ay: f64| -35.0 - 30.0 * (x - ax).hypot(y - ay).log10() - 9.0;
    let scan = WifiScan::from_readings(
        0.0,
        &[
            ("west", rssi(5.0, 5.0)),
            ("east", rssi(35.0, 30.0)),
            ("north", rssi(12.0, 36.0)),
        ],
    );
    let error = |offset: f64| {
        let config = PathLossConfig {
            device_offset_db: offset,
            ..PathLossConfig::default()
        };
        let map = PathLossMap::fit(&half_surveyed(), &config).expect("fit");
        let (px, py) = likeliest(&map, &scan);
        (px - x).hypot(py - y)
    };
    // Without eq. (5) the scan lands far out; an offset as likely as any (τ = 30 dB) is
    // read off the differences and the scan lands where it was taken; the default prior
    // (τ = 4 dB, a 9 dB offset being 2.25 τ) moves it part of the way.
    let (none, free) = (error(0.0), error(30.0));
    let default = error(PathLossConfig::default().device_offset_db);
    assert!(
        none > 5.0 && free < 2.0,
        "none {none} m, τ = 30 dB {free} m"
    );
    assert!(default <= none, "default {default} m, none {none} m");
}

#[test]
fn detection_shares_are_pooled_where_they_fall() {
    // Bins: empty, 1/10, 5/10, 3/10 (a violation, pooled with the one before: 8/20),
    // empty, 9/10.
    let heard = [0.0, 1.0, 5.0, 3.0, 0.0, 9.0];
    let scans = [0.0, 10.0, 10.0, 10.0, 0.0, 10.0];
    let shares = monotone_shares(&heard, &scans);
    let want = [0.1, 0.1, 0.4, 0.4, 0.4, 0.9];
    for (got, want) in shares.iter().zip(want) {
        assert!((got - want).abs() < 1e-12, "{shares:?}");
    }
    assert_eq!(monotone_shares(&[0.0; 3], &[0.0; 3]), vec![0.0; 3]);
}

#[test]
fn a_map_without_enough_readings_is_refused() {
    let mut map = half_surveyed();
    for cell in &mut map.cells[3..] {
        cell.radio = CellRadio::default();
    }
    let err = PathLossMap::fit(&map, &PathLossConfig::default()).unwrap_err();
    assert!(err.to_string().contains("cells or more"), "{err}");
}
