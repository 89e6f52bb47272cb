//! Resampling: which particles survive, by index. Knows nothing of poses or maps.
//!
//! Systematic resampling (Kitagawa 1996) and residual resampling (Liu & Chen 1998), both
//! O(N), writing into a caller-owned buffer so that no step allocates.

use serde::{Deserialize, Serialize};

/// Resampling scheme.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum ResampleMethod {
    /// One uniform offset, N evenly spaced pointers.
    #[default]
    Systematic,
    /// Deterministic copies of ⌊N·wᵢ⌋, the rest systematically from the residuals.
    Residual,
}

/// When and how to resample.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ResampleConfig {
    /// Scheme. Default systematic.
    pub method: ResampleMethod,
    /// Resample when the effective sample size falls below this fraction of N.
    /// Default 0.5.
    pub ess_threshold: f64,
}

impl Default for ResampleConfig {
    fn default() -> Self {
        Self {
            method: ResampleMethod::Systematic,
            ess_threshold: 0.5,
        }
    }
}

/// Effective sample size `1 / Σ wᵢ²` of normalised weights.
#[must_use]
pub fn effective_sample_size(weights: &[f64]) -> f64 {
    let s: f64 = weights.iter().map(|w| w * w).sum();
    if s > 0.0 { 1.0 / s } else { 0.0 }
}

/// Fills `out` with `n` parent indices drawn systematically from normalised `weights`,
/// using the offset `u0` in `[0, 1)`.
pub fn systematic(weights: &[f64], n: usize, u0: f64, out: &mut Vec<usize>) {
    out.clear();
    if weights.is_empty() || n == 0 {
        return;
    }
    let step = 1.0 / n as f64;
    let mut target = u0 * step;
    let mut cumulative = weights[0];
    let mut i = 0;
    for _ in 0..n {
        while target > cumulative && i + 1 < weights.len() {
            i += 1;
            cumulative += weights[i];
        }
        out.push(i);
        target += step;
    }
}

/// Fills `out` with `n` parent indices by residual resampling; `u0` in `[0, 1)` drives the
/// systematic draw of the remainder. `scratch` is reused between calls.
pub fn residual(weights: &[f64], n: usize, u0: f64, out: &mut Vec<usize>, scratch: &mut Vec<f64>) {
    out.clear();
    scratch.clear();
    let nf = n as f64;
    let mut rest = 0.0;
    for (i, &w) in weights.iter().enumerate() {
        let copies = (w * nf).floor();
        out.extend(std::iter::repeat_n(i, copies as usize));
        let r = w * nf - copies;
        scratch.push(r);
        rest += r;
    }
    let remaining = n.saturating_sub(out.len());
    if remaining == 0 || rest <= 0.0 {
        out.truncate(n);
        return;
    }
    for r in scratch.iter_mut() {
        *r /= rest;
    }
    let mut tail = Vec::with_capacity(remaining);
    systematic(scratch, remaining, u0, &mut tail);
    out.extend(tail);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn systematic_copies_in_proportion() {
        let mut out = Vec::new();
        systematic(&[0.5, 0.25, 0.25], 4, 0.5, &mut out);
        assert_eq!(out, vec![0, 0, 1, 2]);
        systematic(&[0.0, 1.0, 0.0], 3, 0.1, &mut out);
        assert_eq!(out, vec![1, 1, 1]);
    }

    #[test]
    fn residual_keeps_integer_parts() {
        let (mut out, mut scratch) = (Vec::new(), Vec::new());
        residual(&[0.6, 0.3, 0.1], 10, 0.3, &mut out, &mut scratch);
        assert_eq!(out.len(), 10);
        assert_eq!(out.iter().filter(|&&i| i == 0).count(), 6);
        assert_eq!(out.iter().filter(|&&i| i == 1).count(), 3);
        assert_eq!(out.iter().filter(|&&i| i == 2).count(), 1);
    }

    #[test]
    fn ess_of_uniform_and_degenerate_weights() {
        assert!((effective_sample_size(&[0.25; 4]) - 4.0).abs() < 1e-12);
        assert!((effective_sample_size(&[1.0, 0.0]) - 1.0).abs() < 1e-12);
    }
}
