//! The region threshold `ε` of a radio map that carries no calibration (another tool's map, a
//! site survey at known positions), derived from the map itself.
//!
//! `footslam survey` calibrates `ε` on leave-one-visit-out distances of its own walks
//! ([`super::wifi_distance::leave_one_out_ndist`]; Woodman & Harle 2009, sec. 5.3 chooses `ε`
//! from the distribution of a walker's distance to its own cell, Fig. 11). A map alone has no
//! walks to hold out, but each cell's histograms say how a scan taken there spreads about the
//! cell's fingerprint: access point `a`, heard in `n_a` of the cell's `S` scans with mean `μ_a`
//! and spread `σ_a`, is heard by a new scan there with probability `n_a / S`, at
//! `μ_a + e`, `e ~ N(0, σ_a² (1 + 1/n_a))` (the new reading's spread plus the error of a mean
//! of `n_a` readings, `σ_a` the unbiased estimate), and missed otherwise (the scan then holds
//! the missing-reading fill). Scans drawn from that model in every cell with at least two
//! scans give the distance distribution, and `ε` is its `1 − miss` quantile, exactly as a
//! calibration on walks ([`super::wifi_distance::calibrate_epsilon`]). Access points heard
//! once in a cell take the map's pooled spread.
//!
//! The draws come from one fixed stream, so the threshold is a property of the map alone.
//! It does not see access points that a later scan hears but the cell's scans never did, so
//! it is somewhat tighter than a calibration on walks.

use super::wifi_distance::{Normalisation, calibrate_epsilon};
use crate::map::RadioMap;
use rand::{RngExt, SeedableRng};
use rand_distr::StandardNormal;
use rand_pcg::Pcg64Mcg;

/// Scans drawn per cell.
const DRAWS_PER_CELL: usize = 64;
/// Seed of the fixed stream.
const SEED: u64 = 0xE951_10A0;
/// Spread assumed when the map gives none at all (no access point heard twice in a cell), dB.
const FALLBACK_SPREAD: f64 = 4.0;

/// `ε` for `norm` derived from `map`'s histograms (cells with at least `min_scans` and at
/// least two scans), missing readings at `missing_rssi`, for a share `miss` of the walker's
/// scans outside their own cell's region; `None` when no cell has two scans.
#[must_use]
pub fn derive_epsilon(
    map: &RadioMap,
    norm: Normalisation,
    missing_rssi: f64,
    miss: f64,
    min_scans: u32,
) -> Option<f64> {
    let pooled = pooled_spread(map).unwrap_or(FALLBACK_SPREAD);
    let mut rng = Pcg64Mcg::seed_from_u64(SEED);
    let mut distances = Vec::new();
    for cell in &map.cells {
        let radio = &cell.radio;
        if radio.scans < min_scans.max(2) {
            continue;
        }
        // (heard with probability, mean, spread of a new reading about the mean)
        let aps: Vec<(f64, f64, f64)> = radio
            .aps
            .values()
            .filter_map(|s| {
                let mean = s.mean()?.max(missing_rssi);
                let n = f64::from(s.n);
                let sigma = match s.std() {
                    Some(pop) if s.n >= 2 => pop * (n / (n - 1.0)).sqrt(),
                    _ => pooled,
                };
                let p = (n / f64::from(radio.scans)).min(1.0);
                Some((p, mean, sigma * (1.0 + 1.0 / n).sqrt()))
            })
            .collect();
        if aps.is_empty() {
            continue;
        }
        let divisor = norm.divisor(aps.len());
        for _ in 0..DRAWS_PER_CELL {
            let squared: f64 = aps
                .iter()
                .map(|&(p, mean, sigma)| {
                    let reading = if rng.random::<f64>() < p {
                        (mean + sigma * rng.sample::<f64, _>(StandardNormal)).max(missing_rssi)
                    } else {
                        missing_rssi
                    };
                    (reading - mean).powi(2)
                })
                .sum();
            distances.push(squared.sqrt() / divisor);
        }
    }
    calibrate_epsilon(&distances, miss)
}

/// The map's pooled spread of readings about their cell's mean, dB (over access points heard
/// at least twice in a cell); `None` without any.
fn pooled_spread(map: &RadioMap) -> Option<f64> {
    let (mut squares, mut dof) = (0.0, 0.0);
    for s in map.cells.iter().flat_map(|c| c.radio.aps.values()) {
        if let (Some(std), true) = (s.std(), s.n >= 2) {
            squares += std * std * f64::from(s.n);
            dof += f64::from(s.n - 1);
        }
    }
    (dof > 0.0).then(|| (squares / dof).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::{ApStats, CellRadio, RadioMapCell};
    use std::collections::BTreeMap;

    fn cell(aps: &[(&str, &[f64])], scans: u32) -> RadioMapCell {
        let mut radio = CellRadio {
            scans,
            aps: BTreeMap::new(),
        };
        for (bssid, readings) in aps {
            let mut s = ApStats::default();
            for &r in *readings {
                s.add(r);
            }
            radio.aps.insert((*bssid).to_string(), s);
        }
        RadioMapCell {
            id: "c".into(),
            level: 0,
            area: geo::MultiPolygon::new(Vec::new()),
            radio,
        }
    }

    #[test]
    fn wider_histograms_and_missed_readings_give_a_larger_threshold() {
        let map = |cells: Vec<RadioMapCell>| RadioMap {
            cells,
            epsilon: None,
            epsilon_sqrt: None,
        };
        let tight = map(vec![cell(
            &[
                ("a", &[-60.0, -61.0, -60.0, -59.0]),
                ("b", &[-70.0, -71.0, -70.0, -69.0]),
            ],
            4,
        )]);
        let wide = map(vec![cell(
            &[
                ("a", &[-55.0, -65.0, -60.0, -58.0]),
                ("b", &[-75.0, -65.0, -70.0, -72.0]),
            ],
            4,
        )]);
        let sporadic = map(vec![cell(
            &[("a", &[-60.0, -61.0, -60.0, -59.0]), ("b", &[-70.0, -71.0])],
            4,
        )]);
        let e = |m: &RadioMap| {
            derive_epsilon(m, Normalisation::Sqrt, -96.0, 0.001, 1).expect("derivable")
        };
        let (t, w, s) = (e(&tight), e(&wide), e(&sporadic));
        assert!(t > 0.5 && t < 5.0, "tight {t}");
        assert!(w > 2.0 * t, "wide {w} vs tight {t}");
        // A reading missed half the time is 26 dB from its mean when missed.
        assert!(s > 15.0, "sporadic {s}");
        // Deterministic: a property of the map.
        assert_eq!(t, e(&tight));
        // The paper's distance divides by k instead of √k.
        let p = derive_epsilon(&tight, Normalisation::Paper, -96.0, 0.001, 1).expect("paper");
        assert!((p * 2f64.sqrt() - t).abs() < 0.2 * t, "{p} vs {t}");
        // One scan per cell says nothing about the spread.
        let single = map(vec![cell(&[("a", &[-60.0])], 1)]);
        assert_eq!(
            derive_epsilon(&single, Normalisation::Sqrt, -96.0, 0.001, 1),
            None
        );
    }
}
