//! Layer 1½: raw IMU recordings → step events ([`crate::sensor::Step`]).
//!
//! Two front ends over shared pieces, after the two pedestrian dead-reckoning families of
//! Harle's survey (2013): a foot-mounted **zero-velocity-aided strapdown INS** (§IV: stance
//! detection, an error-state Kalman filter with zero-velocity updates, one event per stride)
//! and a hand-held phone's **step-and-heading system** (§V: step detection on the
//! acceleration magnitude, a stride-length model, heading from the orientation or from gyro
//! and magnetometer fusion, height from the barometer).
//!
//! Foot-mounted INS:
//! * [`foot`] — the front end: IMU → strides ([`detect_strides`])
//! * [`foot_config`] — its configuration and figures
//! * [`stance`] — stance detection (the SHOE detector, adaptive threshold)
//! * [`strapdown`] — strapdown mechanisation in a local z-up frame
//! * [`zupt`] — the error-state Kalman filter with zero-velocity updates
//!
//! Phone step-and-heading system:
//! * [`phone`] — the front end: IMU → steps ([`detect_steps`])
//! * [`step_detector`] — steps from the acceleration magnitude
//! * [`stride_model`] — stride length from the acceleration swing (Weinberg)
//! * [`heading_fusion`] — walking direction from rotation vector, gyroscope and magnetometer
//! * [`barometer`] — height changes from air pressure
//!
//! Beside the steps:
//! * [`step_field`] — the magnetic field over each step (magnitude, vertical part)
//!
//! Checks of a recording:
//! * [`frame_check`] — gyroscope in the accelerometer's frame, timestamps in seconds
//! * [`mount_check`] — the mount the user named (foot or phone)
//! * [`gait_check`] — step lengths and cadence that fit human walking (timestamps' scale)

pub mod barometer;
pub mod foot;
pub mod foot_config;
pub mod frame_check;
pub mod gait_check;
pub mod heading_fusion;
pub mod mount_check;
pub mod phone;
pub mod stance;
pub mod step_detector;
pub mod step_field;
pub mod strapdown;
pub mod stride_model;
pub mod zupt;

pub use barometer::{BarometerConfig, pressure_height};
pub use foot::detect_strides;
pub use foot_config::{FootConfig, FootFigures};
pub use frame_check::{FrameFinding, check_foot_frame, check_phone_frame};
pub use gait_check::check_gait;
pub use heading_fusion::HeadingFusionConfig;
pub use mount_check::check_mount;
pub use phone::{HeadingFigures, PhoneConfig, PhoneFigures, detect_steps};
pub use step_detector::StepDetectorConfig;
pub use step_field::field_per_step;
pub use stride_model::{StrideModelConfig, calibrate_constant};

use crate::sensor::StepTrace;
use serde::{Deserialize, Serialize};

/// Where the IMU is worn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Mount {
    /// On the shoe: zero-velocity-aided INS, one event per stride.
    Foot,
    /// A phone held in the hand: step-and-heading system, one event per step.
    Phone,
}

/// How the step events' headings were obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HeadingSource {
    /// Integrated angular rate only: heading changes are measured, absolute heading is not
    /// (the `heading` column stays empty).
    Gyroscope,
    /// The recording's orientation quaternion (Android's rotation vector, sensor → ENU).
    RotationVector,
    /// Gyroscope fused with the magnetometer (a complementary filter).
    GyroMagnetometer,
}

/// What a front end made of a recording.
#[derive(Debug, Clone, PartialEq)]
pub struct StepEvents<F> {
    /// The step events, one per step (phone) or stride (foot), in time order.
    pub trace: StepTrace,
    /// The front end's own dead-reckoned position `[x, y, z]` (metres) after each event, in
    /// its navigation frame (x east and y north when the heading is absolute, else x along
    /// the initial heading); its first point is the start, so it holds one point more than
    /// `trace`.
    pub path: Vec<[f64; 3]>,
    /// How headings were obtained.
    pub heading_source: HeadingSource,
    /// The detector's figures (for `summary.json`).
    pub figures: F,
}

/// The configuration of `footslam steps`: one section per front end.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StepsConfig {
    /// The foot-mounted INS.
    pub foot: FootConfig,
    /// The phone's step-and-heading system.
    pub phone: PhoneConfig,
}

impl StepsConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) from [`FootConfig::validate`] or
    /// [`PhoneConfig::validate`], naming the first field out of its range.
    pub fn validate(&self) -> crate::Result<()> {
        self.foot.validate()?;
        self.phone.validate()
    }
}
