//! The configuration and the figures of the foot-mounted INS ([`super::detect_strides`]):
//! every parameter, its unit and default.

use crate::error::Result;
use crate::sensor::step::MAX_STEP_LENGTH;
use serde::{Deserialize, Serialize};

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
/// | `zupt_margin`            | 0.5 decade     | `δ`: ZUPT where `log₁₀ T` ≤ min(stance's own minimum, `m_k`) + `δ` |
/// | `zupt_gate_speed`        | 2.0 m/s        | a stance less still than its neighbours whose every ZUPT sample finds the INS faster is no stance (a mid-swing dip; applies within [`GATE_HORIZON_S`](super::foot::GATE_HORIZON_S) = 2 s of the last update) |
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
    /// the lower of its stance's own minimum and the local minimum `m_k` (or below
    /// `γ_floor`); a stance without any is dropped.
    pub zupt_margin: f64,
    /// A stance that is not clear (see [`super::stance::CLEAR_STANCE_DECADES`]) and whose
    /// every zero-velocity sample finds the INS faster than this is rejected
    /// (when the last update is less than [`GATE_HORIZON_S`](super::foot::GATE_HORIZON_S) old), m/s.
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
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) for the first field that is not finite or is out of
    /// its range (e.g. `window_s` outside [0.005, 1] s, `threshold_ceiling` below
    /// `threshold_floor`, `gravity` outside [9.7, 9.9] m/s²), with the range.
    pub fn validate(&self) -> Result<()> {
        crate::error::check_range("foot.window_s", self.window_s, 0.005..=1.0, "s")?;
        crate::error::check_range("foot.accel_sigma", self.accel_sigma, 1e-4..=10.0, "m/s²")?;
        crate::error::check_range("foot.gyro_sigma", self.gyro_sigma, 1e-5..=10.0, "rad/s")?;
        crate::error::check_range("foot.threshold_floor", self.threshold_floor, 1e-6..=1e9, "")?;
        crate::error::check_range(
            "foot.threshold_ceiling",
            self.threshold_ceiling,
            self.threshold_floor..=1e12,
            "",
        )?;
        crate::error::check_range(
            "foot.adaptive_fraction",
            self.adaptive_fraction,
            0.0..=1.0,
            "",
        )?;
        crate::error::check_range(
            "foot.adaptive_half_window_s",
            self.adaptive_half_window_s,
            0.1..=10.0,
            "s",
        )?;
        crate::error::check_range("foot.min_stance_s", self.min_stance_s, 0.0..=1.0, "s")?;
        crate::error::check_range("foot.max_hole_s", self.max_hole_s, 0.0..=1.0, "s")?;
        crate::error::check_range("foot.zupt_margin", self.zupt_margin, 0.0..=10.0, "decades")?;
        crate::error::check_range(
            "foot.zupt_gate_speed",
            self.zupt_gate_speed,
            0.05..=100.0,
            "m/s",
        )?;
        crate::error::check_range(
            "foot.accel_noise_density",
            self.accel_noise_density,
            1e-5..=10.0,
            "m/s²/√Hz",
        )?;
        crate::error::check_range(
            "foot.gyro_noise_density",
            self.gyro_noise_density,
            1e-7..=1.0,
            "rad/s/√Hz",
        )?;
        crate::error::check_range(
            "foot.zero_velocity_sigma",
            self.zero_velocity_sigma,
            1e-4..=1.0,
            "m/s",
        )?;
        crate::error::check_range(
            "foot.initial_tilt_sigma",
            self.initial_tilt_sigma,
            0.0..=0.5,
            "rad",
        )?;
        if let Some(g) = self.gravity {
            crate::error::check_range("foot.gravity", g, 9.7..=9.9, "m/s² (Earth's surface)")?;
        }
        crate::error::check_range("foot.max_level_s", self.max_level_s, 0.01..=60.0, "s")?;
        crate::error::check_range("foot.min_bias_s", self.min_bias_s, 0.0..=60.0, "s")?;
        crate::error::check_range("foot.max_gap_s", self.max_gap_s, 0.001..=10.0, "s")?;
        crate::error::check_range(
            "foot.min_stride_length",
            self.min_stride_length,
            0.0..=MAX_STEP_LENGTH,
            "m",
        )?;
        crate::error::check_range("foot.min_stride_s", self.min_stride_s, 0.0..=10.0, "s")
    }
}

/// The foot INS's figures (for `summary.json`).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct FootFigures {
    /// Strides emitted.
    pub strides: usize,
    /// Stances accepted (maximal runs of stance samples whose zero-velocity updates were
    /// applied), the first included.
    pub stances: usize,
    /// Stances rejected because the INS's speed at each of their zero-velocity samples
    /// exceeded `zupt_gate_speed`.
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
