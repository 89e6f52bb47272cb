//! The picture of a learned magnetic field map (`fieldmap.png`): each hexagon with readings
//! coloured by the mean field magnitude, the learned path over them, and a colour bar.

use anyhow::Result;
use footslam::geometry::{HexGrid, nearest_rank};
use footslam::map::{FieldMapSnapshot, FloorPlan, FloorPolygon, split_level_key};
use footslam::render::plan_png::{
    ColourBar, PlanCell, PlanPath, PlanPicture, PlanPictureConfig, viridis_rgb, write_plan_png,
};
use geo::{LineString, MultiPolygon, Polygon};
use std::path::Path;

/// Writes `fieldmap.png` of `map` with `path` (`(x, y, level)` per step) over it; the
/// colours run from the map's 2nd to its 98th percentile of magnitude.
pub(super) fn write_field_map_png(
    out: &Path,
    map: &FieldMapSnapshot,
    path: &[(f64, f64, i32)],
    north_up: bool,
) -> Result<()> {
    let grid = HexGrid::new(map.radius);
    let (ox, oy) = map.offset;
    let hexagons: Vec<(MultiPolygon<f64>, i32, f64)> = map
        .cells
        .iter()
        .map(|c| {
            let (level, hex) = split_level_key(c.key);
            let ring: Vec<(f64, f64)> = grid
                .corners(hex)
                .iter()
                .map(|&(x, y)| (x + ox, y + oy))
                .collect();
            let polygon = Polygon::new(LineString::from(ring), Vec::new());
            (MultiPolygon(vec![polygon]), level, c.mean[0])
        })
        .collect();
    let mut sorted: Vec<f64> = hexagons.iter().map(|h| h.2).collect();
    sorted.sort_by(f64::total_cmp);
    let (low, high) = (nearest_rank(&sorted, 2), nearest_rank(&sorted, 98));
    let span = (high - low).max(1e-9);
    // The hexagons themselves are the plan: the learned field's extent.
    let plan = FloorPlan {
        polygons: hexagons
            .iter()
            .map(|(area, level, _)| FloorPolygon {
                polygon: area.0[0].clone(),
                level: *level,
                z: 0.0,
                name: None,
                room: None,
            })
            .collect(),
        barriers: Vec::new(),
    };
    let cells = hexagons
        .iter()
        .map(|(area, level, m)| PlanCell {
            area,
            level: *level,
            colour: viridis_rgb(((m - low) / span).clamp(0.0, 1.0)),
        })
        .collect();
    let picture = PlanPicture {
        plan: &plan,
        title: Some("magnetic field magnitude".into()),
        paths: vec![PlanPath {
            points: path,
            colour: [230, 60, 40],
            label: "most probable path",
        }],
        points: Vec::new(),
        cells,
        markers: Vec::new(),
        north_up,
        colour_bar: Some(ColourBar {
            low: format!("{low:.1} uT"),
            high: format!("{high:.1} uT"),
            colour: viridis_rgb,
        }),
    };
    write_plan_png(out, &[picture], &PlanPictureConfig::default())?;
    Ok(())
}
