//! Registering a learned map onto another of the same building: the grid shift that makes
//! their edge-crossing counts agree best.
//!
//! Two maps of one building learned on GPS-anchored walks differ by a translation (the
//! walks' GPS biases differ by metres); their shapes agree to a fraction of a hexagon. The
//! shift `s` (a vector of the hexagon grid, within `max_shift` metres) maximises the counts
//! the maps share edge by edge, `Σ_h Σ_e min(N^e_a(h), N^e_b(h + s))`: a walked corridor
//! overlaps only where it lines up, direction included. Buildings repeat themselves (rooms
//! every few metres along a corridor), but only the true shift lines up every corridor,
//! door and room at once. Ties go to the smaller shift.

use super::hex_transitions::{HexMapSnapshot, level_key};
use crate::geometry::HexGrid;
use hexx::Hex;
use rayon::prelude::*;
use rustc_hash::FxHashMap;

/// The grid shift `s` that best registers `map` onto `reference` (a hexagon `h` of `map`
/// lies on `h + s` of `reference`), within `max_shift` metres, and the counts shared there.
/// Levels meet by number; the shift is the same on every level.
#[must_use]
pub fn register_maps(
    map: &HexMapSnapshot,
    reference: &HexMapSnapshot,
    max_shift: f64,
) -> (Hex, u64) {
    let grid = HexGrid::new(map.radius);
    let cells: FxHashMap<Hex, [u32; 6]> = reference
        .cells
        .iter()
        .map(|c| (level_key(c.level, c.hex), c.counts))
        .collect();
    // Every grid vector whose centre lies within max_shift of the origin.
    let reach = (max_shift / grid.radius()).ceil() as i32 + 1;
    let mut shifts: Vec<(Hex, f64)> = Vec::new();
    for q in -reach..=reach {
        for r in -reach..=reach {
            let h = Hex::new(q, r);
            let (x, y) = grid.center(h);
            let d = x.hypot(y);
            if d <= max_shift {
                shifts.push((h, d));
            }
        }
    }
    shifts.sort_by(|a, b| {
        a.1.total_cmp(&b.1)
            .then((a.0.x, a.0.y).cmp(&(b.0.x, b.0.y)))
    });
    let scores: Vec<u64> = shifts
        .par_iter()
        .map(|&(s, _)| {
            map.cells
                .iter()
                .map(|c| {
                    cells
                        .get(&(level_key(c.level, c.hex) + s))
                        .map_or(0, |other| {
                            c.counts
                                .iter()
                                .zip(other)
                                .map(|(&a, &b)| u64::from(a.min(b)))
                                .sum::<u64>()
                        })
                })
                .sum()
        })
        .collect();
    // The first maximum in order of distance: ties go to the smaller shift.
    let mut best = (Hex::ZERO, 0u64);
    for (&(s, _), &v) in shifts.iter().zip(&scores) {
        if v > best.1 {
            best = (s, v);
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::HexTransitionMap;

    /// A map of laps round a 20 m × 10 m loop with a spur, walked from `(x0, y0)`.
    fn loop_map(x0: f64, y0: f64) -> HexMapSnapshot {
        let grid = HexGrid::new(0.5);
        let mut m = HexTransitionMap::new();
        let corners = [
            (0.0, 0.0),
            (20.0, 0.0),
            (20.0, 10.0),
            (0.0, 10.0),
            (0.0, 0.0),
            (7.0, 0.0),
            (7.0, -4.0),
        ];
        for _ in 0..2 {
            for w in corners.windows(2) {
                let (a, b) = ((w[0].0 + x0, w[0].1 + y0), (w[1].0 + x0, w[1].1 + y0));
                grid.for_each_crossing(a, b, |c| {
                    m.record_crossing(c.from, c.edge);
                });
            }
        }
        m.snapshot(0.5, 0.8)
    }

    #[test]
    fn finds_the_shift_between_two_walks_of_one_loop() {
        let reference = loop_map(0.0, 0.0);
        // The same loop seen 3.46 m east and 1.5 m south (4 and -2 hexagons of the grid).
        let grid = HexGrid::new(0.5);
        let (dx, dy) = grid.center(Hex::new(4, -2));
        let map = loop_map(dx, dy);
        let (s, shared) = register_maps(&map, &reference, 10.0);
        assert_eq!(s, Hex::new(-4, 2), "{s:?}");
        let total: u64 = map.cells.iter().flat_map(|c| c.counts).map(u64::from).sum();
        assert!(shared * 10 > total * 9, "{shared} of {total}");
        // Out of reach: some other, smaller shift.
        let (s, _) = register_maps(&map, &reference, 1.0);
        assert_ne!(s, Hex::new(-4, 2));
        assert_eq!(register_maps(&reference, &reference, 5.0).0, Hex::ZERO);
    }
}
