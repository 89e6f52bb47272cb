//! Layer 1: measurements as recorded, as plain validated data.

pub mod step;

pub use step::{Step, StepTrace};
