//! Layer 1: measurements as recorded, as plain validated data.

pub mod gps;
pub mod imu;
pub mod step;
pub mod truth;
pub mod wifi;

pub use gps::GpsFix;
pub use imu::{ImuRecording, ImuSample, SamplingReport};
pub use step::{Step, StepTrace};
pub use truth::{TruePath, TruePose};
pub use wifi::{AccessPoint, WifiReading, WifiScan};
