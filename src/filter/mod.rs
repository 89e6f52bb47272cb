//! Layer 3: particle-filter machinery and the filters built from it.

pub mod cluster;
pub mod footslam;
pub mod footslam_anchors;
pub mod footslam_config;
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
pub mod survey;
pub mod tracker;
pub mod tracker_config;

pub use cluster::{Cluster, ClusterConfig};
pub use footslam::{Anchors, FootSlam, FootSlamConfig, FootSlamEstimate};
pub use footslam_config::FOOTSLAM_HEADING_CORRELATION;
pub use kld::KldConfig;
pub use lineage::Lineage;
pub use nearest_fingerprint::{FingerprintConfig, FingerprintFix, NearestFingerprint};
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
pub use tracker::{StepMeasurement, TrackParticle, TrackStep, Tracker};
pub use tracker_config::{StartPose, TrackerConfig};
