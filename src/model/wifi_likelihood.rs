//! The probabilistic WiFi measurement of Woodman & Harle 2009, sec. 5.3, eq. 14:
//! `p(z_t | s_t) = p(z_t | c_i)` for the cell `i` the particle stands in, computed from the
//! cell's histograms.
//!
//! Access points are taken as independent. For access point `a` of the map in a cell with
//! `S` scans of which `n_a` heard it:
//!
//! * heard in the scan at `r` dBm: `P(heard) · ((1 − β) · K(r) + β · U)`, where `K` is the
//!   cell's histogram smoothed by a Gaussian kernel of `kernel_sigma` (a reading seen only a
//!   few times in a cell still makes nearby values likely) and `U` a uniform density over
//!   the receiver's range (an outlier share `β` bounds what one reading can cost);
//! * not heard: `1 − P(heard)`;
//!
//! with `P(heard) = (n_a + ½) / (S + 1)` (never 0 or 1: a cell's few scans cannot rule a
//! sighting in or out). The paper prefers containment regions because such distributions
//! change with the environment; `track --rf-mode` offers both and the README compares them.

use crate::map::RadioMap;
use crate::sensor::WifiScan;
use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

/// Width of the uniform outlier density's range, dB (−96 to −16 dBm or so).
const RSSI_RANGE: f64 = 80.0;

/// The histogram likelihood's parameters; every default in one place.
///
/// | field          | default | meaning                                               |
/// |----------------|---------|-------------------------------------------------------|
/// | `kernel_sigma` | 4 dB    | Gaussian smoothing of each histogram                  |
/// | `outlier`      | 0.05    | share `β` of a reading explained by a uniform density |
/// | `exponent`     | none    | power of the likelihood; none = 1 / (access points of the map) |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LikelihoodConfig {
    /// Gaussian smoothing of each histogram, dB.
    pub kernel_sigma: f64,
    /// Share of a reading explained by a uniform density over the receiver's range.
    pub outlier: f64,
    /// Power the likelihood is raised to. The readings of one scan share the walker's body,
    /// place and moment, so their product over access points overstates the evidence (taken
    /// literally it drags the particles to the likeliest cell and loses the walker); `None`
    /// = one over the number of access points of the map — the geometric mean of the
    /// per-access-point factors, as `ndist` divides by the access points a cell hears.
    pub exponent: Option<f64>,
}

impl Default for LikelihoodConfig {
    fn default() -> Self {
        Self {
            kernel_sigma: 4.0,
            outlier: 0.05,
            exponent: None,
        }
    }
}

/// One access point's histogram in one cell: readings, their 1 dB bins and the bins' total.
#[derive(Debug, Clone, PartialEq)]
struct Histogram {
    n: u32,
    bins: Vec<(f64, f64)>,
    total: f64,
}

/// The histograms of a radio map's cells, ready for eq. 14.
///
/// A scan is likelier in the cell whose histograms it resembles:
///
/// ```
/// use footslam::map::{CellRadio, RadioMap, RadioMapCell};
/// use footslam::model::wifi_likelihood::{HistogramLikelihood, LikelihoodConfig};
/// use footslam::sensor::WifiScan;
///
/// // Two cells, one near access point `a`, one near `b`, three scans each.
/// let cell = |id: &str, x0: f64, readings: &[(f64, f64)]| {
///     let mut radio = CellRadio::default();
///     for &(a, b) in readings {
///         radio.add_scan(&WifiScan::from_readings(0.0, &[("a", a), ("b", b)]));
///     }
///     let area = geo::Rect::new((x0, 0.0), (x0 + 3.0, 3.0)).to_polygon().into();
///     RadioMapCell { id: id.into(), level: 0, area, radio }
/// };
/// let near_a = cell("0-0-0", 0.0, &[(-40.0, -80.0), (-43.0, -78.0), (-41.0, -82.0)]);
/// let near_b = cell("1-0-0", 3.0, &[(-79.0, -44.0), (-81.0, -40.0), (-77.0, -42.0)]);
/// let map = RadioMap { cells: vec![near_a, near_b], ..Default::default() };
///
/// let likelihood = HistogramLikelihood::new(&map, &LikelihoodConfig::default(), 1);
/// let scan = WifiScan::from_readings(10.0, &[("a", -42.0), ("b", -79.0)]);
/// let ln_p = likelihood.log_likelihood(&scan);
/// let (in_a, in_b) = (ln_p[0].expect("surveyed"), ln_p[1].expect("surveyed"));
/// assert!(in_a > in_b + 1.0);
/// // Cells with fewer scans than asked for are unknown, not unlikely.
/// let strict = HistogramLikelihood::new(&map, &LikelihoodConfig::default(), 4);
/// assert_eq!(strict.log_likelihood(&scan), [None, None]);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct HistogramLikelihood {
    config: LikelihoodConfig,
    columns: FxHashMap<String, usize>,
    /// Per cell: scans and a histogram per access point column (`None` for cells with fewer
    /// scans than asked).
    cells: Vec<Option<(u32, Vec<Option<Histogram>>)>>,
}

impl HistogramLikelihood {
    /// The likelihood over `map`'s cells; cells with fewer than `min_scans` scans (at least
    /// one) are unknown.
    #[must_use]
    pub fn new(map: &RadioMap, config: &LikelihoodConfig, min_scans: u32) -> Self {
        let columns = map.access_point_columns();
        let cells = map
            .cells
            .iter()
            .map(|c| {
                if c.radio.scans < min_scans.max(1) {
                    return None;
                }
                let mut hists = vec![None; columns.len()];
                for (bssid, s) in &c.radio.aps {
                    let Some(&col) = columns.get(bssid) else {
                        continue;
                    };
                    let bins = if s.hist.is_empty() {
                        // A map without histograms: its mean stands for every reading.
                        s.mean()
                            .map(|m| vec![(m, f64::from(s.n))])
                            .unwrap_or_default()
                    } else {
                        s.hist
                            .iter()
                            .map(|(&b, &k)| (f64::from(b), f64::from(k)))
                            .collect()
                    };
                    let total = bins.iter().map(|b| b.1).sum();
                    hists[col] = Some(Histogram {
                        n: s.n,
                        bins,
                        total,
                    });
                }
                Some((c.radio.scans, hists))
            })
            .collect();
        Self {
            config: *config,
            columns,
            cells,
        }
    }

    /// `ln p(z | c_i)` for every cell (eq. 14), `None` for unknown cells.
    #[must_use]
    pub fn log_likelihood(&self, scan: &WifiScan) -> Vec<Option<f64>> {
        let mut z: Vec<Option<f64>> = vec![None; self.columns.len()];
        for r in &scan.readings {
            if let Some(&col) = self.columns.get(&r.bssid) {
                z[col] = Some(r.rssi);
            }
        }
        let sigma = self.config.kernel_sigma.max(0.1);
        let beta = self.config.outlier.clamp(0.0, 1.0);
        let norm = 1.0 / (sigma * (2.0 * std::f64::consts::PI).sqrt());
        let exponent = self
            .config
            .exponent
            .unwrap_or(1.0 / self.columns.len().max(1) as f64);
        self.cells
            .iter()
            .map(|cell| {
                let (scans, hists) = cell.as_ref()?;
                let s = f64::from(*scans);
                let mut ll = 0.0;
                for (reading, hist) in z.iter().zip(hists) {
                    let n = hist.as_ref().map_or(0.0, |h| f64::from(h.n));
                    let heard = (n + 0.5) / (s + 1.0);
                    ll += match (reading, hist) {
                        (None, _) => (1.0 - heard).ln(),
                        (Some(r), hist) => {
                            let kernel = hist.as_ref().map_or(0.0, |h| {
                                h.bins
                                    .iter()
                                    .map(|&(b, k)| k * (-0.5 * ((r - b) / sigma).powi(2)).exp())
                                    .sum::<f64>()
                                    * norm
                                    / h.total.max(1.0)
                            });
                            (heard * ((1.0 - beta) * kernel + beta / RSSI_RANGE)).ln()
                        }
                    };
                }
                Some(ll * exponent)
            })
            .collect()
    }
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
    fn the_cell_that_heard_it_so_is_the_likeliest() {
        let cell = |readings: &[&[(&str, f64)]]| {
            let mut radio = CellRadio::default();
            for r in readings {
                radio.add_scan(&scan(r));
            }
            RadioMapCell {
                id: "c".into(),
                level: 0,
                area: MultiPolygon::new(Vec::new()),
                radio,
            }
        };
        let map = RadioMap {
            cells: vec![
                cell(&[&[("a", -60.0), ("b", -80.0)], &[("a", -62.0), ("b", -82.0)]]),
                cell(&[&[("a", -80.0)], &[("a", -82.0)]]),
                cell(&[]),
            ],
            ..Default::default()
        };
        let config = LikelihoodConfig {
            exponent: Some(1.0),
            ..Default::default()
        };
        let model = HistogramLikelihood::new(&map, &config, 1);
        let ll = model.log_likelihood(&scan(&[("a", -61.0), ("b", -81.0)]));
        let (near, far) = (ll[0].expect("known"), ll[1].expect("known"));
        assert!(near > far + 3.0, "{near} {far}");
        assert_eq!(ll[2], None);
        // Hand-computed for the first cell: a at −61 against bins −60, −62 (σ = 4 dB).
        let k =
            (-0.5f64 * (1.0f64 / 4.0).powi(2)).exp() / (4.0 * (2.0 * std::f64::consts::PI).sqrt());
        let pa = (2.5 / 3.0) * (0.95 * k + 0.05 / 80.0);
        assert!(
            (near - 2.0 * pa.ln()).abs() < 1e-9,
            "{near} {}",
            2.0 * pa.ln()
        );
        // Not hearing b, always heard in the first cell and never in the second, favours
        // the second relative to a scan that heard it.
        let ll = model.log_likelihood(&scan(&[("a", -61.0)]));
        let gap = ll[0].expect("known") - ll[1].expect("known");
        assert!(gap < near - far, "{gap} {}", near - far);
        // By default the likelihood is tempered by the number of access points (2).
        let tempered = HistogramLikelihood::new(&map, &LikelihoodConfig::default(), 1);
        let ll = tempered.log_likelihood(&scan(&[("a", -61.0), ("b", -81.0)]));
        assert!((ll[0].expect("known") - near / 2.0).abs() < 1e-9);
    }
}
