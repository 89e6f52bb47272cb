//! Layer 0: pure geometry, no I/O.
//!
//! * [`angle`] — angle wrapping (radians throughout)
//! * [`pose`] — a 2D pose in the local frame
//! * [`hex_grid`] — the hexagon grid of the transition map (the only module that touches
//!   `hexx`)
//! * [`local_frame`] — the local east-north frame placed on the WGS84 globe
//! * [`alignment`] — rigid alignment of matched point sets (trajectories)
//! * [`path_length`](mod@path_length), [`percentile`] — a path's length; nearest-rank percentiles

pub mod alignment;
pub mod angle;
pub mod hex_grid;
pub mod local_frame;
pub mod path_length;
pub mod percentile;
pub mod pose;

pub use alignment::RigidTransform;
pub use angle::{wrap_angle, wrap_turn};
pub use hex_grid::{Crossing, Hex, HexGrid};
pub use local_frame::LocalFrame;
pub use path_length::path_length;
pub use percentile::nearest_rank;
pub use pose::Pose2;
