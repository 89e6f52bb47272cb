//! Layer 1: measurements as recorded, as plain validated data.
//!
//! * [`step`] — step events (length, heading change, height change, absolute heading)
//! * [`imu`] — raw inertial recordings
//! * [`field`] — the magnetic field over each step
//! * [`wifi`] — WiFi scans, and access points
//! * [`gps`] — GNSS position fixes
//! * [`truth`] — true paths, one pose per step (the simulator's, a reference system's)

pub mod field;
pub mod gps;
pub mod imu;
pub mod step;
pub mod truth;
pub mod wifi;

pub use field::{StepField, StepFields};
pub use gps::GpsFix;
pub use imu::{ImuRecording, ImuSample, SamplingReport};
pub use step::{Step, StepTrace};
pub use truth::{TruePath, TruePose};
pub use wifi::{AccessPoint, WifiReading, WifiScan};
