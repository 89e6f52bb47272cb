//! A building's outline (outer perimeter) as RFC 7946 GeoJSON: a `Polygon` (or a
//! `MultiPolygon` of one part) given as a bare geometry, a `Feature`, or a
//! `FeatureCollection` holding exactly one polygon feature. Only the exterior ring is used.

use super::floor_plan_geojson::{polygon_positions, read_polygon};
use crate::error::{Error, Result};
use crate::geometry::LocalFrame;
use geo::{Polygon, Validation};
use geojson::{Feature, FeatureCollection, GeoJson, Geometry, GeometryValue, JsonObject};
use serde_json::json;
use std::path::Path;

/// A building's outline as read, in WGS84 (longitude, latitude): [`WorldOutline::project`]
/// puts it in a run's frame once the run knows its frame.
///
/// ```
/// use footslam::geometry::LocalFrame;
/// use footslam::io::outline_geojson::world_outline_from_str;
/// use geo::Area;
/// let text = r#"{"type": "Polygon", "coordinates":
///     [[[11, 48], [11.001, 48], [11.001, 48.001], [11, 48.001], [11, 48]]]}"#;
/// let outline = world_outline_from_str(text, "outline.geojson")?;
/// let frame = LocalFrame::new(48.0, 11.0).expect("a place on Earth");
/// let area = outline.project(&frame)?.unsigned_area();
/// assert!((8000.0..8400.0).contains(&area), "{area} m²");
/// # Ok::<(), footslam::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct WorldOutline {
    /// The exterior ring's positions, `[lon, lat]` degrees.
    ring: geojson::PolygonType,
    /// The file (or name) it came from, for errors.
    name: std::path::PathBuf,
}

impl WorldOutline {
    /// The outline in the local frame `frame`: a valid polygon, or an error naming the file.
    ///
    /// # Errors
    ///
    /// [`Error::Parse`] naming the outline's file when its ring has under 4 positions, is open,
    /// holds a position that is not finite degrees in range, or is not a valid polygon (e.g.
    /// self-intersecting).
    pub fn project(&self, frame: &LocalFrame) -> Result<Polygon<f64>> {
        let whole = |m: String| Error::parse(&self.name, 0, m);
        let polygon =
            read_polygon(&self.ring, frame).map_err(|m| whole(format!("outline polygon: {m}")))?;
        let polygon = Polygon::new(polygon.exterior().clone(), Vec::new());
        if let Err(e) = polygon.check_validation() {
            return Err(whole(format!("outline polygon is not valid: {e}")));
        }
        Ok(polygon)
    }
}

/// Reads the outline polygon in the local frame `frame`; errors name the file and problem.
///
/// # Errors
///
/// As [`read_world_outline`], then as [`WorldOutline::project`].
pub fn read_outline(path: &Path, frame: &LocalFrame) -> Result<Polygon<f64>> {
    read_world_outline(path)?.project(frame)
}

/// Reads the outline of a GeoJSON file, in WGS84; errors name the file and problem.
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be read; [`Error::Parse`] when it is not GeoJSON (naming
/// the line), a `Feature` has no geometry, a `FeatureCollection` holds other than exactly one
/// polygon feature, the geometry is not a Polygon or one-part `MultiPolygon`, or its exterior
/// ring has more than [`MAX_POLYGON_VERTICES`](super::floor_plan_geojson::MAX_POLYGON_VERTICES)
/// positions. The positions themselves are checked by [`WorldOutline::project`].
pub fn read_world_outline(path: &Path) -> Result<WorldOutline> {
    outline_from_text(&super::geojson_file::read_json_text(path)?, path)
}

/// Reads the outline from GeoJSON `text` (a Polygon, Feature or `FeatureCollection` of one,
/// as [`read_world_outline`] reads a file); errors name `name`.
///
/// # Errors
///
/// As [`read_world_outline`], naming `name`, except that there is no file to read.
pub fn world_outline_from_str(text: &str, name: &str) -> Result<WorldOutline> {
    outline_from_text(text, Path::new(name))
}

/// Reads the outline polygon from GeoJSON `text` in the local frame `frame`; errors name
/// `name`.
///
/// # Errors
///
/// As [`world_outline_from_str`], then as [`WorldOutline::project`].
pub fn outline_from_str(text: &str, name: &str, frame: &LocalFrame) -> Result<Polygon<f64>> {
    world_outline_from_str(text, name)?.project(frame)
}

/// The outline of `text`; errors name `path`.
fn outline_from_text(text: &str, path: &Path) -> Result<WorldOutline> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let whole = |m: String| Error::parse(path, 0, m);
    let json: GeoJson = serde_json::from_str(text)
        .map_err(|e| Error::parse(path, e.line(), format!("not GeoJSON: {e}")))?;
    let geometry = match json {
        GeoJson::Geometry(g) => g,
        GeoJson::Feature(f) => f
            .geometry
            .ok_or_else(|| whole("the feature has no geometry".into()))?,
        GeoJson::FeatureCollection(fc) => {
            let polygons: Vec<Geometry> = fc
                .features
                .into_iter()
                .filter_map(|f| f.geometry)
                .filter(|g| {
                    matches!(
                        g.value,
                        GeometryValue::Polygon { .. } | GeometryValue::MultiPolygon { .. }
                    )
                })
                .collect();
            match <[Geometry; 1]>::try_from(polygons) {
                Ok([g]) => g,
                Err(v) => {
                    return Err(whole(format!(
                        "the collection holds {} polygon features; an outline is exactly one",
                        v.len()
                    )));
                }
            }
        }
    };
    let rings = match geometry.value {
        GeometryValue::Polygon { coordinates } => coordinates,
        GeometryValue::MultiPolygon { coordinates } if coordinates.len() == 1 => {
            coordinates.into_iter().next().unwrap_or_default()
        }
        other => {
            return Err(whole(format!(
                "geometry type {} is not an outline (expected one Polygon)",
                other.type_name()
            )));
        }
    };
    let exterior: geojson::PolygonType = rings.into_iter().take(1).collect();
    crate::io::floor_plan_geojson::check_vertices(&exterior)
        .map_err(|m| whole(format!("outline polygon: {m}")))?;
    Ok(WorldOutline {
        ring: exterior,
        name: path.to_path_buf(),
    })
}

/// Writes `outline` (local coordinates placed by `frame`) as a `FeatureCollection` holding one
/// Polygon feature, atomically.
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be written, as
/// [`write_atomically`](crate::io::write_atomically); an existing file is then left as it was.
pub fn write_outline(path: &Path, outline: &Polygon<f64>, frame: &LocalFrame) -> Result<()> {
    let mut properties = JsonObject::new();
    properties.insert("name".into(), json!("outline"));
    let feature = Feature {
        bbox: None,
        geometry: Some(Geometry::new(GeometryValue::new_polygon(
            polygon_positions(outline, frame),
        ))),
        id: None,
        properties: Some(properties),
        foreign_members: None,
    };
    let collection = FeatureCollection {
        bbox: None,
        features: vec![feature],
        foreign_members: Some(super::geojson_file::origin_member(frame)),
    };
    crate::io::write_geojson(path, &collection)
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::{Area, Rect};

    fn frame() -> LocalFrame {
        LocalFrame::new(48.0, 11.0).expect("frame")
    }

    #[test]
    fn round_trips_and_accepts_a_bare_feature() {
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("outline.geojson");
        let rect = Rect::new((-5.0, -5.0), (30.0, 20.0)).to_polygon();
        write_outline(&p, &rect, &frame()).expect("write");
        let back = read_outline(&p, &frame()).expect("read");
        assert!((back.unsigned_area() - 35.0 * 25.0).abs() < 0.05);
        let text = std::fs::read_to_string(&p).expect("text");
        let fc: FeatureCollection = text.parse().expect("fc");
        std::fs::write(&p, fc.features[0].to_string()).expect("write");
        assert!(
            (read_outline(&p, &frame()).expect("feature").unsigned_area() - 875.0).abs() < 0.05
        );
    }

    #[test]
    fn bad_outlines_are_explained() {
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("outline.geojson");
        std::fs::write(&p, r#"{"type": "FeatureCollection", "features": []}"#).expect("w");
        let e = read_outline(&p, &frame()).unwrap_err().to_string();
        assert!(
            e.contains("outline.geojson") && e.contains("0 polygon"),
            "{e}"
        );
        std::fs::write(&p, r#"{"type": "Point", "coordinates": [11, 48]}"#).expect("w");
        let e = read_outline(&p, &frame()).unwrap_err().to_string();
        assert!(e.contains("Point"), "{e}");
        std::fs::write(
            &p,
            r#"{"type": "Polygon", "coordinates": [[[11, 48], [11.001, 48], [11.001, 48.001], [11, 48]]]}"#,
        )
        .expect("w");
        assert!(read_outline(&p, &frame()).is_ok());
        std::fs::write(
            &p,
            r#"{"type": "Polygon", "coordinates": [[[11, 48], [11.001, 48], [11.001, 48.001], [11, 48.2]]]}"#,
        )
        .expect("w");
        assert!(
            read_outline(&p, &frame())
                .unwrap_err()
                .to_string()
                .contains("closed")
        );
        std::fs::write(&p, "{").expect("w");
        assert!(read_outline(&p, &frame()).is_err());
    }
}
