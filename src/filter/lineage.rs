//! The ancestry tree of particles (GMapping's trajectory tree, reduced to indices).
//!
//! A particle's whole path is a function of the step measurements and the random streams
//! it drew from: at step `k` it used the stream of the index it held then. So instead of
//! storing poses we store, per resampling, which index a particle held from which step
//! on, linked to its parent; the best particle's path is replayed from its chain.
//!
//! The segments live in one vector, linked by index (a parent always before its children),
//! and a particle holds the index of its newest segment: resampling appends one segment
//! per particle whose index changed and touches nothing else. Segments no particle
//! descends from are dropped in bulk ([`Lineage::collect_garbage`], before a resampling
//! appends its segments) once the vector has doubled since the last collection, or would
//! otherwise have to grow: marked from the particles' segments up their chains, the kept
//! ones slide down in order and the links are renumbered. The vector grows only right
//! after a collection, to what the next one needs, never by doubling while full: a copy
//! of a full vector would hold it twice.

/// The link of a root segment.
const ROOT: u32 = u32::MAX;

/// One segment of a particle's ancestry: from step `from_step` on it held `index`.
#[derive(Debug, Clone, Copy)]
struct Segment {
    parent: u32,
    from_step: u32,
    index: u32,
}

/// Every particle's ancestry, as segments linked by index (see the module documentation).
#[derive(Debug, Default)]
pub struct Lineage {
    segments: Vec<Segment>,
    /// Segments kept at the last collection.
    kept: usize,
}

impl Lineage {
    /// An empty tree.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// A new root: a particle that holds `index` from step 0. Returns its segment.
    ///
    /// # Panics
    ///
    /// If the tree already holds 2³² − 1 segments (the last index is the no-parent mark).
    pub fn root(&mut self, index: u32) -> u32 {
        self.push(ROOT, 0, index)
    }

    /// A child of segment `parent` that holds `index` from step `from_step` on. Returns
    /// its segment.
    ///
    /// # Panics
    ///
    /// If the tree already holds 2³² − 1 segments (the last index is the no-parent mark).
    pub fn child(&mut self, parent: u32, from_step: u32, index: u32) -> u32 {
        self.push(parent, from_step, index)
    }

    fn push(&mut self, parent: u32, from_step: u32, index: u32) -> u32 {
        let id = u32::try_from(self.segments.len()).unwrap_or(ROOT);
        assert!(id != ROOT, "more than 2³² − 1 ancestry segments");
        self.segments.push(Segment {
            parent,
            from_step,
            index,
        });
        id
    }

    /// Segments held.
    #[must_use]
    pub fn len(&self) -> usize {
        self.segments.len()
    }

    /// Whether it holds none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.segments.is_empty()
    }

    /// The particle index held at each step `0..steps` by the particle whose newest
    /// segment is `id`, oldest first.
    #[must_use]
    pub fn indices(&self, id: u32, steps: usize) -> Vec<u32> {
        let mut out = vec![0u32; steps];
        let mut end = steps;
        let mut node = id;
        while node != ROOT {
            let s = self.segments[node as usize];
            let start = (s.from_step as usize).min(end);
            out[start..end].fill(s.index);
            end = start;
            node = s.parent;
        }
        out
    }

    /// Makes room for `incoming` new segments: drops the segments that no particle of
    /// `items` (through `id`, its newest segment) descends from if the tree has doubled
    /// since the last collection (and holds more than a segment per particle) or has no
    /// room left, renumbering the kept ones and the particles' links; then, if it still
    /// has no room, grows to room for what the next collection will find.
    pub fn collect_garbage<P>(
        &mut self,
        items: &mut [P],
        id: impl Fn(&mut P) -> &mut u32,
        incoming: usize,
    ) {
        let floor = self.kept.max(items.len());
        let full = self.segments.len() + incoming > self.segments.capacity();
        if full || self.segments.len() >= 2 * floor {
            self.collect(items, id);
        }
        if self.segments.len() + incoming > self.segments.capacity() {
            // The next collection comes at twice what this one kept; a quarter more
            // spares a growth each time the tree grows a little.
            let room = 2 * self.kept.max(items.len()) + self.kept.max(items.len()) / 4;
            let target = room.max(self.segments.len()) + incoming;
            self.segments.reserve_exact(target - self.segments.len());
        }
    }

    /// The collection of [`Self::collect_garbage`].
    fn collect<P>(&mut self, items: &mut [P], id: impl Fn(&mut P) -> &mut u32) {
        let mut marks = vec![0u64; self.segments.len().div_ceil(64)];
        for p in items.iter_mut() {
            let mut node = *id(p);
            while node != ROOT && marks[node as usize / 64] & (1 << (node % 64)) == 0 {
                marks[node as usize / 64] |= 1 << (node % 64);
                node = self.segments[node as usize].parent;
            }
        }
        let mut ranks = Vec::with_capacity(marks.len());
        let mut total = 0;
        for w in &marks {
            ranks.push(total);
            total += w.count_ones();
        }
        let renumber = |i: u32| {
            let w = i as usize / 64;
            ranks[w] + (marks[w] & ((1 << (i % 64)) - 1)).count_ones()
        };
        let mut kept = 0;
        for i in 0..self.segments.len() {
            if marks[i / 64] & (1 << (i % 64)) != 0 {
                let mut s = self.segments[i];
                if s.parent != ROOT {
                    s.parent = renumber(s.parent);
                }
                self.segments[kept] = s;
                kept += 1;
            }
        }
        self.segments.truncate(kept);
        for p in items.iter_mut() {
            let node = id(p);
            *node = renumber(*node);
        }
        self.kept = kept;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn indices_follow_the_chain() {
        let mut tree = Lineage::new();
        let root = tree.root(3);
        let a = tree.child(root, 2, 7);
        let b = tree.child(a, 5, 1);
        assert_eq!(tree.indices(b, 6), vec![3, 3, 7, 7, 7, 1]);
        assert_eq!(tree.indices(a, 4), vec![3, 3, 7, 7]);
    }

    #[test]
    fn collection_keeps_every_living_chain() {
        let mut tree = Lineage::new();
        let mut ids: Vec<u32> = (0..4).map(|i| tree.root(i)).collect();
        let mut want = Vec::new();
        for k in 1..40u32 {
            // Particle 0's line takes over every other step; the others die out.
            let parents = [0, 0, (k % 4) as usize, 1];
            ids = parents
                .iter()
                .enumerate()
                .map(|(i, &j)| {
                    if i == j {
                        ids[j]
                    } else {
                        tree.child(ids[j], k, i as u32)
                    }
                })
                .collect();
            want = ids.iter().map(|&id| tree.indices(id, 45)).collect();
            tree.collect_garbage(&mut ids, |id| id, 4);
            let got: Vec<_> = ids.iter().map(|&id| tree.indices(id, 45)).collect();
            assert_eq!(got, want, "step {k}");
        }
        assert!(
            tree.len() < 40,
            "dead lines dropped: {} segments",
            tree.len()
        );
        assert!(!want.is_empty());
    }

    #[test]
    fn the_vector_grows_only_to_what_the_next_collection_needs() {
        // 100 particles that all take a new index at every step, all from one line.
        let n = 100;
        let mut tree = Lineage::new();
        let mut ids: Vec<u32> = (0..n).map(|i| tree.root(i)).collect();
        let mut floor = n as usize;
        for k in 1..600u32 {
            let mut next = vec![ids[(k % n) as usize]; n as usize];
            tree.collect_garbage(&mut next, |id| id, n as usize);
            floor = floor.max(tree.kept);
            ids = (0..n).map(|i| tree.child(next[i as usize], k, i)).collect();
            let most = 2 * floor + floor / 4 + n as usize;
            assert!(
                tree.segments.capacity() <= most,
                "step {k}: room for {} segments, {most} at most",
                tree.segments.capacity()
            );
        }
        assert_eq!(tree.indices(ids[7], 600)[599], 7);
    }

    #[test]
    fn deep_chains_are_followed_without_recursion() {
        let mut tree = Lineage::new();
        let mut node = tree.root(0);
        for k in 1..200_000 {
            node = tree.child(node, k, k % 5);
        }
        let indices = tree.indices(node, 200_000);
        assert_eq!(indices[199_999], 199_999 % 5);
    }
}
