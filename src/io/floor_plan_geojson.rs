//! Floor plans as RFC 7946 GeoJSON.
//!
//! A plan is one `FeatureCollection` with one `Polygon` feature per [`FloorPolygon`], in WGS84
//! `[lon, lat]` degrees rounded to 1e-8° (about a millimetre), exterior rings
//! counter-clockwise and holes clockwise (RFC 7946 sec. 3.1.6), no `crs` member. Feature
//! properties: `level` (integer floor level, default 0), `z` (surface height in metres,
//! default 0), `name` (optional) and `room` (optional: surfaces sharing it are one room for
//! radio-map cells). Holes are walls. `LineString` features with
//! `"barrier": true` are extra walls ([`Barrier`]) blocking the surfaces of their `level`
//! (default 0). The collection's foreign member `"origin": {"lat", "lon"}` names the local
//! frame's origin (x east, y north, metres).
//!
//! On reading, `MultiPolygon` features give one surface per part, `MultiLineString` barriers
//! one barrier per part, `LineString`s without `"barrier": true` are ignored (annotations),
//! and other geometries are errors. Surfaces must be valid polygons (closed rings, finite
//! coordinates, no self-intersection); every error names the file and the zero-based feature
//! index (and the surface's `name`).
//!
//! Which edges are walls and which are connections between surfaces follows from the
//! geometry (see [`crate::map::floor_topology`]): surfaces that share a boundary
//! (collinear within 5 cm) and differ in height by at most 0.5 m connect; a stair is a chain
//! of tread polygons each a rise above the previous.
//!
//! A plan to GeoJSON and back (to the file's millimetre):
//!
//! ```
//! use footslam::geometry::LocalFrame;
//! use footslam::io::floor_plan_geojson::{floor_plan_from_str, floor_plan_to_geojson};
//! use footslam::map::{FloorPlan, FloorPolygon};
//!
//! let frame = LocalFrame::new(51.5, -0.12).expect("a valid origin");
//! let stair_landing = FloorPolygon {
//!     polygon: geo::Rect::new((0.0, 0.0), (4.0, 3.0)).to_polygon(),
//!     level: 1,
//!     z: 3.2,
//!     name: Some("landing".into()),
//!     room: None,
//! };
//! let plan = FloorPlan { polygons: vec![stair_landing], barriers: Vec::new() };
//! let text = floor_plan_to_geojson(&plan, &frame).to_string();
//!
//! let (read, read_frame) = floor_plan_from_str(&text, "floor.geojson", None)?;
//! assert_eq!(read_frame, frame); // the file's `origin` member
//! let surface = &read.polygons[0];
//! assert_eq!((surface.level, surface.z, surface.name.as_deref()), (1, 3.2, Some("landing")));
//! assert!(read.is_walkable(3.99, 2.99, Some(1)) && !read.is_walkable(4.01, 1.0, Some(1)));
//!
//! // Without an `origin` member the frame must be given.
//! let bare = r#"{"type": "FeatureCollection", "features": []}"#;
//! let err = floor_plan_from_str(bare, "bare.geojson", None).unwrap_err();
//! assert!(err.to_string().starts_with("bare.geojson: no top-level `origin`"), "{err}");
//! # Ok::<(), footslam::Error>(())
//! ```

use crate::error::{Error, Result};
use crate::geometry::LocalFrame;
use crate::map::{Barrier, FloorPlan, FloorPolygon};
use geo::{Coord, LineString, Polygon, Validation, Winding};
use geojson::{
    Feature, FeatureCollection, Geometry, GeometryValue, JsonObject, JsonValue, PolygonType,
};
use serde_json::json;
use std::path::Path;

pub use super::geojson_file::DEGREE_DECIMALS;
use super::geojson_file::round_to;

/// The plan as a GeoJSON feature collection placed on the globe by `frame`.
#[must_use]
pub fn floor_plan_to_geojson(plan: &FloorPlan, frame: &LocalFrame) -> FeatureCollection {
    let features = plan
        .polygons
        .iter()
        .map(|f| surface_feature(f, frame))
        .chain(plan.barriers.iter().map(|b| barrier_feature(b, frame)))
        .collect();
    FeatureCollection {
        bbox: None,
        features,
        foreign_members: Some(super::geojson_file::origin_member(frame)),
    }
}

/// Writes [`floor_plan_to_geojson`] to `path` atomically.
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be written, as
/// [`write_atomically`](crate::io::write_atomically); an existing file is then left as it was.
pub fn write_floor_plan(path: &Path, plan: &FloorPlan, frame: &LocalFrame) -> Result<()> {
    crate::io::write_geojson(path, &floor_plan_to_geojson(plan, frame))
}

/// Reads a floor plan and the frame its local coordinates are in: `origin` when given (it
/// overrides the file's), else the file's `origin` member, else an error.
///
/// # Errors
///
/// * [`Error::Io`] when `path` cannot be read; [`Error::Parse`] naming the line when it is not a
///   GeoJSON `FeatureCollection`.
/// * [`Error::Parse`] on the file when there is no frame: no `origin` given and no valid
///   `origin` member ([`collection_frame`](crate::io::geojson_file::collection_frame)).
/// * [`Error::Parse`] naming the feature (and its `name`) when its geometry is missing or of
///   another type; `level`, `z`, `name`, `room` or `barrier` has the wrong type; a ring is
///   open or has under 4 positions, or a barrier line under 2; a position is not finite
///   degrees in range; or a polygon is not valid (e.g. self-intersecting) or has more than
///   [`MAX_POLYGON_VERTICES`] vertices.
/// * [`Error::Parse`] on the file when the plan breaks
///   [`FloorPlan::check_limits`](crate::map::FloorPlan::check_limits): no surface, too large or
///   too small, too many levels, a surface too high, or a surface given twice.
pub fn read_floor_plan(path: &Path, origin: Option<LocalFrame>) -> Result<(FloorPlan, LocalFrame)> {
    let collection = crate::io::geojson_file::read_feature_collection(path)?;
    floor_plan_from_collection(&collection, path, origin)
}

/// Reads a floor plan from GeoJSON `text` (the file format) as [`read_floor_plan`] reads a
/// file; errors name `name`.
///
/// # Errors
///
/// As [`read_floor_plan`], naming `name`, except that there is no file to read.
pub fn floor_plan_from_str(
    text: &str,
    name: &str,
    origin: Option<LocalFrame>,
) -> Result<(FloorPlan, LocalFrame)> {
    let path = Path::new(name);
    let collection = crate::io::geojson_file::feature_collection_from_str(text, path)?;
    floor_plan_from_collection(&collection, path, origin)
}

/// A floor plan from a parsed collection; errors name `path`.
fn floor_plan_from_collection(
    collection: &FeatureCollection,
    path: &Path,
    origin: Option<LocalFrame>,
) -> Result<(FloorPlan, LocalFrame)> {
    let whole = |message: String| Error::parse(path, 0, message);
    let frame = super::geojson_file::collection_frame(path, collection, origin)?;
    let mut plan = FloorPlan::default();
    for (i, feature) in collection.features.iter().enumerate() {
        read_feature(feature, &frame, &mut plan).map_err(|m| {
            let name = feature
                .property("name")
                .and_then(JsonValue::as_str)
                .map_or(String::new(), |n| format!(" (\"{n}\")"));
            whole(format!("feature {i}{name}: {m}"))
        })?;
    }
    plan.check_limits().map_err(whole)?;
    Ok((plan, frame))
}

/// A local polygon as RFC 7946 rings: exterior counter-clockwise, holes clockwise,
/// `[lon, lat]` degrees placed by `frame`.
pub(crate) fn polygon_positions(polygon: &Polygon<f64>, frame: &LocalFrame) -> Vec<Vec<Vec<f64>>> {
    let mut exterior = polygon.exterior().clone();
    exterior.make_ccw_winding();
    let mut rings = vec![to_positions(&exterior, frame)];
    for hole in polygon.interiors() {
        let mut hole = hole.clone();
        hole.make_cw_winding();
        rings.push(to_positions(&hole, frame));
    }
    rings
}

fn surface_feature(surface: &FloorPolygon, frame: &LocalFrame) -> Feature {
    let rings = polygon_positions(&surface.polygon, frame);
    let mut properties = JsonObject::new();
    properties.insert("level".into(), json!(surface.level));
    properties.insert("z".into(), json!(surface.z));
    if let Some(name) = &surface.name {
        properties.insert("name".into(), json!(name));
    }
    if let Some(room) = &surface.room {
        properties.insert("room".into(), json!(room));
    }
    Feature {
        bbox: None,
        geometry: Some(Geometry::new(GeometryValue::new_polygon(rings))),
        id: None,
        properties: Some(properties),
        foreign_members: None,
    }
}

fn barrier_feature(barrier: &Barrier, frame: &LocalFrame) -> Feature {
    let mut properties = JsonObject::new();
    properties.insert("barrier".into(), json!(true));
    properties.insert("level".into(), json!(barrier.level));
    Feature {
        bbox: None,
        geometry: Some(Geometry::new(GeometryValue::new_line_string(to_positions(
            &barrier.line,
            frame,
        )))),
        id: None,
        properties: Some(properties),
        foreign_members: None,
    }
}

/// A closed local ring as `[lon, lat]` positions.
fn to_positions(ring: &LineString<f64>, frame: &LocalFrame) -> Vec<Vec<f64>> {
    ring.coords()
        .map(|c| {
            let (lon, lat) = written_degrees(c.x, c.y, frame);
            vec![lon, lat]
        })
        .collect()
}

/// The `(lon, lat)` the writer stores for the local point `(x, y)`: placed by `frame`,
/// rounded to [`DEGREE_DECIMALS`] decimals. A plan whose corners are already
/// `frame.to_local(written_degrees(..))` reads back exactly.
#[must_use]
pub fn written_degrees(x: f64, y: f64, frame: &LocalFrame) -> (f64, f64) {
    let (lon, lat) = frame.to_lon_lat(x, y);
    (
        round_to(lon, DEGREE_DECIMALS),
        round_to(lat, DEGREE_DECIMALS),
    )
}

/// Appends the surfaces or barriers of `feature` to `out`.
fn read_feature(feature: &Feature, frame: &LocalFrame, out: &mut FloorPlan) -> Result<(), String> {
    let lines: Option<Vec<&Vec<geojson::Position>>> =
        match feature.geometry.as_ref().map(|g| &g.value) {
            Some(GeometryValue::LineString { coordinates }) => Some(vec![coordinates]),
            Some(GeometryValue::MultiLineString { coordinates }) => {
                Some(coordinates.iter().collect())
            }
            _ => None,
        };
    if let Some(lines) = lines {
        let barrier = match feature.property("barrier") {
            None | Some(JsonValue::Null) | Some(JsonValue::Bool(false)) => false,
            Some(JsonValue::Bool(true)) => true,
            Some(v) => return Err(format!("property `barrier` = {v} is not true or false")),
        };
        if barrier {
            let level = read_level(feature)?;
            for (j, line) in lines.into_iter().enumerate() {
                out.barriers.push(Barrier {
                    line: read_line(line, frame).map_err(|m| format!("line {j}: {m}"))?,
                    level,
                });
            }
        }
        return Ok(());
    }
    let parts: Vec<&PolygonType> = match feature.geometry.as_ref().map(|g| &g.value) {
        Some(GeometryValue::Polygon { coordinates }) => vec![coordinates],
        Some(GeometryValue::MultiPolygon { coordinates }) => coordinates.iter().collect(),
        Some(other) => {
            return Err(format!(
                "geometry type {} is not supported (expected Polygon, MultiPolygon or LineString)",
                other.type_name()
            ));
        }
        None => {
            return Err("has no geometry (expected Polygon, MultiPolygon or LineString)".into());
        }
    };
    let level = read_level(feature)?;
    let z = match feature.property("z") {
        None | Some(JsonValue::Null) => 0.0,
        Some(v) => v
            .as_f64()
            .filter(|z| z.is_finite())
            .ok_or_else(|| format!("property `z` = {v} is not a number of metres"))?,
    };
    let name = match feature.property("name") {
        None | Some(JsonValue::Null) => None,
        Some(JsonValue::String(s)) => Some(s.clone()),
        Some(v) => return Err(format!("property `name` = {v} is not a string")),
    };
    let room = match feature.property("room") {
        None | Some(JsonValue::Null) => None,
        Some(JsonValue::String(s)) => Some(s.clone()),
        Some(JsonValue::Number(n)) => Some(n.to_string()),
        Some(v) => return Err(format!("property `room` = {v} is not a string or number")),
    };
    for (j, rings) in parts.into_iter().enumerate() {
        check_vertices(rings).map_err(|m| format!("polygon {j}: {m}"))?;
        let polygon = read_polygon(rings, frame).map_err(|m| format!("polygon {j}: {m}"))?;
        if let Err(e) = polygon.check_validation() {
            return Err(format!("polygon {j}: not a valid polygon: {e}"));
        }
        out.polygons.push(FloorPolygon {
            polygon,
            level,
            z,
            name: name.clone(),
            room: room.clone(),
        });
    }
    Ok(())
}

/// Most vertices of one polygon (its rings together): validating a polygon compares every
/// pair of its edges, so a 100,000-vertex outline would take minutes. Floor plans drawn by
/// people hold tens to hundreds (ILC's largest: 220).
pub const MAX_POLYGON_VERTICES: usize = 10_000;

/// Refuses a polygon of more than [`MAX_POLYGON_VERTICES`] vertices, with the way out.
pub(crate) fn check_vertices(rings: &[Vec<geojson::Position>]) -> std::result::Result<(), String> {
    let n: usize = rings.iter().map(Vec::len).sum();
    if n > MAX_POLYGON_VERTICES {
        return Err(format!(
            "has {n} vertices, more than the {MAX_POLYGON_VERTICES} a polygon may have: \
             simplify it first (e.g. QGIS's Simplify, or shapely's simplify with a \
             tolerance of a few centimetres)"
        ));
    }
    Ok(())
}

const NOT_DEGREES: &str =
    "is not a finite [lon, lat] pair of degrees (lon in [-180, 180], lat in [-90, 90])";

/// True for a finite longitude and latitude in range.
fn degrees(lon: f64, lat: f64) -> bool {
    lon.is_finite() && lat.is_finite() && lon.abs() <= 180.0 && lat.abs() <= 90.0
}

/// The `level` property: an integer, default 0.
fn read_level(feature: &Feature) -> Result<i32, String> {
    match feature.property("level") {
        None | Some(JsonValue::Null) => Ok(0),
        Some(v) => v
            .as_i64()
            .and_then(|l| i32::try_from(l).ok())
            .ok_or_else(|| format!("property `level` = {v} is not an integer floor level")),
    }
}

/// A line of at least two finite `[lon, lat]` positions in local coordinates.
fn read_line(line: &[geojson::Position], frame: &LocalFrame) -> Result<LineString<f64>, String> {
    if line.len() < 2 {
        return Err(format!(
            "has {} positions; a line needs at least 2",
            line.len()
        ));
    }
    line.iter()
        .enumerate()
        .map(|(k, p)| match p.as_slice() {
            [lon, lat, ..] if degrees(*lon, *lat) => {
                let (x, y) = frame.to_local(*lon, *lat);
                Ok(Coord { x, y })
            }
            _ => Err(format!("position {k} {NOT_DEGREES}")),
        })
        .collect::<Result<Vec<_>, _>>()
        .map(LineString::new)
}

/// A polygon of `[lon, lat]` rings in local coordinates (rings closed, at least 4 finite
/// positions in range).
pub(crate) fn read_polygon(
    rings: &PolygonType,
    frame: &LocalFrame,
) -> Result<Polygon<f64>, String> {
    let mut local = rings
        .iter()
        .enumerate()
        .map(|(r, ring)| read_ring(ring, frame).map_err(|m| format!("ring {r}: {m}")));
    let exterior = local.next().ok_or("has no rings")??;
    let holes = local.collect::<Result<Vec<_>, _>>()?;
    Ok(Polygon::new(exterior, holes))
}

/// A closed ring of `[lon, lat]` positions in local coordinates.
fn read_ring(ring: &[geojson::Position], frame: &LocalFrame) -> Result<LineString<f64>, String> {
    if ring.len() < 4 {
        return Err(format!(
            "has {} positions; a closed ring needs at least 4",
            ring.len()
        ));
    }
    let mut coords = Vec::with_capacity(ring.len());
    for (k, p) in ring.iter().enumerate() {
        let (lon, lat) = match p.as_slice() {
            [lon, lat, ..] if degrees(*lon, *lat) => (*lon, *lat),
            _ => return Err(format!("position {k} {NOT_DEGREES}")),
        };
        let (x, y) = frame.to_local(lon, lat);
        coords.push(Coord { x, y });
    }
    if ring.first().map(|p| p.as_slice()) != ring.last().map(|p| p.as_slice()) {
        return Err("is not closed (its first and last positions differ)".into());
    }
    Ok(LineString::new(coords))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{OfficeConfig, office_floor};

    fn frame() -> LocalFrame {
        LocalFrame {
            lat: 48.0,
            lon: 11.0,
        }
    }

    fn write_text(text: &str) -> (tempfile::TempDir, std::path::PathBuf) {
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("plan.geojson");
        std::fs::write(&p, text).expect("write");
        (dir, p)
    }

    #[test]
    fn round_trips_the_office_with_rfc_7946_windings() {
        let plan = office_floor(&OfficeConfig::default()).expect("office");
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("plan.geojson");
        write_floor_plan(&p, &plan, &frame()).expect("write");
        let (back, f) = read_floor_plan(&p, None).expect("read");
        assert_eq!(f, frame());
        assert_eq!(back.polygons.len(), plan.polygons.len());
        for (a, b) in back.polygons.iter().zip(&plan.polygons) {
            assert_eq!((a.level, a.z, &a.name), (b.level, b.z, &b.name));
            assert_eq!(a.polygon.interiors().len(), b.polygon.interiors().len());
            for (ra, rb) in std::iter::once(a.polygon.exterior())
                .chain(a.polygon.interiors())
                .zip(std::iter::once(b.polygon.exterior()).chain(b.polygon.interiors()))
            {
                // Same corners (up to orientation), within the 1e-8° rounding.
                assert!(
                    ra.coords()
                        .all(|c| rb.coords().any(|d| (c.x - d.x).hypot(c.y - d.y) < 2e-3))
                );
            }
        }
        let value: JsonValue =
            serde_json::from_str(&std::fs::read_to_string(&p).expect("text")).expect("json");
        assert_eq!(value["origin"], json!({"lat": 48.0, "lon": 11.0}));
        assert!(value.get("crs").is_none());
        assert_eq!(
            value["features"][0]["properties"]["name"],
            json!("corridor")
        );
        let collection: FeatureCollection = serde_json::from_value(value).expect("collection");
        for feature in &collection.features {
            let Some(GeometryValue::Polygon { coordinates }) =
                feature.geometry.as_ref().map(|g| &g.value)
            else {
                panic!("not a polygon");
            };
            let ring = |r: &Vec<geojson::Position>| {
                LineString::from(r.iter().map(|p| (p[0], p[1])).collect::<Vec<_>>())
            };
            assert!(ring(&coordinates[0]).is_ccw());
            assert!(coordinates[1..].iter().all(|h| ring(h).is_cw()));
        }
    }

    #[test]
    fn reads_multipolygons_defaults_and_the_fallback_origin() {
        let square = "[[11.0,48.0],[11.0001,48.0],[11.0001,48.0001],[11.0,48.0001],[11.0,48.0]]";
        let beside =
            "[[11.0002,48.0],[11.0003,48.0],[11.0003,48.0001],[11.0002,48.0001],[11.0002,48.0]]";
        let text = format!(
            r#"{{"type":"FeatureCollection","features":[
            {{"type":"Feature","properties":{{"level":1,"z":3.5}},"geometry":{{"type":"MultiPolygon","coordinates":[[{square}],[{beside}]]}}}},
            {{"type":"Feature","properties":null,"geometry":{{"type":"LineString","coordinates":[[11.0,48.0],[11.1,48.0]]}}}},
            {{"type":"Feature","properties":{{"name":"hall"}},"geometry":{{"type":"Polygon","coordinates":[{square}]}}}}]}}"#
        );
        let (_dir, p) = write_text(&text);
        assert!(
            read_floor_plan(&p, None)
                .expect_err("must fail")
                .to_string()
                .contains("origin")
        );
        let (plan, f) = read_floor_plan(&p, Some(frame())).expect("read");
        assert_eq!(f, frame());
        assert_eq!(plan.polygons.len(), 3);
        assert_eq!((plan.polygons[0].level, plan.polygons[0].z), (1, 3.5));
        assert_eq!((plan.polygons[2].level, plan.polygons[2].z), (0, 0.0));
        assert_eq!(plan.polygons[2].name.as_deref(), Some("hall"));
        // 1e-4° of longitude at 48° is about 7.45 m.
        assert!(plan.is_walkable(7.0, 5.0, Some(0)) && !plan.is_walkable(8.0, 5.0, Some(0)));
    }

    #[test]
    fn barriers_round_trip_and_the_given_origin_overrides_the_files() {
        let mut plan = office_floor(&OfficeConfig::default()).expect("office");
        plan.barriers.push(Barrier {
            line: LineString::from(vec![(1.0, 2.0), (3.0, 2.0), (3.0, 5.0)]),
            level: 2,
        });
        plan.polygons[1].room = Some("lab 2".into());
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("plan.geojson");
        write_floor_plan(&p, &plan, &frame()).expect("write");
        let (back, _) = read_floor_plan(&p, None).expect("read");
        assert_eq!(back.barriers.len(), 1);
        assert_eq!(back.polygons[1].room.as_deref(), Some("lab 2"));
        assert_eq!(back.polygons[0].room, None);
        assert_eq!(back.barriers[0].level, 2);
        let c: Vec<_> = back.barriers[0].line.coords().collect();
        assert!((c[2].x - 3.0).abs() < 2e-3 && (c[2].y - 5.0).abs() < 2e-3);
        // Another origin moves the same file's local coordinates.
        let other = LocalFrame::new(48.0, 11.001).expect("frame");
        let (moved, f) = read_floor_plan(&p, Some(other)).expect("override");
        assert_eq!(f, other);
        let x0 = back.polygons[0].polygon.exterior().0[0].x;
        let x1 = moved.polygons[0].polygon.exterior().0[0].x;
        assert!((x0 - x1 - 74.6).abs() < 0.5, "{x0} {x1}");
    }

    #[test]
    fn malformed_files_are_rejected_with_the_feature_index() {
        let origin = r#""origin":{"lat":48.0,"lon":11.0}"#;
        let feature = |geometry: &str, properties: &str| {
            format!(r#"{{"type":"Feature","properties":{properties},"geometry":{geometry}}}"#)
        };
        let square = r#"{"type":"Polygon","coordinates":[[[11,48],[11.0001,48],[11.0001,48.0001],[11,48]]]}"#;
        let open = r#"{"type":"Polygon","coordinates":[[[11,48],[11.0001,48],[11.0001,48.0001],[11,48.0001]]]}"#;
        let point = r#"{"type":"Point","coordinates":[11,48]}"#;
        let collection = |features: &[String]| {
            format!(
                r#"{{"type":"FeatureCollection",{origin},"features":[{}]}}"#,
                features.join(",")
            )
        };
        let cases = [
            (
                collection(&[feature(square, "{}"), feature(open, "{}")]),
                "feature 1: polygon 0: ring 0: is not closed",
            ),
            (
                collection(&[feature(point, "{}")]),
                "feature 0: geometry type Point is not supported",
            ),
            (
                collection(&[feature("null", "{}")]),
                "feature 0: has no geometry",
            ),
            (
                collection(&[feature(square, r#"{"level":1.5}"#)]),
                "feature 0: property `level`",
            ),
            (
                collection(&[feature(square, r#"{"name":3}"#)]),
                "property `name`",
            ),
            (
                collection(&[feature(&square.replace("11.0001,48]", "NaN,48]"), "{}")]),
                "not a GeoJSON FeatureCollection",
            ),
            (
                r#"{"type":"FeatureCollection","origin":{"lat":"x"},"features":[]}"#.into(),
                "origin",
            ),
            ("[1, 2".into(), "not a GeoJSON FeatureCollection"),
        ];
        for (text, expected) in cases {
            let (_dir, p) = write_text(&text);
            let e = read_floor_plan(&p, None)
                .expect_err("must fail")
                .to_string();
            assert!(
                e.contains("plan.geojson") && e.contains(expected),
                "{e}\nexpected: {expected}"
            );
        }
        let bow_tie = r#"{"type":"Polygon","coordinates":[[[11,48],[11.0001,48.0001],[11.0001,48],[11,48.0001],[11,48]]]}"#;
        let far =
            r#"{"type":"Polygon","coordinates":[[[11,48],[191,48],[11.0001,48.0001],[11,48]]]}"#;
        for (text, expected) in [
            (
                collection(&[feature(bow_tie, r#"{"name":"lobby"}"#)]),
                "feature 0 (\"lobby\"): polygon 0: not a valid polygon",
            ),
            (
                collection(&[feature(far, "{}")]),
                "position 1 is not a finite [lon, lat] pair of degrees",
            ),
            (
                collection(&[feature(
                    r#"{"type":"LineString","coordinates":[[11,48]]}"#,
                    r#"{"barrier":true}"#,
                )]),
                "feature 0: line 0: has 1 positions",
            ),
            (
                collection(&[feature(
                    r#"{"type":"LineString","coordinates":[[11,48],[11,49]]}"#,
                    r#"{"barrier":"yes"}"#,
                )]),
                "property `barrier`",
            ),
        ] {
            let (_dir, p) = write_text(&text);
            let e = read_floor_plan(&p, None)
                .expect_err("must fail")
                .to_string();
            assert!(e.contains(expected), "{e}\nexpected: {expected}");
        }
        let missing = tempfile::tempdir().expect("tempdir");
        assert!(matches!(
            read_floor_plan(&missing.path().join("none.geojson"), None),
            Err(Error::Io { .. })
        ));
    }
}
