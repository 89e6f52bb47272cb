//! Interactive map pages of runs (`footslam view`): what a run folder holds, read into map
//! layers, and written as one self-contained HTML page — its data and the vendored map
//! library (Leaflet) beside it — that a browser opens from disk, with no server and no
//! network.
//!
//! * [`layer`] — the page's layers: plans, learned maps, radio and field maps, paths
//! * [`path_csv`] — timed positions from CSV (tracks, truth, waypoints) placed on the globe
//! * [`run_layers`] — a run folder (and its `walk-N/` folders) read into layers
//! * [`page`] — the page written: `index.html`, `data.js`, the viewer's script and Leaflet

pub mod layer;
pub mod page;
pub mod path_csv;
pub mod run_layers;

pub use layer::{Layer, LayerData, LayerKind, PathPoint, ViewRun};
pub use page::{Basemap, Page, write_page};
pub use run_layers::{VIEWABLE_FILES, read_run, read_truth_layer, read_waypoints_layer};
