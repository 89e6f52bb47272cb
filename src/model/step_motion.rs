//! The step measurement model of FootSLAM (Robertson et al. 2009, sec. 2.3, Fig. 6) used as
//! the likelihood proposal of eq. (5):
//! `q = p(E_k | E_{k-1}) · p(U_k | Z^U_k, E_k)`.
//!
//! The error state `E_k` holds the correlated errors of the step measurement:
//! * the IMU heading drift, a rate `b_k` (radians per step) following an unbounded random
//!   walk — so the accumulated heading error can drift without limit, as a gyro bias does;
//! * the "duck angle" `ψ_k` between the body's heading and the foot's, a random walk
//!   reflected at `±ψ_max` (20°, "essentially limited by human physiology");
//! * a stride-length scale `s` fixed per walk (a few percent off is common).
//!
//! Given `E_k` the true step `U_k` is the measured one with the drift removed plus white
//! noise on length and heading change.

use crate::geometry::Pose2;
use crate::random::gauss;
use rand::RngExt;
use serde::{Deserialize, Serialize};

/// Noise parameters of the step model; every default in one place.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StepMotionConfig {
    /// White noise on stride length, metres (1σ). Default 0.03 m.
    pub length_sigma: f64,
    /// White noise on each heading change, radians (1σ). Default 1.0° (0.01745 rad).
    pub dheading_sigma: f64,
    /// Extra white noise on a heading change per radian turned (1σ = `dheading_sigma +
    /// dheading_sigma_per_turn · |Δψ|`): real heading errors sit in the turns and grow
    /// with their size (foot walks with per-stride truth: median error 0.5° straight,
    /// 1.8° in 20–60° turns, 3° beyond). Default 0.
    pub dheading_sigma_per_turn: f64,
    /// Share of heading changes drawn from a wider normal (`dheading_tail_factor` times
    /// the σ above): the heavy tail of real turn errors. Default 0.
    pub dheading_tail_share: f64,
    /// How much wider the tail's normal is. Default 5.
    pub dheading_tail_factor: f64,
    /// Initial spread of the heading-drift rate, radians per step (1σ). Default 0.05°/step,
    /// i.e. 30° over a 600-step walk.
    pub drift_rate_sigma0: f64,
    /// Random walk of the heading-drift rate, radians per step per step (1σ).
    /// Default 0.002°.
    pub drift_rate_walk_sigma: f64,
    /// Random walk of the duck angle, radians per step (1σ). Default 0.1°.
    pub duck_walk_sigma: f64,
    /// Bound of the duck angle, radians. Default 20° (the paper's value).
    pub duck_max: f64,
    /// Spread of the per-walk stride-length scale around 1 (1σ). Default 0: eq. (6) favours
    /// paths that cross fewer edges, so a free scale state drifts towards short strides;
    /// enable it only with an absolute reference (GPS) that pins the scale.
    pub length_scale_sigma0: f64,
}

impl Default for StepMotionConfig {
    fn default() -> Self {
        Self {
            length_sigma: 0.03,
            dheading_sigma: 1.0_f64.to_radians(),
            dheading_sigma_per_turn: 0.0,
            dheading_tail_share: 0.0,
            dheading_tail_factor: 5.0,
            drift_rate_sigma0: 0.05_f64.to_radians(),
            drift_rate_walk_sigma: 0.002_f64.to_radians(),
            duck_walk_sigma: 0.1_f64.to_radians(),
            duck_max: 20.0_f64.to_radians(),
            length_scale_sigma0: 0.0,
        }
    }
}

impl StepMotionConfig {
    /// Checks every field; returns the offending field's name and rule.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) for the first field that is not finite or is out of
    /// its range (each from 0 up to a bound far beyond any sensor, e.g. `length_sigma` to 1 m,
    /// `dheading_sigma` to π radians, `duck_max` to π/2 radians), with the range.
    pub fn validate(&self) -> crate::error::Result<()> {
        // Upper bounds far beyond any sensor: a stride known to a metre, a heading change
        // to 180°, a drift of 6° per step; beyond them the samples are meaningless.
        let fields = [
            (
                "motion.length_sigma",
                self.length_sigma,
                1.0,
                "must be in [0, 1] metres",
            ),
            (
                "motion.dheading_sigma",
                self.dheading_sigma,
                std::f64::consts::PI,
                "must be in [0, π] radians",
            ),
            (
                "motion.drift_rate_sigma0",
                self.drift_rate_sigma0,
                0.1,
                "must be in [0, 0.1] radians per step",
            ),
            (
                "motion.drift_rate_walk_sigma",
                self.drift_rate_walk_sigma,
                0.1,
                "must be in [0, 0.1] radians per step²",
            ),
            (
                "motion.duck_walk_sigma",
                self.duck_walk_sigma,
                0.5,
                "must be in [0, 0.5] radians per step",
            ),
            (
                "motion.dheading_sigma_per_turn",
                self.dheading_sigma_per_turn,
                1.0,
                "must be in [0, 1] radians per radian turned",
            ),
            (
                "motion.dheading_tail_share",
                self.dheading_tail_share,
                1.0,
                "must be in [0, 1]",
            ),
            (
                "motion.dheading_tail_factor",
                self.dheading_tail_factor,
                100.0,
                "must be in [0, 100]",
            ),
            (
                "motion.length_scale_sigma0",
                self.length_scale_sigma0,
                0.3,
                "must be in [0, 0.3]",
            ),
        ];
        for (name, v, hi, rule) in fields {
            if !(v.is_finite() && (0.0..=hi).contains(&v)) {
                return Err(crate::error::Error::config(name, v, rule));
            }
        }
        if !(self.duck_max.is_finite()
            && (0.0..=std::f64::consts::FRAC_PI_2).contains(&self.duck_max))
        {
            return Err(crate::error::Error::config(
                "motion.duck_max",
                self.duck_max,
                "must be in [0, π/2] radians",
            ));
        }
        Ok(())
    }
}

/// The error state `E_k` of one particle (f32 keeps particles small; these are small
/// angles and a scale near 1).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepErrorState {
    /// Heading-drift rate `b_k`, radians per step.
    pub drift_rate: f32,
    /// Duck angle `ψ_k`, radians.
    pub duck: f32,
    /// Stride-length scale `s`.
    pub length_scale: f32,
}

/// The step model with its configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepMotion {
    config: StepMotionConfig,
}

impl StepMotion {
    /// The model for a validated configuration.
    #[must_use]
    pub fn new(config: StepMotionConfig) -> Self {
        Self { config }
    }

    /// The configuration.
    #[must_use]
    pub fn config(&self) -> &StepMotionConfig {
        &self.config
    }

    /// Draws `E_0` (Algorithm step 1): a drift rate and length scale from their initial
    /// spreads, duck angle zero.
    pub fn sample_initial(&self, rng: &mut impl rand::Rng) -> StepErrorState {
        StepErrorState {
            drift_rate: (self.config.drift_rate_sigma0 * gauss(rng)) as f32,
            duck: 0.0,
            length_scale: (1.0 + self.config.length_scale_sigma0 * gauss(rng)).max(0.5) as f32,
        }
    }

    /// Draws `E_k ~ p(E_k | E_{k-1})`.
    pub fn sample_error(&self, e: StepErrorState, rng: &mut impl rand::Rng) -> StepErrorState {
        let c = &self.config;
        let drift_rate = f64::from(e.drift_rate) + c.drift_rate_walk_sigma * gauss(rng);
        let duck = reflect(
            f64::from(e.duck) + c.duck_walk_sigma * gauss(rng),
            c.duck_max,
        );
        StepErrorState {
            drift_rate: drift_rate as f32,
            duck: duck as f32,
            length_scale: e.length_scale,
        }
    }

    /// Draws `U_k ~ p(U_k | Z^U_k, E_k)` and applies it to `pose` (Algorithm steps 2a–2b):
    /// the heading turns by the measured change less the drift plus white noise, and the
    /// walker moves the scaled, noisy stride along its body heading (IMU heading plus duck
    /// angle). The returned pose's heading is the IMU heading (without the duck angle).
    pub fn sample_step(
        &self,
        pose: Pose2,
        e: StepErrorState,
        length: f64,
        dheading: f64,
        rng: &mut impl rand::Rng,
    ) -> Pose2 {
        let c = &self.config;
        let mut sigma = c.dheading_sigma + c.dheading_sigma_per_turn * dheading.abs();
        // The tail's draw only where there is a tail, so that streams without one are
        // unchanged.
        if c.dheading_tail_share > 0.0 && rng.random::<f64>() < c.dheading_tail_share {
            sigma *= c.dheading_tail_factor;
        }
        let heading = pose.heading + dheading - f64::from(e.drift_rate) + sigma * gauss(rng);
        let stride = (length * f64::from(e.length_scale) + c.length_sigma * gauss(rng)).max(0.0);
        let direction = heading + f64::from(e.duck);
        Pose2 {
            x: pose.x + stride * direction.cos(),
            y: pose.y + stride * direction.sin(),
            heading,
        }
    }
}

/// Reflects `x` into `[-bound, bound]`.
fn reflect(x: f64, bound: f64) -> f64 {
    if bound <= 0.0 {
        return 0.0;
    }
    let period = 4.0 * bound;
    let y = (x + bound).rem_euclid(period);
    if y <= 2.0 * bound {
        y - bound
    } else {
        3.0 * bound - y
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn reflection_stays_in_bounds() {
        assert!((reflect(0.3, 0.35) - 0.3).abs() < 1e-12);
        assert!((reflect(0.4, 0.35) - 0.3).abs() < 1e-12);
        assert!((reflect(-0.4, 0.35) + 0.3).abs() < 1e-12);
        for i in -100..100 {
            let r = reflect(f64::from(i) * 0.137, 0.35);
            assert!(r.abs() <= 0.35 + 1e-12);
        }
    }

    #[test]
    fn noise_free_model_reproduces_dead_reckoning() {
        let config = StepMotionConfig {
            length_sigma: 0.0,
            dheading_sigma: 0.0,
            drift_rate_sigma0: 0.0,
            drift_rate_walk_sigma: 0.0,
            duck_walk_sigma: 0.0,
            length_scale_sigma0: 0.0,
            ..Default::default()
        };
        let m = StepMotion::new(config);
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(1);
        let e = m.sample_initial(&mut rng);
        let p = m.sample_step(Pose2::default(), e, 0.7, 0.3, &mut rng);
        let q = Pose2::default().step(0.7, 0.3);
        assert!((p.x - q.x).abs() < 1e-12 && (p.y - q.y).abs() < 1e-12);
    }

    #[test]
    fn drift_rate_is_subtracted_from_heading_change() {
        let config = StepMotionConfig {
            length_sigma: 0.0,
            dheading_sigma: 0.0,
            ..Default::default()
        };
        let m = StepMotion::new(config);
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(1);
        let e = StepErrorState {
            drift_rate: 0.1,
            duck: 0.0,
            length_scale: 1.0,
        };
        let p = m.sample_step(Pose2::default(), e, 1.0, 0.1, &mut rng);
        assert!(p.heading.abs() < 1e-6 && (p.x - 1.0).abs() < 1e-6);
    }

    #[test]
    fn turns_draw_wider_heading_noise_than_straight_steps() {
        let config = StepMotionConfig {
            dheading_sigma_per_turn: 0.1,
            dheading_tail_share: 0.1,
            ..Default::default()
        };
        let m = StepMotion::new(config);
        let e = StepErrorState {
            length_scale: 1.0,
            ..Default::default()
        };
        let spread = |dheading: f64| {
            let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(7);
            let errors: Vec<f64> = (0..4000)
                .map(|_| {
                    m.sample_step(Pose2::default(), e, 0.7, dheading, &mut rng)
                        .heading
                        - dheading
                })
                .collect();
            let mean = errors.iter().sum::<f64>() / errors.len() as f64;
            (errors.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / errors.len() as f64).sqrt()
        };
        let (straight, turn) = (spread(0.0), spread(std::f64::consts::FRAC_PI_2));
        // σ = 1° straight and 1° + 0.1·90° = 10° in the turn, the tail widening both.
        assert!(turn > 5.0 * straight, "straight {straight}, turn {turn}");
        assert!(
            turn.to_degrees() > 10.0 && turn.to_degrees() < 25.0,
            "{}",
            turn.to_degrees()
        );
    }

    #[test]
    fn without_a_tail_the_random_stream_is_unchanged() {
        let m = StepMotion::new(StepMotionConfig::default());
        let e = StepErrorState {
            length_scale: 1.0,
            ..Default::default()
        };
        let mut a = rand_pcg::Pcg64Mcg::seed_from_u64(3);
        let mut b = rand_pcg::Pcg64Mcg::seed_from_u64(3);
        let p = m.sample_step(Pose2::default(), e, 0.7, 0.2, &mut a);
        let want = 0.2 + 1.0_f64.to_radians() * gauss(&mut b);
        assert!((p.heading - want).abs() < 1e-12);
    }
}
