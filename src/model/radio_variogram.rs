//! The kernel of the interpolated radio map ([`super::radio_interpolation`]), calibrated on
//! the survey itself: the empirical semivariogram pooled over access points (Cressie 1993,
//! eq. 2.2.8, Matheron's estimator), each access point's values standardised by its own mean
//! and spread over the surveyed cells, fitted by pair-weighted least squares (Cressie 1985)
//! with an exponential model and a nugget of per-scan noise:
//!
//! `γ(h) = λ·E[1/n] + 1 − exp(−h/ℓ)`,
//!
//! where `E[1/n]` is the mean over surveyed cells of one over their scans (two cells' means of
//! `n_i` and `n_j` scans differ by noise of variance `λ(1/n_i + 1/n_j)`, in units of `σ²_a`).

use serde::Serialize;

/// The surveyed cells as the interpolation sees them.
pub(crate) struct Survey {
    /// Index in the map of each surveyed cell.
    pub cells: Vec<usize>,
    /// Its centre and level.
    pub centres: Vec<(f64, f64, i32)>,
    /// Its scans.
    pub scans: Vec<f64>,
    /// Its values `y_ia`, row-major (cell, access point), dBm.
    pub values: Vec<f64>,
    /// Prior mean `μ_a` per access point, dBm.
    pub mean: Vec<f64>,
    /// Prior variance `σ²_a` per access point, dB².
    pub var: Vec<f64>,
}

/// Access points whose values vary less than this over the survey (dB²) do not enter the
/// variogram: heard almost nowhere, their standardised values are noise.
const MIN_AP_VARIANCE: f64 = 1.0;

/// The kernel's parameters and how they were found.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct VariogramFit {
    /// The exponential kernel's length scale `ℓ`, metres.
    pub length_scale: f64,
    /// Per-scan noise variance over signal variance, `λ`.
    pub noise_ratio: f64,
    /// Pairs of surveyed cells the variogram was computed from (0: nothing fitted, the
    /// fallback `ℓ` = one bin and `λ` = 1 used).
    pub pairs: usize,
}

/// Fits the kernel on `survey` (see the module's documentation); with no pair of surveyed
/// cells on one level within `max_distance`, `ℓ` is one bin and `λ` is 1.
pub(crate) fn fit_variogram(survey: &Survey, bin: f64, max_distance: f64) -> VariogramFit {
    let n_ap = survey.mean.len();
    let used: Vec<usize> = (0..n_ap)
        .filter(|&a| survey.var[a] > MIN_AP_VARIANCE)
        .collect();
    let bins = (max_distance / bin).ceil() as usize;
    let mut sum = vec![0.0; bins];
    let mut pairs = vec![0_usize; bins];
    let z =
        |i: usize, a: usize| (survey.values[i * n_ap + a] - survey.mean[a]) / survey.var[a].sqrt();
    for i in 0..survey.cells.len() {
        for j in i + 1..survey.cells.len() {
            let (p, q) = (survey.centres[i], survey.centres[j]);
            let h = (p.0 - q.0).hypot(p.1 - q.1);
            if p.2 != q.2 || h >= max_distance || used.is_empty() {
                continue;
            }
            let b = ((h / bin) as usize).min(bins - 1);
            let sq: f64 = used.iter().map(|&a| (z(i, a) - z(j, a)).powi(2)).sum();
            sum[b] += 0.5 * sq / used.len() as f64;
            pairs[b] += 1;
        }
    }
    let total: usize = pairs.iter().sum();
    if total == 0 {
        return VariogramFit {
            length_scale: bin,
            noise_ratio: 1.0,
            pairs: 0,
        };
    }
    let gamma: Vec<f64> = sum
        .iter()
        .zip(&pairs)
        .map(|(s, &n)| if n > 0 { s / n as f64 } else { 0.0 })
        .collect();
    let inv_n = survey.scans.iter().map(|n| 1.0 / n).sum::<f64>() / survey.scans.len() as f64;
    let centre = |b: usize| (b as f64 + 0.5) * bin;
    // Grid search: ℓ from a tenth of a bin to ten times the largest distance, geometric;
    // λ in [0, 4] by 0.01. The loss is smooth and cheap (bins × grid).
    let mut best = (f64::INFINITY, bin, 1.0);
    let (lo, hi) = (0.1 * bin, 10.0 * max_distance);
    let steps = 400;
    for s in 0..=steps {
        let ell = lo * (hi / lo).powf(f64::from(s) / f64::from(steps));
        for r in 0..=400 {
            let lambda = f64::from(r) * 0.01;
            let loss: f64 = (0..bins)
                .filter(|&b| pairs[b] > 0)
                .map(|b| {
                    let model = lambda * inv_n + 1.0 - (-centre(b) / ell).exp();
                    pairs[b] as f64 * (gamma[b] - model).powi(2)
                })
                .sum();
            if loss < best.0 {
                best = (loss, ell, lambda);
            }
        }
    }
    VariogramFit {
        length_scale: best.1,
        // λ = 0 would trust one scan exactly; keep the smallest grid step.
        noise_ratio: best.2.max(0.01),
        pairs: total,
    }
}
