//! A learned magnetic field map ([`FieldMapSnapshot`]) as RFC 7946 GeoJSON: one `Polygon`
//! feature per hexagon with readings, in WGS84 `[lon, lat]` degrees rounded to 1e-8°, each
//! ring counter-clockwise and closed, so that a magnetic localiser (or QGIS) can read the
//! field a FootSLAM run learned with no survey.
//!
//! Feature properties:
//!
//! | key            | value                                                            |
//! |----------------|------------------------------------------------------------------|
//! | `q`, `r`       | axial coordinates of the hexagon within its level                |
//! | `level`        | the floor (0: the walk's first)                                  |
//! | `readings`     | step readings averaged                                           |
//! | `magnitude_ut` | mean field magnitude, µT, 3 decimals                             |
//! | `vertical_ut`  | mean upward component, µT (only when the walk's readings had it) |
//!
//! Foreign members: `origin` (`{"lat", "lon"}` of the local frame), `cell_radius`
//! (metres), `offset` (`[x, y]` metres the hexagons were moved by, already applied to the
//! geometry) and `quantity` (`"magnetic field"`).

use super::geojson_file::{hexagon_ring, origin_member, polygon_feature, round_to};
use crate::error::Result;
use crate::geometry::{HexGrid, LocalFrame};
use crate::map::{FieldMapSnapshot, split_level_key};
use geojson::{FeatureCollection, JsonObject};
use serde_json::json;
use std::path::Path;

/// The field map as a GeoJSON feature collection placed on the globe by `frame`.
#[must_use]
pub fn field_map_to_geojson(map: &FieldMapSnapshot, frame: &LocalFrame) -> FeatureCollection {
    let grid = HexGrid::new(map.radius);
    let features = map
        .cells
        .iter()
        .map(|cell| {
            let (level, hex) = split_level_key(cell.key);
            let ring = hexagon_ring(&grid, hex, map.offset, frame);
            let mut properties = JsonObject::new();
            properties.insert("q".into(), json!(hex.x));
            properties.insert("r".into(), json!(hex.y));
            properties.insert("level".into(), json!(level));
            properties.insert("readings".into(), json!(cell.n));
            properties.insert("magnitude_ut".into(), json!(round_to(cell.mean[0], 3)));
            if map.components == 2 {
                properties.insert("vertical_ut".into(), json!(round_to(cell.mean[1], 3)));
            }
            polygon_feature(ring, properties)
        })
        .collect();
    let mut members = origin_member(frame);
    members.insert("cell_radius".into(), json!(map.radius));
    members.insert("offset".into(), json!([map.offset.0, map.offset.1]));
    members.insert("quantity".into(), json!("magnetic field"));
    FeatureCollection {
        bbox: None,
        features,
        foreign_members: Some(members),
    }
}

/// Writes [`field_map_to_geojson`] to `path` atomically.
///
/// # Errors
///
/// [`Error::Io`](crate::Error::Io) when `path` cannot be written, as
/// [`write_geojson`](crate::io::write_geojson); an existing file is then left as it was.
pub fn write_field_map_geojson(
    path: &Path,
    map: &FieldMapSnapshot,
    frame: &LocalFrame,
) -> Result<()> {
    super::write_geojson(path, &field_map_to_geojson(map, frame))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::{FieldMapCell, level_key};
    use hexx::Hex;

    #[test]
    fn hexagons_with_levels_and_components() {
        let frame = LocalFrame::new(48.15, 11.57).unwrap();
        let map = FieldMapSnapshot {
            radius: 1.0,
            components: 2,
            offset: (0.0, 0.0),
            cells: vec![
                FieldMapCell {
                    key: Hex::new(0, 0),
                    n: 3,
                    mean: [45.1234, -38.5],
                },
                FieldMapCell {
                    key: level_key(1, Hex::new(2, -1)),
                    n: 1,
                    mean: [50.0, -40.0],
                },
            ],
        };
        let fc = field_map_to_geojson(&map, &frame);
        assert_eq!(fc.features.len(), 2);
        // Each level's hexagons lie where that floor's are, not at their stacked key.
        let ring = |i: usize| match &fc.features[i].geometry.as_ref().unwrap().value {
            geojson::GeometryValue::Polygon { coordinates } => coordinates[0].clone(),
            other => panic!("{other:?}"),
        };
        for corner in ring(1) {
            assert!((corner[0] - 11.57).abs() < 1e-3 && (corner[1] - 48.15).abs() < 1e-3);
        }
        let p = fc.features[1].properties.as_ref().unwrap();
        assert_eq!((p["q"].as_i64(), p["r"].as_i64()), (Some(2), Some(-1)));
        assert_eq!(p["level"].as_i64(), Some(1));
        assert_eq!(p["vertical_ut"].as_f64(), Some(-40.0));
        let p = fc.features[0].properties.as_ref().unwrap();
        assert_eq!(p["magnitude_ut"].as_f64(), Some(45.123));
        assert_eq!(p["readings"].as_u64(), Some(3));
        let one = FieldMapSnapshot {
            components: 1,
            ..map
        };
        let fc = field_map_to_geojson(&one, &frame);
        assert!(
            !fc.features[0]
                .properties
                .as_ref()
                .unwrap()
                .contains_key("vertical_ut")
        );
        let text = fc.to_string();
        assert!(text.contains("\"quantity\":\"magnetic field\""), "{text}");
    }
}
