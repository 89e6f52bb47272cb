//! A particle's positions at the walk's WiFi scans, shared by its descendants.
//!
//! FootSLAM's WiFi term ([`crate::model::scan_pairs`]) needs, for every particle, where it
//! was at each earlier scan. Resampling copies particles by the thousand, so the trail is
//! persistent: full chunks of [`CHUNK`] positions are immutable and shared through `Arc`;
//! only the last, partly filled chunk is the particle's own, copied when a shared trail is
//! extended. A trail of `n` positions costs a descendant `8·CHUNK` bytes plus a pointer per
//! full chunk of its own, and reads any position in two loads.

use std::sync::Arc;

/// Positions per shared chunk.
pub const CHUNK: usize = 32;

#[derive(Debug, Clone, Default)]
struct Node {
    full: Vec<Arc<[(f32, f32); CHUNK]>>,
    tail: Vec<(f32, f32)>,
}

/// One particle's positions at the scans so far (cheap to clone: one reference count;
/// an empty trail, a walk without scans, holds nothing and counts nothing).
#[derive(Debug, Clone, Default)]
pub struct ScanTrail {
    node: Option<Arc<Node>>,
}

impl ScanTrail {
    /// Positions held.
    #[must_use]
    pub fn len(&self) -> usize {
        self.node
            .as_ref()
            .map_or(0, |n| n.full.len() * CHUNK + n.tail.len())
    }

    /// Whether it holds none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The position at scan `j` (`j < len()`).
    ///
    /// # Panics
    ///
    /// If `j >= len()` (any `j` of an empty trail).
    #[inline]
    #[must_use]
    pub fn get(&self, j: usize) -> (f32, f32) {
        let Some(n) = &self.node else {
            panic!("scan {j} of an empty trail")
        };
        match n.full.get(j / CHUNK) {
            Some(chunk) => chunk[j % CHUNK],
            None => n.tail[j % CHUNK],
        }
    }

    /// Appends the position at the next scan (copying the particle's own chunk first if a
    /// relative shares it).
    pub fn push(&mut self, at: (f32, f32)) {
        let node = Arc::make_mut(self.node.get_or_insert_default());
        node.tail.push(at);
        if node.tail.len() == CHUNK {
            let chunk: [(f32, f32); CHUNK] = std::array::from_fn(|i| node.tail[i]);
            node.full.push(Arc::new(chunk));
            node.tail.clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_survive_sharing_and_chunks() {
        let mut a = ScanTrail::default();
        for i in 0..(2 * CHUNK + 5) {
            a.push((i as f32, -(i as f32)));
        }
        let mut b = a.clone();
        b.push((1000.0, 0.0));
        a.push((2000.0, 0.0));
        assert_eq!(a.len(), 2 * CHUNK + 6);
        assert_eq!(b.len(), a.len());
        for i in 0..(2 * CHUNK + 5) {
            assert_eq!(a.get(i), (i as f32, -(i as f32)));
            assert_eq!(b.get(i), a.get(i));
        }
        assert_eq!(a.get(2 * CHUNK + 5).0, 2000.0);
        assert_eq!(b.get(2 * CHUNK + 5).0, 1000.0);
        assert!(ScanTrail::default().is_empty());
    }
}
