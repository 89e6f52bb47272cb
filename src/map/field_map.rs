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

/// A particle's field map.
#[derive(Debug, Clone, Default)]
pub struct FieldMap {
    cells: HexTree<FieldCell>,
}

impl FieldMap {
    /// An empty map.
    pub fn new() -> Self {
        Self::default()
    }

    /// The readings at hexagon `key` (empty where none).
    pub fn cell(&self, key: Hex) -> FieldCell {
        self.cells.get(key)
    }

    /// Adds the reading `y` (its first `dims` components) taken at step `k` to hexagon
    /// `key`'s running mean; returns the hexagon's readings before it (one descent of the
    /// tree for both).
    pub fn record(&mut self, key: Hex, k: u32, y: [f32; 2], dims: usize) -> FieldCell {
        let c = self.cells.get_mut(key);
        let before = *c;
        let n = c.n.saturating_add(1);
        if n > c.n {
            let share = 1.0 / f32::from(n);
            for d in 0..dims.min(2) {
                c.mean[d] += (y[d] - c.mean[d]) * share;
            }
            c.n = n;
        }
        c.last_step = k as u16;
        before
    }

    /// Every hexagon with readings, sorted by key.
    pub fn snapshot(&self) -> Vec<FieldMapCell> {
        let mut cells = Vec::new();
        self.cells.for_each(|key, c| {
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
        let h = Hex::new(2, -1);
        assert_eq!(m.record(h, 10, [40.0, -30.0], 2), FieldCell::default());
        assert_eq!(m.record(h, 40, [42.0, -34.0], 2).n, 1);
        let c = m.cell(h);
        assert_eq!((c.n, c.last_step), (2, 40));
        assert_eq!(c.mean, [41.0, -32.0]);
        assert_eq!(c.steps_since(45), 5);
        assert_eq!(m.cell(Hex::new(0, 0)), FieldCell::default());
        let shared = m.clone();
        m.record(h, 50, [44.0, 0.0], 1);
        assert_eq!(m.cell(h).mean, [41.0 + 3.0 / 3.0, -32.0]);
        assert_eq!(shared.cell(h).n, 2, "a clone keeps its own readings");
        let s = m.snapshot();
        assert_eq!(s.len(), 1);
        assert_eq!((s[0].key, s[0].n), (h, 3));
    }
}
