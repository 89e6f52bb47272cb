//! The belief's ancestry in the path tree, and the smoothed (whole-walk) answer read from it.

use super::{TrackParticle, Tracker};
use crate::filter::path_tree::{PathNode, PathTree, SmoothedStep, SmoothedWalk};
use rayon::prelude::*;

/// A particle's place as a node of the ancestry.
fn path_node(p: &TrackParticle) -> PathNode {
    PathNode::new(p.x, p.y, p.surface)
}

impl<'a> Tracker<'a> {
    /// The whole-walk answer: the smoothed belief after each step `0..=steps` (0 = the prior),
    /// from the ancestral lines of the current belief ([`crate::filter::path_tree`]); `None` when
    /// `config.smoothing` is off.
    #[must_use]
    pub fn smoothed(&self) -> Option<Vec<SmoothedStep>> {
        let tree = self.tree.as_ref()?;
        Some(tree.smoothed(self.topology, &self.config.cluster))
    }

    /// [`Self::smoothed`], ending the smoothing: the path tree moves into the answer, which
    /// computes each step's belief as it is read (a long walk never holds every step's
    /// answer), and later calls return `None`.
    pub fn take_smoothed(&mut self) -> Option<SmoothedWalk<'a>> {
        let tree = self.tree.take()?;
        self.path_nodes_peak_taken = tree.peak_nodes();
        Some(SmoothedWalk::new(tree, self.topology, self.config.cluster))
    }

    /// Largest number of path nodes (16 bytes each) the smoother held at once (0 without
    /// smoothing).
    pub fn path_nodes_peak(&self) -> usize {
        self.tree
            .as_ref()
            .map_or(self.path_nodes_peak_taken, PathTree::peak_nodes)
    }

    /// The belief as path nodes.
    pub(super) fn path_nodes(&self) -> Vec<PathNode> {
        self.particles.par_iter().map(path_node).collect()
    }

    /// Starts a new ancestry at `step` with the belief as its roots (a prior, or particles
    /// not descended from the last belief).
    pub(super) fn root_tree(&mut self, step: usize) {
        if self.tree.is_some() {
            let nodes = self.path_nodes();
            if let Some(tree) = self.tree.as_mut() {
                tree.root(step, nodes, self.topology, &self.config.cluster);
            }
        }
    }

    /// Adds the resampled belief to the ancestry (its ancestors index the last generation).
    pub(super) fn grow_tree(&mut self) {
        if let Some(tree) = self.tree.as_mut() {
            tree.push_parallel(
                self.particles.par_iter().map(path_node),
                &self.ancestors,
                self.topology,
                &self.config.cluster,
            );
            if tree.nodes() > self.config.smoothing_max_nodes {
                // The belief has not narrowed: give up the whole-walk answer rather than
                // the machine's memory.
                self.path_nodes_peak_taken = tree.peak_nodes();
                self.tree = None;
                self.smoothing_dropped_at = Some(self.steps as usize);
            }
        }
    }

    /// The step at which the ancestry outgrew `smoothing_max_nodes` and was dropped (the run
    /// then has no whole-walk answer).
    #[must_use]
    pub fn smoothing_dropped_at(&self) -> Option<usize> {
        self.smoothing_dropped_at
    }
}
