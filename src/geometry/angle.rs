//! Angle helpers (radians throughout).

use std::f64::consts::{PI, TAU};

/// Wraps an angle into `[-π, π)`.
///
/// `(a + π) mod 2π − π`, with the remainder taken without a division for
/// `a + π ∈ (−2π, 4π)` (every difference of two wrapped angles): there `rem_euclid` is exact
/// and amounts to adding or subtracting 2π at most once (the subtraction is exact by
/// Sterbenz's lemma), so both paths give the same bits.
#[inline]
#[must_use]
pub fn wrap_angle(a: f64) -> f64 {
    let x = a + PI;
    let r = if (0.0..TAU).contains(&x) {
        x
    } else if x < 0.0 && x > -TAU {
        x + TAU
    } else if (TAU..2.0 * TAU).contains(&x) {
        x - TAU
    } else {
        x.rem_euclid(TAU)
    };
    let w = r - PI;
    if w >= PI { w - TAU } else { w }
}

/// Wraps an angle into `(−π, π]`: a turn of exactly half a circle counts as
/// counter-clockwise (heading changes between steps).
#[must_use]
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
    fn the_fast_remainder_gives_the_bits_of_rem_euclid() {
        let reference = |a: f64| {
            let w = (a + PI).rem_euclid(TAU) - PI;
            if w >= PI { w - TAU } else { w }
        };
        let mut edges = vec![0.0, -0.0, PI, -PI, TAU, -TAU, 3.0 * PI, -3.0 * PI, 5.0 * PI];
        for e in edges.clone() {
            edges.extend([e.next_up(), e.next_down(), e - PI, e + PI]);
            edges.extend([(e - PI).next_up(), (e - PI).next_down()]);
        }
        // A low-discrepancy sweep of (−4τ, 4τ).
        let sweep = (0..100_000).map(|i| (f64::from(i) * 0.618_033_988_749_895).fract());
        let spread = sweep.map(|u| (u - 0.5) * 8.0 * TAU);
        for a in edges.into_iter().chain(spread) {
            assert_eq!(wrap_angle(a).to_bits(), reference(a).to_bits(), "{a:e}");
        }
        assert!(wrap_angle(f64::NAN).is_nan());
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
