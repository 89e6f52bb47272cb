//! Layer 0: pure geometry, no I/O.
//!
//! Angles, poses, the hexagon grid (the only module that touches `hexx`), the local
//! east-north frame placed on the WGS84 globe, and rigid alignment of trajectories.

pub mod alignment;
pub mod angle;
pub mod hex_grid;
pub mod local_frame;
pub mod pose;

pub use alignment::RigidTransform;
pub use angle::{wrap_angle, wrap_turn};
pub use hex_grid::{Crossing, Hex, HexGrid};
pub use local_frame::LocalFrame;
pub use pose::Pose2;
