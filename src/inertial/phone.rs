//! Hand-held phone → steps: a step-and-heading system.

use super::StepEvents;
use crate::error::{Error, Result};
use crate::sensor::ImuRecording;
use serde::{Deserialize, Serialize};

/// Parameters of the phone step-and-heading system; every default in one place.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PhoneConfig {}

impl PhoneConfig {
    /// Checks every field against its documented range.
    pub fn validate(&self) -> Result<()> {
        Ok(())
    }
}

/// The detector's figures.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct PhoneFigures {}

/// Steps of a hand-held phone recording.
pub fn detect_steps(
    _recording: &ImuRecording,
    _config: &PhoneConfig,
) -> Result<StepEvents<PhoneFigures>> {
    Err(Error::Input("the phone step-and-heading system is not built yet".into()))
}
