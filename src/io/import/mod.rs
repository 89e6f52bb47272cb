//! Public datasets' recordings converted into footslam's types, each importer reading its
//! source's own format (file, line and problem named in its errors):
//!
//! * [`ilc_trace`] — Indoor Location Competition 2.0 traces: IMU, WiFi and waypoints
//! * [`ilc_floor`] — Indoor Location Competition 2.0 floors as floor plans
//! * [`ipin_log`] — IPIN competition smartphone logfiles: IMU, WiFi, GNSS and waypoints
//!
//! and the pieces they share:
//!
//! * [`log_lines`] — the lines of a phone sensor log, comments counted, a cut-off last line
//!   skipped
//! * [`sensor_streams`] — separately clocked sensor streams put onto the accelerometer's clock
//! * [`wifi_sightings`] — stale and repeated WiFi sightings dropped from a scan
//! * [`walkable_share`] — how many waypoints lie on an imported plan's walkable area

pub mod ilc_floor;
pub mod ilc_trace;
pub mod ipin_log;
pub mod log_lines;
pub mod sensor_streams;
pub mod walkable_share;
pub mod wifi_sightings;
