//! Many particles' hexagon maps in one store: the copy-on-write sharing of
//! [`super::hex_tree`] without reference counts, atomics or a heap allocation per node.
//!
//! Every particle's map is the same quadtree as [`super::hex_tree::HexTree`]'s (leaves of
//! 4×4 records under 4×4-way branches), but its nodes live in one of two places:
//!
//! * **its own nodes** ([`ForestMap`]): nodes only this map reaches, in two small vectors of
//!   its own, written in place;
//! * **the shared store** ([`HexForest`]): nodes several maps may reach, read-only while the
//!   particles move (so every thread reads them without synchronisation).
//!
//! A link is a `u32` index tagged with where its node lives and whether it is a leaf. A write
//! descends from the root; a shared node on the way is copied into the map's own nodes (and
//! its parent's link updated), a missing one created, an own one written in place — the
//! owner test is one bit, not a reference count.
//!
//! **Resampling** ([`HexForest::inherit`]): a particle with one child hands its map over
//! whole, own nodes included; a particle with several moves its own nodes into the store
//! (in parallel, each into its own range) and every child gets the root alone. Particles
//! with no child drop their own nodes in two frees.
//!
//! Each map also remembers its two most recently written leaf blocks and their own leaves,
//! so that most crossings (which stay within a block of 4×4 hexagons) skip the descent.
//!
//! **Freeing** ([`HexForest::collect`], run by [`HexForest::inherit`] when the store would
//! grow past [`GROWTH_PERCENT`] % of what the last collection kept): store nodes that no surviving
//! map reaches any more are found by marking from every such map (in parallel, one bit per
//! node); the live nodes then slide down in place, keeping their order, and every link is
//! renumbered. Nothing is freed node by node.
//!
//! Which nodes are where never changes what a map holds, so results do not depend on it.

use super::hex_tree::{LEAF, LeafKey, MAX_LEVEL, block_at, child_index, hex_of, locate};
use hexx::Hex;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

/// A link to a node: [`NONE`], or an index tagged [`OWN`] (in the map's own nodes; otherwise
/// in the store) and [`IS_LEAF`] (otherwise a branch).
type Link = u32;
const NONE: Link = u32::MAX;
const OWN: Link = 1 << 31;
const IS_LEAF: Link = 1 << 30;
const INDEX: Link = IS_LEAF - 1;

/// A branch: links to its 4×4 children.
type Branch = [Link; LEAF];

/// The store's collection threshold: it collects when it would hold more than this share,
/// in per cent, of the bytes it kept at the previous collection (or `MIN_COLLECT_BYTES`,
/// 4 MiB). At 150 rather than 200 the store peaks at 1.5 times its live nodes, not twice
/// (BENCHMARKS.md: about 100 bytes a particle less at 100,000 particles × 700 steps, for
/// 5–8 % more CPU time).
pub const GROWTH_PERCENT: usize = 150;
/// The store collects no garbage below this size.
const MIN_COLLECT_BYTES: usize = 4 << 20;

fn index(link: Link) -> usize {
    (link & INDEX) as usize
}

fn is_own(link: Link) -> bool {
    link != NONE && link & OWN != 0
}

/// Appends `node`, growing by one node, and returns its index. A map's own nodes hold no
/// slack: after a few steps without a resampling they are the largest part of a particle's
/// memory (up to 1 KB; BENCHMARKS.md), and the allocator's reallocation grows most blocks
/// in place (its size classes leave room).
fn push<N>(nodes: &mut Vec<N>, node: N) -> Link {
    if nodes.len() == nodes.capacity() {
        nodes.reserve_exact(1);
    }
    debug_assert!(nodes.len() < INDEX as usize, "more than 2³⁰ nodes");
    nodes.push(node);
    (nodes.len() - 1) as Link
}

/// The store of nodes shared between maps (see the module documentation).
#[derive(Debug)]
pub struct HexForest<T> {
    branches: Vec<Branch>,
    leaves: Vec<[T; LEAF]>,
    /// Bytes the store kept at its last collection.
    kept_bytes: usize,
    collections: usize,
    /// Scratch: where each sharing map's own nodes go in the store, relative.
    offsets: Vec<(Link, Link)>,
}

/// One map of a [`HexForest`]: its root and the nodes only it reaches.
#[derive(Debug, Clone)]
pub struct ForestMap<T> {
    root: Link,
    /// Height of the root above the leaves (0: the root is a leaf).
    level: u8,
    /// Block coordinates of the root at its level.
    base: LeafKey,
    branches: Vec<Branch>,
    leaves: Vec<[T; LEAF]>,
    /// The two leaf blocks written last and their own leaves (or [`NONE`]): most crossings
    /// stay in them, and then skip the descent.
    recent: [(LeafKey, Link); 2],
}

impl<T> Default for ForestMap<T> {
    fn default() -> Self {
        Self {
            root: NONE,
            level: 0,
            base: (0, 0),
            branches: Vec::new(),
            leaves: Vec::new(),
            recent: [((0, 0), NONE); 2],
        }
    }
}

impl<T> Default for HexForest<T> {
    fn default() -> Self {
        Self {
            branches: Vec::new(),
            leaves: Vec::new(),
            kept_bytes: 0,
            collections: 0,
            offsets: Vec::new(),
        }
    }
}

impl<T: Copy> ForestMap<T> {
    /// Grows the tree upwards until its root block covers `leaf`.
    fn cover(&mut self, leaf: LeafKey) {
        if self.root == NONE {
            self.level = 0;
            self.base = leaf;
            return;
        }
        while block_at(leaf, self.level) != self.base && self.level < MAX_LEVEL {
            let mut children = [NONE; LEAF];
            let (bx, by) = self.base;
            children[((bx & 3) + 4 * (by & 3)) as usize] = self.root;
            self.root = OWN | push(&mut self.branches, children);
            self.level += 1;
            self.base = (bx >> 2, by >> 2);
        }
    }

    /// Bytes of the nodes only this map holds (its vectors' capacity).
    #[must_use]
    pub fn own_bytes(&self) -> usize {
        self.branches.capacity() * size_of::<Branch>()
            + self.leaves.capacity() * size_of::<[T; LEAF]>()
    }

    /// Moves the own nodes into `branches` and `leaves`, which lie at `bb` and `lb` in the
    /// store, and relinks the root to them.
    fn move_into(
        &mut self,
        branches: &mut [Branch],
        leaves: &mut [[T; LEAF]],
        (bb, lb): (Link, Link),
    ) {
        let moved = |link: Link| match link {
            l if !is_own(l) => l,
            l if l & IS_LEAF != 0 => IS_LEAF | (lb + (l & INDEX)),
            l => bb + (l & INDEX),
        };
        for (to, from) in branches.iter_mut().zip(&self.branches) {
            *to = from.map(moved);
        }
        leaves.copy_from_slice(&self.leaves);
        self.root = moved(self.root);
        // Freed: whichever child writes first allocates what it needs.
        (self.branches, self.leaves) = (Vec::new(), Vec::new());
        self.recent = [((0, 0), NONE); 2];
    }
}

impl<T: Copy + Default + Send + Sync> HexForest<T> {
    /// An empty store.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Bytes of the store's nodes.
    #[must_use]
    pub fn bytes(&self) -> usize {
        self.branches.len() * size_of::<Branch>() + self.leaves.len() * size_of::<[T; LEAF]>()
    }

    /// Garbage collections so far.
    #[must_use]
    pub fn collections(&self) -> usize {
        self.collections
    }

    fn branch<'a>(&'a self, map: &'a ForestMap<T>, link: Link) -> &'a Branch {
        if link & OWN != 0 {
            &map.branches[index(link)]
        } else {
            &self.branches[index(link)]
        }
    }

    /// The leaf of leaf block `leaf` in `map`, if stored.
    #[must_use]
    pub fn leaf<'a>(&'a self, map: &'a ForestMap<T>, leaf: LeafKey) -> Option<&'a [T; LEAF]> {
        if map.root == NONE || block_at(leaf, map.level) != map.base {
            return None;
        }
        let (mut link, mut level) = (map.root, map.level);
        while level > 0 {
            link = self.branch(map, link)[child_index(leaf, level)];
            if link == NONE {
                return None;
            }
            level -= 1;
        }
        Some(if link & OWN != 0 {
            &map.leaves[index(link)]
        } else {
            &self.leaves[index(link)]
        })
    }

    /// The record of `h` in `map` (the default where none is stored).
    #[must_use]
    pub fn get(&self, map: &ForestMap<T>, h: Hex) -> T {
        let (leaf, slot) = locate(h);
        self.leaf(map, leaf)
            .map_or_else(T::default, |cells| cells[slot])
    }

    /// `link` as one of `map`'s own nodes at `level`: itself when own, else a copy of the
    /// shared node, or a new node where there is none.
    fn own(&self, map: &mut ForestMap<T>, link: Link, level: u8) -> Link {
        if is_own(link) {
            return link;
        }
        if level == 0 {
            let leaf = if link == NONE {
                [T::default(); LEAF]
            } else {
                self.leaves[index(link)]
            };
            OWN | IS_LEAF | push(&mut map.leaves, leaf)
        } else {
            let branch = if link == NONE {
                [NONE; LEAF]
            } else {
                self.branches[index(link)]
            };
            // A first write copies the whole path: `level` branches.
            if map.branches.capacity() == 0 {
                map.branches.reserve_exact(usize::from(level));
            }
            OWN | push(&mut map.branches, branch)
        }
    }

    /// The mutable leaf of leaf block `leaf` in `map`, copying shared nodes into the map's
    /// own on the way down and creating missing ones.
    pub fn leaf_mut<'m>(&self, map: &'m mut ForestMap<T>, leaf: LeafKey) -> &'m mut [T; LEAF] {
        if map.recent[0].0 == leaf && map.recent[0].1 != NONE {
            return &mut map.leaves[map.recent[0].1 as usize];
        }
        if map.recent[1].0 == leaf && map.recent[1].1 != NONE {
            map.recent.swap(0, 1);
            return &mut map.leaves[map.recent[0].1 as usize];
        }
        map.cover(leaf);
        let mut level = map.level;
        let mut at = self.own(map, map.root, level);
        map.root = at;
        while level > 0 {
            let slot = child_index(leaf, level);
            let child = map.branches[index(at)][slot];
            let child = self.own(map, child, level - 1);
            map.branches[index(at)][slot] = child;
            at = child;
            level -= 1;
        }
        map.recent = [(leaf, index(at) as Link), map.recent[0]];
        &mut map.leaves[index(at)]
    }

    /// Calls `f` with every stored hexagon of `map` and its record (defaults included),
    /// leaf by leaf in no particular order.
    pub fn for_each(&self, map: &ForestMap<T>, mut f: impl FnMut(Hex, &T)) {
        if map.root == NONE {
            return;
        }
        let mut stack = vec![(map.root, map.base)];
        while let Some((link, (bx, by))) = stack.pop() {
            if link & IS_LEAF != 0 {
                let cells = if link & OWN != 0 {
                    &map.leaves[index(link)]
                } else {
                    &self.leaves[index(link)]
                };
                for (slot, c) in cells.iter().enumerate() {
                    f(hex_of((bx, by), slot), c);
                }
                continue;
            }
            for (i, &c) in self.branch(map, link).iter().enumerate() {
                if c != NONE {
                    stack.push((c, (bx * 4 + (i as u32 & 3), by * 4 + (i as u32 >> 2))));
                }
            }
        }
    }

    /// The maps of the next generation after resampling: child `new[i]` inherits the map of
    /// `old[parents[i]]` (each reached through `map` and `new_map`; the children's maps are
    /// overwritten). A parent's only child takes its map whole; a parent of several first
    /// moves its own nodes into the store, and each child gets its root. `children` is
    /// scratch.
    ///
    /// # Panics
    ///
    /// If `new` and `parents` differ in length, if an index of `parents` is not one of
    /// `old`, or if the store would hold 2³⁰ branches or 2³⁰ leaves or more.
    pub fn inherit<P: Send, Q>(
        &mut self,
        old: &mut [P],
        map: impl Fn(&mut P) -> &mut ForestMap<T> + Sync,
        parents: &[usize],
        children: &mut Vec<u32>,
        (new, new_map): (&mut [Q], impl Fn(&mut Q) -> &mut ForestMap<T>),
    ) {
        assert_eq!(new.len(), parents.len(), "one child per parent index");
        children.clear();
        children.resize(old.len(), 0);
        for &j in parents {
            children[j] += 1;
        }
        // Where the own nodes of each parent of several go.
        self.offsets.clear();
        let mut at = (0, 0);
        for (p, &c) in old.iter_mut().zip(children.iter()) {
            self.offsets.push(at);
            if c > 1 {
                let m = map(p);
                at = (
                    at.0 + m.branches.len() as Link,
                    at.1 + m.leaves.len() as Link,
                );
            }
        }
        self.offsets.push(at);
        // Collect the garbage before the store outgrows `GROWTH_PERCENT` % of what it kept.
        let incoming = at.0 as usize * size_of::<Branch>() + at.1 as usize * size_of::<[T; LEAF]>();
        let limit = self.kept_bytes * GROWTH_PERCENT / 100;
        if self.bytes() + incoming > MIN_COLLECT_BYTES.max(limit) {
            self.collect_where(old, &map, |j| children[j] > 0);
        }
        self.share(old, &map, children);
        // The last child of a parent takes its map, the others copy its root.
        for (child, &j) in new.iter_mut().zip(parents) {
            let m = map(&mut old[j]);
            children[j] -= 1;
            *new_map(child) = if children[j] == 0 {
                std::mem::take(m)
            } else {
                m.clone()
            };
        }
    }

    /// Moves the own nodes of the parents of several children (`children`) into the store,
    /// in parallel, each map's into the range [`HexForest::inherit`] chose; the maps then
    /// hold their roots alone.
    fn share<P: Send>(
        &mut self,
        old: &mut [P],
        map: &(impl Fn(&mut P) -> &mut ForestMap<T> + Sync),
        children: &[u32],
    ) {
        let (b0, l0) = (self.branches.len(), self.leaves.len());
        let Some(&(nb, nl)) = self.offsets.last() else {
            return;
        };
        let (nb, nl) = (nb as usize, nl as usize);
        assert!(
            b0 + nb < INDEX as usize && l0 + nl < INDEX as usize,
            "map store beyond 2³⁰ nodes"
        );
        self.branches.resize(b0 + nb, [NONE; LEAF]);
        self.leaves.resize(l0 + nl, [T::default(); LEAF]);
        let range = ShareRange {
            old,
            offsets: &self.offsets,
            children,
            branches: &mut self.branches[b0..],
            leaves: &mut self.leaves[l0..],
            at: (b0 as Link, l0 as Link),
        };
        range.run(map);
    }

    /// Marks every store node the maps of `items` reach, drops the others and renumbers
    /// the links.
    pub fn collect<P: Send>(
        &mut self,
        items: &mut [P],
        map: impl Fn(&mut P) -> &mut ForestMap<T> + Sync,
    ) {
        self.collect_where(items, &map, |_| true);
    }

    /// [`HexForest::collect`] of the maps of the items `live` keeps (the others are dropped
    /// unread).
    fn collect_where<P: Send>(
        &mut self,
        items: &mut [P],
        map: &(impl Fn(&mut P) -> &mut ForestMap<T> + Sync),
        live: impl Fn(usize) -> bool + Sync,
    ) {
        let marks = |n: usize| (0..n.div_ceil(64)).map(|_| AtomicU64::new(0)).collect();
        let (branch_marks, leaf_marks): (Vec<AtomicU64>, Vec<AtomicU64>) =
            (marks(self.branches.len()), marks(self.leaves.len()));
        let store = &*self;
        items
            .par_iter_mut()
            .enumerate()
            .filter(|(i, _)| live(*i))
            .for_each_init(Vec::new, |stack, (_, p)| {
                store.mark(map(p), stack, &branch_marks, &leaf_marks);
            });
        let done = |m: Vec<AtomicU64>| m.into_iter().map(AtomicU64::into_inner).collect();
        let renumber = Renumber::new(done(branch_marks), done(leaf_marks));
        let mut i = 0;
        self.leaves.retain(|_| {
            i += 1;
            renumber.leaf_kept(i - 1)
        });
        let mut i = 0;
        self.branches.retain(|_| {
            i += 1;
            renumber.branch_kept(i - 1)
        });
        let relink = |b: &mut Branch| b.iter_mut().for_each(|c| *c = renumber.link(*c));
        self.branches.par_iter_mut().for_each(relink);
        items.par_iter_mut().enumerate().for_each(|(i, p)| {
            if !live(i) {
                return;
            }
            let m = map(p);
            m.root = renumber.link(m.root);
            m.branches.iter_mut().for_each(relink);
        });
        self.kept_bytes = self.bytes();
        self.collections += 1;
    }

    /// Marks the store nodes `map` reaches (a node already marked was, or is being,
    /// followed from another map).
    fn mark(
        &self,
        map: &ForestMap<T>,
        stack: &mut Vec<Link>,
        branch_marks: &[AtomicU64],
        leaf_marks: &[AtomicU64],
    ) {
        stack.clear();
        stack.push(map.root);
        while let Some(link) = stack.pop() {
            if link == NONE {
                continue;
            }
            let leaf = link & IS_LEAF != 0;
            if link & OWN != 0 {
                if !leaf {
                    stack.extend_from_slice(&map.branches[index(link)]);
                }
                continue;
            }
            let (i, marks) = (index(link), if leaf { leaf_marks } else { branch_marks });
            let bit = 1u64 << (i % 64);
            if marks[i / 64].load(Relaxed) & bit != 0
                || marks[i / 64].fetch_or(bit, Relaxed) & bit != 0
            {
                continue;
            }
            if !leaf {
                stack.extend_from_slice(&self.branches[i]);
            }
        }
    }
}

/// Parents `old` (with their `children`) whose own nodes go to `branches` and `leaves`, at
/// `at` in the store; `offsets` holds where each parent's go, relative, and one past.
struct ShareRange<'a, P, T> {
    old: &'a mut [P],
    offsets: &'a [(Link, Link)],
    children: &'a [u32],
    branches: &'a mut [Branch],
    leaves: &'a mut [[T; LEAF]],
    at: (Link, Link),
}

impl<P: Send, T: Copy + Send + Sync> ShareRange<'_, P, T> {
    /// Moves the nodes, halving the range until it is small.
    fn run(self, map: &(impl Fn(&mut P) -> &mut ForestMap<T> + Sync)) {
        let first = self.offsets[0];
        if self.old.len() <= 256 {
            for (k, p) in self.old.iter_mut().enumerate() {
                if self.children[k] > 1 {
                    let (b, l) = (self.offsets[k].0 - first.0, self.offsets[k].1 - first.1);
                    let m = map(p);
                    let branches = &mut self.branches[b as usize..][..m.branches.len()];
                    let leaves = &mut self.leaves[l as usize..][..m.leaves.len()];
                    m.move_into(branches, leaves, (self.at.0 + b, self.at.1 + l));
                }
            }
            return;
        }
        let mid = self.old.len() / 2;
        let (b, l) = (self.offsets[mid].0 - first.0, self.offsets[mid].1 - first.1);
        let (old_a, old_b) = self.old.split_at_mut(mid);
        let (branches_a, branches_b) = self.branches.split_at_mut(b as usize);
        let (leaves_a, leaves_b) = self.leaves.split_at_mut(l as usize);
        let a = ShareRange {
            old: old_a,
            offsets: &self.offsets[..=mid],
            children: &self.children[..mid],
            branches: branches_a,
            leaves: leaves_a,
            at: self.at,
        };
        let b = ShareRange {
            old: old_b,
            offsets: &self.offsets[mid..],
            children: &self.children[mid..],
            branches: branches_b,
            leaves: leaves_b,
            at: (self.at.0 + b, self.at.1 + l),
        };
        rayon::join(|| a.run(map), || b.run(map));
    }
}

/// The new index of every kept store node: its rank among the kept ones.
struct Renumber {
    branch: (Vec<u64>, Vec<u32>),
    leaf: (Vec<u64>, Vec<u32>),
}

impl Renumber {
    fn new(branch_marks: Vec<u64>, leaf_marks: Vec<u64>) -> Self {
        let ranks = |marks: &[u64]| {
            let mut total = 0;
            marks
                .iter()
                .map(|w| {
                    let r = total;
                    total += w.count_ones();
                    r
                })
                .collect()
        };
        let (branch_ranks, leaf_ranks) = (ranks(&branch_marks), ranks(&leaf_marks));
        Self {
            branch: (branch_marks, branch_ranks),
            leaf: (leaf_marks, leaf_ranks),
        }
    }

    fn kept((marks, _): &(Vec<u64>, Vec<u32>), i: usize) -> bool {
        marks[i / 64] & (1 << (i % 64)) != 0
    }

    fn rank((marks, ranks): &(Vec<u64>, Vec<u32>), i: usize) -> u32 {
        ranks[i / 64] + (marks[i / 64] & ((1 << (i % 64)) - 1)).count_ones()
    }

    fn branch_kept(&self, i: usize) -> bool {
        Self::kept(&self.branch, i)
    }

    fn leaf_kept(&self, i: usize) -> bool {
        Self::kept(&self.leaf, i)
    }

    /// `link` after the collection (own links and [`NONE`] unchanged).
    fn link(&self, link: Link) -> Link {
        match link {
            l if l == NONE || l & OWN != 0 => l,
            l if l & IS_LEAF != 0 => IS_LEAF | Self::rank(&self.leaf, index(l)),
            l => Self::rank(&self.branch, index(l)),
        }
    }
}

#[cfg(test)]
mod tests;
