//! A learned hexagon map as a motion prior for tracking on a known map (FeetSLAM's reuse of
//! a FootSLAM map: Robertson et al. 2009, eq. 6, read with the map's counts fixed).
//!
//! FootSLAM weighs a step by the posterior predictive of every hexagon edge it crosses,
//! `(N^e_h + α) / (N_h + 6α)`. A tracker on a map learned earlier asks the same question of
//! fixed counts: a particle moving along a well-trodden edge is likelier than one crossing
//! an edge nobody crossed. Relative to a map that knows nothing (`1/6` for every edge), a
//! crossing of edge `e` out of hexagon `h` multiplies the particle's weight by
//!
//! `f(h, e) = [6 · (N^e_h + α) / (N_h + 6α)]^w`,
//!
//! which is 1 in a hexagon the map never saw (`N_h = 0`): places the walks did not reach are
//! neither favoured nor penalised, and the plan's walls still decide where a particle may
//! go. `w` (`weight`, default 1) tempers the prior; 0 switches it off.
//!
//! Levels: a plan level `l` reads the map's level `l` (a learned plan numbers its floors as
//! the map it came from).

use crate::error::Result;
use crate::geometry::HexGrid;
use crate::map::{HexMapSnapshot, level_key};
use hexx::Hex;
use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

/// Settings of the transition prior; every default in one place.
///
/// | field    | default | meaning                                                 |
/// |----------|---------|---------------------------------------------------------|
/// | `weight` | 1       | exponent `w` of each crossing's factor (0: no prior)     |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TransitionPriorConfig {
    /// Exponent `w` of each crossing's factor: 1 reads the map as FootSLAM learned it,
    /// less trusts it less (a map of other walkers, a building that changed). Default 1.
    pub weight: f64,
}

impl Default for TransitionPriorConfig {
    fn default() -> Self {
        Self { weight: 1.0 }
    }
}

/// The learned transition probabilities of a map, as log-factors per hexagon edge.
#[derive(Debug, Clone)]
pub struct TransitionPrior {
    grid: HexGrid,
    /// `w · ln f(h, e)` for the six edges of every hexagon the map saw (stacked keys).
    cells: FxHashMap<Hex, [f32; 6]>,
}

impl TransitionPrior {
    /// The prior of `map` (see the module documentation).
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) when `config.weight` is outside [0, 10].
    pub fn new(map: &HexMapSnapshot, config: TransitionPriorConfig) -> Result<Self> {
        let w = config.weight;
        crate::error::check_range("transitions.weight", w, 0.0..=10.0, "")?;
        let alpha = map.alpha.max(1e-9);
        let cells = map
            .cells
            .iter()
            .filter(|c| c.counts.iter().any(|&n| n > 0) && w > 0.0)
            .map(|c| {
                let total: f64 = c.counts.iter().map(|&n| f64::from(n)).sum::<f64>() + 6.0 * alpha;
                let factors = c
                    .counts
                    .map(|n| (w * (6.0 * (f64::from(n) + alpha) / total).ln()) as f32);
                (level_key(c.level, c.hex), factors)
            })
            .collect();
        Ok(Self {
            grid: HexGrid::new(map.radius),
            cells,
        })
    }

    /// Hexagons the prior knows.
    #[must_use]
    pub fn len(&self) -> usize {
        self.cells.len()
    }

    /// True when the prior knows no hexagon (every factor is 1).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    /// `ln ∏ f(h, e)` over every edge crossed on the straight move from `from` to `to` on
    /// `level`.
    #[must_use]
    pub fn log_factor(&self, from: (f64, f64), to: (f64, f64), level: i32) -> f32 {
        let mut sum = 0.0;
        self.grid.for_each_crossing(from, to, |c| {
            if let Some(f) = self.cells.get(&level_key(level, c.from)) {
                sum += f[usize::from(c.edge)];
            }
        });
        sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::HexTransitionMap;

    #[test]
    fn trodden_edges_are_likelier_than_untrodden_ones_and_unknown_places_neutral() {
        // Ten passes east along y = 0.
        let grid = HexGrid::new(0.5);
        let mut m = HexTransitionMap::new();
        for _ in 0..10 {
            grid.for_each_crossing((0.0, 0.0), (10.0, 0.0), |c| {
                m.record_crossing(c.from, c.edge);
            });
        }
        let prior = TransitionPrior::new(&m.snapshot(0.5, 0.8), TransitionPriorConfig::default())
            .expect("prior");
        let along = prior.log_factor((4.0, 0.0), (5.0, 0.0), 0);
        let across = prior.log_factor((4.0, 0.0), (4.0, 1.0), 0);
        assert!(along > 0.5, "{along}");
        assert!(across < -1.0, "{across}");
        assert_eq!(prior.log_factor((40.0, 40.0), (41.0, 40.0), 0), 0.0);
        // Another floor knows nothing of these crossings.
        assert_eq!(prior.log_factor((4.0, 0.0), (4.0, 1.0), 1), 0.0);
        // Weight 0: no prior; out of range: an error.
        let off =
            TransitionPrior::new(&m.snapshot(0.5, 0.8), TransitionPriorConfig { weight: 0.0 })
                .expect("prior");
        assert!(off.is_empty());
        assert!(
            TransitionPrior::new(
                &m.snapshot(0.5, 0.8),
                TransitionPriorConfig { weight: -1.0 }
            )
            .is_err()
        );
    }
}
