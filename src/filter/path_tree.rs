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

use super::cluster::{Cluster, ClusterConfig, ClusterPoint, mean_shift};
use crate::map::FloorTopology;

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

/// `certain`, kept in the top bit of [`StoredStep::ancestors`].
const CERTAIN_BIT: u32 = 1 << 31;

/// A smoothed step as the tree keeps it until the end of the walk: 64 bytes, where a
/// [`SmoothedStep`] takes 96. Lossless: every count here is below 2³¹ (particles are capped
/// at `kld.max_particles` ≤ 2·10⁸, clusters at `cluster.max_particles` ≤ 10⁷); a larger
/// one would be kept as 2³¹ − 1.
#[derive(Debug, Clone, Copy)]
struct StoredStep {
    x: f64,
    y: f64,
    z: f64,
    heading: f64,
    spread: f64,
    weight: f64,
    level: i32,
    /// `u32::MAX`: no estimate.
    particles: u32,
    hypotheses: u32,
    /// Distinct ancestors; the top bit is `certain`.
    ancestors: u32,
}

impl StoredStep {
    const NONE: Self = Self {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        heading: 0.0,
        spread: 0.0,
        weight: 0.0,
        level: 0,
        particles: u32::MAX,
        hypotheses: 0,
        ancestors: 0,
    };

    fn store(step: &SmoothedStep) -> Self {
        let count = |n: usize| u32::try_from(n).map_or(CERTAIN_BIT - 1, |n| n.min(CERTAIN_BIT - 1));
        let certain = if step.certain { CERTAIN_BIT } else { 0 };
        let (hypotheses, ancestors) = (count(step.hypotheses), count(step.ancestors) | certain);
        match step.estimate {
            Some(c) => Self {
                x: c.x,
                y: c.y,
                z: c.z,
                heading: c.heading,
                spread: c.spread,
                weight: c.weight,
                level: c.level,
                particles: count(c.particles),
                hypotheses,
                ancestors,
            },
            None => Self {
                hypotheses,
                ancestors,
                ..Self::NONE
            },
        }
    }

    fn get(&self) -> SmoothedStep {
        SmoothedStep {
            estimate: (self.particles != u32::MAX).then_some(Cluster {
                x: self.x,
                y: self.y,
                z: self.z,
                level: self.level,
                heading: self.heading,
                spread: self.spread,
                weight: self.weight,
                particles: self.particles as usize,
            }),
            hypotheses: self.hypotheses as usize,
            certain: self.ancestors & CERTAIN_BIT != 0,
            ancestors: (self.ancestors & !CERTAIN_BIT) as usize,
        }
    }
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
    pub fn new(lag: usize) -> Self {
        Self {
            lag,
            ..Self::default()
        }
    }

    /// Steps covered: `0..=last step` (0 before anything was added).
    pub fn steps(&self) -> usize {
        self.first_step + self.segment_len()
    }

    /// Nodes held now.
    pub fn nodes(&self) -> usize {
        self.chain.len() + self.generations.iter().map(Vec::len).sum::<usize>()
    }

    /// Largest number of nodes held at once (memory: 16 bytes each).
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

    /// The fixed-lag answer for the step `lag` generations before the newest one.
    fn answer_lagged(&mut self, topology: &FloorTopology, cluster: &ClusterConfig) {
        let len = self.segment_len();
        if self.lag == 0 || len <= self.lag {
            return;
        }
        let newest = self.generation(len - 1);
        if newest.len() > cluster.max_particles {
            return;
        }
        let mut weights = vec![1.0f64; newest.len()];
        for g in (len - self.lag..len).rev() {
            weights = parent_weights(self.generation(g), &weights, self.generation(g - 1).len());
        }
        let g = len - 1 - self.lag;
        let answer = centroid(self.generation(g), &weights, topology, cluster.max_spread);
        if self.lagged.len() <= g {
            self.lagged.resize(g + 1, StoredStep::NONE);
        }
        self.lagged[g] = StoredStep::store(&answer);
    }

    /// Fixes the smoothed answer of every step before `step` from the current belief's
    /// ancestry, and forgets the generations from `step` on (they are about to be replaced).
    /// Steps before the first generation kept their earlier answer.
    pub fn cut(&mut self, step: usize, topology: &FloorTopology, cluster: &ClusterConfig) {
        if step < self.first_step {
            self.settled.truncate(step);
        } else {
            let keep = step - self.first_step;
            let answers: Vec<StoredStep> = self
                .answer_current(topology, cluster)
                .take(keep)
                .map(|s| StoredStep::store(&s))
                .collect();
            self.settled.extend(answers);
            self.settled.resize(step, StoredStep::NONE);
        }
        self.chain.clear();
        self.generations.clear();
        self.lagged.clear();
        self.first_step = step;
    }

    /// The smoothed belief at every step `0..self.steps()`: settled steps as they were fixed,
    /// the current segment from the current belief's ancestry.
    pub fn smoothed(&self, topology: &FloorTopology, cluster: &ClusterConfig) -> Vec<SmoothedStep> {
        self.smoothed_iter(topology, cluster).collect()
    }

    /// [`Self::smoothed`] step by step, without holding the walk's answers: the current
    /// segment's live generations are smoothed first, its chain and the settled steps as
    /// they are read.
    pub fn smoothed_iter<'s>(
        &'s self,
        topology: &'s FloorTopology,
        cluster: &'s ClusterConfig,
    ) -> impl Iterator<Item = SmoothedStep> + 's {
        debug_assert_eq!(self.settled.len(), self.first_step);
        self.settled
            .iter()
            .map(StoredStep::get)
            .chain(self.answer_current(topology, cluster))
    }

    /// The current segment's answer: the final ancestry, refined by the fixed-lag answer
    /// where both are certain and agree.
    fn answer_current<'s>(
        &'s self,
        topology: &'s FloorTopology,
        cluster: &'s ClusterConfig,
    ) -> impl Iterator<Item = SmoothedStep> + 's {
        self.smooth_current(topology, cluster)
            .enumerate()
            .map(move |(g, mut full)| {
                let lagged = self.lagged.get(g).map(StoredStep::get);
                if let (Some(l), Some(f)) = (lagged, full.estimate)
                    && full.certain
                    && l.certain
                    && let Some(e) = l.estimate
                    && e.level == f.level
                    && (e.x - f.x).hypot(e.y - f.y) <= cluster.max_spread
                {
                    full = l;
                }
                full
            })
    }

    /// The current segment's generations smoothed: each node weighted by its number of
    /// descendants in the last generation, clustered as the filter clusters its belief. The
    /// live generations are smoothed at once (backwards, as the weights flow); the chain's
    /// nodes, each holding the whole weight, as they are read.
    fn smooth_current<'s>(
        &'s self,
        topology: &'s FloorTopology,
        cluster: &ClusterConfig,
    ) -> impl Iterator<Item = SmoothedStep> + 's {
        let config = heading_free(cluster);
        let mut live = vec![SmoothedStep::NONE; self.generations.len()];
        let mut chain_weight = Vec::new();
        if let Some(last) = self.generations.last() {
            let mut weights = vec![1.0f64; last.len()];
            for (g, generation) in self.generations.iter().enumerate().rev() {
                live[g] = smooth_generation(generation, &weights, topology, &config);
                weights = match g {
                    0 if self.chain.is_empty() => break,
                    0 => parent_weights(generation, &weights, 1),
                    _ => parent_weights(generation, &weights, self.generations[g - 1].len()),
                };
            }
            chain_weight = weights;
        }
        self.chain
            .iter()
            .map(move |n| {
                smooth_generation(std::slice::from_ref(n), &chain_weight, topology, &config)
            })
            .chain(live)
    }

    /// Drops every node without a descendant in the last generation, newest generations
    /// first, stopping at the first generation that loses nothing (the ones before it were
    /// pruned against it already; the chain never loses a node).
    fn prune(&mut self) {
        let remap = &mut self.remap;
        for g in (1..self.generations.len()).rev() {
            let (before, after) = self.generations.split_at_mut(g);
            let (parents, children) = (&mut before[g - 1], &mut after[0]);
            // `remap[i]`: 0 for a parent with children, then its new index; NO_PARENT else.
            remap.clear();
            remap.resize(parents.len(), NO_PARENT);
            for c in children.iter() {
                if c.parent != NO_PARENT {
                    remap[c.parent as usize] = 0;
                }
            }
            if !remap.contains(&NO_PARENT) {
                break;
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
            if parents.capacity() > 2 * parents.len() {
                // Move the few kept nodes out and keep the large buffer for the next
                // generation (fresh large buffers cost a page fault per 4 KiB).
                let large = std::mem::replace(parents, parents.clone());
                if large.capacity() > self.spare.capacity() {
                    self.spare = large;
                }
            }
            for c in children.iter_mut() {
                if c.parent != NO_PARENT {
                    c.parent = remap[c.parent as usize];
                }
            }
        }
    }

    fn note_size(&mut self) {
        self.peak_nodes = self.peak_nodes.max(self.nodes());
    }
}

/// A finished walk's whole-walk answer, computed step by step as it is read, so that a long
/// walk holds its path tree (tens of bytes a step) rather than every step's answer (a hundred):
/// from [`super::Tracker::take_smoothed`] and [`super::RfTracker::take_smoothed`].
#[derive(Debug, Clone)]
pub struct SmoothedWalk<'a> {
    tree: Option<PathTree>,
    topology: &'a FloorTopology,
    cluster: ClusterConfig,
    /// Walk steps before the first tree answer used (`None` there).
    lead: usize,
    /// Tree answers not used (the prior's, for a tracker started with the walk).
    skip: usize,
    /// Walk steps.
    len: usize,
}

impl<'a> SmoothedWalk<'a> {
    /// The answers of `tree`, one per step `0..=steps` (0 = the prior).
    pub fn new(tree: PathTree, topology: &'a FloorTopology, cluster: ClusterConfig) -> Self {
        let len = tree.steps();
        Self {
            tree: Some(tree),
            topology,
            cluster,
            lead: 0,
            skip: 0,
            len,
        }
    }

    /// A walk of `steps` steps without answers (a tracker that never started).
    pub fn empty(topology: &'a FloorTopology, cluster: ClusterConfig, steps: usize) -> Self {
        Self {
            tree: None,
            topology,
            cluster,
            lead: 0,
            skip: 0,
            len: steps,
        }
    }

    /// Places the answers on a walk of `steps` steps whose tracker's prior stands after
    /// the walk's step `before` (1-based; 0: the tracker started with the walk, and the
    /// prior's answer is dropped): the answer after tracker step `g` becomes the walk's step
    /// `before + g` (1-based). Steps without an answer read `None`.
    pub fn on_walk(self, before: usize, steps: usize) -> Self {
        Self {
            lead: before.saturating_sub(1),
            skip: usize::from(before == 0),
            len: steps,
            ..self
        }
    }

    /// Steps of the walk.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True for a walk of no steps.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Largest number of path nodes held at once.
    pub fn path_nodes_peak(&self) -> usize {
        self.tree.as_ref().map_or(0, PathTree::peak_nodes)
    }

    /// The smoothed belief at each step of the walk, in order (`None` where there is none).
    /// Each call recomputes the current segment's answers (about the cost of clustering
    /// each step once).
    pub fn iter(&self) -> impl Iterator<Item = Option<SmoothedStep>> + '_ {
        let answers = self
            .tree
            .iter()
            .flat_map(|t| t.smoothed_iter(self.topology, &self.cluster))
            .skip(self.skip)
            .map(Some);
        std::iter::repeat_n(None, self.lead)
            .chain(answers)
            .chain(std::iter::repeat(None))
            .take(self.len)
    }
}

/// Headings are not stored: smoothed clusters separate by place and floor only.
fn heading_free(cluster: &ClusterConfig) -> ClusterConfig {
    ClusterConfig {
        max_dheading: std::f64::consts::PI,
        ..*cluster
    }
}

/// Each parent's weight: the sum of its children's (`parents` nodes in the generation before).
fn parent_weights(children: &[PathNode], weights: &[f64], parents: usize) -> Vec<f64> {
    let mut out = vec![0.0f64; parents];
    for (node, &w) in children.iter().zip(weights) {
        if node.parent != NO_PARENT {
            out[node.parent as usize] += w;
        }
    }
    out
}

/// The weighted centroid of one generation's nodes, certain when they all stand on one level
/// within an RMS radius of `max_spread` (the fixed-lag answer: it is used only where the
/// whole walk's clusters agree with it, so a mean suffices where mean shift would cost as
/// much as the filter's own clustering).
fn centroid(
    nodes: &[PathNode],
    weights: &[f64],
    topology: &FloorTopology,
    max_spread: f64,
) -> SmoothedStep {
    let total: f64 = weights.iter().sum();
    let Some(first) = nodes.first() else {
        return SmoothedStep::NONE;
    };
    if total.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return SmoothedStep::NONE;
    }
    let level = topology.level(first.surface);
    let (mut x, mut y, mut z) = (0.0, 0.0, 0.0);
    let mut one_level = true;
    for (n, &w) in nodes.iter().zip(weights) {
        x += w * f64::from(n.x);
        y += w * f64::from(n.y);
        z += w * f64::from(topology.z(n.surface));
        one_level &= topology.level(n.surface) == level;
    }
    let (x, y, z) = (x / total, y / total, z / total);
    let spread = (nodes
        .iter()
        .zip(weights)
        .map(|(n, &w)| w * (f64::from(n.x) - x).powi(2) + w * (f64::from(n.y) - y).powi(2))
        .sum::<f64>()
        / total)
        .sqrt();
    let certain = one_level && spread <= max_spread;
    SmoothedStep {
        estimate: Some(Cluster {
            x,
            y,
            z,
            level,
            heading: 0.0,
            spread,
            weight: 1.0,
            particles: nodes.len(),
        }),
        hypotheses: if certain { 1 } else { 0 },
        certain,
        ancestors: nodes.len(),
    }
}

/// One generation's weighted nodes clustered (through a deterministic systematic subsample by
/// weight when there are more than `config.max_particles` of them).
fn smooth_generation(
    nodes: &[PathNode],
    weights: &[f64],
    topology: &FloorTopology,
    config: &ClusterConfig,
) -> SmoothedStep {
    let total: f64 = weights.iter().sum();
    if nodes.is_empty() || total.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return SmoothedStep::NONE;
    }
    let point = |n: &PathNode, weight: f32| ClusterPoint {
        x: n.x,
        y: n.y,
        z: topology.z(n.surface),
        level: topology.level(n.surface),
        heading: 0.0,
        weight,
    };
    let max = config.max_particles.max(1);
    let points: Vec<ClusterPoint> = if nodes.len() <= max {
        nodes
            .iter()
            .zip(weights)
            .map(|(n, &w)| point(n, w as f32))
            .collect()
    } else {
        // Systematic selection at fixed offsets: `max` equally weighted points.
        let mut out = Vec::with_capacity(max);
        let mut cumulative = 0.0;
        let mut j = 0usize;
        for (n, &w) in nodes.iter().zip(weights) {
            cumulative += w;
            while j < max && (j as f64 + 0.5) / max as f64 * total < cumulative {
                out.push(point(n, 1.0));
                j += 1;
            }
        }
        out
    };
    let clusters = mean_shift(&points, config);
    SmoothedStep {
        estimate: clusters.first().copied(),
        hypotheses: clusters.len(),
        certain: clusters.len() == 1 && clusters[0].spread <= config.max_spread,
        ancestors: nodes.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stored_steps_are_lossless() {
        let certain = SmoothedStep {
            estimate: Some(Cluster {
                x: 1.25,
                y: -3.5,
                z: 6.0,
                level: 2,
                heading: 0.3,
                spread: 0.7,
                weight: 0.99,
                particles: 512,
            }),
            hypotheses: 1,
            certain: true,
            ancestors: 40,
        };
        let unsure = SmoothedStep {
            certain: false,
            hypotheses: 3,
            ..certain
        };
        let bare = SmoothedStep {
            ancestors: 7,
            ..SmoothedStep::NONE
        };
        for s in [certain, unsure, bare, SmoothedStep::NONE] {
            assert_eq!(StoredStep::store(&s).get(), s);
        }
        assert_eq!(std::mem::size_of::<StoredStep>(), 64);
    }

    use crate::map::TopologyConfig;

    fn topology() -> FloorTopology {
        let tower = crate::sim::Tower::new(&Default::default()).expect("tower");
        FloorTopology::build(&tower.plan, &TopologyConfig::default()).expect("topology")
    }

    fn node(x: f32) -> PathNode {
        PathNode::new(x, 0.0, 0)
    }

    #[test]
    fn pruning_keeps_exactly_the_ancestors_of_the_last_generation() {
        let topo = topology();
        let cluster = ClusterConfig::default();
        let mut tree = PathTree::new(0);
        tree.root(0, (0..4).map(|i| node(i as f32)).collect(), &topo, &cluster);
        // Generation 1: everybody descends from 1 and 3.
        tree.push(
            (0..4).map(|i| node(10.0 + i as f32)),
            &[1, 1, 3, 3],
            &topo,
            &cluster,
        );
        assert_eq!(tree.generations[0].len(), 2);
        assert_eq!(tree.generations[0][0].x, 1.0);
        assert_eq!(tree.generations[0][1].x, 3.0);
        // Generation 2: everybody descends from generation 1's node 2 (child of 3).
        tree.push(
            (0..3).map(|i| node(20.0 + i as f32)),
            &[2, 2, 2],
            &topo,
            &cluster,
        );
        assert_eq!(tree.nodes(), 1 + 1 + 3);
        // The two one-node generations are the chain now.
        assert_eq!(tree.chain.len(), 2);
        assert_eq!(tree.chain[0].x, 3.0);
        assert_eq!(tree.chain[1].x, 12.0);
        assert_eq!(tree.generations.len(), 1);
        assert_eq!(tree.generations[0][0].parent, 0);
        assert_eq!(tree.steps(), 3);
        assert_eq!(tree.peak_nodes(), 9);
    }

    #[test]
    fn smoothed_steps_follow_the_surviving_line() {
        let topo = topology();
        let cluster = ClusterConfig::default();
        let mut tree = PathTree::new(0);
        // Two hypotheses 30 m apart; the left one dies at step 2.
        tree.root(
            0,
            vec![node(0.0), node(0.0), node(30.0), node(30.0)],
            &topo,
            &cluster,
        );
        tree.push(
            vec![node(1.0), node(1.0), node(31.0), node(31.0)],
            &[0, 1, 2, 3],
            &topo,
            &cluster,
        );
        let filtered = tree.smoothed(&topo, &cluster);
        assert_eq!(filtered[1].hypotheses, 2);
        assert!(!filtered[1].certain);
        tree.push(vec![node(32.0); 4], &[2, 2, 3, 3], &topo, &cluster);
        let s = tree.smoothed(&topo, &cluster);
        assert_eq!(s.len(), 3);
        for (k, x) in [(0, 30.0), (1, 31.0), (2, 32.0)] {
            let e = s[k].estimate.expect("estimate");
            assert!((e.x - x).abs() < 1e-6, "step {k}: {}", e.x);
            assert!(s[k].certain && s[k].hypotheses == 1);
        }
    }

    #[test]
    fn a_cut_settles_the_steps_before_it() {
        let topo = topology();
        let cluster = ClusterConfig::default();
        let mut tree = PathTree::new(0);
        tree.root(0, vec![node(5.0)], &topo, &cluster);
        tree.push(vec![node(6.0)], &[0], &topo, &cluster);
        tree.push(vec![node(7.0)], &[0], &topo, &cluster);
        // Re-seeded at step 2: steps 0 and 1 keep their answer, 2 is replaced.
        tree.root(2, vec![node(40.0)], &topo, &cluster);
        tree.push(vec![node(41.0)], &[0], &topo, &cluster);
        let s = tree.smoothed(&topo, &cluster);
        let xs: Vec<f64> = s.iter().map(|k| k.estimate.expect("e").x).collect();
        assert_eq!(xs, vec![5.0, 6.0, 40.0, 41.0]);
        // A fresh start after the end leaves no gap unexplained.
        tree.root(6, vec![node(50.0)], &topo, &cluster);
        let s = tree.smoothed(&topo, &cluster);
        assert_eq!(s.len(), 7);
        assert!(s[4].estimate.is_none() && s[5].estimate.is_none());
        assert_eq!(s[3].estimate.expect("kept").x, 41.0);
    }
}
