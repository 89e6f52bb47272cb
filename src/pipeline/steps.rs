//! A raw IMU recording to step events, as stages:
//!
//! 1. **detect** — a foot-mounted recording through the zero-velocity-aided INS (one event
//!    per stride, [`detect_strides`]), a phone's through the step-and-heading system (one per
//!    step, [`detect_steps`]);
//!    The magnetic field over each event comes beside them ([`field_per_step`]);
//! 2. **check** — whether the recording looks like the mount ([`check_mount`]), whether
//!    its axes agree with each other ([`check_foot_frame`], [`check_phone_frame`]), and
//!    whether the steps fit human walking ([`check_gait`]).
//!
//! A phone's recording to steps:
//!
//! ```
//! use footslam::inertial::{HeadingSource, Mount, StepsConfig};
//! use footslam::pipeline::steps;
//! use footslam::sensor::{ImuRecording, ImuSample};
//! use std::f64::consts::PI;
//!
//! // A phone held flat, facing north, for 10 s of walking at two steps a second (100 Hz):
//! // the vertical acceleration swings once a step.
//! let samples: Vec<ImuSample> = (0..1000)
//!     .map(|i| {
//!         let t = f64::from(i) / 100.0;
//!         ImuSample {
//!             t,
//!             accel: [0.0, 0.0, 9.81 + 3.0 * (2.0 * PI * 2.0 * t).sin()],
//!             gyro: [0.0; 3],
//!             mag: None,
//!             orientation: Some([0.0, 0.0, 0.0, 1.0]), // sensor axes = east, north, up
//!             pressure: None,
//!         }
//!     })
//!     .collect();
//! let recording = ImuRecording::new(samples, 0).expect("a valid recording");
//! let run = steps(&recording, Mount::Phone, &StepsConfig::default())?;
//! assert!((19..=21).contains(&run.trace.len()));
//! assert_eq!(run.heading_source, HeadingSource::RotationVector);
//! let (_, cadence) = run.figures.step_and_cadence();
//! assert!((cadence - 120.0).abs() < 5.0);
//! // The front end's path heads north: the headings are absolute.
//! let end = run.path.last().expect("the start and a point per step");
//! assert!(end[1] > 5.0 && end[0].abs() < 0.5);
//! assert!(run.recording_warnings().is_empty());
//! # Ok::<(), footslam::Error>(())
//! ```

use crate::Result;
use crate::inertial::{
    FootFigures, FrameFinding, HeadingSource, Mount, PhoneFigures, StepsConfig, check_foot_frame,
    check_gait, check_mount, check_phone_frame, detect_steps, detect_strides, field_per_step,
};
use crate::sensor::{ImuRecording, StepFields, StepTrace};
use serde::Serialize;

/// The detector's figures, per mount.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum DetectorFigures {
    /// The foot INS's.
    Foot(FootFigures),
    /// The phone's step-and-heading system's.
    Phone(PhoneFigures),
}

/// What [`steps`] gives.
#[derive(Debug, Clone, PartialEq)]
pub struct StepsRun {
    /// The mount the recording was read as.
    pub mount: Mount,
    /// The step events, one per step (phone) or stride (foot), in time order.
    pub trace: StepTrace,
    /// The front end's dead-reckoned `[x, y, z]` after each event, from the start (one
    /// point more than `trace`).
    pub path: Vec<[f64; 3]>,
    /// How headings were obtained.
    pub heading_source: HeadingSource,
    /// The detector's figures.
    pub figures: DetectorFigures,
    /// The recording does not look like the mount (e.g. a phone's rates from a foot).
    pub mount_warning: Option<String>,
    /// What the frame check found (checked on a foot only when the mount looks right).
    pub frame: Option<FrameFinding>,
    /// The steps' lengths and cadence do not fit human walking ([`check_gait`]): the
    /// timestamps are likely in another scale.
    pub gait_warning: Option<String>,
    /// Whether the gyroscope set the headings (a mirrored one then makes them wrong).
    pub gyro_used: bool,
    /// The magnetic field over each event, when the recording has a magnetometer
    /// ([`field_per_step`]).
    pub field: Option<StepFields>,
}

/// Whether a [`StepsRun`]'s frame finding makes its output wrong.
#[derive(Debug, Clone, PartialEq)]
pub enum FrameVerdict {
    /// Nothing found.
    Fine,
    /// A finding the output does not depend on: a mirrored gyroscope whose headings were not
    /// used, or an inconsistency no flip explains.
    Warn(FrameFinding),
    /// A finding that makes the output wrong.
    Reject(FrameFinding),
}

impl DetectorFigures {
    /// Mean step length (metres; a foot's stride is two steps) and steps a minute.
    #[must_use]
    pub fn step_and_cadence(&self) -> (f64, f64) {
        match self {
            Self::Foot(f) => (0.5 * f.mean_stride_length_m, 2.0 * f.cadence_per_min),
            Self::Phone(f) => (f.mean_stride_m, f.cadence_spm),
        }
    }
}

impl StepsRun {
    /// The warnings on the recording the output depends on, in order: the mount, then the
    /// gait (the frame finding is judged apart, [`Self::frame_verdict`]).
    #[must_use]
    pub fn recording_warnings(&self) -> Vec<String> {
        self.mount_warning
            .iter()
            .chain(&self.gait_warning)
            .cloned()
            .collect()
    }

    /// The verdict on the frame finding.
    #[must_use]
    pub fn frame_verdict(&self) -> FrameVerdict {
        match &self.frame {
            None => FrameVerdict::Fine,
            Some(f) => match f {
                FrameFinding::MirroredGyro { .. } if !self.gyro_used => {
                    FrameVerdict::Warn(f.clone())
                }
                FrameFinding::Quaternion { .. } if self.gyro_used => FrameVerdict::Warn(f.clone()),
                FrameFinding::Inconsistent { .. } | FrameFinding::Disagreeing { .. } => {
                    FrameVerdict::Warn(f.clone())
                }
                _ => FrameVerdict::Reject(f.clone()),
            },
        }
    }
}

impl FrameVerdict {
    /// The verdict in words: `Ok` with the warnings to show (none when fine), or `Err` with
    /// why the output would be wrong. `flipped` follows the finding's message (e.g. how the
    /// caller flipped the gyroscope, `""` when it did not).
    ///
    /// # Errors
    ///
    /// The finding's message (with `flipped`) when the verdict is [`FrameVerdict::Reject`]: a
    /// gyroscope that must be flipped, timestamps not in seconds, or an orientation quaternion with
    /// a mistake, whichever the output depends on.
    pub fn messages(self, flipped: &str) -> std::result::Result<Vec<String>, String> {
        match self {
            Self::Fine => Ok(Vec::new()),
            Self::Warn(f @ FrameFinding::MirroredGyro { .. }) => Ok(vec![format!(
                "{}{flipped} (the heading comes from the orientation quaternion, unaffected)",
                f.message()
            )]),
            Self::Warn(f) => Ok(vec![f.message()]),
            Self::Reject(f) => Err(format!("{}{flipped}", f.message())),
        }
    }
}

/// Detects the steps of `recording` as `mount`, in the stages of the [module](self).
///
/// # Errors
///
/// [`Error::Config`](crate::Error::Config) when `config` fails
/// [`StepsConfig::validate`](crate::inertial::StepsConfig::validate); as [`detect_strides`] for a
/// foot: a first stance whose specific force is not gravity (accelerations in g?).
pub fn steps(recording: &ImuRecording, mount: Mount, config: &StepsConfig) -> Result<StepsRun> {
    config.validate()?;
    let mut run = detect_and_check(recording, mount, config)?;
    let (step_m, per_min) = run.figures.step_and_cadence();
    run.gait_warning = check_gait(mount, run.trace.len(), step_m, per_min);
    Ok(run)
}

/// Stages 1 and 2 but the gait check.
fn detect_and_check(
    recording: &ImuRecording,
    mount: Mount,
    config: &StepsConfig,
) -> Result<StepsRun> {
    Ok(match mount {
        Mount::Foot => {
            let events = detect_strides(recording, &config.foot)?;
            let residual = events.figures.mean_zupt_residual;
            // A recording that is not a foot's (said by the mount check) is not judged by
            // the foot INS's residual too.
            let mount_warning = check_mount(recording, Mount::Foot, events.trace.len());
            let frame = mount_warning
                .is_none()
                .then(|| check_foot_frame(recording, &config.foot, residual))
                .flatten();
            StepsRun {
                mount,
                field: field_per_step(recording, &events.trace),
                trace: events.trace,
                path: events.path,
                heading_source: events.heading_source,
                figures: DetectorFigures::Foot(events.figures),
                mount_warning,
                frame,
                gait_warning: None,
                gyro_used: true,
            }
        }
        Mount::Phone => {
            let events = detect_steps(recording, &config.phone)?;
            let mount_warning = check_mount(recording, Mount::Phone, events.trace.len());
            StepsRun {
                mount,
                field: field_per_step(recording, &events.trace),
                trace: events.trace,
                path: events.path,
                // With the quaternion giving the heading, a mirrored gyroscope does no harm.
                gyro_used: events.heading_source != HeadingSource::RotationVector,
                heading_source: events.heading_source,
                figures: DetectorFigures::Phone(events.figures),
                mount_warning,
                frame: check_phone_frame(recording),
                gait_warning: None,
            }
        }
    })
}
