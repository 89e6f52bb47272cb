//! Placing a learned walk against a rough building outline: the most probable shift of the
//! whole path given the GPS bias it may carry and the outline it should not cross.
//!
//! Inside the filter the outline is a low Dirichlet prior on the edges that cross it
//! ([`crate::map::edge_prior`]); that steers the shape, but GPS fixes counted as independent
//! pin the path's absolute position far more firmly than a few improbable crossings can
//! move it, although their common bias (metres, slowly varying) moves every fix alike. So,
//! once the path is learned, its absolute place is re-estimated: the path is shifted by
//! `s`, where `s` maximises
//!
//! `ln N(s; 0, σ²I) + Σ_{outline edges e crossed by path + s, once each} ln(min(α^e, α) / α)`
//!
//! — the GPS bias prior (`σ`: the bias spread left after the walks averaged into the frame)
//! and eq. (6)'s penalty for each first crossing of an outline edge (an edge opened by a
//! prior map's counts costs less or nothing). The maximum is searched on a square grid of
//! shifts 0.25 m apart within `±3σ` (at most ±10 m); ties go to the smaller shift.

use crate::geometry::HexGrid;
use crate::map::EdgePrior;
use rayon::prelude::*;
use rustc_hash::FxHashSet;

/// Spacing of the shifts tried, metres.
const SHIFT_STEP: f64 = 0.25;
/// The widest shift tried, metres.
const MAX_SHIFT: f64 = 10.0;

/// The most probable shift of `path` (positions in walking order) given the outline edges
/// of `prior` and a Gaussian bias prior of spread `sigma` per axis. `(0, 0)` when `prior`
/// has no outline or `sigma` is 0.
pub fn fit_outline_shift(path: &[(f64, f64)], grid: &HexGrid, prior: &EdgePrior, sigma: f64) -> (f64, f64) {
    if !prior.has_outline() || !(sigma > 0.0) || path.len() < 2 {
        return (0.0, 0.0);
    }
    let reach = (3.0 * sigma).min(MAX_SHIFT);
    let k = (reach / SHIFT_STEP).floor() as i32;
    let alpha = prior.base_alpha();
    let shifts: Vec<(f64, f64)> = (-k..=k)
        .flat_map(|i| (-k..=k).map(move |j| (f64::from(i) * SHIFT_STEP, f64::from(j) * SHIFT_STEP)))
        .collect();
    let score = |&(sx, sy): &(f64, f64)| {
        let mut crossed = FxHashSet::default();
        let mut penalty = 0.0;
        for w in path.windows(2) {
            grid.for_each_crossing((w[0].0 + sx, w[0].1 + sy), (w[1].0 + sx, w[1].1 + sy), |c| {
                if prior.is_outline_edge(c.from, c.edge) {
                    let key = if c.edge < 3 { (c.from, c.edge) } else { (c.to, c.edge - 3) };
                    if crossed.insert(key) {
                        penalty += (prior.alpha(c.from, c.edge).min(alpha) / alpha).ln();
                    }
                }
            });
        }
        penalty - (sx * sx + sy * sy) / (2.0 * sigma * sigma)
    };
    let scored: Vec<f64> = shifts.par_iter().map(score).collect();
    // The first maximum in a fixed order (by score, then by the smaller shift).
    let mut best = (f64::NEG_INFINITY, f64::INFINITY, (0.0, 0.0));
    for (&s, &v) in shifts.iter().zip(&scored) {
        let r = s.0 * s.0 + s.1 * s.1;
        if v > best.0 + 1e-12 || ((v - best.0).abs() <= 1e-12 && r < best.1) {
            best = (v, r, s);
        }
    }
    best.2
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::Rect;

    #[test]
    fn a_path_pushed_through_a_wall_is_pulled_back_inside() {
        let grid = HexGrid::new(0.5);
        let outline = Rect::new((0.0, 0.0), (20.0, 20.0)).to_polygon();
        let mut prior = EdgePrior::uniform(0.8);
        prior.add_outline(&grid, &outline, 0.05);
        // Laps of a loop 1 m inside the walls, entered once through a door at (10, 0) —
        // but seen 2.5 m too far south-east (a GPS bias).
        let mut path = vec![(10.0, -8.0), (10.0, 1.0)];
        for _ in 0..3 {
            path.extend([(19.0, 1.0), (19.0, 19.0), (1.0, 19.0), (1.0, 1.0), (10.0, 1.0)]);
        }
        path.push((10.0, -8.0));
        let biased: Vec<(f64, f64)> = path.iter().map(|&(x, y)| (x + 2.5, y - 2.5)).collect();
        let (sx, sy) = fit_outline_shift(&biased, &grid, &prior, 3.0);
        // Back inside: the loop's east and south sides no longer cross the walls.
        assert!(sx <= -1.5 && sx >= -3.5, "{sx}");
        assert!(sy >= 1.5 && sy <= 3.5, "{sy}");
        // The true path needs no shift; without an outline nothing moves.
        assert_eq!(fit_outline_shift(&path, &grid, &prior, 3.0), (0.0, 0.0));
        assert_eq!(fit_outline_shift(&biased, &grid, &EdgePrior::uniform(0.8), 3.0), (0.0, 0.0));
    }
}
