//! The grid index of a topology: a uniform grid over the plan whose cells hold the records of
//! the segments crossing them and the ids of the surfaces whose bounding boxes meet them,
//! each cell's items stored contiguously (compressed rows).
//!
//! The segment records are kept per surface and, for barriers, per level ([`CellRows`]):
//! a step on a surface reads only that surface's walls and connections and its level's
//! barriers, over the part of the grid they cover. A cell's records keep the order they
//! have in the whole plan's cell, so the walk meets the records that concern it in the
//! order of one shared grid (only the order of connections matters to it: a wall ends the
//! step wherever it is met).

use super::segments::{Segment, SegmentKind};

/// Most cells of the spatial index (the cell size grows for larger plans).
pub(super) const MAX_CELLS: usize = 1 << 22;
/// The right-hand side of a wall record: no surface.
pub(super) const NO_SURFACE: u32 = u32::MAX;
/// Barrier records carry this flag and the level's index in their surface fields.
pub(super) const BARRIER_FLAG: u32 = 1 << 31;

/// One segment as stored in a grid cell: 24 bytes.
///
/// Oriented: `left` lies to the left of the direction from `a` to `b`, `right` to its right
/// ([`NO_SURFACE`] for a wall; both the flagged level index for a barrier). Both ends are
/// stored, so segments meeting at a corner hold that corner bit for bit alike.
#[derive(Debug, Clone, Copy)]
pub(super) struct Record {
    pub(super) ax: f32,
    pub(super) ay: f32,
    pub(super) bx: f32,
    pub(super) by: f32,
    pub(super) left: u32,
    pub(super) right: u32,
}

impl Record {
    /// The record of `segment`, barriers keyed by their level's index above `lowest_level`.
    pub(super) fn of(segment: &Segment, lowest_level: i32) -> Self {
        let (left, right) = match segment.kind {
            SegmentKind::Wall { surface } => (surface, NO_SURFACE),
            SegmentKind::Connection { a, b } => (a, b),
            SegmentKind::Barrier { level } => {
                let k = BARRIER_FLAG | (level - lowest_level) as u32;
                (k, k)
            }
        };
        Self {
            ax: segment.a[0] as f32,
            ay: segment.a[1] as f32,
            bx: segment.b[0] as f32,
            by: segment.b[1] as f32,
            left,
            right,
        }
    }

    /// The surfaces the record bounds (a wall one, a connection two).
    fn surfaces(&self) -> impl Iterator<Item = u32> {
        let right = (self.right != self.left).then_some(self.right);
        [Some(self.left), right]
            .into_iter()
            .flatten()
            .filter(|&s| s < BARRIER_FLAG)
    }

    /// The level index of a barrier record (none for a wall or a connection).
    fn barrier_level(&self) -> Option<u32> {
        (self.left >= BARRIER_FLAG && self.left != NO_SURFACE).then_some(self.left & !BARRIER_FLAG)
    }
}

/// The records of one owner (a surface, or a level's barriers) over the cells
/// `x0..=x1` × `y0..=y1` of the grid that hold any (none when `x1 < x0`), in compressed
/// rows.
#[derive(Debug, Clone)]
pub(super) struct CellRows {
    pub(super) x0: usize,
    pub(super) x1: usize,
    pub(super) y0: usize,
    pub(super) y1: usize,
    offsets: Vec<u32>,
    records: Vec<Record>,
}

impl CellRows {
    /// The records of cells `x0..=x1` × `y0..=y1` (clipped to the owner's), one run per row,
    /// in order.
    #[inline]
    pub(super) fn rows(
        &self,
        (x0, x1): (usize, usize),
        (y0, y1): (usize, usize),
    ) -> impl Iterator<Item = &[Record]> {
        let (x0, x1) = (x0.max(self.x0), x1.min(self.x1));
        let (y0, y1) = (y0.max(self.y0), y1.min(self.y1));
        let width = self.x1 + 1 - self.x0;
        let ys = if x0 <= x1 { y0..y1 + 1 } else { 0..0 };
        ys.map(move |y| {
            let row = (y - self.y0) * width;
            let (a, b) = (row + x0 - self.x0, row + x1 + 1 - self.x0);
            &self.records[self.offsets[a] as usize..self.offsets[b] as usize]
        })
    }
}

/// The grid: origin, reciprocal cell size, dimensions, and each level's records.
#[derive(Debug, Clone)]
pub(super) struct SegmentGrid {
    pub(super) origin: [f32; 2],
    pub(super) inv_cell: f32,
    pub(super) nx: usize,
    pub(super) ny: usize,
    /// The walls and connections of each surface.
    pub(super) surfaces: Vec<CellRows>,
    /// The barriers of each level, by level − the lowest level.
    pub(super) barriers: Vec<CellRows>,
    /// Surfaces whose bounding box meets each cell (for `locate`).
    surface_offsets: Vec<u32>,
    surface_ids: Vec<u32>,
}

impl SegmentGrid {
    /// The grid over `bounds` (min x, min y, max x, max y) with every segment's record in
    /// every cell it crosses (in the rows of each surface it bounds, or of its level for a
    /// barrier; `levels`: the lowest and highest), and every surface's id in every cell its
    /// bounding box (`bboxes`, one a surface) meets; barriers are keyed by their level's
    /// index above the lowest level.
    pub(super) fn build(
        segments: &[Segment],
        bboxes: &[[f64; 4]],
        bounds: [f64; 4],
        levels: (i32, i32),
        cell_size: f64,
    ) -> Self {
        let lowest_level = levels.0;
        let b = bounds;
        // Plans spread over kilometres get coarser cells rather than a huge grid.
        let area = (b[2] - b[0] + 2.0 * cell_size) * (b[3] - b[1] + 2.0 * cell_size);
        let cell_size = cell_size.max((area / MAX_CELLS as f64).sqrt());
        let pad = cell_size;
        let mut grid = Self {
            origin: [(b[0] - pad) as f32, (b[1] - pad) as f32],
            inv_cell: (1.0 / cell_size) as f32,
            nx: (((b[2] - b[0] + 2.0 * pad) / cell_size).ceil() as usize).max(1),
            ny: (((b[3] - b[1] + 2.0 * pad) / cell_size).ceil() as usize).max(1),
            surfaces: Vec::new(),
            barriers: Vec::new(),
            surface_offsets: Vec::new(),
            surface_ids: Vec::new(),
        };
        let cells = grid.nx * grid.ny;
        // Each segment in the cells it crosses (a long diagonal wall's bounding box would be
        // most of the grid): per row, the columns of its stretch within the row's band.
        let spans: Vec<(usize, usize, usize, usize)> = segments
            .iter()
            .enumerate()
            .flat_map(|(i, s)| grid.segment_row_spans(i, s.a, s.b))
            .collect();
        let records: Vec<Record> = segments
            .iter()
            .map(|s| Record::of(s, lowest_level))
            .collect();
        let (offsets, items) = compress(cells, spans.iter().copied(), grid.nx);
        let records: Vec<Record> = items.into_iter().map(|i| records[i]).collect();
        let count = (levels.1 - levels.0) as usize + 1;
        grid.surfaces = grid.owned_rows(&offsets, &records, bboxes.len(), |r, f| {
            r.surfaces().for_each(f);
        });
        grid.barriers = grid.owned_rows(&offsets, &records, count, |r, f| {
            r.barrier_level().into_iter().for_each(f);
        });
        let surface_spans: Vec<(usize, usize, usize, usize)> = bboxes
            .iter()
            .enumerate()
            .flat_map(|(i, b)| {
                let (x0, x1) = grid.span(b[0] as f32 - 1e-3, b[2] as f32 + 1e-3, 0);
                let (y0, y1) = grid.span(b[1] as f32 - 1e-3, b[3] as f32 + 1e-3, 1);
                (y0..=y1).map(move |y| (i, y, x0, x1))
            })
            .collect();
        let (offsets, items) = compress(cells, surface_spans.iter().copied(), grid.nx);
        grid.surface_offsets = offsets;
        grid.surface_ids = items.into_iter().map(|i| i as u32).collect();
        grid
    }

    /// The records of the whole plan's cells (`offsets`, `records`) split by owner
    /// (`owners_of` calls its argument with each owner of a record, below `owners`): each
    /// owner's over the cells that hold any, each cell's in their order.
    fn owned_rows(
        &self,
        offsets: &[u32],
        records: &[Record],
        owners: usize,
        owners_of: impl Fn(&Record, &mut dyn FnMut(u32)),
    ) -> Vec<CellRows> {
        let cell = |c: usize| &records[offsets[c] as usize..offsets[c + 1] as usize];
        let mut rows: Vec<CellRows> = (0..owners)
            .map(|_| CellRows {
                x0: usize::MAX,
                x1: 0,
                y0: usize::MAX,
                y1: 0,
                offsets: Vec::new(),
                records: Vec::new(),
            })
            .collect();
        for c in 0..self.nx * self.ny {
            let (x, y) = (c % self.nx, c / self.nx);
            for r in cell(c) {
                owners_of(r, &mut |o| {
                    let o = &mut rows[o as usize];
                    (o.x0, o.x1, o.y0, o.y1) = (o.x0.min(x), o.x1.max(x), o.y0.min(y), o.y1.max(y));
                });
            }
        }
        for (owner, o) in rows.iter_mut().enumerate() {
            if o.x0 > o.x1 {
                (o.x0, o.x1, o.y0, o.y1) = (1, 0, 1, 0);
                o.offsets.push(0);
                continue;
            }
            for y in o.y0..=o.y1 {
                for x in o.x0..=o.x1 {
                    o.offsets.push(o.records.len() as u32);
                    for r in cell(y * self.nx + x) {
                        let mut own = false;
                        owners_of(r, &mut |k| own |= k as usize == owner);
                        if own {
                            o.records.push(*r);
                        }
                    }
                }
            }
            o.offsets.push(o.records.len() as u32);
        }
        rows
    }

    /// The cell holding `(x, y)` (`j · nx + i`; a point off the grid is clamped to it).
    #[inline]
    pub(super) fn cell_of(&self, x: f64, y: f64) -> usize {
        let (ix0, _) = self.span(x as f32, x as f32, 0);
        let (iy0, _) = self.span(y as f32, y as f32, 1);
        iy0 * self.nx + ix0
    }

    /// The surfaces whose bounding box meets cell `cell`.
    #[inline]
    pub(super) fn surfaces_in(&self, cell: usize) -> &[u32] {
        &self.surface_ids
            [self.surface_offsets[cell] as usize..self.surface_offsets[cell + 1] as usize]
    }

    /// Cell range covering `[lo, hi]` along axis `axis`, clamped to the grid.
    #[inline]
    pub(super) fn span(&self, lo: f32, hi: f32, axis: usize) -> (usize, usize) {
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
        (y0..=y1).map(move |y| {
            let band = (
                origin_y + y as f64 * cell - PAD,
                origin_y + (y + 1) as f64 * cell + PAD,
            );
            let (xa, xb) = stretch_in_band(a, b, band);
            let (x0, x1) = self.span((xa - PAD) as f32, (xb + PAD) as f32, 0);
            (item, y, x0, x1)
        })
    }
}

/// The least and greatest `x` of the stretch of segment `a`–`b` between heights `band.0`
/// and `band.1` (of all of it when it is nearly flat or misses the band).
pub(super) fn stretch_in_band(a: [f64; 2], b: [f64; 2], band: (f64, f64)) -> (f64, f64) {
    let dy = b[1] - a[1];
    let (t0, t1) = if dy.abs() < 1e-9 {
        (0.0, 1.0)
    } else {
        let (u, v) = ((band.0 - a[1]) / dy, (band.1 - a[1]) / dy);
        (u.min(v).max(0.0), u.max(v).min(1.0))
    };
    let (t0, t1) = if t0 <= t1 { (t0, t1) } else { (0.0, 1.0) };
    let xa = a[0] + t0 * (b[0] - a[0]);
    let xb = a[0] + t1 * (b[0] - a[0]);
    (xa.min(xb), xa.max(xb))
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
