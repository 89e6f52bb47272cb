//! A sparse, persistent (copy-on-write) store of one small record per hexagon, for maps
//! that every particle of a filter owns and most particles share: FootSLAM's transition
//! counts ([`super::hex_transitions`]) and the magnetic field map ([`super::field_map`]).
//!
//! Hexagons live in leaves of 4×4 hexagons under a persistent quadtree of 4×4-way branch
//! nodes, every node an [`Arc`]. Cloning a tree (resampling) is one reference-count
//! increment; a write copies only the nodes on the path to the leaf that are still shared
//! ([`Arc::make_mut`]), as GMapping shares map patches between particles. The tree grows
//! upwards as the walk leaves its extent, so no size is fixed; the whole `i32 × i32` axial
//! key space is addressable.

use hexx::Hex;
use std::sync::Arc;

/// Hexagons per leaf.
pub const LEAF: usize = 16;

/// Bias that puts the axial origin at two thirds of a block at every tree level, so that
/// walks around the origin need a shallow tree.
const KEY_OFFSET: u32 = 0xAAAA_AAAA;
/// The deepest tree: 4^15 leaves of 4 hexagons cover the whole `u32` key range.
pub(super) const MAX_LEVEL: u8 = 15;

#[derive(Debug, Clone)]
enum Node<T> {
    Branch([Option<Arc<Node<T>>>; LEAF]),
    Leaf([T; LEAF]),
}

/// The leaf block of a hexagon (its key), and its slot within the leaf.
pub type LeafKey = (u32, u32);

/// A copy-on-write map from hexagons to records `T` (`T::default()` where nothing is stored).
#[derive(Debug, Clone)]
pub struct HexTree<T> {
    root: Option<Arc<Node<T>>>,
    /// Height of the root above the leaves (0: the root is a leaf).
    level: u8,
    /// Block coordinates of the root at its level.
    base: LeafKey,
}

impl<T> Default for HexTree<T> {
    fn default() -> Self {
        Self {
            root: None,
            level: 0,
            base: (0, 0),
        }
    }
}

/// Leaf-block coordinates and the index within the leaf of a hexagon.
#[must_use]
pub fn locate(h: Hex) -> (LeafKey, usize) {
    let u = h.x.cast_unsigned().wrapping_add(KEY_OFFSET);
    let v = h.y.cast_unsigned().wrapping_add(KEY_OFFSET);
    ((u >> 2, v >> 2), ((u & 3) + 4 * (v & 3)) as usize)
}

/// The hexagon in `slot` of leaf block `leaf` ([`locate`]'s inverse).
#[must_use]
pub fn hex_of((bx, by): LeafKey, slot: usize) -> Hex {
    let u = bx * 4 + (slot as u32 & 3);
    let v = by * 4 + (slot as u32 >> 2);
    Hex::new(
        u.wrapping_sub(KEY_OFFSET).cast_signed(),
        v.wrapping_sub(KEY_OFFSET).cast_signed(),
    )
}

pub(super) fn child_index((lx, ly): LeafKey, level: u8) -> usize {
    let shift = 2 * (u32::from(level) - 1);
    (((lx >> shift) & 3) + 4 * ((ly >> shift) & 3)) as usize
}

pub(super) fn block_at((lx, ly): LeafKey, level: u8) -> LeafKey {
    let shift = 2 * u32::from(level);
    if shift >= 32 {
        (0, 0)
    } else {
        (lx >> shift, ly >> shift)
    }
}

impl<T: Copy + Default> HexTree<T> {
    /// An empty tree.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// The record of `h` (the default where none is stored).
    pub fn get(&self, h: Hex) -> T {
        let (leaf, slot) = locate(h);
        self.leaf(leaf).map_or_else(T::default, |cells| cells[slot])
    }

    /// The leaf of leaf block `leaf`, if stored.
    #[must_use]
    pub fn leaf(&self, leaf: LeafKey) -> Option<&[T; LEAF]> {
        if block_at(leaf, self.level) != self.base {
            return None;
        }
        let mut node = self.root.as_deref()?;
        let mut level = self.level;
        loop {
            match node {
                Node::Leaf(cells) => return Some(cells),
                Node::Branch(children) => {
                    node = children[child_index(leaf, level)].as_deref()?;
                    level -= 1;
                }
            }
        }
    }

    /// Grows the tree upwards until its root block covers `leaf`.
    fn cover(&mut self, leaf: LeafKey) {
        if self.root.is_none() {
            self.level = 0;
            self.base = leaf;
            return;
        }
        while block_at(leaf, self.level) != self.base && self.level < MAX_LEVEL {
            let mut children: [Option<Arc<Node<T>>>; LEAF] = Default::default();
            let (bx, by) = self.base;
            children[((bx & 3) + 4 * (by & 3)) as usize] = self.root.take();
            self.root = Some(Arc::new(Node::Branch(children)));
            self.level += 1;
            self.base = (bx >> 2, by >> 2);
        }
    }

    /// The mutable leaf of leaf block `leaf`, copying shared nodes on the way down and
    /// creating missing ones.
    pub fn leaf_mut(&mut self, leaf: LeafKey) -> &mut [T; LEAF] {
        self.cover(leaf);
        let mut level = self.level;
        let new_node = |level: u8| {
            Arc::new(if level == 0 {
                Node::Leaf([T::default(); LEAF])
            } else {
                Node::Branch(Default::default())
            })
        };
        let mut node = self.root.get_or_insert_with(|| new_node(level));
        loop {
            match Arc::make_mut(node) {
                Node::Leaf(cells) => return cells,
                Node::Branch(children) => {
                    let child = &mut children[child_index(leaf, level)];
                    level -= 1;
                    node = child.get_or_insert_with(|| new_node(level));
                }
            }
        }
    }

    /// The mutable record of `h` (see [`HexTree::leaf_mut`]).
    pub fn get_mut(&mut self, h: Hex) -> &mut T {
        let (leaf, slot) = locate(h);
        &mut self.leaf_mut(leaf)[slot]
    }

    /// Calls `f` with every stored hexagon and its record (defaults included), leaf by
    /// leaf in no particular order.
    pub fn for_each(&self, mut f: impl FnMut(Hex, &T)) {
        let Some(root) = &self.root else { return };
        let mut stack = vec![(root.as_ref(), self.level, self.base)];
        while let Some((node, level, (bx, by))) = stack.pop() {
            match node {
                Node::Branch(children) => {
                    for (i, c) in children.iter().enumerate() {
                        if let Some(c) = c {
                            let (cx, cy) = (bx * 4 + (i as u32 & 3), by * 4 + (i as u32 >> 2));
                            stack.push((c.as_ref(), level - 1, (cx, cy)));
                        }
                    }
                }
                Node::Leaf(cells) => {
                    for (slot, c) in cells.iter().enumerate() {
                        f(hex_of((bx, by), slot), c);
                    }
                }
            }
        }
    }

    /// Bytes held by nodes not shared with any other tree (a lower bound on what this
    /// tree alone keeps alive); shared nodes are not counted.
    pub fn unshared_bytes(&self) -> usize {
        fn walk<T>(node: &Arc<Node<T>>) -> usize {
            if Arc::strong_count(node) > 1 {
                return 0;
            }
            let own = std::mem::size_of::<Node<T>>() + 2 * std::mem::size_of::<usize>();
            match node.as_ref() {
                Node::Leaf(_) => own,
                Node::Branch(children) => own + children.iter().flatten().map(walk).sum::<usize>(),
            }
        }
        self.root.as_ref().map_or(0, walk)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locate_and_hex_of_are_inverse() {
        for h in [
            Hex::new(0, 0),
            Hex::new(-1, 3),
            Hex::new(i32::MAX, i32::MIN),
            Hex::new(-123_456, 98_765),
        ] {
            let (leaf, slot) = locate(h);
            assert_eq!(hex_of(leaf, slot), h);
        }
    }

    #[test]
    fn writes_copy_only_what_is_shared() {
        let mut t: HexTree<u32> = HexTree::new();
        for q in -40..40 {
            *t.get_mut(Hex::new(q, 7)) += q as u32;
        }
        let whole = t.unshared_bytes();
        let c = t.clone();
        assert_eq!(t.unshared_bytes(), 0);
        *t.get_mut(Hex::new(3, 7)) = 99;
        assert_eq!(t.get(Hex::new(3, 7)), 99);
        assert_eq!(c.get(Hex::new(3, 7)), 3, "the clone is unchanged");
        assert!(t.unshared_bytes() > 0 && t.unshared_bytes() < whole);
        let mut seen = 0;
        t.for_each(|h, &v| {
            if h.y == 7 && (-40..40).contains(&h.x) {
                seen += 1;
                assert!(v == 99 || v == h.x as u32);
            } else {
                assert_eq!(v, 0);
            }
        });
        assert_eq!(seen, 80);
        assert_eq!(t.get(Hex::new(1_000_000, -5)), 0, "outside the extent");
    }
}
