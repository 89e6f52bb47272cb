//! Evaluation of estimates against references: position errors of a track against the
//! ground truth, and how much of a learned map lies in a floor plan's walkable space.

pub mod position_error;
pub mod walkable;

pub use position_error::{Alignment, ErrorReport, position_errors};
pub use walkable::walkable_fraction;
