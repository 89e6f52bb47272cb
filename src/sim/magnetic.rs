//! A building's magnetic field for simulated walks: the Earth's field bent by steel, and a
//! magnetometer that reads it over each step ([`crate::sensor::StepField`]). The
//! simulators draw it over the building's plan from `field.seed`, so that walks of one
//! building read one field ([`MagneticWorld::of_plan`]).
//!
//! The field at a point is the Earth's (`earth_ut`, dipping `inclination` below the
//! horizon, pointing north) plus one anomaly per `anomaly_spacing_m`² of floor: a random
//! vector of spread `anomaly_ut` per axis that fades as a Gaussian of `anomaly_length_m`
//! about a random point (a steel column, a radiator, reinforcement). It depends on the
//! place and the level only, as indoor fields do over the minutes of a walk. Each step's
//! reading is the field at its end point plus white noise `noise_ut` (per component).

use crate::map::FloorPlan;
use crate::random::gauss;
use crate::sensor::{StepField, StepFields, TruePath};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};

/// Parameters of the simulated field; every default in one place.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FieldSimConfig {
    /// Give each step a field reading (`steps.csv`'s `field`, `field_up`). Default false.
    pub enabled: bool,
    /// Seed of the anomalies: walks of one building with the same seed read one field.
    /// Default 0.
    pub seed: u64,
    /// The Earth's field strength, µT. Default 48.
    pub earth_ut: f64,
    /// Its inclination below the horizon, radians. Default 65°.
    pub inclination: f64,
    /// Spread of an anomaly's vector per axis, µT. Default 8.
    pub anomaly_ut: f64,
    /// Distance over which an anomaly fades (1σ of its Gaussian), metres. Default 1.2.
    pub anomaly_length_m: f64,
    /// One anomaly per square of this side, metres. Default 2.5.
    pub anomaly_spacing_m: f64,
    /// White noise of a step's reading per component, µT. Default 0.4.
    pub noise_ut: f64,
}

impl Default for FieldSimConfig {
    fn default() -> Self {
        Self {
            enabled: false,
            seed: 0,
            earth_ut: 48.0,
            inclination: 65f64.to_radians(),
            anomaly_ut: 8.0,
            anomaly_length_m: 1.2,
            anomaly_spacing_m: 2.5,
            noise_ut: 0.4,
        }
    }
}

impl FieldSimConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) when `earth_ut` is outside [0, 200] µT,
    /// `inclination` outside [−1.6, 1.6] radians, `anomaly_ut` outside [0, 500] µT,
    /// `anomaly_length_m` outside [0.05, 100] m, `anomaly_spacing_m` outside [0.5, 1000] m, or
    /// `noise_ut` outside [0, 50] µT.
    pub fn validate(&self) -> crate::error::Result<()> {
        use crate::error::check_range;
        check_range("field.earth_ut", self.earth_ut, 0.0..=200.0, "µT")?;
        check_range("field.inclination", self.inclination, -1.6..=1.6, "rad")?;
        check_range("field.anomaly_ut", self.anomaly_ut, 0.0..=500.0, "µT")?;
        check_range(
            "field.anomaly_length_m",
            self.anomaly_length_m,
            0.05..=100.0,
            "m",
        )?;
        check_range(
            "field.anomaly_spacing_m",
            self.anomaly_spacing_m,
            0.5..=1000.0,
            "m",
        )?;
        check_range("field.noise_ut", self.noise_ut, 0.0..=50.0, "µT")
    }
}

/// A building's field: the anomalies over the area of a walk.
#[derive(Debug, Clone)]
pub struct MagneticWorld {
    config: FieldSimConfig,
    /// `(x, y, level, vector)` of each anomaly.
    anomalies: Vec<(f64, f64, i32, [f64; 3])>,
}

impl MagneticWorld {
    /// Anomalies over the area of `truth` (with a margin of three fading lengths), on each
    /// level it visits, drawn from `seed`.
    #[must_use]
    pub fn around(truth: &TruePath, config: FieldSimConfig, seed: u64) -> Self {
        let mut levels: Vec<i32> = truth.poses.iter().map(|p| p.level).collect();
        levels.sort_unstable();
        levels.dedup();
        let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
        for p in &truth.poses {
            (x0, y0, x1, y1) = (x0.min(p.x), y0.min(p.y), x1.max(p.x), y1.max(p.y));
        }
        if truth.poses.is_empty() {
            return Self {
                config,
                anomalies: Vec::new(),
            };
        }
        Self::over((x0, y0, x1, y1), &levels, config, seed)
    }

    /// A building's field: anomalies over the plan's extent (with the margin) on each of its
    /// levels, drawn from `config.seed`, so that every walk of the building reads the same.
    #[must_use]
    pub fn of_plan(plan: &FloorPlan, config: FieldSimConfig) -> Self {
        match plan.bounds() {
            Some(b) => Self::over(b, &plan.levels(), config, config.seed),
            None => Self {
                config,
                anomalies: Vec::new(),
            },
        }
    }

    /// Anomalies over `(x0, y0, x1, y1)` with a margin of three fading lengths, on `levels`.
    fn over(
        (x0, y0, x1, y1): (f64, f64, f64, f64),
        levels: &[i32],
        config: FieldSimConfig,
        seed: u64,
    ) -> Self {
        let mut rng = Pcg64Mcg::seed_from_u64(seed);
        let margin = 3.0 * config.anomaly_length_m;
        let area = (x1 - x0 + 2.0 * margin) * (y1 - y0 + 2.0 * margin);
        let count = (area / config.anomaly_spacing_m.powi(2)).ceil() as usize;
        let mut anomalies = Vec::with_capacity(count * levels.len());
        for &level in levels {
            for _ in 0..count {
                let x = rng.random_range(x0 - margin..=x1 + margin);
                let y = rng.random_range(y0 - margin..=y1 + margin);
                let v = [0; 3].map(|_| config.anomaly_ut * gauss(&mut rng));
                anomalies.push((x, y, level, v));
            }
        }
        Self { config, anomalies }
    }

    /// The field vector (east, north, up) at `(x, y)` on `level`, µT.
    #[must_use]
    pub fn field_at(&self, x: f64, y: f64, level: i32) -> [f64; 3] {
        let c = &self.config;
        let (s, k) = c.inclination.sin_cos();
        let mut b = [0.0, c.earth_ut * k, -c.earth_ut * s];
        let two_l2 = 2.0 * c.anomaly_length_m * c.anomaly_length_m;
        for &(ax, ay, al, v) in &self.anomalies {
            if al != level {
                continue;
            }
            let d2 = (x - ax).powi(2) + (y - ay).powi(2);
            if d2 < 16.0 * two_l2 {
                let f = (-d2 / two_l2).exp();
                for i in 0..3 {
                    b[i] += f * v[i];
                }
            }
        }
        b
    }

    /// Each step's reading along `truth`, with the configured noise drawn from `seed`.
    ///
    /// # Errors
    ///
    /// [`Error::Simulation`](crate::Error::Simulation) naming the step when a reading is not
    /// finite or its magnitude exceeds [`MAX_FIELD`](crate::sensor::field::MAX_FIELD)
    /// (2000 µT): a `truth` that is not finite, a configuration outside
    /// [`FieldSimConfig::validate`]'s ranges (not checked here), or anomalies so strong and
    /// close that they add up beyond it.
    pub fn readings_along(&self, truth: &TruePath, seed: u64) -> crate::error::Result<StepFields> {
        let mut rng = Pcg64Mcg::seed_from_u64(seed);
        let noise = self.config.noise_ut;
        let fields = truth
            .poses
            .iter()
            .map(|p| {
                let b = self.field_at(p.x, p.y, p.level);
                let magnitude = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt();
                let magnitude = (magnitude + noise * gauss(&mut rng)).max(0.0);
                let vertical = (b[2] + noise * gauss(&mut rng)).clamp(-magnitude, magnitude);
                Some(StepField {
                    magnitude,
                    vertical: Some(vertical),
                })
            })
            .collect();
        StepFields::new(fields).map_err(|(i, problem)| {
            crate::error::Error::Simulation(format!(
                "the simulated magnetic field at step {i}: {problem}; weaken or space out the \
                 anomalies (field.anomaly_ut, field.anomaly_spacing_m)"
            ))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::TruePose;

    #[test]
    fn the_field_is_a_place_signature() {
        let poses = (0..200)
            .map(|i| TruePose {
                t: f64::from(i),
                x: f64::from(i % 100) * 0.5,
                y: 0.0,
                z: 0.0,
                level: 0,
                heading: 0.0,
            })
            .collect();
        let truth = TruePath { poses };
        let world = MagneticWorld::around(&truth, FieldSimConfig::default(), 7);
        let f = world.readings_along(&truth, 1).expect("readings");
        let m = |i: usize| f.get(i).unwrap().magnitude;
        // The same place twice (a lap apart) agrees far better than places 10 m apart.
        let same: f64 = (0..100).map(|i| (m(i) - m(i + 100)).abs()).sum::<f64>() / 100.0;
        let other: f64 = (0..80).map(|i| (m(i) - m(i + 20)).abs()).sum::<f64>() / 80.0;
        assert!(same < 1.0 && other > 3.0 * same, "{same} {other}");
        assert_eq!(world.field_at(3.0, 0.0, 0), world.field_at(3.0, 0.0, 0));
        assert_ne!(world.field_at(3.0, 0.0, 0), world.field_at(3.0, 0.0, 1));
        // Anomalies strong and dense enough to add up past 2000 µT: an error naming the
        // step, not a panic.
        let wild = FieldSimConfig {
            anomaly_ut: 500.0,
            anomaly_spacing_m: 0.5,
            anomaly_length_m: 10.0,
            ..FieldSimConfig::default()
        };
        let err = MagneticWorld::around(&truth, wild, 7)
            .readings_along(&truth, 1)
            .expect_err("beyond any real field");
        assert!(err.to_string().contains("anomaly_ut"), "{err}");
    }
}
