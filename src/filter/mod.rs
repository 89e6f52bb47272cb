//! Layer 3: particle-filter machinery and the filters built from it.
//!
//! Machinery:
//! * [`resample`] — which particles survive, by index
//! * [`kld`] — KLD-sampling (Fox 2003): how many particles a belief needs
//! * [`cluster`] — mean-shift clusters of a belief, its estimate and hypotheses
//! * [`lineage`] — FootSLAM's particle ancestry (the answer's path)
//! * [`scan_trail`] — a FootSLAM particle's positions at the walk's WiFi scans
//! * [`path_tree`] — the tracker's pruned ancestry and its whole-walk (smoothed) answer
//! * [`recovery`] — what to do when every particle dies
//!
//! FootSLAM (learning maps from walks, Robertson et al. 2009):
//! * [`footslam`] — the Rao-Blackwellised particle filter
//! * [`footslam_config`], [`footslam_anchors`] — its settings, and what ties a walk to the
//!   world (GPS, an outline, earlier maps)
//! * [`departure`] — the learned path against dead reckoning: which to trust
//! * [`gps_start`], [`outline_fit`] — a walk's start from GPS fixes; a learned walk against
//!   a building outline
//!
//! Tracking on known plans (Woodman & Harle 2008, 2009):
//! * [`tracker`], [`tracker_config`] — the 2.5D floor-plan tracker and its settings
//! * [`rf_assist`], [`rf_tracker`] — WiFi containment regions from a radio map, and the
//!   tracker driven by steps and scans together
//! * [`survey`] — radio maps built while tracking
//! * [`nearest_fingerprint`] — the radio map alone: weighted k-nearest-neighbour fingerprints

pub mod cluster;
pub mod departure;
pub mod footslam;
pub mod footslam_anchors;
pub mod footslam_config;
mod footslam_map_term;
mod footslam_scans;
pub mod gps_start;
pub mod kld;
pub mod lineage;
pub mod nearest_fingerprint;
pub mod outline_fit;
pub mod path_tree;
pub mod recovery;
pub mod resample;
pub mod rf_assist;
pub mod rf_tracker;
pub mod scan_trail;
pub mod survey;
pub mod tracker;
pub mod tracker_config;

pub use cluster::{Cluster, ClusterConfig};
pub use footslam::{Anchors, FootSlam, FootSlamConfig, FootSlamEstimate, SmoothingConfig};
pub use footslam_config::FOOTSLAM_HEADING_CORRELATION;
pub use kld::KldConfig;
pub use lineage::Lineage;
pub use nearest_fingerprint::{
    FingerprintConfig, FingerprintFix, FingerprintMethod, NearestFingerprint,
};
pub use path_tree::{PathTree, SmoothedStep, SmoothedWalk};
pub use recovery::{Recovery, RecoveryConfig};
pub use resample::{ResampleConfig, ResampleMethod};
pub use rf_assist::{EpsilonSource, RfConfig, RfLocaliser, RfMode};
pub use rf_tracker::RfTracker;
pub use survey::{
    Assignments, EPSILON_MISS, PathPoint, PathSurvey, PlacedStep, SurveyCounts, assign_scans,
    calibrate_map, path_points, path_steps, placed_steps, survey_assignments, survey_paths,
    survey_walk, whole_walk_reports,
};
pub use tracker::{StepFit, StepMeasurement, TrackParticle, TrackStep, Tracker};
pub use tracker_config::{StartPose, TrackerConfig};
