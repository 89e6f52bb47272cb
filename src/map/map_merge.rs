//! Combining maps learned on several walks of one building (Robertson et al. 2009, sec. 4.3,
//! "combining maps from several walks" as future work; DLR's successive collaborative
//! mapping).
//!
//! Maps that share a grid (the same frame and hexagon radius, as GPS-anchored walks placed
//! at one origin do) combine by adding their crossing counts edge by edge, each map's counts
//! scaled by its weight: the counts are sufficient statistics of the Dirichlet-multinomial
//! map, so the sum is the map all the walks would have learned together.

use super::hex_transitions::{HexCell, HexMapSnapshot};
use crate::error::{Error, Result};
use hexx::Hex;
use std::collections::BTreeMap;

/// Hexagon radii closer than this are the same grid, metres.
const RADIUS_TOLERANCE: f64 = 1e-9;

/// The weighted sum of `maps` (each `(map, weight)`, weights finite and ≥ 0), counts rounded
/// to the nearest integer. All maps must have the same hexagon radius; the result has the
/// first map's `α`. Hexagons whose counts round to zero are left out.
pub fn merge_maps(maps: &[(&HexMapSnapshot, f64)]) -> Result<HexMapSnapshot> {
    let (first, _) = maps
        .first()
        .ok_or_else(|| Error::Input("no maps to merge".into()))?;
    let mut sums: BTreeMap<(i32, i32), [f64; 6]> = BTreeMap::new();
    for (i, &(map, weight)) in maps.iter().enumerate() {
        if (map.radius - first.radius).abs() > RADIUS_TOLERANCE {
            return Err(Error::Input(format!(
                "map {} has hexagons of radius {} m, map 1 of {} m: maps merge only on one grid",
                i + 1,
                map.radius,
                first.radius
            )));
        }
        if !(weight.is_finite() && weight >= 0.0) {
            return Err(Error::Input(format!(
                "map {}: weight {weight} must be a finite number ≥ 0",
                i + 1
            )));
        }
        for cell in &map.cells {
            let sum = sums.entry((cell.hex.x, cell.hex.y)).or_insert([0.0; 6]);
            for (s, &n) in sum.iter_mut().zip(&cell.counts) {
                *s += weight * f64::from(n);
            }
        }
    }
    let cells = sums
        .into_iter()
        .map(|((q, r), sum)| HexCell {
            hex: Hex::new(q, r),
            counts: sum.map(|s| s.round().min(f64::from(u32::MAX)) as u32),
        })
        .filter(|c| c.counts.iter().any(|&n| n > 0))
        .collect();
    Ok(HexMapSnapshot {
        radius: first.radius,
        alpha: first.alpha,
        cells,
    })
}

/// `map` moved by the grid vector `by` (every hexagon's axial coordinates plus `by`).
pub fn shift_map(map: &HexMapSnapshot, by: Hex) -> HexMapSnapshot {
    let mut cells: Vec<HexCell> = map
        .cells
        .iter()
        .map(|c| HexCell {
            hex: c.hex + by,
            counts: c.counts,
        })
        .collect();
    cells.sort_by_key(|c| (c.hex.x, c.hex.y));
    HexMapSnapshot {
        radius: map.radius,
        alpha: map.alpha,
        cells,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map(cells: &[((i32, i32), [u32; 6])]) -> HexMapSnapshot {
        HexMapSnapshot {
            radius: 0.5,
            alpha: 0.8,
            cells: cells
                .iter()
                .map(|&((q, r), counts)| HexCell {
                    hex: Hex::new(q, r),
                    counts,
                })
                .collect(),
        }
    }

    #[test]
    fn counts_add_edge_by_edge_with_weights() {
        let a = map(&[((0, 0), [2, 0, 0, 1, 0, 0]), ((1, 0), [0, 0, 0, 2, 0, 0])]);
        let b = map(&[((0, 0), [1, 0, 0, 0, 0, 1]), ((5, 5), [0, 1, 0, 0, 0, 0])]);
        let m = merge_maps(&[(&a, 1.0), (&b, 2.0)]).expect("merge");
        assert_eq!(m.cells.len(), 3);
        assert_eq!(m.cells[0].hex, Hex::new(0, 0));
        assert_eq!(m.cells[0].counts, [4, 0, 0, 1, 0, 2]);
        assert_eq!(m.cells[2].counts, [0, 2, 0, 0, 0, 0]);
        let half = merge_maps(&[(&a, 0.2)]).expect("merge");
        // Every count times 0.2 rounds to 0: no hexagon survives.
        assert!(half.cells.is_empty());
        let double = merge_maps(&[(&a, 0.5)]).expect("merge");
        assert_eq!(double.cells[0].counts, [1, 0, 0, 1, 0, 0]);
    }

    #[test]
    fn shifting_moves_every_hexagon() {
        let a = map(&[((0, 0), [2, 0, 0, 1, 0, 0]), ((1, 0), [0, 0, 0, 2, 0, 0])]);
        let s = shift_map(&a, Hex::new(-3, 2));
        assert_eq!(s.cells[0].hex, Hex::new(-3, 2));
        assert_eq!(s.cells[1].hex, Hex::new(-2, 2));
        assert_eq!(s.cells[1].counts, [0, 0, 0, 2, 0, 0]);
        assert_eq!(shift_map(&s, Hex::new(3, -2)), a);
    }

    #[test]
    fn different_grids_and_bad_weights_are_rejected() {
        let a = map(&[((0, 0), [1, 0, 0, 0, 0, 0])]);
        let mut b = a.clone();
        b.radius = 0.6;
        assert!(
            merge_maps(&[(&a, 1.0), (&b, 1.0)]).is_err_and(|e| e.to_string().contains("radius"))
        );
        assert!(merge_maps(&[(&a, f64::NAN)]).is_err());
        assert!(merge_maps(&[]).is_err());
    }
}
