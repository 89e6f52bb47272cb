//! A radio map that knows what it does not know: per access point, a Gaussian process over
//! the surveyed cells' mean RSSI (Ferris, Hähnel & Fox 2006, "Gaussian processes for signal
//! strength-based location estimation"), predicted at every cell of the map with its
//! variance; cells far from any survey get the prior — the access point's mean over the
//! survey with its whole variance — and are *unknown*.
//!
//! **Data.** A surveyed cell `i` with `n_i` scans has, per access point `a`, the value
//! `y_ia` = mean RSSI over its scans, scans that did not hear `a` counted at the fill
//! `r_miss` (as [`crate::model::wifi_distance`] fills them). The prior is `μ_a` and `σ²_a`,
//! the mean and variance of `y_·a` over the surveyed cells.
//!
//! **Kernel, calibrated on the survey.** In units of `σ_a` every access point shares one
//! kernel `k(d) = exp(−d/ℓ)` (exponential; `d` the distance between cell centres, cells of
//! other levels unrelated) and one per-scan noise ratio `λ`: the semivariogram pooled over
//! the access points (Cressie 1993, eq. 2.2.8), `γ(h) = ½ E[(z_ia − z_ja)²]` over pairs of
//! surveyed cells `h` apart (`z = (y − μ_a)/σ_a`), is fitted by pair-weighted least squares
//! as `γ(h) = λ·E[1/n] + 1 − exp(−h/ℓ)` ([`fit_variogram`](super::radio_variogram)).
//!
//! **Prediction, local.** Each cell `c` is predicted from its `M` nearest surveyed cells on
//! its level (simple kriging with a known mean; Rasmussen & Williams 2006, eqs. 2.23–2.24,
//! on a local neighbourhood): with `K_ij = k(d_ij) + δ_ij λ/n_j` and `k_j = k(d_cj)`,
//! `w = K⁻¹k`, the mean is `m_ca = μ_a + Σ_j w_j (y_ja − μ_a)` and the share of the prior
//! variance left is `v_c = 1 − kᵀw`. The weights do not depend on the access point, so one
//! `M × M` solve per cell serves them all. A single scan at `c` reads `a` with variance
//! `s²_ca = σ²_a (v_c + λ) + s²_0`, `s²_0` the readings' resolution.
//!
//! **Ignorance.** A cell nobody surveyed with `v_c` above `max_share` is unknown: the data
//! explain less than that share of the prior, it is no candidate and has no likelihood. A
//! surveyed cell is always known (it was measured, however noisily).

use crate::error::{Error, Result};
use crate::map::RadioMap;
use crate::sensor::WifiScan;
use nalgebra::{DMatrix, DVector};
use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

use super::radio_variogram::{Survey, VariogramFit, fit_variogram};

/// Parameters of [`RadioInterpolation`]; every default in one place.
///
/// | field            | default | meaning                                                      |
/// |------------------|---------|--------------------------------------------------------------|
/// | `neighbours`     | 12      | nearest surveyed cells a cell is predicted from (`M`)        |
/// | `max_share`      | 0.5     | cells whose variance left exceeds this share are unknown     |
/// | `reading_floor`  | 1 dB²   | variance every reading has at least (`s²_0`, 1 dB readings)  |
/// | `length_scale`   | fitted  | the kernel's `ℓ`, metres (`None`: fitted on the survey)      |
/// | `noise_ratio`    | fitted  | per-scan noise over signal variance `λ` (`None`: fitted)     |
/// | `variogram_bin`  | 3 m     | width of the variogram's distance bins                       |
/// | `variogram_max`  | 60 m    | pairs farther apart do not enter the variogram               |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct InterpolationConfig {
    /// Nearest surveyed cells a cell is predicted from.
    pub neighbours: usize,
    /// Cells whose variance left exceeds this share of the prior's are unknown.
    pub max_share: f64,
    /// Variance every reading has at least, dB².
    pub reading_floor: f64,
    /// The kernel's length scale, metres; `None`: fitted on the survey.
    pub length_scale: Option<f64>,
    /// Per-scan noise variance over signal variance; `None`: fitted on the survey.
    pub noise_ratio: Option<f64>,
    /// Width of the variogram's distance bins, metres.
    pub variogram_bin: f64,
    /// Pairs of cells farther apart do not enter the variogram, metres.
    pub variogram_max: f64,
}

impl Default for InterpolationConfig {
    fn default() -> Self {
        Self {
            neighbours: 12,
            max_share: 0.5,
            reading_floor: 1.0,
            length_scale: None,
            noise_ratio: None,
            variogram_bin: 3.0,
            variogram_max: 60.0,
        }
    }
}

impl InterpolationConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `neighbours` is outside [1, 64], `max_share` outside (0, 1],
    /// `reading_floor` not positive, a given `length_scale` or `noise_ratio` not positive, or
    /// the variogram's bin not positive or above its maximum distance.
    pub fn validate(&self) -> Result<()> {
        use crate::error::check_range;
        use std::ops::Bound::{Excluded, Included, Unbounded};
        check_range(
            "interpolation.neighbours",
            self.neighbours as f64,
            1.0..=64.0,
            "",
        )?;
        check_range(
            "interpolation.max_share",
            self.max_share,
            (Excluded(0.0), Included(1.0)),
            "",
        )?;
        let positive = (Excluded(0.0), Unbounded);
        check_range(
            "interpolation.reading_floor",
            self.reading_floor,
            positive,
            "dB²",
        )?;
        if let Some(l) = self.length_scale {
            check_range("interpolation.length_scale", l, positive, "m")?;
        }
        if let Some(r) = self.noise_ratio {
            check_range("interpolation.noise_ratio", r, positive, "")?;
        }
        check_range(
            "interpolation.variogram_max",
            self.variogram_max,
            positive,
            "m",
        )?;
        check_range(
            "interpolation.variogram_bin",
            self.variogram_bin,
            (Excluded(0.0), Included(self.variogram_max)),
            "m",
        )
    }
}

/// The per-access-point Gaussian-process radio map of a [`RadioMap`].
#[derive(Debug, Clone)]
pub struct RadioInterpolation {
    /// Per cell: surveyed (always known: it was measured).
    surveyed: Vec<bool>,
    columns: FxHashMap<String, usize>,
    /// Per cell: the share of the prior variance left, `v_c` (1 without data).
    share: Vec<f64>,
    /// Predicted means, row-major (cell, access point), dBm; rows of unknown cells unused.
    means: Vec<f32>,
    /// Per known cell: the log-likelihood of a scan that hears nothing.
    silent: Vec<Option<f64>>,
    /// The same under the prior (every access point at its prior mean and whole variance).
    prior_silent: f64,
    /// The data the map was predicted from: the prior (its `mean` and `var` per access
    /// point) and, for [`Self::held_out_scans`], the surveyed cells.
    survey: Survey,
    fit: VariogramFit,
    missing: f64,
    config: InterpolationConfig,
}

/// The surveyed cells of `map` (their centres `centres_all`) as the interpolation's data.
fn survey_of(
    map: &RadioMap,
    centres_all: &[(f64, f64, i32)],
    columns: &FxHashMap<String, usize>,
    (missing, min_scans): (f64, u32),
) -> Survey {
    let n_ap = columns.len();
    let mut s = Survey {
        cells: Vec::new(),
        centres: Vec::new(),
        scans: Vec::new(),
        values: Vec::new(),
        mean: vec![0.0; n_ap],
        var: vec![0.0; n_ap],
        within_ss: vec![0.0; n_ap],
        within_dof: 0.0,
    };
    for (i, c) in map.cells.iter().enumerate() {
        if c.radio.scans < min_scans.max(1) || !centres_all[i].0.is_finite() {
            continue;
        }
        let scans = f64::from(c.radio.scans);
        let start = s.values.len();
        s.values.resize(start + n_ap, missing);
        for (bssid, stats) in &c.radio.aps {
            let (Some(&col), Some(mean)) = (columns.get(bssid), stats.mean()) else {
                continue;
            };
            let heard = f64::from(stats.n);
            s.values[start + col] = (heard * mean.max(missing) + (scans - heard) * missing) / scans;
            s.within_ss[col] += within_cell_squares(stats, scans, missing);
        }
        s.within_dof += scans - 1.0;
        s.cells.push(i);
        s.centres.push(centres_all[i]);
        s.scans.push(scans);
    }
    let n = s.cells.len().max(1) as f64;
    for row in s.values.chunks(n_ap.max(1)) {
        for (m, y) in s.mean.iter_mut().zip(row) {
            *m += y / n;
        }
    }
    for row in s.values.chunks(n_ap.max(1)) {
        for ((v, m), y) in s.var.iter_mut().zip(&s.mean).zip(row) {
            *v += (y - m).powi(2) / n;
        }
    }
    s
}

/// Squared deviations of one cell's per-scan values of one access point from their mean
/// (the histogram's 1 dB bins, misses and weaker readings at `missing`).
fn within_cell_squares(stats: &crate::map::ApStats, scans: f64, missing: f64) -> f64 {
    let misses = scans - f64::from(stats.n);
    let values = || {
        stats
            .hist
            .iter()
            .map(|(&bin, &count)| (f64::from(bin).max(missing), f64::from(count)))
            .chain(std::iter::once((missing, misses)))
    };
    let mean = values().map(|(v, k)| v * k).sum::<f64>() / scans;
    values().map(|(v, k)| k * (v - mean).powi(2)).sum()
}

impl RadioInterpolation {
    /// The interpolated map of `map`: surveyed cells are those with at least `min_scans`
    /// scans (and at least one); readings weaker than `missing_rssi` and scans that did not
    /// hear an access point count as `missing_rssi`.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `config` fails [`InterpolationConfig::validate`];
    /// [`Error::NotEnough`] when no cell of `map` is surveyed.
    pub fn new(
        map: &RadioMap,
        missing_rssi: f64,
        min_scans: u32,
        config: &InterpolationConfig,
    ) -> Result<Self> {
        config.validate()?;
        let columns = map.access_point_columns();
        let centres = map.cell_centres();
        let survey = survey_of(map, &centres, &columns, (missing_rssi, min_scans));
        if survey.cells.is_empty() {
            return Err(Error::not_enough(
                "the radio map has no surveyed cell to interpolate from",
                "survey the building first",
            ));
        }
        let mut fit = fit_variogram(&survey, config.variogram_bin, config.variogram_max);
        if let Some(l) = config.length_scale {
            fit.length_scale = l;
        }
        if let Some(r) = config.noise_ratio {
            fit.noise_ratio = r;
        }
        let n_ap = columns.len();
        let mut share = vec![1.0; map.cells.len()];
        let mut means = vec![0_f32; map.cells.len() * n_ap];
        for (c, &(x, y, level)) in centres.iter().enumerate() {
            let row = &mut means[c * n_ap..(c + 1) * n_ap];
            if !x.is_finite() {
                kriged_means(&survey, &[], &[], row);
                continue;
            }
            let (nb, w, v) = krige(&survey, &fit, config.neighbours, (x, y, level), None);
            share[c] = v;
            kriged_means(&survey, &nb, &w, row);
        }
        let mut surveyed = vec![false; map.cells.len()];
        for &c in &survey.cells {
            surveyed[c] = true;
        }
        let mut me = Self {
            surveyed,
            columns,
            share,
            means,
            silent: Vec::new(),
            prior_silent: 0.0,
            survey,
            fit,
            missing: missing_rssi,
            config: *config,
        };
        me.prior_silent = (0..n_ap)
            .map(|a| me.prior_log_likelihood(a, missing_rssi))
            .sum();
        me.silent = (0..map.cells.len())
            .map(|c| {
                me.is_known(c).then(|| {
                    (0..n_ap)
                        .map(|a| me.reading_log_likelihood(c, a, missing_rssi))
                        .sum()
                })
            })
            .collect();
        Ok(me)
    }

    /// The kernel fitted (or configured).
    #[must_use]
    pub fn fit(&self) -> &VariogramFit {
        &self.fit
    }

    /// True when cell `c` is surveyed or predicted (its variance left at most `max_share`).
    #[must_use]
    pub fn is_known(&self, c: usize) -> bool {
        self.surveyed.get(c).copied().unwrap_or(false)
            || self
                .share
                .get(c)
                .is_some_and(|&v| v <= self.config.max_share)
    }

    /// The share of the prior variance left at cell `c`, `v_c` in [0, 1] (1 without data).
    #[must_use]
    pub fn variance_share(&self, c: usize) -> f64 {
        self.share.get(c).copied().unwrap_or(1.0)
    }

    /// Predicted mean RSSI of `bssid` at cell `c` and its variance for one scan (dBm, dB²);
    /// `None` for an access point the map never heard or a cell it does not have.
    #[must_use]
    pub fn predict(&self, c: usize, bssid: &str) -> Option<(f64, f64)> {
        let &a = self.columns.get(bssid)?;
        (c < self.share.len()).then(|| (self.mean(c, a), self.variance(c, a)))
    }

    fn mean(&self, c: usize, a: usize) -> f64 {
        f64::from(self.means[c * self.survey.mean.len() + a])
    }

    /// `s²_ca = σ²_a (v_c + λ) + s²_0`.
    fn variance(&self, c: usize, a: usize) -> f64 {
        self.scan_variance(a, self.share[c])
    }

    /// A scan's variance of access point `a` where the share `v` of its prior variance is
    /// left: `σ²_a (v + λ) + s²_0` (`v = 1`: the prior, as at a cell the survey explains none
    /// of).
    fn scan_variance(&self, a: usize, v: f64) -> f64 {
        self.survey.var[a] * (v + self.fit.noise_ratio) + self.config.reading_floor
    }

    /// `ln N(z; m_ca, s²_ca)`.
    fn reading_log_likelihood(&self, c: usize, a: usize, z: f64) -> f64 {
        gaussian_log_density(z, self.mean(c, a), self.variance(c, a))
    }

    /// `ln N(z; μ_a, σ²_a (1 + λ) + s²_0)`: a reading under the prior.
    fn prior_log_likelihood(&self, a: usize, z: f64) -> f64 {
        gaussian_log_density(z, self.survey.mean[a], self.scan_variance(a, 1.0))
    }

    /// The readings of `scan` the map can use: (access point column, RSSI floored at the
    /// fill).
    #[must_use]
    pub fn readings(&self, scan: &WifiScan) -> Vec<(usize, f64)> {
        scan.readings
            .iter()
            .filter_map(|r| Some((*self.columns.get(&r.bssid)?, r.rssi.max(self.missing))))
            .collect()
    }

    /// `ln p(z | c)` of `scan` at every cell, independent readings over every access point
    /// of the map (unheard ones at the fill); `None` for unknown cells.
    #[must_use]
    pub fn log_likelihoods(&self, scan: &WifiScan) -> Vec<Option<f64>> {
        self.log_likelihoods_of(&self.readings(scan))
    }

    /// [`Self::log_likelihoods`] of the readings `heard` ([`Self::readings`]).
    fn log_likelihoods_of(&self, heard: &[(usize, f64)]) -> Vec<Option<f64>> {
        self.silent
            .iter()
            .enumerate()
            .map(|(c, base)| base.map(|b| b + self.heard_terms(c, heard)))
            .collect()
    }

    /// `Σ_heard ln N(z_a; m_ca, s²_ca) − ln N(r_miss; m_ca, s²_ca)`: what the heard readings
    /// change from a silent scan's log-likelihood at cell `c`.
    fn heard_terms(&self, c: usize, heard: &[(usize, f64)]) -> f64 {
        heard
            .iter()
            .map(|&(a, z)| heard_change(z, self.missing, self.mean(c, a), self.variance(c, a)))
            .sum()
    }

    /// `ln p(z | c) − ln p(z | prior)` of the readings `heard` ([`Self::readings`]) at every
    /// cell: how much better the map's prediction at `c` explains the scan than the access
    /// points' prior does; `None` for unknown cells.
    #[must_use]
    pub fn log_ratios(&self, heard: &[(usize, f64)]) -> Vec<Option<f64>> {
        let prior = self.prior_silent
            + heard
                .iter()
                .map(|&(a, z)| {
                    let (mu, s2) = (self.survey.mean[a], self.scan_variance(a, 1.0));
                    heard_change(z, self.missing, mu, s2)
                })
                .sum::<f64>();
        let mut ll = self.log_likelihoods_of(heard);
        for l in ll.iter_mut().flatten() {
            *l -= prior;
        }
        ll
    }

    /// Each surveyed cell's fingerprint as a scan, and how its own place explains it when the
    /// map is predicted without it (leave-one-out): the stand-ins of scans taken where nobody
    /// surveyed, for calibrating [`Self::log_ratios`] on the survey itself.
    #[must_use]
    pub fn held_out_scans(&self) -> Vec<HeldOutScan> {
        let s = &self.survey;
        let n_ap = s.mean.len();
        let mut row = vec![0_f32; n_ap];
        (0..s.cells.len())
            .map(|i| {
                let y = &s.values[i * n_ap..(i + 1) * n_ap];
                let readings: Vec<(usize, f64)> = y
                    .iter()
                    .enumerate()
                    .filter(|(_, v)| **v > self.missing)
                    .map(|(a, &v)| (a, v))
                    .collect();
                let (nb, w, v) = krige(s, &self.fit, self.config.neighbours, s.centres[i], Some(i));
                let own = (v <= self.config.max_share).then(|| {
                    kriged_means(s, &nb, &w, &mut row);
                    (0..n_ap)
                        .map(|a| {
                            let m = f64::from(row[a]);
                            gaussian_log_density(y[a], m, self.scan_variance(a, v))
                                - self.prior_log_likelihood(a, y[a])
                        })
                        .sum()
                });
                HeldOutScan {
                    cell: s.cells[i],
                    scans: s.scans[i] as u32,
                    readings,
                    own_log_ratio: own,
                }
            })
            .collect()
    }
}

/// `ln N(z; m, s²)`.
fn gaussian_log_density(z: f64, m: f64, s2: f64) -> f64 {
    -0.5 * ((z - m).powi(2) / s2 + (std::f64::consts::TAU * s2).ln())
}

/// `ln N(z; m, s²) − ln N(r_miss; m, s²)`: what hearing a reading `z` changes from not
/// hearing it (the normalising terms cancel).
fn heard_change(z: f64, missing: f64, m: f64, s2: f64) -> f64 {
    -0.5 * ((z - m).powi(2) - (missing - m).powi(2)) / s2
}

/// The predicted means `m_a = μ_a + Σ_j w_j (y_ja − μ_a)` of every access point from the
/// surveyed cells `nb` weighted `w` (none: the prior), into `row`.
fn kriged_means(survey: &Survey, nb: &[usize], w: &[f64], row: &mut [f32]) {
    let n_ap = survey.mean.len();
    for (m, &mu) in row.iter_mut().zip(&survey.mean) {
        *m = mu as f32;
    }
    for (&j, &wj) in nb.iter().zip(w) {
        let yj = &survey.values[j * n_ap..(j + 1) * n_ap];
        for ((m, &y), &mu) in row.iter_mut().zip(yj).zip(&survey.mean) {
            *m += (wj * (y - mu)) as f32;
        }
    }
}

/// A surveyed cell's fingerprint as a scan ([`RadioInterpolation::held_out_scans`]).
#[derive(Debug, Clone, PartialEq)]
pub struct HeldOutScan {
    /// The cell (index in the map).
    pub cell: usize,
    /// Its scans (a fingerprint of one scan is a scan).
    pub scans: u32,
    /// Its access points' mean RSSI where it heard them: (column, dBm).
    pub readings: Vec<(usize, f64)>,
    /// `ln p(y | c) − ln p(y | prior)` at the cell itself, predicted without it; `None`
    /// where the cell would be unknown without its own data.
    pub own_log_ratio: Option<f64>,
}

/// Simple-kriging weights of the `m` nearest surveyed cells of `at`'s level (but `except`): their survey
/// indices, the weights `w = K⁻¹k` and the variance share left `v = 1 − kᵀw`.
fn krige(
    survey: &Survey,
    fit: &VariogramFit,
    m: usize,
    at: (f64, f64, i32),
    except: Option<usize>,
) -> (Vec<usize>, Vec<f64>, f64) {
    let dist = |a: (f64, f64, i32), b: (f64, f64, i32)| (a.0 - b.0).hypot(a.1 - b.1);
    let mut near: Vec<(f64, usize)> = survey
        .centres
        .iter()
        .enumerate()
        .filter(|&(j, c)| c.2 == at.2 && Some(j) != except)
        .map(|(j, &c)| (dist(at, c), j))
        .collect();
    // The m nearest (distance, then index: a total order), sorted: a selection, not a sort
    // of every surveyed cell, at each of the map's cells.
    let order = |a: &(f64, usize), b: &(f64, usize)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
    if m > 0 && near.len() > m {
        near.select_nth_unstable_by(m - 1, order);
    }
    near.truncate(m);
    near.sort_by(order);
    if near.is_empty() {
        return (Vec::new(), Vec::new(), 1.0);
    }
    let nb: Vec<usize> = near.iter().map(|&(_, j)| j).collect();
    let kern = |d: f64| (-d / fit.length_scale).exp();
    let big_k = DMatrix::from_fn(nb.len(), nb.len(), |i, j| {
        let noise = if i == j {
            fit.noise_ratio / survey.scans[nb[i]]
        } else {
            0.0
        };
        kern(dist(survey.centres[nb[i]], survey.centres[nb[j]])) + noise
    });
    let k = DVector::from_iterator(nb.len(), near.iter().map(|&(d, _)| kern(d)));
    // K is a kernel matrix plus a positive diagonal: positive definite.
    let Some(chol) = big_k.cholesky() else {
        return (Vec::new(), Vec::new(), 1.0);
    };
    let w = chol.solve(&k);
    let v = (1.0 - k.dot(&w)).clamp(0.0, 1.0);
    (nb, w.iter().copied().collect(), v)
}

#[cfg(test)]
#[path = "radio_interpolation_tests.rs"]
mod tests;
