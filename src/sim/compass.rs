//! A compass carried on a walk: the absolute heading (the `heading` column of a step trace)
//! as a phone's rotation vector or a magnetometer gives it, with the errors indoor magnetic
//! fields cause.
//!
//! Each step's reading is the true walking direction plus three errors:
//!
//! * white noise, `noise_sigma` (the walking direction wobbles about the sensor's);
//! * a disturbance that follows a first-order Gauss–Markov process over the distance
//!   walked (stationary spread `disturbance_sigma` indoors, `outdoor_disturbance_sigma`
//!   outdoors, correlation length `disturbance_length`): steel in walls, pillars and
//!   furniture turns the field by tens of degrees over stretches of metres, so errors are
//!   correlated along the walk rather than independent per step;
//! * rarely (`outlier_probability`) a reading uniform over the circle (a magnet, a phone
//!   turned in the hand).
//!
//! The readings are thus heavy-tailed and correlated, as the heading likelihood
//! ([`crate::model::HeadingLikelihood`]) assumes they may be.

use crate::error::{Error, Result};
use crate::geometry::angle::wrap_angle;
use crate::random::gauss;
use crate::sensor::step::{Step, StepTrace};
use crate::sensor::truth::{TruePath, TruePose};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Error parameters of the simulated compass; every default in one place.
///
/// | field                         | default | meaning                                        |
/// |-------------------------------|---------|------------------------------------------------|
/// | `enabled`                     | false   | write a `heading` column                       |
/// | `noise_sigma`                 | 5°      | white noise per reading                        |
/// | `disturbance_sigma`           | 20°     | spread of the indoor magnetic disturbance      |
/// | `outdoor_disturbance_sigma`   | 3°      | the same outdoors, away from steel             |
/// | `disturbance_length`          | 5 m     | distance over which a disturbance persists     |
/// | `outlier_probability`         | 0.02    | share of readings uniform over the circle      |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CompassSimConfig {
    /// Give each step an absolute heading. Default false.
    pub enabled: bool,
    /// White noise on each reading, radians (1σ). Default 5°.
    pub noise_sigma: f64,
    /// Stationary spread of the disturbance indoors, radians (1σ). Default 20°.
    pub disturbance_sigma: f64,
    /// Stationary spread of the disturbance outdoors, radians (1σ). Default 3°.
    pub outdoor_disturbance_sigma: f64,
    /// Correlation length of the disturbance along the walk, metres. Default 5 m.
    pub disturbance_length: f64,
    /// Chance that a reading is uniform over the circle. Default 0.02.
    pub outlier_probability: f64,
}

impl Default for CompassSimConfig {
    fn default() -> Self {
        Self {
            enabled: false,
            noise_sigma: 5f64.to_radians(),
            disturbance_sigma: 20f64.to_radians(),
            outdoor_disturbance_sigma: 3f64.to_radians(),
            disturbance_length: 5.0,
            outlier_probability: 0.02,
        }
    }
}

impl CompassSimConfig {
    /// A phone's rotation-vector heading, as measured on the ILC site-1 traces
    /// (docs/error-models.md): 3.3° white noise, a 13° disturbance over 6.5 m, 2.3 % outliers.
    #[must_use]
    pub fn phone() -> Self {
        Self {
            enabled: true,
            noise_sigma: 0.057,
            disturbance_sigma: 0.231,
            disturbance_length: 6.5,
            outlier_probability: 0.023,
            ..Self::default()
        }
    }

    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when a `*_sigma` is outside [0, 3.2] radians, `disturbance_length` outside
    /// [0.1, 1000] m, or `outlier_probability` outside [0, 0.5].
    pub fn validate(&self) -> Result<()> {
        crate::error::check_range("compass.noise_sigma", self.noise_sigma, 0.0..=3.2, "rad")?;
        crate::error::check_range(
            "compass.disturbance_sigma",
            self.disturbance_sigma,
            0.0..=3.2,
            "rad",
        )?;
        crate::error::check_range(
            "compass.outdoor_disturbance_sigma",
            self.outdoor_disturbance_sigma,
            0.0..=3.2,
            "rad",
        )?;
        crate::error::check_range(
            "compass.disturbance_length",
            self.disturbance_length,
            0.1..=1000.0,
            "m",
        )?;
        crate::error::check_range(
            "compass.outlier_probability",
            self.outlier_probability,
            0.0..=0.5,
            "",
        )?;
        Ok(())
    }
}

/// `trace` with each step's absolute heading as the compass `config` reads it along
/// `truth` (which starts at `start`); `outdoors(x, y)` says where the field is clean.
/// Returns `trace` unchanged when the compass is disabled.
///
/// # Errors
///
/// [`Error::Config`] when `config` fails [`CompassSimConfig::validate`] (even when disabled);
/// [`Error::Simulation`] if a step with its reading is implausible (a safeguard: readings are
/// wrapped to ±π).
pub fn read_compass(
    trace: StepTrace,
    start: &TruePose,
    truth: &TruePath,
    outdoors: impl Fn(f64, f64) -> bool,
    config: &CompassSimConfig,
    seed: u64,
) -> Result<StepTrace> {
    config.validate()?;
    if !config.enabled {
        return Ok(trace);
    }
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let (mut x, mut y) = (start.x, start.y);
    // The indoor and outdoor disturbances run side by side; the reading takes the one of
    // where the walker is, so stepping outside clears the field at once.
    let mut unit = gauss(&mut rng);
    let mut steps: Vec<Step> = trace.steps().to_vec();
    for (step, pose) in steps.iter_mut().zip(&truth.poses) {
        let d = (pose.x - x).hypot(pose.y - y);
        (x, y) = (pose.x, pose.y);
        let rho = (-d / config.disturbance_length).exp();
        unit = rho * unit + (1.0 - rho * rho).sqrt() * gauss(&mut rng);
        let spread = if outdoors(pose.x, pose.y) {
            config.outdoor_disturbance_sigma
        } else {
            config.disturbance_sigma
        };
        let noise = config.noise_sigma * gauss(&mut rng);
        let reading = if rng.random_bool(config.outlier_probability) {
            rng.random_range(-PI..PI)
        } else {
            pose.heading + spread * unit + noise
        };
        step.heading = Some(wrap_angle(reading));
    }
    StepTrace::new(steps)
        .map_err(|(i, m)| Error::Simulation(format!("simulated step {i} is implausible: {m}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn straight_walk(n: usize, heading: f64) -> (TruePose, TruePath, StepTrace) {
        let start = TruePose {
            t: 0.0,
            x: 0.0,
            y: 0.0,
            z: 0.0,
            level: 0,
            heading,
        };
        let poses: Vec<TruePose> = (1..=n)
            .map(|k| TruePose {
                t: k as f64 * 0.5,
                x: 0.7 * k as f64 * heading.cos(),
                y: 0.7 * k as f64 * heading.sin(),
                ..start
            })
            .collect();
        let steps = poses
            .iter()
            .map(|p| Step {
                t: p.t,
                length: 0.7,
                dheading: 0.0,
                dz: 0.0,
                heading: None,
            })
            .collect();
        let truth = TruePath { poses };
        (start, truth, StepTrace::new(steps).expect("trace"))
    }

    #[test]
    fn readings_scatter_about_the_true_heading_with_correlated_heavy_tailed_errors() {
        let heading = 1.0;
        let (start, truth, trace) = straight_walk(4000, heading);
        let config = CompassSimConfig {
            enabled: true,
            ..Default::default()
        };
        let read =
            read_compass(trace.clone(), &start, &truth, |_, _| false, &config, 7).expect("compass");
        let errors: Vec<f64> = read
            .steps()
            .iter()
            .map(|s| wrap_angle(s.heading.expect("heading") - heading))
            .collect();
        let mut sorted: Vec<f64> = errors.iter().map(|e| e.abs()).collect();
        sorted.sort_by(f64::total_cmp);
        let median = sorted[sorted.len() / 2].to_degrees();
        // |N(0, √(20² + 5²))| has a median of 13.9°.
        assert!((10.0..18.0).contains(&median), "median {median}°");
        // Heavy tail: the outliers put a few percent beyond 70° (3.4σ).
        let far = sorted.iter().filter(|e| e.to_degrees() > 70.0).count() as f64;
        assert!((0.005..0.03).contains(&(far / 4000.0)), "{far}");
        // Correlated over metres: successive errors agree far more than independent ones.
        let lag1: f64 = errors.windows(2).map(|w| w[0] * w[1]).sum::<f64>()
            / errors.iter().map(|e| e * e).sum::<f64>();
        assert!(lag1 > 0.5, "lag-1 correlation {lag1}");
        // Outdoors the field is clean; disabled, nothing changes.
        let outside =
            read_compass(trace.clone(), &start, &truth, |_, _| true, &config, 7).expect("compass");
        let quiet = outside
            .steps()
            .iter()
            .filter(|s| {
                wrap_angle(s.heading.expect("heading") - heading).abs() < 20f64.to_radians()
            })
            .count();
        assert!(quiet > 3850, "{quiet}");
        let off = read_compass(
            trace.clone(),
            &start,
            &truth,
            |_, _| false,
            &CompassSimConfig::default(),
            7,
        )
        .expect("off");
        assert_eq!(off, trace);
    }
}
