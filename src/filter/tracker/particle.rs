//! One hypothesis of the walker's state, and the angle and scale bounds it keeps.

use std::f32::consts::PI;

/// Bounds of the per-walk step length scale.
pub(super) const SCALE_RANGE: (f32, f32) = (0.7, 1.3);

/// One hypothesis of the walker's state: where it is, where it heads, on which surface, and
/// its step length scale and heading-drift rate. 24 bytes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[repr(C)]
pub struct TrackParticle {
    /// East, metres.
    pub x: f32,
    /// North, metres.
    pub y: f32,
    /// Heading of the last step, radians in [−π, π).
    pub heading: f32,
    /// Per-walk step length scale.
    pub scale: f32,
    /// Heading drift per step, radians (added to every measured heading change).
    pub drift: f32,
    /// Index of the floor surface the particle stands on.
    pub surface: u32,
}

impl TrackParticle {
    /// The particle with its step length scale clamped to [`SCALE_RANGE`].
    pub(super) fn clamp_scale(mut self) -> Self {
        self.scale = self.scale.clamp(SCALE_RANGE.0, SCALE_RANGE.1);
        self
    }
}

/// Wraps an angle to [−π, π) (up to rounding at the ends).
#[inline]
pub(super) fn wrap(a: f32) -> f32 {
    if (-PI..PI).contains(&a) {
        a
    } else {
        (a + PI).rem_euclid(2.0 * PI) - PI
    }
}
