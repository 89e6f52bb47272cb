//! Layer 1: the maps.
//!
//! Floor plans:
//! * [`floor_plan`] — 2.5D floor plans: walkable polygons with a level and a height, barriers
//! * [`floor_topology`] — a plan's walls and connections, indexed for walking steps through it
//! * [`occupancy_grid`] — a plan as free, occupied and unknown squares (a ROS map)
//!
//! Learned hexagon maps (FootSLAM):
//! * [`hex_tree`] — one record per hexagon in a persistent quadtree, shared copy-on-write
//! * [`hex_forest`] — many particles' hexagon maps in one store: shared nodes, own nodes written in place
//! * [`hex_transitions`] — the per-particle hexagon transition map
//! * [`field_map`] — the per-particle magnetic field map (MagSLAM), shared copy-on-write
//! * [`edge_prior`] — the Dirichlet prior of every hexagon edge (outline, earlier maps)
//! * [`map_merge`] — maps of several walks combined
//! * [`map_registration`] — a map registered onto another of the same building
//! * [`learned_plan`] — a learned map as a walkable floor plan
//!
//! Radio maps:
//! * [`radio_cells`] — rooms and cells of a floor plan, the units of a radio map
//! * [`radio_map`] — per cell, the scans taken there and each access point's histogram
//! * [`cell_raster`] — which cell holds a point, in O(1)

pub mod cell_raster;
pub mod edge_prior;
pub mod field_map;
pub mod floor_plan;
pub mod floor_topology;
pub mod hex_forest;
pub mod hex_transitions;
pub mod hex_tree;
pub mod learned_plan;
pub mod map_merge;
pub mod map_registration;
pub mod occupancy_grid;
pub mod radio_cells;
pub mod radio_map;

pub use cell_raster::{CellField, CellRaster};
pub use edge_prior::EdgePrior;
pub use field_map::{FieldCell, FieldMap, FieldMapCell, FieldMapSnapshot};
pub use floor_plan::{Barrier, FloorLevel, FloorPlan, FloorPolygon};
pub use floor_topology::{FloorTopology, Segment, SegmentKind, TopologyConfig};
pub use hex_transitions::{
    HexCell, HexCounters, HexMapForest, HexMapSnapshot, HexTransitionMap, LEVEL_STRIDE,
    ParticleHexMap, level_key, map_of_path, split_level_key,
};
pub use learned_plan::{LearnedPlan, PlanConfig, grow_plan, walkable_plan};
pub use map_merge::{merge_maps, shift_map};
pub use map_registration::register_maps;
pub use occupancy_grid::{Occupancy, OccupancyConfig, OccupancyGrid};
pub use radio_cells::{CellConfig, CellMap, RadioCell, Room};
pub use radio_map::{ApStats, CellRadio, RadioMap, RadioMapCell};
