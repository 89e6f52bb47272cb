//! The estimate: the belief clustered by mean shift once it is small enough.

use super::Tracker;
use crate::filter::cluster::{Cluster, ClusterPoint};

impl Tracker<'_> {
    /// Clusters the belief when it has at most `cluster.max_particles` particles; once the
    /// walker has been localised, a larger belief is clustered through an evenly strided
    /// subsample of that many particles, so that tracking never stops producing estimates.
    /// The points and mean shift's buffers are reused from step to step.
    pub(super) fn cluster(&mut self) -> Option<Vec<Cluster>> {
        let max = self.config.cluster.max_particles.max(1);
        let n = self.particles.len();
        if n > max && !self.localised_once {
            return None;
        }
        let stride = n.div_ceil(max).max(1);
        let topology = self.topology;
        self.cluster_points.clear();
        self.cluster_points
            .extend(self.particles.iter().step_by(stride).map(|p| ClusterPoint {
                x: p.x,
                y: p.y,
                z: topology.z(p.surface),
                level: topology.level(p.surface),
                heading: p.heading,
                weight: 1.0,
            }));
        Some(
            self.mean_shift
                .cluster(&self.cluster_points, &self.config.cluster),
        )
    }
}
