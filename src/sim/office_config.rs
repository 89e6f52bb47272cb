//! The office's dimensions ([`OfficeConfig`]): every default in one place, validated, shared
//! by the floor plan ([`super::office`]) and the rooms along its loop ([`super::rooms`]).

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// Dimensions of the office; every default in one place (metres).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OfficeConfig {
    /// Outer east–west extent of the corridor loop. Default 30 m.
    pub loop_width: f64,
    /// Outer north–south extent of the corridor loop. Default 18 m.
    pub loop_height: f64,
    /// Corridor width. Default 1.8 m.
    pub corridor_width: f64,
    /// Wall thickness between surfaces (the depth of each door). Default 0.2 m.
    pub wall_thickness: f64,
    /// Door width. Default 0.9 m.
    pub door_width: f64,
    /// Room extent along the corridor. Default 4 m.
    pub room_width: f64,
    /// Room extent away from the corridor. Default 4 m.
    pub room_depth: f64,
    /// Rooms along each long (south, north) side, both inside and outside the loop. Default 3.
    pub rooms_per_long_side: usize,
    /// Rooms along each short (east, west) side, both inside and outside the loop. Default 1.
    pub rooms_per_short_side: usize,
    /// Distance from a room's wall to its entry anchor, straight in from the door. Default 0.8 m.
    pub entry_depth: f64,
}

impl Default for OfficeConfig {
    fn default() -> Self {
        Self {
            loop_width: 30.0,
            loop_height: 18.0,
            corridor_width: 1.8,
            wall_thickness: 0.2,
            door_width: 0.9,
            room_width: 4.0,
            room_depth: 4.0,
            rooms_per_long_side: 3,
            rooms_per_short_side: 1,
            entry_depth: 0.8,
        }
    }
}

impl OfficeConfig {
    /// Checks the dimensions: all positive and finite, doors narrower than rooms and
    /// corridors, and the inner rooms fitting inside the loop.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] naming the first dimension out of its range (e.g. `corridor_width` outside
    /// [0.5, 20] m), a door at least as wide as a room, an `entry_depth` over half the
    /// `room_depth`, or a loop too small for the rooms inside it.
    pub fn validate(&self) -> Result<()> {
        crate::error::check_range("office.loop_width", self.loop_width, 1.0..=1000.0, "m")?;
        crate::error::check_range("office.loop_height", self.loop_height, 1.0..=1000.0, "m")?;
        crate::error::check_range(
            "office.corridor_width",
            self.corridor_width,
            0.5..=20.0,
            "m",
        )?;
        crate::error::check_range(
            "office.wall_thickness",
            self.wall_thickness,
            0.01..=2.0,
            "m",
        )?;
        crate::error::check_range("office.door_width", self.door_width, 0.5..=10.0, "m")?;
        crate::error::check_range("office.room_width", self.room_width, 1.0..=100.0, "m")?;
        crate::error::check_range("office.room_depth", self.room_depth, 1.0..=100.0, "m")?;
        crate::error::check_range("office.entry_depth", self.entry_depth, 0.1..=50.0, "m")?;
        if self.door_width >= self.room_width {
            let reason = "must be less than room_width";
            return Err(config_error("office.door_width", self.door_width, reason));
        }
        if self.entry_depth > self.room_depth / 2.0 {
            let reason = "must be at most room_depth / 2";
            return Err(config_error("office.entry_depth", self.entry_depth, reason));
        }
        let (c, t, d) = (self.corridor_width, self.wall_thickness, self.room_depth);
        let needed = 2.0 * (t + d) + t + 2.0 * c;
        let reason = "too small for rooms inside the loop";
        if self.loop_width < needed {
            return Err(config_error("office.loop_width", self.loop_width, reason));
        }
        if self.loop_height < needed {
            return Err(config_error("office.loop_height", self.loop_height, reason));
        }
        Ok(())
    }

    /// East–west and north–south extents `(a, b)` of the corridor's centre line, metres.
    #[must_use]
    pub fn centre_line_size(&self) -> (f64, f64) {
        let c = self.corridor_width;
        (self.loop_width - c, self.loop_height - c)
    }
}

/// A configuration error of `field`, whose `value` fails for `reason`.
pub(super) fn config_error(field: &'static str, value: f64, reason: &'static str) -> Error {
    crate::error::Error::config(field, value.to_string(), reason)
}
