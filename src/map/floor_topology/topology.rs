//! The topology built from a plan ([`FloorTopology::build`]): its surfaces' heights, levels,
//! areas and polygons, its wall, connection and barrier segments, the grid index over them,
//! and the lookups the filters make (which surface holds a point, a uniform draw over the
//! walkable area). Steps are walked in `walk.rs`.

use super::config::TopologyConfig;
use super::grid::{BARRIER_FLAG, SegmentGrid};
use super::locate::LocateIndex;
use super::sampling::Triangles;
use super::segments::{Segment, barrier_segments, boundary_segments};
use crate::error::{Error, Result};
use crate::map::floor_plan::{FloorPlan, FloorPolygon};
use geo::{Area, BoundingRect, Contains, Intersects, Validation};

/// Most surfaces a plan may have (ids must stay below [`BARRIER_FLAG`]).
const MAX_SURFACES: usize = (BARRIER_FLAG - 1) as usize;

/// The walkable surfaces' heights, levels, edges and spatial index.
///
/// A corridor and a room that share a stretch of wall: the shared stretch is a connection,
/// the rest walls.
///
/// ```
/// use footslam::map::{FloorPlan, FloorPolygon, FloorTopology, SegmentKind, TopologyConfig};
///
/// let surface = |x0: f64, y0: f64, x1: f64, y1: f64| FloorPolygon {
///     polygon: geo::Rect::new((x0, y0), (x1, y1)).to_polygon(),
///     level: 0,
///     z: 0.0,
///     name: None,
///     room: None,
/// };
/// // A corridor (surface 0) and a room north of it (surface 1) open to it over 4 m.
/// let plan = FloorPlan {
///     polygons: vec![surface(0.0, 0.0, 10.0, 2.0), surface(3.0, 2.0, 7.0, 6.0)],
///     barriers: Vec::new(),
/// };
/// let topology = FloorTopology::build(&plan, &TopologyConfig::default())?;
/// assert_eq!(topology.len(), 2);
/// assert_eq!(topology.locate(5.0, 4.0, None, None), Some(1));
/// let segments = topology.segments().iter();
/// let connections = segments.filter(|s| matches!(s.kind, SegmentKind::Connection { .. }));
/// assert_eq!(connections.count(), 1);
///
/// // A step through the opening ends in the room; one through a wall is refused.
/// assert_eq!(topology.walk(0, [5.0, 1.0], [5.0, 4.0]), Some(1));
/// assert_eq!(topology.walk(0, [1.0, 1.0], [1.0, 4.0]), None);
/// # Ok::<(), footslam::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct FloorTopology {
    z: Vec<f32>,
    pub(super) level: Vec<i32>,
    area: Vec<f64>,
    bboxes: Vec<[f64; 4]>,
    polygons: Vec<geo::Polygon<f64>>,
    pub(super) levels: (i32, i32),
    pub(super) bounds: [f64; 4],
    segments: Vec<Segment>,
    /// The spatial index of segments and surfaces.
    pub(super) grid: SegmentGrid,
    /// The surfaces holding each grid cell no boundary crosses.
    pub(super) locator: LocateIndex,
    /// Triangles of all surfaces with cumulative areas (for `sample_uniform`).
    triangles: Triangles,
}

impl FloorTopology {
    /// Builds the topology of `plan`, rejecting plans whose surfaces are not valid polygons
    /// (non-finite coordinates, self-intersecting or unclosed rings, no area).
    ///
    /// # Errors
    ///
    /// - [`Error::Config`](crate::Error::Config) when `config` fails [`TopologyConfig::validate`].
    /// - [`Error::TooLarge`](crate::Error::TooLarge) with 2³¹ surfaces or more.
    /// - [`Error::InvalidData`](crate::Error::InvalidData) naming the first surface whose height or
    ///   a coordinate is not finite (or beyond 10 000 km), whose ring has fewer than three corners,
    ///   is not a valid polygon or has no area; or the first barrier with a coordinate that is not
    ///   finite.
    pub fn build(plan: &FloorPlan, config: &TopologyConfig) -> Result<Self> {
        config.validate()?;
        if plan.polygons.len() > MAX_SURFACES {
            return Err(Error::too_large(
                "the plan",
                format!("{} surfaces", plan.polygons.len()),
                MAX_SURFACES,
                "split the building into several plans",
            ));
        }
        for (i, f) in plan.polygons.iter().enumerate() {
            check_surface(i, f)?;
        }
        let z: Vec<f32> = plan.polygons.iter().map(|f| f.z as f32).collect();
        let level: Vec<i32> = plan.polygons.iter().map(|f| f.level).collect();
        let area: Vec<f64> = plan
            .polygons
            .iter()
            .map(|f| f.polygon.unsigned_area())
            .collect();
        let bboxes: Vec<[f64; 4]> = plan
            .polygons
            .iter()
            .map(|f| {
                f.polygon
                    .bounding_rect()
                    .map_or([0.0; 4], |r| [r.min().x, r.min().y, r.max().x, r.max().y])
            })
            .collect();
        let levels = level
            .iter()
            .chain(plan.barriers.iter().map(|b| &b.level))
            .fold(None, |acc: Option<(i32, i32)>, &l| {
                Some(acc.map_or((l, l), |(lo, hi)| (lo.min(l), hi.max(l))))
            })
            .unwrap_or((0, 0));
        let mut segments = boundary_segments(plan, config);
        segments.extend(barrier_segments(plan)?);
        let bounds = bboxes
            .iter()
            .copied()
            .chain(segments.iter().map(|s| {
                [
                    s.a[0].min(s.b[0]),
                    s.a[1].min(s.b[1]),
                    s.a[0].max(s.b[0]),
                    s.a[1].max(s.b[1]),
                ]
            }))
            .reduce(|a, b| {
                [
                    a[0].min(b[0]),
                    a[1].min(b[1]),
                    a[2].max(b[2]),
                    a[3].max(b[3]),
                ]
            })
            .unwrap_or([0.0; 4]);
        let grid = SegmentGrid::build(&segments, &bboxes, bounds, levels, config.cell_size);
        let polygons: Vec<geo::Polygon<f64>> =
            plan.polygons.iter().map(|f| f.polygon.clone()).collect();
        let triangles = Triangles::new(&polygons);
        let locator = LocateIndex::build(&grid, &polygons);
        Ok(Self {
            z,
            level,
            area,
            bboxes,
            polygons,
            levels,
            bounds,
            segments,
            grid,
            locator,
            triangles,
        })
    }

    /// Number of surfaces.
    #[must_use]
    pub fn len(&self) -> usize {
        self.z.len()
    }

    /// True when the plan has no surface.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.z.is_empty()
    }

    /// Height of `surface`, metres.
    #[inline]
    #[must_use]
    pub fn z(&self, surface: u32) -> f32 {
        self.z[surface as usize]
    }

    /// Level of `surface`.
    #[inline]
    #[must_use]
    pub fn level(&self, surface: u32) -> i32 {
        self.level[surface as usize]
    }

    /// Area of `surface`, square metres.
    #[must_use]
    pub fn area(&self, surface: u32) -> f64 {
        self.area[surface as usize]
    }

    /// Walkable area of all surfaces, square metres.
    #[must_use]
    pub fn total_area(&self) -> f64 {
        self.area.iter().sum()
    }

    /// Bounding box of the plan: min x, min y, max x, max y, metres.
    #[must_use]
    pub fn bounds(&self) -> [f64; 4] {
        self.bounds
    }

    /// Lowest and highest level.
    #[must_use]
    pub fn levels(&self) -> (i32, i32) {
        self.levels
    }

    /// Every wall, connection and barrier segment.
    #[must_use]
    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    /// The surface containing `(x, y)`: on `level` when given; among several (stacked
    /// levels) the one whose height is nearest `z_hint`, else the lowest.
    #[must_use]
    pub fn locate(&self, x: f64, y: f64, level: Option<i32>, z_hint: Option<f64>) -> Option<u32> {
        let cell = self.grid.cell_of(x, y);
        let nearest = |a: &u32, b: &u32| {
            let key = |s: u32| {
                let z = f64::from(self.z[s as usize]);
                z_hint.map_or(z, |h| (z - h).abs())
            };
            key(*a).total_cmp(&key(*b)).then(a.cmp(b))
        };
        let on_level = |&s: &u32| level.is_none_or(|l| l == self.level[s as usize]);
        // Most points: the surfaces holding the point's whole cell, known in advance.
        if let Some(inside) = self.locator.inside(cell, x, y) {
            return inside.iter().copied().filter(on_level).min_by(nearest);
        }
        let p = geo::Point::new(x, y);
        self.grid
            .surfaces_in(cell)
            .iter()
            .copied()
            .filter(on_level)
            .filter(|&s| {
                let b = self.bboxes[s as usize];
                x >= b[0] && x <= b[2] && y >= b[1] && y <= b[3]
            })
            .filter(|&s| {
                let poly = &self.polygons[s as usize];
                poly.contains(&p) || poly.intersects(&p)
            })
            .min_by(nearest)
    }

    /// A point drawn uniformly over the whole walkable area (holes excluded) and its surface.
    pub fn sample_uniform<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> (u32, [f64; 2]) {
        self.triangles.sample(rng)
    }
}

/// Rejects a surface that is not a valid polygon, naming it.
fn check_surface(i: usize, f: &FloorPolygon) -> Result<()> {
    let name = f
        .name
        .as_ref()
        .map_or(String::new(), |n| format!(" (\"{n}\")"));
    let bad = |m: String| Err(Error::invalid(format!("floor polygon {i}{name}"), m));
    if !f.z.is_finite() {
        return bad(format!("height z = {} is not finite", f.z));
    }
    let coords = || {
        std::iter::once(f.polygon.exterior())
            .chain(f.polygon.interiors())
            .flat_map(|r| r.coords())
    };
    if coords().any(|c| !(c.x.is_finite() && c.y.is_finite())) {
        return bad("a coordinate is not finite".into());
    }
    if coords().any(|c| c.x.abs() > 1e7 || c.y.abs() > 1e7) {
        return bad("a coordinate is more than 10,000 km from the origin".into());
    }
    if f.polygon.exterior().0.len() < 4 {
        return bad("the exterior ring has fewer than 3 distinct corners".into());
    }
    if let Err(e) = f.polygon.check_validation() {
        return bad(format!("not a valid polygon: {e}"));
    }
    if f.polygon.unsigned_area() <= 0.0 {
        return bad("the polygon has no area".into());
    }
    Ok(())
}
