//! Other walks' WiFi scans as evidence inside FootSLAM: the cross-walk half of
//! [`super::scan_pairs`], for the FeetSLAM passes of a batch (Robertson et al.'s FeetSLAM
//! shares the walks' transition maps; this shares what they heard).
//!
//! After a pass, every walk's scans have a place: where that pass's answer put the walker
//! at each scan's (latency-corrected) time. In the next pass a walk's scan `k`, taken by a
//! particle at `x`, is weighed against the `M` most similar of the other walks' scans `r`
//! (dissimilarity `D_kr`, eq. 1 of `scan_pairs`), each at its place `y_r` on the same floor,
//! exactly as eq. (3) weighs a walk's own earlier scans:
//!
//! `ln w_k = m_k^(−γ) · Σ_r [ln p_×(D_kr | |x − y_r|) − ln p_×(D_kr | d_far)]`   (1)
//!
//! over the `m_k ≤ M` informative ones. The other walks' places are not the truth — they
//! carry their own pass's errors — and another phone may read a few dB apart, so `p_×` is
//! not the walk's own model: it is eq. (2) calibrated on every pair of this walk's scans and
//! the others' at their previous-pass places. The spread of the places and the devices'
//! offsets thus enter the model's spread, and the evidence is only as strong as the
//! previous pass's agreement allows. Only the most similar scans are kept: they are the ones
//! that can say where the walker was (the rest sit beyond the model's informative range).

use super::scan_pairs::{
    CompactScan, D_STEP, DB_STEP, PairLikelihood, ROW, ScanPairConfig, dissimilarity, tabulate,
};
use crate::sensor::WifiScan;
use rustc_hash::FxHashMap;

/// Another walk's scan, where its previous pass placed it: local metres and level.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlacedScan<'a> {
    /// The scan.
    pub scan: &'a WifiScan,
    /// East, metres.
    pub x: f64,
    /// North, metres.
    pub y: f64,
    /// Its level.
    pub level: i32,
}

/// One reference of a scan: where it was placed and its table row. 16 bytes.
#[derive(Debug, Clone, Copy)]
struct Reference {
    x: f32,
    y: f32,
    level: i32,
    row: u16,
}

/// A walk's scans against the other walks' placed scans, ready for the filter.
#[derive(Debug, Clone)]
pub struct ReferenceScans {
    /// Scan `k`'s references are `refs[offsets[k]..offsets[k + 1]]`.
    offsets: Vec<u32>,
    refs: Vec<Reference>,
    temper: Vec<f32>,
    table: Vec<f32>,
    /// The calibrated `p_×` of eq. (1).
    pub likelihood: PairLikelihood,
    /// Pairs it was calibrated on.
    pub calibration_pairs: usize,
}

impl ReferenceScans {
    /// The references of `scans` (this walk's, in the order its filter applies them),
    /// which its previous pass placed at `places` (one per scan), among `others`. `None`
    /// when the pairs cannot calibrate eq. (2) or no scan has an informative reference.
    #[must_use]
    pub fn new(
        scans: &[WifiScan],
        places: &[(f64, f64, i32)],
        others: &[PlacedScan<'_>],
        config: &ScanPairConfig,
    ) -> Option<Self> {
        if scans.is_empty() || others.is_empty() || config.references_per_scan == 0 {
            return None;
        }
        let floor = config.floor_rssi;
        let mut ids = FxHashMap::default();
        let own: Vec<CompactScan> = scans
            .iter()
            .map(|s| CompactScan::new(s, &mut ids, floor))
            .collect();
        let theirs: Vec<CompactScan> = others
            .iter()
            .map(|o| CompactScan::new(o.scan, &mut ids, floor))
            .collect();
        // Every pair on one floor: its dissimilarity and its distance between the places.
        let mut calibration = Vec::new();
        let mut candidates: Vec<Vec<(f64, usize)>> = vec![Vec::new(); scans.len()];
        for (k, a) in own.iter().enumerate() {
            let (x, y, level) = places[k];
            for (r, b) in theirs.iter().enumerate() {
                let o = &others[r];
                if o.level != level {
                    continue;
                }
                if let Some(big_d) = dissimilarity(a, b, floor) {
                    calibration.push(((x - o.x).hypot(y - o.y), big_d));
                    candidates[k].push((big_d, r));
                }
            }
        }
        let likelihood = PairLikelihood::calibrate(&calibration, config.outlier_share)?;
        let (table, informative) = tabulate(&likelihood);
        let (mut offsets, mut refs, mut temper) = (vec![0u32], Vec::new(), Vec::new());
        for mut c in candidates {
            c.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let start = refs.len();
            for (big_d, r) in c {
                if refs.len() - start == config.references_per_scan {
                    break;
                }
                let row = ((big_d / DB_STEP).round() as usize).min(informative.len() - 1);
                if informative[row] {
                    let o = &others[r];
                    refs.push(Reference {
                        x: o.x as f32,
                        y: o.y as f32,
                        level: o.level,
                        row: row as u16,
                    });
                }
            }
            let n = (refs.len() - start).max(1) as f64;
            temper.push(n.powf(-config.pair_tempering) as f32);
            offsets.push(refs.len() as u32);
        }
        if refs.is_empty() {
            return None;
        }
        Some(Self {
            offsets,
            refs,
            temper,
            table,
            likelihood,
            calibration_pairs: calibration.len(),
        })
    }

    /// References over all scans.
    #[must_use]
    pub fn references(&self) -> usize {
        self.refs.len()
    }

    /// Eq. (1) for scan `k` taken at `at` on `level` (0 past the scans it was built for).
    #[must_use]
    pub fn log_factor(&self, k: usize, at: (f32, f32), level: i32) -> f64 {
        let Some(&end) = self.offsets.get(k + 1) else {
            return 0.0;
        };
        let mut sum = 0.0f32;
        for r in &self.refs[self.offsets[k] as usize..end as usize] {
            if r.level != level {
                continue;
            }
            let d = (at.0 - r.x).hypot(at.1 - r.y);
            let i = ((d * (1.0 / D_STEP as f32)) as usize).min(ROW - 1);
            sum += self.table[usize::from(r.row) * ROW + i];
        }
        f64::from(sum * self.temper[k])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scan at (x, 0) from four access points along a 40 m corridor (log-distance path
    /// loss, a little deterministic noise).
    fn scan_at(t: f64, x: f64, noise: f64) -> WifiScan {
        let readings: Vec<(String, f64)> = (0..4)
            .map(|a| {
                let ax = 13.0 * f64::from(a);
                let d = (x - ax).abs().hypot(2.0);
                (format!("ap{a}"), -35.0 - 25.0 * d.log10() + noise)
            })
            .collect();
        let r: Vec<(&str, f64)> = readings.iter().map(|(n, v)| (n.as_str(), *v)).collect();
        WifiScan::from_readings(t, &r)
    }

    #[test]
    fn a_scan_is_drawn_towards_where_others_heard_the_same() {
        // Other walks heard the corridor every metre, placed where they were.
        let theirs: Vec<WifiScan> = (0..40)
            .map(|i| {
                scan_at(
                    100.0 + f64::from(i),
                    f64::from(i),
                    if i % 2 == 0 { 1.0 } else { -1.0 },
                )
            })
            .collect();
        let others: Vec<PlacedScan> = theirs
            .iter()
            .enumerate()
            .map(|(i, s)| PlacedScan {
                scan: s,
                x: i as f64,
                y: 0.0,
                level: 0,
            })
            .collect();
        // This walk's scans, its previous pass close to right.
        let xs = [3.0, 11.0, 19.0, 27.0, 35.0];
        let mine: Vec<WifiScan> = xs.iter().map(|&x| scan_at(x, x, 0.5)).collect();
        let places: Vec<(f64, f64, i32)> = xs.iter().map(|&x| (x + 0.5, 0.0, 0)).collect();
        let refs = ReferenceScans::new(&mine, &places, &others, &ScanPairConfig::default())
            .expect("calibrates");
        assert!(refs.references() > 0);
        // Scan 2, heard at x = 19: a particle there gains over one 8 m off.
        let here = refs.log_factor(2, (19.0, 0.0), 0);
        let off = refs.log_factor(2, (27.0, 0.0), 0);
        assert!(here > off + 0.5, "here {here}, 8 m off {off}");
        // Another floor's references say nothing; nor do scans past the end.
        assert_eq!(refs.log_factor(2, (19.0, 0.0), 1), 0.0);
        assert_eq!(refs.log_factor(99, (19.0, 0.0), 0), 0.0);
    }

    #[test]
    fn nothing_to_compare_gives_no_references() {
        let mine = vec![scan_at(0.0, 1.0, 0.0)];
        let cfg = ScanPairConfig::default();
        assert!(ReferenceScans::new(&mine, &[(1.0, 0.0, 0)], &[], &cfg).is_none());
    }
}
