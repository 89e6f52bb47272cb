//! A tracked walk as RFC 7946 GeoJSON: one `LineString` of the whole track (positions
//! `[lon, lat, z]`, z in metres above the plan's origin) and one `Point` per step with its
//! time, height and floor level, in WGS84 placed by the plan's local frame.
//!
//! A track longer than [`MAX_STEP_POINTS`] steps (a day and more of walking) gets the line
//! alone, whose properties say how many Points were left out: `track.csv` holds every step,
//! and a GeoJSON Point per step of such a walk is gigabytes no GIS opens. The file is written
//! as it is serialised, never held in memory whole.

use crate::error::{Error, Result};
use crate::geometry::LocalFrame;
use crate::io::TrackPoint;
use geojson::{Feature, FeatureCollection, Geometry, GeometryValue, JsonObject};
use serde_json::json;
use std::path::Path;

/// Degrees are rounded to this many decimals (about a millimetre).
const DEGREE_DECIMALS: i32 = 8;

/// Longest track written with one Point per step (beyond: the line alone).
pub const MAX_STEP_POINTS: usize = 100_000;

/// The track as a feature collection (the Points of every step, whatever the length).
#[must_use]
pub fn track_to_geojson(track: &[TrackPoint], frame: &LocalFrame) -> FeatureCollection {
    let mut features = Vec::with_capacity(track.len() + 1);
    if track.len() >= 2 {
        let positions = track.iter().map(|p| position(p, frame)).collect::<Vec<_>>();
        features.push(line_feature(track, positions, 0));
    }
    features.extend(
        track
            .iter()
            .enumerate()
            .map(|(i, p)| point_feature(i, p, frame)),
    );
    shell(frame, features)
}

/// Writes the track to `path` atomically, streaming it: the bytes of
/// [`track_to_geojson`] for tracks up to [`MAX_STEP_POINTS`] steps, the line alone (with
/// `step_points_omitted`) beyond.
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be written, as
/// [`write_atomically_with`](crate::io::write_atomically_with); an existing file is then left
/// as it was. Points that are not finite are not refused: `serde_json` writes them as `null`.
pub fn write_track_geojson(path: &Path, track: &[TrackPoint], frame: &LocalFrame) -> Result<()> {
    let points = track.len() <= MAX_STEP_POINTS;
    let omitted = if points { 0 } else { track.len() };
    // The collection and the line serialised empty, the positions and Points written into
    // their arrays one at a time.
    let collection =
        serde_json::to_string(&shell(frame, Vec::new())).map_err(|e| Error::io(path, e.into()))?;
    let (head, tail) = super::geojson_file::split_once_at(&collection, "\"features\":[]");
    let line = (track.len() >= 2)
        .then(|| serde_json::to_string(&line_feature(track, Vec::new(), omitted)))
        .transpose()
        .map_err(|e| Error::io(path, e.into()))?;
    super::write_atomically_with(path, |w| {
        w.write_all(head.as_bytes())?;
        let mut first = true;
        if let Some(line) = &line {
            let (line_head, line_tail) =
                super::geojson_file::split_once_at(line, "\"coordinates\":[]");
            w.write_all(line_head.as_bytes())?;
            for (i, p) in track.iter().enumerate() {
                if i > 0 {
                    w.write_all(b",")?;
                }
                serde_json::to_writer(&mut *w, &position(p, frame))?;
            }
            w.write_all(line_tail.as_bytes())?;
            first = false;
        }
        if points {
            for (i, p) in track.iter().enumerate() {
                if !first {
                    w.write_all(b",")?;
                }
                first = false;
                serde_json::to_writer(&mut *w, &point_feature(i, p, frame))?;
            }
        }
        w.write_all(tail.as_bytes())
    })
}

/// A position `[lon, lat, z]`, degrees rounded to [`DEGREE_DECIMALS`], z to a millimetre.
fn position(p: &TrackPoint, frame: &LocalFrame) -> [f64; 3] {
    let (lon, lat) = frame.to_lon_lat(p.x, p.y);
    [round(lon), round(lat), (p.z * 1000.0).round() / 1000.0]
}

/// The whole track's line over `positions` (a track of at least two steps).
fn line_feature(track: &[TrackPoint], positions: Vec<[f64; 3]>, omitted: usize) -> Feature {
    let mut properties = JsonObject::new();
    properties.insert("kind".into(), json!("track"));
    properties.insert("t_start".into(), json!(track[0].t));
    properties.insert("t_end".into(), json!(track[track.len() - 1].t));
    if omitted > 0 {
        properties.insert("step_points_omitted".into(), json!(omitted));
    }
    let positions = positions.into_iter().map(Vec::from).collect::<Vec<_>>();
    feature(GeometryValue::new_line_string(positions), properties)
}

/// Step `i`'s Point.
fn point_feature(i: usize, p: &TrackPoint, frame: &LocalFrame) -> Feature {
    let mut properties = JsonObject::new();
    properties.insert("kind".into(), json!("step"));
    properties.insert("index".into(), json!(i));
    properties.insert("t".into(), json!(p.t));
    properties.insert("z".into(), json!(p.z));
    properties.insert("level".into(), json!(p.level));
    feature(
        GeometryValue::new_point(Vec::from(position(p, frame))),
        properties,
    )
}

fn shell(frame: &LocalFrame, features: Vec<Feature>) -> FeatureCollection {
    FeatureCollection {
        bbox: None,
        features,
        foreign_members: Some(crate::io::geojson_file::origin_member(frame)),
    }
}

fn feature(value: GeometryValue, properties: JsonObject) -> Feature {
    Feature {
        bbox: None,
        geometry: Some(Geometry::new(value)),
        id: None,
        properties: Some(properties),
        foreign_members: None,
    }
}

fn round(v: f64) -> f64 {
    let s = 10f64.powi(DEGREE_DECIMALS);
    (v * s).round() / s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_points_in_lon_lat_order() {
        let frame = LocalFrame::new(52.0, 0.1).expect("frame");
        let track = [
            TrackPoint {
                t: 1.0,
                x: 0.0,
                y: 0.0,
                z: 0.0,
                level: 0,
            },
            TrackPoint {
                t: 2.0,
                x: 10.0,
                y: 0.0,
                z: 3.0,
                level: 1,
            },
        ];
        let c = track_to_geojson(&track, &frame);
        assert_eq!(c.features.len(), 3);
        let text = serde_json::to_string(&c).expect("json");
        assert!(!text.contains("crs"));
        let Some(GeometryValue::Point { coordinates }) =
            c.features[2].geometry.as_ref().map(|g| &g.value)
        else {
            panic!("point expected");
        };
        assert!(coordinates[0] > 0.1 && (coordinates[1] - 52.0).abs() < 1e-6);
        assert_eq!(coordinates[2], 3.0);
        assert!(track_to_geojson(&[], &frame).features.is_empty());
    }

    #[test]
    fn the_streamed_file_is_the_collection_serialised() {
        let frame = LocalFrame::new(52.0, 0.1).expect("frame");
        let dir = std::env::temp_dir().join(format!("footslam-track-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("track.geojson");
        for n in [0, 1, 2, 7] {
            let track: Vec<TrackPoint> = (0..n)
                .map(|i| TrackPoint {
                    t: 1.7e9 + f64::from(i) * 0.55,
                    x: f64::from(i) * 0.7,
                    y: -0.3 * f64::from(i),
                    z: 0.1 * f64::from(i % 3),
                    level: i % 2,
                })
                .collect();
            write_track_geojson(&path, &track, &frame).expect("write");
            let written = std::fs::read_to_string(&path).expect("read");
            let whole = serde_json::to_string(&track_to_geojson(&track, &frame)).expect("json");
            assert_eq!(written, whole, "{n} steps");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
