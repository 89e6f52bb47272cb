//! How the walker tours the office ([`WalkConfig`]): the tour's laps and room visits (planned
//! by [`super::tour`]) and the gait it is walked with (by [`super::walker`]).

use super::stride::Gait;
use crate::error::Result;
use serde::{Deserialize, Serialize};

/// How the walker tours the office; every default in one place.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WalkConfig {
    /// Laps of the corridor loop. Default 3.
    pub laps: usize,
    /// Fewest rooms visited per lap. Default 2.
    pub min_rooms_per_lap: usize,
    /// Most rooms visited per lap (different rooms within a lap). Default 4.
    pub max_rooms_per_lap: usize,
    /// Chance that a room chosen after the first lap is one visited before. Default 0.5.
    pub revisit_probability: f64,
    /// Most points walked to inside a room (at least one). Default 2.
    pub max_points_per_room: usize,
    /// Distance of those points from the room's walls, metres. Default 0.6 m.
    pub room_margin: f64,
    /// Step rate, hertz. Default 1.8 Hz (with 0.7 m strides, 1.26 m/s).
    pub step_frequency: f64,
    /// Relative jitter (1σ) of each step's period. Default 0.05.
    pub step_period_jitter: f64,
    /// Mean stride length, metres. Default 0.7 m.
    pub step_length_mean: f64,
    /// Stride-length spread (1σ), metres; strides are kept within ±50 % of the mean.
    /// Default 0.05 m.
    pub step_length_sigma: f64,
    /// Radius of rounded corners, metres, capped by the office (half the corridor width, the
    /// entry depth). Default 0.6 m.
    pub corner_radius: f64,
    /// Stationary spread (1σ) of the sideways wander about the route, metres. Default 0.03 m.
    pub wander_sigma: f64,
}

impl Default for WalkConfig {
    fn default() -> Self {
        Self {
            laps: 3,
            min_rooms_per_lap: 2,
            max_rooms_per_lap: 4,
            revisit_probability: 0.5,
            max_points_per_room: 2,
            room_margin: 0.6,
            step_frequency: 1.8,
            step_period_jitter: 0.05,
            step_length_mean: 0.7,
            step_length_sigma: 0.05,
            corner_radius: 0.6,
            wander_sigma: 0.03,
        }
    }
}

impl WalkConfig {
    /// The stride parameters.
    pub(super) fn gait(&self) -> Gait {
        Gait {
            frequency: self.step_frequency,
            period_jitter: self.step_period_jitter,
            length_mean: self.step_length_mean,
            length_sigma: self.step_length_sigma,
            wander_sigma: self.wander_sigma,
        }
    }

    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) naming the first field out of its range: `laps`
    /// outside [1, 1000], `max_rooms_per_lap` below `min_rooms_per_lap`, `revisit_probability`
    /// outside [0, 1], …, or a gait field (e.g. `step_length_mean` outside [0.2, 2] m).
    pub fn validate(&self) -> Result<()> {
        crate::error::check_range("walk.laps", self.laps as f64, 1.0..=1000.0, "")?;
        crate::error::check_range(
            "walk.min_rooms_per_lap",
            self.min_rooms_per_lap as f64,
            0.0..=1000.0,
            "",
        )?;
        crate::error::check_range(
            "walk.max_rooms_per_lap",
            self.max_rooms_per_lap as f64,
            0.0..=1000.0,
            "",
        )?;
        if self.max_rooms_per_lap < self.min_rooms_per_lap {
            return Err(crate::error::Error::config(
                "walk.max_rooms_per_lap",
                self.max_rooms_per_lap.to_string(),
                "must be at least min_rooms_per_lap",
            ));
        }
        crate::error::check_range(
            "walk.max_points_per_room",
            self.max_points_per_room as f64,
            1.0..=100.0,
            "",
        )?;
        crate::error::check_range(
            "walk.revisit_probability",
            self.revisit_probability,
            0.0..=1.0,
            "",
        )?;
        crate::error::check_range("walk.room_margin", self.room_margin, 0.0..=100.0, "m")?;
        crate::error::check_range("walk.corner_radius", self.corner_radius, 0.0..=100.0, "m")?;
        self.gait().validate()
    }
}
