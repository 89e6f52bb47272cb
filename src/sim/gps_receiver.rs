//! A GPS receiver carried on a walk: 1 Hz fixes while outdoors, with the errors Robertson et
//! al. 2009 saw (sec. 4.1: 3–7 m with a slowly varying bias).
//!
//! The error of each fix is a bias that follows a first-order Gauss–Markov process in each
//! horizontal axis (stationary spread `bias_sigma`, correlation time `bias_time`), plus white
//! noise (`noise_sigma` per axis), plus, rarely, an outlier 50–100 m off in a random
//! direction. The bias runs all the time, indoors too, so a walker leaving the building sees
//! a bias that drifted while inside. Each fix states its accuracy as
//! `√(bias_sigma² + noise_sigma²)`.

use crate::error::Result;
use crate::geometry::LocalFrame;
use crate::random::gauss;
use crate::sensor::GpsFix;
use crate::sensor::truth::{TruePath, TruePose};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};

/// Error parameters of the simulated receiver; every default in one place.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GpsSimConfig {
    /// Fixes per second. Default 1 Hz.
    pub rate: f64,
    /// Stationary spread of the bias per axis, metres (1σ). Default 3 m.
    pub bias_sigma: f64,
    /// Correlation time of the bias, seconds. Default 300 s.
    pub bias_time: f64,
    /// White noise per axis, metres (1σ). Default 1.5 m.
    pub noise_sigma: f64,
    /// Chance that a fix is an outlier 50–100 m off. Default 0.01.
    pub outlier_probability: f64,
}

impl Default for GpsSimConfig {
    fn default() -> Self {
        Self {
            rate: 1.0,
            bias_sigma: 3.0,
            bias_time: 300.0,
            noise_sigma: 1.5,
            outlier_probability: 0.01,
        }
    }
}

impl GpsSimConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) when `rate` is outside [0.01, 20] Hz, `bias_sigma`
    /// or `noise_sigma` outside [0, 100] m, `bias_time` outside [1, 100 000] s, or
    /// `outlier_probability` outside [0, 0.5].
    pub fn validate(&self) -> Result<()> {
        crate::error::check_range("gps.rate", self.rate, 0.01..=20.0, "Hz")?;
        crate::error::check_range("gps.bias_sigma", self.bias_sigma, 0.0..=100.0, "m")?;
        crate::error::check_range("gps.bias_time", self.bias_time, 1.0..=100000.0, "s")?;
        crate::error::check_range("gps.noise_sigma", self.noise_sigma, 0.0..=100.0, "m")?;
        crate::error::check_range(
            "gps.outlier_probability",
            self.outlier_probability,
            0.0..=0.5,
            "",
        )?;
        Ok(())
    }

    /// The accuracy each fix states, metres.
    #[must_use]
    pub fn stated_accuracy(&self) -> f64 {
        self.bias_sigma.hypot(self.noise_sigma).max(0.5)
    }
}

/// Fixes of one walk and the horizontal error of each (metres).
#[derive(Debug, Clone, PartialEq)]
pub struct GpsRecord {
    /// The fixes, on the steps' clock.
    pub fixes: Vec<GpsFix>,
    /// Horizontal distance of each fix from the truth, metres.
    pub errors: Vec<f64>,
}

/// Summary of a walk's GPS errors, metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GpsErrorSummary {
    /// Mean horizontal error (0 without fixes).
    pub mean: f64,
    /// Root mean square error (0 without fixes).
    pub rms: f64,
    /// 95th percentile, nearest rank (0 without fixes).
    pub p95: f64,
}

impl GpsRecord {
    /// The mean, root mean square and 95th percentile (nearest rank: the error of rank
    /// `⌈0.95·n⌉` of `n` sorted ascending) of the fixes' errors.
    pub fn error_summary(&self) -> GpsErrorSummary {
        let errors = &self.errors;
        let n = errors.len().max(1) as f64;
        let mut sorted = errors.clone();
        sorted.sort_by(f64::total_cmp);
        let p95 = sorted
            .get(((sorted.len() as f64 * 0.95).ceil() as usize).saturating_sub(1))
            .copied()
            .unwrap_or(0.0);
        GpsErrorSummary {
            mean: errors.iter().sum::<f64>() / n,
            rms: (errors.iter().map(|e| e * e).sum::<f64>() / n).sqrt(),
            p95,
        }
    }
}

/// The fixes of a walk from `start` (at time `start.t`) along `truth`, taken every `1/rate`
/// seconds while `outdoors(x, y)` holds at the true position, placed on the globe by
/// `frame`; drawn from a generator seeded with `seed`.
///
/// # Errors
///
/// [`Error::Config`](crate::Error::Config) when `config` fails [`GpsSimConfig::validate`].
pub fn receive_fixes(
    start: &TruePose,
    truth: &TruePath,
    outdoors: impl Fn(f64, f64) -> bool,
    frame: &LocalFrame,
    config: &GpsSimConfig,
    seed: u64,
) -> Result<GpsRecord> {
    config.validate()?;
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let end = truth.poses.last().map_or(start.t, |p| p.t);
    let dt = 1.0 / config.rate;
    let phi = (-dt / config.bias_time).exp();
    let drive = config.bias_sigma * (1.0 - phi * phi).sqrt();
    let mut bias = (
        config.bias_sigma * gauss(&mut rng),
        config.bias_sigma * gauss(&mut rng),
    );
    let accuracy = config.stated_accuracy();
    let mut record = GpsRecord {
        fixes: Vec::new(),
        errors: Vec::new(),
    };
    let mut k = 0u64;
    loop {
        let t = start.t + k as f64 * dt;
        if t > end {
            break;
        }
        if k > 0 {
            bias = (
                phi * bias.0 + drive * gauss(&mut rng),
                phi * bias.1 + drive * gauss(&mut rng),
            );
        }
        k += 1;
        // Draw the noise every epoch, so that one epoch's draws do not depend on where the
        // walker was at the others.
        let noise = (
            config.noise_sigma * gauss(&mut rng),
            config.noise_sigma * gauss(&mut rng),
        );
        let outlier = rng.random_bool(config.outlier_probability);
        let (distance, angle) = (
            rng.random_range(50.0..100.0),
            rng.random_range(0.0..std::f64::consts::TAU),
        );
        let TruePose { x, y, .. } = truth.pose_at(start, t);
        if !outdoors(x, y) {
            continue;
        }
        let (mut ex, mut ey) = (bias.0 + noise.0, bias.1 + noise.1);
        if outlier {
            ex += distance * angle.cos();
            ey += distance * angle.sin();
        }
        let (lon, lat) = frame.to_lon_lat(x + ex, y + ey);
        record.fixes.push(GpsFix {
            t,
            lat,
            lon,
            accuracy,
        });
        record.errors.push(ex.hypot(ey));
    }
    Ok(record)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn straight(n: usize) -> (TruePose, TruePath) {
        let start = TruePose {
            t: 0.0,
            x: 0.0,
            y: 0.0,
            z: 0.0,
            level: 0,
            heading: 0.0,
        };
        let poses = (1..=n)
            .map(|i| TruePose {
                t: i as f64 * 0.5,
                x: i as f64 * 0.7,
                ..start
            })
            .collect();
        (start, TruePath { poses })
    }

    #[test]
    fn error_summary_by_hand() {
        let record = |errors: Vec<f64>| GpsRecord {
            fixes: Vec::new(),
            errors,
        };
        // 20 errors 1..=20 m: mean 10.5, rms √(2870/20), p95 the 19th.
        let s = record((1..=20).map(f64::from).collect()).error_summary();
        assert_eq!((s.mean, s.p95), (10.5, 19.0));
        assert!((s.rms - (2870.0f64 / 20.0).sqrt()).abs() < 1e-12);
        let none = record(Vec::new()).error_summary();
        assert_eq!((none.mean, none.rms, none.p95), (0.0, 0.0, 0.0));
    }

    #[test]
    fn fixes_only_outdoors_with_errors_of_metres() {
        let (start, truth) = straight(2000); // 1000 s
        let frame = LocalFrame::new(48.0, 11.0).expect("frame");
        let config = GpsSimConfig {
            outlier_probability: 0.0,
            ..Default::default()
        };
        let rec = receive_fixes(
            &start,
            &truth,
            |x, _| !(300.0..=600.0).contains(&x),
            &frame,
            &config,
            5,
        )
        .expect("fixes");
        // 1.4 m/s: x < 300 for t < 214.3 s, x > 600 from t > 428.6 s to 1000 s.
        assert!(
            (780..=790).contains(&rec.fixes.len()),
            "{}",
            rec.fixes.len()
        );
        for (f, e) in rec.fixes.iter().zip(&rec.errors) {
            let TruePose { x, y, .. } = truth.pose_at(&start, f.t);
            let (fx, fy) = frame.to_local(f.lon, f.lat);
            assert!(((fx - x).hypot(fy - y) - e).abs() < 1e-3);
            assert!(!(300.0..=600.0).contains(&x));
        }
        // Errors of metres, correlated: neighbouring fixes differ much less than the spread.
        let mean = rec.errors.iter().sum::<f64>() / rec.errors.len() as f64;
        assert!((1.0..10.0).contains(&mean), "{mean}");
        assert!((rec.fixes[0].accuracy - 3.354).abs() < 1e-3);
        assert_eq!(
            rec,
            receive_fixes(
                &start,
                &truth,
                |x, _| !(300.0..=600.0).contains(&x),
                &frame,
                &config,
                5
            )
            .expect("again")
        );
    }

    #[test]
    fn outliers_are_far_off() {
        let (start, truth) = straight(400);
        let frame = LocalFrame::default();
        let config = GpsSimConfig {
            outlier_probability: 0.5,
            ..Default::default()
        };
        let rec = receive_fixes(&start, &truth, |_, _| true, &frame, &config, 1).expect("fixes");
        let far = rec.errors.iter().filter(|&&e| e > 35.0).count();
        assert!(
            far > rec.errors.len() / 4 && far < rec.errors.len() * 3 / 4,
            "{far}"
        );
        assert!(
            GpsSimConfig {
                rate: 0.0,
                ..Default::default()
            }
            .validate()
            .is_err()
        );
    }
}
