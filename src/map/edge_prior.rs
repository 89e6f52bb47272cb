//! The Dirichlet prior `α^e_h` of every hexagon edge (Robertson et al. 2009, eq. 6), shared
//! read-only by all particles.
//!
//! The paper uses one `α` for every edge. Two kinds of knowledge make it vary per edge:
//!
//! * **A rough building outline** (sec. 4.2: the outer walls known only roughly). Every edge
//!   joining a hexagon whose centre is inside the outline to one whose centre is outside
//!   gets a low prior `α_out` instead of `α`. Crossing the outline is then improbable but
//!   possible: an unseen crossing weighs `α_out / (N_h + Σα)` instead of `α / (N_h + 6α)`,
//!   and once crossed (a door, unknown beforehand) the count `N^e_h` takes over as for any
//!   edge. Because the outline is known only to a few metres, the penalty is a soft one
//!   paid once per place; a hard wall would kill the true path wherever the outline is off.
//! * **Maps learned on earlier walks** (sec. 4.3, map combination). Their counts become
//!   pseudo-counts: `α^e_h = α + w · N^e_h(prior)`, with a user-set weight `w`. Eq. (6) then
//!   reads `(N^e_h + α^e_h) / (N_h + Σ_e α^e_h)`, the posterior predictive of a Dirichlet
//!   whose prior is the earlier walks' posterior.
//!
//! Edges are shared by two hexagons, so every value is stored for both sides. Hexagons not
//! in the table have `α` on every edge.

use super::hex_transitions::{HexMapSnapshot, level_key};
use crate::geometry::HexGrid;
use geo::{Contains, Coord, Polygon};
use hexx::Hex;
use rustc_hash::{FxHashMap, FxHashSet};

/// Per-edge Dirichlet priors, `α` everywhere but where an outline or a prior map says more.
///
/// An earlier walk's counts as pseudo-counts, and a rough outline as a soft wall:
///
/// ```
/// use footslam::geometry::{Hex, HexGrid, Pose2};
/// use footslam::map::{EdgePrior, map_of_path};
///
/// // The map of an earlier walk: 5 m east along y = 0.
/// let path: Vec<Pose2> = (1..=5).map(|i| Pose2::new(f64::from(i), 0.0, 0.0)).collect();
/// let earlier = map_of_path(Pose2::default(), &path, &[0; 5], 0.5, 0.8);
///
/// // α + w·N on the edges it crossed, α elsewhere.
/// let mut prior = EdgePrior::uniform(0.8);
/// assert_eq!(prior.add_counts(&earlier, 0.5), 6);
/// assert!((prior.alpha(Hex::ZERO, 0) - (0.8 + 0.5)).abs() < 1e-12);
/// assert_eq!(prior.alpha(Hex::ZERO, 1), 0.8);
///
/// // Every edge crossing the outline gets the low prior.
/// let grid = HexGrid::new(0.5);
/// let outline = geo::Rect::new((-1.0, -3.0), (6.0, 3.0)).to_polygon();
/// assert!(prior.add_outline(&grid, &outline, 0.01) > 0);
/// let at_the_wall = grid.hex_at(5.9, 0.0);
/// assert!((0..6).any(|e| prior.is_outline_edge(at_the_wall, e)));
/// assert!(!(0..6).any(|e| prior.is_outline_edge(Hex::ZERO, e)));
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct EdgePrior {
    alpha: f64,
    /// `α^e_h` of all six edges and their sum, for hexagons where some edge differs from `α`.
    cells: FxHashMap<Hex, [f64; 7]>,
    /// The edges an outline crosses, each as (hexagon, edge 0..3) of the hexagon owning it.
    outline: FxHashSet<(Hex, u8)>,
    /// The outline itself.
    outline_polygon: Option<Polygon<f64>>,
}

/// An edge named from the hexagon that owns it (edges 0..3: E, NE, NW).
fn owned(h: Hex, edge: u8) -> (Hex, u8) {
    let edge = edge % 6;
    if edge < 3 {
        (h, edge)
    } else {
        (HexGrid::neighbour(h, edge), edge - 3)
    }
}

impl EdgePrior {
    /// `α` on every edge (the paper's prior).
    #[must_use]
    pub fn uniform(alpha: f64) -> Self {
        Self {
            alpha,
            cells: FxHashMap::default(),
            outline: FxHashSet::default(),
            outline_polygon: None,
        }
    }

    /// True when every edge has the default `α`.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    /// True for an edge that crosses the outline given to [`EdgePrior::add_outline`].
    #[must_use]
    pub fn is_outline_edge(&self, h: Hex, edge: u8) -> bool {
        self.outline.contains(&owned(h, edge))
    }

    /// True when an outline was added.
    #[must_use]
    pub fn has_outline(&self) -> bool {
        !self.outline.is_empty()
    }

    /// The outline given to [`EdgePrior::add_outline`] (the last one).
    #[must_use]
    pub fn outline(&self) -> Option<&Polygon<f64>> {
        self.outline_polygon.as_ref()
    }

    /// `α^e_h`.
    #[must_use]
    pub fn alpha(&self, h: Hex, edge: u8) -> f64 {
        self.cells
            .get(&h)
            .map_or(self.alpha, |c| c[usize::from(edge % 6)])
    }

    /// `(α^e_h, Σ_e' α^e'_h)`: one edge's prior and the hexagon's total.
    #[must_use]
    pub fn alpha_and_total(&self, h: Hex, edge: u8) -> (f64, f64) {
        match self.cells.get(&h) {
            Some(c) => (c[usize::from(edge % 6)], c[6]),
            None => (self.alpha, 6.0 * self.alpha),
        }
    }

    /// Sets `α` of edge `edge` of `h` (and of the same edge seen from the neighbour) with `f`.
    fn update_edge(&mut self, h: Hex, edge: u8, f: impl Fn(f64) -> f64) {
        let alpha = self.alpha;
        let edge = edge % 6;
        for (hex, e) in [(h, edge), (HexGrid::neighbour(h, edge), (edge + 3) % 6)] {
            let c = self.cells.entry(hex).or_insert_with(|| {
                let mut c = [alpha; 7];
                c[6] = 6.0 * alpha;
                c
            });
            c[usize::from(e)] = f(c[usize::from(e)]);
            c[6] = c[..6].iter().sum();
        }
    }

    /// Lowers to `alpha_outline` the prior of every edge that crosses `outline` (joins a
    /// hexagon whose centre is inside to one whose centre is outside). Returns the number of
    /// edges changed.
    pub fn add_outline(
        &mut self,
        grid: &HexGrid,
        outline: &Polygon<f64>,
        alpha_outline: f64,
    ) -> usize {
        let inside = |h: Hex| {
            let (x, y) = grid.center(h);
            outline.contains(&Coord { x, y })
        };
        // Hexagons the outline passes through: the only ones with such an edge (the segment
        // between two centres lies in their two hexagons).
        let mut touched: FxHashSet<Hex> = FxHashSet::default();
        for ring_segment in outline.exterior().lines() {
            let (a, b) = (ring_segment.start, ring_segment.end);
            touched.insert(grid.hex_at(a.x, a.y));
            grid.for_each_crossing((a.x, a.y), (b.x, b.y), |c| {
                touched.insert(c.to);
            });
        }
        let mut edges: Vec<(Hex, u8)> = Vec::new();
        for &h in &touched {
            let h_in = inside(h);
            for e in 0..6u8 {
                let j = HexGrid::neighbour(h, e);
                // Each edge once: from its inside hexagon.
                if h_in && !inside(j) {
                    edges.push((h, e));
                } else if !h_in && inside(j) && !touched.contains(&j) {
                    edges.push((j, (e + 3) % 6));
                }
            }
        }
        self.outline_polygon = Some(outline.clone());
        edges.sort_unstable_by_key(|&(h, e)| (h.x, h.y, e));
        edges.dedup();
        for &(h, e) in &edges {
            self.update_edge(h, e, |_| alpha_outline);
            self.outline.insert(owned(h, e));
        }
        edges.len()
    }

    /// Adds `weight ×` the crossing counts of an earlier map (in the same grid) as
    /// pseudo-counts, each level's at its stacked keys ([`level_key`]; an outline is on
    /// level 0). Returns the number of edges changed.
    pub fn add_counts(&mut self, map: &HexMapSnapshot, weight: f64) -> usize {
        let mut changed = 0;
        for cell in &map.cells {
            // Edges 0..3 of every cell cover each crossed edge once: both hexagons of a
            // crossed edge are in the snapshot.
            for e in 0..3u8 {
                let n = cell.counts[usize::from(e)];
                if n > 0 && weight > 0.0 {
                    let key = level_key(cell.level, cell.hex);
                    self.update_edge(key, e, |a| a + weight * f64::from(n));
                    changed += 1;
                }
            }
        }
        changed
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::HexCell;
    use geo::Rect;

    #[test]
    fn uniform_prior_is_the_papers() {
        let p = EdgePrior::uniform(0.8);
        let (a, total) = p.alpha_and_total(Hex::new(3, -2), 4);
        assert!(a == 0.8 && (total - 4.8).abs() < 1e-12);
        assert!(p.is_empty());
    }

    #[test]
    fn prior_counts_are_shared_by_both_sides_of_an_edge() {
        let mut p = EdgePrior::uniform(0.8);
        let map = HexMapSnapshot {
            radius: 0.5,
            alpha: 0.8,
            cells: vec![
                HexCell {
                    hex: Hex::new(0, 0),
                    counts: [4, 0, 0, 0, 0, 0],
                    level: 0,
                },
                HexCell {
                    hex: Hex::new(1, 0),
                    counts: [0, 0, 0, 4, 0, 0],
                    level: 0,
                },
            ],
            levels: Vec::new(),
        };
        assert_eq!(p.add_counts(&map, 0.5), 1);
        // α + 0.5 · 4 = 2.8 on edge E of (0,0) and edge W of (1,0); totals 4.0 + 2.8.
        assert!((p.alpha(Hex::new(0, 0), 0) - 2.8).abs() < 1e-12);
        let (a, total) = p.alpha_and_total(Hex::new(1, 0), 3);
        assert!((a - 2.8).abs() < 1e-12 && (total - 6.8).abs() < 1e-12);
        assert_eq!(p.alpha(Hex::new(1, 0), 0), 0.8);
    }

    #[test]
    fn every_way_out_of_an_outline_crosses_one_low_edge() {
        let grid = HexGrid::new(0.5);
        let outline = Rect::new((-4.0, -3.0), (6.0, 5.0)).to_polygon();
        let mut p = EdgePrior::uniform(0.8);
        let n = p.add_outline(&grid, &outline, 0.05);
        assert!(n > 40, "{n} edges");
        // Walk straight out from the centre in many directions: exactly one low edge each.
        for k in 0..36 {
            let a = f64::from(k) * 10f64.to_radians() + 0.013;
            let (bx, by) = (1.0 + 20.0 * a.cos(), 1.0 + 20.0 * a.sin());
            let mut low = 0;
            grid.for_each_crossing((1.0, 1.0), (bx, by), |c| {
                assert_eq!(
                    p.is_outline_edge(c.from, c.edge),
                    p.alpha(c.from, c.edge) < 0.1
                );
                if p.alpha(c.from, c.edge) < 0.1 {
                    low += 1;
                    assert_eq!(p.alpha(c.to, (c.edge + 3) % 6), 0.05);
                }
            });
            assert_eq!(low, 1, "direction {k}");
        }
        // Walking inside, parallel to a wall a metre in, crosses none.
        grid.for_each_crossing((-3.0, -2.0), (5.0, -2.0), |c| {
            assert_eq!(p.alpha(c.from, c.edge), 0.8);
        });
    }
}
