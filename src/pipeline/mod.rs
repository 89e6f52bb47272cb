//! The toolkit's work as functions over typed inputs, each a list of named stages (as
//! kiss-icp's pipeline reads): what the command line, the Python package and the batch
//! runner call. Pipelines read no files, print nothing, and report through [`Progress`].
//!
//! * [`input_checks`] — whether a run's inputs belong together (one clock, one grid, one
//!   building, floors the steps can change), for the faces to check before they call one.
//! * [`learn`](mod@learn) — FootSLAM on one walk or a batch, with GPS, an outline and a prior map
//!   (prior, walks, merge, radio).
//! * [`merge`](mod@merge) — maps of several walks in one frame combined (their counts summed).
//! * [`plan`](mod@plan) — a learned map as a walkable floor plan and occupancy grids.
//! * [`quality`] — every run's verdict (`ok`, `doubtful`, `poor`) and its reasons.
//! * [`steps`](mod@steps) — a raw IMU recording (foot or phone) to step events (detect, check);
//!   [`steps_job`] — the `steps` job: request in, report out.
//! * [`survey`](mod@survey) — a WiFi radio map from walks tracked on a known plan (track, cells, merge,
//!   calibrate, coverage).
//! * [`track`](mod@track) — one walk on a known floor plan (prior, steps, smoothing).
//! * [`track_job`] — the `track` job: request in (overrides, prepare), and
//!   [`track_report`] — its answer and report out.

pub mod fingerprint_job;
pub mod input_checks;
pub mod job_checks;
pub mod learn;
pub mod learn_config;
pub mod learn_job;
pub mod learn_report;
mod learn_reports;
mod learn_walks;
pub mod merge;
pub mod merge_job;
mod named;
pub mod plan;
pub mod plan_job;
mod progress;
pub mod quality;
pub mod steps;
pub mod steps_job;
pub mod survey;
pub mod survey_job;
pub mod track;
pub mod track_job;
mod track_records;
pub mod track_report;

pub use fingerprint_job::{
    FingerprintJob, FingerprintReport, FingerprintRequest, PreparedFingerprint, run_fingerprint,
};
pub use input_checks::{
    GPS_LEAD_S, GridMismatch, MIN_MATCHED_SHARE, SAME_ORIGIN_M, ScanMatch, fixes_far_from_origin,
    fixes_off_clock, grid_mismatch, missing_height_changes, outline_off_walks, partly_off_clock,
    scans_off_clock,
};
pub use learn::{
    Combined, LearnInput, LearnWalk, Learned, LearnedRadio, WalkRun, combine, default_frame,
    feetslam_passes, learn, learn_one, learned_radio_map, others_map,
};
pub use learn_config::{LearnConfig, LearnOverrides};
pub use learn_job::{LearnRequest, LearnWalkRequest, PreparedLearn, WalkLabels, prepare_learn};
pub use learn_report::{HeadingReport, LearnRadioReport, LearnReport, WalkReport, WalkWifiReport};
pub use learn_reports::{AxesReport, FieldReport, SmoothingReport};
pub use merge::merge;
pub use merge_job::{MergeJob, MergeReport, MergeRequest, run_merge};
pub use named::Named;
pub use plan::{PlanRunConfig, Planned, plan};
pub use plan_job::{PlanJob, PlanOverrides, PlanReport, PlanRequest, run_plan};
pub use progress::{ItemProgress, Progress, Silent};
pub use quality::{
    Quality, QualityConfig, Reason, TrackEvidence, Verdict, learn_quality, steps_quality,
    track_quality,
};
pub use steps::{DetectorFigures, FrameVerdict, StepsRun, steps};
pub use steps_job::{StepsJob, StepsReport, StepsRequest, run_steps};
pub use survey::{
    COVERAGE_GRANULARITIES, Coverage, SurveyConfig, SurveyInput, SurveyWalk, Surveyed,
    SurveyedWalk, survey,
};
pub use survey_job::{
    PreparedSurvey, SurveyOverrides, SurveyReport, SurveyRequest, SurveyWalkLabels,
    SurveyWalkReport, SurveyWalkRequest, prepare_survey,
};
pub use track::{CloudSnapshot, RadioInput, SnapshotSteps, TrackInput, TrackRun, track};
pub use track_job::{
    PreparedRadio, PreparedTrack, TrackOverrides, TrackRadioRequest, TrackRequest,
    TrackWalkRequest, prepare,
};
pub use track_records::{PlanFit, RecoveryEvent, StepRecord, StepRecords};
pub use track_report::{PlanStats, RfReport, TrackAnswer, TrackReport, TrackSmoothingReport};
