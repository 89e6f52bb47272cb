//! Evaluation of estimates against references: position errors of a track against the
//! ground truth or at sparse waypoints, how often a 2.5D track is on the right floor, how much of a learned map lies in a floor plan's walkable space, and how a learned plan
//! overlaps the true one.

pub mod floor_accuracy;
pub mod plan_overlap;
pub mod position_error;
pub mod rf_localisation;
pub mod tracking;
pub mod walkable;
pub mod waypoint_error;

pub use floor_accuracy::floor_accuracy;
pub use plan_overlap::{PlanOverlap, plan_overlap};
pub use position_error::{Alignment, ErrorReport, position_errors};
pub use tracking::{SmoothedScore, TrackingScore, score_smoothed, score_tracking};
pub use walkable::walkable_fraction;
pub use waypoint_error::{WaypointError, WaypointErrors, waypoint_errors};
