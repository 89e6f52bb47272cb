//! Layer 4 (in): one reader per file format. Every reader names the file, line and problem
//! in its errors.

pub mod csv_table;
pub mod floor_plan_geojson;
pub mod geojson_file;
pub mod gps_csv;
pub mod gpx_file;
pub mod ilc_floor;
pub mod ilc_trace;
pub mod imu_csv;
pub mod ipin_log;
pub mod log_lines;
pub mod outline_geojson;
pub mod radio_truth_csv;
pub mod sensor_streams;
pub mod steps_csv;
pub mod track_csv;
pub mod trajectory_csv;
pub mod truth_csv;
pub mod walk_manifest;
pub mod waypoints_csv;
pub mod wifi_csv;
pub mod wifi_sightings;

pub use gps_csv::{read_gps_csv, write_gps_csv};
pub use gpx_file::{parse_utc_time, read_gpx};
pub use imu_csv::{ImuUnits, read_imu, read_imu_in, write_imu};
pub use outline_geojson::{read_outline, write_outline};
pub use steps_csv::read_steps;
pub use track_csv::{SmoothedPoint, TrackPoint, read_track, write_smoothed_track, write_track};
pub use trajectory_csv::{TimedPoint, read_certain_trajectory, read_trajectory, write_trajectory};
pub use walk_manifest::{ManifestWalk, read_walk_manifest};
pub use waypoints_csv::{Waypoint, read_waypoints, write_waypoints};
pub use wifi_csv::{read_wifi, write_wifi};
