//! What anchors a FootSLAM walk to the world beyond its steps (Robertson et al. 2009,
//! sec. 4.1–4.3): the start pose, GPS fixes applied at the steps they fall in, and the
//! per-edge Dirichlet priors of an outline or earlier maps ([`Anchors`]).

use super::footslam_config::FootSlamConfig;
use crate::geometry::{Hex, Pose2};
use crate::map::{EdgePrior, FloorLevel};
use crate::model::{
    AxisEvidence, FieldEvidence, GpsLikelihood, GpsObservation, ReferenceScans, ScanEvidence,
};
use crate::sensor::step::share_of_step;
use rand::RngExt;
use rand_distr::StandardNormal;
use std::sync::Arc;

/// What anchors a walk to the world, beyond its steps (all optional).
///
/// GPS fixes orient a walk whose start heading is unknown:
///
/// ```
/// use footslam::filter::{Anchors, FootSlam, FootSlamConfig};
/// use footslam::model::GpsObservation;
/// use footslam::sensor::Step;
///
/// // 30 one-metre steps north, and a fix every 5 s at the walker's place.
/// let steps: Vec<Step> = (1..=30)
///     .map(|i| Step { t: f64::from(i), length: 1.0, dheading: 0.0, dz: 0.0, heading: None })
///     .collect();
/// let gps: Vec<GpsObservation> = (1..=6)
///     .map(|k| f64::from(5 * k))
///     .map(|t| GpsObservation { t, x: 0.0, y: t, sigma: 2.0 })
///     .collect();
/// let config = FootSlamConfig {
///     particles: 300,
///     seed: 4,
///     start_heading_sigma: std::f64::consts::PI, // any start heading
///     ..Default::default()
/// };
/// let mut slam = FootSlam::with_anchors(config, Anchors { gps, ..Default::default() })?;
/// for step in &steps {
///     slam.update(step);
/// }
/// assert_eq!(slam.gps_fixes_used(), 6);
/// let end = *slam.estimate().path.last().expect("a pose per step");
/// assert!(end.x.abs() < 5.0 && end.y > 25.0, "{end:?}");
/// # Ok::<(), footslam::Error>(())
/// ```
#[derive(Debug, Clone, Default)]
pub struct Anchors {
    /// GPS fixes in the local frame on the steps' clock, in time order.
    pub gps: Vec<GpsObservation>,
    /// Per-edge Dirichlet priors (outline, earlier maps); `None`: `α` everywhere.
    pub prior: Option<EdgePrior>,
    /// Walks whose counts the prior holds (0: no prior map, only an outline or nothing).
    pub prior_walks: u32,
    /// `δ`: where the walk's grid meets the prior map's — a hexagon of this walk is read in
    /// the prior at itself plus `δ` (see [`super::FootSlam::with_anchors`]). Zero without GPS.
    pub prior_offset: Hex,
    /// The walk's floors, when known beforehand ([`crate::model::find_levels`] on its
    /// steps): every step goes to the nearest from the first. Empty: found as the steps
    /// come.
    pub levels: Vec<FloorLevel>,
    /// The walk's WiFi scans as evidence of revisits ([`crate::model::scan_pairs`]), on the
    /// steps' clock. `None`: no scans, or not used.
    pub wifi: Option<Arc<ScanEvidence>>,
    /// In a FeetSLAM batch's later passes: the other walks' scans where their previous
    /// pass placed them, for the scans of `wifi` ([`crate::model::scan_references`]).
    /// Used only with `wifi`.
    pub wifi_references: Option<Arc<ReferenceScans>>,
    /// Which steps are straight and whether the walk shows dominant directions
    /// ([`crate::model::building_axes`]). `None`, or evidence that is not active: no axes
    /// prior.
    pub axes: Option<Arc<AxisEvidence>>,
    /// The magnetic field over each step, calibrated on the walk
    /// ([`crate::model::magnetic_field`]); `None`, or evidence that is not active: no field
    /// term.
    pub field: Option<Arc<FieldEvidence>>,
}

/// GPS fixes waiting to be applied.
#[derive(Debug)]
pub(super) struct GpsQueue {
    pub(super) likelihood: GpsLikelihood,
    pub(super) fixes: Vec<GpsObservation>,
    /// Index of the next fix to apply.
    pub(super) next: usize,
}

/// One fix applied at a step: where along the step it falls and its tempering exponent.
#[derive(Debug, Clone, Copy)]
pub(super) struct StepFix {
    fix: GpsObservation,
    /// Fraction of the step walked at the fix's time, in [0, 1].
    along: f64,
    temper: f64,
}

impl GpsQueue {
    /// Moves the fixes taken after `previous` and up to `t` (those before the first step
    /// apply at the start pose) into `out`, with where along the step each falls and its
    /// tempering exponent.
    pub(super) fn take_step(&mut self, previous: Option<f64>, t: f64, out: &mut Vec<StepFix>) {
        while let Some(&fix) = self.fixes.get(self.next).filter(|f| f.t <= t) {
            let dt = self.next.checked_sub(1).map(|j| fix.t - self.fixes[j].t);
            let along = share_of_step(previous, t, fix.t);
            out.push(StepFix {
                fix,
                along,
                temper: self.likelihood.temper(dt),
            });
            self.next += 1;
        }
    }
}

/// The start pose `P_0` of one particle: `config.start`, spread by
/// `start_position_sigma` and `start_heading_sigma` (uniform heading from π up). Draws
/// nothing when both are 0, so walks without anchors replay as before.
pub(super) fn sample_start(config: &FootSlamConfig, rng: &mut impl rand::Rng) -> Pose2 {
    let mut pose = config.start;
    if config.start_position_sigma > 0.0 {
        pose.x += config.start_position_sigma * rng.sample::<f64, _>(StandardNormal);
        pose.y += config.start_position_sigma * rng.sample::<f64, _>(StandardNormal);
    }
    let s = config.start_heading_sigma;
    if s >= std::f64::consts::PI {
        pose.heading = rng.random_range(-std::f64::consts::PI..std::f64::consts::PI);
    } else if s > 0.0 {
        pose.heading += s * rng.sample::<f64, _>(StandardNormal);
    }
    pose
}

/// `Σ_j τ_j · ln p(z_j | P)` over the fixes taken during a step from `from` to `to`, each
/// at the point walked by its time (linear along the step).
pub(super) fn log_gps_factor(
    gps: &GpsLikelihood,
    fixes: &[StepFix],
    from: Pose2,
    to: Pose2,
) -> f64 {
    fixes
        .iter()
        .map(|f| {
            let x = from.x + f.along * (to.x - from.x);
            let y = from.y + f.along * (to.y - from.y);
            f.temper * gps.log_likelihood(&f.fix, (x, y))
        })
        .sum()
}
