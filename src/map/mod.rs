//! Layer 1: the maps.

pub mod cell_raster;
pub mod edge_prior;
pub mod floor_plan;
pub mod floor_topology;
pub mod hex_transitions;
pub mod learned_plan;
pub mod map_merge;
pub mod map_registration;
pub mod occupancy_grid;
pub mod radio_cells;
pub mod radio_map;

pub use cell_raster::{CellField, CellRaster};
pub use edge_prior::EdgePrior;
pub use floor_plan::{Barrier, FloorLevel, FloorPlan, FloorPolygon};
pub use floor_topology::{FloorTopology, Segment, SegmentKind, TopologyConfig};
pub use hex_transitions::{
    HexCell, HexMapSnapshot, HexTransitionMap, LEVEL_STRIDE, level_key, split_level_key,
};
pub use learned_plan::{LearnedPlan, PlanConfig, grow_plan, walkable_plan};
pub use map_merge::{merge_maps, shift_map};
pub use map_registration::register_maps;
pub use occupancy_grid::{Occupancy, OccupancyConfig, OccupancyGrid};
pub use radio_cells::{CellConfig, CellMap, RadioCell, Room};
pub use radio_map::{ApStats, CellRadio, RadioMap, RadioMapCell};
