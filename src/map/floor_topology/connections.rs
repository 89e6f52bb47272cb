//! Connection finding: the stretches of each surface's boundary edges that another
//! surface's edges share — collinear in the plane within
//! [`TopologyConfig::connection_tolerance`], the two surfaces' heights within
//! [`TopologyConfig::max_connection_dz`] — with the edges binned in a coarse grid so that only
//! neighbours are compared.

use super::config::TopologyConfig;
use crate::map::floor_plan::FloorPlan;
use geo::Winding;

/// Edge pieces shorter than this are dropped, metres.
pub(super) const MIN_PIECE: f64 = 1e-4;

/// One boundary edge of a surface.
#[derive(Debug, Clone, Copy)]
pub(super) struct Edge {
    /// The surface, to the edge's left.
    pub(super) surface: u32,
    /// Where the edge starts.
    pub(super) a: [f64; 2],
    /// Where it ends.
    pub(super) b: [f64; 2],
}

/// Every surface's boundary edges, oriented so that the surface lies to the left of each,
/// pieces no longer than [`MIN_PIECE`] left out.
pub(super) fn surface_edges(plan: &FloorPlan) -> Vec<Edge> {
    plan.polygons
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
        .collect()
}

/// A stretch of one edge shared with another surface's edge.
pub(super) struct SharedSpan {
    /// Its ends: parameter along the edge and point, the lower parameter first.
    pub(super) ends: [(f64, [f64; 2]); 2],
    /// The other surface.
    pub(super) surface: u32,
}

/// Finds, edge by edge, the stretches of it that other surfaces' edges share.
pub(super) struct SharedEdges<'a> {
    edges: &'a [Edge],
    neighbours: EdgeGrid,
    /// The edge that last tested each edge (a candidate in several cells is tested once).
    stamp: Vec<usize>,
}

impl<'a> SharedEdges<'a> {
    /// The finder over `edges`.
    pub(super) fn new(edges: &'a [Edge], config: &TopologyConfig) -> Self {
        Self {
            edges,
            neighbours: EdgeGrid::new(edges, config.connection_tolerance),
            stamp: vec![usize::MAX; edges.len()],
        }
    }

    /// Parameter intervals along edge `i` shared with other surfaces' edges: collinear
    /// within the tolerance, the surfaces' heights within `max_connection_dz`.
    pub(super) fn of(
        &mut self,
        i: usize,
        plan: &FloorPlan,
        config: &TopologyConfig,
    ) -> Vec<SharedSpan> {
        let Self {
            edges,
            neighbours,
            stamp,
        } = self;
        let e = &edges[i];
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
        shared
    }
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
