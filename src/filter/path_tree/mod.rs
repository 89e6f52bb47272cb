//! Path storage for the whole-walk (smoothed) answer of a particle filter: the ancestral
//! lines of the final cloud.
//!
//! After step `T` every particle of the belief carries, through its chain of resampling
//! ancestors, one whole path `s_0 … s_T`. The equally weighted final particles' paths are a
//! sample of the joint smoothing distribution `p(s_0:T | z_1:T)` (Kitagawa 1996, sec. 4.1;
//! Doucet & Johansen's "genealogical tree"), so the smoothed belief at step `k` is the cloud
//! of the final particles' ancestors at `k`, each weighted by its number of descendants.
//!
//! Storing every particle of every step is out of reach at 10⁶ particles, but most of it has
//! no descendant left: ancestries coalesce backwards in time. The tree keeps one node
//! (position, surface and parent: 16 bytes) for each particle that still has a descendant in
//! the current belief, and prunes the rest after every step — Jacob, Murray & Rubenthaler
//! (2015, "Path storage in the particle filter"), whose bound on the expected size is
//! `T + C·N·log N` nodes. Pruning walks back from the newest generation and stops at the
//! first generation that loses nothing, so its cost is that of the nodes it removes plus
//! one pass over the previous generation.
//!
//! A belief that is not descended from the last one (a fresh prior after every particle died,
//! or particles re-seeded about an earlier belief) cuts the tree: the steps before the cut are
//! smoothed with what was known then and kept as they are ([`PathTree::cut`]).
//!
//! Everything here is sequential and deterministic: the answer does not depend on the number
//! of threads.
//!
//! The pieces, one file each:
//! * this file — the tree: nodes, generations, pruning, coalescing and cuts
//! * `smoothing` — the answers read from it: each generation weighted by its descendants and
//!   clustered, and the fixed-lag answer
//! * `stored_step` — a smoothed step as the tree keeps it (64 bytes)
//! * `smoothed_walk` — a finished walk's answer, computed as it is read ([`SmoothedWalk`])

mod smoothed_walk;
mod smoothing;
mod stored_step;
#[cfg(test)]
mod tests;

pub use smoothed_walk::SmoothedWalk;

use super::cluster::{Cluster, ClusterConfig};
use crate::map::FloorTopology;
use rayon::prelude::*;
use stored_step::StoredStep;

/// Marks a node without a parent (a root of the current segment).
const NO_PARENT: u32 = u32::MAX;

/// One stored particle: where it stood after its step, and its parent in the generation
/// before. 16 bytes.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C)]
pub struct PathNode {
    /// East, metres.
    pub x: f32,
    /// North, metres.
    pub y: f32,
    /// Floor surface index.
    pub surface: u32,
    parent: u32,
}

impl PathNode {
    /// A node at `(x, y)` on `surface`.
    #[must_use]
    pub fn new(x: f32, y: f32, surface: u32) -> Self {
        Self {
            x,
            y,
            surface,
            parent: NO_PARENT,
        }
    }
}

/// The smoothed belief at one step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SmoothedStep {
    /// The heaviest cluster of the final particles' ancestors at this step (`None` when the
    /// step has no stored ancestors).
    pub estimate: Option<Cluster>,
    /// Clusters among the ancestors (holding at least `min_weight` of them).
    pub hypotheses: usize,
    /// True when the ancestors form one cluster no wider than `max_spread`: the walker's
    /// place at this step is known, whatever the filter believed then.
    pub certain: bool,
    /// Distinct ancestors at this step.
    pub ancestors: usize,
}

impl SmoothedStep {
    const NONE: Self = Self {
        estimate: None,
        hypotheses: 0,
        certain: false,
        ancestors: 0,
    };
}

/// The ancestry of the current belief, generation by generation, pruned to the nodes that
/// still have descendants.
///
/// Memory on a long walk: the current segment's coalesced start is one node a step (16
/// bytes) in [`Self::chain`](#structfield.chain), its fixed-lag answers 64 bytes a step, and
/// the steps settled by earlier cuts 64 bytes a step; only the generations since the last
/// coalescence hold several nodes.
#[derive(Debug, Clone, Default)]
pub struct PathTree {
    /// Lag of the fixed-lag answer (0 = none).
    lag: usize,
    /// Fixed-lag answers of the current segment, by step − `first_step` (`NONE` where not
    /// computed).
    lagged: Vec<StoredStep>,
    /// First step of the current segment.
    first_step: usize,
    /// The current segment's coalesced start: one node per step from `first_step` on, each
    /// the only ancestor of everything after it. The first generation after the chain
    /// descends from its last node.
    chain: Vec<PathNode>,
    /// The generations after the chain, one per step; the last is the current belief.
    generations: Vec<Vec<PathNode>>,
    /// Smoothed steps `0..first_step`, fixed by earlier cuts.
    settled: Vec<StoredStep>,
    /// Largest number of nodes held at once.
    peak_nodes: usize,
    /// A pruned generation's buffer, reused by the next one.
    spare: Vec<PathNode>,
    /// Scratch of the pruning pass.
    remap: Vec<u32>,
}

impl PathTree {
    /// An empty tree whose answer at a step is, where the whole walk is sure of the place,
    /// the ancestry `lag` steps later (0: the final belief's ancestry only).
    ///
    /// Why a lag: the final belief's ancestors at an early step have coalesced into one or a
    /// few particles, whose paths carry every step's motion noise; `lag` steps on, the same
    /// step still has many distinct ancestors to average, and they have seen the walls of
    /// the next `lag` steps. The whole walk decides where that answer is trusted: only where
    /// the final ancestry holds one hypothesis and agrees with it (within `max_spread`).
    #[must_use]
    pub fn new(lag: usize) -> Self {
        Self {
            lag,
            ..Self::default()
        }
    }

    /// Steps covered: `0..=last step` (0 before anything was added).
    #[must_use]
    pub fn steps(&self) -> usize {
        self.first_step + self.segment_len()
    }

    /// Nodes held now.
    pub fn nodes(&self) -> usize {
        self.chain.len() + self.generations.iter().map(Vec::len).sum::<usize>()
    }

    /// Largest number of nodes held at once (memory: 16 bytes each).
    #[must_use]
    pub fn peak_nodes(&self) -> usize {
        self.peak_nodes
    }

    /// Starts a new segment at `step` whose particles have no ancestors: the steps before
    /// it are smoothed with the current belief's ancestry ([`Self::cut`]) and steps from
    /// `step` on are replaced.
    pub fn root(
        &mut self,
        step: usize,
        nodes: Vec<PathNode>,
        topology: &FloorTopology,
        cluster: &ClusterConfig,
    ) {
        self.cut(step, topology, cluster);
        // Nodes made outside the tree have no parent (`PathNode::new`).
        self.generations.push(nodes);
        self.note_size();
    }

    /// Adds the next generation: `nodes[i]` descends from node `ancestors[i]` of the current
    /// last generation. Then prunes the nodes without descendants and, when the new belief
    /// is small enough to cluster (`cluster.max_particles`), answers for the step `lag`
    /// steps back.
    ///
    /// # Panics
    /// In debug builds, when the lengths differ or an ancestor is out of range.
    pub fn push(
        &mut self,
        nodes: impl IntoIterator<Item = PathNode>,
        ancestors: &[u32],
        topology: &FloorTopology,
        cluster: &ClusterConfig,
    ) {
        debug_assert!(!self.generations.is_empty(), "push before root");
        let previous = self.generations.last().map_or(0, Vec::len);
        let mut generation = std::mem::take(&mut self.spare);
        generation.clear();
        generation.extend(nodes.into_iter().zip(ancestors).map(|(n, &a)| {
            debug_assert!((a as usize) < previous);
            PathNode { parent: a, ..n }
        }));
        self.add_generation(generation, ancestors, topology, cluster);
    }

    /// [`Self::push`] from a parallel iterator: a large generation is written by every
    /// thread (the same nodes).
    pub fn push_parallel(
        &mut self,
        nodes: impl IndexedParallelIterator<Item = PathNode>,
        ancestors: &[u32],
        topology: &FloorTopology,
        cluster: &ClusterConfig,
    ) {
        debug_assert!(!self.generations.is_empty(), "push before root");
        let previous = self.generations.last().map_or(0, Vec::len);
        let mut generation = std::mem::take(&mut self.spare);
        generation.clear();
        generation.par_extend(nodes.zip(ancestors.par_iter()).map(|(n, &a)| {
            debug_assert!((a as usize) < previous);
            PathNode { parent: a, ..n }
        }));
        self.add_generation(generation, ancestors, topology, cluster);
    }

    /// The end of [`Self::push`]: `generation` appended, then pruning, coalescing and the
    /// lagged answer.
    fn add_generation(
        &mut self,
        generation: Vec<PathNode>,
        ancestors: &[u32],
        topology: &FloorTopology,
        cluster: &ClusterConfig,
    ) {
        debug_assert_eq!(generation.len(), ancestors.len());
        self.generations.push(generation);
        self.note_size();
        self.prune();
        self.coalesce();
        self.answer_lagged(topology, cluster);
    }

    /// Generations of the current segment (chain and live ones).
    fn segment_len(&self) -> usize {
        self.chain.len() + self.generations.len()
    }

    /// Generation `g` of the current segment.
    fn generation(&self, g: usize) -> &[PathNode] {
        match g.checked_sub(self.chain.len()) {
            None => std::slice::from_ref(&self.chain[g]),
            Some(i) => &self.generations[i],
        }
    }

    /// Moves the leading one-node generations into the chain: nothing after them can prune
    /// them (every later node descends from their one node), so each keeps 16 bytes instead
    /// of a buffer of its own.
    fn coalesce(&mut self) {
        if self.generations.last().is_none_or(Vec::is_empty) {
            return;
        }
        let single = self.generations[..self.generations.len() - 1]
            .iter()
            .take_while(|g| g.len() == 1)
            .count();
        if single > 0 {
            self.chain
                .extend(self.generations.drain(..single).map(|g| g[0]));
        }
    }

    /// Fixes the smoothed answer of every step before `step` from the current belief's
    /// ancestry, and forgets the generations from `step` on (they are about to be replaced).
    /// Steps before the first generation kept their earlier answer.
    pub fn cut(&mut self, step: usize, topology: &FloorTopology, cluster: &ClusterConfig) {
        if step < self.first_step {
            self.settled.truncate(step);
        } else {
            // Settled straight from the answer as it is read (no copy of the segment's).
            let keep = step - self.first_step;
            let mut settled = std::mem::take(&mut self.settled);
            settled.extend(
                self.answer_current(topology, cluster)
                    .take(keep)
                    .map(|s| StoredStep::store(&s)),
            );
            settled.resize(step, StoredStep::NONE);
            self.settled = settled;
        }
        self.chain.clear();
        self.generations.clear();
        self.lagged.clear();
        self.first_step = step;
    }

    /// Drops every node without a descendant in the last generation, newest generations
    /// first, stopping at the first generation that loses nothing (the ones before it were
    /// pruned against it already; the chain never loses a node).
    fn prune(&mut self) {
        for g in (1..self.generations.len()).rev() {
            let (before, after) = self.generations.split_at_mut(g);
            let (parents, children) = (&mut before[g - 1], &mut after[0]);
            let lost = match prune_sorted(parents, children) {
                Some(lost) => lost,
                None => prune_any(parents, children, &mut self.remap),
            };
            if !lost {
                break;
            }
            if parents.capacity() > 2 * parents.len() {
                // Move the few kept nodes out and keep the large buffer for the next
                // generation (fresh large buffers cost a page fault per 4 KiB).
                let kept: Vec<PathNode> = parents.par_iter().copied().collect();
                let large = std::mem::replace(parents, kept);
                if large.capacity() > self.spare.capacity() {
                    self.spare = large;
                }
            }
        }
    }

    fn note_size(&mut self) {
        self.peak_nodes = self.peak_nodes.max(self.nodes());
    }
}

/// Prunes `parents` against `children` whose parent links are in increasing order (as
/// systematic resampling writes them, and as pruning keeps them): the kept parents are the
/// distinct links in order, so one pass copies each kept parent down to its new place and
/// relinks its children — no scratch, two passes over the children (one to count, one to
/// compact). Returns whether a parent was dropped, or `None` (nothing changed) when the links
/// are not in order or one has no parent.
fn prune_sorted(parents: &mut Vec<PathNode>, children: &mut [PathNode]) -> Option<bool> {
    let m = parents.len();
    let mut distinct = 0usize;
    let mut previous = None;
    for c in children.iter() {
        let p = c.parent;
        if p as usize >= m {
            return None;
        }
        match previous {
            Some(q) if p < q => return None,
            Some(q) if p == q => {}
            _ => distinct += 1,
        }
        previous = Some(p);
    }
    if distinct == m {
        return Some(false);
    }
    // `kept` ≤ the parent's index: each kept parent moves down over dropped ones only.
    let mut kept = 0u32;
    let mut previous = NO_PARENT;
    for c in children.iter_mut() {
        if c.parent != previous {
            previous = c.parent;
            parents[kept as usize] = parents[previous as usize];
            kept += 1;
        }
        c.parent = kept - 1;
    }
    parents.truncate(kept as usize);
    Some(true)
}

/// Prunes `parents` against `children` linked in any order, through `remap` (scratch).
/// Returns whether a parent was dropped.
fn prune_any(parents: &mut Vec<PathNode>, children: &mut [PathNode], remap: &mut Vec<u32>) -> bool {
    // `remap[i]`: 0 for a parent with children, then its new index; NO_PARENT else.
    remap.clear();
    remap.resize(parents.len(), NO_PARENT);
    for c in children.iter() {
        if c.parent != NO_PARENT {
            remap[c.parent as usize] = 0;
        }
    }
    if !remap.contains(&NO_PARENT) {
        return false;
    }
    let mut kept = 0u32;
    for (i, r) in remap.iter_mut().enumerate() {
        if *r == 0 {
            *r = kept;
            parents[kept as usize] = parents[i];
            kept += 1;
        }
    }
    parents.truncate(kept as usize);
    for c in children.iter_mut() {
        if c.parent != NO_PARENT {
            c.parent = remap[c.parent as usize];
        }
    }
    true
}
