//! Foot-mounted IMU → strides: a zero-velocity-aided strapdown INS (Harle 2013 §IV; Foxlin
//! 2005; Skog et al. 2010 for the stance detector).
//!
//! The pipeline, one stage per file:
//! 1. [`super::stance`]: the SHOE detector marks the samples where the foot is flat and still;
//! 2. [`super::strapdown`]: from the first stance (roll and pitch from its mean specific
//!    force, yaw 0) the INS integrates every sample with its own `dt`;
//! 3. [`super::zupt`]: during stance the error-state filter applies zero-velocity updates;
//! 4. here: the stances cut the path into strides. Each stance's last sample closes a stride
//!    from the previous stance (its `t`, horizontal `length`, change of the foot's yaw
//!    `dheading`, height change `dz`). A stride that is too short in distance or time (a
//!    shuffle, a spurious stance) is merged into the next one; standing still produces no
//!    stance end and so no stride. A gap in the samples longer than `max_gap_s` cannot be
//!    integrated: the open stride is dropped, and the INS restarts at the next stance
//!    (re-levelled, same yaw, same position).

use super::stance::{ShoeDetector, samples_in};
use super::strapdown::{NavState, heading_axis, heading_of, level};
use super::zupt::ZuptFilter;
use super::{HeadingSource, StepEvents};
use crate::error::{Error, Result};
use crate::sensor::step::{MAX_STEP_DZ, MAX_STEP_LENGTH};
use crate::sensor::{ImuRecording, Step, StepTrace};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Parameters of the foot-mounted INS; every default in one place.
///
/// | field                    | default        | meaning                                                        |
/// |--------------------------|----------------|----------------------------------------------------------------|
/// | `window_s`               | 0.05 s         | SHOE window `W` (10 samples at 200 Hz, 5 at 100 Hz)            |
/// | `accel_sigma`            | 0.1 m/s²       | SHOE accelerometer scale `σ_a`                                 |
/// | `gyro_sigma`             | 0.1 rad/s      | SHOE gyroscope scale `σ_ω`                                     |
/// | `threshold_floor`        | 3              | `γ_floor`: `T` below it is always stance (standing still)      |
/// | `threshold_ceiling`      | 3 000          | `γ_ceiling`: `T` above it is never stance                      |
/// | `adaptive_fraction`      | 0.4            | `α`: threshold at this fraction from local log-min to log-max  |
/// | `adaptive_half_window_s` | 1.0 s          | `H`: half-width of the local min/max window (≈ one stride)     |
/// | `min_stance_s`           | 0.05 s         | shorter stances are dropped (no zero-velocity update)          |
/// | `max_hole_s`             | 0.05 s         | shorter motion inside a stance is filled in                    |
/// | `zupt_margin`            | 0.5 decade     | `δ`: ZUPT where `log₁₀ T` ≤ `m_k + δ` (local minimum + δ)         |
/// | `zupt_gate_speed`        | 2.0 m/s        | a stance starting at a higher INS speed is no stance (within [`GATE_HORIZON_S`] of the last update) |
/// | `accel_noise_density`    | 0.1 m/s²/√Hz   | filter's accelerometer noise `√q_a`                            |
/// | `gyro_noise_density`     | 0.005 rad/s/√Hz| filter's gyroscope noise `√q_ω` (≈ 0.3 °/s/√Hz)                |
/// | `zero_velocity_sigma`    | 0.01 m/s       | ZUPT measurement noise `σ_z`                                   |
/// | `initial_tilt_sigma`     | 0.02 rad       | roll/pitch uncertainty after levelling (≈ 1°)                  |
/// | `gravity`                | none (measured)| `g`, m/s²; none = norm of the first stance's mean specific force |
/// | `max_level_s`            | 1.0 s          | levelling averages at most this much of a stance               |
/// | `min_bias_s`             | 0.5 s          | the gyro bias is the mean of a still start this long (0 = off) |
/// | `max_gap_s`              | 0.1 s          | longer intervals between samples cannot be integrated          |
/// | `min_stride_length`      | 0.1 m          | shorter strides are merged into the next                       |
/// | `min_stride_s`           | 0.3 s          | quicker strides are merged into the next                       |
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FootConfig {
    /// SHOE window `W`, seconds.
    pub window_s: f64,
    /// SHOE accelerometer scale `σ_a`, m/s².
    pub accel_sigma: f64,
    /// SHOE gyroscope scale `σ_ω`, rad/s.
    pub gyro_sigma: f64,
    /// `γ_floor`: a SHOE statistic below it is always stance.
    pub threshold_floor: f64,
    /// `γ_ceiling`: a SHOE statistic above it is never stance.
    pub threshold_ceiling: f64,
    /// `α`: the adaptive threshold's place between the local log-minimum (0) and
    /// log-maximum (1) of the statistic.
    pub adaptive_fraction: f64,
    /// `H`: half-width of the adaptive threshold's local window, seconds.
    pub adaptive_half_window_s: f64,
    /// Shortest stance kept, seconds.
    pub min_stance_s: f64,
    /// Longest motion inside a stance that is filled in, seconds.
    pub max_hole_s: f64,
    /// `δ`: zero-velocity updates apply where the SHOE statistic is within `δ` decades of
    /// its local minimum `m_k` (or below `γ_floor`); a stance without any is dropped.
    pub zupt_margin: f64,
    /// A stance whose first zero-velocity sample finds the INS faster than this is rejected
    /// (when the last update is less than [`GATE_HORIZON_S`] old), m/s.
    pub zupt_gate_speed: f64,
    /// Accelerometer noise density of the filter's model, m/s²/√Hz.
    pub accel_noise_density: f64,
    /// Gyroscope noise density of the filter's model, rad/s/√Hz.
    pub gyro_noise_density: f64,
    /// Zero-velocity measurement noise, m/s.
    pub zero_velocity_sigma: f64,
    /// Roll and pitch uncertainty after levelling, radians.
    pub initial_tilt_sigma: f64,
    /// Gravity, m/s²; `None` = the norm of the first stance's mean specific force.
    pub gravity: Option<f64>,
    /// Levelling averages at most this much of a stance, seconds.
    pub max_level_s: f64,
    /// The gyroscope bias is estimated as its mean over the first stance's still samples when
    /// they last at least this long, seconds; 0 = never.
    pub min_bias_s: f64,
    /// Longest interval between samples that is integrated, seconds.
    pub max_gap_s: f64,
    /// Shortest stride emitted, metres; shorter ones are merged into the next.
    pub min_stride_length: f64,
    /// Quickest stride emitted, seconds; quicker ones are merged into the next.
    pub min_stride_s: f64,
}

impl Default for FootConfig {
    fn default() -> Self {
        Self {
            window_s: 0.05,
            accel_sigma: 0.1,
            gyro_sigma: 0.1,
            threshold_floor: 3.0,
            threshold_ceiling: 3000.0,
            adaptive_fraction: 0.4,
            adaptive_half_window_s: 1.0,
            min_stance_s: 0.05,
            max_hole_s: 0.05,
            zupt_margin: 0.5,
            zupt_gate_speed: 2.0,
            accel_noise_density: 0.1,
            gyro_noise_density: 0.005,
            zero_velocity_sigma: 0.01,
            initial_tilt_sigma: 0.02,
            gravity: None,
            max_level_s: 1.0,
            min_bias_s: 0.5,
            max_gap_s: 0.1,
            min_stride_length: 0.1,
            min_stride_s: 0.3,
        }
    }
}

impl FootConfig {
    /// Checks every field against its documented range.
    pub fn validate(&self) -> Result<()> {
        let check = |field: &'static str, v: f64, lo: f64, hi: f64, reason: &'static str| {
            if v.is_finite() && (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(Error::Config {
                    field,
                    value: v.to_string(),
                    reason,
                })
            }
        };
        check("foot.window_s", self.window_s, 0.005, 1.0, "must be in [0.005, 1] s")?;
        check("foot.accel_sigma", self.accel_sigma, 1e-4, 10.0, "must be in [1e-4, 10] m/s²")?;
        check("foot.gyro_sigma", self.gyro_sigma, 1e-5, 10.0, "must be in [1e-5, 10] rad/s")?;
        check("foot.threshold_floor", self.threshold_floor, 1e-6, 1e9, "must be in [1e-6, 1e9]")?;
        check(
            "foot.threshold_ceiling",
            self.threshold_ceiling,
            self.threshold_floor,
            1e12,
            "must be in [threshold_floor, 1e12]",
        )?;
        check("foot.adaptive_fraction", self.adaptive_fraction, 0.0, 1.0, "must be in [0, 1]")?;
        check(
            "foot.adaptive_half_window_s",
            self.adaptive_half_window_s,
            0.1,
            10.0,
            "must be in [0.1, 10] s",
        )?;
        check("foot.min_stance_s", self.min_stance_s, 0.0, 1.0, "must be in [0, 1] s")?;
        check("foot.max_hole_s", self.max_hole_s, 0.0, 1.0, "must be in [0, 1] s")?;
        check("foot.zupt_margin", self.zupt_margin, 0.0, 10.0, "must be in [0, 10] decades")?;
        check("foot.zupt_gate_speed", self.zupt_gate_speed, 0.05, 100.0, "must be in [0.05, 100] m/s")?;
        check(
            "foot.accel_noise_density",
            self.accel_noise_density,
            1e-5,
            10.0,
            "must be in [1e-5, 10] m/s²/√Hz",
        )?;
        check(
            "foot.gyro_noise_density",
            self.gyro_noise_density,
            1e-7,
            1.0,
            "must be in [1e-7, 1] rad/s/√Hz",
        )?;
        check(
            "foot.zero_velocity_sigma",
            self.zero_velocity_sigma,
            1e-4,
            1.0,
            "must be in [1e-4, 1] m/s",
        )?;
        check(
            "foot.initial_tilt_sigma",
            self.initial_tilt_sigma,
            0.0,
            0.5,
            "must be in [0, 0.5] rad",
        )?;
        if let Some(g) = self.gravity {
            check("foot.gravity", g, 9.7, 9.9, "must be in [9.7, 9.9] m/s² (Earth's surface)")?;
        }
        check("foot.max_level_s", self.max_level_s, 0.01, 60.0, "must be in [0.01, 60] s")?;
        check("foot.min_bias_s", self.min_bias_s, 0.0, 60.0, "must be in [0, 60] s")?;
        check("foot.max_gap_s", self.max_gap_s, 0.001, 10.0, "must be in [0.001, 10] s")?;
        check(
            "foot.min_stride_length",
            self.min_stride_length,
            0.0,
            MAX_STEP_LENGTH,
            "must be in [0, 3] m",
        )?;
        check("foot.min_stride_s", self.min_stride_s, 0.0, 10.0, "must be in [0, 10] s")
    }

    fn detector(&self, gravity: f64) -> ShoeDetector {
        ShoeDetector {
            window_s: self.window_s,
            accel_sigma: self.accel_sigma,
            gyro_sigma: self.gyro_sigma,
            gravity,
            threshold_floor: self.threshold_floor,
            threshold_ceiling: self.threshold_ceiling,
            adaptive_fraction: self.adaptive_fraction,
            adaptive_half_window_s: self.adaptive_half_window_s,
            min_stance_s: self.min_stance_s,
            max_hole_s: self.max_hole_s,
            zupt_margin: self.zupt_margin,
        }
    }
}

/// The foot INS's figures (for `summary.json`).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct FootFigures {
    /// Strides emitted.
    pub strides: usize,
    /// Stances detected (maximal runs of zero-velocity samples).
    pub stances: usize,
    /// Stances rejected because the INS's speed at their start exceeded `zupt_gate_speed`.
    pub gated_stances: usize,
    /// Strides too short in distance or time, merged into the next.
    pub merged_strides: usize,
    /// Strides longer than the plausible maximum, split into equal parts.
    pub split_strides: usize,
    /// Sum of the stride lengths, metres.
    pub distance_m: f64,
    /// Mean stride length, metres (0 without strides).
    pub mean_stride_length_m: f64,
    /// Strides per minute of walking (the strides' summed durations).
    pub cadence_per_min: f64,
    /// Time in stance (zero-velocity samples), seconds.
    pub stationary_s: f64,
    /// Intervals longer than `max_gap_s` (not integrated).
    pub gaps_skipped: usize,
    /// Strides dropped because a gap interrupted them.
    pub strides_lost_to_gaps: usize,
    /// Median over the recording of the SHOE detector's adaptive threshold `γ`.
    pub detector_threshold: f64,
    /// Gravity used, m/s².
    pub gravity: f64,
    /// Mean velocity residual `‖v̂‖` of the zero-velocity updates, m/s.
    pub mean_zupt_residual: f64,
    /// Largest velocity residual of a zero-velocity update, m/s.
    pub max_zupt_residual: f64,
    /// Gyroscope bias removed, rad/s (zero when the recording does not start standing).
    pub gyro_bias: [f64; 3],
    /// Final height relative to the start, metres.
    pub final_dz_m: f64,
}

/// The gate on zero-velocity updates applies while the last update is this recent, seconds:
/// after a longer unaided stretch the velocity error itself may exceed the gate.
pub const GATE_HORIZON_S: f64 = 2.0;

/// Whether the current stance's zero-velocity updates are applied.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Run {
    /// No zero-velocity sample seen yet.
    Undecided,
    /// Applied: the foot is at rest.
    Accepted,
    /// Rejected by the gate: a dip of the statistic while the foot moves fast.
    Rejected,
}

/// The INS state at a stance that opened a stride.
#[derive(Debug, Clone, Copy)]
struct Anchor {
    t: f64,
    position: Vector3<f64>,
    yaw: f64,
}

/// Strides of a foot-mounted recording.
pub fn detect_strides(
    recording: &ImuRecording,
    config: &FootConfig,
) -> Result<StepEvents<FootFigures>> {
    config.validate()?;
    let samples = recording.samples();
    let n = samples.len();
    let dt_median = recording.report().median_dt_s;
    let t: Vec<f64> = samples.iter().map(|s| s.t).collect();
    let accel: Vec<[f64; 3]> = samples.iter().map(|s| s.accel).collect();
    let gyro: Vec<[f64; 3]> = samples.iter().map(|s| s.gyro).collect();

    let mask = config
        .detector(config.gravity.unwrap_or(9.81))
        .detect(&t, &accel, &gyro, dt_median);
    let stance = &mask.stance;
    let mut figures = FootFigures {
        detector_threshold: mask.median_threshold,
        ..FootFigures::default()
    };
    let level_samples = samples_in(config.max_level_s, dt_median, 1);
    let mean_force = |k: usize| -> Vector3<f64> {
        // The mean specific force of the stance run containing sample k, from its start.
        let mut start = k;
        while start > 0 && stance[start - 1] {
            start -= 1;
        }
        let mut sum = Vector3::zeros();
        let mut count = 0.0_f64;
        for a in accel[start..].iter().zip(&stance[start..]).take(level_samples) {
            if !*a.1 {
                break;
            }
            sum += Vector3::from(*a.0);
            count += 1.0;
        }
        sum / count.max(1.0)
    };

    let mut steps: Vec<Step> = Vec::new();
    let mut path: Vec<[f64; 3]> = Vec::new();
    let Some(first) = stance.iter().position(|&s| s) else {
        return finish(steps, path, figures);
    };
    let f0 = mean_force(first);
    let gravity = config.gravity.unwrap_or(f0.norm());
    if !(5.0..=15.0).contains(&gravity) {
        return Err(Error::Input(format!(
            "the first stance's mean specific force is {gravity:.2} m/s², not gravity: are the \
             accelerations in m/s² (not g)?"
        )));
    }
    figures.gravity = gravity;
    let bias = gyro_bias(&t, &gyro, &mask.statistic, first, config);
    figures.gyro_bias = bias.into();
    let axis = heading_axis(&f0);
    let mut state = NavState::at_rest(Vector3::zeros(), level(&f0, &axis, 0.0), gravity);
    let mut filter = ZuptFilter::new(
        config.accel_noise_density,
        config.gyro_noise_density,
        config.zero_velocity_sigma,
        config.initial_tilt_sigma,
    );

    let mut anchor: Option<Anchor> = None;
    let mut lost = false; // after a gap, until the next stance
    let mut reanchor = false; // after a restart, until the stance ends
    let mut run = Run::Undecided; // the current stance's fate
    let mut last_zupt_t = t[first];
    let (mut residual_sum, mut residual_count) = (0.0, 0usize);
    let mut stride_time = 0.0;
    for k in first..n {
        if k > first {
            let dt = t[k] - t[k - 1];
            if dt > config.max_gap_s {
                figures.gaps_skipped += 1;
                if !(stance[k - 1] && stance[k]) {
                    // The foot moved across the gap: the open stride cannot be measured.
                    if anchor.is_some() && !lost {
                        figures.strides_lost_to_gaps += 1;
                    }
                    lost = true;
                }
            } else if !lost {
                let f = 0.5 * (Vector3::from(accel[k - 1]) + Vector3::from(accel[k]));
                let w = 0.5 * (Vector3::from(gyro[k - 1]) + Vector3::from(gyro[k])) - bias;
                let f_n = state.propagate(&f, &w, dt);
                filter.predict(&f_n, dt);
            }
        }
        if !stance[k] {
            continue;
        }
        if k == first || !stance[k - 1] {
            run = Run::Undecided;
        }
        if lost {
            // Restart cleanly: re-levelled, at rest, same position and yaw.
            let yaw = heading_of(&state.attitude, &axis);
            state = NavState::at_rest(state.position, level(&mean_force(k), &axis, yaw), gravity);
            filter.restart(config.initial_tilt_sigma);
            lost = false;
            reanchor = true;
            run = Run::Accepted;
            if let Some(a) = anchor {
                // The walker is assumed not to have moved across the gap.
                state.position = a.position;
            }
        }
        if mask.zupt[k] && run == Run::Undecided {
            // Gate (after Foxlin's plausibility tests): a foot at rest after a recent update
            // cannot have drifted to `zupt_gate_speed`; a mid-swing dip of the statistic can.
            let recent = t[k] - last_zupt_t < GATE_HORIZON_S;
            run = if recent && state.velocity.norm() > config.zupt_gate_speed {
                figures.gated_stances += 1;
                Run::Rejected
            } else {
                Run::Accepted
            };
        }
        if run == Run::Rejected {
            continue;
        }
        if mask.zupt[k] {
            last_zupt_t = t[k];
            let r = filter.update_zero_velocity(&mut state);
            residual_sum += r;
            residual_count += 1;
            figures.max_zupt_residual = figures.max_zupt_residual.max(r);
        }
        if k > first {
            figures.stationary_s += (t[k] - t[k - 1]).min(config.max_gap_s);
        }
        let stance_ends = k + 1 == n || !stance[k + 1];
        if !stance_ends || run != Run::Accepted {
            continue;
        }
        figures.stances += 1;
        let here = Anchor {
            t: t[k],
            position: state.position,
            yaw: heading_of(&state.attitude, &axis),
        };
        let Some(from) = anchor.filter(|_| !reanchor) else {
            if anchor.is_none() {
                path.push(here.position.into());
            }
            anchor = Some(here);
            reanchor = false;
            continue;
        };
        let d = here.position - from.position;
        let length = d.xy().norm();
        if length < config.min_stride_length || here.t - from.t < config.min_stride_s {
            figures.merged_strides += 1;
            continue;
        }
        stride_time += here.t - from.t;
        emit(&from, &here, &mut steps, &mut path, &mut figures);
        anchor = Some(here);
    }
    figures.mean_zupt_residual = residual_sum / (residual_count.max(1) as f64);
    if stride_time > 0.0 {
        figures.cadence_per_min = 60.0 * steps.len() as f64 / stride_time;
    }
    finish(steps, path, figures)
}

/// The gyroscope's bias: its mean over the still samples (`T < γ_floor`) of the first stance
/// when they span at least `min_bias_s` (the walker stands before setting off), else zero.
fn gyro_bias(
    t: &[f64],
    gyro: &[[f64; 3]],
    statistic: &[f64],
    first: usize,
    config: &FootConfig,
) -> Vector3<f64> {
    let mut sum = Vector3::zeros();
    let (mut count, mut span) = (0.0_f64, 0.0);
    for k in first + 1..t.len() {
        if statistic[k] >= config.threshold_floor {
            break;
        }
        sum += Vector3::from(gyro[k]);
        count += 1.0;
        span = t[k] - t[first];
    }
    if config.min_bias_s > 0.0 && span >= config.min_bias_s {
        sum / count
    } else {
        Vector3::zeros()
    }
}

/// Appends the stride `from → to` (split into equal parts if implausibly long).
fn emit(
    from: &Anchor,
    to: &Anchor,
    steps: &mut Vec<Step>,
    path: &mut Vec<[f64; 3]>,
    figures: &mut FootFigures,
) {
    let d = to.position - from.position;
    let length = d.xy().norm();
    let parts = ((length / MAX_STEP_LENGTH).ceil())
        .max((d.z.abs() / MAX_STEP_DZ).ceil())
        .max(1.0);
    if parts > 1.0 {
        figures.split_strides += 1;
    }
    let m = parts as usize;
    for i in 1..=m {
        let s = i as f64 / parts;
        let p = from.position + d * s;
        steps.push(Step {
            t: from.t + (to.t - from.t) * s,
            length: length / parts,
            dheading: if i == 1 {
                wrap_half_open(to.yaw - from.yaw)
            } else {
                0.0
            },
            dz: d.z / parts,
            heading: None,
        });
        path.push(p.into());
    }
}

/// Wraps an angle into `(−π, π]`.
fn wrap_half_open(a: f64) -> f64 {
    let w = crate::geometry::wrap_angle(a);
    if w <= -PI { w + 2.0 * PI } else { w }
}

fn finish(
    steps: Vec<Step>,
    path: Vec<[f64; 3]>,
    mut figures: FootFigures,
) -> Result<StepEvents<FootFigures>> {
    figures.strides = steps.len();
    figures.distance_m = steps.iter().map(|s| s.length).sum();
    if !steps.is_empty() {
        figures.mean_stride_length_m = figures.distance_m / steps.len() as f64;
    }
    figures.final_dz_m = match (path.first(), path.last()) {
        (Some(a), Some(b)) => b[2] - a[2],
        _ => 0.0,
    };
    let trace = StepTrace::new(steps)
        .map_err(|(i, m)| Error::Input(format!("stride {i} of the foot INS: {m}")))?;
    Ok(StepEvents {
        trace,
        path,
        heading_source: HeadingSource::Gyroscope,
        figures,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::ImuSample;
    use nalgebra::{Rotation3, Vector3};
    use std::f64::consts::TAU;

    /// A foot on a known trajectory: stands 2 s, then for each `(length, turn)` a 0.7 s swing
    /// along a straight line (position and yaw follow `s(τ) = τ − sin(2πτ)/2π`, whose speed
    /// and acceleration vanish at both ends; the foot pitches by up to [`PITCH`] and back, as
    /// a real foot does — a pure translation would look still to any IMU at mid-swing) and a
    /// 0.8 s stance; the turn happens in the swing and the stride runs along the new heading. The sensor is mounted upside down and tilted
    /// (z down, 0.1 rad about y). Samples in `drop` (a time interval) are left out.
    fn synthetic(rate: f64, strides: &[(f64, f64)], drop: Option<(f64, f64)>) -> ImuRecording {
        let (stand, swing, stance) = (2.0, 0.7, 0.8);
        let mount = Rotation3::from_euler_angles(std::f64::consts::PI, 0.1, 0.0);
        let g = 9.81;
        let duration = stand + strides.len() as f64 * (swing + stance);
        let mut samples = Vec::new();
        let mut k = 0;
        loop {
            let t = k as f64 / rate;
            k += 1;
            if t > duration {
                break;
            }
            if drop.is_some_and(|(a, b)| t > a && t < b) {
                continue;
            }
            // Where in the walk: heading before this stride, and the swing's phase τ.
            let mut yaw = 0.0;
            let (mut accel, mut yaw_rate) = (Vector3::zeros(), 0.0);
            let (mut pitch, mut pitch_rate) = (0.0, 0.0);
            let mut start = stand;
            for &(length, turn) in strides {
                if t >= start && t < start + swing {
                    let tau = (t - start) / swing;
                    let s = tau - (TAU * tau).sin() / TAU;
                    let ds = (1.0 - (TAU * tau).cos()) / swing;
                    let dds = TAU * (TAU * tau).sin() / (swing * swing);
                    let heading = yaw + turn;
                    accel = length * dds * Vector3::new(heading.cos(), heading.sin(), 0.0);
                    yaw_rate = turn * ds;
                    yaw += turn * s;
                    // The foot pitches up to PITCH and back: β = P sin²(πτ).
                    pitch = PITCH * (std::f64::consts::PI * tau).sin().powi(2);
                    pitch_rate = PITCH * std::f64::consts::PI * (TAU * tau).sin() / swing;
                    break;
                }
                if t >= start + swing {
                    yaw += turn;
                }
                start += swing + stance;
            }
            // C = R_z(ψ) R_y(β) M; ω^n = ψ̇ ẑ + R_z(ψ) β̇ ŷ; ω^b = Cᵀ ω^n.
            let rz = Rotation3::from_axis_angle(&Vector3::z_axis(), yaw);
            let c = rz * Rotation3::from_axis_angle(&Vector3::y_axis(), pitch) * mount;
            let f = c.inverse() * (accel + Vector3::new(0.0, 0.0, g));
            let w_n = Vector3::new(0.0, 0.0, yaw_rate) + rz * Vector3::new(0.0, pitch_rate, 0.0);
            let w = c.inverse() * w_n;
            samples.push(ImuSample {
                t,
                accel: f.into(),
                gyro: w.into(),
                mag: None,
                orientation: None,
                pressure: None,
            });
        }
        ImuRecording::new(samples, 0).expect("valid synthetic recording")
    }

    /// The foot's largest pitch in a swing, radians.
    const PITCH: f64 = 0.5;

    const WALK: [(f64, f64); 4] = [(1.2, 0.0), (1.4, 0.5), (1.0, -1.2), (1.3, 0.0)];

    #[test]
    fn synthetic_strides_are_measured_at_any_rate() {
        for rate in [100.0, 200.0, 250.0] {
            let e = detect_strides(&synthetic(rate, &WALK, None), &FootConfig::default())
                .expect("strides");
            let steps = e.trace.steps();
            assert_eq!(steps.len(), WALK.len(), "{rate} Hz: {steps:?}");
            assert_eq!(e.path.len(), WALK.len() + 1);
            for (s, &(length, turn)) in steps.iter().zip(&WALK) {
                assert!((s.length - length).abs() < 0.03, "{rate} Hz: {s:?} vs {length}");
                assert!((s.dheading - turn).abs() < 0.01, "{rate} Hz: {s:?} vs {turn}");
                assert!(s.dz.abs() < 0.01 && s.heading.is_none());
            }
            // Each stride ends with its stance: 2 + i (0.7 + 0.8) s.
            assert!((steps[3].t - 8.0).abs() < 0.02, "{}", steps[3].t);
            let f = &e.figures;
            assert_eq!((f.strides, f.gaps_skipped, f.merged_strides), (4, 0, 0));
            assert!((f.gravity - 9.81).abs() < 1e-6);
            assert!((f.distance_m - 4.9).abs() < 0.1, "{f:?}");
            // 4 strides in 4 × 1.5 s of walking: 40 per minute.
            assert!((f.cadence_per_min - 40.0).abs() < 1.0, "{f:?}");
        }
    }

    #[test]
    fn a_gap_drops_the_open_stride_and_the_walk_resumes() {
        // Half a second missing in the middle of the second swing (3.5 s + 0.35 s).
        let rec = synthetic(200.0, &WALK, Some((3.7, 4.2)));
        let e = detect_strides(&rec, &FootConfig::default()).expect("strides");
        let f = &e.figures;
        assert_eq!((f.gaps_skipped, f.strides_lost_to_gaps), (1, 1), "{f:?}");
        let steps = e.trace.steps();
        assert_eq!(steps.len(), 3, "{steps:?}");
        // The strides before and after the gap keep their lengths and turns.
        assert!((steps[0].length - 1.2).abs() < 0.03);
        assert!((steps[1].length - 1.0).abs() < 0.03 && (steps[1].dheading + 1.2).abs() < 0.02);
        assert!((steps[2].length - 1.3).abs() < 0.03);
        // The path holds one point per stride plus the start, each stride its length apart.
        assert_eq!(e.path.len(), 4);
        for (s, w) in steps.iter().zip(e.path.windows(2)) {
            let d = (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
            assert!((d - s.length).abs() < 1e-9);
        }
    }

    #[test]
    fn standing_still_makes_no_strides() {
        // A minute at 100 Hz of a still sensor with a little deterministic noise.
        let samples = (0..6000)
            .map(|k| {
                let n = |i: f64| (k as f64 * 0.37 + i).sin();
                ImuSample {
                    t: k as f64 * 0.01,
                    accel: [0.02 * n(1.0), 0.02 * n(2.0), -9.81 + 0.02 * n(3.0)],
                    gyro: [0.003 * n(4.0), 0.003 * n(5.0), 0.003 * n(6.0)],
                    mag: None,
                    orientation: None,
                    pressure: None,
                }
            })
            .collect();
        let rec = ImuRecording::new(samples, 0).expect("valid");
        let e = detect_strides(&rec, &FootConfig::default()).expect("strides");
        assert!(e.trace.is_empty());
        assert_eq!(e.path.len(), 1);
        assert_eq!(e.figures.stances, 1);
        assert!(e.figures.stationary_s > 59.0, "{:?}", e.figures);
    }

    #[test]
    fn short_shuffles_are_merged() {
        // A 5 cm shuffle then a real stride: one stride of 1.25 m.
        let e = detect_strides(
            &synthetic(200.0, &[(0.05, 0.0), (1.2, 0.0)], None),
            &FootConfig::default(),
        )
        .expect("strides");
        assert_eq!(e.trace.len(), 1, "{:?} {:?}", e.trace, e.figures);
        assert_eq!(e.figures.merged_strides, 1, "{:?}", e.figures);
        assert!((e.trace.steps()[0].length - 1.25).abs() < 0.03);
    }

    #[test]
    fn config_defaults_validate_and_unknown_fields_are_refused() {
        assert!(FootConfig::default().validate().is_ok());
        let c: FootConfig = serde_json::from_str(r#"{"max_gap_s": 0.2}"#).expect("parse");
        assert_eq!(c.max_gap_s, 0.2);
        assert_eq!(c.window_s, FootConfig::default().window_s);
        assert!(serde_json::from_str::<FootConfig>(r#"{"window": 1}"#).is_err());
        let bad = FootConfig {
            threshold_ceiling: 1.0,
            ..FootConfig::default()
        };
        assert!(bad.validate().is_err());
    }

    #[test]
    fn turns_wrap_into_the_half_open_interval() {
        assert!((wrap_half_open(-PI) - PI).abs() < 1e-12);
        assert!((wrap_half_open(PI) - PI).abs() < 1e-12);
        assert!((wrap_half_open(1.5 * PI) + 0.5 * PI).abs() < 1e-12);
    }
}
