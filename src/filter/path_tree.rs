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

/// A fixed-lag answer as the tree keeps it until the end: only a certain one is ever used,
/// so only a certain one is kept, in 64 bytes (an `Option<SmoothedStep>` takes 96, every
/// step of the walk). Lossless: counts below 2³² are kept exactly.
#[derive(Debug, Clone, Copy)]
struct LaggedAnswer {
    x: f64,
    y: f64,
    z: f64,
    heading: f64,
    spread: f64,
    weight: f64,
    level: i32,
    /// `u32::MAX`: no answer kept.
    particles: u32,
    hypotheses: u32,
    ancestors: u32,
}

impl LaggedAnswer {
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

    /// `answer` when certain and its counts fit, else [`Self::NONE`].
    fn keep(answer: &SmoothedStep) -> Self {
        let fits = |n: usize| u32::try_from(n).ok().filter(|&n| n < u32::MAX);
        match (answer.estimate, answer.certain) {
            (Some(c), true) => match (
                fits(c.particles),
                fits(answer.hypotheses),
                fits(answer.ancestors),
            ) {
                (Some(particles), Some(hypotheses), Some(ancestors)) => Self {
                    x: c.x,
                    y: c.y,
                    z: c.z,
                    heading: c.heading,
                    spread: c.spread,
                    weight: c.weight,
                    level: c.level,
                    particles,
                    hypotheses,
                    ancestors,
                },
                _ => Self::NONE,
            },
            _ => Self::NONE,
        }
    }

    /// The answer kept, `None` when none.
    fn get(&self) -> Option<SmoothedStep> {
        (self.particles != u32::MAX).then_some(SmoothedStep {
            estimate: Some(Cluster {
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
            certain: true,
            ancestors: self.ancestors as usize,
        })
    }
}

/// The ancestry of the current belief, generation by generation, pruned to the nodes that
/// still have descendants.
#[derive(Debug, Clone, Default)]
pub struct PathTree {
    /// Lag of the fixed-lag answer (0 = none).
    lag: usize,
    /// Fixed-lag answers by step (`None` where not computed).
    lagged: Vec<LaggedAnswer>,
    /// Step of `generations[0]`.
    first_step: usize,
    /// One generation per step from `first_step` on; the last is the current belief.
    generations: Vec<Vec<PathNode>>,
    /// Smoothed steps `0..first_step`, fixed by earlier cuts.
    settled: Vec<SmoothedStep>,
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
        self.first_step + self.generations.len()
    }

    /// Nodes held now.
    pub fn nodes(&self) -> usize {
        self.generations.iter().map(Vec::len).sum()
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
        self.lagged.truncate(step);
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
        self.answer_lagged(topology, cluster);
    }

    /// The fixed-lag answer for the step `lag` generations before the newest one.
    fn answer_lagged(&mut self, topology: &FloorTopology, cluster: &ClusterConfig) {
        let len = self.generations.len();
        if self.lag == 0 || len <= self.lag {
            return;
        }
        let newest = &self.generations[len - 1];
        if newest.len() > cluster.max_particles {
            return;
        }
        let mut weights = vec![1.0f64; newest.len()];
        for g in (len - self.lag..len).rev() {
            weights = parent_weights(
                &self.generations[g],
                &weights,
                self.generations[g - 1].len(),
            );
        }
        let g = len - 1 - self.lag;
        let step = self.first_step + g;
        let answer = centroid(&self.generations[g], &weights, topology, cluster.max_spread);
        if self.lagged.len() <= step {
            self.lagged.resize(step + 1, LaggedAnswer::NONE);
        }
        self.lagged[step] = LaggedAnswer::keep(&answer);
    }

    /// Fixes the smoothed answer of every step before `step` from the current belief's
    /// ancestry, and forgets the generations from `step` on (they are about to be replaced).
    /// Steps before the first generation kept their earlier answer.
    pub fn cut(&mut self, step: usize, topology: &FloorTopology, cluster: &ClusterConfig) {
        if step < self.first_step {
            self.settled.truncate(step);
        } else {
            let smoothed = self.answer_current(topology, cluster);
            let keep = (step - self.first_step).min(smoothed.len());
            self.settled.extend_from_slice(&smoothed[..keep]);
            self.settled.resize(step, SmoothedStep::NONE);
        }
        self.generations.clear();
        self.first_step = step;
    }

    /// The smoothed belief at every step `0..self.steps()`: settled steps as they were fixed,
    /// the current segment from the current belief's ancestry.
    pub fn smoothed(&self, topology: &FloorTopology, cluster: &ClusterConfig) -> Vec<SmoothedStep> {
        let mut out = self.settled.clone();
        out.resize(self.first_step, SmoothedStep::NONE);
        out.extend(self.answer_current(topology, cluster));
        out
    }

    /// [`Self::smoothed`], consuming the tree: the settled steps are moved rather than copied
    /// and the fixed-lag answers freed before the answer grows (a long walk's smoother holds
    /// about 100 bytes a step in each).
    pub fn into_smoothed(
        mut self,
        topology: &FloorTopology,
        cluster: &ClusterConfig,
    ) -> Vec<SmoothedStep> {
        let current = self.answer_current(topology, cluster);
        self.lagged = Vec::new();
        self.generations = Vec::new();
        let mut out = std::mem::take(&mut self.settled);
        out.resize(self.first_step, SmoothedStep::NONE);
        out.extend(current);
        out
    }

    /// The current segment's answer: the final ancestry, refined by the fixed-lag answer
    /// where both are certain and agree.
    fn answer_current(
        &self,
        topology: &FloorTopology,
        cluster: &ClusterConfig,
    ) -> Vec<SmoothedStep> {
        let mut out = self.smooth_current(topology, cluster);
        for (g, full) in out.iter_mut().enumerate() {
            let lagged = self
                .lagged
                .get(self.first_step + g)
                .and_then(LaggedAnswer::get);
            if let (Some(l), Some(f)) = (lagged, full.estimate)
                && full.certain
                && l.certain
                && let Some(e) = l.estimate
                && e.level == f.level
                && (e.x - f.x).hypot(e.y - f.y) <= cluster.max_spread
            {
                *full = l;
            }
        }
        out
    }

    /// The current segment's generations smoothed: each node weighted by its number of
    /// descendants in the last generation, clustered as the filter clusters its belief.
    fn smooth_current(
        &self,
        topology: &FloorTopology,
        cluster: &ClusterConfig,
    ) -> Vec<SmoothedStep> {
        let Some(last) = self.generations.last() else {
            return Vec::new();
        };
        let config = heading_free(cluster);
        let mut out = vec![SmoothedStep::NONE; self.generations.len()];
        let mut weights = vec![1.0f64; last.len()];
        for (g, generation) in self.generations.iter().enumerate().rev() {
            out[g] = smooth_generation(generation, &weights, topology, &config);
            if g == 0 {
                break;
            }
            weights = parent_weights(generation, &weights, self.generations[g - 1].len());
        }
        out
    }

    /// Drops every node without a descendant in the last generation, newest generations
    /// first, stopping at the first generation that loses nothing (the ones before it were
    /// pruned against it already).
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
    fn lagged_answers_keep_certain_ones_exactly() {
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
        assert_eq!(LaggedAnswer::keep(&certain).get(), Some(certain));
        let unsure = SmoothedStep {
            certain: false,
            ..certain
        };
        assert_eq!(LaggedAnswer::keep(&unsure).get(), None);
        assert_eq!(LaggedAnswer::keep(&SmoothedStep::NONE).get(), None);
        assert_eq!(std::mem::size_of::<LaggedAnswer>(), 64);
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
        assert_eq!(tree.generations[0][0].x, 3.0);
        assert_eq!(tree.generations[1][0].x, 12.0);
        assert_eq!(tree.generations[2][0].parent, 0);
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
