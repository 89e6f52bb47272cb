//! Evaluation of estimates against references.
//!
//! * [`position_error`] — position errors of a track against the ground truth
//! * [`waypoint_error`] — errors at sparse ground-truth points (real datasets)
//! * [`dead_reckoning`] — the step trace dead-reckoned, the baseline a track is scored beside
//! * [`reprojection`] — a track moved from its run's local frame into the truth's
//! * [`floor_accuracy`](mod@floor_accuracy) — how often a 2.5D track is on the right floor
//! * [`tracking`] — a known-map tracking run scored against the truth
//! * [`rf_localisation`] — RF-assisted localisation scored against localisation without it
//! * [`walkable`] — how much of a learned map lies in a floor plan's walkable space
//! * [`plan_overlap`](mod@plan_overlap) — how a learned plan overlaps the true one

pub mod dead_reckoning;
pub mod floor_accuracy;
pub mod plan_overlap;
pub mod position_error;
pub mod reprojection;
pub mod rf_localisation;
pub mod tracking;
pub mod walkable;
pub mod waypoint_error;

pub use dead_reckoning::{
    WaypointDeadReckoning, dead_reckoning_from, dead_reckoning_track, waypoint_dead_reckoning,
};
pub use floor_accuracy::{floor_accuracy, track_floor_accuracy};
pub use plan_overlap::{PlanOverlap, plan_overlap};
pub use position_error::{Alignment, ErrorReport, position_errors};
pub use reprojection::reproject;
pub use tracking::{SmoothedScore, TrackingScore, score_smoothed, score_tracking};
pub use walkable::walkable_fraction;
pub use waypoint_error::{WaypointError, WaypointErrors, waypoint_errors};
