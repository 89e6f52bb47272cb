//! Height changes from air pressure: the hypsometric (barometric) formula of the
//! International Standard Atmosphere,
//!
//! ```text
//! h(p) = (T₀ / L) · (1 − (p / p₀)^{R L / g M}) = 44 330.8 m · (1 − (p / 1013.25 hPa)^{0.190263})
//! ```
//!
//! whose slope near sea level is `dh/dp ≈ −8.3 m/hPa`. Only differences are used, so the
//! weather's slow drift of `p₀` cancels over a walk's minutes. The height is low-passed
//! (a phone barometer's noise is about ±0.1 m per sample) and differenced between steps.

use crate::error::Result;
use serde::{Deserialize, Serialize};

/// ISA sea-level pressure `p₀`, hPa.
pub const SEA_LEVEL_PRESSURE: f64 = 1013.25;
/// `T₀ / L` of the ISA troposphere, metres (288.15 K / 0.0065 K/m).
const ISA_SCALE_HEIGHT: f64 = 44_330.8;
/// The exponent `R L / (g M)` of the ISA troposphere.
const ISA_EXPONENT: f64 = 0.190_263;

/// Parameters of the barometric height; every default in one place.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BarometerConfig {
    /// Time constant of the low-pass on the pressure height, seconds. Default 1.5 s: noise
    /// falls about four-fold at 50 Hz while a staircase's 0.17 m per step still shows
    /// within two steps (and the total height change is kept exactly).
    pub time_constant_s: f64,
}

impl Default for BarometerConfig {
    fn default() -> Self {
        Self {
            time_constant_s: 1.5,
        }
    }
}

impl BarometerConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) when `time_constant_s` is outside [0, 60] s.
    pub fn validate(&self) -> Result<()> {
        let t = self.time_constant_s;
        if t.is_finite() && (0.0..=60.0).contains(&t) {
            Ok(())
        } else {
            Err(crate::error::Error::config(
                "phone.barometer.time_constant_s",
                t.to_string(),
                "must be in [0, 60] s",
            ))
        }
    }
}

/// Pressure altitude of `pressure` hPa in the ISA, metres (the hypsometric formula).
#[must_use]
pub fn pressure_height(pressure: f64) -> f64 {
    ISA_SCALE_HEIGHT * (1.0 - (pressure / SEA_LEVEL_PRESSURE).powf(ISA_EXPONENT))
}

/// The low-passed pressure height, one sample at a time (no allocation).
#[derive(Debug, Clone)]
pub struct Barometer {
    time_constant_s: f64,
    height: Option<f64>,
}

impl Barometer {
    /// A barometer filter; `config` must be valid.
    #[must_use]
    pub fn new(config: &BarometerConfig) -> Self {
        Self {
            time_constant_s: config.time_constant_s,
            height: None,
        }
    }

    /// Feeds one pressure reading (hPa) `dt` seconds after the previous; returns the
    /// filtered height, metres.
    pub fn update(&mut self, dt: f64, pressure: f64) -> f64 {
        let h = pressure_height(pressure);
        let filtered = match self.height {
            None => h,
            Some(prev) => prev + dt / (self.time_constant_s + dt) * (h - prev),
        };
        self.height = Some(filtered);
        filtered
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_drop_of_0_36_hpa_is_about_3_metres_up() {
        // Slope 44 330.8 · 0.190263 / 1013.25 = 8.324 m/hPa → 0.36 hPa ≈ 3.0 m.
        let dz = pressure_height(1013.25 - 0.36) - pressure_height(1013.25);
        assert!((dz - 3.0).abs() < 0.02, "{dz}");
        assert!(pressure_height(SEA_LEVEL_PRESSURE).abs() < 1e-9);
    }

    #[test]
    fn the_filtered_height_settles_on_the_new_level() {
        let mut b = Barometer::new(&BarometerConfig::default());
        let h0 = b.update(0.0, 1000.0);
        for _ in 0..1000 {
            b.update(0.02, 1000.0 - 0.36); // 20 s at 50 Hz, 13 time constants
        }
        let dz = b.update(0.02, 999.64) - h0;
        assert!((dz - 3.0).abs() < 0.05, "{dz}"); // 8.43 m/hPa at 1000 hPa
    }
}
