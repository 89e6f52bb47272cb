//! A floor plan as an occupancy grid — free, occupied, unknown squares — the map that most
//! robot and indoor localisers load (ROS `map_server`, AMCL, Cartographer's pure
//! localisation, Nav2). Written by [`crate::io::write_ros_map`].
//!
//! A square is **free** when its centre lies in a walkable polygon of the level (scan-line
//! fill, even–odd per polygon, so holes stay out); **occupied** when it is not free but lies
//! within `wall` metres of a free square (the walls around the walkable area, as a laser or
//! a particle filter expects them); **unknown** elsewhere. The grid covers the level's
//! polygons plus `border` metres on every side.

use super::floor_plan::FloorPlan;
use crate::error::{Error, Result};
use geo::BoundingRect;
use serde::{Deserialize, Serialize};

/// Settings of [`OccupancyGrid::from_plan`]; every default in one place.
///
/// | field        | default | meaning                                            |
/// |--------------|---------|----------------------------------------------------|
/// | `resolution` | 0.05 m  | side of a square (ROS maps' usual 5 cm)            |
/// | `wall`       | 0.15 m  | band of occupied squares around the walkable area  |
/// | `border`     | 1 m     | margin around the level's polygons                 |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OccupancyConfig {
    /// Side of a square, metres. Default 0.05.
    pub resolution: f64,
    /// Width of the occupied band around the walkable area, metres. Default 0.15.
    pub wall: f64,
    /// Margin around the level's polygons, metres. Default 1.
    pub border: f64,
}

impl Default for OccupancyConfig {
    fn default() -> Self {
        Self {
            resolution: 0.05,
            wall: 0.15,
            border: 1.0,
        }
    }
}

impl OccupancyConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `resolution` is outside [0.005, 10] m, `wall` outside [0, 10] m or
    /// `border` outside [0, 1000] m.
    pub fn validate(&self) -> Result<()> {
        crate::error::check_range("grid.resolution", self.resolution, 0.005..=10.0, "m")?;
        crate::error::check_range("grid.wall", self.wall, 0.0..=10.0, "m")?;
        crate::error::check_range("grid.border", self.border, 0.0..=1000.0, "m")?;
        Ok(())
    }
}

/// What a square holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Occupancy {
    /// Walkable.
    Free,
    /// A wall (not walkable, next to walkable space).
    Occupied,
    /// Not known.
    Unknown,
}

/// The largest grid built, squares (a 16,384 × 16,384 image).
const MAX_SQUARES: usize = 1 << 28;

/// An occupancy grid in a plan's local frame.
#[derive(Debug, Clone, PartialEq)]
pub struct OccupancyGrid {
    /// Squares per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Side of a square, metres.
    pub resolution: f64,
    /// South-west corner of the first square, local metres.
    pub origin: (f64, f64),
    /// Row by row from the south, west to east.
    pub cells: Vec<Occupancy>,
}

impl OccupancyGrid {
    /// The grid of `plan`'s polygons on `level` (see the module documentation).
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `config` fails [`OccupancyConfig::validate`]; [`Error::NotEnough`]
    /// when the plan has no polygon on `level`; [`Error::TooLarge`] when the grid would exceed 2²⁸
    /// squares.
    pub fn from_plan(plan: &FloorPlan, level: i32, config: &OccupancyConfig) -> Result<Self> {
        config.validate()?;
        let polygons: Vec<_> = plan
            .polygons
            .iter()
            .filter(|p| p.level == level)
            .map(|p| &p.polygon)
            .collect();
        // The exteriors bound their holes too.
        let Some((lo, hi)) = polygons
            .iter()
            .filter_map(|p| p.bounding_rect())
            .map(|r| ((r.min().x, r.min().y), (r.max().x, r.max().y)))
            .reduce(|a, b| {
                (
                    (a.0.0.min(b.0.0), a.0.1.min(b.0.1)),
                    (a.1.0.max(b.1.0), a.1.1.max(b.1.1)),
                )
            })
        else {
            return Err(Error::not_enough(
                format!("the plan has no polygon on level {level} to make an occupancy grid of"),
                "choose a level the plan has",
            ));
        };
        let r = config.resolution;
        let origin = (lo.0 - config.border, lo.1 - config.border);
        let width = ((hi.0 + config.border - origin.0) / r).ceil().max(1.0) as usize;
        let height = ((hi.1 + config.border - origin.1) / r).ceil().max(1.0) as usize;
        if width.saturating_mul(height) > MAX_SQUARES {
            return Err(Error::too_large(
                format!("an occupancy grid at {r} m"),
                format!("{width} × {height} squares"),
                MAX_SQUARES,
                "raise the resolution",
            ));
        }
        let mut cells = vec![Occupancy::Unknown; width * height];
        // Scan lines through the squares' centres: each polygon fills between pairs of
        // crossings of its rings (even–odd, so its holes stay out).
        let mut xs = Vec::new();
        for row in 0..height {
            let y = origin.1 + (row as f64 + 0.5) * r;
            for polygon in &polygons {
                xs.clear();
                for ring in std::iter::once(polygon.exterior()).chain(polygon.interiors()) {
                    for line in ring.lines() {
                        let (a, b) = (line.start, line.end);
                        // Half-open in y, so a vertex on the line counts once.
                        if (a.y <= y) != (b.y <= y) {
                            xs.push(a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x));
                        }
                    }
                }
                xs.sort_by(f64::total_cmp);
                for pair in xs.chunks_exact(2) {
                    // Squares whose centre lies between the two crossings.
                    let first = ((pair[0] - origin.0) / r - 0.5).ceil().max(0.0) as usize;
                    let last = ((pair[1] - origin.0) / r - 0.5).floor();
                    if last < 0.0 {
                        continue;
                    }
                    let last = (last as usize).min(width - 1);
                    if first <= last {
                        cells[row * width + first..=row * width + last].fill(Occupancy::Free);
                    }
                }
            }
        }
        // Walls: squares not free within `wall` of a free square.
        let k = (config.wall / r).round() as isize;
        if k > 0 {
            let free: Vec<bool> = cells.iter().map(|c| *c == Occupancy::Free).collect();
            // The square `(dc, dr)` from `(col, row)`, if on the grid.
            let at = |col: usize, row: usize, dc: isize, dr: isize| -> Option<usize> {
                let (c, rw) = (col.checked_add_signed(dc)?, row.checked_add_signed(dr)?);
                (c < width && rw < height).then_some(rw * width + c)
            };
            for row in 0..height {
                for col in 0..width {
                    let i = row * width + col;
                    if !free[i] {
                        continue;
                    }
                    // Only squares on the edge of the free area have non-free neighbours.
                    let edge = [(1, 0), (-1, 0), (0, 1), (0, -1)]
                        .iter()
                        .any(|&(dc, dr)| at(col, row, dc, dr).is_none_or(|j| !free[j]));
                    if !edge {
                        continue;
                    }
                    for dr in -k..=k {
                        for dc in -k..=k {
                            if dc * dc + dr * dr > k * k {
                                continue;
                            }
                            if let Some(j) = at(col, row, dc, dr)
                                && !free[j]
                            {
                                cells[j] = Occupancy::Occupied;
                            }
                        }
                    }
                }
            }
        }
        Ok(Self {
            width,
            height,
            resolution: r,
            origin,
            cells,
        })
    }

    /// The square holding `(x, y)`, if the grid covers it.
    #[must_use]
    pub fn at(&self, x: f64, y: f64) -> Option<Occupancy> {
        let c = ((x - self.origin.0) / self.resolution).floor();
        let r = ((y - self.origin.1) / self.resolution).floor();
        (c >= 0.0 && r >= 0.0 && (c as usize) < self.width && (r as usize) < self.height)
            .then(|| self.cells[r as usize * self.width + c as usize])
    }

    /// Squares of each kind: (free, occupied, unknown).
    #[must_use]
    pub fn counts(&self) -> (usize, usize, usize) {
        self.cells.iter().fold((0, 0, 0), |(f, o, u), c| match c {
            Occupancy::Free => (f + 1, o, u),
            Occupancy::Occupied => (f, o + 1, u),
            Occupancy::Unknown => (f, o, u + 1),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::FloorPolygon;
    use geo::{LineString, Polygon, Rect};

    #[test]
    fn a_room_with_a_pillar_is_free_inside_walled_around_and_unknown_beyond() {
        let room = Polygon::new(
            Rect::new((0.0, 0.0), (4.0, 3.0))
                .to_polygon()
                .exterior()
                .clone(),
            vec![LineString::from(vec![
                (1.5, 1.0),
                (2.5, 1.0),
                (2.5, 2.0),
                (1.5, 2.0),
                (1.5, 1.0),
            ])],
        );
        let plan = FloorPlan {
            polygons: vec![FloorPolygon {
                polygon: room,
                level: 0,
                z: 0.0,
                name: None,
                room: None,
            }],
            barriers: vec![],
        };
        let config = OccupancyConfig {
            resolution: 0.1,
            wall: 0.2,
            border: 0.5,
        };
        let grid = OccupancyGrid::from_plan(&plan, 0, &config).expect("grid");
        assert_eq!((grid.width, grid.height), (50, 40));
        assert_eq!(grid.at(0.55, 0.55), Some(Occupancy::Free));
        assert_eq!(grid.at(3.95, 2.95), Some(Occupancy::Free));
        assert_eq!(
            grid.at(2.0, 1.5),
            Some(Occupancy::Unknown),
            "inside the pillar"
        );
        assert_eq!(
            grid.at(1.55, 1.5),
            Some(Occupancy::Occupied),
            "the pillar's face"
        );
        assert_eq!(
            grid.at(-0.15, 1.5),
            Some(Occupancy::Occupied),
            "the west wall"
        );
        assert_eq!(
            grid.at(-0.45, 1.5),
            Some(Occupancy::Unknown),
            "beyond the wall"
        );
        assert_eq!(grid.at(-1.0, 1.5), None);
        let (free, _, _) = grid.counts();
        // 12 m² less the 1 m² pillar, in 0.01 m² squares.
        assert_eq!(free, 1100);
        assert!(OccupancyGrid::from_plan(&plan, 3, &config).is_err());
        let huge = OccupancyConfig {
            resolution: 0.005,
            border: 1000.0,
            ..config
        };
        assert!(OccupancyGrid::from_plan(&plan, 0, &huge).is_err());
    }
}
