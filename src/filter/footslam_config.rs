//! The configuration of [`super::FootSlam`]: every parameter, its unit and default.

use super::resample::ResampleConfig;
use crate::error::{Error, Result};
use crate::geometry::Pose2;
use crate::model::StepMotionConfig;
use serde::{Deserialize, Serialize};

/// FootSLAM's parameters; every default in one place.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FootSlamConfig {
    /// Number of particles `N_p`. Default 20,000.
    pub particles: usize,
    /// Seed of every random draw; equal seeds give equal results on any thread count.
    pub seed: u64,
    /// Hexagon circumradius `r`, metres. Default 0.5 m (the paper's value).
    pub hex_radius: f64,
    /// Dirichlet prior `α^e_h` per edge. Default 0.8 (the paper's value).
    pub alpha: f64,
    /// Apply the paper's direction correction to eq. (6) (sec. 3). Default true.
    pub direction_correction: bool,
    /// The walk's start pose (x, y metres, heading radians). Default (0, 0, 0).
    pub start: Pose2,
    /// Step error model.
    pub motion: StepMotionConfig,
    /// Resampling.
    pub resample: ResampleConfig,
}

impl Default for FootSlamConfig {
    fn default() -> Self {
        Self {
            particles: 20_000,
            seed: 0,
            hex_radius: 0.5,
            alpha: 0.8,
            direction_correction: true,
            start: Pose2::default(),
            motion: StepMotionConfig::default(),
            resample: ResampleConfig::default(),
        }
    }
}

impl FootSlamConfig {
    /// Checks every field against its documented range.
    pub fn validate(&self) -> Result<()> {
        let bad = |field, value: String, reason| {
            Err(Error::Config {
                field,
                value,
                reason,
            })
        };
        if !(1..=100_000_000).contains(&self.particles) {
            return bad(
                "particles",
                self.particles.to_string(),
                "must be in 1..=100000000",
            );
        }
        if !(self.hex_radius.is_finite() && (0.05..=10.0).contains(&self.hex_radius)) {
            return bad(
                "hex_radius",
                self.hex_radius.to_string(),
                "must be in [0.05, 10] metres",
            );
        }
        if !(self.alpha.is_finite() && self.alpha > 0.0 && self.alpha <= 1000.0) {
            return bad("alpha", self.alpha.to_string(), "must be in (0, 1000]");
        }
        let s = self.start;
        if !(s.x.is_finite() && s.y.is_finite() && s.heading.is_finite()) {
            return bad("start", format!("{s:?}"), "must be finite");
        }
        let t = self.resample.ess_threshold;
        if !(t.is_finite() && (0.0..=1.0).contains(&t)) {
            return bad("resample.ess_threshold", t.to_string(), "must be in [0, 1]");
        }
        self.motion
            .validate()
            .or_else(|(field, v, reason)| bad(field, v.to_string(), reason))
    }
}
