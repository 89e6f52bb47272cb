//! A tracked walk as RFC 7946 GeoJSON: one `LineString` of the whole track (positions
//! `[lon, lat, z]`, z in metres above the plan's origin) and one `Point` per step with its
//! time, height and floor level, in WGS84 placed by the plan's local frame.

use crate::dataset::TrackPoint;
use crate::error::Result;
use crate::geometry::LocalFrame;
use geojson::{Feature, FeatureCollection, Geometry, GeometryValue, JsonObject};
use serde_json::json;
use std::path::Path;

/// Degrees are rounded to this many decimals (about a millimetre).
const DEGREE_DECIMALS: i32 = 8;

/// The track as a feature collection.
pub fn track_to_geojson(track: &[TrackPoint], frame: &LocalFrame) -> FeatureCollection {
    let position = |p: &TrackPoint| {
        let (lon, lat) = frame.to_lon_lat(p.x, p.y);
        vec![round(lon), round(lat), (p.z * 1000.0).round() / 1000.0]
    };
    let mut features = Vec::with_capacity(track.len() + 1);
    if track.len() >= 2 {
        let mut properties = JsonObject::new();
        properties.insert("kind".into(), json!("track"));
        properties.insert("t_start".into(), json!(track[0].t));
        properties.insert("t_end".into(), json!(track[track.len() - 1].t));
        features.push(feature(
            GeometryValue::new_line_string(track.iter().map(position).collect::<Vec<_>>()),
            properties,
        ));
    }
    for (i, p) in track.iter().enumerate() {
        let mut properties = JsonObject::new();
        properties.insert("kind".into(), json!("step"));
        properties.insert("index".into(), json!(i));
        properties.insert("t".into(), json!(p.t));
        properties.insert("z".into(), json!(p.z));
        properties.insert("level".into(), json!(p.level));
        features.push(feature(GeometryValue::new_point(position(p)), properties));
    }
    FeatureCollection {
        bbox: None,
        features,
        foreign_members: Some(crate::dataset::geojson_file::origin_member(frame)),
    }
}

/// Writes [`track_to_geojson`] to `path` atomically.
pub fn write_track_geojson(path: &Path, track: &[TrackPoint], frame: &LocalFrame) -> Result<()> {
    super::write_geojson(path, &track_to_geojson(track, frame))
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
}
