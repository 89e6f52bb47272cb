//! FootSLAM: the Rao-Blackwellised particle filter of Robertson et al. (2009), sec. 3.
//!
//! Each particle carries a pose `P_k`, the step error state `E_k` and its own hexagon
//! transition map `M` (the Rao-Blackwellised part, eq. 2: `p(M | P_{0:k})` is kept in
//! closed form as Dirichlet counts). One call of [`FootSlam::update`] runs the algorithm
//! box's steps 2a–2f for one step measurement `Z^U_k`:
//!
//! * (a, b) draw `E_k` and `U_k` from the likelihood proposal, eq. (5), and move;
//! * (c) weight by the map's posterior predictive of every edge crossed, eq. (6);
//! * (e) count the crossings in the particle's map;
//! * (d) normalise; (f) resample when the effective sample size is low.
//!
//! Anchors to the world (sec. 4.1–4.3), all optional ([`Anchors`]): GPS fixes weight the
//! particles at the steps they fall in ([`crate::model::GpsLikelihood`]); a step's absolute
//! heading (a compass), where it has one, weights them the same way
//! ([`crate::model::HeadingLikelihood`]) — a measurement beside eq. (6) that keeps the
//! learned map's orientation (x east, y north) and checks the heading drift; a rough building
//! outline and maps of earlier walks become per-edge Dirichlet priors `α^e_h` in eq. (6)
//! ([`EdgePrior`]), one read-only table shared by every particle.
//!
//! Floors (sec. 5, 2.5D): each step is on a level found from the steps' height changes
//! ([`LevelTracker`], the same for every particle), and each level has its own hexagon map
//! (stacked keys, [`crate::map::level_key`]); a walk on one floor has level 0 only.
//!
//! Evidence beside eq. (6), also optional: the walk's WiFi scans against each particle's
//! own positions at earlier scans ([`crate::model::scan_pairs`]) and, in a FeetSLAM pass,
//! against other walks' placed scans ([`crate::model::scan_references`]); and the building's
//! dominant directions on straight steps ([`crate::model::building_axes`]); and the magnetic
//! field over each step against each particle's own field map
//! ([`crate::model::magnetic_field`], MagSLAM).
//!
//! The answer ([`FootSlam::estimate`]): the most probable particle's map, and the whole-walk
//! path — the final particles' ancestral paths near its own, averaged (`smoothing`).

pub use super::footslam_anchors::Anchors;
use super::footslam_anchors::{GpsQueue, StepFix, log_gps_factor, sample_start};
pub use super::footslam_config::FootSlamConfig;
pub use super::footslam_config::SmoothingConfig;
use super::footslam_map_term::{MapPrior, log_map_factor};
use super::footslam_scans::ScanQueue;
use super::lineage::Lineage;
use super::outline_fit::{OUTAGE, OutlineZone, in_outage};
use super::resample;
use super::scan_trail::ScanTrail;
use crate::error::Result;
use crate::geometry::{Hex, HexGrid, Pose2};
use crate::map::{
    EdgePrior, FieldMap, FieldMapSnapshot, HexMapForest, HexMapSnapshot, ParticleHexMap,
};
use crate::model::{
    AxisEvidence, AxisLikelihood, AxisState, FieldEvidence, GpsLikelihood, HeadingLikelihood,
    LevelTracker, StepErrorState, StepMotion,
};
use crate::random::stream;
use crate::sensor::Step;
use rayon::prelude::*;
use std::sync::Arc;

/// One particle: pose, error state, its own map and its ancestry.
#[derive(Debug, Clone)]
struct Particle {
    pose: Pose2,
    error: StepErrorState,
    /// Its map, in [`FootSlam::maps`].
    map: ParticleHexMap,
    /// Its newest segment in [`FootSlam::lineage`].
    ancestry: u32,
    /// `ln ∏ₖ` of eq. (6)'s factors over the particle's whole path (its ancestors' steps
    /// included): the unnormalised posterior of the path under the likelihood proposal,
    /// never reset by resampling.
    path_log_likelihood: f64,
    /// The share of `path_log_likelihood` that came from WiFi scans (eq. 3 of
    /// [`crate::model::scan_pairs`]).
    wifi_log_likelihood: f32,
    /// Its positions at the walk's WiFi scans so far.
    trail: ScanTrail,
    /// The building's axes it learned from its straight steps so far.
    axes: AxisState,
    /// Its map of the magnetic field, from its first reading on (none in a walk without
    /// magnetometer readings: 8 bytes a particle, not a map's 64).
    field: Option<Box<FieldMap>>,
}

/// The filter's answer: the most probable particle's map and whole path.
#[derive(Debug, Clone)]
pub struct FootSlamEstimate {
    /// Index of the particle whose whole path is the most probable.
    pub index: usize,
    /// Its current normalised weight.
    pub weight: f64,
    /// `ln` of the product of eq. (6)'s factors over its whole path.
    pub path_log_likelihood: f64,
    /// The part of `path_log_likelihood` WiFi scans gave (0 without scans).
    pub wifi_log_likelihood: f64,
    /// The whole-walk answer, one pose per step processed: the mean of the final
    /// particles' ancestral paths near its path ([`SmoothingConfig`]; its own path with
    /// `smoothing.draws = 0`).
    pub path: Vec<Pose2>,
    /// Per step, how far the averaged paths spread about `path` (RMS, metres).
    pub spread_m: Vec<f64>,
    /// Distinct final paths drawn for `path`, and how many of them it averages (the
    /// others lay in another mode).
    pub smoothed_paths: (usize, usize),
    /// The level of each step of `path` (all 0 on one floor).
    pub levels: Vec<i32>,
    /// Its map.
    pub map: HexMapSnapshot,
    /// Its map of the magnetic field, when the field weighed the particles.
    pub field_map: Option<FieldMapSnapshot>,
    /// How far path and map were moved: `κ·δ` towards a prior map's frame plus the
    /// outline fit ([`super::outline_fit`]), metres.
    pub prior_offset: (f64, f64),
    /// The grid vector that moves the prior map into the frame of `path` and `map` (the
    /// particle read the prior `δ` away, and the answer moved by `κ·δ` plus the outline
    /// fit): add the prior's counts shifted by it to `map` to merge them consistently.
    pub prior_shift: Hex,
}

/// What an outline and GPS fixes tell together: a walker GPS does not see is indoors.
#[derive(Debug)]
struct OutageCheck {
    /// The outline, known to `outline_margin`.
    zone: OutlineZone,
    /// Every fix's time, in order.
    fix_times: Vec<f64>,
    /// `ln(α / α_out)`: eq. (6)'s price of a first crossing of an outline edge.
    crossing_cost: f64,
    /// Each step's time, for the outline fit's outages.
    times: Vec<f64>,
}

/// The FootSLAM Rao-Blackwellised particle filter.
///
#[doc = include_str!("footslam/example.md")]
#[derive(Debug)]
pub struct FootSlam {
    config: FootSlamConfig,
    motion: StepMotion,
    grid: HexGrid,
    prior: Option<EdgePrior>,
    gps: Option<GpsQueue>,
    /// Fixes applied at the current step (scratch).
    step_fixes: Vec<StepFix>,
    /// WiFi scans as evidence of revisits (`None` without scans).
    wifi: Option<ScanQueue>,
    /// The axes prior and which steps are straight (`None` when the walk shows no
    /// dominant directions, or without evidence).
    axes: Option<(AxisLikelihood, Arc<AxisEvidence>)>,
    /// Straight steps that the axes prior weighed.
    axis_steps: usize,
    /// The magnetic field over each step (`None` without readings, or when they do not
    /// tell places apart).
    field: Option<Arc<FieldEvidence>>,
    /// Steps whose field reading weighted the particles.
    field_steps: usize,
    /// The absolute-heading model (`None` when disabled).
    heading: Option<HeadingLikelihood>,
    /// Steps whose absolute heading weighted the particles.
    headings_used: usize,
    /// Time of the previous step.
    last_t: Option<f64>,
    /// Floors from the steps' height changes.
    level_tracker: LevelTracker,
    /// The level of each step processed.
    step_levels: Vec<i32>,
    /// The prior-map offset `δ`.
    offset: Hex,
    /// Share `κ` of the offset applied to the answer (see [`FootSlam::with_anchors`]).
    offset_pull: f64,
    /// Spread of the GPS bias left for the outline fit, metres (0: no fit).
    outline_fit_sigma: f64,
    particles: Vec<Particle>,
    /// The store of the particles' maps' shared nodes.
    maps: HexMapForest,
    /// The particles' ancestry.
    lineage: Lineage,
    /// Normalised log weights, `ln wᵢ`.
    log_weights: Vec<f64>,
    /// Scratch buffers reused every step.
    weights: Vec<f64>,
    parents: Vec<usize>,
    children: Vec<u32>,
    residuals: Vec<f64>,
    next: Vec<Particle>,
    /// Step measurements seen, needed to replay paths.
    steps: Vec<(f64, f64)>,
    /// The outline and GPS together, when both are given.
    outage_check: Option<OutageCheck>,
    ess_history: Vec<f64>,
    resamplings: usize,
    resample_pending: bool,
}

impl FootSlam {
    /// A filter with all particles at the start pose (Algorithm step 1) and `E_0` drawn
    /// from its initial distribution.
    ///
    /// # Errors
    ///
    /// As [`Self::with_anchors`] without anchors: `config` out of range, or more particles than the
    /// machine's available memory holds.
    pub fn new(config: FootSlamConfig) -> Result<Self> {
        Self::with_anchors(config, Anchors::default())
    }

    /// A filter anchored to the world by `anchors`: the start pose is drawn about
    /// `config.start` with the configured spreads, and with GPS fixes the per-walk stride
    /// scale spread is `gps.length_scale_sigma0`.
    ///
    /// **GPS and a prior map together.** The prior map (merged from `n` earlier walks) sits
    /// in the frame of their GPS fixes, off the truth by the mean of their biases; this
    /// walk's fixes are off by their own bias. Neither frame is the truth, so the particles
    /// read the prior map `δ = anchors.prior_offset` away from where they walk (`δ`: the
    /// prior's frame less this walk's GPS frame, found by registering a map of this walk
    /// learned without the prior, [`crate::map::register_maps`]). The answer is placed
    /// between the two frames, `κ = n / (n + 1)` of the way towards the prior (the
    /// least-squares combination of one bias and a mean of `n` independent ones), so that
    /// successive walks average their GPS biases: the path moves by `κ·δ`, the map by the
    /// grid vector nearest it.
    ///
    /// # Errors
    ///
    /// - [`Error::Config`](crate::Error::Config) when `config` fails [`FootSlamConfig::validate`]
    ///   or `start_level` is beyond ±1000.
    /// - [`Error::InvalidData`](crate::Error::InvalidData) when the GPS fixes are not in increasing
    ///   time order, or a level of `anchors.levels` is given twice or at a height that is not
    ///   finite.
    /// - [`Error::TooLarge`](crate::Error::TooLarge) when the particles would not fit in the memory
    ///   the machine has available.
    pub fn with_anchors(config: FootSlamConfig, anchors: Anchors) -> Result<Self> {
        config.validate()?;
        let mut motion_config = config.motion;
        if !anchors.gps.is_empty() {
            motion_config.length_scale_sigma0 = config.gps.length_scale_sigma0;
            if let Some(w) = anchors.gps.windows(2).find(|w| w[1].t <= w[0].t) {
                return Err(crate::error::Error::invalid(
                    format!("GPS fix at {} s", w[1].t),
                    format!(
                        "follows one at {} s: fixes must be in increasing time order",
                        w[0].t
                    ),
                ));
            }
        }
        let motion = StepMotion::new(motion_config);
        let grid = HexGrid::new(config.hex_radius);
        let prior = anchors.prior.filter(|p| !p.is_empty());
        let (offset, offset_pull) =
            if !anchors.gps.is_empty() && prior.is_some() && anchors.prior_walks > 0 {
                let n = f64::from(anchors.prior_walks);
                (anchors.prior_offset, n / (n + 1.0))
            } else {
                (Hex::ZERO, 0.0)
            };
        // The bias spread of the frame after this walk joins the `n` averaged before it.
        let outline_fit_sigma = match &prior {
            Some(p) if p.has_outline() && !anchors.gps.is_empty() => {
                config.gps.bias_sigma / f64::from(anchors.prior_walks + 1).sqrt()
            }
            _ => 0.0,
        };
        let n = config.particles;
        // The particles, their next generation and their weights, before anything is
        // allocated: a run the machine cannot hold fails here, not aborted mid-allocation.
        let per_particle = 2 * std::mem::size_of::<Particle>()
            + 2 * std::mem::size_of::<f64>()
            + std::mem::size_of::<usize>();
        crate::memory::check_fits(
            &format!("{n} particles"),
            (n as u64).saturating_mul(per_particle as u64),
            crate::memory::available_bytes(),
            "use fewer particles (`particles`, --particles)",
        )?;
        let mut lineage = Lineage::new();
        let roots: Vec<u32> = (0..n).map(|i| lineage.root(i as u32)).collect();
        let particles: Vec<Particle> = (0..n)
            .into_par_iter()
            .map(|i| {
                let mut rng = stream(config.seed, 0, i as u64);
                let error = motion.sample_initial(&mut rng);
                let pose = sample_start(&config, &mut rng);
                Particle {
                    error,
                    pose,
                    map: ParticleHexMap::default(),
                    ancestry: roots[i],
                    path_log_likelihood: 0.0,
                    wifi_log_likelihood: 0.0,
                    trail: ScanTrail::default(),
                    axes: AxisState::default(),
                    field: None,
                }
            })
            .collect();
        let outage_check = prior
            .as_ref()
            .and_then(|p| p.outline())
            .filter(|_| !anchors.gps.is_empty())
            .map(|o| OutageCheck {
                zone: OutlineZone::new(o, config.outline_margin),
                fix_times: anchors.gps.iter().map(|f| f.t).collect(),
                crossing_cost: (config.alpha / config.outline_alpha).ln(),
                times: Vec::new(),
            });
        let gps = (!anchors.gps.is_empty()).then(|| GpsQueue {
            likelihood: GpsLikelihood::new(config.gps),
            fixes: anchors.gps,
            next: 0,
        });
        let level_tracker = LevelTracker::new(config.levels, config.start_level, &anchors.levels)?;
        Ok(Self {
            level_tracker,
            step_levels: Vec::new(),
            grid,
            prior,
            gps,
            step_fixes: Vec::new(),
            wifi: anchors.wifi.map(|e| {
                ScanQueue::new(
                    e,
                    anchors.wifi_references.filter(|_| config.wifi.cross_walk),
                )
            }),
            axes: anchors
                .axes
                .filter(|e| e.active && config.axes.enabled)
                .map(|e| (AxisLikelihood::new(config.axes, e.directions), e)),
            axis_steps: 0,
            field: anchors.field.filter(|e| e.active()),
            field_steps: 0,
            heading: config
                .heading
                .enabled
                .then(|| HeadingLikelihood::new(config.heading)),
            headings_used: 0,
            last_t: None,
            offset,
            offset_pull,
            outline_fit_sigma,
            motion,
            log_weights: vec![-(n as f64).ln(); n],
            weights: vec![1.0 / n as f64; n],
            parents: Vec::with_capacity(n),
            children: Vec::new(),
            residuals: Vec::new(),
            next: Vec::with_capacity(n),
            particles,
            maps: HexMapForest::new(),
            lineage,
            steps: Vec::new(),
            outage_check,
            ess_history: Vec::new(),
            resamplings: 0,
            resample_pending: false,
            config,
        })
    }

    /// The configuration in force.
    #[must_use]
    pub fn config(&self) -> &FootSlamConfig {
        &self.config
    }

    /// Steps processed so far.
    #[must_use]
    pub fn steps_processed(&self) -> usize {
        self.steps.len()
    }

    /// Resamplings so far.
    #[must_use]
    pub fn resamplings(&self) -> usize {
        self.resamplings
    }

    /// Effective sample size after each step (before any resampling at that step).
    #[must_use]
    pub fn ess_history(&self) -> &[f64] {
        &self.ess_history
    }

    /// Current effective sample size `1 / Σ wᵢ²`.
    #[must_use]
    pub fn effective_sample_size(&self) -> f64 {
        resample::effective_sample_size(&self.weights)
    }

    /// The weighted circular spread of the particles' current headings, radians
    /// (`√(−2 ln R)` for the weighted mean resultant length `R`): how firmly the walk pins
    /// the map's orientation. Every particle integrates the same measured heading changes,
    /// so their headings differ only by the start heading each drew and the heading noise
    /// of eq. (5); GPS fixes, compass readings, an outline or a prior map narrow it.
    #[must_use]
    pub fn heading_spread(&self) -> f64 {
        let (c, s) = self
            .particles
            .iter()
            .zip(&self.weights)
            .fold((0.0, 0.0), |(c, s), (p, w)| {
                (c + w * p.pose.heading.cos(), s + w * p.pose.heading.sin())
            });
        let r = c.hypot(s).clamp(1e-300, 1.0);
        (-2.0 * r.ln()).sqrt()
    }

    /// GPS fixes applied so far.
    #[must_use]
    pub fn gps_fixes_used(&self) -> usize {
        self.gps.as_ref().map_or(0, |g| g.next)
    }

    /// Steps whose absolute heading weighted the particles so far.
    #[must_use]
    pub fn headings_used(&self) -> usize {
        self.headings_used
    }

    /// WiFi scans that weighted the particles so far.
    #[must_use]
    pub fn scans_used(&self) -> usize {
        self.wifi.as_ref().map_or(0, |w| w.next)
    }

    /// Straight steps that the building's axes weighed so far (0 when the walk showed no
    /// dominant directions).
    #[must_use]
    pub fn axis_steps(&self) -> usize {
        self.axis_steps
    }

    /// Steps whose magnetic field reading weighed the particles so far (0 without readings
    /// or when they do not tell places apart).
    #[must_use]
    pub fn field_steps(&self) -> usize {
        self.field_steps
    }

    /// Whether the scans are weighed against other walks' scans too (a FeetSLAM pass).
    pub fn scans_cross_walk(&self) -> bool {
        self.wifi.as_ref().is_some_and(ScanQueue::has_references)
    }

    /// Current positions and normalised weights of all particles.
    pub fn particle_positions(&self) -> impl Iterator<Item = ((f64, f64), f64)> + '_ {
        self.particles
            .iter()
            .zip(&self.weights)
            .map(|(p, &w)| ((p.pose.x, p.pose.y), w))
    }

    /// Runs steps 2a–2f of the algorithm for one step measurement `Z^U_k`.
    pub fn update(&mut self, z: &Step) {
        // (f) of the previous step, done lazily so that the weights of the last step
        // survive for [`FootSlam::estimate`].
        if self.resample_pending {
            self.resample(self.steps.len() as u64);
            self.resample_pending = false;
        }
        // A step GPS did not see (an outage, `outline_fit::OUTAGE`), taken far outside the
        // outline, costs a crossing pair per `OUTAGE` seconds: out and back in unseen.
        let mut unseen_cost = 0.0;
        if let Some(check) = &mut self.outage_check {
            check.times.push(z.t);
            if let Some(t0) = self.last_t.filter(|_| in_outage(&check.fix_times, z.t)) {
                unseen_cost = 2.0 * check.crossing_cost * (z.t - t0).max(0.0) / OUTAGE;
            }
        }
        self.steps.push((z.length, z.dheading));
        let level = self.level_tracker.step(z);
        self.step_levels.push(level);
        let k = self.steps.len() as u64;
        if let Some(wifi) = &mut self.wifi {
            wifi.take_step(self.last_t, z.t, level);
        }
        self.collect_step_fixes(z.t);
        let (seed, motion, grid) = (self.config.seed, self.motion, self.grid);
        let (alpha, correct) = (self.config.alpha, self.config.direction_correction);
        let prior = self.prior.as_ref();
        let (offset, maps) = (self.offset, &self.maps);
        let (gps, fixes) = (self.gps.as_ref().map(|g| g.likelihood), &self.step_fixes);
        let compass = self.heading.zip(z.heading);
        self.headings_used += usize::from(compass.is_some());
        let zone = self.outage_check.as_ref().map(|c| &c.zone);
        let wifi = self.wifi.as_ref();
        let axes = self
            .axes
            .as_ref()
            .filter(|(_, e)| e.is_straight(self.steps.len() - 1))
            .map(|(m, _)| m);
        self.axis_steps += usize::from(axes.is_some());
        let field = self
            .field
            .as_ref()
            .and_then(|e| e.reading(self.steps.len() - 1));
        self.field_steps += usize::from(field.is_some());
        self.particles
            .par_iter_mut()
            .zip(self.log_weights.par_iter_mut())
            .enumerate()
            .for_each(|(i, (p, log_w))| {
                let mut rng = stream(seed, k, i as u64);
                // (a) E_k ~ p(E_k | E_{k-1}), U_k ~ p(U_k | Z^U_k, E_k): eq. (5).
                p.error = motion.sample_error(p.error, &mut rng);
                // (b) P_k = P_{k-1} + U_k.
                let pose = motion.sample_step(p.pose, p.error, z.length, z.dheading, &mut rng);
                // (c) and (e): weight by every edge crossed, then count it.
                let edges = MapPrior {
                    alpha,
                    prior,
                    offset,
                    level,
                };
                let record = |h, e| maps.record_crossing(&mut p.map, h, e);
                let mut log_factor = log_map_factor(&grid, record, edges, correct, p.pose, pose);
                // GPS fixes that fell during the step, at the point walked by then.
                if let Some(gps) = gps {
                    log_factor += log_gps_factor(&gps, fixes, p.pose, pose);
                }
                if unseen_cost > 0.0 && zone.is_some_and(|o| o.is_far_outside(pose.x, pose.y)) {
                    log_factor -= unseen_cost;
                }
                // The step's absolute heading against the particle's (IMU) heading, which
                // the measured heading changes integrate.
                // Tempered by the disturbance's correlation length (heading_likelihood eq. 3).
                if let Some((model, h)) = compass {
                    log_factor += model.temper(z.length) * model.log_likelihood(h, pose.heading);
                }
                // WiFi scans taken during the step, at the point walked by then, against
                // the particle's own positions at the earlier scans (scan_pairs eq. 3).
                if let Some(wifi) = wifi {
                    let log_wifi = wifi.log_factor(p.pose, pose, &mut p.trail);
                    p.wifi_log_likelihood += log_wifi as f32;
                    log_factor += log_wifi;
                }
                // A straight step against the axes the particle learned so far
                // (building_axes eq. 3), then learned from (eq. 1).
                if let Some(model) = axes {
                    log_factor +=
                        p.axes
                            .weigh_and_learn(model, pose.x - p.pose.x, pose.y - p.pose.y);
                }
                // The step's field reading against the particle's own field map
                // (magnetic_field eq. 3), then added to it.
                if let Some((model, y)) = field {
                    log_factor += model.weigh_and_learn(
                        p.field.get_or_insert_default(),
                        &pose,
                        level,
                        k as u32,
                        y,
                    );
                }
                *log_w += log_factor;
                p.path_log_likelihood += log_factor;
                p.pose = pose;
            });
        // (d) normalise.
        self.normalise();
        let ess = self.effective_sample_size();
        self.ess_history.push(ess);
        // (f) resample if required (before the next step moves the particles).
        self.resample_pending =
            ess < self.config.resample.ess_threshold * self.particles.len() as f64;
    }

    /// The GPS fixes taken after the previous step and up to `t` (those before the first
    /// step apply at the start pose), with their tempering exponents.
    fn collect_step_fixes(&mut self, t: f64) {
        self.step_fixes.clear();
        let previous = self.last_t.replace(t);
        if let Some(gps) = self.gps.as_mut() {
            gps.take_step(previous, t, &mut self.step_fixes);
        }
    }
}

mod estimate;
mod resampling;
mod smoothing;
#[cfg(test)]
mod tests;
