//! The walking direction of a phone held in front of the body: from the rotation vector, or
//! from a complementary filter of gyroscope and magnetometer, or from the gyroscope alone
//! (Harle 2013, §V-B and §IV-B; Ab Rahman et al., §2.3 after Kang et al. 2012).
//!
//! **Forward axis.** Held in portrait in front of the body, the phone's top (+y) points
//! ahead when the phone lies flat and its back (−z) points ahead when it stands upright; in
//! between both lean forward. The walking direction is therefore the horizontal part of
//! `f = R·(0, 1, −1)ᵀ` (R: sensor → east-north-up), which stays well defined from flat to
//! upright (|`f_h`| ≥ 1 for any pitch in [0°, 90°]); heading `ψ = atan2(f_N, f_E)`, radians
//! counter-clockwise from east.
//!
//! **Gyro + magnetometer.** Gravity's direction `u` in the sensor frame comes from the
//! low-passed accelerometer; the yaw rate is the angular rate about it, `ψ̇ = ω·u`, and the
//! tilt-compensated magnetometer heading takes `east = m × u`, `north = u × east` (the
//! construction of Android's `getRotationMatrix`). The complementary filter
//!
//! ```text
//! ψ_k = ψ_{k−1} + (ω·u) Δt                              (gyro propagation)
//! ψ_k ← ψ_k + Δt/(τ_m + Δt) · wrap(ψ_mag − ψ_k)          (magnetometer correction)
//! ```
//!
//! trusts the gyroscope over seconds and the magnetometer over `τ_m`; readings whose field
//! strength is outside the geomagnetic range (steel, motors) are skipped.

use crate::error::Result;
use crate::geometry::wrap_turn;
use serde::{Deserialize, Serialize};

/// Parameters of the heading estimate; every default in one place.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HeadingFusionConfig {
    /// Magnetic declination at the site, radians, east positive: absolute headings
    /// (rotation vector and magnetometer, both referenced to magnetic north) are turned
    /// to true north by `ψ_true = ψ_mag − declination`. Default 0 (on the ILC 2.0 site the
    /// rotation vector agreed with the map's north within 1°; see docs/phone-pdr.md).
    pub declination: f64,
    /// Time constant `τ_m` of the magnetometer correction, seconds. Default 5 s: indoor
    /// disturbances pass within a few steps, the gyroscope drifts about 1°/min.
    pub magnetometer_time_constant_s: f64,
    /// Time constant of the accelerometer low-pass giving gravity's direction, seconds.
    /// Default 0.5 s (attenuates the 2 Hz step oscillation about six-fold).
    pub tilt_time_constant_s: f64,
    /// Magnetometer readings are used only with a field strength in this range, µT.
    /// Default [20, 70] µT: Earth's field is 25–65 µT.
    pub magnetic_field_range: [f64; 2],
}

impl Default for HeadingFusionConfig {
    fn default() -> Self {
        Self {
            declination: 0.0,
            magnetometer_time_constant_s: 5.0,
            tilt_time_constant_s: 0.5,
            magnetic_field_range: [20.0, 70.0],
        }
    }
}

impl HeadingFusionConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) when `declination` is beyond ±π radians,
    /// `magnetometer_time_constant_s` outside [0.01, 3600] s, `tilt_time_constant_s` outside
    /// [0.01, 10] s, or `magnetic_field_range` is not two finite µT values `0 ≤ low < high`.
    pub fn validate(&self) -> Result<()> {
        if !(self.declination.is_finite() && self.declination.abs() <= std::f64::consts::PI) {
            return Err(crate::error::Error::config(
                "phone.heading.declination",
                self.declination.to_string(),
                "must be in [-π, π] radians",
            ));
        }
        let tm = self.magnetometer_time_constant_s;
        if !(tm.is_finite() && (0.01..=3600.0).contains(&tm)) {
            return Err(crate::error::Error::config(
                "phone.heading.magnetometer_time_constant_s",
                tm.to_string(),
                "must be in [0.01, 3600] s",
            ));
        }
        let tt = self.tilt_time_constant_s;
        if !(tt.is_finite() && (0.01..=10.0).contains(&tt)) {
            return Err(crate::error::Error::config(
                "phone.heading.tilt_time_constant_s",
                tt.to_string(),
                "must be in [0.01, 10] s",
            ));
        }
        let [lo, hi] = self.magnetic_field_range;
        if !(lo.is_finite() && hi.is_finite() && 0.0 <= lo && lo < hi) {
            return Err(crate::error::Error::config(
                "phone.heading.magnetic_field_range",
                format!("[{lo}, {hi}]"),
                "must be two finite µT values, 0 ≤ low < high",
            ));
        }
        Ok(())
    }
}

/// The dot product of two 3-vectors.
pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn normalise(v: [f64; 3]) -> Option<[f64; 3]> {
    let n = dot(v, v).sqrt();
    (n > 1e-9 && n.is_finite()).then(|| [v[0] / n, v[1] / n, v[2] / n])
}

/// The horizontal forward vector `(f_E, f_N)` of a phone with orientation `q = [x, y, z, w]`
/// (sensor → ENU): the east and north parts of `R·(0, 1, −1)ᵀ`. Its length (≥ 1 when the
/// phone is held between flat and upright) weighs it in a step's mean direction.
#[must_use]
pub fn forward_from_quaternion(q: [f64; 4]) -> [f64; 2] {
    let [x, y, z, w] = q;
    // Columns 2 and 3 of the rotation matrix of a unit quaternion, east and north rows.
    let y_axis = [2.0 * (x * y - w * z), 1.0 - 2.0 * (x * x + z * z)];
    let z_axis = [2.0 * (x * z + w * y), 2.0 * (y * z - w * x)];
    [y_axis[0] - z_axis[0], y_axis[1] - z_axis[1]]
}

/// The tilt-compensated magnetometer's forward vector `(f_E, f_N)`: `up` is the (low-passed)
/// specific force and `mag` the field, both in the sensor frame. None when the two are
/// parallel or zero.
#[must_use]
pub fn forward_from_magnetometer(up: [f64; 3], mag: [f64; 3]) -> Option<[f64; 2]> {
    let u = normalise(up)?;
    let east = normalise(cross(mag, u))?;
    let north = cross(u, east);
    Some([east[1] - east[2], north[1] - north[2]])
}

/// Heading of a forward vector, radians CCW from east, turned by the declination.
#[must_use]
pub fn heading_of(forward: [f64; 2], declination: f64) -> f64 {
    wrap_turn(forward[1].atan2(forward[0]) - declination)
}

/// Gyroscope (+ magnetometer) heading: the complementary filter above, one sample at a time
/// (no allocation).
#[derive(Debug, Clone)]
pub struct HeadingFilter {
    config: HeadingFusionConfig,
    /// Low-passed specific force, sensor frame, m/s².
    up: [f64; 3],
    /// Heading ψ, radians CCW from east (or from the start for the gyroscope alone).
    psi: f64,
    started: bool,
    /// Magnetometer readings used and skipped.
    used: usize,
    skipped: usize,
}

impl HeadingFilter {
    /// A filter; `config` must be valid. Without a magnetometer the heading starts at 0.
    #[must_use]
    pub fn new(config: &HeadingFusionConfig) -> Self {
        Self {
            config: config.clone(),
            up: [0.0; 3],
            psi: 0.0,
            started: false,
            used: 0,
            skipped: 0,
        }
    }

    /// The current heading ψ, radians.
    #[must_use]
    pub fn heading(&self) -> f64 {
        self.psi
    }

    /// Magnetometer readings used in corrections and readings skipped for their strength.
    #[must_use]
    pub fn magnetometer_use(&self) -> (usize, usize) {
        (self.used, self.skipped)
    }

    fn magnetometer_heading(&mut self, mag: [f64; 3]) -> Option<f64> {
        let strength = dot(mag, mag).sqrt();
        let [lo, hi] = self.config.magnetic_field_range;
        if !(lo..=hi).contains(&strength) {
            self.skipped += 1;
            return None;
        }
        self.used += 1;
        forward_from_magnetometer(self.up, mag).map(|f| heading_of(f, self.config.declination))
    }

    /// Restarts at a sample (the first, or the first after a gap): gravity from this
    /// sample; the heading from the magnetometer when it gives one, else kept.
    pub fn restart(&mut self, accel: [f64; 3], mag: Option<[f64; 3]>) {
        self.up = accel;
        if let Some(psi) = mag.and_then(|m| self.magnetometer_heading(m)) {
            self.psi = psi;
        }
        self.started = true;
    }

    /// Feeds one sample `dt` seconds after the previous; returns the heading.
    pub fn update(
        &mut self,
        dt: f64,
        accel: [f64; 3],
        gyro: [f64; 3],
        mag: Option<[f64; 3]>,
    ) -> f64 {
        if !self.started {
            self.restart(accel, mag);
            return self.psi;
        }
        let a = dt / (self.config.tilt_time_constant_s + dt);
        for (u, f) in self.up.iter_mut().zip(accel) {
            *u += a * (f - *u);
        }
        if let Some(u) = normalise(self.up) {
            self.psi += dot(gyro, u) * dt; // gyro propagation
        }
        if let Some(psi_mag) = mag.and_then(|m| self.magnetometer_heading(m)) {
            let k = dt / (self.config.magnetometer_time_constant_s + dt);
            self.psi += k * wrap_turn(psi_mag - self.psi); // magnetometer correction
        }
        self.psi = wrap_turn(self.psi);
        self.psi
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

    /// Quaternion `[x, y, z, w]` of a rotation by `angle` about the unit `axis`.
    fn about(axis: [f64; 3], angle: f64) -> [f64; 4] {
        let s = (angle / 2.0).sin();
        [axis[0] * s, axis[1] * s, axis[2] * s, (angle / 2.0).cos()]
    }

    /// `v` rotated by the inverse of `q` (world → sensor).
    fn to_sensor(q: [f64; 4], v: [f64; 3]) -> [f64; 3] {
        let [x, y, z, w] = q;
        let r = [
            [
                1.0 - 2.0 * (y * y + z * z),
                2.0 * (x * y - w * z),
                2.0 * (x * z + w * y),
            ],
            [
                2.0 * (x * y + w * z),
                1.0 - 2.0 * (x * x + z * z),
                2.0 * (y * z - w * x),
            ],
            [
                2.0 * (x * z - w * y),
                2.0 * (y * z + w * x),
                1.0 - 2.0 * (x * x + y * y),
            ],
        ];
        [0, 1, 2].map(|j| r[0][j] * v[0] + r[1][j] * v[1] + r[2][j] * v[2])
    }

    /// Quaternion product `a ⊗ b` (apply b, then a).
    fn mul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
        let [ax, ay, az, aw] = a;
        let [bx, by, bz, bw] = b;
        [
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz,
        ]
    }

    #[test]
    fn flat_phone_points_north_and_a_quarter_turn_about_up_adds_90_degrees() {
        let flat = [0.0, 0.0, 0.0, 1.0];
        assert!((heading_of(forward_from_quaternion(flat), 0.0) - FRAC_PI_2).abs() < 1e-12);
        let turned = about([0.0, 0.0, 1.0], FRAC_PI_2);
        assert!((heading_of(forward_from_quaternion(turned), 0.0) - PI).abs() < 1e-12);
        // Upright (screen towards the walker: +y up, −z ahead), then turned 45° CCW: the
        // heading is north + 45°, and the forward vector stays of unit length.
        let upright = about([1.0, 0.0, 0.0], FRAC_PI_2);
        let q = mul(about([0.0, 0.0, 1.0], FRAC_PI_4), upright);
        let f = forward_from_quaternion(q);
        assert!((heading_of(f, 0.0) - 3.0 * FRAC_PI_4).abs() < 1e-12);
        assert!(((f[0] * f[0] + f[1] * f[1]).sqrt() - 1.0).abs() < 1e-12);
        // Declination 5° east: true heading 5° less counter-clockwise.
        let d = 5f64.to_radians();
        assert!((heading_of(forward_from_quaternion(flat), d) - (FRAC_PI_2 - d)).abs() < 1e-12);
    }

    #[test]
    fn magnetometer_heading_is_tilt_compensated() {
        // Field 20 µT north, 40 µT down; gravity's reaction 9.81 m/s² up.
        let (field, up) = ([0.0, 20.0, -40.0], [0.0, 0.0, 9.81]);
        // Facing north-west (heading 135°), pitched 30° and rolled 20°: the same heading.
        let yaw = about([0.0, 0.0, 1.0], FRAC_PI_4);
        let tilt = mul(
            about([1.0, 0.0, 0.0], 30f64.to_radians()),
            about([0.0, 1.0, 0.0], 20f64.to_radians()),
        );
        for q in [yaw, mul(yaw, tilt)] {
            let f = forward_from_magnetometer(to_sensor(q, up), to_sensor(q, field))
                .expect("not parallel");
            let h = heading_of(f, 0.0);
            // Tilt moves the forward axis itself only by the pitch/roll's horizontal part:
            // compare with the rotation vector's heading of the same orientation.
            let expected = heading_of(forward_from_quaternion(q), 0.0);
            assert!((h - expected).abs() < 1e-9, "{h} vs {expected}");
        }
        let f = forward_from_magnetometer(to_sensor(yaw, up), to_sensor(yaw, field))
            .expect("not parallel");
        assert!((heading_of(f, 0.0) - 3.0 * FRAC_PI_4).abs() < 1e-12);
        assert!(forward_from_magnetometer([0.0, 0.0, 1.0], [0.0, 0.0, 5.0]).is_none());
    }

    #[test]
    fn gyro_turn_about_gravity_integrates_and_the_magnetometer_pulls_back() {
        let mut f = HeadingFilter::new(&HeadingFusionConfig::default());
        // Phone flat: up = +z. 1 s at 0.5 rad/s about z at 100 Hz, no magnetometer.
        f.restart([0.0, 0.0, 9.81], None);
        for _ in 0..100 {
            f.update(0.01, [0.0, 0.0, 9.81], [0.0, 0.0, 0.5], None);
        }
        assert!((f.heading() - 0.5).abs() < 1e-9, "{}", f.heading());
        // A magnetometer saying north (π/2), held 5 time constants: within e⁻⁵ of it.
        for _ in 0..2500 {
            f.update(0.01, [0.0, 0.0, 9.81], [0.0; 3], Some([0.0, 20.0, -40.0]));
        }
        let left = (FRAC_PI_2 - f.heading()).abs();
        assert!(left < (FRAC_PI_2 - 0.5) * 0.01, "{left}");
        // A 200 µT reading (a steel door) is skipped.
        let before = f.heading();
        f.update(0.01, [0.0, 0.0, 9.81], [0.0; 3], Some([200.0, 0.0, 0.0]));
        assert_eq!(f.heading(), before);
        assert_eq!(f.magnetometer_use().1, 1);
    }
}
