//! How much of a learned map lies in walkable space: a plausibility check of a map against
//! a floor plan.

use crate::geometry::{HexGrid, RigidTransform};
use crate::map::hex_transitions::visits;
use crate::map::{FloorPlan, HexMapSnapshot};

/// The visit-weighted fraction, in [0, 1], of `map`'s hexagon centres that lie on a
/// walkable surface of `plan` (any level).
///
/// Each hexagon weighs its number of passes, `⌈Σ counts / 2⌉`. `transform` maps the map's
/// frame into the plan's (e.g. the rigid alignment from position evaluation); `None` when
/// they share a frame. An empty map (or one without crossings) gives 0.
#[must_use]
pub fn walkable_fraction(
    map: &HexMapSnapshot,
    plan: &FloorPlan,
    transform: Option<&RigidTransform>,
) -> f64 {
    let grid = HexGrid::new(map.radius);
    let (mut inside, mut total) = (0u64, 0u64);
    for cell in &map.cells {
        let weight = visits(&cell.counts);
        let centre = grid.center(cell.hex);
        let (x, y) = transform.map_or(centre, |t| t.apply(centre));
        total += weight;
        if plan.is_walkable(x, y, None) {
            inside += weight;
        }
    }
    if total == 0 {
        0.0
    } else {
        inside as f64 / total as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::{FloorPolygon, HexCell};
    use geo::{LineString, Polygon};
    use hexx::Hex;

    fn square_plan() -> FloorPlan {
        let ring = LineString::from(vec![
            (-1.0, -1.0),
            (1.0, -1.0),
            (1.0, 1.0),
            (-1.0, 1.0),
            (-1.0, -1.0),
        ]);
        let polygon = Polygon::new(ring, vec![]);
        FloorPlan {
            barriers: Vec::new(),
            polygons: vec![FloorPolygon {
                polygon,
                level: 2,
                z: 7.0,
                name: None,
                room: None,
            }],
        }
    }

    fn map() -> HexMapSnapshot {
        let cell = |x, y, n: u32| HexCell {
            hex: Hex { x, y },
            counts: [n, 0, 0, 0, 0, 0],
            level: 0,
        };
        // Radius 0.5: centres (0, 0), (1.732, 0), (0.433, 0.75); visits 2, 4, 1.
        HexMapSnapshot {
            radius: 0.5,
            alpha: 1.0,
            cells: vec![cell(0, 0, 4), cell(2, 0, 8), cell(0, 1, 1)],
            levels: Vec::new(),
        }
    }

    #[test]
    fn weighs_hexagons_by_visits() {
        let plan = square_plan();
        // (0, 0) and (0, 1) inside: (2 + 1) / 7.
        assert!((walkable_fraction(&map(), &plan, None) - 3.0 / 7.0).abs() < 1e-12);
        // Shifted west by 1.732 m only (2, 0) lands inside: 4 / 7.
        let shift = RigidTransform {
            angle: 0.0,
            tx: -0.5 * 3f64.sqrt() * 2.0,
            ty: 0.0,
        };
        assert!((walkable_fraction(&map(), &plan, Some(&shift)) - 4.0 / 7.0).abs() < 1e-12);
    }

    #[test]
    fn empty_map_gives_zero() {
        let empty = HexMapSnapshot {
            radius: 0.5,
            alpha: 1.0,
            cells: vec![],
            levels: Vec::new(),
        };
        assert_eq!(walkable_fraction(&empty, &square_plan(), None), 0.0);
    }
}
