//! How well each step fitted the plan: the share of the belief the step's walls left alive
//! (eq. 14) and the height change the survivors' surfaces do not explain (eq. 17). Neither
//! changes the filter; they are the evidence of a run's verdict (a walk on another
//! building's plan loses particles to walls at every turn, and climbs where the plan has no
//! stairs).

/// The evidence of one step's propagation.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepFit {
    /// Share of the particles the step left alive at its first propagation (0 when every
    /// particle hit a wall and the filter had to recover).
    pub survival: f32,
    /// The step's height change minus the mean change of surface (`δz_poly`, eq. 15) of the
    /// particles that carried it, weighted by eq. 17, metres. 0 when no propagation
    /// succeeded (a fresh prior).
    pub unexplained_dz: f32,
}

/// Sums over one propagation, gathered per chunk of particles and added in chunk order (so
/// that the figures do not depend on the number of threads).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Propagation {
    pub(super) particles: usize,
    pub(super) alive: usize,
    /// Σ w over the alive particles, w = exp(eq. 17's log-weight).
    pub(super) weight: f64,
    /// Σ w · `δz_poly` over the alive particles.
    pub(super) weighted_dz: f64,
}

impl Propagation {
    pub(super) fn add(self, other: Self) -> Self {
        Self {
            particles: self.particles + other.particles,
            alive: self.alive + other.alive,
            weight: self.weight + other.weight,
            weighted_dz: self.weighted_dz + other.weighted_dz,
        }
    }

    /// Share of the particles alive.
    pub(super) fn survival(&self) -> f32 {
        if self.particles == 0 {
            return 0.0;
        }
        (self.alive as f64 / self.particles as f64) as f32
    }

    /// The mean surface height change the survivors explain, weighted by eq. 17 (`None`
    /// when none survived or every weight underflowed).
    pub(super) fn explained_dz(&self) -> Option<f64> {
        (self.alive > 0 && self.weight > 0.0).then(|| self.weighted_dz / self.weight)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sums_and_shares() {
        let a = Propagation {
            particles: 4,
            alive: 3,
            weight: 2.0,
            weighted_dz: 6.0,
        };
        let b = Propagation {
            particles: 4,
            alive: 1,
            weight: 1.0,
            weighted_dz: 0.0,
        };
        let s = a.add(b);
        assert_eq!(s.survival(), 0.5);
        assert_eq!(s.explained_dz(), Some(2.0));
        assert_eq!(Propagation::default().survival(), 0.0);
        assert_eq!(Propagation::default().explained_dz(), None);
    }
}
