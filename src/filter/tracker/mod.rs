//! Tracking a walker on a known 2.5D floor plan (Woodman & Harle 2008), from an unknown
//! start, with KLD-sampling, clustering and recovery when every particle dies.
//!
//! One [`Tracker::update`] per step event `u_t = (l, δθ, δz)`:
//!
//! 1. **propagate** every particle by Algorithm 1: perturb the step (eqs. 7–8), move it
//!    (eqs. 9–11), walk the move through the floor polygons' edges (wall → weight 0,
//!    connection → next polygon) and weight it by the height change,
//!    `w_t = N_{0,σ_h}(|δz − δz_poly|)` (eqs. 15–17);
//! 2. **recover** if every particle died (see [`super::recovery`]);
//! 3. **weigh by the step's heading** where the step carries an absolute heading: heading
//!    measurement (not in Woodman & Harle; a compass as in harle-2013 §V),
//!    `w_t ← w_t · p(h_t | θ_t)` with the outlier-robust model of
//!    [`crate::model::HeadingLikelihood`] (eq. 1 there); no heading, no cost;
//! 4. **size** the next particle set by KLD-sampling over 1 m × 1 m × 10° × level bins
//!    ([`super::kld`]);
//! 5. **resample** that many particles systematically;
//! 6. **cluster** the particles by mean shift once there are few enough of them; the walker
//!    is localised when one cluster remains (no wider than `cluster.max_spread`), and the
//!    estimate is the heaviest cluster's mean.
//!
//! Each particle also carries a per-walk step length scale (a few percent off for a whole
//! walk is common) and, optionally, a heading-drift rate (a gyro's bias turns every step a
//! little), both estimated as FootSLAM estimates its sensor errors: drawn at the start,
//! random-walked slowly, kept by the particles that fit the walls.
//!
//! Memory: 24 bytes per particle, twice (current and proposed), plus 4 bytes of log-weight
//! and 4 of bin index: 56 bytes per particle. Randomness is drawn per chunk of
//! [`CHUNK`] particles from a stream keyed by (seed, step, chunk), so results do not depend on
//! the number of threads.
//!
//! The pieces, one file each:
//! * `particle` — one hypothesis of the walker's state ([`TrackParticle`])
//! * `prior` — the prior drawn by KLD-sampling: uniform over the plan (or a region), or about
//!   a known start
//! * `propagate` — Algorithm 1 for every particle: the step model, walls, stairs
//! * `measure` — the step's extra measurement, absolute heading and learned transitions
//! * `memo` — a function's last value, for runs of equal log-weights
//! * `resample` — KLD sizing and systematic resampling
//! * `estimate` — clustering the belief into the estimate
//! * `recover` — recovery when every particle died: heading search, history fitting, a fresh
//!   prior
//! * `ancestry` — the belief's ancestry in the path tree, for the smoothed answer

mod ancestry;
mod estimate;
mod fit;
mod measure;
mod memo;
mod particle;
mod prior;
mod propagate;
mod recover;
mod resample;
#[cfg(test)]
mod tests;

pub use fit::StepFit;
pub use particle::TrackParticle;

use super::cluster::{Cluster, ClusterPoint, MeanShift};
use super::kld::KldBins;
use super::path_tree::PathTree;
use super::recovery::Recovery;
use super::tracker_config::TrackerConfig;
use crate::error::{Error, Result};
use crate::map::{CellField, FloorTopology};
use crate::model::{HeadingLikelihood, TransitionPrior};
use crate::sensor::Step;
use propagate::StepInput;
use std::collections::VecDeque;

/// Particles per chunk of work and per random stream.
pub const CHUNK: usize = 16_384;
/// Stream salts, so that the prior, the steps and every recovery draw unrelated numbers.
const SALT_PRIOR: u64 = 0x5EED_0001;
const SALT_STEP: u64 = 0x5EED_0002;
const SALT_RESAMPLE: u64 = 0x5EED_0003;
const SALT_HEADING: u64 = 0x5EED_0004;
const SALT_HISTORY: u64 = 0x5EED_0005;

/// An extra measurement for one step ([`Tracker::update_with`]): a field over the plan, and
/// when within the step it was taken.
#[derive(Debug, Clone, Copy)]
pub struct StepMeasurement<'m> {
    /// Log-weight at each place.
    pub field: &'m CellField,
    /// Share of the step's motion done when the measurement was taken: 0 = where the
    /// particle stood before the step, 1 = where the step took it. Each particle is judged
    /// at that point of its own straight move, so a scan taken mid-step judges it where the
    /// walker was when the scan was taken.
    pub at: f32,
}

impl<'m> StepMeasurement<'m> {
    /// `field` judged where the step took each particle.
    #[must_use]
    pub fn at_end(field: &'m CellField) -> Self {
        Self { field, at: 1.0 }
    }
}

/// What one step did to the belief.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackStep {
    /// Time of the step, seconds.
    pub t: f64,
    /// Particles after the step.
    pub particles: usize,
    /// Clusters counted (`None` while there are too many particles to cluster).
    pub clusters: Option<usize>,
    /// The heaviest cluster (`None` while not clustered).
    pub estimate: Option<Cluster>,
    /// True when exactly one cluster remains.
    pub localised: bool,
    /// Set when every particle died at this step, with how the filter recovered.
    pub recovery: Option<Recovery>,
    /// How well the step fitted the plan (`None`: no filter ran, e.g. before a radio
    /// tracker's first scan).
    pub fit: Option<StepFit>,
}

/// The particle filter of Woodman & Harle 2008 on a [`FloorTopology`].
///
/// A walk from a known start, out of a corridor into a room:
///
/// ```
/// use footslam::filter::{StartPose, Tracker, TrackerConfig};
/// use footslam::map::{FloorPlan, FloorPolygon, FloorTopology};
/// use footslam::sensor::Step;
/// use std::f64::consts::FRAC_PI_2;
///
/// let surface = |x0: f64, y0: f64, x1: f64, y1: f64| FloorPolygon {
///     polygon: geo::Rect::new((x0, y0), (x1, y1)).to_polygon(),
///     level: 0,
///     z: 0.0,
///     name: None,
///     room: None,
/// };
/// // A corridor (surface 0) and a room north of it (surface 1) open to it over 4 m.
/// let plan = FloorPlan {
///     polygons: vec![surface(0.0, 0.0, 10.0, 2.0), surface(3.0, 2.0, 7.0, 6.0)],
///     barriers: Vec::new(),
/// };
/// let start = StartPose { x: 1.0, y: 1.0, heading: Some(0.0), level: Some(0) };
/// let config = TrackerConfig { start: Some(start), ..Default::default() };
/// let topology = FloorTopology::build(&plan, &config.topology)?;
/// let mut tracker = Tracker::new(&topology, &config)?;
///
/// // Four steps east, a left turn, three steps north.
/// let turns = [0.0, 0.0, 0.0, 0.0, FRAC_PI_2, 0.0, 0.0];
/// let mut estimate = None;
/// for (i, dheading) in turns.into_iter().enumerate() {
///     let step = Step { t: i as f64, length: 1.0, dheading, dz: 0.0, heading: None };
///     estimate = tracker.update(&step)?.estimate;
/// }
/// let estimate = estimate.expect("one cluster");
/// assert!((estimate.x - 5.0).abs() < 0.75 && (estimate.y - 4.0).abs() < 0.75);
/// // Every particle left went through the opening: those that met a wall died.
/// assert!(tracker.particles().iter().all(|p| p.surface == 1));
/// # Ok::<(), footslam::Error>(())
/// ```
#[derive(Debug)]
pub struct Tracker<'a> {
    topology: &'a FloorTopology,
    config: TrackerConfig,
    /// The belief after the last step, equally weighted.
    particles: Vec<TrackParticle>,
    /// The proposal of the current step.
    proposal: Vec<TrackParticle>,
    log_weights: Vec<f32>,
    bin_index: Vec<u32>,
    bins: KldBins,
    dense_bins: bool,
    /// Steps processed.
    steps: u64,
    initial: usize,
    /// The last belief with a single cluster, and the steps taken since (history fitting).
    last_good: Option<Vec<TrackParticle>>,
    history: VecDeque<Step>,
    /// True once the belief has formed a single cluster.
    localised_once: bool,
    /// True when the last step ended with a single cluster.
    localised_now: bool,
    /// Where a uniform prior is drawn (`R_prior` of the 2009 paper, eq. 2; points where the
    /// field is −∞ are outside); `None` = the whole plan.
    region: Option<CellField>,
    /// Steps whose extra measurement was ignored because no particle was consistent with it.
    ignored: usize,
    /// The absolute-heading measurement model.
    heading: HeadingLikelihood,
    /// Steps whose absolute heading weighted the particles.
    headings_used: usize,
    /// The belief's ancestry for the smoothed answer (`config.smoothing`).
    tree: Option<PathTree>,
    /// The tree's peak after [`Self::take_smoothed`] consumed it.
    path_nodes_peak_taken: usize,
    /// A learned map's transitions as a motion prior ([`Self::set_transition_prior`]).
    transitions: Option<&'a TransitionPrior>,
    /// The resampling ancestor of each particle of the belief (kept with the tree only).
    ancestors: Vec<u32>,
    /// Prior draws cut at `kld.max_particles` before KLD was satisfied.
    capped_draws: usize,
    /// The sums of the latest propagation.
    propagation: fit::Propagation,
    /// The step at which the ancestry outgrew `smoothing_max_nodes` and was dropped.
    smoothing_dropped_at: Option<usize>,
    /// The belief as clustered (reused from step to step).
    cluster_points: Vec<ClusterPoint>,
    /// Mean shift's buffers (reused from step to step).
    mean_shift: MeanShift,
}

impl<'a> Tracker<'a> {
    /// A tracker on `topology` with its prior drawn (uniform over every surface and heading,
    /// or about `config.start`) by KLD-sampling.
    ///
    /// # Errors
    ///
    /// As [`Self::new_in_region`].
    pub fn new(topology: &'a FloorTopology, config: &TrackerConfig) -> Result<Self> {
        Self::new_in_region(topology, config, None)
    }

    /// A tracker whose uniform prior — at the start (unless `config.start` is known) and at
    /// every global re-initialisation — is drawn only where `region` is finite (Woodman &
    /// Harle 2009, eq. 2), or over the whole plan when no particle can be placed there.
    ///
    /// # Errors
    ///
    /// - [`Error::Config`] when `config` fails [`TrackerConfig::validate`].
    /// - [`Error::NotEnough`] when the plan has no walkable surface, or no prior particle can be
    ///   placed on one.
    /// - [`Error::Mismatch`] when `config.start` is not on a walkable surface of the plan
    ///   (another frame?).
    pub fn new_in_region(
        topology: &'a FloorTopology,
        config: &TrackerConfig,
        region: Option<CellField>,
    ) -> Result<Self> {
        config.validate()?;
        if topology.is_empty() {
            return Err(Error::not_enough(
                "the floor plan has no walkable surface",
                "",
            ));
        }
        let bins = KldBins::new(&config.kld, topology.bounds(), topology.levels())?;
        let dense_bins = bins.dense();
        let mut tracker = Self {
            topology,
            config: config.clone(),
            particles: Vec::new(),
            proposal: Vec::new(),
            log_weights: Vec::new(),
            bin_index: Vec::new(),
            bins,
            dense_bins,
            steps: 0,
            initial: 0,
            last_good: None,
            history: VecDeque::new(),
            localised_once: false,
            localised_now: false,
            region,
            ignored: 0,
            transitions: None,
            heading: HeadingLikelihood::new(config.heading),
            headings_used: 0,
            tree: config
                .smoothing
                .then(|| PathTree::new(config.smoothing_lag)),
            path_nodes_peak_taken: 0,
            ancestors: Vec::new(),
            capped_draws: 0,
            propagation: fit::Propagation::default(),
            smoothing_dropped_at: None,
            cluster_points: Vec::new(),
            mean_shift: MeanShift::default(),
        };
        if let Some(start) = config.start {
            let s = tracker.locate_start(&start)?;
            tracker.draw_prior(SALT_PRIOR, |rng| s.sample(rng))?;
        } else {
            tracker.draw_uniform_prior(SALT_PRIOR)?;
        }
        tracker.initial = tracker.particles.len();
        tracker.root_tree(0);
        Ok(tracker)
    }

    /// Replaces the region a global re-initialisation draws its prior in (e.g. that of the
    /// latest WiFi scan); `None` = the whole plan.
    pub fn set_region(&mut self, region: Option<CellField>) {
        self.region = region;
    }

    /// Uses a learned map's transitions as a motion prior from the next step on (`None`:
    /// none, the default). The map must be in the plan's frame (a learned plan and the map
    /// it came from share it).
    pub fn set_transition_prior(&mut self, prior: Option<&'a TransitionPrior>) {
        self.transitions = prior;
    }

    /// Prior draws (the start's and re-initialisations') that stopped at
    /// `kld.max_particles` before the KLD bound was met: the plan is too large for the cap
    /// to cover it at the bins' resolution, and the prior is thinner than KLD asks.
    #[must_use]
    pub fn capped_draws(&self) -> usize {
        self.capped_draws
    }

    /// Steps whose extra measurement ([`Self::update_with`]) no particle was consistent with,
    /// so that it was ignored rather than let kill the belief.
    #[must_use]
    pub fn measurements_ignored(&self) -> usize {
        self.ignored
    }

    /// Steps whose absolute heading weighted the particles (0 when the trace has none or
    /// `heading.enabled` is false).
    #[must_use]
    pub fn headings_used(&self) -> usize {
        self.headings_used
    }

    /// The configuration.
    #[must_use]
    pub fn config(&self) -> &TrackerConfig {
        &self.config
    }

    /// The floor plan's topology.
    #[must_use]
    pub fn topology(&self) -> &FloorTopology {
        self.topology
    }

    /// The current particles (equally weighted).
    #[must_use]
    pub fn particles(&self) -> &[TrackParticle] {
        &self.particles
    }

    /// Number of particles drawn from the prior.
    #[must_use]
    pub fn initial_particles(&self) -> usize {
        self.initial
    }

    /// Bytes held per particle, double buffers included: the belief and the proposal, each
    /// particle's log-weight and KLD bin, and its resampling ancestor when the path tree is
    /// kept. Every buffer is as long as the largest set so far (none is shrunk).
    #[must_use]
    pub fn bytes_per_particle(&self) -> f64 {
        fn per_particle<T>(v: &Vec<T>) -> usize {
            if v.capacity() > 0 {
                std::mem::size_of::<T>()
            } else {
                0
            }
        }
        (per_particle(&self.particles)
            + per_particle(&self.proposal)
            + per_particle(&self.log_weights)
            + per_particle(&self.bin_index)
            + per_particle(&self.ancestors)) as f64
    }

    /// Processes one step event (Algorithm 1 for every particle, then KLD-resampling and
    /// clustering).
    ///
    /// # Errors
    ///
    /// [`Error::InvalidData`] when the step's length, heading change or height change is not finite
    /// (a step of a [`StepTrace`](crate::sensor::StepTrace) always is).
    pub fn update(&mut self, step: &Step) -> Result<TrackStep> {
        self.update_with(step, None)
    }

    /// [`Self::update`] with an extra measurement: its field's value at each particle's
    /// place (at the measurement's time within the step) is added to the particle's
    /// log-weight (e.g. a WiFi containment region, eqs. 12–13 of the 2009 paper, or a
    /// likelihood, eq. 14) before resampling. A measurement no particle is consistent with is
    /// ignored (counted in [`Self::measurements_ignored`]).
    ///
    /// # Errors
    ///
    /// [`Error::InvalidData`] when the step's length, heading change or height change is not
    /// finite, as [`Self::update`].
    pub fn update_with(
        &mut self,
        step: &Step,
        measurement: Option<StepMeasurement<'_>>,
    ) -> Result<TrackStep> {
        let input = StepInput::of(step)?;
        self.steps += 1;
        let mut recovery = None;
        let alive = self.propagate(&input, 0.0, SALT_STEP);
        let survival = self.propagation.survival();
        if !alive {
            recovery = Some(self.recover(&input));
        }
        // The height change the particles that carried the step explain (none after a
        // fresh prior, whose sums are those of a failed search).
        let explained = match recovery {
            Some(Recovery::Global) => None,
            _ => self.propagation.explained_dz(),
        };
        let fit = StepFit {
            survival,
            unexplained_dz: explained.map_or(0.0, |dz| (f64::from(input.dz) - dz) as f32),
        };
        if !matches!(recovery, Some(Recovery::Global)) {
            if let Some(mut m) = measurement {
                // History fitting re-seeds and replays the belief: its particles are judged
                // where this step took them.
                if matches!(recovery, Some(Recovery::History { .. })) {
                    m.at = 1.0;
                }
                self.measure(m);
            }
            if self.measure_heading(step) {
                self.headings_used += 1;
            }
            self.measure_transitions();
            let n = self.weigh();
            self.resample(n, SALT_RESAMPLE);
            self.grow_tree();
        } else {
            self.root_tree(self.steps as usize);
        }
        let clusters = self.cluster();
        let localised = clusters
            .as_ref()
            .is_some_and(|c| c.len() == 1 && c[0].spread <= self.config.cluster.max_spread);
        self.localised_once |= localised;
        self.localised_now = localised;
        self.remember(step, localised);
        Ok(TrackStep {
            t: step.t,
            particles: self.particles.len(),
            clusters: clusters.as_ref().map(Vec::len),
            estimate: clusters.and_then(|c| c.first().copied()),
            localised,
            recovery,
            fit: Some(fit),
        })
    }
}
