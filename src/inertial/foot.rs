//! Foot-mounted IMU → strides: a zero-velocity-aided strapdown INS.

use super::StepEvents;
use crate::error::{Error, Result};
use crate::sensor::ImuRecording;
use serde::{Deserialize, Serialize};

/// Parameters of the foot-mounted INS; every default in one place.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FootConfig {}

impl FootConfig {
    /// Checks every field against its documented range.
    pub fn validate(&self) -> Result<()> {
        Ok(())
    }
}

/// The detector's figures.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct FootFigures {}

/// Strides of a foot-mounted recording.
pub fn detect_strides(
    _recording: &ImuRecording,
    _config: &FootConfig,
) -> Result<StepEvents<FootFigures>> {
    Err(Error::Input("the foot-mounted INS is not built yet".into()))
}
