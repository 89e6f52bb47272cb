//! The `steps` job, request in, report out: what the command line and the Python package
//! both run.
//!
//! 1. **prepare** — the configuration checked, the gyroscope's mirrored axes flipped back;
//! 2. **detect** — [`steps`](super::steps()) on the recording;
//! 3. **check** — the warnings on the recording the output depends on, a frame finding that
//!    makes the output wrong as an error, no steps at all as an error;
//! 4. **report** — `summary.json` as one typed struct ([`StepsReport`]).

use super::named::Named;
use super::steps::{DetectorFigures, StepsRun, steps};
use super::{Quality, steps_quality};
use crate::error::{Error, Result};
use crate::inertial::frame_check::axes_flag;
use crate::inertial::{HeadingSource, Mount, StepsConfig};
use crate::sensor::{ImuRecording, SamplingReport};
use serde::Serialize;
use std::time::Instant;

/// Everything `steps` runs on, read by a face.
#[derive(Debug, Clone)]
pub struct StepsRequest {
    /// The recording, in SI units (the face converts g and deg/s as it reads).
    pub recording: Named<ImuRecording>,
    /// How the sensor was worn.
    pub mount: Mount,
    /// Gyroscope axes to negate (x, y, z), for a mirrored gyroscope.
    pub gyro_flip: Option<[bool; 3]>,
    /// The detector's configuration.
    pub config: StepsConfig,
}

/// What the `steps` job gives: the run and its report.
#[derive(Debug, Clone)]
pub struct StepsJob {
    /// The step events, the dead-reckoned path and the checks' findings.
    pub run: StepsRun,
    /// `summary.json`.
    pub report: StepsReport,
}

/// `summary.json` of `steps`, and the `summary` Python returns.
#[derive(Debug, Clone, Serialize)]
pub struct StepsReport {
    /// The steps' verdict and its reasons (docs/robustness.md).
    pub quality: Quality,
    /// The recording's name.
    pub imu_file: String,
    /// How the sensor was worn.
    pub mount: Mount,
    /// Step events (a foot's strides).
    pub steps: usize,
    /// Their mean length, m.
    pub mean_stride_m: f64,
    /// Their summed length, m.
    pub total_length_m: f64,
    /// Their summed height change, m.
    pub net_height_change_m: f64,
    /// Where the headings came from.
    pub heading_source: HeadingSource,
    /// Steps with an absolute heading.
    pub steps_with_heading: usize,
    /// Steps with a magnetic field reading (`field` column).
    pub steps_with_field: usize,
    /// Of them, with its vertical part (`field_up`).
    pub steps_with_field_up: usize,
    /// Why the output may be wrong (e.g. the recording does not look like the mount).
    pub warnings: Vec<String>,
    /// The recording's sampling.
    pub sampling: SamplingReport,
    /// The detector's figures.
    pub detector: DetectorFigures,
    /// Seconds from the job's start to the report.
    pub runtime_s: f64,
    /// footslam's version.
    pub version: &'static str,
}

/// Runs the `steps` job on `request`, the job having started at `started` (its runtime).
///
/// # Errors
///
/// [`Error::Config`] when the configuration is out of range; [`Error::InvalidData`] naming the
/// recording when its steps cannot be detected or the frame check rejects it
/// ([`FrameVerdict::messages`](super::FrameVerdict::messages)); [`Error::NotEnough`] when no step
/// or stride is detected.
pub fn run_steps(request: StepsRequest, started: Instant) -> Result<StepsJob> {
    request.config.validate()?;
    let Named {
        value: mut recording,
        label,
    } = request.recording;
    if let Some(flip) = request.gyro_flip {
        recording = recording.with_gyro_flipped(flip);
    }
    let run = steps(&recording, request.mount, &request.config)
        .map_err(|e| Error::invalid(&label, format!("cannot detect steps: {e}")))?;
    let flipped = request.gyro_flip.map_or(String::new(), |flip| {
        format!(" (after negating the gyroscope's {} axis)", axes_flag(flip))
    });
    let mut warnings = run.recording_warnings();
    let frame = run
        .frame_verdict()
        .messages(&flipped)
        .map_err(|problem| Error::invalid(&label, problem))?;
    warnings.extend(frame);
    let sampling = recording.report().clone();
    let steps = run.trace.steps();
    if steps.is_empty() {
        let what = match run.mount {
            Mount::Foot => "strides",
            Mount::Phone => "steps",
        };
        return Err(Error::not_enough(
            format!(
                "{label}: no {what} detected in {:.1} s of data",
                sampling.duration_s
            ),
            "check the mount and that the walker is moving",
        ));
    }
    let total_length_m: f64 = steps.iter().map(|s| s.length).sum();
    let report = StepsReport {
        quality: steps_quality(&warnings),
        imu_file: label,
        mount: run.mount,
        steps: steps.len(),
        mean_stride_m: total_length_m / steps.len() as f64,
        total_length_m,
        net_height_change_m: steps.iter().map(|s| s.dz).sum(),
        heading_source: run.heading_source,
        steps_with_heading: run.trace.with_heading(),
        steps_with_field: run.field.as_ref().map_or(0, |f| f.observed()),
        steps_with_field_up: run.field.as_ref().map_or(0, |f| f.with_vertical()),
        warnings,
        sampling,
        detector: run.figures.clone(),
        runtime_s: started.elapsed().as_secs_f64(),
        version: env!("CARGO_PKG_VERSION"),
    };
    Ok(StepsJob { run, report })
}
