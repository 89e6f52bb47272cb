//! Layer 1: the maps.

pub mod floor_plan;
pub mod hex_transitions;

pub use floor_plan::{FloorPlan, FloorPolygon};
pub use hex_transitions::{HexCell, HexMapSnapshot, HexTransitionMap};
