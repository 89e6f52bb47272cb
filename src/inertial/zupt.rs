//! The 9-state error-state Kalman filter of a zero-velocity-aided INS (Foxlin 2005,
//! "Pedestrian tracking with shoe-mounted inertial sensors"; Harle 2013 §IV-B).
//!
//! The filter estimates the errors of the nominal [`NavState`],
//! `δx = [δp, δv, δθ]` (position, velocity, attitude as a small rotation in the navigation
//! frame: `C = (I + [δθ]×) Ĉ`). Between updates the errors evolve as (Foxlin eq. 4)
//!
//! ```text
//! δṗ = δv,   δv̇ = −[f^n]× δθ + C w_a,   δθ̇ = −C w_ω
//! ```
//!
//! discretised over each sample's `dt` as `F = I + A dt` and `Q = diag(0, q_a dt I, q_ω dt I)`
//! with `q_a`, `q_ω` the squared noise densities. While the foot is in stance the true
//! velocity is zero: the pseudo-measurement `z = 0 − v̂` with `H = [0 I 0]` and
//! `R = σ_z² I` (the ZUPT) corrects all nine errors through their correlations, which is what
//! bounds the drift of a foot-mounted INS to a fraction of a percent of the distance. The
//! estimated errors are injected into the nominal state and reset to zero after each update.

use super::strapdown::NavState;
use nalgebra::{Matrix3, SMatrix, UnitQuaternion, Vector3};

type Matrix9 = SMatrix<f64, 9, 9>;
type Matrix9x3 = SMatrix<f64, 9, 3>;
type Vector9 = SMatrix<f64, 9, 1>;

/// The error covariance and the noise model.
#[derive(Debug, Clone, PartialEq)]
pub struct ZuptFilter {
    /// Error covariance `P` of `[δp, δv, δθ]`.
    pub covariance: Matrix9,
    /// Accelerometer noise density squared `q_a`, (m/s²)²/Hz.
    accel_psd: f64,
    /// Gyroscope noise density squared `q_ω`, (rad/s)²/Hz.
    gyro_psd: f64,
    /// Zero-velocity measurement variance `σ_z²`, (m/s)².
    zero_velocity_variance: f64,
}

impl ZuptFilter {
    /// A filter with the given noise densities (m/s²/√Hz, rad/s/√Hz), zero-velocity
    /// measurement noise (m/s) and initial attitude uncertainty (radians, 1σ, each axis).
    #[must_use]
    pub fn new(
        accel_noise_density: f64,
        gyro_noise_density: f64,
        zero_velocity_sigma: f64,
        initial_tilt_sigma: f64,
    ) -> Self {
        let mut filter = Self {
            covariance: Matrix9::zeros(),
            accel_psd: accel_noise_density.powi(2),
            gyro_psd: gyro_noise_density.powi(2),
            zero_velocity_variance: zero_velocity_sigma.powi(2),
        };
        filter.restart(initial_tilt_sigma);
        filter
    }

    /// Forgets all correlations: position and velocity known (the walker stands at the
    /// origin of a new stride), roll and pitch within `tilt_sigma`, yaw exact (it is defined
    /// by the start).
    pub fn restart(&mut self, tilt_sigma: f64) {
        self.covariance = Matrix9::zeros();
        let t2 = tilt_sigma * tilt_sigma;
        self.covariance[(6, 6)] = t2;
        self.covariance[(7, 7)] = t2;
    }

    /// Propagates `P` over `dt` seconds given the specific force in the navigation frame
    /// `f^n`: `P ← F P Fᵀ + Q`.
    pub fn predict(&mut self, f_n: &Vector3<f64>, dt: f64) {
        let mut f = Matrix9::identity();
        f.fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&(Matrix3::identity() * dt));
        f.fixed_view_mut::<3, 3>(3, 6)
            .copy_from(&(-f_n.cross_matrix() * dt));
        let mut p = f * self.covariance * f.transpose();
        for i in 3..6 {
            p[(i, i)] += self.accel_psd * dt;
        }
        for i in 6..9 {
            p[(i, i)] += self.gyro_psd * dt;
        }
        self.covariance = p;
    }

    /// The zero-velocity update: corrects `state` and `P`; returns the residual's norm
    /// `‖v̂‖` before the update, m/s.
    pub fn update_zero_velocity(&mut self, state: &mut NavState) -> f64 {
        let residual = -state.velocity; // z − H x̂ with z = 0
        let p = &self.covariance;
        let p_h: Matrix9x3 = p.fixed_view::<9, 3>(0, 3).into_owned(); // P Hᵀ
        let mut s: Matrix3<f64> = p.fixed_view::<3, 3>(3, 3).into_owned(); // H P Hᵀ + R
        for i in 0..3 {
            s[(i, i)] += self.zero_velocity_variance;
        }
        let Some(s_inv) = s.try_inverse() else {
            return residual.norm();
        };
        let k: Matrix9x3 = p_h * s_inv;
        let dx: Vector9 = k * residual;
        // P ← P − K S Kᵀ, kept symmetric.
        let mut updated = self.covariance - k * s * k.transpose();
        updated = 0.5 * (updated + updated.transpose());
        self.covariance = updated;
        inject(state, &dx);
        residual.norm()
    }
}

/// Adds the estimated errors to the nominal state (the covariance's reset Jacobian is taken
/// as the identity, as usual for small corrections).
fn inject(state: &mut NavState, dx: &Vector9) {
    state.position += dx.fixed_rows::<3>(0);
    state.velocity += dx.fixed_rows::<3>(3);
    let dtheta: Vector3<f64> = dx.fixed_rows::<3>(6).into_owned();
    state.attitude = UnitQuaternion::from_scaled_axis(dtheta) * state.attitude;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zupt_zeroes_the_velocity_and_shrinks_its_variance() {
        let mut f = ZuptFilter::new(0.05, 0.005, 0.01, 0.01);
        let mut s = NavState::at_rest(Vector3::zeros(), UnitQuaternion::identity(), 9.81);
        // One second of free propagation at rest: the velocity variance grows by q_a·1 s.
        for _ in 0..100 {
            f.predict(&Vector3::new(0.0, 0.0, 9.81), 0.01);
        }
        let before = f.covariance[(3, 3)];
        assert!(before > 0.05 * 0.05 * 0.99, "{before}");
        s.velocity = Vector3::new(0.2, 0.0, 0.0);
        let r = f.update_zero_velocity(&mut s);
        assert!((r - 0.2).abs() < 1e-12);
        // Scalar Kalman gain on v_x: K = P/(P + σ²): v = 0.2 σ²/(P + σ²).
        let expect = 0.2 * 1e-4 / (before + 1e-4);
        assert!(
            (s.velocity.x - expect).abs() < 1e-9,
            "{} vs {expect}",
            s.velocity.x
        );
        assert!(f.covariance[(3, 3)] < before);
    }
}
