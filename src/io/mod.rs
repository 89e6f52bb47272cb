//! Layer 4: files. One module per file format, reading and writing it; every reader names the
//! file, line and problem in its errors, and every file is written completely or not at all.
//!
//! Recordings (the inputs of a run):
//! * [`steps_csv`] — step traces, `t,length,dheading[,dz][,heading][,field[,field_up]]`
//! * [`imu_csv`] — raw IMU recordings, `t,ax,ay,az,gx,gy,gz[,mx,my,mz][,qx,qy,qz,qw][,pressure]`
//! * [`wifi_csv`] — WiFi logs, `t,bssid,rssi[,ssid,freq]`
//! * [`gps_csv`], [`gpx_file`] — GPS fixes as CSV or GPX 1.1
//! * [`walk_manifest`] — a CSV naming many walks
//! * [`import`] — public datasets' recordings (Indoor Location Competition, IPIN)
//!
//! Plans and maps:
//! * [`floor_plan_geojson`] — 2.5D floor plans as GeoJSON
//! * [`outline_geojson`] — a building's rough outline as GeoJSON
//! * [`map_geojson`] — learned hexagon transition maps as GeoJSON
//! * [`field_map_geojson`] — learned magnetic field maps as GeoJSON
//! * [`radio_map_geojson`] — radio maps as GeoJSON (and CSV)
//! * [`ros_map`] — occupancy grids as ROS maps (`map.pgm` + `map.yaml`)
//!
//! Paths and truth:
//! * [`track_csv`] — a tracked walker's 2.5D positions, `t,x,y,z,level`
//! * [`trajectory_csv`] — timed positions, `t,x,y`
//! * [`track_geojson`] — a tracked walk as GeoJSON
//! * [`truth_csv`] — the simulator's true paths
//! * [`waypoints_csv`] — sparse ground-truth positions
//! * [`radio_truth_csv`] — the simulator's access points and expected RSSI field
//!
//! Plumbing:
//! * [`csv_table`] — header-addressed CSV reading shared by the CSV readers
//! * [`geojson_file`] — GeoJSON collections read and written, and their `origin` member
//! * [`atomic_file`] — files written completely or not at all
//! * [`run_folder`] — a run's output folder, committed completely or not at all

pub mod atomic_file;
pub mod csv_table;
pub mod field_map_geojson;
pub mod floor_plan_geojson;
pub mod geojson_file;
pub mod gps_csv;
pub mod gpx_file;
pub mod import;
pub mod imu_csv;
pub mod map_geojson;
pub mod outline_geojson;
pub mod radio_map_geojson;
pub mod radio_truth_csv;
pub mod ros_map;
pub mod run_folder;
pub mod steps_csv;
pub mod track_csv;
pub mod track_geojson;
pub mod trajectory_csv;
pub mod truth_csv;
pub mod walk_manifest;
pub mod waypoints_csv;
pub mod wifi_csv;

pub use atomic_file::{write_atomically, write_atomically_with};
pub use geojson_file::write_geojson;
pub use gps_csv::{read_gps_csv, write_gps_csv};
pub use gpx_file::{parse_utc_time, read_gpx};
pub use imu_csv::{ImuUnits, read_imu, read_imu_in, write_imu};
pub use outline_geojson::{WorldOutline, read_outline, read_world_outline, write_outline};
pub use ros_map::write_ros_map;
pub use run_folder::RunFolder;
pub use steps_csv::{read_steps, read_steps_with_field};
pub use track_csv::{SmoothedPoint, TrackPoint, read_track, write_smoothed_track, write_track};
pub use trajectory_csv::{
    TimedPoint, read_certain_trajectory, read_trajectory, write_trajectory, write_trajectory_with,
};
pub use walk_manifest::{ManifestWalk, read_walk_manifest, write_walk_manifest};
pub use waypoints_csv::{Waypoint, read_waypoints, write_waypoints};
pub use wifi_csv::{WifiLog, read_wifi, read_wifi_log, write_wifi};
