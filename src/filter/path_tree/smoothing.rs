//! The smoothed answers read from the tree: each generation's nodes weighted by their
//! descendants in the current belief and clustered as the filter clusters its belief, refined
//! by the fixed-lag answer where both are certain.

use super::stored_step::StoredStep;
use super::{NO_PARENT, PathNode, PathTree, SmoothedStep};
use crate::filter::cluster::{Cluster, ClusterConfig, ClusterPoint, mean_shift};
use crate::map::FloorTopology;

impl PathTree {
    /// The fixed-lag answer for the step `lag` generations before the newest one.
    pub(super) fn answer_lagged(&mut self, topology: &FloorTopology, cluster: &ClusterConfig) {
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

    /// The smoothed belief at every step `0..self.steps()`: settled steps as they were fixed,
    /// the current segment from the current belief's ancestry.
    #[must_use]
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
    pub(super) fn answer_current<'s>(
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
