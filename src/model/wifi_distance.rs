//! The normalised RSSI distance between a scan and a radio-map cell (Woodman & Harle 2009,
//! sec. 5.1, eqs. 2–11), the basis of the prior region `R_prior` (eq. 2) and the containment
//! regions `R_t` (eq. 12).
//!
//! A cell's fingerprint `c_i` is the mean RSSI of every access point it heard. The distance is
//! Euclidean over the access points of the map, missing readings in both the scan and the
//! cell filled with the weakest measurable RSSI, and divided by a function of the number `k`
//! of access points visible from the cell, so that a strong access point missing from the
//! scan (body shadowing) costs less than one missing from the cell (eqs. 6–11). Access points
//! the map never heard carry no information about place and are left out.
//!
//! [`Normalisation`] chooses the divisor: the paper's `k` (eqs. 8 and 11), or `√k`. With
//! independent errors of spread `σ` on each of the `k` readings, the Euclidean distance of a
//! scan to its own cell grows as `σ·√k`, so the paper's `ndist` is about `σ/√k`: one
//! threshold `ε` is then tight for cells that hear few access points and loose for cells
//! that hear many, and to miss few walkers in the former it admits many wrong cells of the
//! latter. Divided by `√k` the distance to the walker's own cell is about `σ` wherever the
//! cell is, so one `ε` misses equally often everywhere and the regions are smaller for the
//! same miss rate (on the simulated building, half the area at a 0.1 % miss rate).

use crate::map::{CellRadio, RadioMap};
use crate::sensor::WifiScan;
use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

/// What the Euclidean scan-to-cell distance is divided by.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Normalisation {
    /// The number of access points visible from the cell, `k` (the paper's eqs. 8 and 11).
    Paper,
    /// Its square root, `√k`: a distance whose spread to the walker's own cell does not
    /// depend on how many access points the cell hears.
    Sqrt,
}

impl Normalisation {
    /// Both, the paper's first.
    pub const ALL: [Normalisation; 2] = [Normalisation::Paper, Normalisation::Sqrt];

    /// The divisor for a cell that hears `visible` access points (at least one).
    #[must_use]
    pub fn divisor(self, visible: usize) -> f64 {
        let k = visible.max(1) as f64;
        match self {
            Normalisation::Paper => k,
            Normalisation::Sqrt => k.sqrt(),
        }
    }

    /// `map`'s region threshold calibrated for this distance, if any.
    #[must_use]
    pub fn epsilon_of(self, map: &RadioMap) -> Option<f64> {
        match self {
            Normalisation::Paper => map.epsilon,
            Normalisation::Sqrt => map.epsilon_sqrt,
        }
    }

    /// The same, to set it.
    pub fn epsilon_of_mut(self, map: &mut RadioMap) -> &mut Option<f64> {
        match self {
            Normalisation::Paper => &mut map.epsilon,
            Normalisation::Sqrt => &mut map.epsilon_sqrt,
        }
    }

    /// Its name in configs and maps: `paper` or `sqrt`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Normalisation::Paper => "paper",
            Normalisation::Sqrt => "sqrt",
        }
    }
}

/// Mean-RSSI fingerprints of a radio map's cells.
#[derive(Debug, Clone, PartialEq)]
pub struct Fingerprints {
    /// Column of each access point of the map.
    columns: FxHashMap<String, usize>,
    /// Per cell: the mean RSSI per access point (`missing` where not heard) and the number
    /// of access points heard; `None` for cells without scans (nothing known).
    cells: Vec<Option<(Vec<f64>, usize)>>,
    /// The fill for missing readings, dBm.
    missing: f64,
    /// The distance's divisor.
    norm: Normalisation,
}

impl Fingerprints {
    /// The fingerprints of `map`'s cells; cells with fewer than `min_scans` scans (at least
    /// one) are unknown. Readings weaker than `missing_rssi` count as `missing_rssi`;
    /// distances are divided as `norm` says.
    #[must_use]
    pub fn new(map: &RadioMap, missing_rssi: f64, min_scans: u32, norm: Normalisation) -> Self {
        let columns = map.access_point_columns();
        let cells = map
            .cells
            .iter()
            .map(|c| {
                (c.radio.scans >= min_scans.max(1))
                    .then(|| fingerprint(&c.radio, &columns, missing_rssi, &[]))
            })
            .collect();
        Self {
            columns,
            cells,
            missing: missing_rssi,
            norm,
        }
    }

    /// Number of access points of the map.
    #[must_use]
    pub fn access_points(&self) -> usize {
        self.columns.len()
    }

    /// The scan as a vector over the map's access points (`missing` where not heard).
    #[must_use]
    pub fn scan_vector(&self, scan: &WifiScan) -> Vec<f64> {
        scan_vector(&self.columns, self.missing, scan)
    }

    /// True when cell `c` has a fingerprint (enough scans).
    pub fn is_known(&self, c: usize) -> bool {
        self.cells.get(c).is_some_and(Option::is_some)
    }

    /// `ndist` of cell `from`'s fingerprint, read as a scan, to cell `to`'s (`None` unless
    /// both are known).
    #[must_use]
    pub fn cell_ndist(&self, from: usize, to: usize) -> Option<f64> {
        let (z, _) = self.cells.get(from)?.as_ref()?;
        let (means, visible) = self.cells.get(to)?.as_ref()?;
        Some(ndist(z, means, *visible, self.norm))
    }

    /// `ndist(z, c_i)` for every cell (eqs. 2–11), `None` for unknown cells.
    #[must_use]
    pub fn ndist(&self, scan: &WifiScan) -> Vec<Option<f64>> {
        let z = self.scan_vector(scan);
        self.cells
            .iter()
            .map(|c| {
                c.as_ref()
                    .map(|(means, visible)| ndist(&z, means, *visible, self.norm))
            })
            .collect()
    }
}

/// A scan's distance to its own cell's fingerprint, before normalisation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeldOut {
    /// The Euclidean distance over the map's access points, dB.
    pub euclidean: f64,
    /// Access points visible from the cell without the held-out scans.
    pub visible: usize,
}

impl HeldOut {
    /// The normalised distance.
    #[must_use]
    pub fn ndist(&self, norm: Normalisation) -> f64 {
        self.euclidean / norm.divisor(self.visible)
    }
}

/// Quantiles (p50, p90, p99, max) of held-out distances per distance divisor (`paper`,
/// `sqrt`): the spread `ε` is chosen from, as `summary.json` reports it.
#[must_use]
pub fn held_out_quantiles(
    held: &[HeldOut],
) -> std::collections::BTreeMap<&'static str, [Option<f64>; 4]> {
    Normalisation::ALL
        .into_iter()
        .map(|norm| {
            let mut d: Vec<f64> = held.iter().map(|h| h.ndist(norm)).collect();
            d.sort_by(f64::total_cmp);
            let q =
                |q: f64| (!d.is_empty()).then(|| d[((d.len() - 1) as f64 * q).round() as usize]);
            (norm.name(), [q(0.5), q(0.9), q(0.99), q(1.0)])
        })
        .collect()
}

/// Leave-one-visit-out distances of a survey (the paper's Fig. 11, computed from the survey
/// itself): for each `(scan, cell)` of `assignments` (in time order), the distance between
/// the scan and its cell's fingerprint without any scan of the same visit — the run
/// of consecutive assignments to that cell. Scans of one visit share the walker's place and
/// heading (so its body shadowing): against a fingerprint that still holds them, a scan
/// looks closer to its cell than a later walker's scan will, and `ε` calibrated on it is
/// too tight. Cells with no scan outside the visit are skipped.
#[must_use]
pub fn leave_one_out_ndist(
    map: &RadioMap,
    assignments: &[(usize, Option<usize>)],
    scans: &[WifiScan],
    missing_rssi: f64,
) -> Vec<HeldOut> {
    let columns = map.access_point_columns();
    let mut out = Vec::with_capacity(assignments.len());
    for visit in assignments.chunk_by(|a, b| a.1 == b.1) {
        let Some(c) = visit[0].1 else { continue };
        let Some(radio) = map.cells.get(c).map(|c| &c.radio) else {
            continue;
        };
        let held: Vec<&WifiScan> = visit.iter().filter_map(|&(s, _)| scans.get(s)).collect();
        if radio.scans as usize <= held.len() {
            continue;
        }
        let (means, visible) = fingerprint(radio, &columns, missing_rssi, &held);
        for scan in held {
            out.push(HeldOut {
                euclidean: euclidean(&scan_vector(&columns, missing_rssi, scan), &means),
                visible,
            });
        }
    }
    out
}

/// `scan` as a vector over `columns` (`missing` where not heard; weaker readings count as
/// `missing`).
fn scan_vector(columns: &FxHashMap<String, usize>, missing: f64, scan: &WifiScan) -> Vec<f64> {
    let mut z = vec![missing; columns.len()];
    for r in &scan.readings {
        if let Some(&col) = columns.get(&r.bssid) {
            z[col] = r.rssi.max(missing);
        }
    }
    z
}

/// A cell's fingerprint over `columns`: the mean RSSI of every access point it heard
/// (readings weaker than `missing` count as `missing`), not counting the readings of the
/// scans `without` (held out), `missing` for the others; and the number of access points
/// heard.
fn fingerprint(
    radio: &CellRadio,
    columns: &FxHashMap<String, usize>,
    missing: f64,
    without: &[&WifiScan],
) -> (Vec<f64>, usize) {
    let mut means = vec![missing; columns.len()];
    let mut visible = 0;
    for (bssid, stats) in &radio.aps {
        let Some(&col) = columns.get(bssid) else {
            continue;
        };
        let (mut n, mut sum) = (stats.n, stats.sum);
        for r in without.iter().filter_map(|scan| scan.rssi(bssid)) {
            n = n.saturating_sub(1);
            sum -= r;
        }
        if n > 0 {
            means[col] = (sum / f64::from(n)).max(missing);
            visible += 1;
        }
    }
    (means, visible)
}

/// The threshold `ε` under which a share `1 − miss` of `distances` fall (the paper's
/// choice of ε from the distribution of Fig. 11): the smallest distance with at least that
/// share at or below it, nudged up by 1 % so that it is strictly above; `None` without
/// distances.
pub fn calibrate_epsilon(distances: &[f64], miss: f64) -> Option<f64> {
    let mut d: Vec<f64> = distances
        .iter()
        .copied()
        .filter(|d| d.is_finite())
        .collect();
    if d.is_empty() {
        return None;
    }
    d.sort_by(f64::total_cmp);
    let rank = ((1.0 - miss.clamp(0.0, 1.0)) * d.len() as f64).ceil() as usize;
    Some(d[rank.clamp(1, d.len()) - 1] * 1.01)
}

/// The normalised distance of eqs. 8 and 11 (with [`Normalisation::Paper`]): the Euclidean
/// distance between the filled vectors `z` and `c`, divided as `norm` says by the number of
/// access points visible from the cell.
#[must_use]
pub fn ndist(z: &[f64], c: &[f64], visible: usize, norm: Normalisation) -> f64 {
    euclidean(z, c) / norm.divisor(visible)
}

/// The Euclidean distance between the filled vectors `z` and `c`.
fn euclidean(z: &[f64], c: &[f64]) -> f64 {
    debug_assert_eq!(z.len(), c.len());
    z.iter()
        .zip(c)
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        .sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::{CellRadio, RadioMapCell};
    use geo::MultiPolygon;

    fn scan(readings: &[(&str, f64)]) -> WifiScan {
        WifiScan::from_readings(0.0, readings)
    }

    #[test]
    fn the_papers_examples() {
        // Eqs. 6–8: the scan misses an access point the cell hears: 7.1 dBm.
        let paper = Normalisation::Paper;
        let d = ndist(&[-82.0, -73.0, -96.0], &[-84.0, -75.0, -75.0], 3, paper);
        assert!((d - 7.06).abs() < 0.01, "{d}");
        // Eqs. 9–11: the cell misses one the scan hears: 10.6 dBm.
        let d = ndist(&[-84.0, -75.0, -75.0], &[-82.0, -73.0, -96.0], 2, paper);
        assert!((d - 10.6).abs() < 0.01, "{d}");
        // Divided by √k instead: 21.2 / √3 and 21.2 / √2.
        let d = ndist(
            &[-82.0, -73.0, -96.0],
            &[-84.0, -75.0, -75.0],
            3,
            Normalisation::Sqrt,
        );
        assert!((d - 449f64.sqrt() / 3f64.sqrt()).abs() < 1e-9, "{d}");
        let d = ndist(
            &[-84.0, -75.0, -75.0],
            &[-82.0, -73.0, -96.0],
            2,
            Normalisation::Sqrt,
        );
        assert!((d - 449f64.sqrt() / 2f64.sqrt()).abs() < 1e-9, "{d}");
    }

    #[test]
    fn fingerprints_fill_missing_readings_and_skip_unknown_cells_and_aps() {
        let mut heard = CellRadio::default();
        heard.add_scan(&scan(&[("a", -84.0), ("b", -75.0)]));
        heard.add_scan(&scan(&[("a", -84.0), ("b", -75.0), ("c", -99.0)]));
        let cell = |radio| RadioMapCell {
            id: "x".into(),
            level: 0,
            area: MultiPolygon::new(Vec::new()),
            radio,
        };
        let map = RadioMap {
            cells: vec![cell(heard), cell(CellRadio::default())],
            ..Default::default()
        };
        let prints = Fingerprints::new(&map, -96.0, 1, Normalisation::Paper);
        assert_eq!(prints.access_points(), 3);
        // "zz" is unknown to the map and left out; "c" (heard below the floor) counts as −96.
        let z = scan(&[("a", -82.0), ("b", -73.0), ("zz", -40.0)]);
        let d = prints.ndist(&z);
        assert_eq!(d.len(), 2);
        assert!((d[0].expect("known") - 8f64.sqrt() / 3.0).abs() < 1e-9);
        assert_eq!(d[1], None);
        let d = Fingerprints::new(&map, -96.0, 1, Normalisation::Sqrt).ndist(&z);
        assert!((d[0].expect("known") - 8f64.sqrt() / 3f64.sqrt()).abs() < 1e-9);
        let unknown = Fingerprints::new(&map, -96.0, 3, Normalisation::Paper);
        assert_eq!(unknown.ndist(&scan(&[]))[0], None);
    }

    #[test]
    fn leave_one_visit_out_and_calibration() {
        let mut radio = CellRadio::default();
        let scans = [
            scan(&[("a", -60.0), ("b", -80.0)]),
            scan(&[("a", -64.0)]),
            scan(&[("a", -70.0)]),
        ];
        for s in &scans {
            radio.add_scan(s);
        }
        let map = RadioMap {
            cells: vec![RadioMapCell {
                id: "x".into(),
                level: 0,
                area: MultiPolygon::new(Vec::new()),
                radio,
            }],
            ..Default::default()
        };
        // Visits: scans 0 and 1 (one visit), then scan 2 after leaving the cell.
        let d: Vec<f64> = leave_one_out_ndist(
            &map,
            &[(0, Some(0)), (1, Some(0)), (3, None), (2, Some(0))],
            &scans,
            -96.0,
        )
        .iter()
        .map(|h| h.ndist(Normalisation::Paper))
        .collect();
        assert_eq!(d.len(), 3, "{d:?}");
        // Scans 0 and 1 against scan 2 alone (a = −70, b unseen = −96; one AP visible).
        assert!((d[0] - (100f64 + 256.0).sqrt()).abs() < 1e-9, "{d:?}");
        assert!((d[1] - 6.0).abs() < 1e-9, "{d:?}");
        // Scan 2 against scans 0 and 1: a = −62, b = −80; scan 2 misses b (−96).
        assert!((d[2] - (64f64 + 256.0).sqrt() / 2.0).abs() < 1e-9, "{d:?}");
        // A cell whose only visit is held out is skipped.
        let one_visit = [(0, Some(0)), (1, Some(0)), (2, Some(0))];
        assert!(leave_one_out_ndist(&map, &one_visit, &scans, -96.0).is_empty());
        let e = calibrate_epsilon(&[1.0, 2.0, 3.0, 4.0], 0.25).expect("epsilon");
        assert!((e - 3.03).abs() < 1e-9);
        assert!((calibrate_epsilon(&[1.0, 2.0, 3.0, 4.0], 0.0).expect("max") - 4.04).abs() < 1e-9);
        assert_eq!(calibrate_epsilon(&[], 0.1), None);
    }
}
