//! A 2D pose in the local frame (x east, y north, metres; heading counter-clockwise from east).

use serde::{Deserialize, Serialize};

/// Position and heading of the walker in the local frame.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Pose2 {
    /// East, metres.
    pub x: f64,
    /// North, metres.
    pub y: f64,
    /// Heading, radians counter-clockwise from east.
    pub heading: f64,
}

impl Pose2 {
    /// A pose from its parts.
    #[must_use]
    pub const fn new(x: f64, y: f64, heading: f64) -> Self {
        Self { x, y, heading }
    }

    /// Applies one step (Woodman & Harle 2008, eq. 9–11): turn by `dheading`, then walk
    /// `length` along the new heading.
    #[must_use]
    pub fn step(self, length: f64, dheading: f64) -> Self {
        let heading = self.heading + dheading; // eq. (9)
        Self {
            x: self.x + length * heading.cos(), // eq. (10)
            y: self.y + length * heading.sin(), // eq. (11)
            heading,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn step_turns_then_walks() {
        let p = Pose2::default().step(1.0, FRAC_PI_2);
        assert!(p.x.abs() < 1e-12 && (p.y - 1.0).abs() < 1e-12);
        let q = p.step(2.0, -FRAC_PI_2);
        assert!((q.x - 2.0).abs() < 1e-12 && (q.y - 1.0).abs() < 1e-12);
    }
}
