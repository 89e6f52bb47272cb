//! Radio evidence from the path-loss model per access point
//! ([`crate::model::radio_pathloss`]): how much more likely a scan is at a place than
//! elsewhere, everywhere on the floor, surveyed or not, calibrated on the survey itself.
//!
//! The statistic is the scan's log-likelihood at the place (eq. 4 there) against its
//! likeliest place, per square root of the modelled access points it hears:
//!
//! ```text
//!   x(z, c) = (ln p(z | c) − max_c' ln p(z | c')) / √k                        (1)
//! ```
//!
//! Readings are not independent (access points on one mast, cached scans), so `x` is no
//! likelihood ratio; what it is worth is measured on the survey as for the other sources:
//! each surveyed cell's fingerprint stands in for a scan (the cells of one scan, which are
//! scans, where at least `min_pairs` hold one; else every cell's), scored at its own cell
//! — `p(x | here)` — and at every cell at least `far_cells` cells away or on another level —
//! `p(x | elsewhere)`:
//!
//! ```text
//!   Λ(z, c) = p(x(z, c) | here) / p(x(z, c) | elsewhere)                      (2)
//! ```
//!
//! as Gaussian kernel densities, made non-decreasing in `x`, clamped to `±max_log_ratio`
//! and tempered ([`EvidenceConfig`]). The stand-ins are scored by a model fitted with them
//! (three or four numbers per access point over tens of cells, so one cell barely moves
//! it); a scan of no modelled access point gives `Λ = 1` everywhere.

use crate::error::Result;
use crate::map::RadioMap;
use crate::model::radio_pathloss::{PathLossConfig, PathLossMap, PathLossSummary};
use crate::model::wifi_evidence::{
    EvidenceConfig, LogRatio, StandInScores, cell_size, enough_scores, ratio_of_scores,
};
use crate::sensor::{WifiReading, WifiScan};
use rayon::prelude::*;
use serde::Serialize;

/// Most stand-in scans scored (evenly chosen among the surveyed cells).
const MAX_STAND_INS: usize = 600;

/// What the calibration found, for the run's summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PathLossCalibration {
    /// Cells of the map.
    pub cells: usize,
    /// Surveyed cells.
    pub surveyed_cells: usize,
    /// The model's fit.
    pub model: PathLossSummary,
    /// What the stand-ins scored.
    #[serde(flatten)]
    pub scores: StandInScores,
}

/// Eq. (2) on every cell of a radio map, from its path-loss model.
#[derive(Debug, Clone)]
pub struct PathLossEvidence {
    model: PathLossMap,
    ratio: LogRatio,
    calibration: PathLossCalibration,
}

/// Eq. (1) at every cell (0 at the likeliest; cells without area `None`), or `None` when the
/// scan hears no modelled access point.
fn statistics(model: &PathLossMap, scan: &WifiScan) -> Option<Vec<Option<f64>>> {
    let ll = model.log_likelihoods(scan)?;
    let best = ll
        .iter()
        .flatten()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    let k = (model.heard(scan).max(1) as f64).sqrt();
    Some(ll.into_iter().map(|l| l.map(|l| (l - best) / k)).collect())
}

impl PathLossEvidence {
    /// Fits the path-loss model on `map` ([`PathLossMap::fit`]) and calibrates eq. (2) on it.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) when `config` or `pathloss` fail their checks; [`Error::NotEnough`](crate::Error::NotEnough)
    /// when no access point can be modelled, or the stand-ins give fewer than `min_pairs`
    /// scores at their own cell or far away.
    pub fn calibrate(
        map: &RadioMap,
        pathloss: &PathLossConfig,
        config: &EvidenceConfig,
    ) -> Result<Self> {
        config.validate()?;
        let model = PathLossMap::fit(map, pathloss)?;
        let cell_m = cell_size(map);
        let centres = model.centres();
        let surveyed: Vec<usize> = (0..map.cells.len())
            .filter(|&c| map.cells[c].radio.scans > 0 && centres[c].0.is_finite())
            .collect();
        let singles = surveyed
            .iter()
            .filter(|&&c| map.cells[c].radio.scans == 1)
            .count();
        let most_scans = if singles >= config.min_pairs {
            1
        } else {
            u32::MAX
        };
        let mut stand_ins: Vec<usize> = surveyed
            .iter()
            .copied()
            .filter(|&c| map.cells[c].radio.scans <= most_scans)
            .collect();
        if stand_ins.len() > MAX_STAND_INS {
            let n = stand_ins.len();
            stand_ins = (0..MAX_STAND_INS)
                .map(|i| stand_ins[i * n / MAX_STAND_INS])
                .collect();
        }
        let far_m = config.far_cells * cell_m;
        let scored: Vec<(Option<f64>, Vec<f64>)> = stand_ins
            .par_iter()
            .map(|&c| {
                let scan = WifiScan {
                    t: 0.0,
                    readings: map.cells[c]
                        .radio
                        .aps
                        .iter()
                        .filter_map(|(bssid, stats)| {
                            stats.mean().map(|rssi| WifiReading {
                                bssid: bssid.clone(),
                                rssi,
                                ssid: None,
                                freq: None,
                            })
                        })
                        .collect(),
                };
                let Some(x) = statistics(&model, &scan) else {
                    return (None, Vec::new());
                };
                let (x0, y0, level) = centres[c];
                let far = x
                    .iter()
                    .enumerate()
                    .filter(|&(o, _)| {
                        let (x1, y1, l) = centres[o];
                        l != level || (x1 - x0).hypot(y1 - y0) >= far_m
                    })
                    .filter_map(|(_, v)| *v)
                    .collect();
                (x[c], far)
            })
            .collect();
        let mut here: Vec<f64> = scored.iter().filter_map(|s| s.0).collect();
        let mut far: Vec<f64> = scored.into_iter().flat_map(|s| s.1).collect();
        enough_scores(
            &mut here,
            &mut far,
            config,
            [
                "surveyed cells the path-loss model scores",
                "cells far from a surveyed cell",
            ],
        )?;
        let calibration = PathLossCalibration {
            cells: map.cells.len(),
            surveyed_cells: surveyed.len(),
            model: model.summary(),
            scores: StandInScores::of(&here, &far, most_scans, config.far_cells),
        };
        // Every score is at most 0 (the likeliest cell's): the table's argument is −x.
        let ratio = ratio_of_scores(&here, &far, 0.0, config);
        Ok(Self {
            model,
            ratio,
            calibration,
        })
    }

    /// What the calibration found.
    #[must_use]
    pub fn calibration(&self) -> &PathLossCalibration {
        &self.calibration
    }

    /// `ln Λ` (tempered) of `scan` on every cell of the map; 0 for cells without area and
    /// everywhere for a scan that hears no modelled access point.
    #[must_use]
    pub fn log_ratios(&self, scan: &WifiScan) -> Vec<f32> {
        match statistics(&self.model, scan) {
            Some(x) => x
                .into_iter()
                .map(|x| x.map_or(0.0, |x| self.ratio.at(-x)))
                .collect(),
            None => vec![0.0; self.calibration.cells],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::{CellRadio, RadioMapCell};
    use crate::model::wifi_evidence_interpolated::tests::scan_at;
    use geo::Rect;

    /// 3 m cells along 240 m, surveyed (one scan each) only over the first 120 m.
    fn half_corridor() -> RadioMap {
        let cells = (0..80)
            .map(|i| {
                let x = 1.5 + 3.0 * f64::from(i);
                let mut radio = CellRadio::default();
                if x < 120.0 {
                    radio.add_scan(&scan_at(x, if i % 2 == 0 { 1.5 } else { -1.5 }));
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
        RadioMap {
            cells,
            ..Default::default()
        }
    }

    #[test]
    fn a_scan_beyond_the_survey_is_evidence_for_its_place() {
        let map = half_corridor();
        let ev = PathLossEvidence::calibrate(
            &map,
            &PathLossConfig::default(),
            &EvidenceConfig::default(),
        )
        .expect("calibrated");
        let cal = ev.calibration();
        assert_eq!((cal.surveyed_cells, cal.cells), (40, 80));
        assert!(
            cal.scores.median_here > cal.scores.median_elsewhere,
            "{cal:?}"
        );
        // A scan at x = 127.5 m (cell 42), just beyond the survey, near the access point at
        // 120 m that the survey heard loudest at its end.
        let r = ev.log_ratios(&scan_at(127.5, 0.5));
        assert_eq!(r.len(), 80);
        let best = (0..80).max_by(|&a, &b| r[a].total_cmp(&r[b])).unwrap();
        assert!(best.abs_diff(42) <= 3, "likeliest cell {best}: {r:?}");
        for far in [0, 10, 25, 70] {
            assert!(r[far] < r[42], "cell {far}: {} vs {}", r[far], r[42]);
        }
        // A scan of access points the map never heard says nothing anywhere.
        let stranger = WifiScan::from_readings(0.0, &[("nobody", -50.0)]);
        assert!(ev.log_ratios(&stranger).iter().all(|&v| v == 0.0));
    }
}
