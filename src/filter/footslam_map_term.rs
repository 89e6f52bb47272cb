//! Eq. (6) of Robertson et al. (2009): the posterior predictive of the edges a step
//! crosses under a particle's Dirichlet-count hexagon map, with the direction correction
//! of sec. 3.

use crate::geometry::{Hex, HexGrid, Pose2};
use crate::map::{EdgePrior, level_key};

/// The Dirichlet prior of eq. (6): `α` on every edge, or per-edge values.
#[derive(Debug, Clone, Copy)]
pub(super) struct MapPrior<'a> {
    pub(super) alpha: f64,
    pub(super) prior: Option<&'a EdgePrior>,
    /// Where the particles read the prior, relative to their own grid.
    pub(super) offset: Hex,
    /// The step's level: its map's keys are [`level_key`]`(level, h)`.
    pub(super) level: i32,
}

impl MapPrior<'_> {
    /// `(α^e_h, Σ_e α^e_h)`.
    fn alpha_and_total(&self, h: Hex, edge: u8) -> (f64, f64) {
        match self.prior {
            Some(p) => p.alpha_and_total(h + self.offset, edge),
            None => (self.alpha, 6.0 * self.alpha),
        }
    }
}

/// Eq. (6) for one step: the product over every edge crossed between `from` and `to` of
/// `(N^ẽ_h̃ + α^ẽ_h̃) / (N_h̃ + Σ_e α^e_h̃)` with the counts so far, raised to the direction
/// correction (sec. 3); each crossing is counted in the map right after it is weighed (step
/// 2e: `record` counts edge `e` out of `h` in the particle's map and returns its counts
/// before, `(N^e_h, N_h)`), so a step over several edges multiplies one factor per edge.
/// Returns the log of the product.
pub(super) fn log_map_factor(
    grid: &HexGrid,
    mut record: impl FnMut(Hex, u8) -> (u32, u32),
    prior: MapPrior<'_>,
    correct: bool,
    from: Pose2,
    to: Pose2,
) -> f64 {
    let mut log_factor = 0.0;
    grid.for_each_crossing((from.x, from.y), (to.x, to.y), |c| {
        let h = level_key(prior.level, c.from);
        let (n_e, n_h) = record(h, c.edge); // step (e), counts before it
        let (alpha_e, alpha_h) = prior.alpha_and_total(h, c.edge);
        log_factor += ((f64::from(n_e) + alpha_e) / (f64::from(n_h) + alpha_h)).ln(); // eq. (6)
    });
    if correct && log_factor != 0.0 {
        log_factor *= HexGrid::direction_exponent_of(to.x - from.x, to.y - from.y);
    }
    log_factor
}
