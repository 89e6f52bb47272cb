//! Radio evidence on a sparse radio map: how much more likely a scan is where the walker
//! stands than somewhere else, learned from the survey itself.
//!
//! Woodman & Harle (2009) assume a complete survey: every cell holds a fingerprint, and a
//! scan far from all of them rules a place out. Ordinary walks cover 15–30 % of a floor's
//! cells with a few scans each, so what a scan says about a cell nobody surveyed is nothing,
//! and what it says about a surveyed cell depends on how alike two fingerprints of one place
//! are *on this survey* (its phones, its stale scans, its access points).
//!
//! The evidence of scan `z` for a place `x` is the likelihood ratio of two hypotheses about
//! the distance `D = ndist(z, c_s)` ([`crate::model::wifi_distance`]) to the fingerprint of
//! the surveyed cell `s` nearest `x` along the floor:
//!
//! ```text
//!   Λ(z, x) = p(D | x is within r of s) / p(D | x is elsewhere)            (1)
//! ```
//!
//! Both densities are calibrated on the map: the pairs of surveyed cells whose centres lie
//! within a band of distances give `p(D | near)` (one band for the cell itself and its
//! neighbours, one for the cells a cell further out), the pairs at least `far_cells` cells
//! apart give `p(D | elsewhere)`; each is a Gaussian kernel density of the pairs' distances
//! (Silverman's bandwidth), and `ln Λ` is made non-increasing in `D` (a closer fingerprint is
//! never weaker evidence) and clamped to `±max_log_ratio`. A place farther than `reach_cells`
//! cells (walking) from every surveyed cell gets `Λ = 1`: the map does not know it, so the scan
//! neither favours nor excludes it (honest ignorance, not the best cell's likelihood).
//!
//! Pairs of cells stand in for a scan and its cell: most cells of an ordinary survey hold one
//! or two scans, so a cell's fingerprint is about as noisy as a scan, and the neighbouring
//! cells' distances are the spread of one place's fingerprints seen from a step or two away
//! (a little wider than the cell's own: the evidence errs on the weak side).

use crate::error::{Error, Result};
use crate::geometry::percentile::nearest_rank;
use crate::map::{CellRaster, RadioMap};
use crate::model::wifi_distance::Fingerprints;
use geo::{BoundingRect, Centroid};
use serde::{Deserialize, Serialize};

/// Radio evidence's parameters; every default in one place.
///
/// | field            | default          | meaning                                              |
/// |------------------|------------------|------------------------------------------------------|
/// | `bands_cells`    | 1.5, 3, 5, 8     | upper centre distances (in cells) of the bands a place is judged in by its nearest surveyed cell: the cell and its neighbours, then farther rings; a place beyond the last (walking) is out of reach |
/// | `far_cells`      | 12               | pairs at least this far apart (in cells), or on different floors, stand for "elsewhere"; in a building too small for `min_pairs` of them, pairs beyond the farthest band edge that has enough |
/// | `max_log_ratio`  | 3                | `ln Λ` is clamped to ± this (a factor of 20)          |
/// | `tempering`      | 0.5              | exponent on `Λ`: consecutive scans of a walk are not independent |
/// | `min_pairs`      | 20               | fewest pairs a band needs to be calibrated (a band with fewer is left out, and so are those beyond it) |
/// | `auto_below_coverage` | 0.6         | `rf.mode = "auto"` uses the evidence on maps whose surveyed share of cells is below this, containment regions above |
/// | `source`         | combined         | what a scan is compared with: `ndist`, the nearest surveyed cell's fingerprint (eq. 1 here); `pathloss`, a path-loss model per access point everywhere ([`crate::model::wifi_evidence_pathloss`]); `combined`, both added within reach of the survey and the path-loss model beyond; or `interpolated`, the interpolated map's prediction at each place ([`crate::model::wifi_evidence_interpolated`]; on the ILC mall floor it places walks worse, docs/radio-survey.md) |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct EvidenceConfig {
    /// What a scan is compared with.
    pub source: EvidenceSource,
    /// Upper centre distances of the bands, in cells, increasing.
    pub bands_cells: [f64; BANDS],
    /// Least centre distance of an "elsewhere" pair, in cells.
    pub far_cells: f64,
    /// Clamp on `ln Λ`.
    pub max_log_ratio: f64,
    /// Exponent on `Λ`.
    pub tempering: f64,
    /// Fewest pairs per band.
    pub min_pairs: usize,
    /// The surveyed share of cells below which `auto` uses the evidence.
    pub auto_below_coverage: f64,
}

/// What radio evidence compares a scan with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EvidenceSource {
    /// The fingerprint of the surveyed cell nearest each place along the floor, by `ndist`
    /// (eq. 1 here).
    Ndist,
    /// The interpolated radio map's prediction at each place
    /// ([`crate::model::wifi_evidence_interpolated`]).
    Interpolated,
    /// A path-loss model per access point, everywhere on the floor
    /// ([`crate::model::wifi_evidence_pathloss`]).
    #[serde(rename = "pathloss")]
    PathLoss,
    /// Within walking reach of a surveyed cell both `ndist` and the path-loss model (their
    /// log-ratios added: the nearest fingerprint and the access points' geometry read the
    /// scan differently), beyond it the path-loss model alone.
    #[default]
    Combined,
}

/// Bands of distance from a surveyed cell.
pub const BANDS: usize = 4;

impl Default for EvidenceConfig {
    fn default() -> Self {
        Self {
            source: EvidenceSource::default(),
            bands_cells: [1.5, 3.0, 5.0, 8.0],
            far_cells: 12.0,
            max_log_ratio: 3.0,
            tempering: 0.5,
            min_pairs: 20,
            auto_below_coverage: 0.6,
        }
    }
}

impl EvidenceConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `bands_cells` do not increase from 0.5 within 50 cells, `far_cells`
    /// is below the last band or above 200, `max_log_ratio` is outside [0, 20], `tempering` or
    /// `auto_below_coverage` outside [0, 1], or `min_pairs` below 2.
    pub fn validate(&self) -> Result<()> {
        use crate::error::check_range;
        let mut lower = 0.5;
        for b in self.bands_cells {
            check_range(
                "rf.evidence.bands_cells",
                b,
                lower..=50.0,
                "cells (increasing, from 0.5)",
            )?;
            lower = b;
        }
        check_range(
            "rf.evidence.far_cells",
            self.far_cells,
            lower..=200.0,
            "cells (at least the last band)",
        )?;
        check_range(
            "rf.evidence.max_log_ratio",
            self.max_log_ratio,
            0.0..=20.0,
            "",
        )?;
        check_range("rf.evidence.tempering", self.tempering, 0.0..=1.0, "")?;
        check_range(
            "rf.evidence.min_pairs",
            self.min_pairs as f64,
            2.0..=1e6,
            "",
        )?;
        check_range(
            "rf.evidence.auto_below_coverage",
            self.auto_below_coverage,
            0.0..=1.0,
            "",
        )
    }

    /// The band of a centre distance `r` (in cells), if within the last.
    fn band(&self, r: f64) -> Option<usize> {
        self.bands_cells.iter().position(|&b| r <= b)
    }
}

/// Step of the tabulated `ln Λ(D)`, dB.
const TABLE_STEP: f64 = 0.25;
/// Largest number of pairs a density is estimated from (an even subsample beyond).
const MAX_PAIRS: usize = 20_000;

/// `ln Λ(D)` tabulated on `D = 0, step, …`; the first value holds below, the last beyond.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LogRatio {
    values: Vec<f32>,
    step: f64,
}

impl LogRatio {
    /// Eq. (1) from the near and far pairs' distances (each non-empty), in dB.
    fn fit(near: &[f64], far: &[f64], config: &EvidenceConfig) -> Self {
        Self::fit_on(near, far, config, TABLE_STEP)
    }

    /// Eq. (1) from samples of any non-negative distance-like statistic `D` (smaller: more
    /// alike) tabulated every `step` (the densities' least bandwidth is two steps).
    pub(crate) fn fit_on(near: &[f64], far: &[f64], config: &EvidenceConfig, step: f64) -> Self {
        let margin = 20.0 * step;
        let top = near.iter().chain(far).copied().fold(0.0, f64::max) + margin;
        let n = (top / step).ceil() as usize + 1;
        let least = 2.0 * step;
        let (p_near, p_far) = (Density::of(near, least), Density::of(far, least));
        // A floor on both densities: one pair's worth spread over the whole range, so an
        // empty tail is "rare", not "impossible" (the same for both, so that where neither
        // has pairs the ratio is 1).
        let floor = 1.0 / ((near.len() + far.len()) as f64 * top);
        let raw: Vec<f64> = (0..n)
            .map(|i| {
                let d = i as f64 * step;
                ((p_near.at(d) + floor) / (p_far.at(d) + floor)).ln()
            })
            .collect();
        // Non-increasing in D: below the likeliest ratio's distance (where both densities
        // vanish and their ratio means nothing) every distance is worth that ratio; beyond
        // it, no larger distance is worth more than a smaller one.
        let peak = raw
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .map_or(0, |(i, _)| i);
        let mut values = Vec::with_capacity(n);
        let mut lowest = raw[peak];
        for (i, &r) in raw.iter().enumerate() {
            if i > peak {
                lowest = lowest.min(r);
            }
            values.push(
                (lowest.clamp(-config.max_log_ratio, config.max_log_ratio) * config.tempering)
                    as f32,
            );
        }
        Self { values, step }
    }

    /// `ln Λ` (tempered, clamped) at `D = d`.
    pub(crate) fn at(&self, d: f64) -> f32 {
        let i = ((d / self.step).round().max(0.0) as usize).min(self.values.len() - 1);
        self.values[i]
    }
}

/// What the model-based sources' calibration scored (the last fields of their reports).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StandInScores {
    /// Most scans of a surveyed cell whose fingerprint stood in for a scan (1 where enough
    /// cells hold one scan, else every cell's).
    pub stand_in_max_scans: u32,
    /// Stand-ins scored at their own place ("here").
    pub here_samples: usize,
    /// Scores far from the stand-in's own place ("elsewhere").
    pub elsewhere_samples: usize,
    /// Median statistic `x` of each (eq. 1 of the source).
    pub median_here: f64,
    /// The same for the far places.
    pub median_elsewhere: f64,
    /// Centre distance from which a cell stood for "elsewhere", in cells.
    pub elsewhere_cells: f64,
}

impl StandInScores {
    /// The summary of the (checked, thinned) scores.
    pub(crate) fn of(
        here: &[f64],
        far: &[f64],
        stand_in_max_scans: u32,
        elsewhere_cells: f64,
    ) -> Self {
        Self {
            stand_in_max_scans,
            here_samples: here.len(),
            elsewhere_samples: far.len(),
            median_here: median(here),
            median_elsewhere: median(far),
            elsewhere_cells,
        }
    }
}

/// Checks that the model-based sources' calibration has `min_pairs` scores of each kind —
/// stand-ins at their own place (`here`, described by `what[0]`) and far from it (`far`,
/// `what[1]`) — and thins both to [`MAX_PAIRS`].
///
/// # Errors
///
/// [`Error::NotEnough`] naming the kind that falls short.
pub(crate) fn enough_scores(
    here: &mut Vec<f64>,
    far: &mut Vec<f64>,
    config: &EvidenceConfig,
    what: [&str; 2],
) -> Result<()> {
    if here.len() < config.min_pairs || far.len() < config.min_pairs {
        let (n, what) = if here.len() < config.min_pairs {
            (here.len(), what[0])
        } else {
            (far.len(), what[1])
        };
        return Err(Error::not_enough(
            format!(
                "the radio map has {n} {what} (at least {} are needed to calibrate the radio evidence)",
                config.min_pairs
            ),
            "survey more of the building, or use --rf-mode containment",
        ));
    }
    thin(here);
    thin(far);
    Ok(())
}

/// Eq. (2) of the model-based sources from scores `x` (larger: likelier) here and far,
/// tabulated on `D = top − x` in [`STATISTIC_STEPS`] steps down to the least score.
pub(crate) fn ratio_of_scores(
    here: &[f64],
    far: &[f64],
    top: f64,
    config: &EvidenceConfig,
) -> LogRatio {
    let bottom = here.iter().chain(far).copied().fold(f64::MAX, f64::min);
    let step = ((top - bottom) / STATISTIC_STEPS).max(1e-9);
    let to_d = |v: &[f64]| v.iter().map(|x| top - x).collect::<Vec<f64>>();
    LogRatio::fit_on(&to_d(here), &to_d(far), config, step)
}

/// Table steps over the model-based sources' score range.
const STATISTIC_STEPS: f64 = 1000.0;

/// A Gaussian kernel density of samples (Silverman's rule of thumb).
struct Density {
    /// The samples, sorted.
    sorted: Vec<f64>,
    bandwidth: f64,
}

/// Kernel reach in bandwidths: samples further off weigh `exp(−KERNEL_REACH² / 2)` (< 1e-17)
/// of one at the point and are left out.
const KERNEL_REACH: f64 = 9.0;

impl Density {
    fn of(samples: &[f64], least_bandwidth: f64) -> Self {
        let n = samples.len() as f64;
        let mean = samples.iter().sum::<f64>() / n;
        let sd = (samples.iter().map(|s| (s - mean).powi(2)).sum::<f64>() / n).sqrt();
        let mut sorted = samples.to_vec();
        sorted.sort_unstable_by(f64::total_cmp);
        Self {
            sorted,
            bandwidth: (1.06 * sd * n.powf(-0.2)).max(least_bandwidth),
        }
    }

    fn at(&self, x: f64) -> f64 {
        let h = self.bandwidth;
        let from = self.sorted.partition_point(|&s| s < x - KERNEL_REACH * h);
        let to = self.sorted.partition_point(|&s| s <= x + KERNEL_REACH * h);
        let sum: f64 = self.sorted[from..to.max(from)]
            .iter()
            .map(|s| (-0.5 * ((x - s) / h).powi(2)).exp())
            .sum();
        sum / (self.sorted.len() as f64 * h * (2.0 * std::f64::consts::PI).sqrt())
    }
}

/// What the calibration found, for the run's summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EvidenceCalibration {
    /// Cell size of the map (its cells' median longest side), metres.
    pub cell_m: f64,
    /// Surveyed cells.
    pub surveyed_cells: usize,
    /// Cells within reach of a surveyed cell (surveyed ones included).
    pub cells_in_reach: usize,
    /// Cells of the map.
    pub cells: usize,
    /// Pairs per band, the "elsewhere" pairs last.
    pub pairs: Vec<usize>,
    /// Median distance of each band's pairs (the same order), dB.
    pub median_ndist: Vec<f64>,
    /// Bands calibrated (those with enough pairs, from the nearest).
    pub bands_used: usize,
    /// Centre distance from which a pair stood for "elsewhere", in cells (`far_cells`, or
    /// less in a building too small for enough such pairs; other floors always count).
    pub elsewhere_cells: f64,
}

/// Eq. (1) on every cell of a radio map, calibrated on the map.
#[derive(Debug, Clone)]
pub struct RadioEvidence {
    bands: Vec<LogRatio>,
    /// Per cell: the surveyed cell that judges it and the band, or none (out of reach).
    judge: Vec<Option<(u32, u8)>>,
    calibration: EvidenceCalibration,
}

impl RadioEvidence {
    /// Calibrates eq. (1) on `map` (whose fingerprints are `prints`) and finds each cell's
    /// judge along the floor of `raster`.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `config` fails [`EvidenceConfig::validate`]; [`Error::NotEnough`]
    /// when the map's surveyed cells give fewer than `min_pairs` pairs in the first band or far
    /// apart.
    pub fn calibrate(
        map: &RadioMap,
        prints: &Fingerprints,
        raster: &CellRaster,
        config: &EvidenceConfig,
    ) -> Result<Self> {
        config.validate()?;
        let cell_m = cell_size(map);
        let surveyed: Vec<usize> = (0..map.cells.len())
            .filter(|&c| prints.is_known(c))
            .collect();
        let centres: Vec<Option<(f64, f64)>> = map
            .cells
            .iter()
            .map(|c| c.area.centroid().map(|p| (p.x(), p.y())))
            .collect();
        // Every pair's centre distance in cells (infinite across levels: another floor is
        // elsewhere) and fingerprint distance.
        let mut all: Vec<(f64, f64)> = Vec::new();
        for (i, &a) in surveyed.iter().enumerate() {
            for &b in &surveyed[i + 1..] {
                let (Some(pa), Some(pb)) = (centres[a], centres[b]) else {
                    continue;
                };
                let r = if map.cells[a].level == map.cells[b].level {
                    (pa.0 - pb.0).hypot(pa.1 - pb.1) / cell_m
                } else {
                    f64::INFINITY
                };
                if let Some(d) = prints.cell_ndist(a, b) {
                    all.push((r, d));
                }
            }
        }
        // "Elsewhere" starts at `far_cells`, or (a building too small for enough such pairs)
        // beyond the last band; the bands kept end before it.
        let count_from = |from: f64| all.iter().filter(|(r, _)| *r >= from).count();
        let last_edge = config.bands_cells[BANDS - 1];
        let elsewhere_cells = if count_from(config.far_cells) >= config.min_pairs {
            config.far_cells
        } else {
            let below = config.bands_cells[..BANDS - 1]
                .iter()
                .rev()
                .copied()
                .find(|&edge| count_from(edge) >= config.min_pairs);
            below.unwrap_or(last_edge).max(config.bands_cells[0])
        };
        let mut samples: Vec<Vec<f64>> = vec![Vec::new(); BANDS + 1];
        for &(r, d) in &all {
            match config.band(r) {
                Some(band)
                    if config.bands_cells[band] <= elsewhere_cells && r < elsewhere_cells =>
                {
                    samples[band].push(d)
                }
                _ if r >= elsewhere_cells => samples[BANDS].push(d),
                _ => {}
            }
        }
        let pairs: Vec<usize> = samples.iter().map(Vec::len).collect();
        let bands_used = pairs[..BANDS]
            .iter()
            .zip(config.bands_cells)
            .position(|(&n, edge)| n < config.min_pairs || edge > elsewhere_cells)
            .unwrap_or(BANDS);
        if bands_used == 0 || pairs[BANDS] < config.min_pairs {
            let what = if bands_used == 0 {
                "neighbouring"
            } else {
                "distant"
            };
            let n = if bands_used == 0 {
                pairs[0]
            } else {
                pairs[BANDS]
            };
            return Err(Error::not_enough(
                format!(
                    "the radio map has {n} pairs of {what} surveyed cells (at least {} are needed to calibrate the radio evidence)",
                    config.min_pairs
                ),
                "survey more of the building, or use --rf-mode containment",
            ));
        }
        for s in &mut samples {
            thin(s);
        }
        let median_ndist = samples
            .iter()
            .map(|s| if s.is_empty() { f64::NAN } else { median(s) })
            .collect();
        let bands = (0..bands_used)
            .map(|b| LogRatio::fit(&samples[b], &samples[BANDS], config))
            .collect();
        let is_source: Vec<bool> = (0..map.cells.len()).map(|c| prints.is_known(c)).collect();
        let reach_cells = config.bands_cells[bands_used - 1];
        let reach = raster.walking_reach(&is_source, (reach_cells + 0.5) * cell_m);
        let judge: Vec<Option<(u32, u8)>> = reach
            .iter()
            .map(|r| {
                let (source, mean_distance) = (*r)?;
                // Centre distance ≈ the mean distance of the cell's floor to the surveyed
                // cell's edge plus half a cell.
                let r = if is_source.get(source).copied().unwrap_or(false) && mean_distance == 0.0 {
                    0.0
                } else {
                    mean_distance / cell_m + 0.5
                };
                config
                    .band(r)
                    .filter(|&b| b < bands_used)
                    .map(|b| (source as u32, b as u8))
            })
            .collect();
        let calibration = EvidenceCalibration {
            cell_m,
            surveyed_cells: surveyed.len(),
            cells_in_reach: judge.iter().filter(|j| j.is_some()).count(),
            cells: map.cells.len(),
            pairs,
            median_ndist,
            bands_used,
            elsewhere_cells,
        };
        Ok(Self {
            bands,
            judge,
            calibration,
        })
    }

    /// What the calibration found.
    #[must_use]
    pub fn calibration(&self) -> &EvidenceCalibration {
        &self.calibration
    }

    /// `ln Λ` (tempered) of a scan on every cell, from the scan's `ndist` to every cell
    /// ([`Fingerprints::ndist`]); 0 for cells out of reach.
    #[must_use]
    pub fn log_ratios(&self, ndist: &[Option<f64>]) -> Vec<f32> {
        self.judged_log_ratios(ndist)
            .into_iter()
            .map(|r| r.unwrap_or(0.0))
            .collect()
    }

    /// [`Self::log_ratios`] with `None` for the cells out of walking reach of the survey
    /// (the cells it does not judge).
    #[must_use]
    pub fn judged_log_ratios(&self, ndist: &[Option<f64>]) -> Vec<Option<f32>> {
        self.judge
            .iter()
            .map(|j| {
                let (s, band) = (*j)?;
                Some(
                    ndist
                        .get(s as usize)
                        .copied()
                        .flatten()
                        .map_or(0.0, |d| self.bands[band as usize].at(d)),
                )
            })
            .collect()
    }
}

/// The map's cell size: the median of its cells' longer bounding-box sides.
pub(crate) fn cell_size(map: &RadioMap) -> f64 {
    let sides: Vec<f64> = map
        .cells
        .iter()
        .filter_map(|c| c.area.bounding_rect())
        .map(|r| r.width().max(r.height()))
        .filter(|s| *s > 0.0)
        .collect();
    if sides.is_empty() {
        return 1.0;
    }
    median(&sides)
}

/// The nearest-rank median of non-empty samples.
pub(crate) fn median(samples: &[f64]) -> f64 {
    let mut sorted = samples.to_vec();
    sorted.sort_by(f64::total_cmp);
    nearest_rank(&sorted, 50)
}

/// Keeps at most [`MAX_PAIRS`] samples, evenly spaced.
pub(crate) fn thin(samples: &mut Vec<f64>) {
    if samples.len() > MAX_PAIRS {
        let n = samples.len();
        *samples = (0..MAX_PAIRS).map(|i| samples[i * n / MAX_PAIRS]).collect();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ratio_falls_with_distance_and_is_clamped() {
        let near: Vec<f64> = (0..200).map(|i| 4.0 + f64::from(i % 7)).collect();
        let far: Vec<f64> = (0..400).map(|i| 14.0 + f64::from(i % 13)).collect();
        let config = EvidenceConfig {
            tempering: 1.0,
            ..Default::default()
        };
        let l = LogRatio::fit(&near, &far, &config);
        assert!(
            l.at(5.0) > 1.0,
            "a near distance favours the place: {}",
            l.at(5.0)
        );
        assert!(
            l.at(20.0) < -1.0,
            "a far one speaks against it: {}",
            l.at(20.0)
        );
        assert!(l.values.windows(2).all(|w| w[1] <= w[0]));
        assert!(l.values.iter().all(|v| v.abs() <= 3.0 + 1e-6));
        assert_eq!(l.at(1e9), *l.values.last().unwrap());
    }

    #[test]
    fn tempering_scales_the_evidence() {
        let near: Vec<f64> = (0..200).map(|i| 4.0 + f64::from(i % 7)).collect();
        let far: Vec<f64> = (0..400).map(|i| 14.0 + f64::from(i % 13)).collect();
        let full = LogRatio::fit(
            &near,
            &far,
            &EvidenceConfig {
                tempering: 1.0,
                ..Default::default()
            },
        );
        let half = LogRatio::fit(
            &near,
            &far,
            &EvidenceConfig {
                tempering: 0.5,
                ..Default::default()
            },
        );
        for d in [0.0, 6.0, 12.0, 30.0] {
            assert!((half.at(d) - 0.5 * full.at(d)).abs() < 1e-5);
        }
    }
}
