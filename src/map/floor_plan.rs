//! 2.5D floor plans: walkable floor polygons with a level and a height.
//!
//! Each [`FloorPolygon`] is a walkable surface (holes are walls) on an integer `level` at
//! height `z` metres, in the local frame (x east, y north, metres).

use geo::{Contains, Polygon};

/// The widest plan supported, metres: a building or campus in one local (tangent-plane) frame.
pub const PLAN_MAX_EXTENT: f64 = 10_000.0;
/// The narrowest plan supported, metres (its larger side): anything smaller is not in metres.
pub const PLAN_MIN_EXTENT: f64 = 1.0;
/// The largest surface height supported, metres from the frame's zero (the tallest building
/// is 828 m; deep basements are tens of metres).
pub const PLAN_MAX_HEIGHT: f64 = 1_000.0;
/// The most levels a plan may have.
pub const PLAN_MAX_LEVELS: usize = 300;

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
///
/// A hall with a glass wall across it ([`Barrier`]): the floor under it stays walkable, but
/// no step crosses it.
///
/// ```
/// use footslam::map::{Barrier, FloorPlan, FloorPolygon, FloorTopology, TopologyConfig};
///
/// let plan = FloorPlan {
///     polygons: vec![FloorPolygon {
///         polygon: geo::Rect::new((0.0, 0.0), (10.0, 4.0)).to_polygon(),
///         level: 0,
///         z: 0.0,
///         name: Some("hall".into()),
///         room: None,
///     }],
///     // Across the hall at x = 5, open for its last metre.
///     barriers: vec![Barrier { line: vec![(5.0, 0.0), (5.0, 3.0)].into(), level: 0 }],
/// };
/// assert!(plan.is_walkable(5.0, 1.0, Some(0)));
/// assert!(!plan.is_walkable(5.0, 1.0, Some(1)));
/// assert_eq!(plan.bounds(), Some((0.0, 0.0, 10.0, 4.0)));
/// assert!(plan.check_limits().is_ok());
///
/// let topology = FloorTopology::build(&plan, &TopologyConfig::default())?;
/// assert_eq!(topology.walk(0, [2.0, 1.0], [8.0, 1.0]), None);
/// assert_eq!(topology.walk(0, [2.0, 3.5], [8.0, 3.5]), Some(0));
/// # Ok::<(), footslam::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FloorPlan {
    /// The surfaces.
    pub polygons: Vec<FloorPolygon>,
    /// Extra walls.
    pub barriers: Vec<Barrier>,
}

impl FloorPlan {
    /// True when `(x, y)` lies on a walkable surface of `level` (any level when `None`).
    #[must_use]
    pub fn is_walkable(&self, x: f64, y: f64, level: Option<i32>) -> bool {
        let p = geo::Point::new(x, y);
        self.polygons
            .iter()
            .filter(|f| level.is_none_or(|l| l == f.level))
            .any(|f| f.polygon.contains(&p) || geo::Intersects::intersects(&f.polygon, &p))
    }

    /// The levels of its surfaces, ascending, each once.
    #[must_use]
    pub fn levels(&self) -> Vec<i32> {
        let mut levels: Vec<i32> = self.polygons.iter().map(|p| p.level).collect();
        levels.sort_unstable();
        levels.dedup();
        levels
    }

    /// Bounding box `(min_x, min_y, max_x, max_y)` of all surfaces, `None` when empty.
    #[must_use]
    pub fn bounds(&self) -> Option<(f64, f64, f64, f64)> {
        use geo::BoundingRect;
        self.polygons
            .iter()
            .filter_map(|f| f.polygon.bounding_rect())
            .map(|r| (r.min().x, r.min().y, r.max().x, r.max().y))
            .reduce(|a, b| (a.0.min(b.0), a.1.min(b.1), a.2.max(b.2), a.3.max(b.3)))
    }

    /// Checks the plan against the limits of a building a walker can be tracked in
    /// ([`PLAN_MAX_EXTENT`], [`PLAN_MIN_EXTENT`], [`PLAN_MAX_HEIGHT`], [`PLAN_MAX_LEVELS`]), and
    /// that no surface is given twice (a duplicate doubles its share of the particles). The
    /// message says what is wrong and the limit.
    ///
    /// # Errors
    ///
    /// The message, when the plan has no surface, spans more than [`PLAN_MAX_EXTENT`] or less than
    /// [`PLAN_MIN_EXTENT`], reaches farther than [`PLAN_MAX_EXTENT`] from its origin, has a surface
    /// higher than [`PLAN_MAX_HEIGHT`] or more than [`PLAN_MAX_LEVELS`] levels, or gives a surface
    /// twice.
    pub fn check_limits(&self) -> Result<(), String> {
        let Some((x0, y0, x1, y1)) = self.bounds() else {
            return Err("the plan has no walkable surface".into());
        };
        let (w, h) = (x1 - x0, y1 - y0);
        if w.max(h) > PLAN_MAX_EXTENT {
            return Err(format!(
                "the plan spans {w:.0} m × {h:.0} m; at most {PLAN_MAX_EXTENT} m is supported \
                 (one building or campus in one local frame): is it in metres and in one place?"
            ));
        }
        let far = x0.abs().max(x1.abs()).max(y0.abs()).max(y1.abs());
        if far > PLAN_MAX_EXTENT {
            return Err(format!(
                "the plan reaches {:.0} km from its frame's origin; at most {PLAN_MAX_EXTENT} m is \
                 supported (a local frame that far is distorted): put the `origin` in the building",
                far / 1000.0
            ));
        }
        if w.max(h) < PLAN_MIN_EXTENT {
            return Err(format!(
                "the plan spans only {w:.3} m × {h:.3} m; a walkable plan spans at least \
                 {PLAN_MIN_EXTENT} m: is it in metres?"
            ));
        }
        if let Some(p) = self.polygons.iter().find(|p| p.z.abs() > PLAN_MAX_HEIGHT) {
            return Err(format!(
                "a surface of level {} has z = {:e} m; heights must be within ±{PLAN_MAX_HEIGHT} m",
                p.level, p.z
            ));
        }
        let levels = self.levels().len();
        if levels > PLAN_MAX_LEVELS {
            return Err(format!(
                "the plan has {levels} levels; at most {PLAN_MAX_LEVELS} are supported"
            ));
        }
        let key = |p: &FloorPolygon| {
            let ring: Vec<(u64, u64)> = p
                .polygon
                .exterior()
                .coords()
                .map(|c| (c.x.to_bits(), c.y.to_bits()))
                .collect();
            (p.level, p.z.to_bits(), ring)
        };
        let mut seen = std::collections::HashMap::with_capacity(self.polygons.len());
        for (i, p) in self.polygons.iter().enumerate() {
            if let Some(j) = seen.insert(key(p), i) {
                return Err(format!(
                    "surfaces {j} and {i} are the same polygon on level {}: remove one (a \
                     duplicate counts its area twice)",
                    p.level
                ));
            }
        }
        Ok(())
    }
}
