//! A finished walk's whole-walk answer, computed step by step as it is read.

use super::{PathTree, SmoothedStep};
use crate::filter::cluster::ClusterConfig;
use crate::map::FloorTopology;

/// A finished walk's whole-walk answer, computed step by step as it is read, so that a long
/// walk holds its path tree (tens of bytes a step) rather than every step's answer (a hundred):
/// from [`crate::filter::Tracker::take_smoothed`] and [`crate::filter::RfTracker::take_smoothed`].
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
    #[must_use]
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
    #[must_use]
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
    #[must_use]
    pub fn on_walk(self, before: usize, steps: usize) -> Self {
        Self {
            lead: before.saturating_sub(1),
            skip: usize::from(before == 0),
            len: steps,
            ..self
        }
    }

    /// Steps of the walk.
    #[must_use]
    pub fn len(&self) -> usize {
        self.len
    }

    /// True for a walk of no steps.
    #[must_use]
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
