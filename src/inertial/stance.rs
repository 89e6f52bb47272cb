//! Stance detection: the SHOE detector (stance hypothesis optimal estimator) of Skog et al.
//! (2010), "Zero-velocity detection — an algorithm evaluation", with a threshold that adapts
//! to the gait.
//!
//! The foot is still while flat on the floor; the accelerometer then reads gravity alone and the
//! gyroscope reads nothing. Over a window `Ω_k` of `W` samples around sample `k` the generalised
//! likelihood ratio of "stationary" is, up to constants (Skog et al. eq. 11),
//!
//! ```text
//! T_k = 1/W Σ_{j∈Ω_k} ( ‖a_j − g ā/‖ā‖‖² / σ_a²  +  ‖ω_j‖² / σ_ω² )
//! ```
//!
//! with `ā` the window's mean specific force. Stance is `T_k < γ`. A single `γ` does not fit
//! every gait: a slow walker's swing may score lower than a runner's stance (on the shared
//! data, stance minima range from 1 to 1 000 and swings from 10 to 10⁵). So `γ_k` adapts in the
//! log domain between the local extremes of `T` over about one gait cycle,
//!
//! ```text
//! log γ_k = m_k + α (M_k − m_k)
//! ```
//!
//! with `M_k` the maximum of `log T` over `[t_k − H, t_k + H]` and `m_k` the larger of its
//! minima over `[t_k − H, t_k]` and `[t_k, t_k + H]` (so that standing still on one side does
//! not pull the threshold below a brisk walk's stances on the other),
//! clamped to `[γ_floor, γ_ceiling]`: below the floor the foot is certainly still (standing),
//! above the ceiling it certainly moves. The mask is then cleaned: holes shorter than
//! `max_hole` inside a stance are filled, stances shorter than `min_stance` dropped.

use super::foot_config::FootConfig;
use std::collections::VecDeque;

/// The detector: the foot INS's configuration (see [`FootConfig`] for units and defaults)
/// and the recording's gravity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShoeDetector<'a> {
    /// Window, scales, thresholds and cleaning.
    pub config: &'a FootConfig,
    /// Gravity, m/s².
    pub gravity: f64,
}

/// What the detector found, sample by sample.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StanceMask {
    /// True where the foot is in stance (the stances cut the strides).
    pub stance: Vec<bool>,
    /// True where a zero-velocity update applies: the stillest part of each stance.
    pub zupt: Vec<bool>,
    /// True on the samples of a *clear* stance: one whose minimum of `log₁₀ T` is within
    /// [`CLEAR_STANCE_DECADES`] of the local minimum `m_k` (the stances around it). Only
    /// the others can be mid-swing dips, so only they need the INS's plausibility gate.
    pub clear: Vec<bool>,
    /// The SHOE statistic `T_k`.
    pub statistic: Vec<f64>,
    /// Median of the adaptive threshold `γ_k` over the recording.
    pub median_threshold: f64,
}

/// A stance whose minimum of `log₁₀ T` lies within this many decades of the local minimum
/// `m_k` is clear: as still as the stances around it (mid-swing dips stay ≥ 0.4 decade above
/// on the shared data, at 100 and 200 Hz).
pub const CLEAR_STANCE_DECADES: f64 = 0.2;

/// Number of samples spanning `seconds` at sampling interval `dt`, at least `min`.
#[must_use]
pub fn samples_in(seconds: f64, dt: f64, min: usize) -> usize {
    ((seconds / dt).round() as usize).max(min)
}

impl<'a> ShoeDetector<'a> {
    /// The stance detector on `config`, with gravity `gravity` (m/s²).
    #[must_use]
    pub fn new(config: &'a FootConfig, gravity: f64) -> Self {
        ShoeDetector { config, gravity }
    }

    /// The SHOE statistic `T_k` (eq. 11) of every sample; the window is centred on `k` and
    /// shrinks at the ends. `dt` is the median sampling interval.
    #[must_use]
    pub fn statistic(&self, accel: &[[f64; 3]], gyro: &[[f64; 3]], dt: f64) -> Vec<f64> {
        debug_assert_eq!(accel.len(), gyro.len());
        let n = accel.len();
        let w = samples_in(self.config.window_s, dt, 2);
        let (before, after) = ((w - 1) / 2, w / 2);
        let (ia2, iw2) = (
            1.0 / (self.config.accel_sigma * self.config.accel_sigma),
            1.0 / (self.config.gyro_sigma * self.config.gyro_sigma),
        );
        (0..n)
            .map(|k| {
                let (lo, hi) = (k.saturating_sub(before), (k + after + 1).min(n));
                let count = (hi - lo) as f64;
                let mut mean = [0.0; 3];
                for a in &accel[lo..hi] {
                    for i in 0..3 {
                        mean[i] += a[i] / count;
                    }
                }
                let norm = (mean[0] * mean[0] + mean[1] * mean[1] + mean[2] * mean[2]).sqrt();
                let up = if norm > 0.0 {
                    mean.map(|m| self.gravity * m / norm)
                } else {
                    [0.0; 3]
                };
                let mut sum = 0.0;
                for j in lo..hi {
                    let (a, g) = (accel[j], gyro[j]);
                    let da = (0..3).map(|i| (a[i] - up[i]).powi(2)).sum::<f64>();
                    let dw = g.iter().map(|v| v * v).sum::<f64>();
                    sum += da * ia2 + dw * iw2;
                }
                sum / count
            })
            .collect()
    }

    /// The stance mask of a recording: the statistic, the adaptive threshold, the cleaning.
    pub fn detect(&self, t: &[f64], accel: &[[f64; 3]], gyro: &[[f64; 3]], dt: f64) -> StanceMask {
        let statistic = self.statistic(accel, gyro, dt);
        let log_t: Vec<f64> = statistic.iter().map(|&v| v.max(1e-12).log10()).collect();
        let h = samples_in(self.config.adaptive_half_window_s, dt, 1);
        // m_k: the larger of the minima before and after k, so that standing still on one
        // side does not pull the threshold below the walking stances on the other.
        let below = |a: f64, b: f64| a <= b;
        let lows: Vec<f64> = sliding_extreme(&log_t, h, 0, below)
            .into_iter()
            .zip(sliding_extreme(&log_t, 0, h, below))
            .map(|(before, after)| before.max(after))
            .collect();
        let highs = sliding_extreme(&log_t, h, h, |a, b| a >= b);
        let (floor, ceiling) = (
            self.config.threshold_floor.log10(),
            self.config.threshold_ceiling.log10(),
        );
        let mut thresholds = Vec::with_capacity(log_t.len());
        let mut stance: Vec<bool> = log_t
            .iter()
            .zip(lows.iter().zip(&highs))
            .map(|(&l, (&m, &big_m))| {
                let gamma = (m + self.config.adaptive_fraction * (big_m - m)).clamp(floor, ceiling);
                thresholds.push(gamma);
                l < gamma
            })
            .collect();
        clean_runs(&mut stance, t, true, self.config.max_hole_s);
        clean_runs(&mut stance, t, false, self.config.min_stance_s);
        thresholds.sort_by(f64::total_cmp);
        let median_threshold = 10f64.powf(thresholds[thresholds.len() / 2]);
        let (zupt, clear) = stillest(&mut stance, &log_t, &lows, floor, self.config.zupt_margin);
        StanceMask {
            stance,
            zupt,
            clear,
            statistic,
            median_threshold,
        }
    }
}

/// The zero-velocity samples: those of a stance whose `log₁₀ T` is within `δ` of the lower of
/// the stance's own minimum and the local minimum `m_k` (or below the floor). The generous
/// stance that counts strides includes the foot's landing and rolling, where a zero-velocity
/// update would shorten the stride; and a brief dip of `T` in mid-swing (the foot's rotation
/// reverses there) stays far above `m_k`, set by the true stances around it. A stance with no
/// zero-velocity sample is no stance: it is removed from `stance`. Also returns which samples
/// belong to a clear stance ([`CLEAR_STANCE_DECADES`]).
fn stillest(
    stance: &mut [bool],
    log_t: &[f64],
    lows: &[f64],
    floor: f64,
    margin: f64,
) -> (Vec<bool>, Vec<bool>) {
    let mut zupt = vec![false; stance.len()];
    let mut clear = vec![false; stance.len()];
    let mut k = 0;
    while k < stance.len() {
        if !stance[k] {
            k += 1;
            continue;
        }
        let start = k;
        while k < stance.len() && stance[k] {
            k += 1;
        }
        let own = log_t[start..k]
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        let local = lows[start..k].iter().copied().fold(f64::INFINITY, f64::min);
        if own < floor || own <= local + CLEAR_STANCE_DECADES {
            clear[start..k].fill(true);
        }
        let mut any = false;
        for j in start..k {
            zupt[j] = log_t[j] < floor || log_t[j] <= own.min(lows[j]) + margin;
            any |= zupt[j];
        }
        if !any {
            stance[start..k].fill(false);
            clear[start..k].fill(false);
        }
    }
    (zupt, clear)
}

/// The extreme (by `keep(candidate, other)`: `<=` for the minimum, `>=` for the maximum) of
/// `x` over `[k − before, k + after]` for every `k`, in O(n) with a monotonic deque.
fn sliding_extreme(
    x: &[f64],
    before: usize,
    after: usize,
    keep: impl Fn(f64, f64) -> bool,
) -> Vec<f64> {
    let n = x.len();
    let mut out = Vec::with_capacity(n);
    let mut deque: VecDeque<usize> = VecDeque::new();
    let mut next = 0;
    for k in 0..n {
        while next < n && next <= k + after {
            while deque.back().is_some_and(|&b| keep(x[next], x[b])) {
                deque.pop_back();
            }
            deque.push_back(next);
            next += 1;
        }
        while deque.front().is_some_and(|&f| f + before < k) {
            deque.pop_front();
        }
        out.push(deque.front().map_or(x[k], |&f| x[f]));
    }
    out
}

/// Every maximal run of samples equal to `!fill_with` that lies strictly inside the recording
/// and lasts less than `max_s` seconds (from the sample before it to the sample after it)
/// becomes `fill_with`. With `fill_with = true` it fills short motion holes in a
/// stance; with `false` it drops short stances.
fn clean_runs(mask: &mut [bool], t: &[f64], fill_with: bool, max_s: f64) {
    let n = mask.len();
    let mut k = 0;
    while k < n {
        if mask[k] == fill_with {
            k += 1;
            continue;
        }
        let start = k;
        while k < n && mask[k] != fill_with {
            k += 1;
        }
        // The run is [start, k); its duration counts the intervals to its neighbours.
        let inside = start > 0 && k < n;
        let from = t[start.saturating_sub(1)];
        let to = t[k.min(n - 1)];
        if inside && to - from < max_s {
            mask[start..k].fill(fill_with);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The defaults with a lower adaptive fraction and a wider ZUPT margin.
    fn config() -> FootConfig {
        FootConfig {
            adaptive_fraction: 0.35,
            zupt_margin: 1.0,
            ..Default::default()
        }
    }

    fn detector(config: &FootConfig) -> ShoeDetector<'_> {
        ShoeDetector {
            config,
            gravity: 9.81,
        }
    }

    #[test]
    fn statistic_is_zero_at_rest_and_large_in_motion() {
        let config = config();
        let d = detector(&config);
        // At rest, tilted: the specific force is gravity along any direction, no rotation.
        let s = 9.81 / 2f64.sqrt();
        let rest = d.statistic(&[[s, 0.0, s]; 10], &[[0.0; 3]; 10], 0.01);
        assert!(rest.iter().all(|&v| v.abs() < 1e-18), "{rest:?}");
        // Spinning at 1 rad/s about z: ‖ω‖²/σ_ω² = 1/0.01 = 100 exactly.
        let spin = d.statistic(&[[0.0, 0.0, 9.81]; 10], &[[0.0, 0.0, 1.0]; 10], 0.01);
        assert!(spin.iter().all(|&v| (v - 100.0).abs() < 1e-9), "{spin:?}");
        // A window of 5 samples (0.05 s at 100 Hz) whose middle sample reads 1 m/s² more
        // along gravity: ā = 9.81 + 0.2 along z, so ĝ = 9.81 ẑ; deviations −0.0 for four
        // samples and +1.0 for one: T = (1/5)(1²/0.1²) = 20 at the centre.
        let mut a = [[0.0, 0.0, 9.81]; 9];
        a[4][2] += 1.0;
        let bump = d.statistic(&a, &[[0.0; 3]; 9], 0.01);
        assert!((bump[4] - 20.0).abs() < 1e-9, "{}", bump[4]);
    }

    #[test]
    fn sliding_extremes_match_brute_force() {
        let x = [3.0, 1.0, 4.0, 1.0, 5.0, 9.0, 2.0, 6.0];
        let lo = sliding_extreme(&x, 1, 1, |a, b| a <= b);
        let hi = sliding_extreme(&x, 2, 0, |a, b| a >= b);
        for k in 0..x.len() {
            let w = |b: usize, a: usize| &x[k.saturating_sub(b)..(k + a + 1).min(x.len())];
            assert_eq!(lo[k], w(1, 1).iter().copied().fold(f64::INFINITY, f64::min));
            assert_eq!(
                hi[k],
                w(2, 0).iter().copied().fold(f64::NEG_INFINITY, f64::max)
            );
        }
    }

    #[test]
    fn cleaning_fills_holes_and_drops_blips() {
        let t: Vec<f64> = (0..12).map(|i| f64::from(i) * 0.01).collect();
        let mut m = [
            true, true, true, false, true, true, false, false, true, false, false, false,
        ];
        // The one-sample hole at 3 spans 0.02 s (< 0.03): filled; the one at 6–7 spans 0.03 s: kept.
        clean_runs(&mut m, &t, true, 0.025);
        assert_eq!(&m[..8], &[true, true, true, true, true, true, false, false]);
        // The lone stance sample at 8 spans 0.02 s: dropped.
        clean_runs(&mut m, &t, false, 0.025);
        assert!(!m[8]);
    }

    #[test]
    fn adaptive_threshold_separates_a_fast_gait() {
        // A runner's gait: "stance" scores 500, "swing" 50 000 — above a fixed floor of 3,
        // yet the adaptive threshold (log: 2.7 + 0.35 × 2 = 3.4, γ ≈ 2 500) splits them.
        let dt = 0.01;
        let n = 400;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * dt).collect();
        let config = config();
        let d = detector(&config);
        let stance_truth: Vec<bool> = (0..n).map(|i| (i / 40) % 2 == 0).collect();
        // Build samples whose statistic is the wanted level: a constant rotation rate.
        let rate = |level: f64| (level * d.config.gyro_sigma * d.config.gyro_sigma).sqrt();
        let gyro: Vec<[f64; 3]> = stance_truth
            .iter()
            .map(|&s| [0.0, 0.0, if s { rate(500.0) } else { rate(50_000.0) }])
            .collect();
        let accel = vec![[0.0, 0.0, 9.81]; n];
        let mask = d.detect(&t, &accel, &gyro, dt);
        let agree = mask
            .stance
            .iter()
            .zip(&stance_truth)
            .filter(|(a, b)| a == b)
            .count();
        assert!(agree >= n - 20, "{agree} of {n}");
        // Every stance here is as still as its neighbours: clear (no gate needed).
        for k in 0..n {
            assert!(!mask.clear[k] || mask.stance[k]);
            if mask.stance[k] {
                assert!(mask.clear[k] && mask.zupt[k], "sample {k}");
            }
        }
    }
}
