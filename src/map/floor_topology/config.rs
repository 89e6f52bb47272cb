//! The topology's tolerances and the spatial index's cell ([`TopologyConfig`]).

use crate::error::Result;
use serde::{Deserialize, Serialize};

/// Topology tolerances and the spatial index's cell; every default in one place.
///
/// | field                  | default | meaning                                                 |
/// |------------------------|---------|---------------------------------------------------------|
/// | `connection_tolerance` | 0.05 m  | collinear edges within this are one shared boundary     |
/// | `max_connection_dz`    | 0.5 m   | surfaces further apart in height never connect          |
/// | `cell_size`            | 1.0 m   | edge of the grid cells indexing the segments            |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TopologyConfig {
    /// Two boundary segments closer than this to each other's line are collinear, metres.
    pub connection_tolerance: f64,
    /// Largest height difference of connected surfaces, metres.
    pub max_connection_dz: f64,
    /// Edge of the spatial index's cells, metres.
    pub cell_size: f64,
}

impl Default for TopologyConfig {
    fn default() -> Self {
        Self {
            connection_tolerance: 0.05,
            max_connection_dz: 0.5,
            cell_size: 1.0,
        }
    }
}

impl TopologyConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) when `connection_tolerance` is outside [0, 1] m,
    /// `max_connection_dz` outside [0, 100] m or `cell_size` outside [0.1, 1000] m.
    pub fn validate(&self) -> Result<()> {
        crate::error::check_range(
            "topology.connection_tolerance",
            self.connection_tolerance,
            0.0..=1.0,
            "metres",
        )?;
        crate::error::check_range(
            "topology.max_connection_dz",
            self.max_connection_dz,
            0.0..=100.0,
            "metres",
        )?;
        crate::error::check_range("topology.cell_size", self.cell_size, 0.1..=1000.0, "metres")
    }
}
