//! Combining maps learned on several walks of one building (Robertson et al. 2009, sec. 4.3,
//! "combining maps from several walks" as future work; DLR's successive collaborative
//! mapping).
//!
//! Maps that share a grid (the same frame and hexagon radius, as GPS-anchored walks placed
//! at one origin do) combine by adding their crossing counts edge by edge, each map's counts
//! scaled by its weight: the counts are sufficient statistics of the Dirichlet-multinomial
//! map, so the sum is the map all the walks would have learned together.
//!
//! Two walks of one corridor merged, and a map of another grid refused:
//!
//! ```
//! use footslam::geometry::Pose2;
//! use footslam::map::{map_of_path, merge_maps};
//!
//! let path: Vec<Pose2> = (1..=10).map(|i| Pose2::new(f64::from(i), 0.0, 0.0)).collect();
//! let start = Pose2::default();
//! let a = map_of_path(start, &path, &[0; 10], 0.5, 0.8);
//! let b = map_of_path(start, &path, &[0; 10], 0.5, 0.8);
//!
//! // Counts add up edge by edge; a map of weight 0 is left out.
//! let merged = merge_maps(&[(&a, 1.0), (&b, 1.0)])?;
//! assert_eq!(merged.cells.len(), a.cells.len());
//! assert_eq!(merged.cells[0].counts, a.cells[0].counts.map(|n| 2 * n));
//! assert_eq!(merge_maps(&[(&a, 1.0), (&b, 0.0)])?.cells, a.cells);
//!
//! let coarse = map_of_path(start, &path, &[0; 10], 1.0, 0.8);
//! let err = merge_maps(&[(&a, 1.0), (&coarse, 1.0)]).unwrap_err();
//! assert!(err.to_string().contains("radius"));
//! # Ok::<(), footslam::Error>(())
//! ```

use super::floor_plan::FloorLevel;
use super::hex_transitions::{HexCell, HexMapSnapshot};
use crate::error::{Error, Result};
use hexx::Hex;
use std::collections::BTreeMap;

/// Hexagon radii closer than this are the same grid, metres.
const RADIUS_TOLERANCE: f64 = 1e-9;

/// The weighted sum of `maps` (each `(map, weight)`, weights finite and ≥ 0), counts rounded
/// to the nearest integer. Weights are relative: they are scaled so that the largest is 1
/// (the map of the largest weight counts each crossing once, so `1e12, 1` cannot overflow
/// the counts and `0.3, 0.3` is `1, 1`), and an edge crossed in a map of weight > 0 keeps
/// at least one crossing (a small weight lowers a map's say, it does not erase the places
/// only it walked). All maps must have the same hexagon radius; the result has the first
/// map's `α`. Maps of weight 0 are left out. Levels meet by number
/// (walks that start on different floors say so with their start level); a level's height
/// is the weighted mean of the maps' heights for it, each map's heights first moved onto
/// those of the maps before it by their mean difference on the levels they share (each
/// walk measures heights from its own first floor).
///
/// # Errors
///
/// [`Error::NotEnough`] when `maps` is empty; [`Error::Mismatch`] when a map's hexagon radius
/// differs from the first map's; [`Error::InvalidData`] when a weight is negative or not finite.
pub fn merge_maps(maps: &[(&HexMapSnapshot, f64)]) -> Result<HexMapSnapshot> {
    let (first, _) = maps
        .first()
        .ok_or_else(|| Error::not_enough("no maps to merge", "give at least one map"))?;
    let largest = maps.iter().map(|&(_, w)| w).fold(0.0_f64, f64::max);
    let scale = if largest > 0.0 { 1.0 / largest } else { 1.0 };
    let mut sums: BTreeMap<(i32, i32, i32), [f64; 6]> = BTreeMap::new();
    // Per level: Σ weight·z and Σ weight over the maps that give its height.
    let mut heights: BTreeMap<i32, (f64, f64)> = BTreeMap::new();
    for (i, &(map, weight)) in maps.iter().enumerate() {
        if (map.radius - first.radius).abs() > RADIUS_TOLERANCE {
            return Err(Error::mismatch(
                format!(
                    "map {} has hexagons of radius {} m, map 1 of {} m",
                    i + 1,
                    map.radius,
                    first.radius
                ),
                "maps merge only on one grid; learn them with one footslam.hex_radius",
            ));
        }
        if !(weight.is_finite() && weight >= 0.0) {
            return Err(Error::invalid(
                format!("map {}", i + 1),
                format!("weight {weight} must be a finite number ≥ 0"),
            ));
        }
        // Heights are relative to each walk's first floor: move this map's onto the
        // heights so far by the mean difference on the levels they share.
        let shared: Vec<f64> = map
            .levels
            .iter()
            .filter_map(|l| {
                heights
                    .get(&l.level)
                    .filter(|h| h.1 > 0.0)
                    .map(|h| h.0 / h.1 - l.z)
            })
            .collect();
        let lift = if shared.is_empty() {
            0.0
        } else {
            shared.iter().sum::<f64>() / shared.len() as f64
        };
        for l in &map.levels {
            let h = heights.entry(l.level).or_insert((0.0, 0.0));
            let w = weight.max(1e-12);
            *h = (h.0 + w * (l.z + lift), h.1 + w);
        }
        for cell in &map.cells {
            let sum = sums
                .entry((cell.level, cell.hex.x, cell.hex.y))
                .or_insert([0.0; 6]);
            for (s, &n) in sum.iter_mut().zip(&cell.counts) {
                *s += weight * scale * f64::from(n);
            }
        }
    }
    let cells = sums
        .into_iter()
        .map(|((level, q, r), sum)| HexCell {
            hex: Hex::new(q, r),
            level,
            counts: sum.map(|s| {
                if s > 0.0 {
                    s.round().clamp(1.0, f64::from(u32::MAX)) as u32
                } else {
                    0
                }
            }),
        })
        .filter(|c| c.counts.iter().any(|&n| n > 0))
        .collect();
    Ok(HexMapSnapshot {
        radius: first.radius,
        alpha: first.alpha,
        cells,
        levels: heights
            .into_iter()
            .map(|(level, (zw, w))| FloorLevel { level, z: zw / w })
            .collect(),
    })
}

/// `map` moved by the grid vector `by` (every hexagon's axial coordinates plus `by`, on
/// every level).
#[must_use]
pub fn shift_map(map: &HexMapSnapshot, by: Hex) -> HexMapSnapshot {
    let mut cells: Vec<HexCell> = map
        .cells
        .iter()
        .map(|c| HexCell {
            hex: c.hex + by,
            ..c.clone()
        })
        .collect();
    cells.sort_by_key(|c| (c.level, c.hex.x, c.hex.y));
    HexMapSnapshot {
        cells,
        ..map.clone()
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
                    level: 0,
                })
                .collect(),
            levels: Vec::new(),
        }
    }

    #[test]
    fn counts_add_edge_by_edge_with_weights() {
        let a = map(&[((0, 0), [2, 0, 0, 1, 0, 0]), ((1, 0), [0, 0, 0, 2, 0, 0])]);
        let b = map(&[((0, 0), [1, 0, 0, 0, 0, 1]), ((5, 5), [0, 1, 0, 0, 0, 0])]);
        let m = merge_maps(&[(&a, 1.0), (&b, 2.0)]).expect("merge");
        assert_eq!(m.cells.len(), 3);
        assert_eq!(m.cells[0].hex, Hex::new(0, 0));
        // Weights 1, 2 are ½, 1: a's 1 on edge 3 weighs ½ and stays one crossing.
        assert_eq!(m.cells[0].counts, [2, 0, 0, 1, 0, 1]);
        assert_eq!(m.cells[1].counts, [0, 0, 0, 1, 0, 0]);
        assert_eq!(m.cells[2].counts, [0, 1, 0, 0, 0, 0]);
        // Weights are relative: one map alone is itself at any weight.
        for w in [0.2, 0.5, 1e12] {
            assert_eq!(merge_maps(&[(&a, w)]).expect("merge").cells, a.cells, "{w}");
        }
        // 0.3, 0.3 is 1, 1 (no hexagon dropped by rounding) …
        let both = merge_maps(&[(&a, 0.3), (&b, 0.3)]).expect("merge");
        assert_eq!(both, merge_maps(&[(&a, 1.0), (&b, 1.0)]).expect("merge"));
        // … and 1e12, 1 neither saturates the counts nor erases b's own hexagon.
        let heavy = merge_maps(&[(&a, 1e12), (&b, 1.0)]).expect("merge");
        assert_eq!(heavy.cells[0].counts, [2, 0, 0, 1, 0, 1]);
        assert_eq!(heavy.cells[2].counts, [0, 1, 0, 0, 0, 0]);
        // A map of weight 0 is left out.
        let zero = merge_maps(&[(&a, 1.0), (&b, 0.0)]).expect("merge");
        assert_eq!(zero.cells, a.cells);
    }

    #[test]
    fn levels_merge_by_number_with_heights_made_relative_to_the_first_map() {
        let mut a = map(&[((0, 0), [2, 0, 0, 0, 0, 0])]);
        a.levels = vec![
            FloorLevel { level: 0, z: 0.0 },
            FloorLevel { level: 1, z: 3.2 },
        ];
        // A walk that started on level 1: its heights from there.
        let mut b = map(&[((0, 0), [1, 0, 0, 0, 0, 0])]);
        b.cells[0].level = 2;
        b.levels = vec![
            FloorLevel { level: 1, z: 0.0 },
            FloorLevel { level: 2, z: 3.0 },
        ];
        let m = merge_maps(&[(&a, 1.0), (&b, 1.0)]).expect("merge");
        assert_eq!(m.cells.len(), 2);
        assert_eq!((m.cells[0].level, m.cells[1].level), (0, 2));
        let z: Vec<f64> = m.levels.iter().map(|l| l.z).collect();
        assert_eq!(z.len(), 3);
        assert!(
            (z[0] - 0.0).abs() < 1e-9 && (z[1] - 3.2).abs() < 1e-9,
            "{z:?}"
        );
        assert!((z[2] - 6.2).abs() < 1e-9, "{z:?}");
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
