//! The true path of a walk, one pose per step: the simulator's truth, or a reference
//! system's (read and written by [`crate::io::truth_csv`]).

use crate::geometry::Pose2;
use serde::{Deserialize, Serialize};

/// Where the walker truly is just after a step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TruePose {
    /// Time of the step, seconds.
    pub t: f64,
    /// East, metres.
    pub x: f64,
    /// North, metres.
    pub y: f64,
    /// Height, metres.
    pub z: f64,
    /// Floor level.
    pub level: i32,
    /// Direction of motion over the step, radians counter-clockwise from east, in `[-π, π)`.
    pub heading: f64,
}

/// True poses, one per step, in time order.
///
/// Pose `k` is where step `k` ends. The walk starts before the first step at the origin of
/// the local frame facing east (heading 0), the step-trace convention (see
/// [`crate::geometry::Pose2::step`]), so dead-reckoning a noise-free trace from
/// `Pose2::default()` reproduces these poses.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct TruePath {
    /// The poses.
    pub poses: Vec<TruePose>,
}

impl TruePath {
    /// The walker at time `t`: the position linear between the poses around it (standing at
    /// `start` until the first step, at the last pose after it), with the next pose's level,
    /// height and heading.
    #[must_use]
    pub fn pose_at(&self, start: &TruePose, t: f64) -> TruePose {
        let i = self.poses.partition_point(|p| p.t < t);
        let before = if i == 0 { start } else { &self.poses[i - 1] };
        let Some(after) = self.poses.get(i) else {
            return TruePose { t, ..*before };
        };
        let (x, y) = if after.t > before.t {
            let u = ((t - before.t) / (after.t - before.t)).clamp(0.0, 1.0);
            (
                before.x + u * (after.x - before.x),
                before.y + u * (after.y - before.y),
            )
        } else {
            (after.x, after.y)
        };
        TruePose { t, x, y, ..*after }
    }

    /// Number of poses (steps).
    #[must_use]
    pub fn len(&self) -> usize {
        self.poses.len()
    }

    /// True when there are no poses.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.poses.is_empty()
    }

    /// The poses as 2D poses.
    #[must_use]
    pub fn to_pose2s(&self) -> Vec<Pose2> {
        self.poses
            .iter()
            .map(|p| Pose2::new(p.x, p.y, p.heading))
            .collect()
    }

    /// Length of the path from the origin through every pose, metres.
    #[must_use]
    pub fn length(&self) -> f64 {
        let mut previous = (0.0, 0.0);
        self.poses
            .iter()
            .map(|p| {
                let d = (p.x - previous.0).hypot(p.y - previous.1);
                previous = (p.x, p.y);
                d
            })
            .sum()
    }
}
