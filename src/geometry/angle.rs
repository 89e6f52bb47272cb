//! Angle helpers (radians throughout).

use std::f64::consts::{PI, TAU};

/// Wraps an angle into `[-π, π)`.
pub fn wrap_angle(a: f64) -> f64 {
    let w = (a + PI).rem_euclid(TAU) - PI;
    if w >= PI { w - TAU } else { w }
}

/// Wraps an angle into `(−π, π]`: a turn of exactly half a circle counts as
/// counter-clockwise (heading changes between steps).
pub fn wrap_turn(a: f64) -> f64 {
    -wrap_angle(-a)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wraps_turns_into_minus_pi_exclusive_to_pi_inclusive() {
        assert!((wrap_turn(PI) - PI).abs() < 1e-12);
        assert!((wrap_turn(-PI) - PI).abs() < 1e-12);
        assert!((wrap_turn(1.5 * PI) + 0.5 * PI).abs() < 1e-12);
    }

    #[test]
    fn wraps_into_half_open_interval() {
        assert!((wrap_angle(3.0 * PI) + PI).abs() < 1e-12);
        assert!((wrap_angle(-PI) + PI).abs() < 1e-12);
        assert!((wrap_angle(0.5) - 0.5).abs() < 1e-12);
        assert!((wrap_angle(TAU + 0.25) - 0.25).abs() < 1e-12);
        assert!((wrap_angle(-TAU - 0.25) + 0.25).abs() < 1e-12);
    }
}
