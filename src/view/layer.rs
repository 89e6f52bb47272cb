//! The layers of a viewer page: a run's files as the page draws them, on the WGS84 globe.

use crate::geometry::LocalFrame;
use serde::Serialize;
use std::path::PathBuf;

/// What a layer shows, and so how the page draws it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LayerKind {
    /// Walkable polygons: a floor plan (`floor.geojson`) or a learned plan
    /// (`plan.geojson`, `merged_plan.geojson`).
    Plan,
    /// A building's rough outline (`outline.geojson`).
    Outline,
    /// A learned hexagon transition map (`map.geojson`, `merged.geojson`): hexagons shaded
    /// by visits, transition arrows when zoomed in.
    HexMap,
    /// A radio map (`radiomap.geojson`): cells with each access point's mean RSSI.
    RadioMap,
    /// A learned magnetic field map (`fieldmap.geojson`).
    FieldMap,
    /// A run's answer: the estimated track (`track.csv`, else `track.geojson`).
    Track,
    /// The tracking filter's causal estimates (`track_filtered.csv`).
    FilteredTrack,
    /// The steps dead-reckoned from the start (`dead_reckoning.csv`).
    DeadReckoning,
    /// The true path (`truth.csv`, `--truth`).
    Truth,
    /// Sparse ground-truth points (`waypoints.csv`, `--waypoints`).
    Waypoints,
    /// GPS fixes (`gps.csv`), each with its accuracy as its spread.
    GpsFixes,
}

impl LayerKind {
    /// Whether the layer is a path of timed positions (drawn as a line with a marker the
    /// time slider moves), not GeoJSON features.
    #[must_use]
    pub fn is_path(self) -> bool {
        matches!(
            self,
            Self::Track
                | Self::FilteredTrack
                | Self::DeadReckoning
                | Self::Truth
                | Self::Waypoints
                | Self::GpsFixes
        )
    }
}

/// One timed position of a path, placed on the globe.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PathPoint {
    /// Time, seconds on the walk's clock.
    pub t: f64,
    /// Longitude, degrees.
    pub lon: f64,
    /// Latitude, degrees.
    pub lat: f64,
    /// Floor level, when the file says (a point without one is drawn on every level).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub level: Option<i32>,
    /// How far the estimate may be off, metres (`spread` or `spread_m`), when the file says.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub spread: Option<f64>,
    /// Whether the whole walk leaves one hypothesis here (`certain`), when the file says.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub certain: Option<bool>,
}

impl PathPoint {
    /// The point at local `(x, y)` metres of `frame`, at time `t`, with nothing else known.
    #[must_use]
    pub fn from_local(frame: &LocalFrame, t: f64, x: f64, y: f64) -> Self {
        let (lon, lat) = frame.to_lon_lat(x, y);
        Self {
            t,
            lon: crate::io::geojson_file::round_to(lon, DEGREE_DECIMALS),
            lat: crate::io::geojson_file::round_to(lat, DEGREE_DECIMALS),
            level: None,
            spread: None,
            certain: None,
        }
    }
}

/// Degrees of a page's coordinates are rounded to this many decimals (about a millimetre).
const DEGREE_DECIMALS: i32 = crate::io::geojson_file::DEGREE_DECIMALS;

/// What a layer draws.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LayerData {
    /// An RFC 7946 `FeatureCollection` as the file holds it, its foreign members kept (a
    /// radio map without its RSSI histograms).
    Geojson(serde_json::Value),
    /// Timed positions, in time order.
    Path(Vec<PathPoint>),
}

/// One layer of the page: a file of a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Layer {
    /// The name the page's layer list shows, e.g. `learned map` or `walk 2 · track`.
    pub name: String,
    /// What it shows.
    pub kind: LayerKind,
    /// The file it comes from, relative to the run folder (or as given, for `--truth`).
    pub file: String,
    /// The floor levels its features lie on, ascending (empty: none said).
    pub levels: Vec<i32>,
    /// How many features or points it holds.
    pub features: usize,
    /// What it draws.
    pub data: LayerData,
}

/// One run folder, read for the page.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ViewRun {
    /// The name the page gives the run (the folder's name).
    pub name: String,
    /// The folder as given.
    pub folder: PathBuf,
    /// The WGS84 origin of the run's local frame (x east, y north, metres).
    pub origin: LocalFrame,
    /// Metres per degree of longitude and of latitude at the origin, for the page's read-out
    /// of local coordinates.
    pub metres_per_degree: [f64; 2],
    /// Its layers, bottom to top.
    pub layers: Vec<Layer>,
    /// The files read, which the page's output folder must not replace.
    #[serde(skip)]
    pub inputs: Vec<PathBuf>,
}

impl ViewRun {
    /// A run named `name` with no layers yet.
    #[must_use]
    pub fn new(name: String, folder: PathBuf, origin: LocalFrame) -> Self {
        Self {
            name,
            folder,
            origin,
            metres_per_degree: metres_per_degree(&origin),
            layers: Vec::new(),
            inputs: Vec::new(),
        }
    }

    /// The floor levels of all its layers, ascending.
    #[must_use]
    pub fn levels(&self) -> Vec<i32> {
        let mut levels: Vec<i32> = self
            .layers
            .iter()
            .flat_map(|l| l.levels.iter().copied())
            .collect();
        levels.sort_unstable();
        levels.dedup();
        levels
    }
}

/// Metres per degree of longitude and of latitude at `frame`'s origin.
fn metres_per_degree(frame: &LocalFrame) -> [f64; 2] {
    const SPAN_M: f64 = 1000.0;
    let (east, _) = frame.to_lon_lat(SPAN_M, 0.0);
    let (_, north) = frame.to_lon_lat(0.0, SPAN_M);
    [
        SPAN_M / (east - frame.lon).abs().max(f64::MIN_POSITIVE),
        SPAN_M / (north - frame.lat).abs().max(f64::MIN_POSITIVE),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_degree_at_the_equator_is_about_111_km() {
        let [lon, lat] = metres_per_degree(&LocalFrame::default());
        assert!((lon - 111_319.5).abs() < 1.0, "{lon}");
        assert!((lat - 110_574.3).abs() < 1.0, "{lat}");
        let p = PathPoint::from_local(&LocalFrame::default(), 0.0, lon, 0.0);
        assert!((p.lon - 1.0).abs() < 1e-6 && p.lat == 0.0, "{p:?}");
    }
}
