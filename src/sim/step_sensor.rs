//! A foot-mounted-INS-grade step sensor: turns a true path into the step measurements
//! `Z^U_k` that FootSLAM reads.
//!
//! The errors follow the measurement model of Robertson et al. 2009, sec. 2.3: additive white
//! noise on the stride length and on each heading change, plus an IMU heading drift — a
//! slowly varying, gyro-bias-like rate whose sum over the walk is `±drift_total` (sign drawn
//! at random). The rate is the mean `±drift_total / n` plus a random walk with its mean
//! removed, so the total is exact while the drift still bends the track unevenly. A constant
//! stride-length scale and white height noise complete the model.

use crate::error::{Error, Result};
use crate::geometry::angle::wrap_angle;
use crate::random::gauss;
use crate::sensor::step::{MAX_STEP_LENGTH, Step, StepTrace};
use crate::sensor::truth::{TruePath, TruePose};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};

/// Error parameters of the simulated step sensor (radians, metres); every default in one
/// place. The defaults are those of a foot-mounted IMU.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StepNoiseConfig {
    /// White noise on each stride length, metres (1σ). Default 0.02 m.
    pub length_sigma: f64,
    /// Constant factor on every measured stride length (1 = unbiased). Default 1.0.
    pub length_scale: f64,
    /// White noise on each heading change, radians (1σ). Default 0.5° (0.00873 rad).
    pub dheading_sigma: f64,
    /// Magnitude of the heading drift accumulated over the whole walk, radians; its sign is
    /// drawn at random. Default 15° (0.2618 rad).
    pub drift_total: f64,
    /// Random walk of the drift rate, radians per step per step (1σ), before its mean is
    /// removed. Default 0.001°.
    pub drift_rate_walk_sigma: f64,
    /// White noise on each height change, metres (1σ). Default 0.02 m.
    pub dz_sigma: f64,
}

impl Default for StepNoiseConfig {
    fn default() -> Self {
        Self {
            length_sigma: 0.02,
            length_scale: 1.0,
            dheading_sigma: 0.5_f64.to_radians(),
            drift_total: 15.0_f64.to_radians(),
            drift_rate_walk_sigma: 0.001_f64.to_radians(),
            dz_sigma: 0.02,
        }
    }
}

impl StepNoiseConfig {
    /// A foot-mounted IMU's strides (the default): stride noise 0.02 m, as measured on the
    /// PyShoe hallway walks (robust σ 0.019 m, docs/error-models.md); 15° of drift over the
    /// walk (0.15°/stride over 100 strides: the spread of the hallway walks' drift rates is
    /// 0.14°/stride).
    #[must_use]
    pub fn foot() -> Self {
        Self::default()
    }

    /// A hand-held phone's steps (step-and-heading PDR with the gyroscope): measured on the
    /// ILC site-1 traces (docs/error-models.md) — heading-change noise 0.63° per step (the
    /// measurement's upper bound), stride noise 0.10 m (the data bound it at ≤ 0.23 m),
    /// height noise 0.05 m (a barometer's); 30° of gyro drift over the walk (the traces are
    /// too short to measure it; their bound, 0.11°/step, allows more).
    #[must_use]
    pub fn phone() -> Self {
        Self {
            length_sigma: 0.10,
            length_scale: 1.0,
            dheading_sigma: 0.011,
            drift_total: 30.0_f64.to_radians(),
            drift_rate_walk_sigma: 0.001_f64.to_radians(),
            dz_sigma: 0.05,
        }
    }

    /// A perfect sensor: no noise, no drift, unit scale.
    #[must_use]
    pub fn noise_free() -> Self {
        Self {
            length_sigma: 0.0,
            length_scale: 1.0,
            dheading_sigma: 0.0,
            drift_total: 0.0,
            drift_rate_walk_sigma: 0.0,
            dz_sigma: 0.0,
        }
    }

    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `length_sigma` is outside [0, 0.5] m, `length_scale` outside
    /// [0.5, 1.5], `dheading_sigma` outside [0, 0.5] radians, `drift_total` outside
    /// [0, 100] radians, `drift_rate_walk_sigma` outside [0, 0.01] radians, or `dz_sigma` outside
    /// [0, 0.2] m.
    pub fn validate(&self) -> Result<()> {
        crate::error::check_range("noise.length_sigma", self.length_sigma, 0.0..=0.5, "m")?;
        crate::error::check_range("noise.length_scale", self.length_scale, 0.5..=1.5, "")?;
        crate::error::check_range(
            "noise.dheading_sigma",
            self.dheading_sigma,
            0.0..=0.5,
            "rad",
        )?;
        crate::error::check_range("noise.drift_total", self.drift_total, 0.0..=100.0, "rad")?;
        crate::error::check_range(
            "noise.drift_rate_walk_sigma",
            self.drift_rate_walk_sigma,
            0.0..=0.01,
            "rad",
        )?;
        crate::error::check_range("noise.dz_sigma", self.dz_sigma, 0.0..=0.2, "m")?;
        Ok(())
    }
}

/// The steps a sensor with errors `config` measures along `truth`, drawing from a generator
/// seeded with `seed`.
///
/// Step `k` has the time of pose `k`; its length is the scaled distance from pose `k − 1` (the
/// origin for the first step) to pose `k` plus noise, and its heading change is the true change
/// of direction (from heading 0 for the first step) plus noise plus the drift increment. With
/// [`StepNoiseConfig::noise_free`], dead-reckoning the trace from the origin reproduces `truth`.
///
/// # Errors
///
/// As [`measure_steps_from`].
pub fn measure_steps(truth: &TruePath, config: &StepNoiseConfig, seed: u64) -> Result<StepTrace> {
    let origin = TruePose {
        t: 0.0,
        x: 0.0,
        y: 0.0,
        z: 0.0,
        level: 0,
        heading: 0.0,
    };
    measure_steps_from(truth, &origin, config, seed)
}

/// As [`measure_steps`], for a walk that starts at `start` (position, height and the heading
/// before the first step) instead of the origin facing east.
///
/// # Errors
///
/// [`Error::Config`] when `config` fails [`StepNoiseConfig::validate`]; [`Error::Simulation`] when
/// a measured step fails [`check_step`](crate::sensor::step::check_step), e.g. a height change
/// beyond 1 m between successive poses of `truth`, or poses not in time order.
pub fn measure_steps_from(
    truth: &TruePath,
    start: &TruePose,
    config: &StepNoiseConfig,
    seed: u64,
) -> Result<StepTrace> {
    config.validate()?;
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let drift = drift_increments(truth.len(), config, &mut rng);
    let (mut x, mut y, mut z, mut heading) = (start.x, start.y, start.z, start.heading);
    let mut steps = Vec::with_capacity(truth.len());
    for (pose, drift) in truth.poses.iter().zip(drift) {
        let true_length = (pose.x - x).hypot(pose.y - y);
        let length = config.length_scale * true_length + config.length_sigma * gauss(&mut rng);
        let dheading =
            wrap_angle(pose.heading - heading) + config.dheading_sigma * gauss(&mut rng) + drift;
        steps.push(Step {
            t: pose.t,
            length: length.clamp(0.0, MAX_STEP_LENGTH),
            dheading,
            dz: pose.z - z + config.dz_sigma * gauss(&mut rng),
            heading: None,
        });
        (x, y, z, heading) = (pose.x, pose.y, pose.z, pose.heading);
    }
    StepTrace::new(steps)
        .map_err(|(i, m)| Error::Simulation(format!("simulated step {i} is implausible: {m}")))
}

/// Heading-drift increments for `n` steps: a random walk of the rate with its mean replaced
/// by `±drift_total / n`, so that they sum to `±drift_total`.
fn drift_increments(n: usize, config: &StepNoiseConfig, rng: &mut Pcg64Mcg) -> Vec<f64> {
    if n == 0 {
        return Vec::new();
    }
    let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
    let mut rate = 0.0;
    let walk: Vec<f64> = (0..n)
        .map(|_| {
            rate += config.drift_rate_walk_sigma * gauss(rng);
            rate
        })
        .collect();
    let mean = walk.iter().sum::<f64>() / n as f64;
    let bias = sign * config.drift_total / n as f64;
    walk.into_iter().map(|r| bias + r - mean).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Pose2;
    use crate::sim::office::Office;
    use crate::sim::office_config::OfficeConfig;
    use crate::sim::walk_config::WalkConfig;
    use crate::sim::walker::simulate_walk;

    fn truth() -> TruePath {
        let office = Office::new(&OfficeConfig::default()).expect("office");
        simulate_walk(&office, &WalkConfig::default(), 3).expect("walk")
    }

    #[test]
    fn noise_free_trace_dead_reckons_to_the_truth() {
        let truth = truth();
        let trace = measure_steps(&truth, &StepNoiseConfig::noise_free(), 1).expect("trace");
        assert_eq!(trace.len(), truth.len());
        for (p, q) in trace.dead_reckon(Pose2::default()).iter().zip(&truth.poses) {
            assert!(
                (p.x - q.x).abs() < 1e-9 && (p.y - q.y).abs() < 1e-9,
                "{p:?} vs {q:?}"
            );
            assert!(wrap_angle(p.heading - q.heading).abs() < 1e-9);
        }
        assert!(
            trace
                .steps()
                .iter()
                .zip(&truth.poses)
                .all(|(s, p)| s.t == p.t && s.dz == 0.0)
        );
    }

    #[test]
    fn heading_drift_sums_to_the_configured_total() {
        let truth = truth();
        let config = StepNoiseConfig {
            dheading_sigma: 0.0,
            ..Default::default()
        };
        let true_turn: f64 = truth
            .poses
            .iter()
            .scan(0.0, |h, p| {
                let d = wrap_angle(p.heading - *h);
                *h = p.heading;
                Some(d)
            })
            .sum();
        let mut signs = Vec::new();
        for seed in 0..8 {
            let trace = measure_steps(&truth, &config, seed).expect("trace");
            let measured_turn: f64 = trace.steps().iter().map(|s| s.dheading).sum();
            let drift = measured_turn - true_turn;
            assert!(
                (drift.abs() - 15f64.to_radians()).abs() < 1e-9,
                "seed {seed}: {}°",
                drift.to_degrees()
            );
            signs.push(drift > 0.0);
        }
        assert!(
            signs.contains(&true) && signs.contains(&false),
            "the sign is random"
        );
    }

    #[test]
    fn white_noise_has_the_configured_spread() {
        let truth = truth();
        let config = StepNoiseConfig {
            drift_total: 0.0,
            drift_rate_walk_sigma: 0.0,
            length_scale: 1.1,
            ..Default::default()
        };
        let exact = measure_steps(&truth, &StepNoiseConfig::noise_free(), 0).expect("trace");
        let noisy = measure_steps(&truth, &config, 9).expect("trace");
        let n = exact.len() as f64;
        let pairs = || exact.steps().iter().zip(noisy.steps());
        let length_rms = (pairs()
            .map(|(e, m)| (m.length - 1.1 * e.length).powi(2))
            .sum::<f64>()
            / n)
            .sqrt();
        let dheading_rms = (pairs()
            .map(|(e, m)| (m.dheading - e.dheading).powi(2))
            .sum::<f64>()
            / n)
            .sqrt();
        let dz_rms = (noisy.steps().iter().map(|m| m.dz * m.dz).sum::<f64>() / n).sqrt();
        assert!((0.016..0.024).contains(&length_rms), "{length_rms}");
        assert!(
            (0.4..0.6).contains(&dheading_rms.to_degrees()),
            "{}",
            dheading_rms.to_degrees()
        );
        assert!((0.016..0.024).contains(&dz_rms), "{dz_rms}");
    }

    #[test]
    fn measurement_is_deterministic_and_validated() {
        let truth = truth();
        let config = StepNoiseConfig::default();
        assert_eq!(
            measure_steps(&truth, &config, 4).expect("a"),
            measure_steps(&truth, &config, 4).expect("b")
        );
        assert_ne!(
            measure_steps(&truth, &config, 4).expect("a"),
            measure_steps(&truth, &config, 5).expect("b")
        );
        let bad = StepNoiseConfig {
            length_scale: 0.0,
            ..Default::default()
        };
        assert!(matches!(
            measure_steps(&truth, &bad, 0),
            Err(Error::Config {
                field: "noise.length_scale",
                ..
            })
        ));
        assert!(
            measure_steps(&TruePath::default(), &config, 0)
                .expect("empty")
                .is_empty()
        );
    }
}
