//! Strapdown mechanisation in a local z-up navigation frame (Woodman & Harle 2008 §3.1;
//! Titterton & Weston ch. 3): integrate the gyroscope into attitude, rotate the specific force
//! into the navigation frame, remove gravity, integrate twice.
//!
//! Frame and symbols: `n` is the navigation frame (x along the foot's initial heading, y to its
//! left, z up); `b` the sensor frame; `q` the attitude quaternion with `C = C_b^n` rotating
//! sensor vectors into `n`; `f` the specific force (what an accelerometer reads: at rest, `+g`
//! upwards); `ω` the angular rate; `g^n = [0, 0, −g]`.

use nalgebra::{UnitQuaternion, Vector3};

/// The INS's nominal state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NavState {
    /// Position `p^n`, metres.
    pub position: Vector3<f64>,
    /// Velocity `v^n`, m/s.
    pub velocity: Vector3<f64>,
    /// Attitude `q` (sensor → navigation).
    pub attitude: UnitQuaternion<f64>,
    /// Gravity magnitude `g`, m/s².
    pub gravity: f64,
}

impl NavState {
    /// At rest at `position` with the given attitude.
    #[must_use]
    pub fn at_rest(position: Vector3<f64>, attitude: UnitQuaternion<f64>, gravity: f64) -> Self {
        Self {
            position,
            velocity: Vector3::zeros(),
            attitude,
            gravity,
        }
    }

    /// One mechanisation step over `dt` seconds with the mean specific force `f` (m/s²) and
    /// mean rate `ω` (rad/s) of the interval; returns the specific force in the navigation
    /// frame `f^n`, which the error-state filter's transition matrix needs.
    pub fn propagate(&mut self, f: &Vector3<f64>, omega: &Vector3<f64>, dt: f64) -> Vector3<f64> {
        let before = self.attitude;
        // q_{k+1} = q_k ⊗ exp(ω dt / 2): the body turned by ω dt over the interval.
        self.attitude = before * UnitQuaternion::from_scaled_axis(omega * dt);
        // f^n over the interval: the mean of the specific force rotated by both attitudes.
        let f_n = 0.5 * (before * f + self.attitude * f);
        // v̇^n = C f + g^n; ṗ^n = v^n (trapezoidal).
        let a_n = f_n - Vector3::new(0.0, 0.0, self.gravity);
        let v0 = self.velocity;
        self.velocity += a_n * dt;
        self.position += 0.5 * (v0 + self.velocity) * dt;
        f_n
    }
}

/// The attitude of a sensor at rest whose mean specific force is `f` (any orientation): the
/// shortest rotation taking `f` to `+z` (roll and pitch from gravity), then a turn about `z`
/// that puts `heading_axis` (a sensor axis, see [`heading_axis`]) at yaw `yaw`.
#[must_use]
pub fn level(f: &Vector3<f64>, heading_axis: &Vector3<f64>, yaw: f64) -> UnitQuaternion<f64> {
    let up = Vector3::z();
    let tilt = UnitQuaternion::rotation_between(f, &up)
        // f points exactly down: any half turn about a horizontal axis will do.
        .unwrap_or_else(|| {
            UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
        });
    let now = heading_of(&tilt, heading_axis);
    UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw - now) * tilt
}

/// The sensor axis whose yaw is the foot's heading: of `x`, `y`, `z` the one most nearly
/// horizontal while the sensor reads `f` at rest, projected onto the horizontal plane (so any
/// mounting works, not only one with `x` along the foot).
pub fn heading_axis(f: &Vector3<f64>) -> Vector3<f64> {
    let up = f.try_normalize(1e-9).unwrap_or_else(Vector3::z);
    let axes = [Vector3::x(), Vector3::y(), Vector3::z()];
    let mut best = axes[0];
    for a in axes {
        if a.dot(&up).abs() < best.dot(&up).abs() {
            best = a;
        }
    }
    (best - best.dot(&up) * up)
        .try_normalize(1e-9)
        .unwrap_or(best)
}

/// Yaw of the sensor axis `axis` under attitude `q`, radians CCW from the navigation `x`.
#[must_use]
pub fn heading_of(q: &UnitQuaternion<f64>, axis: &Vector3<f64>) -> f64 {
    let h = q * axis;
    h.y.atan2(h.x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn levels_any_orientation_and_sets_yaw() {
        // Sensor upside down (z down, as on the shared data's shoes), tilted 10° about x.
        let f = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.17)
            * Vector3::new(0.0, 0.0, -9.81);
        let axis = heading_axis(&f);
        let q = level(&f, &axis, 0.3);
        let up = q * f;
        assert!((up - Vector3::new(0.0, 0.0, 9.81)).norm() < 1e-9, "{up}");
        assert!((heading_of(&q, &axis) - 0.3).abs() < 1e-9);
        // x is horizontal here, so it is the heading axis.
        assert!((axis - Vector3::x()).norm() < 1e-9, "{axis}");
    }

    #[test]
    fn constant_rate_rotation_integrates_exactly() {
        // 90°/s about the vertical for 1 s at 200 Hz turns the heading by exactly π/2, and a
        // sensor at rest (f = +g up) stays at rest whatever its rotation about z.
        let mut s = NavState::at_rest(Vector3::zeros(), UnitQuaternion::identity(), 9.81);
        let (f, w) = (
            Vector3::new(0.0, 0.0, 9.81),
            Vector3::new(0.0, 0.0, FRAC_PI_2),
        );
        for _ in 0..200 {
            s.propagate(&f, &w, 0.005);
        }
        assert!((heading_of(&s.attitude, &Vector3::x()) - FRAC_PI_2).abs() < 1e-12);
        assert!(s.velocity.norm() < 1e-12 && s.position.norm() < 1e-12);
    }

    #[test]
    fn constant_acceleration_integrates_to_half_a_t_squared() {
        // 1 m/s² along x for 2 s: v = 2 m/s, p = ½·1·2² = 2 m (trapezoidal is exact here).
        let mut s = NavState::at_rest(Vector3::zeros(), UnitQuaternion::identity(), 9.81);
        let f = Vector3::new(1.0, 0.0, 9.81);
        for _ in 0..400 {
            s.propagate(&f, &Vector3::zeros(), 0.005);
        }
        assert!((s.velocity.x - 2.0).abs() < 1e-9 && (s.position.x - 2.0).abs() < 1e-9);
    }
}
