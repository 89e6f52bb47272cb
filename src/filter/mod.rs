//! Layer 3: particle-filter machinery and the filters built from it.

pub mod footslam;
pub mod footslam_config;
pub mod lineage;
pub mod resample;

pub use footslam::{FootSlam, FootSlamConfig, FootSlamEstimate};
pub use lineage::Lineage;
pub use resample::{ResampleConfig, ResampleMethod};
