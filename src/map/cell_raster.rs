//! Which radio-map cell holds a point, in O(1): the cells' polygons (any shapes, from this
//! crate's [`super::CellMap`] or another tool's map) rasterised once per level on a fine grid,
//! since every particle looks up its cell at every step of RF-assisted localisation.
//!
//! A grid square belongs to the first cell whose floor contains (or touches) its centre; a
//! point of no cell (outside the map, or in a sliver between cells narrower than the grid)
//! has none. [`CellField`] puts one value on every cell of a raster, such as a measurement's
//! log-weight.

use super::radio_map::RadioMap;
use crate::error::{Error, Result};
use geo::{BoundingRect, Coord, Intersects, Point, Rect};
use std::sync::Arc;

/// Marks grid squares of no cell.
const NONE: u32 = u32::MAX;

/// The cell of every grid square of every level.
#[derive(Debug, Clone, PartialEq)]
pub struct CellRaster {
    /// West and south edges of the grid, metres.
    origin: [f64; 2],
    /// Side of a grid square, metres.
    resolution: f64,
    nx: usize,
    ny: usize,
    /// Lowest and highest level.
    levels: (i32, i32),
    /// Cell index per square, level by level, row by row.
    squares: Vec<u32>,
    /// Cells of the map.
    cells: usize,
}

impl CellRaster {
    /// Rasterises `map`'s cells over `bounds` (min x, min y, max x, max y, local metres) for
    /// levels `levels.0..=levels.1` with squares of `resolution` metres. Cells on other
    /// levels or outside the bounds are left out.
    ///
    /// # Errors
    ///
    /// - [`Error::InvalidData`] when `resolution` is not a positive number, a bound is not finite,
    ///   or the bounds or levels are reversed.
    /// - [`Error::TooLarge`] beyond 2³⁰ squares over all levels.
    /// - [`Error::Mismatch`] when no square falls in a cell: a map of another building, or in
    ///   another frame.
    pub fn build(
        map: &RadioMap,
        bounds: [f64; 4],
        levels: (i32, i32),
        resolution: f64,
    ) -> Result<Self> {
        if !(resolution.is_finite() && resolution > 0.0)
            || bounds.iter().any(|b| !b.is_finite())
            || bounds[2] < bounds[0]
            || bounds[3] < bounds[1]
            || levels.1 < levels.0
        {
            return Err(Error::invalid(
                "a radio-map raster",
                format!(
                    "bounds {bounds:?}, levels {levels:?} at {resolution} m are not a valid extent"
                ),
            ));
        }
        let nx = ((bounds[2] - bounds[0]) / resolution).ceil() as usize + 1;
        let ny = ((bounds[3] - bounds[1]) / resolution).ceil() as usize + 1;
        let n_levels = (levels.1 - levels.0 + 1) as usize;
        let size = nx
            .checked_mul(ny)
            .and_then(|s| s.checked_mul(n_levels))
            .filter(|&s| s <= 1 << 30)
            .ok_or_else(|| {
                Error::too_large(
                    format!("a {resolution} m raster of the radio map"),
                    format!("{nx} × {ny} squares on {n_levels} levels"),
                    "2³⁰ squares",
                    "",
                )
            })?;
        let mut squares = vec![NONE; size];
        let mut placed = 0usize;
        // First every square whose centre is in a cell; then the squares along the cells'
        // edges that a cell only partly covers, so that no point of a cell falls in no cell
        // (a point of no cell takes the field's `elsewhere` value: inside every region).
        for partial in [false, true] {
            for (c, cell) in map.cells.iter().enumerate() {
                if cell.level < levels.0 || cell.level > levels.1 {
                    continue;
                }
                let Some(b) = cell.area.bounding_rect() else {
                    continue;
                };
                let li = (cell.level - levels.0) as usize;
                let index = |v: f64, lo: f64, n: usize| {
                    (((v - lo) / resolution).floor().max(0.0) as usize).min(n - 1)
                };
                let (i0, i1) = (
                    index(b.min().x, bounds[0], nx),
                    index(b.max().x, bounds[0], nx),
                );
                let (j0, j1) = (
                    index(b.min().y, bounds[1], ny),
                    index(b.max().y, bounds[1], ny),
                );
                for j in j0..=j1 {
                    for i in i0..=i1 {
                        let k = (li * ny + j) * nx + i;
                        if squares[k] != NONE {
                            continue;
                        }
                        let (x, y) = (
                            bounds[0] + i as f64 * resolution,
                            bounds[1] + j as f64 * resolution,
                        );
                        let inside = if partial {
                            cell.area.intersects(&Rect::new(
                                Coord { x, y },
                                Coord {
                                    x: x + resolution,
                                    y: y + resolution,
                                },
                            ))
                        } else {
                            cell.area
                                .intersects(&Point::new(x + 0.5 * resolution, y + 0.5 * resolution))
                        };
                        if inside {
                            squares[k] = c as u32;
                            placed += 1;
                        }
                    }
                }
            }
        }
        if placed == 0 {
            return Err(Error::mismatch(
                "no radio-map cell lies on the floor plan",
                "a map of another building, or another origin? Use the plan the map was surveyed on",
            ));
        }
        Ok(Self {
            origin: [bounds[0], bounds[1]],
            resolution,
            nx,
            ny,
            levels,
            squares,
            cells: map.cells.len(),
        })
    }

    /// [`Self::build`] over the whole of `topology`'s plan: its bounds and levels.
    ///
    /// # Errors
    ///
    /// As [`Self::build`]: `resolution` not a positive number, a raster beyond 2³⁰ squares, or no
    /// cell of `map` on the plan.
    pub fn on_plan(
        map: &RadioMap,
        topology: &super::FloorTopology,
        resolution: f64,
    ) -> Result<Self> {
        Self::build(map, topology.bounds(), topology.levels(), resolution)
    }

    /// Number of cells of the map rasterised.
    #[must_use]
    pub fn cells(&self) -> usize {
        self.cells
    }

    /// The cell holding `(x, y)` on `level`, if any.
    #[inline]
    #[must_use]
    pub fn cell_at(&self, level: i32, x: f32, y: f32) -> Option<usize> {
        if level < self.levels.0 || level > self.levels.1 {
            return None;
        }
        let fx = (f64::from(x) - self.origin[0]) / self.resolution;
        let fy = (f64::from(y) - self.origin[1]) / self.resolution;
        if !(fx >= 0.0 && fy >= 0.0) {
            return None;
        }
        let (i, j) = (fx as usize, fy as usize);
        if i >= self.nx || j >= self.ny {
            return None;
        }
        let li = (level - self.levels.0) as usize;
        let c = self.squares[(li * self.ny + j) * self.nx + i];
        (c != NONE).then_some(c as usize)
    }
}

impl CellRaster {
    /// For every cell, the nearest `source` cell along the floor and the mean walking
    /// distance of the cell's squares to it (0 for a source's own squares), metres; `None`
    /// for cells with no square within `max_m` of a source (or with no square). Distances
    /// run between the centres of squares that belong to a cell, 8-connected (Dijkstra on
    /// the grid), so they follow the floor round walls and never cross levels.
    #[must_use]
    pub fn walking_reach(&self, sources: &[bool], max_m: f64) -> Vec<Option<(usize, f64)>> {
        use std::cmp::Reverse;
        use std::collections::BinaryHeap;
        let (nx, ny) = (self.nx, self.ny);
        let per_level = nx * ny;
        let mut dist = vec![f32::INFINITY; self.squares.len()];
        let mut from = vec![NONE; self.squares.len()];
        // Distances in grid squares, as integers of 1/1000 of a square for the heap.
        let scale = 1000.0;
        let limit = (max_m / self.resolution * scale) as u64;
        let mut heap = BinaryHeap::new();
        for (i, &c) in self.squares.iter().enumerate() {
            if c != NONE && sources.get(c as usize).copied().unwrap_or(false) {
                dist[i] = 0.0;
                from[i] = c;
                heap.push(Reverse((0u64, i)));
            }
        }
        const MOVES: [(isize, isize, u64); 8] = [
            (1, 0, 1000),
            (-1, 0, 1000),
            (0, 1, 1000),
            (0, -1, 1000),
            (1, 1, 1414),
            (1, -1, 1414),
            (-1, 1, 1414),
            (-1, -1, 1414),
        ];
        while let Some(Reverse((d, i))) = heap.pop() {
            if d as f32 > dist[i] * scale as f32 + 0.5 {
                continue;
            }
            let (level_base, within) = (i / per_level * per_level, i % per_level);
            let (x, y) = (within % nx, within / nx);
            for (dx, dy, cost) in MOVES {
                let (Some(x2), Some(y2)) = (x.checked_add_signed(dx), y.checked_add_signed(dy))
                else {
                    continue;
                };
                if x2 >= nx || y2 >= ny {
                    continue;
                }
                let j = level_base + y2 * nx + x2;
                if self.squares[j] == NONE {
                    continue;
                }
                // A diagonal move may not cut a corner of the floor.
                if dx != 0 && dy != 0 {
                    let a = level_base + y * nx + x2;
                    let b = level_base + y2 * nx + x;
                    if self.squares[a] == NONE || self.squares[b] == NONE {
                        continue;
                    }
                }
                let nd = d + cost;
                if nd <= limit && (nd as f32) < dist[j] * scale as f32 {
                    dist[j] = nd as f32 / scale as f32;
                    from[j] = from[i];
                    heap.push(Reverse((nd, j)));
                }
            }
        }
        // Per cell: its squares' mean distance and the source nearest its nearest square.
        let mut sum = vec![0.0f64; self.cells];
        let mut count = vec![0u32; self.cells];
        let mut reached = vec![0u32; self.cells];
        let mut best: Vec<(f32, u32)> = vec![(f32::INFINITY, NONE); self.cells];
        for (i, &c) in self.squares.iter().enumerate() {
            if c == NONE {
                continue;
            }
            let c = c as usize;
            count[c] += 1;
            if dist[i].is_finite() {
                reached[c] += 1;
                sum[c] += f64::from(dist[i]);
                if dist[i] < best[c].0 {
                    best[c] = (dist[i], from[i]);
                }
            }
        }
        (0..self.cells)
            .map(|c| {
                // Most of the cell's floor must be within reach.
                (count[c] > 0 && 2 * reached[c] > count[c]).then(|| {
                    (
                        best[c].1 as usize,
                        sum[c] / f64::from(reached[c]) * self.resolution,
                    )
                })
            })
            .collect()
    }
}

/// One value per cell of a raster (e.g. a measurement's log-weight), with a value for points
/// of no cell.
#[derive(Debug, Clone, PartialEq)]
pub struct CellField {
    raster: Arc<CellRaster>,
    values: Vec<f32>,
    elsewhere: f32,
}

impl CellField {
    /// `values[c]` on cell `c`, `elsewhere` off every cell (and on cells past the end of
    /// `values`; values past the raster's cells are dropped).
    #[must_use]
    pub fn new(raster: Arc<CellRaster>, mut values: Vec<f32>, elsewhere: f32) -> Self {
        values.resize(raster.cells(), elsewhere);
        Self {
            raster,
            values,
            elsewhere,
        }
    }

    /// The value at `(x, y)` on `level`.
    #[inline]
    #[must_use]
    pub fn at(&self, level: i32, x: f32, y: f32) -> f32 {
        self.raster
            .cell_at(level, x, y)
            .map_or(self.elsewhere, |c| self.values[c])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::{CellRadio, RadioMapCell};
    use geo::{MultiPolygon, Rect};

    fn cell(id: &str, level: i32, r: Rect<f64>) -> RadioMapCell {
        RadioMapCell {
            id: id.into(),
            level,
            area: MultiPolygon::new(vec![r.to_polygon()]),
            radio: CellRadio::default(),
        }
    }

    #[test]
    fn points_find_their_cell_on_their_level() {
        let map = RadioMap {
            cells: vec![
                cell("a", 0, Rect::new((0.0, 0.0), (3.0, 2.0))),
                cell("b", 0, Rect::new((3.0, 0.0), (6.0, 2.0))),
                cell("c", 1, Rect::new((0.0, 0.0), (6.0, 2.0))),
                cell("far", 5, Rect::new((0.0, 0.0), (6.0, 2.0))),
            ],
            ..Default::default()
        };
        let r = CellRaster::build(&map, [0.0, 0.0, 6.0, 2.0], (0, 1), 0.25).expect("raster");
        assert_eq!(r.cell_at(0, 1.0, 1.0), Some(0));
        assert_eq!(r.cell_at(0, 4.0, 1.9), Some(1));
        assert_eq!(r.cell_at(1, 4.0, 1.0), Some(2));
        assert_eq!(r.cell_at(2, 1.0, 1.0), None);
        assert_eq!(r.cell_at(0, -1.0, 1.0), None);
        assert_eq!(r.cell_at(0, 1.0, 7.0), None);
        let field = CellField::new(Arc::new(r), vec![1.0, 2.0], -1.0);
        assert_eq!(field.at(0, 4.0, 1.0), 2.0);
        assert_eq!(field.at(1, 4.0, 1.0), -1.0);
        assert_eq!(field.at(3, 4.0, 1.0), -1.0);
        let elsewhere = RadioMap {
            cells: vec![cell("x", 0, Rect::new((100.0, 100.0), (103.0, 102.0)))],
            ..Default::default()
        };
        assert!(CellRaster::build(&elsewhere, [0.0, 0.0, 6.0, 2.0], (0, 1), 0.25).is_err());
    }

    #[test]
    fn every_point_of_a_cell_off_the_grid_finds_a_cell() {
        // Edges at 0.1 and 2.9 m: the squares along them have their centres outside.
        let map = RadioMap {
            cells: vec![
                cell("a", 0, Rect::new((0.1, 0.1), (2.9, 1.9))),
                cell("b", 0, Rect::new((3.1, 0.1), (5.9, 1.9))),
            ],
            ..Default::default()
        };
        let r = CellRaster::build(&map, [0.0, 0.0, 6.0, 2.0], (0, 0), 0.25).expect("raster");
        for i in 0..=280 {
            let x = 0.1 + 0.01 * i as f32;
            assert_eq!(r.cell_at(0, x, 0.11), Some(0), "x = {x}");
            assert_eq!(r.cell_at(0, x + 3.0, 1.89), Some(1), "x = {x}");
        }
        // In the gap between them, a point takes the cell of its square.
        assert_eq!(r.cell_at(0, 2.95, 1.0), Some(0));
        assert_eq!(r.cell_at(0, 3.05, 1.0), Some(1));
        assert_eq!(r.cell_at(0, 1.0, 1.99), Some(0));
    }

    #[test]
    fn walking_reach_goes_round_walls_and_stays_on_its_level() {
        // A U: cells a (west arm) and c (east arm) 1 m apart across a wall, joined by b
        // along the south; d on another level over a.
        let map = RadioMap {
            cells: vec![
                cell("a", 0, Rect::new((0.0, 2.0), (2.0, 10.0))),
                cell("b", 0, Rect::new((0.0, 0.0), (5.0, 2.0))),
                cell("c", 0, Rect::new((3.0, 2.0), (5.0, 10.0))),
                cell("d", 1, Rect::new((0.0, 2.0), (2.0, 10.0))),
            ],
            ..Default::default()
        };
        let r = CellRaster::build(&map, [0.0, 0.0, 5.0, 10.0], (0, 1), 0.25).expect("raster");
        let reach = r.walking_reach(&[true, false, false, false], 100.0);
        assert_eq!(reach[0], Some((0, 0.0)));
        let (from_b, b) = reach[1].expect("b reached");
        assert_eq!(from_b, 0);
        assert!(b > 1.0 && b < 3.0, "b {b}");
        // c's squares lie 1 m from a across the wall, but a walk goes round through b.
        let (_, c) = reach[2].expect("c reached");
        assert!(c > 5.0, "c {c}: the wall is not crossed");
        assert_eq!(reach[3], None, "another level is never reached");
        // Within 3 m of a: b's floor is mostly within reach, c's is not.
        let near = r.walking_reach(&[true, false, false, false], 3.0);
        assert!(near[1].is_some() && near[2].is_none());
    }
}
