//! FootSLAM's probabilistic hexagon transition map (Robertson et al. 2009, sec. 2.4–2.5),
//! stored so that thousands of particles can share it.
//!
//! The map `M = {M_h}` holds, for each visited hexagon `h`, the Dirichlet-multinomial
//! counts `N^e_h` of crossings of its six edges. A crossing of edge `e` from `h` into `j`
//! is counted for the outgoing *and* the incoming hexagon (sec. 3, "implementation
//! issues"), so each edge has one count shared by its two hexagons. We store it once, at
//! the hexagon that owns the edge (edges 0, 1, 2 = E, NE, NW; edge 3..5 of `h` is edge
//! 0..2 of its neighbour), together with the hexagon's total `N_h`. That is four `u16`
//! per hexagon, 8 bytes.
//!
//! **Sharing.** The counters live in a [`HexTree`]: leaves of 4×4 hexagons (128 bytes)
//! under a persistent quadtree, copied on write, so that cloning a map (resampling) is one
//! reference-count increment and a write copies only the path to its leaf.
//!
//! **Levels.** A walk over several floors has one map per floor (the paper's 2.5D remark,
//! sec. 5), stacked in one key space: hexagon `(q, r)` of level `l` is stored at
//! `(q, r + l · LEVEL_STRIDE)` ([`level_key`]). Level 0 is stored as before; each level spans
//! ±2¹⁹ hexagon rows (±390 km at 0.5 m), far beyond any building.

use super::floor_plan::FloorLevel;
use super::hex_forest::{ForestMap, HexForest};
use super::hex_tree::{HexTree, LEAF, LeafKey, locate};
use crate::geometry::{HexGrid, Pose2};
use hexx::Hex;
use rustc_hash::FxHashMap;

/// Rows of the axial grid between two stacked levels (see the module documentation).
pub const LEVEL_STRIDE: i32 = 1 << 20;

/// The stacked key of hexagon `h` on `level`: one key space for every level's map.
#[must_use]
pub fn level_key(level: i32, h: Hex) -> Hex {
    Hex::new(h.x, h.y.wrapping_add(level.wrapping_mul(LEVEL_STRIDE)))
}

/// The level and in-level hexagon of a stacked key ([`level_key`]'s inverse).
#[must_use]
pub fn split_level_key(key: Hex) -> (i32, Hex) {
    let level = (key.y + LEVEL_STRIDE / 2).div_euclid(LEVEL_STRIDE);
    (level, Hex::new(key.x, key.y - level * LEVEL_STRIDE))
}

/// Per-hexagon counters: crossings of owned edges 0, 1, 2 and the total over all six.
pub type HexCounters = [u16; 4];
type Counters = HexCounters;
const TOTAL: usize = 3;

/// One hexagon of a learned map, as exported.
#[derive(Debug, Clone, PartialEq)]
pub struct HexCell {
    /// Axial coordinates within its level.
    pub hex: Hex,
    /// The level (0 for one-floor maps; see [`FloorLevel`]).
    pub level: i32,
    /// Crossings of each edge (edge order of [`crate::geometry::HexGrid`]: 0 = E, 1 = NE,
    /// 2 = NW, 3 = W, 4 = SW, 5 = SE), counted in both directions.
    pub counts: [u32; 6],
}

impl HexCell {
    /// Passes through the hexagon: each pass enters and leaves once, so half the edge
    /// crossings, rounded up.
    #[must_use]
    pub fn visits(&self) -> u32 {
        self.counts.iter().sum::<u32>().div_ceil(2)
    }
}

/// Posterior-mean transition probabilities `(N_e + α) / (N + 6α)`; uniform when `N + 6α = 0`.
#[must_use]
pub fn transition_probabilities(counts: &[u32; 6], alpha: f64) -> [f64; 6] {
    let total: f64 = counts.iter().map(|&n| f64::from(n)).sum::<f64>() + 6.0 * alpha;
    if total > 0.0 {
        counts.map(|n| (f64::from(n) + alpha) / total)
    } else {
        [1.0 / 6.0; 6]
    }
}

/// Passes through a hexagon with edge counts `counts`: `⌈Σ counts / 2⌉`.
#[must_use]
pub fn visits(counts: &[u32; 6]) -> u64 {
    counts
        .iter()
        .map(|&n| u64::from(n))
        .sum::<u64>()
        .div_ceil(2)
}

/// A read-only copy of a map for export.
#[derive(Debug, Clone, PartialEq)]
pub struct HexMapSnapshot {
    /// Hexagon circumradius, metres.
    pub radius: f64,
    /// Dirichlet prior per edge.
    pub alpha: f64,
    /// Visited hexagons, sorted by (level, q, r).
    pub cells: Vec<HexCell>,
    /// Heights of the levels the cells use, by number; empty for a one-floor map (level 0
    /// at height 0).
    pub levels: Vec<FloorLevel>,
}

impl HexMapSnapshot {
    /// The floor height of `level`, metres (0 when the map does not say).
    #[must_use]
    pub fn level_height(&self, level: i32) -> f64 {
        self.levels
            .iter()
            .find(|l| l.level == level)
            .map_or(0.0, |l| l.z)
    }

    /// The distinct levels of the cells, ascending.
    #[must_use]
    pub fn cell_levels(&self) -> Vec<i32> {
        let mut levels: Vec<i32> = self.cells.iter().map(|c| c.level).collect();
        levels.sort_unstable();
        levels.dedup();
        levels
    }
}

/// A particle's transition map: shared, copy-on-write edge-crossing counts.
///
/// Crossings counted, and a transition probability read with the Dirichlet prior:
///
/// ```
/// use footslam::geometry::{Hex, HexGrid};
/// use footslam::map::HexTransitionMap;
/// use footslam::map::hex_transitions::transition_probabilities;
///
/// let mut map = HexTransitionMap::new();
/// let h = Hex::new(2, -1);
/// // Three crossings east out of `h`, one back in: an edge has one count for both sides.
/// for _ in 0..3 {
///     map.record_crossing(h, 0);
/// }
/// let east = HexGrid::neighbour(h, 0);
/// let (n_e, n_h) = map.record_crossing(east, 3); // the counts before it, as eq. (6) reads them
/// assert_eq!((n_e, n_h), (3, 3));
/// assert_eq!(map.edge_count(east, 3), 4);
/// assert_eq!(map.edge_counts(h), [4, 0, 0, 0, 0, 0]);
///
/// // Posterior-mean probabilities (N_e + α) / (N + 6α) with α = 0.8.
/// let snapshot = map.snapshot(0.5, 0.8);
/// let cell = snapshot.cells.iter().find(|c| c.hex == h).expect("visited");
/// let p = transition_probabilities(&cell.counts, snapshot.alpha);
/// assert!((p[0] - 4.8 / 8.8).abs() < 1e-12);
/// assert!((p[3] - 0.8 / 8.8).abs() < 1e-12); // never walked, still possible
/// assert!((p.iter().sum::<f64>() - 1.0).abs() < 1e-12);
/// ```
#[derive(Debug, Clone, Default)]
pub struct HexTransitionMap {
    counts: HexTree<Counters>,
}

fn bump(c: &mut u16) {
    *c = c.saturating_add(1);
}

impl HexTransitionMap {
    /// An empty map.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    fn counters(&self, h: Hex) -> Counters {
        self.counts.get(h)
    }

    /// `N^e_h`: crossings of edge `edge` of hexagon `h`, both directions.
    #[must_use]
    pub fn edge_count(&self, h: Hex, edge: u8) -> u32 {
        if edge < 3 {
            u32::from(self.counters(h)[usize::from(edge)])
        } else {
            u32::from(self.counters(HexGrid::neighbour(h, edge))[usize::from(edge - 3)])
        }
    }

    /// `N_h`: crossings of all six edges of `h`.
    #[must_use]
    pub fn total_count(&self, h: Hex) -> u32 {
        u32::from(self.counters(h)[TOTAL])
    }

    /// The six edge counts of `h` in edge order.
    #[must_use]
    pub fn edge_counts(&self, h: Hex) -> [u32; 6] {
        std::array::from_fn(|e| self.edge_count(h, e as u8))
    }

    fn leaf_mut(&mut self, leaf: LeafKey) -> &mut [Counters; LEAF] {
        self.counts.leaf_mut(leaf)
    }

    /// Counts one crossing of edge `edge` out of `from` (sec. 3: for the outgoing and the
    /// incoming hexagon alike) and returns the counts before it, `(N^e_h, N_h)` of `from`,
    /// as eq. (6) needs them. Counters saturate at `u16::MAX`. One descent of the tree
    /// when both hexagons share a leaf, two otherwise.
    pub fn record_crossing(&mut self, from: Hex, edge: u8) -> (u32, u32) {
        count_crossing(&mut self.counts, from, edge)
    }

    /// Adds `n` crossings of an edge at once (used to seed a map from prior counts).
    pub fn add_crossings(&mut self, from: Hex, edge: u8, n: u16) {
        let to = HexGrid::neighbour(from, edge);
        let (owner, owned) = if edge < 3 {
            (from, edge)
        } else {
            (to, edge - 3)
        };
        let (leaf, slot) = locate(owner);
        let c = &mut self.leaf_mut(leaf)[slot][usize::from(owned)];
        *c = c.saturating_add(n);
        for h in [from, to] {
            let (leaf, slot) = locate(h);
            let c = &mut self.leaf_mut(leaf)[slot][TOTAL];
            *c = c.saturating_add(n);
        }
    }

    /// Every hexagon with at least one crossing, sorted by (level, q, r), with its six
    /// counts (levels decoded from the stacked keys; `levels` left empty for the caller).
    #[must_use]
    pub fn snapshot(&self, radius: f64, alpha: f64) -> HexMapSnapshot {
        snapshot_of(|f| self.counts.for_each(f), radius, alpha)
    }

    /// Bytes held by nodes not shared with any other map (a lower bound on what this
    /// map alone keeps alive); shared nodes are not counted.
    #[must_use]
    pub fn unshared_bytes(&self) -> usize {
        self.counts.unshared_bytes()
    }
}

/// Where a map's counters live, for [`count_crossing`]: a tree of its own, or a map of a
/// [`HexForest`].
trait CounterLeaves {
    /// The mutable leaf of leaf block `leaf`, copied or created as needed.
    fn leaf_mut(&mut self, leaf: LeafKey) -> &mut [Counters; LEAF];
}

impl CounterLeaves for HexTree<Counters> {
    fn leaf_mut(&mut self, leaf: LeafKey) -> &mut [Counters; LEAF] {
        HexTree::leaf_mut(self, leaf)
    }
}

impl CounterLeaves for (&HexForest<Counters>, &mut ForestMap<Counters>) {
    fn leaf_mut(&mut self, leaf: LeafKey) -> &mut [Counters; LEAF] {
        self.0.leaf_mut(self.1, leaf)
    }
}

/// [`HexTransitionMap::record_crossing`] in any [`CounterLeaves`].
fn count_crossing(leaves: &mut impl CounterLeaves, from: Hex, edge: u8) -> (u32, u32) {
    let to = HexGrid::neighbour(from, edge);
    let ((leaf_from, slot_from), (leaf_to, slot_to)) = (locate(from), locate(to));
    // The slot owning the edge and the edge's index there.
    let (owner_slot, owned) = if edge < 3 {
        (slot_from, usize::from(edge))
    } else {
        (slot_to, usize::from(edge - 3))
    };
    if leaf_from == leaf_to {
        let cells = leaves.leaf_mut(leaf_from);
        let before = (cells[owner_slot][owned], cells[slot_from][TOTAL]);
        bump(&mut cells[owner_slot][owned]);
        bump(&mut cells[slot_from][TOTAL]);
        bump(&mut cells[slot_to][TOTAL]);
        return (u32::from(before.0), u32::from(before.1));
    }
    let c = &mut leaves.leaf_mut(leaf_from)[slot_from];
    let n_h = c[TOTAL];
    bump(&mut c[TOTAL]);
    let mut n_e = 0;
    if edge < 3 {
        n_e = c[owned];
        bump(&mut c[owned]);
    }
    let c = &mut leaves.leaf_mut(leaf_to)[slot_to];
    bump(&mut c[TOTAL]);
    if edge >= 3 {
        n_e = c[owned];
        bump(&mut c[owned]);
    }
    (u32::from(n_e), u32::from(n_h))
}

/// Many particles' transition maps in one store ([`HexForest`]; FootSLAM's particles).
pub type HexMapForest = HexForest<Counters>;
/// One particle's transition map in a [`HexMapForest`].
pub type ParticleHexMap = ForestMap<Counters>;

impl HexForest<Counters> {
    /// [`HexTransitionMap::record_crossing`] in `map`.
    pub fn record_crossing(&self, map: &mut ParticleHexMap, from: Hex, edge: u8) -> (u32, u32) {
        count_crossing(&mut (self, map), from, edge)
    }

    /// [`HexTransitionMap::snapshot`] of `map`.
    #[must_use]
    pub fn snapshot(&self, map: &ParticleHexMap, radius: f64, alpha: f64) -> HexMapSnapshot {
        snapshot_of(|f| self.for_each(map, f), radius, alpha)
    }
}

/// The snapshot of the map whose stored counters `for_each` visits.
fn snapshot_of(
    for_each: impl FnOnce(&mut dyn FnMut(Hex, &Counters)),
    radius: f64,
    alpha: f64,
) -> HexMapSnapshot {
    let mut stored: FxHashMap<Hex, Counters> = FxHashMap::default();
    for_each(&mut |h, c| {
        if c[TOTAL] > 0 {
            stored.insert(h, *c);
        }
    });
    let get = |h: Hex| stored.get(&h).copied().unwrap_or([0; 4]);
    let mut cells: Vec<HexCell> = stored
        .keys()
        .map(|&h| {
            let own = get(h);
            let counts = std::array::from_fn(|e| {
                if e < 3 {
                    u32::from(own[e])
                } else {
                    u32::from(get(HexGrid::neighbour(h, e as u8))[e - 3])
                }
            });
            let (level, hex) = split_level_key(h);
            HexCell { hex, level, counts }
        })
        .collect();
    cells.sort_by_key(|c| (c.level, c.hex.x, c.hex.y));
    HexMapSnapshot {
        radius,
        alpha,
        cells,
        levels: Vec::new(),
    }
}

/// The hexagon map a path walks from `start` (every edge crossing counted, each step on its
/// level of `levels`), with Dirichlet prior `alpha`: e.g. the map of a dead-reckoned path.
#[must_use]
pub fn map_of_path(
    start: Pose2,
    path: &[Pose2],
    levels: &[i32],
    radius: f64,
    alpha: f64,
) -> HexMapSnapshot {
    let grid = HexGrid::new(radius);
    let mut map = HexTransitionMap::new();
    let mut from = start;
    for (to, &level) in path.iter().zip(levels) {
        grid.for_each_crossing((from.x, from.y), (to.x, to.y), |c| {
            map.record_crossing(level_key(level, c.from), c.edge);
        });
        from = *to;
    }
    map.snapshot(radius, alpha)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossings_count_for_both_hexagons() {
        let mut m = HexTransitionMap::new();
        let a = Hex::new(0, 0);
        m.record_crossing(a, 0);
        let b = HexGrid::neighbour(a, 0);
        assert_eq!(m.edge_count(a, 0), 1);
        assert_eq!(m.edge_count(b, 3), 1);
        assert_eq!(m.total_count(a), 1);
        assert_eq!(m.total_count(b), 1);
        m.record_crossing(b, 4);
        assert_eq!(m.edge_count(b, 4), 1);
        assert_eq!(m.total_count(b), 2);
        assert_eq!(m.edge_counts(b), [0, 0, 0, 1, 1, 0]);
    }

    #[test]
    fn clones_share_until_written() {
        let mut m = HexTransitionMap::new();
        for q in -40..40 {
            m.record_crossing(Hex::new(q, 3), 0);
        }
        let before = m.unshared_bytes();
        assert!(before > 0);
        let mut c = m.clone();
        assert_eq!(m.unshared_bytes(), 0, "a clone shares everything");
        c.record_crossing(Hex::new(0, 3), 1);
        assert!(c.unshared_bytes() < before, "a write copies only one path");
        assert_eq!(
            m.edge_count(Hex::new(0, 3), 1),
            0,
            "the original is unchanged"
        );
        assert_eq!(c.edge_count(Hex::new(0, 3), 1), 1);
    }

    #[test]
    fn grows_to_far_hexagons_and_snapshots_everything() {
        let mut m = HexTransitionMap::new();
        let far = [
            Hex::new(0, 0),
            Hex::new(-5000, 7),
            Hex::new(123_456, -98_765),
            Hex::new(-1, -1),
        ];
        for (i, &h) in far.iter().enumerate() {
            for _ in 0..=i {
                m.record_crossing(h, (i % 6) as u8);
            }
        }
        for (i, &h) in far.iter().enumerate() {
            assert_eq!(m.edge_count(h, (i % 6) as u8), i as u32 + 1, "{h:?}");
        }
        let s = m.snapshot(0.5, 0.8);
        assert_eq!(s.cells.len(), 8);
        let total: u32 = s.cells.iter().map(|c| c.counts.iter().sum::<u32>()).sum();
        assert_eq!(total, 2 * (1 + 2 + 3 + 4));
        for c in &s.cells {
            assert_eq!(c.counts, m.edge_counts(c.hex));
        }
    }
}
