//! A particle's map of the magnetic field (MagSLAM, Robertson et al., IPIN 2013): per
//! hexagon, the mean of the field readings the particle took there and how many, shared
//! copy-on-write between particles like the transition counts ([`super::hex_tree`]).
//!
//! A record is 12 bytes: the count, the step of the last reading (so that a particle does
//! not take its own reading of a moment ago for a revisit) and the running means of up to
//! two field components (magnitude and vertical part, [`crate::sensor::StepField`]).

use super::hex_tree::HexTree;
use hexx::Hex;

/// One hexagon's field readings.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FieldCell {
    /// Readings averaged (saturates at `u16::MAX`).
    pub n: u16,
    /// The step of the last reading, modulo 2¹⁶.
    pub last_step: u16,
    /// Mean of each component, µT.
    pub mean: [f32; 2],
}

impl FieldCell {
    /// Steps since the last reading at step `k` (modulo 2¹⁶, so a reading 65,536 steps
    /// ago reads as recent: it then only skips one comparison).
    #[must_use]
    pub fn steps_since(&self, k: u32) -> u16 {
        (k as u16).wrapping_sub(self.last_step)
    }
}

/// One hexagon of an exported field map.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldMapCell {
    /// The stacked key ([`super::level_key`]) of the hexagon.
    pub key: Hex,
    /// Readings averaged.
    pub n: u32,
    /// Mean of each component, µT.
    pub mean: [f64; 2],
}

/// The readings of the hexagon a particle is in, not yet written to its map.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Pending {
    key: Hex,
    /// The hexagon's readings written before the particle entered it.
    before: FieldCell,
    /// The step of the last reading.
    k: u32,
    /// Sum of the readings' components.
    sum: [f32; 2],
    n: u16,
}

/// A learned field map for export: its hexagons, their size, and how far the answer moved
/// them (the path's shift towards a prior map's frame, [`crate::filter::FootSlamEstimate`]).
#[derive(Debug, Clone, PartialEq)]
pub struct FieldMapSnapshot {
    /// Circumradius of the hexagons, metres.
    pub radius: f64,
    /// Components the means hold: 1 (magnitude) or 2 (magnitude, vertical part).
    pub components: usize,
    /// Add this to every hexagon's centre and corners, metres.
    pub offset: (f64, f64),
    /// Hexagons with readings, sorted by key.
    pub cells: Vec<FieldMapCell>,
}

/// A particle's field map.
///
/// The readings of the hexagon the particle is in are held aside and written to the shared
/// tree when it leaves (one copy-on-write descent per hexagon passed, not per step); they
/// belong to this pass and are never compared with it anyway.
#[derive(Debug, Clone, Default)]
pub struct FieldMap {
    cells: HexTree<FieldCell>,
    pending: Option<Pending>,
}

impl FieldMap {
    /// An empty map.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// The readings at hexagon `key` written so far (empty where none; the readings of the
    /// hexagon the particle is in are written when it leaves).
    #[must_use]
    pub fn cell(&self, key: Hex) -> FieldCell {
        self.cells.get(key)
    }

    /// Takes the reading `y` (its first `dims` components) at step `k` in hexagon `key`;
    /// returns the hexagon's readings written before (from earlier passes). Leaving a
    /// hexagon writes its readings of this pass into its running mean.
    pub fn observe(&mut self, key: Hex, k: u32, y: [f32; 2], dims: usize) -> FieldCell {
        match &mut self.pending {
            Some(p) if p.key == key => {
                for (sum, &y) in p.sum.iter_mut().zip(&y).take(dims) {
                    *sum += y;
                }
                p.n = p.n.saturating_add(1);
                p.k = k;
                p.before
            }
            _ => {
                self.flush();
                let before = self.cells.get(key);
                self.pending = Some(Pending {
                    key,
                    before,
                    k,
                    sum: y,
                    n: 1,
                });
                before
            }
        }
    }

    /// Writes the held readings into the tree.
    fn flush(&mut self) {
        let Some(p) = self.pending.take() else { return };
        let c = self.cells.get_mut(p.key);
        let n = c.n.saturating_add(p.n);
        let added = f32::from(n - c.n);
        if added > 0.0 {
            let share = 1.0 / f32::from(n);
            let mean_of_pass = p.sum.map(|v| v / f32::from(p.n));
            for (mean, &y) in c.mean.iter_mut().zip(&mean_of_pass) {
                *mean += (y - *mean) * added * share;
            }
            c.n = n;
        }
        c.last_step = p.k as u16;
    }

    /// Every hexagon with readings (those held aside included), sorted by key.
    #[must_use]
    pub fn snapshot(&self) -> Vec<FieldMapCell> {
        let mut all = self.clone();
        all.flush();
        let mut cells = Vec::new();
        all.cells.for_each(|key, c| {
            if c.n > 0 {
                cells.push(FieldMapCell {
                    key,
                    n: u32::from(c.n),
                    mean: c.mean.map(f64::from),
                });
            }
        });
        cells.sort_by_key(|c| (c.key.y, c.key.x));
        cells
    }

    /// Bytes held by nodes not shared with any other map.
    #[must_use]
    pub fn unshared_bytes(&self) -> usize {
        self.cells.unshared_bytes()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn running_means_and_recency() {
        let mut m = FieldMap::new();
        let (h, g) = (Hex::new(2, -1), Hex::new(3, -1));
        assert_eq!(m.observe(h, 10, [40.0, -30.0], 2), FieldCell::default());
        assert_eq!(
            m.observe(h, 11, [42.0, -34.0], 2),
            FieldCell::default(),
            "this pass"
        );
        assert_eq!(
            m.cell(h),
            FieldCell::default(),
            "held until the hexagon is left"
        );
        m.observe(g, 12, [50.0, -20.0], 2);
        let c = m.cell(h);
        assert_eq!((c.n, c.last_step), (2, 11));
        assert_eq!(c.mean, [41.0, -32.0]);
        assert_eq!(c.steps_since(15), 4);
        let shared = m.clone();
        assert_eq!(m.observe(h, 50, [44.0, 0.0], 1).n, 2, "an earlier pass");
        m.observe(g, 51, [50.0, -20.0], 2);
        assert_eq!(m.cell(h).mean, [41.0 + 3.0 / 3.0, -32.0 + 32.0 / 3.0]);
        assert_eq!(shared.cell(h).n, 2, "a clone keeps its own readings");
        let s = m.snapshot();
        assert_eq!(s.len(), 2);
        assert_eq!((s[0].key, s[0].n), (h, 3));
        assert_eq!(s[1].n, 2, "the held readings of g are in the snapshot");
    }
}
