//! Layer 2: probabilistic models, apart from the filter machinery.

pub mod step_motion;
pub mod wifi_distance;
pub mod wifi_likelihood;

pub use step_motion::{StepErrorState, StepMotion, StepMotionConfig};
