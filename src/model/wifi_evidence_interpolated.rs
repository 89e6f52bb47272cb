//! Radio evidence on the interpolated radio map: how much more likely a scan is at a place
//! than elsewhere, from the map's Gaussian-process prediction at that place
//! ([`crate::model::radio_interpolation`]), calibrated on the survey itself.
//!
//! The statistic is the scan's log-likelihood at the place over its log-likelihood under
//! the access points' prior, per square root of the readings it holds:
//!
//! ```text
//!   x(z, c) = (ln p(z | c) − ln p(z | prior)) / √k                            (1)
//! ```
//!
//! Its readings are not independent (access points on one mast, a scan cached over a few
//! steps), so `x` is no likelihood ratio. What it is worth is measured on the survey, as
//! [`crate::model::wifi_evidence`] does for fingerprint distances: each surveyed cell's
//! fingerprint stands in for a scan taken where nobody surveyed, scored at its own place by
//! the map predicted *without* it (leave-one-out) — `p(x | here)` — and at every known cell
//! at least `far_cells` cells away or on another level — `p(x | elsewhere)`. The evidence is
//!
//! ```text
//!   Λ(z, c) = p(x(z, c) | here) / p(x(z, c) | elsewhere)                      (2)
//! ```
//!
//! as Gaussian kernel densities (Silverman's bandwidth), made non-decreasing in `x`, clamped
//! to `±max_log_ratio` and tempered ([`EvidenceConfig`]). A cell the interpolated map does
//! not know (no survey near enough to explain half its prior variance) gets `Λ = 1`: the
//! scan neither favours nor excludes it.

use crate::error::Result;
use crate::map::RadioMap;
use crate::model::radio_interpolation::{InterpolationConfig, RadioInterpolation};
use crate::model::wifi_evidence::{
    EvidenceConfig, LogRatio, StandInScores, cell_size, enough_scores, ratio_of_scores,
};
use crate::sensor::WifiScan;
use serde::Serialize;

/// What the calibration found, for the run's summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InterpolatedCalibration {
    /// Cells of the map.
    pub cells: usize,
    /// Surveyed cells.
    pub surveyed_cells: usize,
    /// Cells the interpolated map knows (surveyed or predicted well enough).
    pub known_cells: usize,
    /// The kernel's length scale, metres.
    pub length_scale_m: f64,
    /// Per-scan noise over signal variance.
    pub noise_ratio: f64,
    /// What the stand-ins scored.
    #[serde(flatten)]
    pub scores: StandInScores,
}

/// Eq. (2) on every cell of a radio map, calibrated on the map.
#[derive(Debug, Clone)]
pub struct InterpolatedEvidence {
    map: RadioInterpolation,
    ratio: LogRatio,
    /// `D = top − x`: the table's distance-like argument (non-negative on the samples).
    top: f64,
    calibration: InterpolatedCalibration,
}

/// Eq. (1) from `ln p(z | c) − ln p(z | prior)` and the readings' count.
fn statistic(log_ratio: f64, readings: usize) -> f64 {
    log_ratio / (readings.max(1) as f64).sqrt()
}

impl InterpolatedEvidence {
    /// Interpolates `map` ([`RadioInterpolation::new`]) and calibrates eq. (2) on it.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) when `config` or `interpolation` fail their checks;
    /// [`Error::NotEnough`](crate::Error::NotEnough) when the map has no surveyed cell, or its surveyed cells give
    /// fewer than `min_pairs` scores at their own place or far away.
    pub fn calibrate(
        map: &RadioMap,
        (missing_rssi, min_scans): (f64, u32),
        interpolation: &InterpolationConfig,
        config: &EvidenceConfig,
    ) -> Result<Self> {
        config.validate()?;
        let gp = RadioInterpolation::new(map, missing_rssi, min_scans, interpolation)?;
        let cell_m = cell_size(map);
        let centres = map.cell_centres();
        let held_out = gp.held_out_scans();
        let elsewhere_cells = config.far_cells;
        let (mut here, mut far) = (Vec::new(), Vec::new());
        // Stand-ins: the fingerprints of one scan (they are scans), or every fingerprint
        // where too few cells hold one scan (a mean over scans is a less noisy stand-in:
        // the evidence then errs on the strong side).
        let singles = held_out
            .iter()
            .filter(|s| s.scans == 1 && s.own_log_ratio.is_some())
            .count();
        let most_scans = if singles >= config.min_pairs {
            1
        } else {
            u32::MAX
        };
        for scan in held_out
            .iter()
            .filter(|s| !s.readings.is_empty() && s.scans <= most_scans)
        {
            let k = scan.readings.len();
            if let Some(own) = scan.own_log_ratio {
                here.push(statistic(own, k));
            }
            let (x0, y0, level) = centres[scan.cell];
            // Known cells only: the others have no ratio.
            for (c, r) in gp.log_ratios(&scan.readings).into_iter().enumerate() {
                let (x, y, l) = centres[c];
                let apart = l != level || (x - x0).hypot(y - y0) >= elsewhere_cells * cell_m;
                if let (Some(r), true) = (r, apart) {
                    far.push(statistic(r, k));
                }
            }
        }
        enough_scores(
            &mut here,
            &mut far,
            config,
            [
                "surveyed cells the rest of the survey predicts",
                "known cells far from a surveyed cell",
            ],
        )?;
        let calibration = InterpolatedCalibration {
            cells: map.cells.len(),
            surveyed_cells: held_out.len(),
            known_cells: (0..map.cells.len()).filter(|&c| gp.is_known(c)).count(),
            length_scale_m: gp.fit().length_scale,
            noise_ratio: gp.fit().noise_ratio,
            scores: StandInScores::of(&here, &far, most_scans, elsewhere_cells),
        };
        let top = here.iter().chain(&far).copied().fold(f64::MIN, f64::max);
        let ratio = ratio_of_scores(&here, &far, top, config);
        Ok(Self {
            map: gp,
            ratio,
            top,
            calibration,
        })
    }

    /// What the calibration found.
    #[must_use]
    pub fn calibration(&self) -> &InterpolatedCalibration {
        &self.calibration
    }

    /// `ln Λ` (tempered) of `scan` on every cell of the map; 0 for cells the map does not know
    /// and for a scan that holds no access point the map heard.
    #[must_use]
    pub fn log_ratios(&self, scan: &WifiScan) -> Vec<f32> {
        let readings = self.map.readings(scan);
        if readings.is_empty() {
            return vec![0.0; self.calibration.cells];
        }
        self.map
            .log_ratios(&readings)
            .into_iter()
            .map(|r| {
                r.map_or(0.0, |r| {
                    self.ratio.at(self.top - statistic(r, readings.len()))
                })
            })
            .collect()
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::map::{CellRadio, RadioMapCell};
    use geo::Rect;

    /// RSSI at `x` metres along a corridor of access points every 30 m (path loss, dBm).
    fn field(x: f64) -> Vec<(String, f64)> {
        (0..9)
            .map(|k| {
                let d = (x - 30.0 * f64::from(k)).abs().max(1.0);
                (format!("ap{k}"), -35.0 - 25.0 * d.log10())
            })
            .filter(|(_, r)| *r > -90.0)
            .collect()
    }

    /// A scan at `x` along the corridor, each reading rounded to the dB and moved by
    /// `wobble` dB, up and down alternately.
    pub(crate) fn scan_at(x: f64, wobble: f64) -> WifiScan {
        let readings: Vec<(String, f64)> = field(x)
            .into_iter()
            .enumerate()
            .map(|(i, (b, r))| {
                (
                    b,
                    (r + wobble * if i % 2 == 0 { 1.0 } else { -1.0 }).round(),
                )
            })
            .collect();
        let refs: Vec<(&str, f64)> = readings.iter().map(|(b, r)| (b.as_str(), *r)).collect();
        WifiScan::from_readings(0.0, &refs)
    }

    /// 3 m cells along 240 m, every other one surveyed with one scan, and a detached cell
    /// 2 km away nobody surveyed.
    fn corridor() -> RadioMap {
        let mut cells: Vec<RadioMapCell> = (0..80)
            .map(|i| {
                let x = 1.5 + 3.0 * f64::from(i);
                let mut radio = CellRadio::default();
                if i % 2 == 0 {
                    radio.add_scan(&scan_at(x, if i % 4 == 0 { 1.5 } else { -1.5 }));
                }
                RadioMapCell {
                    id: format!("0-{i}-0"),
                    level: 0,
                    area: Rect::new((x - 1.5, 0.0), (x + 1.5, 3.0))
                        .to_polygon()
                        .into(),
                    radio,
                }
            })
            .collect();
        cells.push(RadioMapCell {
            id: "0-999-0".into(),
            level: 0,
            area: Rect::new((2000.0, 0.0), (2003.0, 3.0)).to_polygon().into(),
            radio: CellRadio::default(),
        });
        RadioMap {
            cells,
            ..Default::default()
        }
    }

    #[test]
    fn a_scan_is_evidence_for_its_place_against_far_ones_and_none_where_the_map_knows_nothing() {
        let map = corridor();
        let ev = InterpolatedEvidence::calibrate(
            &map,
            (-96.0, 1),
            &InterpolationConfig::default(),
            &EvidenceConfig::default(),
        )
        .expect("calibrated");
        let cal = ev.calibration();
        assert_eq!((cal.surveyed_cells, cal.cells), (40, 81));
        assert_eq!(cal.scores.stand_in_max_scans, 1);
        assert!(
            cal.scores.median_here > cal.scores.median_elsewhere,
            "{cal:?}"
        );
        // A scan at an unsurveyed cell (x = 100.5 m, cell 33).
        let r = ev.log_ratios(&scan_at(100.5, 0.5));
        assert_eq!(r.len(), 81);
        assert!(r[33] > 0.0, "the scan's own place is favoured: {}", r[33]);
        for far in [0, 10, 60, 79] {
            assert!(
                r[far] < 0.0 && r[far] < r[33],
                "cell {far}: {} vs {}",
                r[far],
                r[33]
            );
        }
        let best = (0..81).max_by(|&a, &b| r[a].total_cmp(&r[b])).unwrap();
        assert!(best.abs_diff(33) <= 3, "likeliest cell {best}");
        // The detached cell is unknown: neither favoured nor excluded.
        assert_eq!(r[80], 0.0);
        // A scan of access points the map never heard says nothing anywhere.
        let stranger = WifiScan::from_readings(0.0, &[("nobody", -50.0)]);
        assert!(ev.log_ratios(&stranger).iter().all(|&v| v == 0.0));
    }

    #[test]
    fn a_map_too_small_to_calibrate_is_not_enough() {
        let mut map = corridor();
        map.cells.truncate(6);
        let err = InterpolatedEvidence::calibrate(
            &map,
            (-96.0, 1),
            &InterpolationConfig::default(),
            &EvidenceConfig::default(),
        )
        .unwrap_err();
        assert!(matches!(err, crate::Error::NotEnough { .. }), "{err}");
    }
}
