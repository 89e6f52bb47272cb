//! Layer 2: probabilistic models, apart from the filter machinery.

pub mod derived_epsilon;
pub mod floor_levels;
pub mod gps_likelihood;
pub mod heading_likelihood;
pub mod step_motion;
pub mod transition_prior;
pub mod wifi_distance;
pub mod wifi_likelihood;

pub use floor_levels::{FloorLevel, LevelConfig, LevelTracker, find_levels};
pub use gps_likelihood::{GpsConfig, GpsLikelihood, GpsObservation};
pub use heading_likelihood::{HeadingConfig, HeadingConstants, HeadingLikelihood};
pub use step_motion::{StepErrorState, StepMotion, StepMotionConfig};
pub use transition_prior::{TransitionPrior, TransitionPriorConfig};
