//! The absolute-heading measurement model: the likelihood of a compass (magnetometer or
//! rotation-vector) heading given a particle's heading, robust to the tens of degrees by
//! which indoor magnetic fields turn a compass near steel.
//!
//! A measured heading `h` (radians counter-clockwise from east, plus a per-walk `offset`:
//! the phone's forward axis against the walking direction, or a map rotated from north) is
//! modelled as a mixture of a wrapped-normal error about the particle's heading `θ` and a
//! uniform density over the circle (a disturbed reading that says nothing):
//!
//! `p(h | θ) = (1 − ε) · N(wrap_angle(h + offset − θ); 0, σ) + ε / (2π)`        (1)
//!
//! (the wrapped normal is approximated by the normal of the wrapped difference, exact to
//! within `e^{−2π²/σ²}`, below 10⁻²⁰ for `σ ≤ 30°`). The uniform floor bounds what one
//! outlier can cost a particle: the likelihood ratio of the best-placed particle to the
//! worst is at most
//!
//! `1 + (1 − ε) · √(2π) / (σ · ε)`                                           (2)
//!
//! — 29.7 (3.4 nats) with the defaults — so a reading 60° or 180° off cannot wipe out the
//! particles that are right, while ten consistent readings (34 nats) settle a heading.
//!
//! Disturbances persist over metres (a steel pillar turns every reading taken near it the
//! same way), so successive readings are not independent: counted in full, a few metres of
//! readings 20° off would turn the particles as firmly as a long clean stretch. Each
//! reading therefore enters with the exponent
//!
//! `τ = min(1, ℓ / L)`                                                       (3)
//!
//! for a step of length `ℓ` and a disturbance correlation length `L`: over `L` metres the
//! readings weigh about as much as one independent reading, the way GPS fixes are tempered
//! by their correlation time ([`super::GpsLikelihood::temper`]).
//!
//! Defaults and why: `σ = 20°` — indoor magnetometer headings away from disturbances are
//! good to 5–15°, and the walking direction wobbles about the phone's by several degrees
//! per step, so 20° keeps an undisturbed reading from over-ruling the walls; `ε = 0.2` —
//! surveys of indoor magnetic fields find a fifth to a third of places near steel
//! furniture, pillars and radiators disturbed by tens of degrees; with `ε` this large the
//! floor dominates beyond about 2.6σ (52°): a reading that far off costs about as much
//! as one 180° off. Many consistent readings 40–60° off (a long disturbed stretch) still
//! pull, as they should where they might be right; `L` — indoor magnetic anomalies vary
//! over one to a few metres (steel studs, pillars, furniture), so readings a stride apart
//! share most of their disturbance: FootSLAM, which sums a whole walk's readings into the
//! map's orientation, tempers with `L = 3 m`; the tracker, which reads them mostly to
//! settle an unknown heading in the first metres, keeps them independent (`L = 0`; on real
//! phone walks tempering placed fewer waypoints and none better).
//!
//! Not in Woodman & Harle 2008 (whose foot-mounted INS has only relative heading); a
//! compass used the same way in Harle's 2013 survey of pedestrian dead reckoning (§V).

use crate::geometry::wrap_angle;
use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, TAU};

/// Parameters of the heading likelihood; every default in one place.
///
/// | field                 | default | meaning                                                  |
/// |-----------------------|---------|----------------------------------------------------------|
/// | `enabled`             | true    | weight particles by step headings where a step has one   |
/// | `sigma`               | 20°     | `σ` of an undisturbed reading's error (eq. 1), radians   |
/// | `outlier_probability` | 0.2     | `ε`, share of disturbed readings (uniform over the circle) |
/// | `offset`              | 0       | radians added to every measured heading (per walk)       |
/// | `correlation_length`  | 0 m     | distance over which disturbances persist (tempering, eq. 3; FootSLAM: 3 m) |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HeadingConfig {
    /// Use the steps' absolute headings (false: ignore the column).
    pub enabled: bool,
    /// `σ` of an undisturbed reading's error, radians. Default 20° (0.349 rad).
    pub sigma: f64,
    /// `ε`, the prior probability that a reading is disturbed. Default 0.2.
    pub outlier_probability: f64,
    /// Radians added to every measured heading: the phone's forward axis against the
    /// walking direction, or the map's rotation from north. Default 0.
    pub offset: f64,
    /// `L`, the distance walked over which a disturbance persists, metres: readings closer
    /// than `L` are not independent, so each counts with the exponent `min(1, ℓ / L)` for
    /// a step of length `ℓ` (eq. 3). 0: every reading counts in full. Default 0 (FootSLAM
    /// sets 3 m: [`crate::filter::FOOTSLAM_HEADING_CORRELATION`]).
    pub correlation_length: f64,
}

impl Default for HeadingConfig {
    fn default() -> Self {
        Self {
            enabled: true,
            sigma: 20f64.to_radians(),
            outlier_probability: 0.2,
            offset: 0.0,
            correlation_length: 0.0,
        }
    }
}

impl HeadingConfig {
    /// Checks every field; returns the offending field's name, value and rule.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) when `sigma` is outside [0.1°, π] radians,
    /// `outlier_probability` outside (0, 1), `offset` beyond ±2π radians or `correlation_length`
    /// outside [0, 1000] m.
    pub fn validate(&self) -> crate::error::Result<()> {
        let s = self.sigma;
        if !(s.is_finite() && (0.1f64.to_radians()..=PI).contains(&s)) {
            return Err(crate::error::Error::config(
                "heading.sigma",
                s,
                "must be in [0.1°, π] radians",
            ));
        }
        let e = self.outlier_probability;
        if !(e.is_finite() && e > 0.0 && e < 1.0) {
            return Err(crate::error::Error::config(
                "heading.outlier_probability",
                e,
                "must be in (0, 1): the floor keeps an outlier's cost bounded",
            ));
        }
        let o = self.offset;
        if !(o.is_finite() && o.abs() <= TAU) {
            return Err(crate::error::Error::config(
                "heading.offset",
                o,
                "must be in [−2π, 2π] radians",
            ));
        }
        let l = self.correlation_length;
        if !(l.is_finite() && (0.0..=1000.0).contains(&l)) {
            return Err(crate::error::Error::config(
                "heading.correlation_length",
                l,
                "must be in [0, 1000] metres",
            ));
        }
        Ok(())
    }
}

/// The heading likelihood (eq. 1) with its constants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeadingLikelihood {
    config: HeadingConfig,
    /// `(1 − ε) / (σ √(2π))`, the inliers' peak density.
    inlier_peak: f64,
    /// `ε / (2π)`, the outlier floor.
    floor: f64,
    /// `1 / (2σ²)`.
    half_precision: f64,
}

impl HeadingLikelihood {
    /// The model for a validated configuration.
    #[must_use]
    pub fn new(config: HeadingConfig) -> Self {
        let (s, e) = (config.sigma, config.outlier_probability);
        Self {
            inlier_peak: (1.0 - e) / (s * TAU.sqrt()),
            floor: e / TAU,
            half_precision: 0.5 / (s * s),
            config,
        }
    }

    /// The configuration.
    #[must_use]
    pub fn config(&self) -> &HeadingConfig {
        &self.config
    }

    /// True when step headings are to be used.
    #[must_use]
    pub fn enabled(&self) -> bool {
        self.config.enabled
    }

    /// `ln p(h | θ)` (eq. 1) of the measured heading `measured` (before the offset) for a
    /// particle heading `heading`, both radians counter-clockwise from east (any turn).
    #[must_use]
    pub fn log_likelihood(&self, measured: f64, heading: f64) -> f64 {
        let e = wrap_angle(measured + self.config.offset - heading);
        (self.inlier_peak * (-e * e * self.half_precision).exp() + self.floor).ln()
    }

    /// The exponent `τ = min(1, ℓ / L)` of the reading taken on a step of length `ℓ`
    /// metres (eq. 3): a disturbance persists over `L` metres, so the readings within it
    /// count together as about one.
    #[must_use]
    pub fn temper(&self, step_length: f64) -> f64 {
        let l = self.config.correlation_length;
        if l > 0.0 {
            (step_length / l).clamp(0.0, 1.0)
        } else {
            1.0
        }
    }

    /// The largest likelihood ratio between two particles for one reading (eq. 2).
    #[must_use]
    pub fn max_ratio(&self) -> f64 {
        (self.inlier_peak + self.floor) / self.floor
    }

    /// Eq. (1) in the particles' precision, for many particles against one reading:
    /// `measured` is already offset and wrapped ([`Self::offset_measurement`]) and
    /// `heading` in `[−π, π)`, so the difference needs one conditional wrap (no
    /// trigonometry): one `exp` and one `ln` per particle.
    #[inline]
    #[must_use]
    pub fn log_likelihood_f32(&self, constants: &HeadingConstants, heading: f32) -> f32 {
        let mut e = constants.measured - heading;
        if e >= std::f32::consts::PI {
            e -= std::f32::consts::TAU;
        } else if e < -std::f32::consts::PI {
            e += std::f32::consts::TAU;
        }
        (constants.inlier_peak * (-e * e * constants.half_precision).exp() + constants.floor).ln()
    }

    /// The constants of [`Self::log_likelihood_f32`] for one reading `measured`.
    #[must_use]
    pub fn offset_measurement(&self, measured: f64) -> HeadingConstants {
        HeadingConstants {
            measured: wrap_angle(measured + self.config.offset) as f32,
            inlier_peak: self.inlier_peak as f32,
            floor: self.floor as f32,
            half_precision: self.half_precision as f32,
        }
    }

    /// The heading before the first step that best explains the first `window` readings
    /// (each carried back to the start through the measured heading changes, as
    /// [`crate::geometry::Pose2::step`] turns by `dheading` before moving), found by
    /// maximising the sum of eq. (1) over the circle in 0.5° steps — so that disturbed
    /// readings among them do not pull it. Returns the heading and its spread
    /// (`σ / √n` for `n` readings within 2σ of it, at least 2°), or `None` without a
    /// reading.
    #[must_use]
    pub fn start_heading(
        &self,
        steps: &[crate::sensor::Step],
        window: usize,
    ) -> Option<(f64, f64)> {
        let mut turned = 0.0;
        let mut back = Vec::with_capacity(window);
        for s in steps {
            turned += s.dheading;
            if let Some(h) = s.heading {
                back.push(h - turned);
                if back.len() >= window {
                    break;
                }
            }
        }
        if back.is_empty() {
            return None;
        }
        const CANDIDATES: usize = 720;
        let (best, _) = (0..CANDIDATES)
            .map(|i| -PI + TAU * i as f64 / CANDIDATES as f64)
            .map(|c| {
                let ll: f64 = back.iter().map(|&h| self.log_likelihood(h, c)).sum();
                (c, ll)
            })
            .fold(
                (0.0, f64::NEG_INFINITY),
                |a, b| if b.1 > a.1 { b } else { a },
            );
        let best = wrap_angle(best);
        let sigma = self.config.sigma;
        let inliers = back
            .iter()
            .filter(|&&h| wrap_angle(h + self.config.offset - best).abs() <= 2.0 * sigma)
            .count()
            .max(1);
        Some((
            best,
            (sigma / (inliers as f64).sqrt()).max(2f64.to_radians()),
        ))
    }
}

/// Per-reading constants of [`HeadingLikelihood::log_likelihood_f32`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeadingConstants {
    /// The reading plus the offset, wrapped to `[−π, π)`.
    pub measured: f32,
    inlier_peak: f32,
    floor: f32,
    half_precision: f32,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model() -> HeadingLikelihood {
        HeadingLikelihood::new(HeadingConfig::default())
    }

    #[test]
    fn hand_computed_values_at_0_and_180_degrees() {
        let m = model();
        let s = 20f64.to_radians();
        // No error: (1 − 0.2) / (σ √(2π)) + 0.2 / (2π) = 0.8 / 0.874969 + 0.031831.
        let peak = 0.8 / (s * (2.0 * PI).sqrt()) + 0.2 / (2.0 * PI);
        assert!((peak - 0.946139).abs() < 1e-5, "{peak}");
        assert!((m.log_likelihood(1.0, 1.0) - peak.ln()).abs() < 1e-12);
        // 180° off: the Gaussian is e^{−π²/(2σ²)} = e^{−40.5} ≈ 0, only the floor is left.
        let floor = 0.2 / (2.0 * PI);
        assert!((m.log_likelihood(PI, 0.0) - floor.ln()).abs() < 1e-12);
        // One σ off: the Gaussian falls by e^{−1/2}.
        let one = 0.8 / (s * (2.0 * PI).sqrt()) * (-0.5f64).exp() + floor;
        assert!((m.log_likelihood(s, 0.0) - one.ln()).abs() < 1e-12);
        // Wrapping: 179° and −179° are 2° apart; a whole turn changes nothing.
        let (a, b) = (179f64.to_radians(), -179f64.to_radians());
        let two = 0.8 / (s * (2.0 * PI).sqrt()) * (-0.5 * (2f64 / 20.0).powi(2)).exp() + floor;
        assert!((m.log_likelihood(a, b) - two.ln()).abs() < 1e-12);
        assert!((m.log_likelihood(0.3 + TAU, 0.3) - peak.ln()).abs() < 1e-12);
    }

    #[test]
    fn an_outliers_weight_is_bounded_by_eq_2() {
        let m = model();
        // eq. (2): 1 + 0.8 √(2π) / (0.349 · 0.2) = 29.72.
        let bound = m.max_ratio();
        assert!((bound - 29.7238).abs() < 1e-3, "{bound}");
        let best = m.log_likelihood(0.0, 0.0);
        for deg in [60.0, 90.0, 180.0, -120.0] {
            let ratio = (best - m.log_likelihood(f64::to_radians(deg), 0.0)).exp();
            assert!(ratio <= bound + 1e-9, "{deg}°: {ratio}");
        }
        // Without the floor a 60° outlier would cost e^{4.5} = 90.
        assert!((0.5f64 * 3.0 * 3.0).exp() > 90.0);
    }

    #[test]
    fn the_offset_and_the_f32_path_agree() {
        let m = HeadingLikelihood::new(HeadingConfig {
            offset: 0.5,
            ..Default::default()
        });
        assert!((m.log_likelihood(0.0, 0.5) - model().log_likelihood(0.0, 0.0)).abs() < 1e-12);
        for (z, h) in [(3.0, -3.0), (-3.1, 3.1), (0.2, 1.0), (-2.0, 2.5)] {
            let c = m.offset_measurement(z);
            let a = f64::from(m.log_likelihood_f32(&c, h as f32));
            assert!((a - m.log_likelihood(z, h)).abs() < 1e-4, "{z} {h}");
        }
    }

    #[test]
    fn start_heading_ignores_disturbed_readings() {
        use crate::sensor::Step;
        let m = model();
        // The walker turns 0.1 rad a step from a start heading of 1.0; readings are exact
        // but every fifth is 90° off.
        let steps: Vec<Step> = (0..12)
            .map(|k| Step {
                t: f64::from(k),
                length: 0.7,
                dheading: 0.1,
                dz: 0.0,
                heading: Some(
                    1.0 + 0.1 * f64::from(k + 1)
                        + if k % 5 == 0 { 90f64.to_radians() } else { 0.0 },
                ),
            })
            .collect();
        let (h, s) = m.start_heading(&steps, 10).expect("a heading");
        assert!((h - 1.0).abs() < 0.5f64.to_radians(), "{h}");
        assert!(s < 10f64.to_radians() && s >= 2f64.to_radians(), "{s}");
        assert!(m.start_heading(&steps[..0], 10).is_none());
    }

    #[test]
    fn validation() {
        assert!(HeadingConfig::default().validate().is_ok());
        for bad in [
            HeadingConfig {
                outlier_probability: 0.0,
                ..Default::default()
            },
            HeadingConfig {
                sigma: f64::NAN,
                ..Default::default()
            },
            HeadingConfig {
                offset: 10.0,
                ..Default::default()
            },
        ] {
            assert!(bad.validate().is_err(), "{bad:?}");
        }
    }
}
