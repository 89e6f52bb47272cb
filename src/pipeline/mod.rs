//! The toolkit's work as functions over typed inputs, each a list of named stages (as
//! kiss-icp's pipeline reads): what the command line, the Python package and the batch
//! runner call. Pipelines read no files, print nothing, and report through [`Progress`].
//!
//! * [`learn`] — FootSLAM on one walk or a batch, with GPS, an outline and a prior map
//!   (prior, walks, merge, radio).
//! * [`survey`] — a WiFi radio map from walks tracked on a known plan (track, cells, merge,
//!   calibrate, coverage).
//! * [`track`] — one walk on a known floor plan (prior, steps, smoothing).

mod learn;
mod learn_walks;
mod progress;
mod survey;
mod track;
mod track_records;

pub use learn::{
    LearnInput, LearnWalk, Learned, LearnedRadio, WalkRun, default_frame, learn,
};
pub use progress::{Progress, Silent};
pub use survey::{
    COVERAGE_GRANULARITIES, Coverage, SurveyConfig, SurveyInput, SurveyWalk, Surveyed,
    SurveyedWalk, survey,
};
pub use track::{CloudSnapshot, RadioInput, SnapshotSteps, TrackInput, TrackRun, track};
pub use track_records::{RecoveryEvent, StepRecord, StepRecords};
