//! The tower's dimensions ([`TowerConfig`]): every default in one place, validated, with the
//! stairwell measures derived from them (see [`super::tower`] for the frame).

use crate::error::Result;
use serde::{Deserialize, Serialize};

/// Dimensions of the building; every default in one place (metres).
///
/// | field              | default | meaning                                               |
/// |--------------------|---------|-------------------------------------------------------|
/// | `floors`           | 3       | floors (levels 0 ..)                                  |
/// | `floor_height`     | 3.0     | height between floors                                 |
/// | `corridor_length`  | 40      | corridor along x                                      |
/// | `corridor_width`   | 2.0     | corridor across                                       |
/// | `room_depth`       | 6.0     | rooms across                                          |
/// | `min_room_width`   | 3.0     | narrowest room                                        |
/// | `max_room_width`   | 7.0     | widest room                                           |
/// | `wall_thickness`   | 0.2     | gap between surfaces that do not connect              |
/// | `door_width`       | 0.9     | door rectangles                                       |
/// | `treads`           | 8       | treads per flight (two flights per floor)             |
/// | `tread_depth`      | 0.28    | tread along the flight                                |
/// | `lane_width`       | 1.2     | width of a flight                                     |
/// | `landing_depth`    | 2.5     | floor landing between corridor and flights            |
/// | `identical_floors` | false   | every floor with the same layout                      |
/// | `layout_seed`      | 1       | seed of the room layouts                              |
/// | `hall_width`       | 0       | an open hall on one side of each floor (0 = none)     |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TowerConfig {
    /// Number of floors.
    pub floors: usize,
    /// Height between floors.
    pub floor_height: f64,
    /// Corridor length (x).
    pub corridor_length: f64,
    /// Corridor width (y).
    pub corridor_width: f64,
    /// Room depth away from the corridor.
    pub room_depth: f64,
    /// Narrowest room along the corridor.
    pub min_room_width: f64,
    /// Widest room along the corridor.
    pub max_room_width: f64,
    /// Gap between surfaces that must not connect.
    pub wall_thickness: f64,
    /// Door width.
    pub door_width: f64,
    /// Treads per flight.
    pub treads: usize,
    /// Tread depth along a flight.
    pub tread_depth: f64,
    /// Width of a flight.
    pub lane_width: f64,
    /// Depth of each floor's stair landing (x).
    pub landing_depth: f64,
    /// Every floor with the same layout.
    pub identical_floors: bool,
    /// Seed of the room layouts.
    pub layout_seed: u64,
    /// Width of the open hall on one side of each floor, at a place drawn with the layout;
    /// 0 for none.
    pub hall_width: f64,
}

impl Default for TowerConfig {
    fn default() -> Self {
        Self {
            floors: 3,
            floor_height: 3.0,
            corridor_length: 40.0,
            corridor_width: 2.0,
            room_depth: 6.0,
            min_room_width: 3.0,
            max_room_width: 7.0,
            wall_thickness: 0.2,
            door_width: 0.9,
            treads: 8,
            tread_depth: 0.28,
            lane_width: 1.2,
            landing_depth: 2.5,
            identical_floors: false,
            layout_seed: 1,
            hall_width: 0.0,
        }
    }
}

impl TowerConfig {
    /// The number of floors as a count of levels (levels `0..level_count()`); `validate`
    /// bounds it to 50.
    #[must_use]
    pub fn level_count(&self) -> i32 {
        i32::try_from(self.floors).unwrap_or(i32::MAX)
    }

    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) naming the first field out of its range (e.g.
    /// `floors` outside [1, 50]), or a layout that cannot be built: `max_room_width` below
    /// `min_room_width`, a door without 0.2 m of wall each side, a corridor too short for two rooms
    /// a side, treads rising more than 0.45 m, or two stair lanes too wide for the building.
    pub fn validate(&self) -> Result<()> {
        crate::error::check_range("building.floors", self.floors as f64, 1.0..=50.0, "")?;
        crate::error::check_range("building.floor_height", self.floor_height, 2.0..=10.0, "m")?;
        crate::error::check_range(
            "building.corridor_length",
            self.corridor_length,
            10.0..=1000.0,
            "m",
        )?;
        crate::error::check_range(
            "building.corridor_width",
            self.corridor_width,
            1.0..=10.0,
            "m",
        )?;
        crate::error::check_range("building.room_depth", self.room_depth, 2.0..=50.0, "m")?;
        crate::error::check_range(
            "building.min_room_width",
            self.min_room_width,
            2.0..=50.0,
            "m",
        )?;
        crate::error::check_range(
            "building.max_room_width",
            self.max_room_width,
            2.0..=50.0,
            "m",
        )?;
        crate::error::check_range(
            "building.wall_thickness",
            self.wall_thickness,
            0.1..=1.0,
            "m",
        )?;
        crate::error::check_range("building.door_width", self.door_width, 0.6..=3.0, "m")?;
        crate::error::check_range("building.hall_width", self.hall_width, 0.0..=1000.0, "m")?;
        crate::error::check_range("building.treads", self.treads as f64, 2.0..=30.0, "")?;
        crate::error::check_range("building.tread_depth", self.tread_depth, 0.2..=0.5, "m")?;
        crate::error::check_range("building.lane_width", self.lane_width, 0.8..=3.0, "m")?;
        crate::error::check_range(
            "building.landing_depth",
            self.landing_depth,
            1.5..=10.0,
            "m",
        )?;
        if self.max_room_width < self.min_room_width {
            return Err(crate::error::Error::config(
                "building.max_room_width",
                self.max_room_width,
                "must be at least min_room_width",
            ));
        }
        if self.door_width + 0.4 > self.min_room_width {
            return Err(crate::error::Error::config(
                "building.door_width",
                self.door_width,
                "must leave 0.2 m of wall on each side in the narrowest room",
            ));
        }
        if self.corridor_length < 2.0 * self.min_room_width + 3.0 * self.wall_thickness {
            return Err(crate::error::Error::config(
                "building.corridor_length",
                self.corridor_length,
                "must hold at least two rooms a side",
            ));
        }
        if self.rise() > 0.45 {
            return Err(crate::error::Error::config(
                "building.treads",
                self.treads as f64,
                "too few for the floor height: a tread may rise at most 0.45 m",
            ));
        }
        if 2.0 * self.lane_width + self.wall_thickness > self.corridor_width + 2.0 * self.room_depth
        {
            return Err(crate::error::Error::config(
                "building.lane_width",
                self.lane_width,
                "two lanes must fit across the building",
            ));
        }
        Ok(())
    }

    /// Height of one tread above the previous.
    #[must_use]
    pub fn rise(&self) -> f64 {
        self.floor_height / (2.0 * self.treads as f64 + 2.0)
    }

    /// Centre line (y) of the first flight's lane (north) in the west stairwell; the second
    /// flight's lane is its mirror (south).
    pub(super) fn lane_centre(&self) -> f64 {
        (self.wall_thickness + self.lane_width) / 2.0
    }

    /// West end of the flights (the half landing's east edge), x.
    pub(super) fn flights_end(&self) -> f64 {
        -self.landing_depth - self.treads as f64 * self.tread_depth
    }
}
