//! A learned hexagon transition map as RFC 7946 GeoJSON, and back.
//!
//! The file is one `FeatureCollection` with one `Polygon` feature per visited hexagon, in
//! WGS84 `[lon, lat]` degrees rounded to 1e-8° (about a millimetre). Each exterior ring is
//! counter-clockwise and closed (first corner repeated); there is no `crs` member.
//!
//! Feature properties:
//!
//! | key      | value                                                                    |
//! |----------|--------------------------------------------------------------------------|
//! | `q`, `r` | axial coordinates of the hexagon                                         |
//! | `counts` | crossings `N_e` of each edge, both directions, in edge order (below)      |
//! | `p`      | posterior-mean transition probabilities `(N_e + α) / (N + 6α)`, 4 decimals |
//! | `visits` | passes through the hexagon, `⌈N / 2⌉` (each pass crosses two edges)       |
//! | `level`  | the floor (0: the walk's first; one map per floor, read as 0 when absent)  |
//!
//! where `N = Σ_e N_e`. The edge order is that of [`HexGrid`]: 0 = E, 1 = NE, 2 = NW, 3 = W,
//! 4 = SW, 5 = SE (outward normals 60° apart, counter-clockwise from east).
//!
//! Foreign members of the collection make the file self-describing, so that
//! [`read_map_geojson`] can restore the map exactly: `origin` (`{"lat", "lon"}` of the local
//! frame), `hex_radius` (metres), `alpha` (the Dirichlet prior per edge), `edge_order`
//! (`["E","NE","NW","W","SW","SE"]`) and `walks` (how many walks' counts the map holds: 1 for
//! a learned map, the sum for a merge; read as 1 when absent) and, for maps of several
//! floors, `levels` (`[{"level", "z"}]`, each floor's height in metres above the first).

use super::geojson_file::{hexagon_ring, origin_member, polygon_feature, round_to};
use crate::error::{Error, Result};
use crate::geometry::{HexGrid, LocalFrame};
use crate::map::hex_transitions::{transition_probabilities, visits};
use crate::map::{FloorLevel, HexCell, HexMapSnapshot};
use geojson::{Feature, FeatureCollection, GeometryValue, JsonObject, JsonValue};
use hexx::Hex;
use serde_json::json;
use std::path::Path;

/// Names of the six edges in storage order, as written to the `edge_order` member.
pub const EDGE_ORDER: [&str; 6] = ["E", "NE", "NW", "W", "SW", "SE"];

/// Level numbers a map file may hold, ±.
const MAX_LEVEL: i64 = 1000;

/// A polygon centre may lie this fraction of a radius from its hexagon's centre on reading.
const CENTRE_TOLERANCE: f64 = 0.05;

/// The map as a GeoJSON feature collection placed on the globe by `frame`.
#[must_use]
pub fn map_to_geojson(map: &HexMapSnapshot, frame: &LocalFrame) -> FeatureCollection {
    walks_map_to_geojson(map, frame, 1)
}

/// As [`map_to_geojson`] for a map holding the counts of `walks` walks.
#[must_use]
pub fn walks_map_to_geojson(
    map: &HexMapSnapshot,
    frame: &LocalFrame,
    walks: u32,
) -> FeatureCollection {
    let grid = HexGrid::new(map.radius);
    let features = map
        .cells
        .iter()
        .map(|cell| cell_feature(&grid, frame, map.alpha, cell))
        .collect();
    let mut members = origin_member(frame);
    members.insert("hex_radius".into(), json!(map.radius));
    members.insert("alpha".into(), json!(map.alpha));
    members.insert("edge_order".into(), json!(EDGE_ORDER));
    members.insert("walks".into(), json!(walks));
    if !map.levels.is_empty() {
        members.insert("levels".into(), json!(map.levels));
    }
    FeatureCollection {
        bbox: None,
        features,
        foreign_members: Some(members),
    }
}

/// Writes [`map_to_geojson`] to `path` atomically.
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be written, as [`write_geojson`](crate::io::write_geojson);
/// an existing file is then left as it was.
pub fn write_map_geojson(path: &Path, map: &HexMapSnapshot, frame: &LocalFrame) -> Result<()> {
    super::write_geojson(path, &map_to_geojson(map, frame))
}

/// Writes [`walks_map_to_geojson`] to `path` atomically.
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be written, as [`write_geojson`](crate::io::write_geojson);
/// an existing file is then left as it was.
pub fn write_walks_map_geojson(
    path: &Path,
    map: &HexMapSnapshot,
    frame: &LocalFrame,
    walks: u32,
) -> Result<()> {
    super::write_geojson(path, &walks_map_to_geojson(map, frame, walks))
}

/// A map read back with its frame and the number of walks it holds.
///
/// A map to GeoJSON and back, exactly:
///
/// ```
/// use footslam::geometry::{LocalFrame, Pose2};
/// use footslam::io::map_geojson::{map_to_geojson, stored_map_from_str, walks_map_to_geojson};
/// use footslam::map::map_of_path;
///
/// let path: Vec<Pose2> = (1..=8).map(|i| Pose2::new(0.6 * f64::from(i), 0.0, 0.0)).collect();
/// let map = map_of_path(Pose2::default(), &path, &[0; 8], 0.5, 0.8);
/// let frame = LocalFrame::new(47.37, 8.54).expect("a valid origin");
///
/// // One hexagon polygon per visited cell, in WGS84.
/// let geojson = map_to_geojson(&map, &frame);
/// assert_eq!(geojson.features.len(), map.cells.len());
/// let text = geojson.to_string();
/// assert!(text.contains("\"hex_radius\":0.5") && text.contains("\"edge_order\""));
///
/// let stored = stored_map_from_str(&text, "map.geojson")?;
/// assert_eq!((stored.map, stored.frame, stored.walks), (map.clone(), frame, 1));
/// // A merged map says how many walks its counts hold.
/// let text = walks_map_to_geojson(&map, &frame, 3).to_string();
/// assert_eq!(stored_map_from_str(&text, "merged.geojson")?.walks, 3);
/// // A file that is not a map is refused, named.
/// let plan = r#"{"type": "FeatureCollection", "features": []}"#;
/// let err = stored_map_from_str(plan, "plan.geojson").unwrap_err();
/// assert!(err.to_string().starts_with("plan.geojson"), "{err}");
/// # Ok::<(), footslam::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct StoredMap {
    /// The counts.
    pub map: HexMapSnapshot,
    /// The frame it is placed by.
    pub frame: LocalFrame,
    /// Walks whose counts it holds (at least 1).
    pub walks: u32,
}

/// Reads a map written by [`write_map_geojson`] or [`write_walks_map_geojson`].
///
/// # Errors
///
/// As [`read_map_geojson`], and [`Error::Parse`] when the `walks` member is not an integer ≥ 1.
pub fn read_stored_map(path: &Path) -> Result<StoredMap> {
    let collection = crate::io::geojson_file::read_feature_collection(path)?;
    stored_map_from_collection(collection, path)
}

/// Reads a map from GeoJSON `text` (the format [`write_walks_map_geojson`] writes), as
/// [`read_stored_map`] reads a file; errors name `name`.
///
/// # Errors
///
/// As [`read_stored_map`], naming `name`, except that there is no file to read.
pub fn stored_map_from_str(text: &str, name: &str) -> Result<StoredMap> {
    let path = Path::new(name);
    let collection = crate::io::geojson_file::feature_collection_from_str(text, path)?;
    stored_map_from_collection(collection, path)
}

/// A stored map from a parsed collection; errors name `path`.
fn stored_map_from_collection(collection: FeatureCollection, path: &Path) -> Result<StoredMap> {
    let (map, frame, members) = map_and_members(collection, path)?;
    let walks = match members.get("walks") {
        None | Some(JsonValue::Null) => 1,
        Some(v) => v
            .as_u64()
            .and_then(|w| u32::try_from(w).ok())
            .filter(|&w| w >= 1)
            .ok_or_else(|| Error::parse(path, 0, format!("walks = {v}: must be an integer ≥ 1")))?,
    };
    Ok(StoredMap { map, frame, walks })
}

/// Reads a map written by [`write_map_geojson`], with the frame it was placed by.
///
/// Cells are restored from `q`, `r` and `counts`; each polygon must lie on its hexagon
/// (within 5 % of a radius), which catches files whose `origin` or `hex_radius` was edited.
/// Errors name the file and the zero-based feature index.
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be read; [`Error::Parse`] naming the line when it is not a
/// GeoJSON `FeatureCollection`, else naming the file (and the feature):
/// * `origin`, `hex_radius` or `alpha` is missing or out of range, `edge_order` is not
///   [`EDGE_ORDER`], or `levels` is malformed or out of range;
/// * a feature's `q`, `r`, `counts` (six non-negative integers) or `level` is missing or
///   malformed, or its polygon is not a closed ring centred on its hexagon;
/// * a hexagon appears twice on one level.
pub fn read_map_geojson(path: &Path) -> Result<(HexMapSnapshot, LocalFrame)> {
    let collection = crate::io::geojson_file::read_feature_collection(path)?;
    map_and_members(collection, path).map(|(map, frame, _)| (map, frame))
}

/// The map of a parsed collection, with the collection's foreign members; errors name
/// `path`.
fn map_and_members(
    collection: FeatureCollection,
    path: &Path,
) -> Result<(HexMapSnapshot, LocalFrame, JsonObject)> {
    let whole = |message: String| Error::parse(path, 0, message);
    let members = collection.foreign_members.unwrap_or_default();
    let (frame, radius, alpha) = read_header(&members).map_err(whole)?;
    let grid = HexGrid::new(radius);
    let mut cells = Vec::with_capacity(collection.features.len());
    for (i, feature) in collection.features.iter().enumerate() {
        let cell =
            read_cell(&grid, &frame, feature).map_err(|m| whole(format!("feature {i}: {m}")))?;
        cells.push(cell);
    }
    cells.sort_by_key(|c| (c.level, c.hex.x, c.hex.y));
    if let Some(pair) = cells
        .windows(2)
        .find(|w| (w[0].level, w[0].hex) == (w[1].level, w[1].hex))
    {
        return Err(whole(format!(
            "hexagon (q, r) = ({}, {}) of level {} appears twice",
            pair[0].hex.x, pair[0].hex.y, pair[0].level
        )));
    }
    let levels = read_levels(&members).map_err(whole)?;
    Ok((
        HexMapSnapshot {
            radius,
            alpha,
            cells,
            levels,
        },
        frame,
        members,
    ))
}

fn cell_feature(grid: &HexGrid, frame: &LocalFrame, alpha: f64, cell: &HexCell) -> Feature {
    let ring = hexagon_ring(grid, cell.hex, (0.0, 0.0), frame);
    let p = transition_probabilities(&cell.counts, alpha).map(|p| round_to(p, 4));
    let mut properties = JsonObject::new();
    properties.insert("q".into(), json!(cell.hex.x));
    properties.insert("r".into(), json!(cell.hex.y));
    properties.insert("counts".into(), json!(cell.counts));
    properties.insert("p".into(), json!(p));
    properties.insert("visits".into(), json!(visits(&cell.counts)));
    properties.insert("level".into(), json!(cell.level));
    polygon_feature(ring, properties)
}

/// `(frame, hex_radius, alpha)` from the collection's foreign members.
fn read_header(members: &JsonObject) -> Result<(LocalFrame, f64, f64), String> {
    let number = |v: Option<&JsonValue>, name: &str| {
        v.and_then(JsonValue::as_f64)
            .ok_or_else(|| format!("missing or non-numeric top-level member `{name}`"))
    };
    let origin = members.get("origin");
    let lat = number(origin.and_then(|o| o.get("lat")), "origin.lat")?;
    let lon = number(origin.and_then(|o| o.get("lon")), "origin.lon")?;
    let frame = LocalFrame::new(lat, lon)
        .ok_or_else(|| format!("origin ({lat}, {lon}) is not a latitude/longitude an origin may have (latitude within ±89°, longitude within ±180°)"))?;
    let radius = number(members.get("hex_radius"), "hex_radius")?;
    if !(radius.is_finite() && radius > 0.0) {
        return Err(format!(
            "hex_radius = {radius}: must be a positive number of metres"
        ));
    }
    let alpha = number(members.get("alpha"), "alpha")?;
    if !(alpha.is_finite() && alpha >= 0.0) {
        return Err(format!("alpha = {alpha}: must be finite and non-negative"));
    }
    if let Some(order) = members.get("edge_order")
        && *order != json!(EDGE_ORDER)
    {
        return Err(format!(
            "edge_order = {order}: only {} is supported",
            json!(EDGE_ORDER)
        ));
    }
    Ok((frame, radius, alpha))
}

fn read_cell(grid: &HexGrid, frame: &LocalFrame, feature: &Feature) -> Result<HexCell, String> {
    let axial = |name: &str| {
        feature
            .property(name)
            .and_then(JsonValue::as_i64)
            .and_then(|v| i32::try_from(v).ok())
            .ok_or_else(|| format!("property `{name}` is missing or not a 32-bit integer"))
    };
    let hex = Hex {
        x: axial("q")?,
        y: axial("r")?,
    };
    let counts = feature
        .property("counts")
        .and_then(JsonValue::as_array)
        .filter(|a| a.len() == 6)
        .ok_or("property `counts` is missing or not an array of 6 integers")?;
    let mut parsed = [0u32; 6];
    for (slot, value) in parsed.iter_mut().zip(counts) {
        *slot = value
            .as_u64()
            .and_then(|v| u32::try_from(v).ok())
            .ok_or_else(|| format!("counts entry {value} is not a non-negative 32-bit integer"))?;
    }
    check_polygon(grid, frame, feature, hex)?;
    let level = match feature.property("level") {
        None | Some(JsonValue::Null) => 0,
        Some(v) => v.as_i64().filter(|l| l.abs() <= MAX_LEVEL).ok_or_else(|| {
            format!("level = {v}: must be an integer in [-{MAX_LEVEL}, {MAX_LEVEL}]")
        })? as i32,
    };
    Ok(HexCell {
        hex,
        level,
        counts: parsed,
    })
}

/// The `levels` member: each floor's number and height (empty when absent).
fn read_levels(members: &JsonObject) -> Result<Vec<FloorLevel>, String> {
    let Some(value) = members.get("levels").filter(|v| !v.is_null()) else {
        return Ok(Vec::new());
    };
    let levels: Vec<FloorLevel> = serde_json::from_value(value.clone())
        .map_err(|e| format!("levels: {e} (an array of {{\"level\", \"z\"}})"))?;
    for l in &levels {
        if !(l.z.is_finite() && l.z.abs() <= 10_000.0 && i64::from(l.level).abs() <= MAX_LEVEL) {
            return Err(format!(
                "levels: level {} at z = {} m is out of range (|level| ≤ {MAX_LEVEL}, |z| ≤ 10 km)",
                l.level,
                crate::error::short_number(l.z)
            ));
        }
    }
    Ok(levels)
}

/// The feature's polygon must be a closed ring whose centre lies on hexagon `hex`.
fn check_polygon(
    grid: &HexGrid,
    frame: &LocalFrame,
    feature: &Feature,
    hex: Hex,
) -> Result<(), String> {
    let Some(GeometryValue::Polygon { coordinates }) = feature.geometry.as_ref().map(|g| &g.value)
    else {
        return Err("geometry is missing or not a Polygon".into());
    };
    let ring = coordinates.first().ok_or("polygon has no exterior ring")?;
    if ring.len() < 4 || ring.first() != ring.last() || ring.iter().any(|p| p.len() < 2) {
        return Err("exterior ring is not a closed ring of [lon, lat] positions".into());
    }
    let open = &ring[..ring.len() - 1];
    let n = open.len() as f64;
    let (lon, lat) = open
        .iter()
        .fold((0.0, 0.0), |(a, b), p| (a + p[0] / n, b + p[1] / n));
    let (x, y) = frame.to_local(lon, lat);
    let (cx, cy) = grid.center(hex);
    let off = (x - cx).hypot(y - cy);
    if off > CENTRE_TOLERANCE * grid.radius() {
        return Err(format!(
            "polygon centre lies {off:.3} m from the centre of hexagon ({}, {}); \
             hex_radius or origin do not match the geometry",
            hex.x, hex.y
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::{Coord, LineString, Winding};

    fn sample_map() -> HexMapSnapshot {
        HexMapSnapshot {
            radius: 0.5,
            alpha: 0.8,
            cells: vec![
                HexCell {
                    hex: Hex { x: -1, y: 2 },
                    counts: [0, 3, 0, 1, 0, 0],
                    level: 0,
                },
                HexCell {
                    hex: Hex { x: 0, y: 0 },
                    counts: [4, 0, 0, 3, 0, 0],
                    level: 0,
                },
                HexCell {
                    hex: Hex { x: 1, y: 0 },
                    counts: [0, 0, 0, 4, 0, 1],
                    level: 0,
                },
            ],
            levels: Vec::new(),
        }
    }

    fn frame() -> LocalFrame {
        LocalFrame {
            lat: 48.0,
            lon: 11.0,
        }
    }

    fn ring_of(feature: &Feature) -> Vec<Vec<f64>> {
        match feature.geometry.as_ref().map(|g| &g.value) {
            Some(GeometryValue::Polygon { coordinates }) => coordinates[0]
                .iter()
                .map(|p| p.as_slice().to_vec())
                .collect(),
            other => panic!("not a polygon: {other:?}"),
        }
    }

    #[test]
    fn text_reads_as_a_file_does() {
        let fc = walks_map_to_geojson(&sample_map(), &frame(), 3);
        let text = serde_json::to_string(&fc).expect("json");
        let stored = stored_map_from_str(&text, "map").expect("read");
        assert_eq!(stored.map, sample_map());
        assert_eq!((stored.frame, stored.walks), (frame(), 3));
        let e = stored_map_from_str("{\"type\": \"Feature", "maps[1]").unwrap_err();
        assert!(e.to_string().starts_with("maps[1]:1: not a GeoJSON"), "{e}");
    }

    #[test]
    fn properties_hold_the_hand_computed_values() {
        let fc = map_to_geojson(&sample_map(), &frame());
        assert_eq!(fc.features.len(), 3);
        let f = &fc.features[1];
        assert_eq!(f.property("q"), Some(&json!(0)));
        assert_eq!(f.property("counts"), Some(&json!([4, 0, 0, 3, 0, 0])));
        // N = 7, α = 0.8: (4 + 0.8) / 11.8 = 0.40678, 0.8 / 11.8 = 0.06780, 3.8 / 11.8 = 0.32203.
        assert_eq!(
            f.property("p"),
            Some(&json!([0.4068, 0.0678, 0.0678, 0.322, 0.0678, 0.0678]))
        );
        assert_eq!(f.property("visits"), Some(&json!(4)));
        let members = fc.foreign_members.as_ref().expect("members");
        assert_eq!(
            members["edge_order"],
            json!(["E", "NE", "NW", "W", "SW", "SE"])
        );
        assert_eq!(members["origin"], json!({ "lat": 48.0, "lon": 11.0 }));
        let text = fc.to_string();
        assert!(!text.contains("crs"));
    }

    #[test]
    fn rings_are_closed_counter_clockwise_and_lon_first() {
        let fc = map_to_geojson(&sample_map(), &frame());
        for f in &fc.features {
            let ring = ring_of(f);
            assert_eq!(ring.len(), 7);
            assert_eq!(ring[0], ring[6]);
            let line: LineString<f64> = ring.iter().map(|p| Coord { x: p[0], y: p[1] }).collect();
            assert!(line.is_ccw(), "ring not counter-clockwise: {ring:?}");
            for p in &ring {
                // Near (lon 11, lat 48): [lon, lat] order, rounded to 1e-8°.
                assert!(
                    (p[0] - 11.0).abs() < 1e-3 && (p[1] - 48.0).abs() < 1e-3,
                    "{p:?}"
                );
                assert!(((p[0] * 1e8).round() - p[0] * 1e8).abs() < 1e-3);
            }
        }
        // Hexagon (1, 0) is east of (0, 0): larger longitude, same latitude.
        let centre = |f: &Feature| {
            let r = ring_of(f);
            (
                r[..6].iter().map(|p| p[0]).sum::<f64>() / 6.0,
                r[..6].iter().map(|p| p[1]).sum::<f64>() / 6.0,
            )
        };
        let (a, b) = (centre(&fc.features[1]), centre(&fc.features[2]));
        assert!(b.0 > a.0 && (b.1 - a.1).abs() < 1e-9);
    }

    #[test]
    fn round_trips_through_a_file() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("map.geojson");
        let map = sample_map();
        write_map_geojson(&path, &map, &frame()).expect("write");
        let (back, f) = read_map_geojson(&path).expect("read");
        assert_eq!(back, map);
        assert_eq!(f, frame());
    }

    #[test]
    fn reading_names_the_feature_at_fault() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("bad.geojson");
        let mut fc = map_to_geojson(&sample_map(), &frame());
        if let Some(p) = fc.features[2].properties.as_mut() {
            p.insert("counts".into(), json!([1, 2, 3]));
        }
        std::fs::write(&path, fc.to_string()).expect("write");
        let err = read_map_geojson(&path).expect_err("must fail").to_string();
        assert!(
            err.contains("bad.geojson") && err.contains("feature 2") && err.contains("counts"),
            "{err}"
        );

        // A moved origin no longer matches the polygons.
        let mut fc = map_to_geojson(&sample_map(), &frame());
        if let Some(m) = fc.foreign_members.as_mut() {
            m.insert("origin".into(), json!({ "lat": 48.0001, "lon": 11.0 }));
        }
        std::fs::write(&path, fc.to_string()).expect("write");
        let err = read_map_geojson(&path).expect_err("must fail").to_string();
        assert!(err.contains("feature 0") && err.contains("origin"), "{err}");

        std::fs::write(
            &path,
            "{\"type\": \"FeatureCollection\",\n \"features\": [}",
        )
        .expect("write");
        let err = read_map_geojson(&path).expect_err("must fail").to_string();
        assert!(err.contains("bad.geojson:2"), "{err}");
    }

    #[test]
    fn probabilities_and_visits_of_edge_cases() {
        assert_eq!(transition_probabilities(&[0; 6], 0.0), [1.0 / 6.0; 6]);
        assert_eq!(visits(&[1, 0, 0, 0, 0, 0]), 1);
        assert_eq!(visits(&[1, 1, 1, 0, 0, 0]), 2);
    }
}
