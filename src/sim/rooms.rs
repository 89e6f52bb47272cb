//! Rooms along the sides of the office's corridor loop: their placement, doors and the anchors
//! a walker steers by (see [`super::office`] for the frame).

use super::office_config::{OfficeConfig, config_error};
use crate::error::Result;
use geo::{Coord, Rect};

/// One room with the anchors a walker steers by.
#[derive(Debug, Clone, PartialEq)]
pub struct Room {
    /// Name, `"room N"` (1-based, in the order of a counter-clockwise lap); its door is
    /// `"door N"`.
    pub name: String,
    /// True for rooms inside the corridor loop.
    pub inside_loop: bool,
    /// The room's floor.
    pub area: Rect<f64>,
    /// Point on the corridor's centre line in front of the door.
    pub corridor: Coord<f64>,
    /// Centre of the door (the middle of the wall gap).
    pub door: Coord<f64>,
    /// Point `entry_depth` inside the room, straight in from the door.
    pub entry: Coord<f64>,
    /// Centre of the room.
    pub centre: Coord<f64>,
    /// Arc length along a counter-clockwise lap of the centre line, from the origin, at which
    /// [`Room::corridor`] lies, metres.
    pub lap_position: f64,
}

/// A side of the loop, as (along, across) coordinates: `along` runs along the side's centre
/// line (x on south and north sides, y on east and west) and `across` points away from the
/// loop's middle, zero on the centre line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Side {
    South,
    East,
    North,
    West,
}

impl Side {
    /// The point at `along`, `across` on this side.
    pub(super) fn point(self, a: f64, b: f64, along: f64, across: f64) -> Coord<f64> {
        let (x, y) = match self {
            Side::South => (along, -across),
            Side::East => (a + across, along),
            Side::North => (along, b + across),
            Side::West => (-across, along),
        };
        Coord { x, y }
    }

    /// Arc length of the centre-line point at `along` on a counter-clockwise lap from the
    /// origin (south → east → north → west).
    pub(super) fn lap_position(self, a: f64, b: f64, along: f64) -> f64 {
        match self {
            Side::South => along,
            Side::East => a + along,
            Side::North => a + b + (a - along),
            Side::West => 2.0 * a + b + (b - along),
        }
    }
}

/// A room before numbering, with its door's surface.
pub(super) struct PlacedRoom {
    /// The room, unnamed.
    pub(super) anchors: Room,
    /// The door's floor.
    pub(super) door_area: Rect<f64>,
}

/// The rooms on one side, inside or outside the loop, spread evenly over the free stretch.
pub(super) fn side_rooms(
    config: &OfficeConfig,
    side: Side,
    inside_loop: bool,
) -> Result<Vec<PlacedRoom>> {
    let (c, t, d) = (
        config.corridor_width,
        config.wall_thickness,
        config.room_depth,
    );
    let (a, b) = config.centre_line_size();
    let long = matches!(side, Side::South | Side::North);
    let (count, span) = if long {
        (config.rooms_per_long_side, a)
    } else {
        (config.rooms_per_short_side, b)
    };
    if count == 0 {
        return Ok(Vec::new());
    }
    // The stretch of the side free for rooms: the whole outer wall outside the loop; inside
    // it, clear of the corridor's inner corners and, on short sides, of the long sides' rooms.
    let (lo, hi) = match (inside_loop, long) {
        (false, _) => (-c / 2.0, span + c / 2.0),
        (true, true) => (c / 2.0 + t, span - c / 2.0 - t),
        (true, false) => (c / 2.0 + 2.0 * t + d, span - c / 2.0 - 2.0 * t - d),
    };
    let slot = (hi - lo) / count as f64;
    if slot < config.room_width + t {
        let field = if long {
            "office.rooms_per_long_side"
        } else {
            "office.rooms_per_short_side"
        };
        return Err(crate::error::Error::config(
            field,
            count.to_string(),
            "too many rooms of room_width (plus a wall) for the side",
        ));
    }
    // The door opens onto the straight part of the corridor, within the room's width.
    let half_door = config.door_width / 2.0;
    let (door_lo, door_hi) = (c / 2.0 + half_door, span - c / 2.0 - half_door);
    let sign = if inside_loop { -1.0 } else { 1.0 };
    let wall = (c / 2.0, c / 2.0 + t); // |across| of the wall between corridor and room
    (0..count)
        .map(|i| {
            let mid = lo + (i as f64 + 0.5) * slot;
            let (r_lo, r_hi) = (mid - config.room_width / 2.0, mid + config.room_width / 2.0);
            let (first, last) = (door_lo.max(r_lo + half_door), door_hi.min(r_hi - half_door));
            if first > last {
                let reason = "a room's door cannot open onto the straight part of the corridor";
                return Err(config_error("office.room_width", config.room_width, reason));
            }
            let door_along = mid.clamp(first, last);
            let at = |along: f64, across: f64| side.point(a, b, along, sign * across);
            let area = Rect::new(at(r_lo, wall.1), at(r_hi, wall.1 + d));
            let door_area = Rect::new(
                at(door_along - half_door, wall.0),
                at(door_along + half_door, wall.1),
            );
            let anchors = Room {
                name: String::new(),
                inside_loop,
                area,
                corridor: at(door_along, 0.0),
                door: at(door_along, (wall.0 + wall.1) / 2.0),
                entry: at(door_along, wall.1 + config.entry_depth),
                centre: area.center(),
                lap_position: side.lap_position(a, b, door_along),
            };
            Ok(PlacedRoom { anchors, door_area })
        })
        .collect()
}
