//! The topology of a 2.5D floor plan, built once: which polygon edges are walls and which are
//! connections between surfaces, indexed for the particle filter's hot path (Woodman & Harle
//! 2008, sec. "Floor polygons", eqs. 12–16 and Algorithm 1 lines 7–24).
//!
//! Rules:
//! * every boundary segment of a surface (exterior ring and holes) is a **wall**, except
//! * the parts of it that overlap, collinearly in the horizontal plane within
//!   [`TopologyConfig::connection_tolerance`], a boundary segment of another surface whose
//!   height differs by at most [`TopologyConfig::max_connection_dz`]: those are
//!   **connections** between the two surfaces (a door rectangle touching a corridor and a
//!   room, adjacent stair treads, a corridor split into pieces). Partly overlapping edges are
//!   split into their connection and wall parts;
//! * every segment of a [`Barrier`](super::floor_plan::Barrier) line is a wall for the
//!   surfaces of its level.
//!
//! A step is walked from its surface through that surface's own edges only: surfaces on other
//! levels that overlap it in the plane (stairwells) never interfere.
//!
//! The index is a uniform grid over the plan with the segments of each cell stored
//! contiguously (compressed rows), as compact `f32` records, each surface holding its own
//! walls and connections (each level its barriers) over the cells they cover: a step tests
//! only its surface's records in the few cells its bounding box touches (stacked floors and
//! neighbouring rooms never cost it a record), as in Woodman & Harle's per-polygon edges.
//!
//! The pieces, one file each:
//! * `config` — tolerances and the index's cell ([`TopologyConfig`])
//! * `topology` — the topology built from a plan ([`FloorTopology`]): its surfaces and lookups
//! * `connections` — connection finding: the stretches of boundary edges surfaces share
//! * `segments` — segment splitting: boundary edges cut into walls and connections
//!   ([`Segment`]), and barrier walls
//! * `grid` — the grid index of segments (per surface) and surfaces (compressed rows of
//!   `f32` records)
//! * `locate` — the surfaces holding each grid cell no boundary crosses, known in advance
//! * `walk` — a step walked through walls and connections (Algorithm 1)
//! * `sampling` — points drawn uniformly over the walkable area

mod config;
mod connections;
mod grid;
mod locate;
mod sampling;
mod segments;
#[cfg(test)]
mod tests;
mod topology;
mod walk;

pub use config::TopologyConfig;
pub use segments::{Segment, SegmentKind};
pub use topology::FloorTopology;
