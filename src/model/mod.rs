//! Layer 2: probabilistic models, apart from the filter machinery.
//!
//! * [`step_motion`] — the step measurement model of FootSLAM (the proposal)
//! * [`building_axes`] — the building's dominant directions as a prior on straight walking
//! * [`floor_levels`] — floors from height changes
//! * [`transition_prior`] — a learned hexagon map as a motion prior for tracking
//! * [`gps_likelihood`] — the GPS fix likelihood, robust and tempered
//! * [`heading_likelihood`] — the compass heading likelihood, robust to disturbances
//! * [`magnetic_field`] — the magnetic field against each particle's own field map (MagSLAM)
//! * [`scan_pairs`] — WiFi scans as evidence of revisits inside FootSLAM (scan to scan)
//! * [`scan_references`] — other walks' scans as evidence in a FeetSLAM batch's later passes
//! * [`wifi_distance`] — the normalised RSSI distance between a scan and a radio-map cell
//! * [`radio_interpolation`] — the radio map between surveyed cells: a Gaussian process per
//!   access point, with its variance, and honest ignorance far from the survey
//! * [`radio_variogram`] — its kernel, fitted on the survey's pooled variogram
//! * [`radio_pathloss`] — the radio map beyond the survey: a path-loss model per access point
//! * [`wifi_likelihood`] — the probabilistic WiFi measurement (eq. 14)
//! * [`derived_epsilon`] — a radio map's region threshold derived from the map itself

pub mod building_axes;
pub mod derived_epsilon;
pub mod floor_levels;
pub mod gps_likelihood;
pub mod heading_likelihood;
pub mod magnetic_field;
pub mod radio_interpolation;
pub mod radio_pathloss;
pub mod radio_variogram;
pub mod scan_pairs;
pub mod scan_references;
pub mod step_motion;
pub mod transition_prior;
pub mod wifi_distance;
pub mod wifi_evidence;
pub mod wifi_evidence_interpolated;
pub mod wifi_evidence_pathloss;
pub mod wifi_likelihood;

pub use building_axes::{AxesConfig, AxisEvidence, AxisLikelihood, AxisState};
pub use floor_levels::{FloorLevel, LevelConfig, LevelTracker, find_levels};
pub use gps_likelihood::{GpsConfig, GpsLikelihood, GpsObservation};
pub use heading_likelihood::{HeadingConfig, HeadingConstants, HeadingLikelihood};
pub use magnetic_field::{
    FieldCalibration, FieldConfig, FieldEvidence, FieldLikelihood, FieldUnused,
};
pub use radio_interpolation::{InterpolationConfig, RadioInterpolation};
pub use radio_pathloss::{PathLossConfig, PathLossMap, PathLossSummary};
pub use radio_variogram::VariogramFit;
pub use scan_pairs::{PairLikelihood, ScanEvidence, ScanPairConfig, ScanPairsUnused};
pub use scan_references::{PlacedScan, ReferenceScans};
pub use step_motion::{StepErrorState, StepMotion, StepMotionConfig};
pub use transition_prior::{TransitionPrior, TransitionPriorConfig};
pub use wifi_evidence::{
    EvidenceCalibration, EvidenceConfig, EvidenceSource, RadioEvidence, StandInScores,
};
pub use wifi_evidence_interpolated::{InterpolatedCalibration, InterpolatedEvidence};
pub use wifi_evidence_pathloss::{PathLossCalibration, PathLossEvidence};
