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
//!
//! The nugget `λ` is measured directly where the survey allows: the pooled within-cell
//! variance of single scans (cells of two scans or more), in units of each access point's
//! `σ²_a`, `λ = Σ_a SS_a/σ²_a / (A·Σ_i (n_i − 1))`; only `ℓ` is then fitted to the
//! variogram. A survey of one scan per cell fits both. (On the ILC mall floor the two agree:
//! `λ` = 0.40 within cells, 0.46 from the variogram.)

use serde::Serialize;

/// The surveyed cells as the interpolation sees them.
#[derive(Debug, Clone)]
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
    /// Per access point, squared deviations of the per-scan values from their cell's mean,
    /// summed over the surveyed cells, dB².
    pub within_ss: Vec<f64>,
    /// Their degrees of freedom: scans less one, summed over the surveyed cells.
    pub within_dof: f64,
}

/// Access points whose values vary less than this over the survey (dB²) do not enter the
/// variogram: heard almost nowhere, their standardised values are noise.
const MIN_AP_VARIANCE: f64 = 1.0;

/// The smallest noise ratio `λ`: zero would trust one scan exactly.
const MIN_NOISE_RATIO: f64 = 0.01;

/// The kernel's parameters and how they were found.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct VariogramFit {
    /// The exponential kernel's length scale `ℓ`, metres.
    pub length_scale: f64,
    /// Per-scan noise variance over signal variance, `λ`.
    pub noise_ratio: f64,
    /// Pairs of surveyed cells the variogram was computed from (0: nothing fitted, the
    /// fallback `ℓ` = one bin used, and `λ` = 1 unless measured within cells).
    pub pairs: usize,
    /// True when `λ` is the pooled within-cell variance, false when fitted to the variogram.
    pub noise_within_cells: bool,
}

/// Fits the kernel on `survey` (see the module's documentation); with no pair of surveyed
/// cells on one level within `max_distance`, `ℓ` is one bin (and `λ` is 1 unless measured
/// within cells).
pub(crate) fn fit_variogram(survey: &Survey, bin: f64, max_distance: f64) -> VariogramFit {
    let n_ap = survey.mean.len();
    let used: Vec<usize> = (0..n_ap)
        .filter(|&a| survey.var[a] > MIN_AP_VARIANCE)
        .collect();
    let bins = (max_distance / bin).ceil() as usize;
    let mut sum = vec![0.0; bins];
    let mut pairs = vec![0_usize; bins];
    // Each cell's standardised values of the access points used, once (not per pair).
    let k = used.len();
    let z: Vec<f64> = (0..survey.cells.len())
        .flat_map(|i| {
            used.iter().map(move |&a| {
                (survey.values[i * n_ap + a] - survey.mean[a]) / survey.var[a].sqrt()
            })
        })
        .collect();
    for i in 0..survey.cells.len() {
        for j in i + 1..survey.cells.len() {
            let (p, q) = (survey.centres[i], survey.centres[j]);
            let h = (p.0 - q.0).hypot(p.1 - q.1);
            if p.2 != q.2 || h >= max_distance || k == 0 {
                continue;
            }
            let b = ((h / bin) as usize).min(bins - 1);
            let (zi, zj) = (&z[i * k..(i + 1) * k], &z[j * k..(j + 1) * k]);
            let sq: f64 = zi.iter().zip(zj).map(|(x, y)| (x - y).powi(2)).sum();
            sum[b] += 0.5 * sq / used.len() as f64;
            pairs[b] += 1;
        }
    }
    let total: usize = pairs.iter().sum();
    let within = (survey.within_dof > 0.0 && !used.is_empty()).then(|| {
        used.iter()
            .map(|&a| survey.within_ss[a] / survey.var[a])
            .sum::<f64>()
            / (used.len() as f64 * survey.within_dof)
    });
    if total == 0 {
        return VariogramFit {
            length_scale: bin,
            noise_ratio: within.unwrap_or(1.0).max(MIN_NOISE_RATIO),
            pairs: 0,
            noise_within_cells: within.is_some(),
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
    // λ (unless measured within cells) in [0, 4] by 0.01. The loss is smooth and cheap.
    let lambdas: Vec<f64> = match within {
        Some(l) => vec![l],
        None => (0..=400).map(|r| f64::from(r) * 0.01).collect(),
    };
    let mut best = (f64::INFINITY, bin, 1.0);
    let (lo, hi) = (0.1 * bin, 10.0 * max_distance);
    let steps = 400;
    for s in 0..=steps {
        let ell = lo * (hi / lo).powf(f64::from(s) / f64::from(steps));
        for &lambda in &lambdas {
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
        noise_ratio: best.2.max(MIN_NOISE_RATIO),
        pairs: total,
        noise_within_cells: within.is_some(),
    }
}
