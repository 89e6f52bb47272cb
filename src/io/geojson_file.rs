//! GeoJSON `FeatureCollection` files: read with the file and line named in errors, written
//! atomically, and the collection's `origin` foreign member (`{"lat", "lon"}`: the WGS84
//! place of the local frame).

use super::atomic_file::write_atomically;
use crate::error::{Error, Result};
use crate::geometry::LocalFrame;
use geojson::{FeatureCollection, JsonObject, JsonValue};
use serde_json::json;
use std::path::Path;

/// Foreign members holding `frame` as the `origin` member.
#[must_use]
pub fn origin_member(frame: &LocalFrame) -> JsonObject {
    let mut members = JsonObject::new();
    members.insert(
        "origin".into(),
        json!({ "lat": frame.lat, "lon": frame.lon }),
    );
    members
}

/// `v` rounded to `decimals` decimal places (dividing by the exact power of ten keeps the
/// printed form short).
#[must_use]
pub fn round_to(v: f64, decimals: i32) -> f64 {
    let scale = 10f64.powi(decimals);
    (v * scale).round() / scale
}

/// Degrees of a written coordinate are rounded to this many decimals (1e-8° is about
/// 1.1 mm of latitude).
pub const DEGREE_DECIMALS: i32 = 8;

/// The closed, counter-clockwise `[lon, lat]` ring of hexagon `hex` of `grid`, moved by
/// `offset` metres, placed on the globe by `frame`.
#[must_use]
pub fn hexagon_ring(
    grid: &crate::geometry::HexGrid,
    hex: hexx::Hex,
    offset: (f64, f64),
    frame: &LocalFrame,
) -> Vec<Vec<f64>> {
    let mut ring: Vec<Vec<f64>> = grid
        .corners(hex)
        .iter()
        .map(|&(x, y)| {
            let (lon, lat) = frame.to_lon_lat(x + offset.0, y + offset.1);
            vec![
                round_to(lon, DEGREE_DECIMALS),
                round_to(lat, DEGREE_DECIMALS),
            ]
        })
        .collect();
    if let Some(first) = ring.first().cloned() {
        ring.push(first);
    }
    ring
}

/// A feature of one polygon with the exterior `ring` (`[lon, lat]` pairs) and `properties`.
#[must_use]
pub fn polygon_feature(ring: Vec<Vec<f64>>, properties: JsonObject) -> geojson::Feature {
    geojson::Feature {
        bbox: None,
        geometry: Some(geojson::Geometry::new(geojson::GeometryValue::new_polygon(
            [ring],
        ))),
        id: None,
        properties: Some(properties),
        foreign_members: None,
    }
}

/// The frame of a collection read from `path`: `given` when there is one (it overrides the
/// file's), else the collection's `origin` member, else an error saying what to pass.
///
/// # Errors
///
/// Only when `given` is `None`: [`Error::Parse`] on `path` when the collection has no `origin`
/// member, or the member is not one [`read_origin`] accepts.
pub fn collection_frame(
    path: &Path,
    collection: &FeatureCollection,
    given: Option<LocalFrame>,
) -> Result<LocalFrame> {
    let member = collection
        .foreign_members
        .as_ref()
        .and_then(|m| m.get("origin"));
    match (given, member) {
        (Some(frame), _) => Ok(frame),
        (None, Some(member)) => read_origin(member).map_err(|m| Error::parse(path, 0, m)),
        (None, None) => Err(Error::parse(
            path,
            0,
            "no top-level `origin` member ({\"lat\": .., \"lon\": ..}) and no origin given: \
             pass the latitude and longitude of the local frame's origin",
        )),
    }
}

/// The frame an `origin` member names.
///
/// # Errors
///
/// A message when `origin` lacks a numeric `lat` or `lon`, or they are not a place an origin
/// may have ([`LocalFrame::new`]: latitude within ±89°, longitude within ±180°).
pub fn read_origin(origin: &JsonValue) -> Result<LocalFrame, String> {
    let number = |name: &str| {
        origin
            .get(name)
            .and_then(JsonValue::as_f64)
            .ok_or_else(|| format!("top-level member `origin` lacks a numeric `{name}`"))
    };
    let (lat, lon) = (number("lat")?, number("lon")?);
    LocalFrame::new(lat, lon)
        .ok_or_else(|| format!("origin ({lat}, {lon}) is not a latitude/longitude an origin may have (latitude within ±89°, longitude within ±180°)"))
}

/// The text of a JSON file without a leading byte-order mark (editors on Windows write one;
/// RFC 8259 lets a parser ignore it, and the CSV readers do).
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be read or is not UTF-8.
pub fn read_json_text(path: &Path) -> Result<String> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    Ok(match text.strip_prefix('\u{feff}') {
        Some(rest) => rest.to_owned(),
        None => text,
    })
}

/// Reads `path` as an RFC 7946 `FeatureCollection`.
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be read or is not UTF-8; as
/// [`feature_collection_from_str`] when its text is not a `FeatureCollection`.
pub fn read_feature_collection(path: &Path) -> Result<FeatureCollection> {
    feature_collection_from_str(&read_json_text(path)?, path)
}

/// Parses `text` as an RFC 7946 `FeatureCollection`; errors name `name` (a file's path, or a
/// name for text held in memory) and the line.
///
/// # Errors
///
/// [`Error::Parse`] naming `name` and the line when `text` is not JSON, or is JSON but not a
/// GeoJSON `FeatureCollection` (another GeoJSON object, a missing or malformed member).
pub fn feature_collection_from_str(text: &str, name: &Path) -> Result<FeatureCollection> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    serde_json::from_str(text).map_err(|e| {
        Error::parse(
            name,
            e.line(),
            format!("not a GeoJSON FeatureCollection: {e}"),
        )
    })
}

/// Writes a GeoJSON feature collection to `path` atomically.
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be written, as [`write_atomically`]; an existing file is
/// then left as it was.
pub fn write_geojson(path: &Path, collection: &geojson::FeatureCollection) -> Result<()> {
    let text = serde_json::to_string(collection).map_err(|e| Error::io(path, e.into()))?;
    write_atomically(path, text.as_bytes())
}

/// `text` split around the first `marker`, the marker's last character (`]`) kept in the
/// tail; panics when there is none (a serialisation of our own types).
pub(crate) fn split_once_at<'a>(text: &'a str, marker: &str) -> (&'a str, &'a str) {
    let at = text
        .find(marker)
        .expect("the serialised shell holds its empty array");
    let cut = at + marker.len() - 1;
    (&text[..cut], &text[cut..])
}
