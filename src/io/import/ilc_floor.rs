//! Floors of the Microsoft Indoor Location Competition 2.0 (ILC; MIT licence, © XYZ10 Inc.)
//! as footslam floor plans.
//!
//! A floor folder holds `floor_info.json` (`{"map_info": {"width": W, "height": H}}`, metres)
//! and `geojson_map.json` (WGS84; the first feature is the floor outline, Polygon or
//! `MultiPolygon`; the others are shops and rooms). The competition's waypoints live in a
//! metre frame onto which the GeoJSON's bounding box maps linearly: `[min_lon, max_lon] →
//! [0, W]` (x east), `[min_lat, max_lat] → [0, H]` (y north, no flip). [`read_ilc_floor`]
//! takes every polygon into that frame and [`IlcFloor::plan`] builds a [`FloorPlan`] (level
//! 0, z 0) whose walkable area is, by [`Walkable`]:
//! * `Outline`: the whole floor outline (shops are walkable; a walker who enters one is not
//!   lost to the filter);
//! * `Corridors`: the outline minus the union of the shops (`geo::BooleanOps`), i.e. the
//!   public corridors only.
//!
//! The polygons are cleaned by the boolean operations (valid output, no self-intersection);
//! parts and holes smaller than [`MIN_PART_AREA`] are dropped (slivers between shops).
//! [`IlcFloor::frame`] puts the local frame's origin at the bounding box's south-west corner,
//! so that a plan written with it reads back in the waypoints' metres (the frame's own
//! metres differ slightly from the W × H scaling; [`IlcFloorSummary::geodesic_width_m`]
//! tells by how much).

use crate::error::{Error, Result};
use crate::geometry::LocalFrame;
use crate::io::floor_plan_geojson::written_degrees;
use crate::map::{FloorPlan, FloorPolygon};
use geo::{
    Area, BooleanOps, Coord, LineString, MapCoords, MultiPolygon, Orient, Polygon, Validation,
    orient::Direction,
};
use serde::Serialize;
use serde_json::Value;
use std::path::Path;

/// Parts and holes smaller than this are dropped from the walkable area, m².
pub const MIN_PART_AREA: f64 = 0.5;

/// Which part of an ILC floor is walkable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Walkable {
    /// The whole floor outline, shops included.
    Outline,
    /// The outline minus the shops and rooms.
    Corridors,
}

/// A floor's figures.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IlcFloorSummary {
    /// The floor's extent from `floor_info.json`, metres.
    pub width_m: f64,
    /// The floor's extent from `floor_info.json`, metres.
    pub height_m: f64,
    /// The GeoJSON's bounding box `[min_lon, min_lat, max_lon, max_lat]`, degrees.
    pub bbox: [f64; 4],
    /// The bounding box's east-west extent on the WGS84 ellipsoid, metres.
    pub geodesic_width_m: f64,
    /// The bounding box's north-south extent on the WGS84 ellipsoid, metres.
    pub geodesic_height_m: f64,
    /// The outline feature's `name`, when given.
    pub floor_name: Option<String>,
    /// Shop and room polygons read.
    pub shops: usize,
    /// Area of the outline, m².
    pub outline_area_m2: f64,
    /// Area of the union of the shops within the outline, m².
    pub shop_area_m2: f64,
}

/// A floor read from its two files, in the waypoints' metre frame.
#[derive(Debug, Clone)]
pub struct IlcFloor {
    /// The floor outline, cleaned.
    pub outline: MultiPolygon<f64>,
    /// The union of the shops and rooms.
    pub shops: MultiPolygon<f64>,
    /// The frame placing local metres on the globe (origin at the bounding box's
    /// south-west corner).
    pub frame: LocalFrame,
    /// Figures.
    pub summary: IlcFloorSummary,
}

/// What building a plan dropped.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlanReport {
    /// The choice made.
    pub walkable: Walkable,
    /// Surfaces in the plan.
    pub surfaces: usize,
    /// Walkable area, m².
    pub walkable_area_m2: f64,
    /// Parts and holes under [`MIN_PART_AREA`] dropped.
    pub slivers_dropped: usize,
}

/// Reads `floor_info.json` and `geojson_map.json` from `dir`. Errors name the file (and the
/// zero-based feature).
///
/// # Errors
///
/// [`Error::Io`] when a file cannot be read, else [`Error::Parse`] naming it:
/// * `floor_info.json`: not JSON, or `map_info`'s `width` or `height` is not a number of
///   metres in (0, 100000);
/// * `geojson_map.json`: not JSON, no features, a feature (named by index) that is not a
///   Polygon or `MultiPolygon` of rings of at least 3 finite positions, a bounding box with no
///   extent, outside WGS84 degrees or within a degree of a pole, or an outline with no area.
pub fn read_ilc_floor(dir: &Path) -> Result<IlcFloor> {
    let info_path = dir.join("floor_info.json");
    let map_path = dir.join("geojson_map.json");
    let info = read_json(&info_path)?;
    let size = |name: &str| {
        info.get("map_info")
            .and_then(|m| m.get(name))
            .and_then(Value::as_f64)
            .filter(|v| v.is_finite() && *v > 0.0 && *v < 1e5)
            .ok_or_else(|| {
                Error::parse(
                    &info_path,
                    0,
                    format!(
                        "expected {{\"map_info\": {{\"{name}\": a positive number of metres}}}}"
                    ),
                )
            })
    };
    let (width, height) = (size("width")?, size("height")?);
    let map = read_json(&map_path)?;
    let whole = |m: String| Error::parse(&map_path, 0, m);
    let features = map
        .get("features")
        .and_then(Value::as_array)
        .filter(|f| !f.is_empty())
        .ok_or_else(|| whole("expected a FeatureCollection with the floor outline first".into()))?;
    let mut degrees: Vec<Vec<Polygon<f64>>> = Vec::with_capacity(features.len());
    for (i, feature) in features.iter().enumerate() {
        let polygons = feature_polygons(feature).map_err(|m| whole(format!("feature {i}: {m}")))?;
        degrees.push(polygons);
    }
    let bbox = degrees
        .iter()
        .flatten()
        .flat_map(|p| p.exterior().coords())
        .fold([f64::MAX, f64::MAX, f64::MIN, f64::MIN], |b, c| {
            [b[0].min(c.x), b[1].min(c.y), b[2].max(c.x), b[3].max(c.y)]
        });
    if !(bbox[2] > bbox[0] && bbox[3] > bbox[1]) {
        return Err(whole("the features have no extent".into()));
    }
    if bbox[0] < -180.0 || bbox[2] > 180.0 || bbox[1] < -90.0 || bbox[3] > 90.0 {
        return Err(whole(format!(
            "bounding box {bbox:?} is not in WGS84 degrees"
        )));
    }
    let to_metres = |c: Coord<f64>| Coord {
        x: (c.x - bbox[0]) / (bbox[2] - bbox[0]) * width,
        y: (c.y - bbox[1]) / (bbox[3] - bbox[1]) * height,
    };
    let mut metric: Vec<Vec<Polygon<f64>>> = degrees
        .into_iter()
        .map(|ps| {
            ps.into_iter()
                .map(|p| p.map_coords(to_metres).orient(Direction::Default))
                .collect()
        })
        .collect();
    let outline_parts = metric.remove(0);
    let outline = geo::unary_union(outline_parts.iter());
    if outline.unsigned_area() <= 0.0 {
        return Err(whole("feature 0 (the floor outline) has no area".into()));
    }
    let shop_parts: Vec<Polygon<f64>> = metric.iter().flatten().cloned().collect();
    let shops = geo::unary_union(shop_parts.iter());
    let frame = LocalFrame::new(bbox[1], bbox[0]).ok_or_else(|| {
        whole(format!(
            "bounding box corner ({}, {}) is not a valid place",
            bbox[1], bbox[0]
        ))
    })?;
    let (geodesic_width_m, _) = frame.to_local(bbox[2], bbox[1]);
    let (_, geodesic_height_m) = frame.to_local(bbox[0], bbox[3]);
    let summary = IlcFloorSummary {
        width_m: width,
        height_m: height,
        bbox,
        geodesic_width_m,
        geodesic_height_m,
        floor_name: features[0]
            .get("properties")
            .and_then(|p| p.get("name"))
            .and_then(Value::as_str)
            .map(str::to_string),
        shops: shop_parts.len(),
        outline_area_m2: outline.unsigned_area(),
        shop_area_m2: outline.intersection(&shops).unsigned_area(),
    };
    Ok(IlcFloor {
        outline,
        shops,
        frame,
        summary,
    })
}

impl IlcFloor {
    /// The floor plan for `walkable`, level 0, z 0, in the waypoints' metres.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidData`] when the walkable area does not stay a valid polygon at the GeoJSON
    /// writer's precision; [`Error::NotEnough`] when no part of at least [`MIN_PART_AREA`] is left
    /// (e.g. with `Corridors`, shops covering the whole outline).
    pub fn plan(&self, walkable: Walkable) -> Result<(FloorPlan, PlanReport)> {
        let area = match walkable {
            Walkable::Outline => self.outline.clone(),
            Walkable::Corridors => self.outline.difference(&self.shops),
        };
        let area = self.settle(area)?;
        let mut slivers = 0;
        let mut polygons = Vec::new();
        for part in area {
            if part.unsigned_area() < MIN_PART_AREA {
                slivers += 1;
                continue;
            }
            let (exterior, holes) = part.into_inner();
            let holes: Vec<LineString<f64>> = holes
                .into_iter()
                .filter(|h| {
                    let keep = Polygon::new(h.clone(), vec![]).unsigned_area() >= MIN_PART_AREA;
                    slivers += usize::from(!keep);
                    keep
                })
                .collect();
            let polygon = Polygon::new(exterior, holes);
            if let Err(e) = polygon.check_validation() {
                return Err(Error::invalid(
                    format!("the walkable area's part {}", polygons.len()),
                    format!("is not a valid polygon after cleaning: {e}"),
                ));
            }
            polygons.push(polygon);
        }
        if polygons.is_empty() {
            return Err(Error::not_enough("the walkable area is empty", ""));
        }
        let name = self
            .summary
            .floor_name
            .clone()
            .unwrap_or_else(|| "floor".into());
        let walkable_area_m2 = polygons.iter().map(Area::unsigned_area).sum();
        let plan = FloorPlan {
            polygons: polygons
                .into_iter()
                .enumerate()
                .map(|(i, polygon)| FloorPolygon {
                    polygon,
                    level: 0,
                    z: 0.0,
                    name: Some(format!(
                        "{name} {} {i}",
                        match walkable {
                            Walkable::Outline => "floor",
                            Walkable::Corridors => "corridors",
                        }
                    )),
                    room: None,
                })
                .collect(),
            barriers: Vec::new(),
        };
        let report = PlanReport {
            walkable,
            surfaces: plan.polygons.len(),
            walkable_area_m2,
            slivers_dropped: slivers,
        };
        Ok((plan, report))
    }
}

impl IlcFloor {
    /// `area` with its corners moved to where the GeoJSON writer's rounding puts them
    /// (1e-8°, about a millimetre), cleaned again: boolean operations leave corners a
    /// fraction of a millimetre apart, which the rounding could make cross. Repeats until
    /// the rounded area is valid (at most three times).
    fn settle(&self, area: MultiPolygon<f64>) -> Result<MultiPolygon<f64>> {
        let frame = self.frame;
        let snap = |c: Coord<f64>| {
            let (lon, lat) = written_degrees(c.x, c.y, &frame);
            let (x, y) = frame.to_local(lon, lat);
            Coord { x, y }
        };
        let mut area = area;
        for _ in 0..3 {
            let snapped = area.map_coords(snap);
            if snapped.is_valid() {
                return Ok(snapped);
            }
            area = geo::unary_union(std::iter::once(&snapped));
        }
        Err(Error::invalid(
            "the walkable area",
            "does not stay valid at the GeoJSON writer's precision",
        ))
    }
}

fn read_json(path: &Path) -> Result<Value> {
    let text = crate::io::geojson_file::read_json_text(path)?;
    serde_json::from_str(&text).map_err(|e| Error::parse(path, e.line(), format!("not JSON: {e}")))
}

/// The polygons of a Polygon or `MultiPolygon` feature, `[lon, lat]` degrees.
fn feature_polygons(feature: &Value) -> Result<Vec<Polygon<f64>>, String> {
    let geometry = feature.get("geometry").ok_or("no geometry")?;
    let kind = geometry.get("type").and_then(Value::as_str).unwrap_or("");
    let coordinates = geometry
        .get("coordinates")
        .ok_or("geometry without coordinates")?;
    match kind {
        "Polygon" => Ok(vec![polygon(coordinates)?]),
        "MultiPolygon" => coordinates
            .as_array()
            .ok_or("MultiPolygon coordinates are not an array")?
            .iter()
            .map(polygon)
            .collect(),
        other => Err(format!(
            "expected a Polygon or MultiPolygon, found `{other}`"
        )),
    }
}

fn polygon(rings: &Value) -> Result<Polygon<f64>, String> {
    let rings = rings
        .as_array()
        .ok_or("polygon coordinates are not an array of rings")?;
    let mut out: Vec<LineString<f64>> = Vec::with_capacity(rings.len());
    for ring in rings {
        let positions = ring
            .as_array()
            .ok_or("a ring is not an array of positions")?;
        let coords = positions
            .iter()
            .map(|p| {
                let xy = p
                    .as_array()
                    .filter(|a| a.len() >= 2)
                    .ok_or("a position is not [lon, lat]")?;
                match (xy[0].as_f64(), xy[1].as_f64()) {
                    (Some(x), Some(y)) if x.is_finite() && y.is_finite() => Ok(Coord { x, y }),
                    _ => Err("a position is not two finite numbers"),
                }
            })
            .collect::<Result<Vec<_>, _>>()?;
        if coords.len() < 3 {
            return Err("a ring has fewer than 3 positions".into());
        }
        out.push(LineString::new(coords));
    }
    if out.is_empty() {
        return Err("a polygon without rings".into());
    }
    let exterior = out.remove(0);
    Ok(Polygon::new(exterior, out))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::{FloorTopology, TopologyConfig};

    /// A 100 m × 50 m floor (bbox 0.001° × 0.0005°) with a 20 m × 10 m shop.
    pub(crate) fn write_floor(dir: &Path) {
        let lon = |x: f64| 120.0 + x / 100.0 * 0.001;
        let lat = |y: f64| 30.0 + y / 50.0 * 0.0005;
        let rect = |x0: f64, y0: f64, x1: f64, y1: f64| {
            serde_json::json!([[
                [lon(x0), lat(y0)],
                [lon(x1), lat(y0)],
                [lon(x1), lat(y1)],
                [lon(x0), lat(y1)],
                [lon(x0), lat(y0)]
            ]])
        };
        let map = serde_json::json!({"type": "FeatureCollection", "features": [
            {"type": "Feature", "properties": {"name": "F1"}, "geometry": {"type": "MultiPolygon", "coordinates": [rect(0.0, 0.0, 100.0, 50.0)]}},
            {"type": "Feature", "properties": {"name": "shop"}, "geometry": {"type": "Polygon", "coordinates": rect(10.0, 10.0, 30.0, 20.0)}},
            {"type": "Feature", "properties": {"name": "sliver"}, "geometry": {"type": "Polygon", "coordinates": rect(30.0, 10.0, 30.01, 20.0)}}
        ]});
        std::fs::write(dir.join("geojson_map.json"), map.to_string()).expect("write");
        std::fs::write(
            dir.join("floor_info.json"),
            r#"{"map_info": {"width": 100.0, "height": 50.0}}"#,
        )
        .expect("write");
    }

    #[test]
    fn bbox_maps_onto_metres_and_shops_are_cut_out() {
        let dir = tempfile::tempdir().expect("tempdir");
        write_floor(dir.path());
        let floor = read_ilc_floor(dir.path()).expect("valid");
        assert!((floor.summary.outline_area_m2 - 5000.0).abs() < 1e-6);
        assert!((floor.summary.shop_area_m2 - 200.1).abs() < 1e-3);
        let (outline, r) = floor.plan(Walkable::Outline).expect("plan");
        assert_eq!(r.surfaces, 1);
        assert!(outline.is_walkable(20.0, 15.0, Some(0)));
        let (corridors, r) = floor.plan(Walkable::Corridors).expect("plan");
        // Corners moved to the writer's millimetre grid change the area a little.
        assert!(
            (r.walkable_area_m2 - 4799.9).abs() < 0.5,
            "{}",
            r.walkable_area_m2
        );
        assert!(!corridors.is_walkable(20.0, 15.0, Some(0)));
        assert!(corridors.is_walkable(50.0, 30.0, Some(0)));
        FloorTopology::build(&corridors, &TopologyConfig::default()).expect("topology");
        // The frame's origin is the south-west corner; its metres are close to W × H.
        assert_eq!((floor.frame.lat, floor.frame.lon), (30.0, 120.0));
        assert!(
            (floor.summary.geodesic_width_m - 96.4).abs() < 0.5,
            "{}",
            floor.summary.geodesic_width_m
        );
    }

    #[test]
    fn errors_name_the_file() {
        let dir = tempfile::tempdir().expect("tempdir");
        write_floor(dir.path());
        std::fs::write(
            dir.path().join("floor_info.json"),
            r#"{"map_info": {"width": -1}}"#,
        )
        .expect("write");
        let e = read_ilc_floor(dir.path()).unwrap_err().to_string();
        assert!(e.contains("floor_info.json") && e.contains("width"), "{e}");
        std::fs::remove_file(dir.path().join("geojson_map.json")).expect("rm");
        write_floor(dir.path());
        std::fs::write(dir.path().join("geojson_map.json"), r#"{"type": "FeatureCollection", "features": [{"geometry": {"type": "Point", "coordinates": [1, 2]}}]}"#).expect("write");
        let e = read_ilc_floor(dir.path()).unwrap_err().to_string();
        assert!(
            e.contains("geojson_map.json") && e.contains("feature 0"),
            "{e}"
        );
    }
}
