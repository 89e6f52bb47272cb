//! The GPS measurement model: the likelihood of a position fix given a particle's position,
//! robust to outliers and tempered for errors that are correlated in time.
//!
//! A fix `z = (x, y)` with stated accuracy `σ` (1σ per horizontal axis) is modelled as a
//! mixture of a Gaussian about the true position and a uniform density over a disc of
//! radius `R` (a multipath or cold-start outlier, 50 m or more off):
//!
//! `p(z | P) = (1 − ε) · N(z; P, σ² I) + ε / (π R²)`.
//!
//! The uniform floor bounds what one outlier can cost a particle (a Student-t would do the
//! same; the mixture keeps the Gaussian's exact shape near the truth). GPS errors are far
//! from white — the paper saw 3–7 m with a slowly varying bias — so treating 1 Hz fixes as
//! independent over-counts them. Optionally every fix's log-likelihood is scaled by
//! `min(1, Δt / τ)`, where `Δt` is the time since the previous fix and `τ` the error's
//! correlation time (a tempered likelihood: about one independent fix per `τ` seconds); by
//! default fixes count fully, and the common bias is handled where it matters — between a
//! walk and a prior map — by an explicit offset state (see [`crate::filter::FootSlam`]).

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Parameters of the GPS likelihood; every default in one place.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GpsConfig {
    /// Prior probability `ε` that a fix is an outlier. Default 0.05.
    pub outlier_probability: f64,
    /// Radius `R` of the disc over which outliers are uniform, metres. Default 200 m.
    pub outlier_radius: f64,
    /// Correlation time `τ` of GPS errors, seconds: fixes closer than this count as a
    /// fraction of an independent one. Default 0: fixes count as independent. Their common
    /// bias then moves the whole path (which no other information can correct within one
    /// walk), while their differences fix the walker's heading; on simulated walks a 10 s
    /// tempering left the heading too loose for the map to converge (5 m shape errors).
    pub correlation_time: f64,
    /// Spread of the slowly varying part of GPS errors (the bias), per axis, metres (1σ).
    /// With a prior map it sets how far the map's frame may sit from this walk's GPS
    /// frame (see [`crate::filter::FootSlam`]). Default 3 m (the paper saw 3–7 m errors).
    pub bias_sigma: f64,
    /// Spread (1σ) of the per-walk stride-length scale when fixes are given (replaces
    /// `motion.length_scale_sigma0`). Default 0: with fixes only outdoors, eq. (6) still
    /// shrinks the strides indoors (on a simulated outdoor–indoor–outdoor walk a spread of
    /// 0.03 took the shape error, p95 after rigid alignment, from 0.46 m to 2.1 m); set it
    /// when fixes cover most of the walk.
    pub length_scale_sigma0: f64,
}

impl Default for GpsConfig {
    fn default() -> Self {
        Self {
            outlier_probability: 0.05,
            outlier_radius: 200.0,
            correlation_time: 0.0,
            bias_sigma: 3.0,
            length_scale_sigma0: 0.0,
        }
    }
}

impl GpsConfig {
    /// Checks every field; returns the offending field's name, value and rule.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) when `outlier_probability` is outside [0, 1),
    /// `outlier_radius` outside [1, 100 000] m, `correlation_time` outside [0, 3600] s,
    /// `bias_sigma` outside [0, 1000] m or `length_scale_sigma0` outside [0, 0.3].
    pub fn validate(&self) -> crate::error::Result<()> {
        let e = self.outlier_probability;
        if !(e.is_finite() && (0.0..1.0).contains(&e)) {
            return Err(crate::error::Error::config(
                "gps.outlier_probability",
                e,
                "must be in [0, 1)",
            ));
        }
        let r = self.outlier_radius;
        if !(r.is_finite() && (1.0..=100_000.0).contains(&r)) {
            return Err(crate::error::Error::config(
                "gps.outlier_radius",
                r,
                "must be in [1, 100000] metres",
            ));
        }
        let t = self.correlation_time;
        if !(t.is_finite() && (0.0..=3600.0).contains(&t)) {
            return Err(crate::error::Error::config(
                "gps.correlation_time",
                t,
                "must be in [0, 3600] seconds",
            ));
        }
        let b = self.bias_sigma;
        if !(b.is_finite() && (0.0..=1000.0).contains(&b)) {
            return Err(crate::error::Error::config(
                "gps.bias_sigma",
                b,
                "must be in [0, 1000] metres",
            ));
        }
        let s = self.length_scale_sigma0;
        if !(s.is_finite() && (0.0..=0.3).contains(&s)) {
            return Err(crate::error::Error::config(
                "gps.length_scale_sigma0",
                s,
                "must be in [0, 0.3]",
            ));
        }
        Ok(())
    }
}

/// A fix in the local frame (x east, y north, metres) on the steps' clock.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GpsObservation {
    /// Time, seconds on the steps' clock.
    pub t: f64,
    /// East, metres.
    pub x: f64,
    /// North, metres.
    pub y: f64,
    /// Stated accuracy `σ`, metres (1σ per axis).
    pub sigma: f64,
}

impl GpsObservation {
    /// A fix placed in the local frame `frame`.
    #[must_use]
    pub fn from_fix(fix: &crate::sensor::GpsFix, frame: &crate::geometry::LocalFrame) -> Self {
        let (x, y) = frame.to_local(fix.lon, fix.lat);
        Self {
            t: fix.t,
            x,
            y,
            sigma: fix.accuracy,
        }
    }
}

/// The GPS likelihood with its configuration.
///
/// A fix placed in the local frame, and what it says about particles near and far:
///
/// ```
/// use footslam::geometry::LocalFrame;
/// use footslam::model::{GpsConfig, GpsLikelihood, GpsObservation};
/// use footslam::sensor::GpsFix;
///
/// let frame = LocalFrame::new(52.52, 13.40).expect("a valid origin");
/// let fix = GpsFix { t: 10.0, lat: 52.52, lon: 13.40, accuracy: 4.0 };
/// let z = GpsObservation::from_fix(&fix, &frame);
/// assert!(z.x.abs() < 1e-9 && z.y.abs() < 1e-9 && z.sigma == 4.0);
///
/// let gps = GpsLikelihood::new(GpsConfig::default());
/// let at = |d: f64| gps.log_likelihood(&z, (d, 0.0));
/// assert!(at(0.0) > at(5.0) && at(5.0) > at(20.0));
/// // An outlier costs every particle about the same: the uniform floor.
/// assert!((at(500.0) - at(5000.0)).abs() < 1e-9);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GpsLikelihood {
    config: GpsConfig,
    /// `ln(ε / (π R²))`, the outlier floor.
    log_outlier: f64,
    /// `ln(1 − ε)`, the inliers' share.
    log_inlier: f64,
}

impl GpsLikelihood {
    /// The model for a validated configuration.
    #[must_use]
    pub fn new(config: GpsConfig) -> Self {
        let r = config.outlier_radius;
        Self {
            log_outlier: (config.outlier_probability / (PI * r * r)).ln(),
            log_inlier: (1.0 - config.outlier_probability).ln(),
            config,
        }
    }

    /// `ln p(z | P)` of fix `z` for a particle at `(x, y)`, untempered.
    #[must_use]
    pub fn log_likelihood(&self, z: &GpsObservation, (x, y): (f64, f64)) -> f64 {
        let d2 = (z.x - x).powi(2) + (z.y - y).powi(2);
        let s2 = z.sigma * z.sigma;
        let log_gauss = self.log_inlier - (2.0 * PI * s2).ln() - d2 / (2.0 * s2);
        log_add(log_gauss, self.log_outlier)
    }

    /// The tempering exponent `min(1, Δt / τ)` of a fix `dt` seconds after the previous one
    /// (the first fix counts fully).
    #[must_use]
    pub fn temper(&self, dt: Option<f64>) -> f64 {
        match dt {
            Some(dt) if self.config.correlation_time > 0.0 => {
                (dt / self.config.correlation_time).clamp(0.0, 1.0)
            }
            _ => 1.0,
        }
    }
}

/// `ln(eᵃ + eᵇ)` without overflow.
fn log_add(a: f64, b: f64) -> f64 {
    let (hi, lo) = if a > b { (a, b) } else { (b, a) };
    if hi == f64::NEG_INFINITY {
        hi
    } else {
        hi + (lo - hi).exp().ln_1p()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fix(x: f64, y: f64, sigma: f64) -> GpsObservation {
        GpsObservation {
            t: 0.0,
            x,
            y,
            sigma,
        }
    }

    #[test]
    fn near_the_fix_it_is_the_gaussian() {
        let m = GpsLikelihood::new(GpsConfig::default());
        let z = fix(3.0, 4.0, 5.0);
        // At the fix: (1 − 0.05) / (2π·25) + 0.05 / (π·200²).
        let want = (0.95 / (2.0 * PI * 25.0) + 0.05 / (PI * 40_000.0)).ln();
        assert!((m.log_likelihood(&z, (3.0, 4.0)) - want).abs() < 1e-12);
        // 5 m away (one sigma per axis, d² = 25): the Gaussian falls by e^-0.5.
        let want = (0.95 / (2.0 * PI * 25.0) * (-0.5f64).exp() + 0.05 / (PI * 40_000.0)).ln();
        assert!((m.log_likelihood(&z, (0.0, 0.0)) - want).abs() < 1e-12);
    }

    #[test]
    fn outliers_cost_a_bounded_amount() {
        let m = GpsLikelihood::new(GpsConfig::default());
        let z = fix(0.0, 0.0, 3.0);
        let floor = (0.05 / (PI * 40_000.0)).ln();
        for d in [60.0, 100.0, 1000.0] {
            let l = m.log_likelihood(&z, (d, 0.0));
            assert!((l - floor).abs() < 1e-9, "{d} m: {l} vs {floor}");
        }
        // A particle 60 m from an outlying fix and one on it differ by a bounded factor.
        let gap = m.log_likelihood(&z, (0.0, 0.0)) - m.log_likelihood(&z, (60.0, 0.0));
        assert!(gap < 12.0, "{gap}");
        // Without the mixture the same gap would be 200 nats.
        let pure = GpsLikelihood::new(GpsConfig {
            outlier_probability: 0.0,
            ..Default::default()
        });
        let gap = pure.log_likelihood(&z, (0.0, 0.0)) - pure.log_likelihood(&z, (60.0, 0.0));
        assert!((gap - 200.0).abs() < 1e-9, "{gap}");
    }

    #[test]
    fn tempering_and_validation() {
        let m = GpsLikelihood::new(GpsConfig::default());
        assert_eq!(m.temper(None), 1.0);
        assert_eq!(m.temper(Some(1.0)), 1.0, "independent fixes by default");
        let m = GpsLikelihood::new(GpsConfig {
            correlation_time: 10.0,
            ..Default::default()
        });
        assert!((m.temper(Some(1.0)) - 0.1).abs() < 1e-12);
        assert_eq!(m.temper(Some(30.0)), 1.0);
        assert!(GpsConfig::default().validate().is_ok());
        let bad = GpsConfig {
            outlier_probability: 1.0,
            ..Default::default()
        };
        assert!(bad.validate().is_err());
        assert!(
            GpsConfig {
                correlation_time: f64::NAN,
                ..Default::default()
            }
            .validate()
            .is_err()
        );
    }
}
