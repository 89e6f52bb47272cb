//! The ancestry tree of particles (GMapping's trajectory tree, reduced to indices).
//!
//! A particle's whole path is a function of the step measurements and the random streams
//! it drew from: at step `k` it used the stream of the index it held then. So instead of
//! storing poses we store, per resampling, which index a particle held from which step
//! on, linked to its parent. Nodes are shared by descendants and freed when no
//! particle descends from them; the best particle's path is replayed from its chain.

use std::sync::Arc;

/// One segment of a particle's ancestry: from step `from_step` on it held `index`.
#[derive(Debug)]
pub struct Lineage {
    parent: Option<Arc<Lineage>>,
    from_step: u32,
    index: u32,
}

impl Lineage {
    /// The root of a particle that holds `index` from step 0.
    #[must_use]
    pub fn root(index: u32) -> Arc<Self> {
        Arc::new(Self {
            parent: None,
            from_step: 0,
            index,
        })
    }

    /// A child of `parent` that holds `index` from step `from_step` on.
    #[must_use]
    pub fn child(parent: &Arc<Self>, from_step: u32, index: u32) -> Arc<Self> {
        Arc::new(Self {
            parent: Some(Arc::clone(parent)),
            from_step,
            index,
        })
    }

    /// The particle index held at each step `0..steps`, oldest first.
    #[must_use]
    pub fn indices(self: &Arc<Self>, steps: usize) -> Vec<u32> {
        let mut out = vec![0u32; steps];
        let mut end = steps;
        let mut node = Some(self);
        while let Some(n) = node {
            let start = (n.from_step as usize).min(end);
            out[start..end].fill(n.index);
            end = start;
            node = n.parent.as_ref();
        }
        out
    }
}

impl Drop for Lineage {
    /// Unlinks long chains iteratively so dropping a deep ancestry cannot overflow the stack.
    fn drop(&mut self) {
        let mut parent = self.parent.take();
        while let Some(p) = parent {
            match Arc::try_unwrap(p) {
                Ok(mut owned) => parent = owned.parent.take(),
                Err(_) => break,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn indices_follow_the_chain() {
        let root = Lineage::root(3);
        let a = Lineage::child(&root, 2, 7);
        let b = Lineage::child(&a, 5, 1);
        assert_eq!(b.indices(6), vec![3, 3, 7, 7, 7, 1]);
        assert_eq!(a.indices(4), vec![3, 3, 7, 7]);
    }

    #[test]
    fn deep_chains_drop_without_overflow() {
        let mut node = Lineage::root(0);
        for k in 1..200_000 {
            node = Lineage::child(&node, k, k % 5);
        }
        drop(node);
    }
}
