//! Stride length from the step's acceleration swing: Weinberg's model (Harle 2013, §V-A;
//! Weinberg, Analog Devices AN-602, 2002)
//!
//! ```text
//! L = K · (a_max − a_min)^{1/4}                                  (Weinberg)
//! ```
//!
//! with `a_max`, `a_min` the filtered acceleration magnitude's peak and valley of the step
//! ([`super::step_detector`]) and `K` the one constant to calibrate per person and phone.
//! Harle reports such models within about 8 % of the true length for a calibrated walker.

use crate::error::{Error, Result, check_range};
use crate::sensor::step::MAX_STEP_LENGTH;
use serde::{Deserialize, Serialize};
use std::ops::Bound::{Excluded, Unbounded};

/// The stride model's one constant; every default in one place.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StrideModelConfig {
    /// Weinberg's constant `K`, metres per (m/s²)^{1/4}. Default 0.47: a step of a phone held
    /// in front of the body swings about 4–6 m/s² after the 3 Hz low-pass, giving 0.66–0.74 m,
    /// the step length of an adult walking at 1.2–1.4 m/s (the constant depends on the
    /// detector's low-pass cut-off: recalibrate it after changing `steps.low_pass_hz`).
    ///
    /// Calibration: walk a known distance `D` (e.g. 50 m along a corridor, turning around
    /// at most once), run the detector, read the measured length `D̂` (`total_length_m` in
    /// the figures), and set `K_new = K_old · D / D̂` ([`calibrate_constant`]).
    pub weinberg_k: f64,
}

impl Default for StrideModelConfig {
    fn default() -> Self {
        Self { weinberg_k: 0.47 }
    }
}

impl StrideModelConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `weinberg_k` is outside [0.05, 2] m/(m/s²)^¼.
    pub fn validate(&self) -> Result<()> {
        if self.weinberg_k.is_finite() && (0.05..=2.0).contains(&self.weinberg_k) {
            Ok(())
        } else {
            Err(crate::error::Error::config(
                "phone.stride.weinberg_k",
                self.weinberg_k.to_string(),
                "must be in [0.05, 2] m/(m/s²)^¼",
            ))
        }
    }

    /// The stride length of a step whose filtered magnitude swung from `a_max` down to
    /// `a_min` (m/s²), metres, capped at [`MAX_STEP_LENGTH`].
    #[must_use]
    pub fn length(&self, a_max: f64, a_min: f64) -> f64 {
        let swing = (a_max - a_min).max(0.0);
        (self.weinberg_k * swing.powf(0.25)).min(MAX_STEP_LENGTH) // Weinberg
    }
}

/// The calibrated constant after a walk of known length: `K_new = K_old · D / D̂`, with `D`
/// the true and `D̂` the measured length (metres). The model is linear in `K`, so one walk
/// suffices; average over several walks to beat the step-to-step noise.
///
/// # Errors
///
/// [`Error::Config`] when `k_old` or `true_length` is not a positive number; [`Error::NotEnough`]
/// when `measured_length` is not (no steps detected).
pub fn calibrate_constant(k_old: f64, true_length: f64, measured_length: f64) -> Result<f64> {
    let positive = (Excluded(0.0), Unbounded);
    check_range("stride constant", k_old, positive, "")?;
    check_range("calibration walk's true length", true_length, positive, "m")?;
    if !(measured_length.is_finite() && measured_length > 0.0) {
        return Err(Error::not_enough(
            format!("the calibration walk's measured length is {measured_length} m"),
            "no steps were detected; check the recording",
        ));
    }
    Ok(k_old * true_length / measured_length)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weinberg_length_by_hand() {
        let m = StrideModelConfig { weinberg_k: 0.5 };
        // 16^{1/4} = 2 → 1.0 m; 81^{1/4} = 3 → 1.5 m.
        assert!((m.length(20.0, 4.0) - 1.0).abs() < 1e-12);
        assert!((m.length(90.0, 9.0) - 1.5).abs() < 1e-12);
        assert_eq!(m.length(9.0, 10.0), 0.0);
    }

    #[test]
    fn calibration_scales_the_constant_by_true_over_measured() {
        // Measured 40 m of a 50 m corridor with K = 0.4 → K = 0.5.
        let k = calibrate_constant(0.4, 50.0, 40.0).expect("valid");
        assert!((k - 0.5).abs() < 1e-12);
        // Re-measuring with the new K gives the true length: lengths are linear in K.
        let (old, new) = (
            StrideModelConfig { weinberg_k: 0.4 },
            StrideModelConfig { weinberg_k: k },
        );
        assert!((new.length(14.0, 9.0) / old.length(14.0, 9.0) - 50.0 / 40.0).abs() < 1e-12);
        assert!(calibrate_constant(0.4, 50.0, 0.0).is_err());
        assert!(calibrate_constant(-1.0, 50.0, 40.0).is_err());
    }
}
