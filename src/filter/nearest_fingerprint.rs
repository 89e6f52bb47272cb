//! The radio map used alone, the baseline a map-aided tracker must beat. Two methods:
//!
//! * `interpolated`: the `k` most likely cells of the interpolated radio map
//!   ([`crate::model::radio_interpolation`], a Gaussian process per access point after Ferris,
//!   Hähnel & Fox 2006), each reading Gaussian about the cell's predicted mean with its
//!   predicted variance; candidates are every cell the survey predicts, surveyed or not, so a
//!   scan taken between surveyed places lands between them. The scan is placed at the mean
//!   of their centroids; the level is the most likely cell's.
//! * `auto` (the default): `pathloss` on a map that covers less than `auto_below_coverage`
//!   of its cells (ordinary walks), else `interpolated`.
//! * `pathloss`: the `k` most likely cells under a log-distance path-loss model per access
//!   point ([`crate::model::radio_pathloss`]), every cell of the map a candidate: it reaches
//!   beyond the survey, where later walks mostly go.
//! * `ndist`: weighted k-nearest-neighbour fingerprinting (RADAR, Bahl & Padmanabhan 2000)
//!   over the surveyed cells alone: the mean of the centroids of the `k` cells whose
//!   fingerprints are nearest to it (the radio map's `ndist`,
//!   [`crate::model::wifi_distance`]), weighted by `1 / (ndist + δ)`; the level is the nearest
//!   cell's.

use crate::error::{Error, Result};
use crate::map::RadioMap;
use crate::model::radio_interpolation::{InterpolationConfig, RadioInterpolation};
use crate::model::radio_pathloss::{PathLossConfig, PathLossMap};
use crate::model::radio_variogram::VariogramFit;
use crate::model::wifi_distance::{Fingerprints, Normalisation};
use crate::sensor::WifiScan;
use serde::{Deserialize, Serialize};

/// Parameters of [`NearestFingerprint`]; every default in one place.
///
/// | field          | default | meaning                                                    |
/// |----------------|---------|------------------------------------------------------------|
/// | `k`            | 3       | nearest cells averaged                                     |
/// | `delta`        | 0.5 dBm | added to each distance before inverting it (weights)       |
/// | `missing_rssi` | −96 dBm | fill for access points not heard (as the tracker's `rf`)   |
/// | `min_scans`    | 1       | cells with fewer scans are not candidates                  |
/// | `distance`     | `sqrt`  | `ndist`'s divisor: `paper` (k) or `sqrt` (√k)              |
/// | `min_common`   | 1       | fewest of a scan's access points the map must know         |
/// | `method`       | `auto`  | `auto`, `pathloss` (likeliest cells under a path-loss model), `interpolated` (of the GP map) or `ndist` |
/// | `auto_below_coverage` | 0.6 | `auto` is `pathloss` on maps whose surveyed share of cells is below this, else `interpolated` |
/// | `interpolation`| see [`InterpolationConfig`] | the interpolated map's parameters   |
/// | `pathloss`     | see [`PathLossConfig`] | the path-loss model's parameters         |
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FingerprintConfig {
    /// Nearest cells averaged.
    pub k: usize,
    /// Added to each distance before inverting it, dBm.
    pub delta: f64,
    /// Fill for access points not heard, dBm.
    pub missing_rssi: f64,
    /// Cells with fewer scans are not candidates.
    pub min_scans: u32,
    /// The distance's divisor.
    pub distance: Normalisation,
    /// A scan that shares fewer access points with the map is not placed.
    pub min_common: usize,
    /// How cells are ranked.
    pub method: FingerprintMethod,
    /// The surveyed share of cells below which `auto` uses `pathloss`.
    pub auto_below_coverage: f64,
    /// The interpolated map's parameters (method `interpolated`).
    pub interpolation: InterpolationConfig,
    /// The path-loss model's parameters (method `pathloss`).
    pub pathloss: PathLossConfig,
}

/// How [`NearestFingerprint`] ranks the cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FingerprintMethod {
    /// `pathloss` on a map whose surveyed share of cells is below `auto_below_coverage`
    /// (ordinary walks: later scans mostly come from where nobody surveyed), else
    /// `interpolated` (a survey that covers the floor: the interpolated map is sharper).
    Auto,
    /// By likelihood on the interpolated radio map, surveyed and predicted cells alike.
    Interpolated,
    /// By likelihood under a path-loss model per access point, every cell a candidate.
    #[serde(rename = "pathloss")]
    PathLoss,
    /// By `ndist` to the surveyed cells' fingerprints, weighted `1 / (ndist + δ)`.
    Ndist,
}

impl Default for FingerprintConfig {
    fn default() -> Self {
        Self {
            k: 3,
            delta: 0.5,
            missing_rssi: -96.0,
            min_scans: 1,
            distance: Normalisation::Sqrt,
            min_common: 1,
            method: FingerprintMethod::Auto,
            auto_below_coverage: 0.6,
            interpolation: InterpolationConfig::default(),
            pathloss: PathLossConfig::default(),
        }
    }
}

impl FingerprintConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `k` is outside [1, 100], `delta` is not a positive number of dBm,
    /// `missing_rssi` is outside [−130, −30] dBm, or `interpolation` fails
    /// [`InterpolationConfig::validate`].
    pub fn validate(&self) -> Result<()> {
        use crate::error::check_range;
        self.interpolation.validate()?;
        self.pathloss.validate()?;
        check_range(
            "fingerprint.auto_below_coverage",
            self.auto_below_coverage,
            0.0..=1.0,
            "",
        )?;
        check_range("fingerprint.k", self.k as f64, 1.0..=100.0, "")?;
        check_range(
            "fingerprint.delta",
            self.delta,
            (std::ops::Bound::Excluded(0.0), std::ops::Bound::Unbounded),
            "dBm",
        )?;
        check_range(
            "fingerprint.missing_rssi",
            self.missing_rssi,
            -130.0..=-30.0,
            "dBm",
        )
    }
}

/// A scan's estimated place.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FingerprintFix {
    /// Time of the scan, seconds.
    pub t: f64,
    /// East, local metres.
    pub x: f64,
    /// North, local metres.
    pub y: f64,
    /// Level of the nearest cell.
    pub level: i32,
    /// `ndist` to the nearest surveyed cell's fingerprint, dBm (NaN when none is comparable).
    pub ndist: f64,
}

/// Weighted k-nearest-fingerprint positioning on a radio map.
///
/// A scan placed by the cells whose fingerprints are nearest to it:
///
/// ```
/// use footslam::filter::{FingerprintConfig, NearestFingerprint};
/// use footslam::map::{CellRadio, RadioMap, RadioMapCell};
/// use footslam::sensor::WifiScan;
///
/// // Four 3 m cells along a corridor, one scan each of the access points at its two ends.
/// let cells = (0..4)
///     .map(|i| {
///         let x = 3.0 * f64::from(i) + 1.5; // the cell's centre
///         let mut radio = CellRadio::default();
///         let readings = [("west", -40.0 - 3.0 * x), ("east", -76.0 + 3.0 * x)];
///         radio.add_scan(&WifiScan::from_readings(0.0, &readings));
///         let area = geo::Rect::new((x - 1.5, 0.0), (x + 1.5, 2.0)).to_polygon().into();
///         RadioMapCell { id: format!("0-{i}-0"), level: 0, area, radio }
///     })
///     .collect();
/// let map = RadioMap { cells, ..Default::default() };
///
/// let config = FingerprintConfig { k: 2, ..Default::default() };
/// let localiser = NearestFingerprint::new(&map, &config)?;
/// // A scan taken at x = 5.5 m, between the second and third cells' centres.
/// let scan = WifiScan::from_readings(7.0, &[("west", -56.5), ("east", -59.5)]);
/// let fix = localiser.locate(&scan).expect("the map knows both access points");
/// assert!((fix.x - 5.5).abs() < 1.0 && (fix.y - 1.0).abs() < 1e-9);
/// assert_eq!((fix.t, fix.level), (7.0, 0));
/// // A scan of access points the map never heard is not placed.
/// assert!(localiser.locate(&WifiScan::from_readings(8.0, &[("other", -50.0)])).is_none());
/// # Ok::<(), footslam::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct NearestFingerprint {
    prints: Fingerprints,
    /// Centroid and level of each cell.
    centres: Vec<(f64, f64, i32)>,
    bssids: rustc_hash::FxHashSet<String>,
    /// The interpolated map (method `interpolated`).
    interpolation: Option<RadioInterpolation>,
    /// The path-loss model (method `pathloss`).
    pathloss: Option<PathLossMap>,
    config: FingerprintConfig,
}

impl NearestFingerprint {
    /// A localiser on `map`.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `config` fails [`FingerprintConfig::validate`]; [`Error::NotEnough`]
    /// when no cell of `map` holds `min_scans` scans (at least one) with an area.
    pub fn new(map: &RadioMap, config: &FingerprintConfig) -> Result<Self> {
        config.validate()?;
        if !map
            .cells
            .iter()
            .any(|c| c.radio.scans >= config.min_scans.max(1))
        {
            return Err(Error::not_enough(
                "the radio map has no cell with scans",
                "survey the building first",
            ));
        }
        let centres = map.cell_centres();
        let mut config = config.clone();
        if config.method == FingerprintMethod::Auto {
            let surveyed = map
                .cells
                .iter()
                .filter(|c| c.radio.scans >= config.min_scans.max(1))
                .count();
            let coverage = surveyed as f64 / map.cells.len() as f64;
            config.method = if coverage < config.auto_below_coverage {
                FingerprintMethod::PathLoss
            } else {
                FingerprintMethod::Interpolated
            };
        }
        let interpolation = match config.method {
            FingerprintMethod::Interpolated => Some(RadioInterpolation::new(
                map,
                config.missing_rssi,
                config.min_scans,
                &config.interpolation,
            )?),
            _ => None,
        };
        let pathloss = match config.method {
            FingerprintMethod::PathLoss => Some(PathLossMap::fit(map, &config.pathloss)?),
            _ => None,
        };
        Ok(Self {
            interpolation,
            pathloss,
            prints: Fingerprints::new(map, config.missing_rssi, config.min_scans, config.distance),
            centres,
            bssids: map.access_points().into_iter().map(str::to_owned).collect(),
            config,
        })
    }

    /// The method in use (never [`FingerprintMethod::Auto`]).
    #[must_use]
    pub fn method(&self) -> FingerprintMethod {
        self.config.method
    }

    /// The interpolated map's kernel (method `interpolated`).
    #[must_use]
    pub fn interpolation_fit(&self) -> Option<VariogramFit> {
        self.interpolation.as_ref().map(|i| *i.fit())
    }

    /// What the path-loss model's fit found (method `pathloss`).
    #[must_use]
    pub fn pathloss_summary(&self) -> Option<crate::model::PathLossSummary> {
        self.pathloss.as_ref().map(PathLossMap::summary)
    }

    /// The scan's place, `None` when it shares fewer than `min_common` access points with the
    /// map.
    #[must_use]
    pub fn locate(&self, scan: &WifiScan) -> Option<FingerprintFix> {
        let common = scan
            .readings
            .iter()
            .filter(|r| self.bssids.contains(&r.bssid))
            .count();
        if common < self.config.min_common.max(1) {
            return None;
        }
        let ranked = self.placeable(self.prints.ndist(scan));
        // The nearest distance is reported either way; only `ndist` places by the ranking.
        let nearest = ranked.iter().map(|r| r.0).min_by(f64::total_cmp);
        let (x, y, level) = match (&self.interpolation, &self.pathloss) {
            // The likeliest cells, unweighted.
            (Some(gp), _) => {
                let neg_ll = gp.log_likelihoods(scan).into_iter().map(|l| l.map(|l| -l));
                self.centre_of_first(self.placeable(neg_ll), |_| 1.0)?
            }
            (None, Some(pl)) => {
                let neg_ll = pl.log_likelihoods(scan)?.into_iter().map(|l| l.map(|l| -l));
                self.centre_of_first(self.placeable(neg_ll), |_| 1.0)?
            }
            (None, None) => {
                let delta = self.config.delta;
                self.centre_of_first(ranked, |d| 1.0 / (d + delta))?
            }
        };
        Some(FingerprintFix {
            t: scan.t,
            x,
            y,
            level,
            ndist: nearest.unwrap_or(f64::NAN),
        })
    }

    /// `(value, cell)` of every cell with a finite value and a centre.
    fn placeable(&self, values: impl IntoIterator<Item = Option<f64>>) -> Vec<(f64, usize)> {
        values
            .into_iter()
            .enumerate()
            .filter_map(|(i, v)| v.filter(|v| v.is_finite()).map(|v| (v, i)))
            .filter(|&(_, i)| self.centres[i].0.is_finite())
            .collect()
    }

    /// The mean centre, weighted `weight(value)`, of the `k` cells of least value (`ranked`
    /// sorted here: value, then cell) on the level of the least.
    fn centre_of_first(
        &self,
        mut ranked: Vec<(f64, usize)>,
        weight: impl Fn(f64) -> f64,
    ) -> Option<(f64, f64, i32)> {
        ranked.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let &(_, first) = ranked.first()?;
        let level = self.centres[first].2;
        let (mut sx, mut sy, mut sw) = (0.0, 0.0, 0.0);
        for &(v, i) in ranked
            .iter()
            .filter(|&&(_, i)| self.centres[i].2 == level)
            .take(self.config.k)
        {
            let w = weight(v);
            sx += w * self.centres[i].0;
            sy += w * self.centres[i].1;
            sw += w;
        }
        Some((sx / sw, sy / sw, level))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::radio_map::{CellRadio, RadioMapCell};
    use geo::{MultiPolygon, Rect};

    fn cell(id: &str, x: f64, level: i32, rssi: &[(&str, f64)]) -> RadioMapCell {
        let mut radio = CellRadio::default();
        radio.add_scan(&WifiScan::from_readings(0.0, rssi));
        RadioMapCell {
            id: id.into(),
            level,
            area: MultiPolygon(vec![
                Rect::new((x - 1.0, -1.0), (x + 1.0, 1.0)).to_polygon(),
            ]),
            radio,
        }
    }

    #[test]
    fn places_a_scan_between_its_nearest_cells() {
        let map = RadioMap {
            cells: vec![
                cell("a", 0.0, 0, &[("ap1", -40.0), ("ap2", -80.0)]),
                cell("b", 10.0, 0, &[("ap1", -80.0), ("ap2", -40.0)]),
                cell("c", 20.0, 1, &[("ap1", -90.0), ("ap2", -90.0)]),
            ],
            ..Default::default()
        };
        let config = FingerprintConfig {
            k: 2,
            method: FingerprintMethod::Ndist,
            ..Default::default()
        };
        let nf = NearestFingerprint::new(&map, &config).expect("localiser");
        // Equal distances to a and b: halfway, on their level.
        let fix = nf
            .locate(&WifiScan::from_readings(
                5.0,
                &[("ap1", -60.0), ("ap2", -60.0)],
            ))
            .expect("fix");
        assert!((fix.x - 5.0).abs() < 1e-9 && fix.level == 0, "{fix:?}");
        // Exactly a's fingerprint: weight 1/δ against 1/(d + δ) pulls it to a.
        let fix = nf
            .locate(&WifiScan::from_readings(
                6.0,
                &[("ap1", -40.0), ("ap2", -80.0)],
            ))
            .expect("fix");
        assert!(fix.x < 1.0 && fix.ndist == 0.0, "{fix:?}");
        assert!(
            nf.locate(&WifiScan::from_readings(7.0, &[("other", -50.0)]))
                .is_none()
        );
    }

    #[test]
    fn interpolated_map_places_a_scan_between_surveyed_places() {
        // A corridor of 2 m cells from 1 to 59 m with an access point every 12 m (log-distance
        // path loss); surveyed everywhere but 25–29 m, two scans a cell 2 dB apart.
        let rssi = |x: f64| -> Vec<(String, f64)> {
            (0..6)
                .map(|a| {
                    let d = (x - 12.0 * f64::from(a)).abs();
                    (format!("ap{a}"), -35.0 - 25.0 * (1.0 + d).log10())
                })
                .collect()
        };
        let cells = (0..30)
            .map(|i| {
                let x = 1.0 + 2.0 * f64::from(i);
                let readings = rssi(x);
                let readings: Vec<(&str, f64)> =
                    readings.iter().map(|(b, r)| (b.as_str(), *r)).collect();
                let mut c = cell(&format!("0-{i}-0"), x, 0, &readings);
                let louder: Vec<(&str, f64)> =
                    readings.iter().map(|&(b, r)| (b, r + 2.0)).collect();
                c.radio.add_scan(&WifiScan::from_readings(0.0, &louder));
                if (12..15).contains(&i) {
                    c.radio = CellRadio::default();
                }
                c
            })
            .collect();
        let map = RadioMap {
            cells,
            ..Default::default()
        };
        let config = FingerprintConfig {
            k: 1,
            method: FingerprintMethod::Interpolated,
            ..Default::default()
        };
        let nf = NearestFingerprint::new(&map, &config).expect("localiser");
        let fit = nf.interpolation_fit().expect("interpolated");
        // A survey of 27 of 30 cells: `auto` takes the interpolated map.
        let auto = NearestFingerprint::new(&map, &FingerprintConfig::default()).expect("auto");
        assert_eq!(auto.method(), FingerprintMethod::Interpolated);
        assert!(fit.pairs > 0 && fit.noise_within_cells, "{fit:?}");
        // A scan at 27 m, 4 m from any surveyed cell: placed in the gap (on an unsurveyed
        // cell), where the surveyed cells alone (method `ndist`) can only put it at its edge.
        let readings = rssi(27.0);
        let readings: Vec<(&str, f64)> = readings
            .iter()
            .map(|(b, r)| (b.as_str(), *r + 1.0))
            .collect();
        let scan = WifiScan::from_readings(1.0, &readings);
        let fix = nf.locate(&scan).expect("fix");
        assert!((24.0..=30.0).contains(&fix.x), "{fix:?} {fit:?}");
        // The path-loss model places it in the gap too.
        let pathloss = NearestFingerprint::new(
            &map,
            &FingerprintConfig {
                k: 1,
                method: FingerprintMethod::PathLoss,
                ..Default::default()
            },
        )
        .expect("localiser");
        assert!(
            pathloss
                .pathloss_summary()
                .is_some_and(|s| s.access_points == 6)
        );
        let fix = pathloss.locate(&scan).expect("fix");
        assert!((24.0..=30.0).contains(&fix.x), "{fix:?}");
        let ndist = NearestFingerprint::new(
            &map,
            &FingerprintConfig {
                method: FingerprintMethod::Ndist,
                ..config
            },
        )
        .expect("localiser");
        let edge = ndist.locate(&scan).expect("fix");
        assert!((edge.x - 27.0).abs() > 3.0, "{edge:?}");
    }
}
