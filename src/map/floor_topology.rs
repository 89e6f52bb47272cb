//! The topology of a 2.5D floor plan, built once: which polygon edges are walls and which are
//! connections between surfaces, indexed for the particle filter's hot path (Woodman & Harle
//! 2008, sec. "Floor polygons", eqs. 12–16 and Algorithm 1 lines 7–24).
//!
//! Rules:
//! * every boundary segment of a surface (exterior ring and holes) is a **wall**, except
//! * the parts of it that overlap, collinearly in the horizontal plane within
//!   [`TopologyConfig::connection_tolerance`], a boundary segment of another surface whose
//!   height differs by at most [`TopologyConfig::max_connection_dz`]: those are
//!   **connections** between the two surfaces (a door rectangle touching a corridor and a
//!   room, adjacent stair treads, a corridor split into pieces). Partly overlapping edges are
//!   split into their connection and wall parts;
//! * every segment of a [`Barrier`](super::floor_plan::Barrier) line is a wall for the
//!   surfaces of its level.
//!
//! A step is walked from its surface through that surface's own edges only: surfaces on other
//! levels that overlap it in the plane (stairwells) never interfere.
//!
//! The index is a uniform grid over the plan with the segments of each cell stored
//! contiguously (compressed rows), as compact `f32` records; a step tests the records of the
//! few cells its bounding box touches, filtered by surface id before any arithmetic.

use super::floor_plan::FloorPlan;
use crate::error::{Error, Result};
use geo::{Area, BoundingRect, Contains, Intersects, TriangulateEarcut, Validation, Winding};
use rand::RngExt;
use serde::{Deserialize, Serialize};

/// Most connections one step may cross (a long step down a steep stair crosses a few).
const MAX_HOPS: usize = 64;
/// Most cells of the spatial index (the cell size grows for larger plans).
const MAX_CELLS: usize = 1 << 22;
/// The right-hand side of a wall record: no surface.
const NO_SURFACE: u32 = u32::MAX;
/// Edge pieces shorter than this are dropped, metres.
const MIN_PIECE: f64 = 1e-4;
/// Barrier records carry this flag and the level's index in their surface fields.
const BARRIER_FLAG: u32 = 1 << 31;
/// Most surfaces a plan may have (ids must stay below [`BARRIER_FLAG`]).
const MAX_SURFACES: usize = (BARRIER_FLAG - 1) as usize;

/// Topology tolerances and the spatial index's cell; every default in one place.
///
/// | field                  | default | meaning                                                 |
/// |------------------------|---------|---------------------------------------------------------|
/// | `connection_tolerance` | 0.05 m  | collinear edges within this are one shared boundary     |
/// | `max_connection_dz`    | 0.5 m   | surfaces further apart in height never connect          |
/// | `cell_size`            | 1.0 m   | edge of the grid cells indexing the segments            |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TopologyConfig {
    /// Two boundary segments closer than this to each other's line are collinear, metres.
    pub connection_tolerance: f64,
    /// Largest height difference of connected surfaces, metres.
    pub max_connection_dz: f64,
    /// Edge of the spatial index's cells, metres.
    pub cell_size: f64,
}

impl Default for TopologyConfig {
    fn default() -> Self {
        Self {
            connection_tolerance: 0.05,
            max_connection_dz: 0.5,
            cell_size: 1.0,
        }
    }
}

impl TopologyConfig {
    /// Checks every field against its documented range.
    pub fn validate(&self) -> Result<()> {
        crate::error::check_range(
            "topology.connection_tolerance",
            self.connection_tolerance,
            0.0..=1.0,
            "metres",
        )?;
        crate::error::check_range(
            "topology.max_connection_dz",
            self.max_connection_dz,
            0.0..=100.0,
            "metres",
        )?;
        crate::error::check_range("topology.cell_size", self.cell_size, 0.1..=1000.0, "metres")
    }
}

/// What a segment does to a walker crossing it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SegmentKind {
    /// A wall of `surface`, which lies to the left of the direction from `a` to `b`.
    Wall {
        /// The surface it bounds.
        surface: u32,
    },
    /// A passage between surfaces `a` (to the left of the direction from the segment's `a`
    /// to its `b`) and `b` (to the right).
    Connection {
        /// One surface.
        a: u32,
        /// The other surface.
        b: u32,
    },
    /// An extra wall for every surface of `level`.
    Barrier {
        /// The level it blocks.
        level: i32,
    },
}

/// A wall, connection or barrier segment, local metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// One end.
    pub a: [f64; 2],
    /// The other end.
    pub b: [f64; 2],
    /// Its role.
    pub kind: SegmentKind,
}

/// One segment as stored in a grid cell: 24 bytes.
///
/// Oriented: `left` lies to the left of the direction from `a` to `b`, `right` to its right
/// ([`NO_SURFACE`] for a wall; both the flagged level index for a barrier). Both ends are
/// stored, so segments meeting at a corner hold that corner bit for bit alike.
#[derive(Debug, Clone, Copy)]
struct Record {
    ax: f32,
    ay: f32,
    bx: f32,
    by: f32,
    left: u32,
    right: u32,
}

/// Connections are crossed only beyond the step fraction of the previous crossing; walls and
/// barriers from this far before it, so that no wall is lost to rounding at a shared corner.
const WALL_SLACK: f32 = 1e-4;

/// The walkable surfaces' heights, levels, edges and spatial index.
#[derive(Debug, Clone)]
pub struct FloorTopology {
    z: Vec<f32>,
    level: Vec<i32>,
    area: Vec<f64>,
    bboxes: Vec<[f64; 4]>,
    polygons: Vec<geo::Polygon<f64>>,
    levels: (i32, i32),
    bounds: [f64; 4],
    segments: Vec<Segment>,
    /// Grid: origin, reciprocal cell size, dimensions, row offsets and records.
    origin: [f32; 2],
    inv_cell: f32,
    nx: usize,
    ny: usize,
    offsets: Vec<u32>,
    records: Vec<Record>,
    /// Surfaces whose bounding box meets each cell (for `locate`).
    surface_offsets: Vec<u32>,
    surface_ids: Vec<u32>,
    /// Triangles of all surfaces with cumulative areas (for `sample_uniform`).
    triangles: Vec<(u32, [[f64; 2]; 3])>,
    cumulative: Vec<f64>,
}

impl FloorTopology {
    /// Builds the topology of `plan`, rejecting plans whose surfaces are not valid polygons
    /// (non-finite coordinates, self-intersecting or unclosed rings, no area).
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
        for (i, b) in plan.barriers.iter().enumerate() {
            if b.line
                .coords()
                .any(|c| !(c.x.is_finite() && c.y.is_finite()))
            {
                return Err(Error::invalid(
                    format!("barrier {i}"),
                    "has a non-finite coordinate",
                ));
            }
            for l in b.line.lines() {
                if (l.end.x - l.start.x).hypot(l.end.y - l.start.y) > MIN_PIECE {
                    segments.push(Segment {
                        a: [l.start.x, l.start.y],
                        b: [l.end.x, l.end.y],
                        kind: SegmentKind::Barrier { level: b.level },
                    });
                }
            }
        }
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
        let mut topology = Self {
            z,
            level,
            area,
            bboxes,
            polygons: plan.polygons.iter().map(|f| f.polygon.clone()).collect(),
            levels,
            bounds,
            segments,
            origin: [0.0; 2],
            inv_cell: 1.0,
            nx: 1,
            ny: 1,
            offsets: Vec::new(),
            records: Vec::new(),
            surface_offsets: Vec::new(),
            surface_ids: Vec::new(),
            triangles: Vec::new(),
            cumulative: Vec::new(),
        };
        topology.index(config.cell_size);
        topology.triangulate();
        Ok(topology)
    }

    /// Number of surfaces.
    pub fn len(&self) -> usize {
        self.z.len()
    }

    /// True when the plan has no surface.
    pub fn is_empty(&self) -> bool {
        self.z.is_empty()
    }

    /// Height of `surface`, metres.
    #[inline]
    pub fn z(&self, surface: u32) -> f32 {
        self.z[surface as usize]
    }

    /// Level of `surface`.
    #[inline]
    pub fn level(&self, surface: u32) -> i32 {
        self.level[surface as usize]
    }

    /// Area of `surface`, square metres.
    pub fn area(&self, surface: u32) -> f64 {
        self.area[surface as usize]
    }

    /// Walkable area of all surfaces, square metres.
    pub fn total_area(&self) -> f64 {
        self.area.iter().sum()
    }

    /// Bounding box of the plan: min x, min y, max x, max y, metres.
    pub fn bounds(&self) -> [f64; 4] {
        self.bounds
    }

    /// Lowest and highest level.
    pub fn levels(&self) -> (i32, i32) {
        self.levels
    }

    /// Every wall, connection and barrier segment.
    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    /// Algorithm 1, lines 7–24: walks the straight step from `from` (on `surface`) to `to`
    /// through the surface's edges, into the next surface at each connection, for the rest of
    /// the step. Returns the surface `to` lies on, or `None` when the step crosses a wall or
    /// a barrier (or more than 64 connections).
    #[inline]
    pub fn walk(&self, surface: u32, from: [f32; 2], to: [f32; 2]) -> Option<u32> {
        // The step stays one fixed segment; `t_c` is the fraction of it where the last
        // connection was crossed (a start a hair past a connection still crosses it).
        let (sx, sy) = (to[0] - from[0], to[1] - from[1]);
        let (ix0, ix1) = self.span(from[0].min(to[0]), from[0].max(to[0]), 0);
        let (iy0, iy1) = self.span(from[1].min(to[1]), from[1].max(to[1]), 1);
        let mut s = surface;
        let mut t_c = -WALL_SLACK;
        for _ in 0..MAX_HOPS {
            let barrier = BARRIER_FLAG | (self.level[s as usize] - self.levels.0) as u32;
            let mut best_t = f32::INFINITY;
            let mut best: Option<(&Record, bool, bool)> = None;
            for iy in iy0..=iy1 {
                let row = iy * self.nx;
                let lo = self.offsets[row + ix0] as usize;
                let hi = self.offsets[row + ix1 + 1] as usize;
                for r in &self.records[lo..hi] {
                    let (on_left, on_right) = (r.left == s, r.right == s);
                    let is_barrier = r.left == barrier;
                    if !(on_left || on_right || is_barrier) {
                        continue;
                    }
                    let (dx, dy) = (r.bx - r.ax, r.by - r.ay);
                    // The step leaves the surface's side: left to right is cross(d, S) < 0.
                    let denom = dx * sy - dy * sx;
                    let leaves = if on_left {
                        denom < 0.0
                    } else if on_right {
                        denom > 0.0
                    } else {
                        denom != 0.0
                    };
                    if !leaves {
                        continue;
                    }
                    // The segment's ends lie on both sides of (or on) the step's line.
                    let ca = sx * (r.ay - from[1]) - sy * (r.ax - from[0]);
                    let cb = sx * (r.by - from[1]) - sy * (r.bx - from[0]);
                    if ca * cb > 0.0 {
                        continue;
                    }
                    let t = (dx * (r.ay - from[1]) - dy * (r.ax - from[0])) / denom;
                    let wall = is_barrier || r.right == NO_SURFACE || r.left == NO_SURFACE;
                    let after = if wall { t >= t_c - WALL_SLACK } else { t > t_c };
                    if after && t <= 1.0 && (t < best_t || (t == best_t && wall)) {
                        best_t = t;
                        best = Some((r, on_left, wall));
                    }
                }
            }
            let Some((r, on_left, wall)) = best else {
                return Some(s);
            };
            if wall {
                return None; // eq. (14)
            }
            s = if on_left { r.right } else { r.left }; // eq. (13)
            t_c = best_t;
        }
        None
    }

    /// The surface containing `(x, y)`: on `level` when given; among several (stacked
    /// levels) the one whose height is nearest `z_hint`, else the lowest.
    pub fn locate(&self, x: f64, y: f64, level: Option<i32>, z_hint: Option<f64>) -> Option<u32> {
        let (ix0, _) = self.span(x as f32, x as f32, 0);
        let (iy0, _) = self.span(y as f32, y as f32, 1);
        let cell = iy0 * self.nx + ix0;
        let ids = &self.surface_ids
            [self.surface_offsets[cell] as usize..self.surface_offsets[cell + 1] as usize];
        let p = geo::Point::new(x, y);
        ids.iter()
            .copied()
            .filter(|&s| level.is_none_or(|l| l == self.level[s as usize]))
            .filter(|&s| {
                let b = self.bboxes[s as usize];
                x >= b[0] && x <= b[2] && y >= b[1] && y <= b[3]
            })
            .filter(|&s| {
                let poly = &self.polygons[s as usize];
                poly.contains(&p) || poly.intersects(&p)
            })
            .min_by(|&a, &b| {
                let key = |s: u32| {
                    let z = f64::from(self.z[s as usize]);
                    z_hint.map_or(z, |h| (z - h).abs())
                };
                key(a).total_cmp(&key(b)).then(a.cmp(&b))
            })
    }

    /// A point drawn uniformly over the whole walkable area (holes excluded) and its surface.
    pub fn sample_uniform<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> (u32, [f64; 2]) {
        let total = self.cumulative.last().copied().unwrap_or(0.0);
        let u = rng.random::<f64>() * total;
        let i = self
            .cumulative
            .partition_point(|&c| c <= u)
            .min(self.triangles.len().saturating_sub(1));
        let Some(&(surface, [a, b, c])) = self.triangles.get(i) else {
            return (0, [0.0, 0.0]);
        };
        let (mut r1, mut r2) = (rng.random::<f64>(), rng.random::<f64>());
        if r1 + r2 > 1.0 {
            (r1, r2) = (1.0 - r1, 1.0 - r2);
        }
        let p = [
            a[0] + r1 * (b[0] - a[0]) + r2 * (c[0] - a[0]),
            a[1] + r1 * (b[1] - a[1]) + r2 * (c[1] - a[1]),
        ];
        (surface, p)
    }

    /// Cell range covering `[lo, hi]` along axis `axis`, clamped to the grid.
    #[inline]
    fn span(&self, lo: f32, hi: f32, axis: usize) -> (usize, usize) {
        let n = if axis == 0 { self.nx } else { self.ny };
        // Truncation is the floor for positive values; the rest clamp to cell 0.
        let cell = |v: f32| {
            let c = (v - self.origin[axis]) * self.inv_cell;
            if c > 0.0 { (c as usize).min(n - 1) } else { 0 }
        };
        (cell(lo), cell(hi))
    }

    /// The row spans `(item, row, x0, x1)` of the cells segment `a`–`b` crosses, each row's
    /// band and the segment padded by a millimetre (f32 rounding at kilometres from the
    /// origin).
    fn segment_row_spans(
        &self,
        item: usize,
        a: [f64; 2],
        b: [f64; 2],
    ) -> impl Iterator<Item = (usize, usize, usize, usize)> + '_ {
        const PAD: f64 = 1e-3;
        let (y0, y1) = self.span(
            (a[1].min(b[1]) - PAD) as f32,
            (a[1].max(b[1]) + PAD) as f32,
            1,
        );
        let cell = 1.0 / f64::from(self.inv_cell);
        let origin_y = f64::from(self.origin[1]);
        let dy = b[1] - a[1];
        (y0..=y1).map(move |y| {
            let band = (
                origin_y + y as f64 * cell - PAD,
                origin_y + (y + 1) as f64 * cell + PAD,
            );
            // The stretch of the segment inside the band (all of it when nearly flat).
            let (t0, t1) = if dy.abs() < 1e-9 {
                (0.0, 1.0)
            } else {
                let (u, v) = ((band.0 - a[1]) / dy, (band.1 - a[1]) / dy);
                (u.min(v).max(0.0), u.max(v).min(1.0))
            };
            let (t0, t1) = if t0 <= t1 { (t0, t1) } else { (0.0, 1.0) };
            let xa = a[0] + t0 * (b[0] - a[0]);
            let xb = a[0] + t1 * (b[0] - a[0]);
            let (x0, x1) = self.span((xa.min(xb) - PAD) as f32, (xa.max(xb) + PAD) as f32, 0);
            (item, y, x0, x1)
        })
    }

    /// Fills the grid with every segment's record in every cell it crosses, and
    /// every surface's id in every cell its bounding box meets.
    fn index(&mut self, cell_size: f64) {
        let b = self.bounds;
        // Plans spread over kilometres get coarser cells rather than a huge grid.
        let area = (b[2] - b[0] + 2.0 * cell_size) * (b[3] - b[1] + 2.0 * cell_size);
        let cell_size = cell_size.max((area / MAX_CELLS as f64).sqrt());
        let pad = cell_size;
        self.origin = [(b[0] - pad) as f32, (b[1] - pad) as f32];
        self.inv_cell = (1.0 / cell_size) as f32;
        self.nx = (((b[2] - b[0] + 2.0 * pad) / cell_size).ceil() as usize).max(1);
        self.ny = (((b[3] - b[1] + 2.0 * pad) / cell_size).ceil() as usize).max(1);
        let cells = self.nx * self.ny;
        // Each segment in the cells it crosses (a long diagonal wall's bounding box would be
        // most of the grid): per row, the columns of its stretch within the row's band.
        let spans: Vec<(usize, usize, usize, usize)> = self
            .segments
            .iter()
            .enumerate()
            .flat_map(|(i, s)| self.segment_row_spans(i, s.a, s.b))
            .collect();
        let records: Vec<Record> = self
            .segments
            .iter()
            .map(|s| {
                let (left, right) = match s.kind {
                    SegmentKind::Wall { surface } => (surface, NO_SURFACE),
                    SegmentKind::Connection { a, b } => (a, b),
                    SegmentKind::Barrier { level } => {
                        let k = BARRIER_FLAG | (level - self.levels.0) as u32;
                        (k, k)
                    }
                };
                Record {
                    ax: s.a[0] as f32,
                    ay: s.a[1] as f32,
                    bx: s.b[0] as f32,
                    by: s.b[1] as f32,
                    left,
                    right,
                }
            })
            .collect();
        let (offsets, items) = compress(cells, spans.iter().copied(), self.nx);
        self.offsets = offsets;
        self.records = items.into_iter().map(|i| records[i]).collect();
        let surface_spans: Vec<(usize, usize, usize, usize)> = self
            .bboxes
            .iter()
            .enumerate()
            .flat_map(|(i, b)| {
                let (x0, x1) = self.span(b[0] as f32 - 1e-3, b[2] as f32 + 1e-3, 0);
                let (y0, y1) = self.span(b[1] as f32 - 1e-3, b[3] as f32 + 1e-3, 1);
                (y0..=y1).map(move |y| (i, y, x0, x1))
            })
            .collect();
        let (offsets, items) = compress(cells, surface_spans.iter().copied(), self.nx);
        self.surface_offsets = offsets;
        self.surface_ids = items.into_iter().map(|i| i as u32).collect();
    }

    /// Triangulates every surface (ear clipping) for uniform sampling.
    fn triangulate(&mut self) {
        let mut total = 0.0;
        for (s, poly) in self.polygons.iter().enumerate() {
            for t in poly.earcut_triangles_iter() {
                let area = t.unsigned_area();
                if area <= 0.0 {
                    continue;
                }
                total += area;
                self.triangles
                    .push((s as u32, [t.v1(), t.v2(), t.v3()].map(|c| [c.x, c.y])));
                self.cumulative.push(total);
            }
        }
    }
}

/// Compressed rows: for items given as row spans `(item, row, x0, x1)` (the cells
/// `x0..=x1` of `row`), the offsets of each cell's run (row-major, `cells + 1` entries) and
/// the item indices in cell order.
fn compress(
    cells: usize,
    spans: impl Iterator<Item = (usize, usize, usize, usize)> + Clone,
    nx: usize,
) -> (Vec<u32>, Vec<usize>) {
    let mut counts = vec![0u32; cells + 1];
    for (_, y, x0, x1) in spans.clone() {
        for x in x0..=x1 {
            counts[y * nx + x + 1] += 1;
        }
    }
    for i in 1..=cells {
        counts[i] += counts[i - 1];
    }
    let mut fill = counts.clone();
    let mut items = vec![0usize; counts[cells] as usize];
    for (i, y, x0, x1) in spans {
        for x in x0..=x1 {
            let c = y * nx + x;
            items[fill[c] as usize] = i;
            fill[c] += 1;
        }
    }
    (counts, items)
}

/// Rejects a surface that is not a valid polygon, naming it.
fn check_surface(i: usize, f: &super::FloorPolygon) -> Result<()> {
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

/// One boundary edge of a surface.
#[derive(Debug, Clone, Copy)]
struct Edge {
    surface: u32,
    a: [f64; 2],
    b: [f64; 2],
}

/// Walls and connections of every surface's boundary.
fn boundary_segments(plan: &FloorPlan, config: &TopologyConfig) -> Vec<Segment> {
    let edges: Vec<Edge> = plan
        .polygons
        .iter()
        .enumerate()
        .flat_map(|(s, f)| {
            // Exterior counter-clockwise and holes clockwise: the surface lies to the left
            // of every edge.
            let mut exterior = f.polygon.exterior().clone();
            exterior.make_ccw_winding();
            let holes = f.polygon.interiors().iter().map(|h| {
                let mut h = h.clone();
                h.make_cw_winding();
                h
            });
            std::iter::once(exterior)
                .chain(holes)
                .collect::<Vec<_>>()
                .into_iter()
                .flat_map(|ring| ring.lines().collect::<Vec<_>>())
                .filter(|l| (l.end.x - l.start.x).hypot(l.end.y - l.start.y) > MIN_PIECE)
                .map(move |l| Edge {
                    surface: s as u32,
                    a: [l.start.x, l.start.y],
                    b: [l.end.x, l.end.y],
                })
        })
        .collect();
    let neighbours = EdgeGrid::new(&edges, config.connection_tolerance);
    let mut segments = Vec::new();
    let mut stamp = vec![usize::MAX; edges.len()];
    for (i, e) in edges.iter().enumerate() {
        // Parameter intervals along `e` shared with other surfaces' edges.
        let mut shared: Vec<SharedSpan> = Vec::new();
        neighbours.candidates(e, config.connection_tolerance, |j| {
            if stamp[j] == i {
                return;
            }
            stamp[j] = i;
            let f = &edges[j];
            if f.surface == e.surface {
                return;
            }
            let dz = plan.polygons[e.surface as usize].z - plan.polygons[f.surface as usize].z;
            if dz.abs() > config.max_connection_dz {
                return;
            }
            if let Some(ends) = collinear_overlap(e, f, config.connection_tolerance) {
                shared.push(SharedSpan {
                    ends,
                    surface: f.surface,
                });
            }
        });
        // Cut points: the edge's ends and the other edges' corners that fall on it, at
        // those corners' own coordinates (so the pieces meet the neighbours' edges exactly).
        let mut cuts: Vec<(f64, [f64; 2])> = vec![(0.0, e.a), (1.0, e.b)];
        cuts.extend(shared.iter().flat_map(|s| s.ends));
        cuts.sort_by(|a, b| a.0.total_cmp(&b.0));
        cuts.dedup_by(|a, b| (a.0 - b.0).abs() < 1e-12);
        let length = (e.b[0] - e.a[0]).hypot(e.b[1] - e.a[1]);
        for w in cuts.windows(2) {
            let ((t0, p0), (t1, p1)) = (w[0], w[1]);
            if (t1 - t0) * length < MIN_PIECE {
                continue;
            }
            let mid = 0.5 * (t0 + t1);
            let other = shared
                .iter()
                .filter(|s| s.ends[0].0 <= mid && mid <= s.ends[1].0)
                .map(|s| s.surface)
                .min();
            let kind = match other {
                None => SegmentKind::Wall { surface: e.surface },
                // Each connection once, from the lower-numbered surface's edge.
                Some(o) if e.surface < o => SegmentKind::Connection { a: e.surface, b: o },
                Some(_) => continue,
            };
            segments.push(Segment { a: p0, b: p1, kind });
        }
    }
    segments
}

/// A stretch of one edge shared with another surface's edge.
struct SharedSpan {
    /// Its ends: parameter along the edge and point, the lower parameter first.
    ends: [(f64, [f64; 2]); 2],
    /// The other surface.
    surface: u32,
}

/// The parameter interval of `e` over which `f` lies on `e`'s line (within `tol`), if it is
/// longer than [`MIN_PIECE`], with the points bounding it: `f`'s corners where they fall on
/// `e`, else `e`'s own ends.
fn collinear_overlap(e: &Edge, f: &Edge, tol: f64) -> Option<[(f64, [f64; 2]); 2]> {
    let (dx, dy) = (e.b[0] - e.a[0], e.b[1] - e.a[1]);
    let len2 = dx * dx + dy * dy;
    let len = len2.sqrt();
    let offset = |p: [f64; 2]| ((p[0] - e.a[0]) * dy - (p[1] - e.a[1]) * dx).abs() / len;
    if offset(f.a) > tol || offset(f.b) > tol {
        return None;
    }
    let param = |p: [f64; 2]| ((p[0] - e.a[0]) * dx + (p[1] - e.a[1]) * dy) / len2;
    let mut ends = [(param(f.a), f.a), (param(f.b), f.b)];
    ends.sort_by(|a, b| a.0.total_cmp(&b.0));
    let lo = if ends[0].0 > 0.0 { ends[0] } else { (0.0, e.a) };
    let hi = if ends[1].0 < 1.0 { ends[1] } else { (1.0, e.b) };
    ((hi.0 - lo.0) * len > MIN_PIECE).then_some([lo, hi])
}

/// Edges binned by their bounding boxes, for finding collinear neighbours.
struct EdgeGrid {
    cell: f64,
    cells: rustc_hash::FxHashMap<(i64, i64), Vec<usize>>,
}

impl EdgeGrid {
    /// Cells of about 4 m hold few edges in buildings; long edges span several.
    const CELL: f64 = 4.0;

    fn new(edges: &[Edge], tol: f64) -> Self {
        let mut grid = Self {
            cell: Self::CELL,
            cells: rustc_hash::FxHashMap::default(),
        };
        for (i, e) in edges.iter().enumerate() {
            for key in grid.keys(e, tol) {
                grid.cells.entry(key).or_default().push(i);
            }
        }
        grid
    }

    fn keys(&self, e: &Edge, tol: f64) -> impl Iterator<Item = (i64, i64)> + use<> {
        let k = |v: f64| (v / self.cell).floor() as i64;
        let (x0, x1) = (k(e.a[0].min(e.b[0]) - tol), k(e.a[0].max(e.b[0]) + tol));
        let (y0, y1) = (k(e.a[1].min(e.b[1]) - tol), k(e.a[1].max(e.b[1]) + tol));
        (x0..=x1).flat_map(move |x| (y0..=y1).map(move |y| (x, y)))
    }

    fn candidates(&self, e: &Edge, tol: f64, mut f: impl FnMut(usize)) {
        for key in self.keys(e, tol) {
            if let Some(v) = self.cells.get(&key) {
                v.iter().for_each(|&j| f(j));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::{Barrier, FloorPolygon};
    use geo::{LineString, Rect};

    fn rect(x0: f64, y0: f64, x1: f64, y1: f64, z: f64, level: i32) -> FloorPolygon {
        FloorPolygon {
            polygon: Rect::new((x0, y0), (x1, y1)).to_polygon(),
            level,
            z,
            name: None,
            room: None,
        }
    }

    /// Two 4 m rooms 0.2 m apart joined by a 1 m door rectangle filling the gap.
    fn two_rooms() -> FloorPlan {
        FloorPlan {
            polygons: vec![
                rect(0.0, 0.0, 4.0, 4.0, 0.0, 0),
                rect(4.2, 0.0, 8.2, 4.0, 0.0, 0),
                rect(4.0, 1.5, 4.2, 2.5, 0.0, 0),
            ],
            ..Default::default()
        }
    }

    fn build(plan: &FloorPlan) -> FloorTopology {
        FloorTopology::build(plan, &TopologyConfig::default()).expect("topology")
    }

    #[test]
    fn doors_connect_and_walls_block() {
        let t = build(&two_rooms());
        let connections = t
            .segments()
            .iter()
            .filter(|s| matches!(s.kind, SegmentKind::Connection { .. }))
            .count();
        assert_eq!(connections, 2);
        // Partial overlap: each room's 4 m wall is split into wall, door, wall.
        let walls = t
            .segments()
            .iter()
            .filter(|s| matches!(s.kind, SegmentKind::Wall { .. }))
            .count();
        assert_eq!(walls, 5 + 5 + 2);
        assert_eq!(t.walk(0, [3.5, 2.0], [4.7, 2.0]), Some(1));
        assert_eq!(t.walk(0, [3.5, 2.0], [4.1, 2.0]), Some(2));
        assert_eq!(t.walk(0, [3.5, 3.5], [4.7, 3.5]), None);
        assert_eq!(t.walk(0, [1.0, 1.0], [2.0, 1.5]), Some(0));
        assert_eq!(t.walk(1, [4.7, 2.0], [3.5, 2.0]), Some(0));
        // Starting on (or a hair off) a connection line never loses the crossing.
        for x in [4.0, 4.0 - 1e-6, 3.999_999_8] {
            assert_eq!(t.walk(0, [x, 2.0], [4.7, 2.0]), Some(1), "from x = {x}");
        }
        assert_eq!(t.walk(0, [4.0, 2.0], [3.0, 2.0]), Some(0));
        assert_eq!(t.walk(2, [4.0, 2.0], [4.1, 2.0]), Some(2));
        assert!((t.total_area() - (32.0 + 0.2)).abs() < 1e-9);
    }

    #[test]
    fn heights_decide_connections_and_stairs_chain() {
        // A corridor, then five treads rising 0.17 m, then a landing 1 m up.
        let mut polygons = vec![rect(0.0, 0.0, 2.0, 1.0, 0.0, 0)];
        for k in 0..5 {
            let x = 2.0 + 0.3 * f64::from(k);
            polygons.push(rect(x, 0.0, x + 0.3, 1.0, 0.17 * f64::from(k + 1), 0));
        }
        polygons.push(rect(3.5, 0.0, 5.0, 1.0, 1.0, 1));
        // Beside the landing, 1 m lower: a wall, not a connection.
        polygons.push(rect(5.0, 0.0, 6.0, 1.0, 0.0, 0));
        let t = build(&FloorPlan {
            polygons,
            ..Default::default()
        });
        let end = t.walk(0, [1.5, 0.5], [2.7, 0.5]).expect("up three treads");
        assert!((t.z(end) - 0.51).abs() < 1e-6);
        assert_eq!(t.walk(0, [1.0, 0.5], [4.0, 0.5]), Some(6));
        assert_eq!(t.walk(6, [4.5, 0.5], [5.5, 0.5]), None);
        assert_eq!(t.levels(), (0, 1));
    }

    #[test]
    fn barriers_block_their_level_only() {
        let mut plan = FloorPlan {
            polygons: vec![
                rect(0.0, 0.0, 10.0, 4.0, 0.0, 0),
                rect(0.0, 0.0, 10.0, 4.0, 3.0, 1),
            ],
            ..Default::default()
        };
        plan.barriers.push(Barrier {
            line: LineString::from(vec![(5.0, -1.0), (5.0, 5.0)]),
            level: 1,
        });
        let t = build(&plan);
        assert_eq!(t.walk(0, [4.5, 2.0], [5.5, 2.0]), Some(0));
        assert_eq!(t.walk(1, [4.5, 2.0], [5.5, 2.0]), None);
        // Stacked floors never leak into each other.
        assert_eq!(t.locate(2.0, 2.0, None, None), Some(0));
        assert_eq!(t.locate(2.0, 2.0, None, Some(2.9)), Some(1));
        assert_eq!(t.locate(2.0, 2.0, Some(1), None), Some(1));
        assert_eq!(t.locate(20.0, 2.0, None, None), None);
    }

    #[test]
    fn uniform_samples_respect_holes_and_areas() {
        let outer = Rect::new((0.0, 0.0), (10.0, 10.0)).to_polygon();
        let hole = Rect::new((2.0, 2.0), (8.0, 8.0))
            .to_polygon()
            .exterior()
            .clone();
        let plan = FloorPlan {
            polygons: vec![
                FloorPolygon {
                    polygon: geo::Polygon::new(outer.exterior().clone(), vec![hole]),
                    level: 0,
                    z: 0.0,
                    name: None,
                    room: None,
                },
                rect(20.0, 0.0, 28.0, 8.0, 0.0, 0),
            ],
            ..Default::default()
        };
        let t = build(&plan);
        let mut rng = crate::random::stream(3, 0, 0);
        let mut first = 0;
        let n = 20_000;
        for _ in 0..n {
            let (s, [x, y]) = t.sample_uniform(&mut rng);
            assert!(plan.is_walkable(x, y, Some(0)), "({x}, {y})");
            assert_eq!(t.locate(x, y, None, None), Some(s));
            first += usize::from(s == 0);
        }
        // Areas 64 and 64: half each.
        let share = first as f64 / f64::from(n);
        assert!((share - 0.5).abs() < 0.02, "{share}");
    }

    /// Random 0.7 m steps, a quarter aimed through segment corners: every step that
    /// survives ends on (or within a millimetre of) the surface it reports.
    fn leaks(plan: &FloorPlan, seed: u64) -> usize {
        use geo::{Distance, Euclidean};
        let t = build(plan);
        let mut rng = crate::random::stream(seed, 0, 0);
        let mut leaks = 0;
        for _ in 0..60_000 {
            let (s, [x, y]) = t.sample_uniform(&mut rng);
            let from = [x as f32, y as f32];
            let h: f32 = rng.random_range(0.0..std::f32::consts::TAU);
            let mut to = [from[0] + 0.7 * h.cos(), from[1] + 0.7 * h.sin()];
            if rng.random_range(0..4) == 0 {
                let seg = &t.segments()[rng.random_range(0..t.segments().len())];
                let v = [seg.a[0] as f32, seg.a[1] as f32];
                let d = (v[0] - from[0]).hypot(v[1] - from[1]);
                if d > 0.05 && d < 1.0 {
                    let k = 0.8 / d;
                    to = [
                        from[0] + k * (v[0] - from[0]),
                        from[1] + k * (v[1] - from[1]),
                    ];
                }
            }
            if let Some(end) = t.walk(s, from, to) {
                let p = geo::Point::new(f64::from(to[0]), f64::from(to[1]));
                if Euclidean.distance(&p, &plan.polygons[end as usize].polygon) > 1e-3 {
                    leaks += 1;
                }
            }
        }
        leaks
    }

    #[test]
    fn no_step_leaks_through_corners() {
        let office = crate::sim::office_floor(&Default::default()).expect("office");
        assert_eq!(leaks(&office, 1), 0);
        let tower = crate::sim::Tower::new(&Default::default()).expect("tower");
        assert_eq!(leaks(&tower.plan, 2), 0);
    }

    #[test]
    fn far_apart_surfaces_get_a_coarser_index_not_a_huge_one() {
        let plan = FloorPlan {
            polygons: vec![
                rect(0.0, 0.0, 4.0, 4.0, 0.0, 0),
                rect(50_000.0, 50_000.0, 50_004.0, 50_004.0, 0.0, 0),
            ],
            ..Default::default()
        };
        let t = build(&plan);
        assert!(t.nx * t.ny <= MAX_CELLS + 2 * (t.nx + t.ny));
        assert_eq!(t.walk(0, [1.0, 1.0], [2.0, 2.0]), Some(0));
        assert_eq!(t.walk(1, [50_001.0, 50_001.0], [50_006.0, 50_001.0]), None);
    }

    #[test]
    fn broken_plans_are_rejected_by_name() {
        let bow_tie = FloorPolygon {
            polygon: geo::Polygon::new(
                LineString::from(vec![
                    (0.0, 0.0),
                    (2.0, 2.0),
                    (2.0, 0.0),
                    (0.0, 2.0),
                    (0.0, 0.0),
                ]),
                vec![],
            ),
            level: 0,
            z: 0.0,
            name: Some("lobby".into()),
            room: None,
        };
        let plan = FloorPlan {
            polygons: vec![rect(0.0, 0.0, 1.0, 1.0, 0.0, 0), bow_tie],
            ..Default::default()
        };
        let e = FloorTopology::build(&plan, &TopologyConfig::default())
            .expect_err("bow tie")
            .to_string();
        assert!(e.contains("polygon 1") && e.contains("lobby"), "{e}");
        let nan = FloorPlan {
            polygons: vec![rect(0.0, 0.0, f64::NAN, 1.0, 0.0, 0)],
            ..Default::default()
        };
        assert!(FloorTopology::build(&nan, &TopologyConfig::default()).is_err());
        let high = FloorPlan {
            polygons: vec![rect(0.0, 0.0, 1.0, 1.0, f64::INFINITY, 0)],
            ..Default::default()
        };
        assert!(FloorTopology::build(&high, &TopologyConfig::default()).is_err());
    }

    #[test]
    fn walks_agree_with_a_brute_force_reference_on_the_office() {
        let plan = crate::sim::office_floor(&Default::default()).expect("office");
        let t = build(&plan);
        let mut rng = crate::random::stream(5, 0, 0);
        let mut checked = 0;
        for _ in 0..20_000 {
            let (s, [x, y]) = t.sample_uniform(&mut rng);
            let h = rng.random_range(0.0..std::f64::consts::TAU);
            let l = rng.random_range(0.0..1.0);
            let (tx, ty) = (x + l * h.cos(), y + l * h.sin());
            let got = t.walk(s, [x as f32, y as f32], [tx as f32, ty as f32]);
            // Reference: the step stays inside the union of walkable surfaces when every
            // point along it is walkable (office walls are 0.2 m thick, steps ≤ 1 m).
            let inside = (0..=50).all(|k| {
                let f = f64::from(k) / 50.0;
                plan.is_walkable(x + f * (tx - x), y + f * (ty - y), Some(0))
            });
            // Grazing a corner within a millimetre can go either way.
            let near_edge = (0..=50).any(|k| {
                let f = f64::from(k) / 50.0;
                let (px, py) = (x + f * (tx - x), y + f * (ty - y));
                [(0.001, 0.0), (-0.001, 0.0), (0.0, 0.001), (0.0, -0.001)]
                    .iter()
                    .any(|(dx, dy)| plan.is_walkable(px + dx, py + dy, Some(0)) != inside)
            });
            if near_edge {
                continue;
            }
            checked += 1;
            assert_eq!(got.is_some(), inside, "step ({x}, {y}) → ({tx}, {ty})");
            if let Some(end) = got {
                assert_eq!(t.locate(tx, ty, None, None).map(|_| ()), Some(()));
                let poly = &plan.polygons[end as usize].polygon;
                let p = geo::Point::new(tx, ty);
                assert!(poly.contains(&p) || poly.intersects(&p), "ends in {end}");
            }
        }
        assert!(checked > 15_000);
    }
}
