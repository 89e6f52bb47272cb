//! Which surface holds a point without a point-in-polygon test where the answer is known in
//! advance: a grid cell that no candidate surface's boundary comes near lies wholly inside
//! or wholly outside each candidate, so the surfaces holding any point of it are fixed when
//! the topology is built.
//!
//! A tracker drawing a known start's prior locates every particle, hundreds of thousands
//! per walk, mostly in a mall's corridor polygon of hundreds of corners: each test walks
//! its whole ring. Here most points cost a grid lookup, and only points in cells that a
//! candidate's boundary crosses are tested against the polygons, exactly as before: the
//! answer is the same for every point ([`FloorTopology::locate`](super::FloorTopology::locate)).
//!
//! The cells are the segment grid's (the cell a point maps to there), each taken as the
//! square `origin + (i, j) · cell`, in `f64`. A boundary segment marks every cell whose
//! square it passes within a millimetre of; a point is answered from the index only when
//! it lies inside its cell's square (a point off the grid, clamped to an edge cell, is
//! tested).

use super::grid::{SegmentGrid, stretch_in_band};

/// Segments closer than this to a cell's square mark it as crossed, metres.
const MARGIN: f64 = 1e-3;

/// The surfaces holding the points of each cell no candidate's boundary crosses.
#[derive(Debug, Clone)]
pub(super) struct LocateIndex {
    origin: [f64; 2],
    cell: f64,
    nx: usize,
    /// One bit per cell: its answer is in `inside`.
    known: Vec<u64>,
    /// Per cell, its run of `inside` (compressed rows, `cells + 1` entries).
    offsets: Vec<u32>,
    /// The candidates holding the whole cell.
    inside: Vec<u32>,
}

impl LocateIndex {
    /// The index of `polygons` over `grid`'s cells and candidates.
    pub(super) fn build(grid: &SegmentGrid, polygons: &[geo::Polygon<f64>]) -> Self {
        let origin = [f64::from(grid.origin[0]), f64::from(grid.origin[1])];
        let cell = 1.0 / f64::from(grid.inv_cell);
        let (nx, ny) = (grid.nx, grid.ny);
        // (cell, surface) for every cell a surface's boundary crosses.
        let mut crossed: Vec<(u32, u32)> = Vec::new();
        for (s, polygon) in polygons.iter().enumerate() {
            for line in rings(polygon).flat_map(geo::LineString::lines) {
                let (a, b) = ([line.start.x, line.start.y], [line.end.x, line.end.y]);
                for_each_cell_near(a, b, (origin, cell, nx, ny), |c| {
                    crossed.push((c as u32, s as u32));
                });
            }
        }
        crossed.sort_unstable();
        crossed.dedup();
        let mut known = vec![0u64; (nx * ny).div_ceil(64)];
        let mut offsets = Vec::with_capacity(nx * ny + 1);
        let mut inside = Vec::new();
        // Per row, each polygon's crossings of the row's centre line, sorted (parity).
        let mut crossings: Vec<Option<Vec<f64>>> = vec![None; polygons.len()];
        let mut next_crossed = 0;
        for j in 0..ny {
            crossings.iter_mut().for_each(|c| *c = None);
            let yc = origin[1] + (j as f64 + 0.5) * cell;
            for i in 0..nx {
                let c = j * nx + i;
                offsets.push(inside.len() as u32);
                let start = next_crossed;
                while next_crossed < crossed.len() && crossed[next_crossed].0 as usize == c {
                    next_crossed += 1;
                }
                let here = &crossed[start..next_crossed];
                let candidates = grid.surfaces_in(c);
                if candidates
                    .iter()
                    .any(|&s| here.binary_search(&(c as u32, s)).is_ok())
                {
                    continue;
                }
                // No candidate's boundary comes near the cell: its centre says for all of it.
                let xc = origin[0] + (i as f64 + 0.5) * cell;
                for &s in candidates {
                    let xs = crossings[s as usize]
                        .get_or_insert_with(|| row_crossings(&polygons[s as usize], yc));
                    if xs.partition_point(|&x| x < xc) % 2 == 1 {
                        inside.push(s);
                    }
                }
                known[c / 64] |= 1 << (c % 64);
            }
        }
        offsets.push(inside.len() as u32);
        Self {
            origin,
            cell,
            nx,
            known,
            offsets,
            inside,
        }
    }

    /// The surfaces holding `(x, y)`, which the grid puts in cell `c`: `None` where a
    /// candidate's boundary crosses the cell or the point is off its square (test them).
    #[inline]
    pub(super) fn inside(&self, c: usize, x: f64, y: f64) -> Option<&[u32]> {
        if self.known[c / 64] & (1 << (c % 64)) == 0 {
            return None;
        }
        let (i, j) = ((c % self.nx) as f64, (c / self.nx) as f64);
        let x0 = self.origin[0] + i * self.cell;
        let y0 = self.origin[1] + j * self.cell;
        let on_square = x >= x0 && x <= x0 + self.cell && y >= y0 && y <= y0 + self.cell;
        on_square.then(|| &self.inside[self.offsets[c] as usize..self.offsets[c + 1] as usize])
    }
}

/// A polygon's rings: the exterior, then its holes.
fn rings(polygon: &geo::Polygon<f64>) -> impl Iterator<Item = &geo::LineString<f64>> {
    std::iter::once(polygon.exterior()).chain(polygon.interiors())
}

/// The sorted `x` where `polygon`'s rings cross the line at height `y` (each edge counted
/// when its ends lie on either side, the lower end included: a corner on the line counts
/// once or twice as the ring passes through or touches it, so the parity holds).
fn row_crossings(polygon: &geo::Polygon<f64>, y: f64) -> Vec<f64> {
    let mut xs: Vec<f64> = rings(polygon)
        .flat_map(geo::LineString::lines)
        .filter(|l| (l.start.y <= y) != (l.end.y <= y))
        .map(|l| l.start.x + (y - l.start.y) / (l.end.y - l.start.y) * (l.end.x - l.start.x))
        .collect();
    xs.sort_unstable_by(f64::total_cmp);
    xs
}

/// Calls `f` with every cell (`j · nx + i`) whose square segment `a`–`b` passes within
/// [`MARGIN`] of (and a few more: each row's stretch is taken whole), over the grid
/// `(origin, cell, nx, ny)`.
fn for_each_cell_near(
    a: [f64; 2],
    b: [f64; 2],
    (origin, cell, nx, ny): ([f64; 2], f64, usize, usize),
    mut f: impl FnMut(usize),
) {
    let index = |v: f64, o: f64, n: usize| {
        let k = ((v - o) / cell).floor();
        if k <= 0.0 { 0 } else { (k as usize).min(n - 1) }
    };
    let (j0, j1) = (
        index(a[1].min(b[1]) - MARGIN, origin[1], ny),
        index(a[1].max(b[1]) + MARGIN, origin[1], ny),
    );
    for j in j0..=j1 {
        let band = (
            origin[1] + j as f64 * cell - MARGIN,
            origin[1] + (j + 1) as f64 * cell + MARGIN,
        );
        let (xa, xb) = stretch_in_band(a, b, band);
        let i0 = index(xa - MARGIN, origin[0], nx);
        let i1 = index(xb + MARGIN, origin[0], nx);
        for i in i0..=i1 {
            f(j * nx + i);
        }
    }
}
