//! 2.5D floor plans: walkable floor polygons with a level and a height.
//!
//! Each [`FloorPolygon`] is a walkable surface (holes are walls) on an integer `level` at
//! height `z` metres, in the local frame (x east, y north, metres).

use geo::{Contains, Polygon};

/// One walkable floor surface.
#[derive(Debug, Clone, PartialEq)]
pub struct FloorPolygon {
    /// The surface; interior rings are walls or obstacles.
    pub polygon: Polygon<f64>,
    /// Floor level (0 = ground floor).
    pub level: i32,
    /// Height of the surface, metres.
    pub z: f64,
    /// Optional name (e.g. "corridor", "room 3").
    pub name: Option<String>,
    /// Optional room this surface belongs to (surfaces sharing it form one room for radio
    /// cells); `None` lets the plan's connections decide.
    pub room: Option<String>,
}

/// A level of a building as learned from walks: its number and floor height, metres above
/// the walk's start floor ([`crate::model::floor_levels`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FloorLevel {
    /// Level number: 0 is the walk's first floor, 1 the next one up, −1 the one below.
    pub level: i32,
    /// Floor height, metres, relative to the first floor.
    pub z: f64,
}

/// An extra wall (a handrail, a glass wall, a wall missing from the polygons) that blocks
/// walkers on every surface of its level.
#[derive(Debug, Clone, PartialEq)]
pub struct Barrier {
    /// The wall's centre line.
    pub line: geo::LineString<f64>,
    /// The level it blocks.
    pub level: i32,
}

/// A building's walkable floor surfaces and extra walls.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FloorPlan {
    /// The surfaces.
    pub polygons: Vec<FloorPolygon>,
    /// Extra walls.
    pub barriers: Vec<Barrier>,
}

impl FloorPlan {
    /// True when `(x, y)` lies on a walkable surface of `level` (any level when `None`).
    pub fn is_walkable(&self, x: f64, y: f64, level: Option<i32>) -> bool {
        let p = geo::Point::new(x, y);
        self.polygons
            .iter()
            .filter(|f| level.is_none_or(|l| l == f.level))
            .any(|f| f.polygon.contains(&p) || geo::Intersects::intersects(&f.polygon, &p))
    }

    /// The levels of its surfaces, ascending, each once.
    pub fn levels(&self) -> Vec<i32> {
        let mut levels: Vec<i32> = self.polygons.iter().map(|p| p.level).collect();
        levels.sort_unstable();
        levels.dedup();
        levels
    }

    /// Bounding box `(min_x, min_y, max_x, max_y)` of all surfaces, `None` when empty.
    pub fn bounds(&self) -> Option<(f64, f64, f64, f64)> {
        use geo::BoundingRect;
        self.polygons
            .iter()
            .filter_map(|f| f.polygon.bounding_rect())
            .map(|r| (r.min().x, r.min().y, r.max().x, r.max().y))
            .reduce(|a, b| (a.0.min(b.0), a.1.min(b.1), a.2.max(b.2), a.3.max(b.3)))
    }
}
