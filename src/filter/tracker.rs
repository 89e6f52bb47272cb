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

use super::cluster::{Cluster, ClusterPoint, mean_shift};
use super::kld::KldBins;
use super::path_tree::{PathNode, PathTree, SmoothedStep, SmoothedWalk};
use super::recovery::{Recovery, heading_corrections};
use super::tracker_config::{StartPose, TrackerConfig};
use crate::error::{Error, Result};
use crate::map::{CellField, FloorTopology};
use crate::model::{HeadingLikelihood, TransitionPrior};
use crate::sensor::Step;
use rand::RngExt;
use rand_distr::StandardNormal;
use rand_pcg::Pcg64Mcg;
use rayon::prelude::*;
use std::collections::VecDeque;
use std::f32::consts::PI;

/// Particles per chunk of work and per random stream.
pub const CHUNK: usize = 16_384;
/// Chunks drawn at once when sampling a prior (a fixed number, so results do not depend on
/// the number of threads).
const PRIOR_BATCH: usize = 8;
/// Tries to place one prior particle on a surface before giving up on it.
const PLACEMENT_TRIES: usize = 64;
/// Stream salts, so that the prior, the steps and every recovery draw unrelated numbers.
const SALT_PRIOR: u64 = 0x5EED_0001;
const SALT_STEP: u64 = 0x5EED_0002;
const SALT_RESAMPLE: u64 = 0x5EED_0003;
const SALT_HEADING: u64 = 0x5EED_0004;
const SALT_HISTORY: u64 = 0x5EED_0005;
/// Bounds of the per-walk step length scale.
const SCALE_RANGE: (f32, f32) = (0.7, 1.3);

/// One hypothesis of the walker's state: where it is, where it heads, on which surface, and
/// its step length scale and heading-drift rate. 24 bytes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[repr(C)]
pub struct TrackParticle {
    /// East, metres.
    pub x: f32,
    /// North, metres.
    pub y: f32,
    /// Heading of the last step, radians in [−π, π).
    pub heading: f32,
    /// Per-walk step length scale.
    pub scale: f32,
    /// Heading drift per step, radians (added to every measured heading change).
    pub drift: f32,
    /// Index of the floor surface the particle stands on.
    pub surface: u32,
}

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
}

/// The particle filter of Woodman & Harle 2008 on a [`FloorTopology`].
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
}

/// A particle's place as a node of the ancestry.
fn path_node(p: &TrackParticle) -> PathNode {
    PathNode::new(p.x, p.y, p.surface)
}

/// Step inputs in the particles' precision.
#[derive(Debug, Clone, Copy)]
struct StepInput {
    length: f32,
    dheading: f32,
    dz: f32,
}

impl<'a> Tracker<'a> {
    /// A tracker on `topology` with its prior drawn (uniform over every surface and heading,
    /// or about `config.start`) by KLD-sampling.
    pub fn new(topology: &'a FloorTopology, config: &TrackerConfig) -> Result<Self> {
        Self::new_in_region(topology, config, None)
    }

    /// A tracker whose uniform prior — at the start (unless `config.start` is known) and at
    /// every global re-initialisation — is drawn only where `region` is finite (Woodman &
    /// Harle 2009, eq. 2), or over the whole plan when no particle can be placed there.
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
    pub fn capped_draws(&self) -> usize {
        self.capped_draws
    }

    /// Steps whose extra measurement ([`Self::update_with`]) no particle was consistent with,
    /// so that it was ignored rather than let kill the belief.
    pub fn measurements_ignored(&self) -> usize {
        self.ignored
    }

    /// Steps whose absolute heading weighted the particles (0 when the trace has none or
    /// `heading.enabled` is false).
    pub fn headings_used(&self) -> usize {
        self.headings_used
    }

    /// The configuration.
    pub fn config(&self) -> &TrackerConfig {
        &self.config
    }

    /// The floor plan's topology.
    pub fn topology(&self) -> &FloorTopology {
        self.topology
    }

    /// The current particles (equally weighted).
    pub fn particles(&self) -> &[TrackParticle] {
        &self.particles
    }

    /// Number of particles drawn from the prior.
    pub fn initial_particles(&self) -> usize {
        self.initial
    }

    /// Bytes held per particle of the largest set so far, double buffers included.
    pub fn bytes_per_particle(&self) -> f64 {
        let bytes = (self.particles.capacity() + self.proposal.capacity())
            * std::mem::size_of::<TrackParticle>()
            + self.log_weights.capacity() * 4
            + self.bin_index.capacity() * 4
            + self.ancestors.capacity() * 4;
        let n = self
            .particles
            .capacity()
            .max(self.proposal.capacity())
            .max(1);
        bytes as f64 / n as f64
    }

    /// The whole-walk answer: the smoothed belief after each step `0..=steps` (0 = the prior),
    /// from the ancestral lines of the current belief ([`super::path_tree`]); `None` when
    /// `config.smoothing` is off.
    pub fn smoothed(&self) -> Option<Vec<SmoothedStep>> {
        let tree = self.tree.as_ref()?;
        Some(tree.smoothed(self.topology, &self.config.cluster))
    }

    /// [`Self::smoothed`], ending the smoothing: the path tree moves into the answer, which
    /// computes each step's belief as it is read (a long walk never holds every step's
    /// answer), and later calls return `None`.
    pub fn take_smoothed(&mut self) -> Option<SmoothedWalk<'a>> {
        let tree = self.tree.take()?;
        self.path_nodes_peak_taken = tree.peak_nodes();
        Some(SmoothedWalk::new(tree, self.topology, self.config.cluster))
    }

    /// Largest number of path nodes (16 bytes each) the smoother held at once (0 without
    /// smoothing).
    pub fn path_nodes_peak(&self) -> usize {
        self.tree
            .as_ref()
            .map_or(self.path_nodes_peak_taken, PathTree::peak_nodes)
    }

    /// Processes one step event (Algorithm 1 for every particle, then KLD-resampling and
    /// clustering).
    pub fn update(&mut self, step: &Step) -> Result<TrackStep> {
        self.update_with(step, None)
    }

    /// [`Self::update`] with an extra measurement: its field's value at each particle's
    /// place (at the measurement's time within the step) is added to the particle's
    /// log-weight (e.g. a WiFi containment region, eqs. 12–13 of the 2009 paper, or a
    /// likelihood, eq. 14) before resampling. A measurement no particle is consistent with is
    /// ignored (counted in [`Self::measurements_ignored`]).
    pub fn update_with(
        &mut self,
        step: &Step,
        measurement: Option<StepMeasurement<'_>>,
    ) -> Result<TrackStep> {
        let input = StepInput::of(step)?;
        self.steps += 1;
        let mut recovery = None;
        if !self.propagate(&input, 0.0, SALT_STEP) {
            recovery = Some(self.recover(&input));
        }
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
        })
    }

    /// Algorithm 1 for every particle of the belief, into the proposal: returns false when
    /// every particle hit a wall. `heading_offset` is added to the step's heading change
    /// (the heading search of recovery).
    fn propagate(&mut self, u: &StepInput, heading_offset: f32, salt: u64) -> bool {
        let n = self.particles.len();
        resize(&mut self.proposal, n);
        resize(&mut self.log_weights, n);
        resize(&mut self.bin_index, n);
        let model = Motion {
            topology: self.topology,
            length_sigma: self.config.length_sigma as f32,
            dheading_sigma: self.config.dheading_sigma as f32,
            dz_sigma: self.config.dz_sigma as f32,
            scale_walk_sigma: self.config.scale_walk_sigma as f32,
            drift_walk_sigma: self.config.drift_walk_sigma as f32,
            u: StepInput {
                dheading: u.dheading + heading_offset,
                ..*u
            },
        };
        let (seed, step, bins, dense) = (
            self.config.seed ^ salt,
            self.steps,
            &self.bins,
            self.dense_bins,
        );
        let alive = self
            .particles
            .par_chunks(CHUNK)
            .zip(self.proposal.par_chunks_mut(CHUNK))
            .zip(self.log_weights.par_chunks_mut(CHUNK))
            .zip(self.bin_index.par_chunks_mut(CHUNK))
            .enumerate()
            .map(|(c, (((from, to), lw), bi))| {
                let mut rng = crate::random::stream(seed, step, c as u64);
                let mut alive = 0usize;
                for (i, (p, q)) in from.iter().zip(to.iter_mut()).enumerate() {
                    let (next, ll) = model.apply(p, &mut rng);
                    *q = next;
                    lw[i] = ll;
                    alive += usize::from(ll > f32::NEG_INFINITY);
                    if dense {
                        let level = model.topology.level(next.surface);
                        bi[i] = bins.bin(next.x, next.y, next.heading, level) as u32;
                    }
                }
                alive
            })
            .sum::<usize>();
        alive > 0
    }

    /// Adds `m`'s value at every proposed particle to its log-weight, unless that would leave
    /// no particle alive (eq. 1 of the 2009 paper: `w_t = w_{t−1} · p(z_t | s_t)`). Each
    /// particle is judged at the share `m.at` of its move from its parent (`particles[i]`,
    /// which `proposal[i]` was propagated from: every path here ends in [`Self::propagate`]),
    /// on the floor of the nearer end.
    fn measure(&mut self, m: StepMeasurement<'_>) {
        let (topology, at) = (self.topology, m.at.clamp(0.0, 1.0));
        debug_assert_eq!(self.particles.len(), self.proposal.len());
        let value = |from: &TrackParticle, to: &TrackParticle| {
            if at >= 1.0 {
                return m.field.at(topology.level(to.surface), to.x, to.y);
            }
            let level = topology.level(if at < 0.5 { from.surface } else { to.surface });
            let x = from.x + at * (to.x - from.x);
            let y = from.y + at * (to.y - from.y);
            m.field.at(level, x, y)
        };
        let parents = &self.particles;
        let any_alive = self
            .proposal
            .par_iter()
            .zip(parents.par_iter())
            .zip(self.log_weights.par_iter())
            .any(|((to, from), lw)| *lw > f32::NEG_INFINITY && value(from, to) > f32::NEG_INFINITY);
        if !any_alive {
            self.ignored += 1;
            return;
        }
        self.proposal
            .par_iter()
            .zip(parents.par_iter())
            .zip(self.log_weights.par_iter_mut())
            .for_each(|((to, from), lw)| *lw += value(from, to));
    }

    /// Heading measurement (not in Woodman & Harle; a compass as in harle-2013 §V): adds
    /// `ln p(h_t | θ_t)` of the step's absolute heading to every proposed particle's
    /// log-weight (tempered by its eq. 3), where the step has one and the model is enabled.
    /// The model's floor keeps every particle alive, so a disturbed reading cannot kill the
    /// belief. Returns whether the step had a heading to apply.
    fn measure_heading(&mut self, step: &Step) -> bool {
        let Some(h) = step.heading.filter(|_| self.heading.enabled()) else {
            return false;
        };
        let (model, c) = (&self.heading, self.heading.offset_measurement(h));
        // Tempered by the disturbance's correlation length (heading_likelihood eq. 3).
        let tau = model.temper(step.length) as f32;
        self.proposal
            .par_iter()
            .zip(self.log_weights.par_iter_mut())
            .for_each(|(p, lw)| *lw += tau * model.log_likelihood_f32(&c, p.heading));
        true
    }

    /// The learned map's transitions (FeetSLAM's reuse of a FootSLAM map): adds each
    /// proposed particle's [`TransitionPrior::log_factor`] for its move from its parent, on
    /// the floor it reached. A factor is finite, so no particle dies of it.
    fn measure_transitions(&mut self) {
        let Some(prior) = self.transitions else {
            return;
        };
        let topology = self.topology;
        self.proposal
            .par_iter()
            .zip(self.particles.par_iter())
            .zip(self.log_weights.par_iter_mut())
            .for_each(|((to, from), lw)| {
                if *lw > f32::NEG_INFINITY {
                    let level = topology.level(to.surface);
                    *lw += prior.log_factor(
                        (f64::from(from.x), f64::from(from.y)),
                        (f64::from(to.x), f64::from(to.y)),
                        level,
                    );
                }
            });
    }

    /// Turns the proposal's log-weights into weights (relative to the largest), fills the
    /// KLD bins with them and returns the KLD sample size.
    fn weigh(&mut self) -> usize {
        let max = self
            .log_weights
            .par_iter()
            .copied()
            .reduce(|| f32::NEG_INFINITY, f32::max);
        self.log_weights
            .par_iter_mut()
            .for_each(|l| *l = (*l - max).exp());
        self.bins.clear();
        if self.dense_bins {
            for (&b, &w) in self.bin_index.iter().zip(&self.log_weights) {
                if w > 0.0 {
                    self.bins.add(u64::from(b), f64::from(w));
                }
            }
        } else {
            for (p, &w) in self.proposal.iter().zip(&self.log_weights) {
                if w > 0.0 {
                    let level = self.topology.level(p.surface);
                    let b = self.bins.bin(p.x, p.y, p.heading, level);
                    self.bins.add(b, f64::from(w));
                }
            }
        }
        let min = if self.localised_now {
            self.config.kld.min_particles
        } else {
            self.config.ambiguous_min_particles
        };
        self.bins.sample_size_at_least(min)
    }

    /// Systematic resampling of `n` particles from the weighted proposal into the belief,
    /// chunk by chunk in parallel (each chunk emits the pointers that fall in its share of
    /// the cumulative weight).
    fn resample(&mut self, n: usize, salt: u64) {
        let weights = &self.log_weights;
        let sums: Vec<f64> = weights
            .par_chunks(CHUNK)
            .map(|c| c.iter().map(|&w| f64::from(w)).sum())
            .collect();
        let mut starts = Vec::with_capacity(sums.len() + 1);
        let mut total = 0.0;
        for s in &sums {
            starts.push(total);
            total += s;
        }
        debug_assert!(total > 0.0 && total.is_finite());
        let u0: f64 = crate::random::filter_stream(self.config.seed ^ salt, self.steps).random();
        let target = |j: usize| (u0 + j as f64) / n as f64 * total;
        let first_pointer = |s: f64| {
            let mut j = ((s / total * n as f64 - u0).ceil().max(0.0) as usize).min(n);
            while j > 0 && target(j - 1) >= s {
                j -= 1;
            }
            while j < n && target(j) < s {
                j += 1;
            }
            j
        };
        let mut bounds: Vec<usize> = starts.iter().map(|&s| first_pointer(s)).collect();
        bounds.push(n);
        resize(&mut self.particles, n);
        // Ancestors are recorded only for the path tree (an empty slice per chunk otherwise).
        let record = self.tree.is_some();
        resize(&mut self.ancestors, if record { n } else { 0 });
        let mut rest: &mut [TrackParticle] = &mut self.particles;
        let mut rest_ancestors: &mut [u32] = &mut self.ancestors;
        let mut outputs = Vec::with_capacity(sums.len());
        for w in bounds.windows(2) {
            let (head, tail) = rest.split_at_mut(w[1] - w[0]);
            let split = if record { w[1] - w[0] } else { 0 };
            let (a_head, a_tail) = rest_ancestors.split_at_mut(split);
            outputs.push((w[0], head, a_head));
            rest = tail;
            rest_ancestors = a_tail;
        }
        let proposal = &self.proposal;
        outputs
            .into_par_iter()
            .zip(weights.par_chunks(CHUNK))
            .zip(starts.par_iter())
            .enumerate()
            .for_each(|(c, (((j0, out, ancestors), w), &start))| {
                let base = c * CHUNK;
                let mut i = 0;
                let mut cumulative = start + f64::from(w[0]);
                for (k, slot) in out.iter_mut().enumerate() {
                    let t = target(j0 + k);
                    while t >= cumulative && i + 1 < w.len() {
                        i += 1;
                        cumulative += f64::from(w[i]);
                    }
                    *slot = proposal[base + i];
                    if let Some(a) = ancestors.get_mut(k) {
                        *a = (base + i) as u32;
                    }
                }
            });
    }

    /// The belief as path nodes.
    fn path_nodes(&self) -> Vec<PathNode> {
        self.particles.iter().map(path_node).collect()
    }

    /// Starts a new ancestry at `step` with the belief as its roots (a prior, or particles
    /// not descended from the last belief).
    fn root_tree(&mut self, step: usize) {
        if self.tree.is_some() {
            let nodes = self.path_nodes();
            if let Some(tree) = self.tree.as_mut() {
                tree.root(step, nodes, self.topology, &self.config.cluster);
            }
        }
    }

    /// Adds the resampled belief to the ancestry (its ancestors index the last generation).
    fn grow_tree(&mut self) {
        if let Some(tree) = self.tree.as_mut() {
            tree.push(
                self.particles.iter().map(path_node),
                &self.ancestors,
                self.topology,
                &self.config.cluster,
            );
        }
    }

    /// Clusters the belief when it has at most `cluster.max_particles` particles; once the
    /// walker has been localised, a larger belief is clustered through an evenly strided
    /// subsample of that many particles, so that tracking never stops producing estimates.
    fn cluster(&self) -> Option<Vec<Cluster>> {
        let max = self.config.cluster.max_particles.max(1);
        let n = self.particles.len();
        if n > max && !self.localised_once {
            return None;
        }
        let stride = n.div_ceil(max).max(1);
        let points: Vec<ClusterPoint> = self
            .particles
            .iter()
            .step_by(stride)
            .map(|p| ClusterPoint {
                x: p.x,
                y: p.y,
                z: self.topology.z(p.surface),
                level: self.topology.level(p.surface),
                heading: p.heading,
                weight: 1.0,
            })
            .collect();
        Some(mean_shift(&points, &self.config.cluster))
    }

    /// Keeps the last single-cluster belief and the steps since, for history fitting.
    fn remember(&mut self, step: &Step, localised: bool) {
        if localised {
            self.last_good = Some(self.particles.clone());
            self.history.clear();
        } else if self.last_good.is_some() {
            self.history.push_back(*step);
            if self.history.len() > self.config.recovery.history_steps {
                self.last_good = None;
                self.history.clear();
            }
        }
    }

    /// Every particle died at this step: heading search, then history fitting from the last
    /// good belief, then a fresh uniform prior. On return the proposal holds live particles
    /// (or, for [`Recovery::Global`], the belief is a fresh prior).
    fn recover(&mut self, u: &StepInput) -> Recovery {
        let r = self.config.recovery;
        for (attempt, correction) in
            heading_corrections(u.dheading, r.heading_increment as f32, r.heading_max as f32)
                .enumerate()
        {
            let salt = SALT_HEADING ^ crate::random::mix(attempt as u64);
            if self.propagate(u, correction, salt) {
                return Recovery::HeadingSearch {
                    correction_deg: f64::from(correction).to_degrees(),
                };
            }
        }
        if let Some(good) = self.last_good.take() {
            let history: Vec<Step> = self.history.iter().copied().collect();
            for attempt in 0..r.history_attempts {
                let radius = r.history_radius * f64::from(1u32 << attempt.min(16));
                if self.fit_history(&good, &history, u, radius, attempt as u64) {
                    self.last_good = Some(good);
                    return Recovery::History {
                        radius_m: radius,
                        steps: history.len() + 1,
                    };
                }
            }
        }
        self.last_good = None;
        self.history.clear();
        self.localised_once = false;
        if self
            .draw_uniform_prior(SALT_PRIOR ^ crate::random::mix(self.steps))
            .is_err()
        {
            // Unreachable for a non-empty plan; keep the previous belief rather than none.
            self.proposal.clone_from(&self.particles);
        }
        Recovery::Global
    }

    /// History fitting: re-seeds particles within `radius` of the last good belief (eq. 5 of
    /// the smartphone paper) and replays the steps since then through the filter; true when
    /// some survive the current step too (the proposal then holds them).
    fn fit_history(
        &mut self,
        good: &[TrackParticle],
        history: &[Step],
        u: &StepInput,
        radius: f64,
        attempt: u64,
    ) -> bool {
        let salt = SALT_HISTORY ^ crate::random::mix(self.steps ^ (attempt << 48));
        let topology = self.topology;
        let heading_sigma = (self.config.recovery.heading_max / 2.0) as f32;
        let n = self.config.recovery.history_particles;
        let seeded: Vec<TrackParticle> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .flat_map_iter(|c| {
                let mut rng = crate::random::stream(self.config.seed ^ salt, 0, c as u64);
                let count = CHUNK.min(n - c * CHUNK);
                (0..count)
                    .filter_map(|_| {
                        let p = good[rng.random_range(0..good.len())];
                        jitter(topology, &p, radius, heading_sigma, &mut rng)
                    })
                    .collect::<Vec<_>>()
            })
            .collect();
        if seeded.is_empty() {
            return false;
        }
        self.particles = seeded;
        // The re-seeded belief stands at the last good step; the replay replaces the steps
        // since in the ancestry (kept aside until the fit succeeds).
        let keep_paths = self.tree.is_some();
        let roots = if keep_paths {
            self.path_nodes()
        } else {
            Vec::new()
        };
        let mut replayed = Vec::new();
        for (k, s) in history.iter().enumerate() {
            let Ok(h) = StepInput::of(s) else {
                return false;
            };
            if !self.propagate(&h, 0.0, salt ^ crate::random::mix(k as u64 + 1)) {
                return false;
            }
            // A replayed step's heading weighs again but is not counted again.
            self.measure_heading(s);
            self.measure_transitions();
            let m = self.weigh();
            self.resample(m, salt ^ crate::random::mix(k as u64 + 1));
            if keep_paths {
                replayed.push((self.path_nodes(), self.ancestors.clone()));
            }
        }
        if !self.propagate(u, 0.0, salt) {
            return false;
        }
        if let Some(tree) = self.tree.as_mut() {
            let good_step = (self.steps as usize).saturating_sub(1 + history.len());
            tree.root(good_step, roots, self.topology, &self.config.cluster);
            for (nodes, ancestors) in replayed {
                tree.push(nodes, &ancestors, self.topology, &self.config.cluster);
            }
        }
        true
    }

    /// Draws the uniform prior over every surface and heading — inside the region when one
    /// is set and particles can be placed there, else over the whole plan.
    fn draw_uniform_prior(&mut self, salt: u64) -> Result<()> {
        if let Some(region) = self.region.take() {
            let drawn = self.draw_prior_in(salt, Some(&region));
            self.region = Some(region);
            if drawn.is_ok() {
                return drawn;
            }
        }
        self.draw_prior_in(salt, None)
    }

    /// The uniform prior over every surface and heading, restricted to where `region` is
    /// finite when given: candidates are drawn uniformly over the whole plan and counted by
    /// the KLD rule exactly as the unrestricted prior, and those outside the region are
    /// dropped. The prior thus has the unrestricted prior's density, its particle count
    /// proportional to the region's floor area (Woodman & Harle 2009, sec. 2 and 5.1) — KLD
    /// counted over the region's own bins would ask for more particles per square metre the
    /// more fragmented the region (every cell's edge bins count whole).
    fn draw_prior_in(&mut self, salt: u64, region: Option<&CellField>) -> Result<()> {
        let topology = self.topology;
        let (lo, hi) = SCALE_RANGE;
        let scale_sigma = self.config.scale_sigma as f32;
        let drift_sigma = self.config.drift_sigma as f32;
        let at_least = self.config.kld.min_particles;
        self.draw_candidates(salt, at_least, move |rng| {
            let (surface, [x, y]) = topology.sample_uniform(rng);
            let keep = region.is_none_or(|r| {
                r.at(topology.level(surface), x as f32, y as f32) > f32::NEG_INFINITY
            });
            let particle = TrackParticle {
                x: x as f32,
                y: y as f32,
                heading: rng.random_range(-PI..PI),
                scale: (1.0 + scale_sigma * rng.sample::<f32, _>(StandardNormal)).clamp(lo, hi),
                drift: if drift_sigma > 0.0 {
                    drift_sigma * rng.sample::<f32, _>(StandardNormal)
                } else {
                    0.0
                },
                surface,
            };
            Some((particle, keep))
        })
    }

    /// Draws prior particles by Fox's sequential KLD rule: chunks are generated in parallel
    /// from per-chunk streams, then counted in order until `n ≥ n_χ(k)`.
    fn draw_prior(
        &mut self,
        salt: u64,
        draw: impl Fn(&mut Pcg64Mcg) -> Option<TrackParticle> + Sync,
    ) -> Result<()> {
        self.draw_candidates(salt, 0, move |rng| draw(rng).map(|p| (p, true)))
    }

    /// The KLD rule of [`Self::draw_prior`] over candidates `(particle, keep)`: every
    /// candidate counts towards `n` and its bin, only kept ones become particles; drawing
    /// goes on (up to `max_particles` candidates) until at least `at_least` are kept.
    fn draw_candidates(
        &mut self,
        salt: u64,
        at_least: usize,
        draw: impl Fn(&mut Pcg64Mcg) -> Option<(TrackParticle, bool)> + Sync,
    ) -> Result<()> {
        let seed = self.config.seed ^ salt;
        let max = self.config.kld.max_particles;
        let mut drawn: Vec<TrackParticle> = Vec::new();
        let mut candidates = 0usize;
        let mut settled = false;
        self.bins.clear();
        let mut chunk = 0usize;
        'outer: loop {
            let batch: Vec<Vec<(TrackParticle, bool)>> = (chunk..chunk + PRIOR_BATCH)
                .into_par_iter()
                .map(|c| {
                    let mut rng = crate::random::stream(seed, 0, c as u64);
                    (0..CHUNK)
                        .filter_map(|_| (0..PLACEMENT_TRIES).find_map(|_| draw(&mut rng)))
                        .collect()
                })
                .collect();
            chunk += PRIOR_BATCH;
            if batch.iter().all(Vec::is_empty) {
                return Err(Error::not_enough(
                    "no prior particle could be placed on a walkable surface",
                    "",
                ));
            }
            for (p, keep) in batch.into_iter().flatten() {
                candidates += 1;
                if !settled {
                    let level = self.topology.level(p.surface);
                    self.bins.mark(self.bins.bin(p.x, p.y, p.heading, level));
                    settled = self.bins.enough(candidates, self.bins.occupied());
                }
                if keep {
                    drawn.push(p);
                }
                if (settled && drawn.len() >= at_least) || candidates >= max {
                    let met = self.bins.satisfied(candidates, self.bins.occupied());
                    self.capped_draws += usize::from(candidates >= max && !met);
                    break 'outer;
                }
            }
        }
        if drawn.is_empty() {
            return Err(Error::not_enough(
                "no prior particle could be placed inside the prior region",
                "",
            ));
        }
        drawn.shrink_to_fit();
        self.particles = drawn;
        // The uniform prior stands in for this step's proposal when it replaces a dead belief.
        self.proposal.clone_from(&self.particles);
        Ok(())
    }

    /// The known start's surface, or a clear error when the point is off the plan.
    fn locate_start(&self, start: &StartPose) -> Result<StartSampler<'a>> {
        let surface = self
            .topology
            .locate(start.x, start.y, start.level, None)
            .ok_or_else(|| {
                Error::mismatch(
                    format!(
                        "the start ({}, {}{}) is not on a walkable surface of the plan",
                        start.x,
                        start.y,
                        start
                            .level
                            .map_or(String::new(), |l| format!(", level {l}"))
                    ),
                    "give a start inside the plan, in its frame",
                )
            })?;
        Ok(StartSampler {
            topology: self.topology,
            start: *start,
            level: self.topology.level(surface),
            z: f64::from(self.topology.z(surface)),
            position_sigma: self.config.start_position_sigma,
            heading_sigma: self.config.start_heading_sigma,
            scale_sigma: self.config.scale_sigma,
            drift_sigma: self.config.drift_sigma,
        })
    }
}

/// The step model and the map the particles move on (Algorithm 1).
struct Motion<'a> {
    topology: &'a FloorTopology,
    length_sigma: f32,
    dheading_sigma: f32,
    dz_sigma: f32,
    scale_walk_sigma: f32,
    drift_walk_sigma: f32,
    u: StepInput,
}

impl Motion<'_> {
    /// Algorithm 1 for one particle: the moved particle and its log-weight (−∞ when a wall
    /// was crossed).
    #[inline]
    fn apply(&self, p: &TrackParticle, rng: &mut Pcg64Mcg) -> (TrackParticle, f32) {
        let x: f32 = rng.sample(StandardNormal);
        let y: f32 = rng.sample(StandardNormal);
        let drift = if self.drift_walk_sigma > 0.0 {
            let d: f32 = rng.sample(StandardNormal);
            p.drift + self.drift_walk_sigma * d
        } else {
            p.drift
        };
        let dtheta = self.u.dheading + drift + self.dheading_sigma * x; // eq. (8)
        let length = (self.u.length * p.scale + self.length_sigma * y).max(0.0); // eq. (7)
        let heading = wrap(p.heading + dtheta); // eq. (9)
        let (sin, cos) = heading.sin_cos();
        let to = [p.x + length * cos, p.y + length * sin]; // eqs. (10), (11)
        let scale = if self.scale_walk_sigma > 0.0 {
            let s: f32 = rng.sample(StandardNormal);
            (p.scale + self.scale_walk_sigma * s).clamp(SCALE_RANGE.0, SCALE_RANGE.1)
        } else {
            p.scale
        };
        let moved = |surface| TrackParticle {
            x: to[0],
            y: to[1],
            heading,
            scale,
            drift,
            surface,
        };
        match self.topology.walk(p.surface, [p.x, p.y], to) {
            None => (moved(p.surface), f32::NEG_INFINITY), // eq. (14)
            Some(surface) => {
                let dz_poly = self.topology.z(surface) - self.topology.z(p.surface); // eq. (15)
                let e = (self.u.dz - dz_poly) / self.dz_sigma;
                (moved(surface), -0.5 * e * e) // eq. (17), up to a constant
            }
        }
    }
}

impl StepInput {
    fn of(step: &Step) -> Result<Self> {
        if !(step.length.is_finite() && step.dheading.is_finite() && step.dz.is_finite()) {
            return Err(Error::invalid(
                format!("step at t = {} s", step.t),
                "has a non-finite length, heading change or height change",
            ));
        }
        Ok(Self {
            length: step.length as f32,
            dheading: step.dheading as f32,
            dz: step.dz as f32,
        })
    }
}

/// Draws particles about a known start.
struct StartSampler<'a> {
    topology: &'a FloorTopology,
    start: StartPose,
    level: i32,
    z: f64,
    position_sigma: f64,
    heading_sigma: f64,
    scale_sigma: f64,
    drift_sigma: f64,
}

impl StartSampler<'_> {
    fn sample(&self, rng: &mut Pcg64Mcg) -> Option<TrackParticle> {
        let g = |rng: &mut Pcg64Mcg| rng.sample::<f64, _>(StandardNormal);
        let x = self.start.x + self.position_sigma * g(rng);
        let y = self.start.y + self.position_sigma * g(rng);
        let surface = self.topology.locate(x, y, Some(self.level), Some(self.z))?;
        Some(
            TrackParticle {
                x: x as f32,
                y: y as f32,
                heading: match self.start.heading {
                    Some(h) => wrap((h + self.heading_sigma * g(rng)) as f32),
                    // Unknown: uniform over the circle.
                    None => rng.random_range(-PI..PI),
                },
                scale: (1.0 + self.scale_sigma * g(rng)) as f32,
                drift: (self.drift_sigma * g(rng)) as f32,
                surface,
            }
            .clamp_scale(),
        )
    }
}

impl TrackParticle {
    fn clamp_scale(mut self) -> Self {
        self.scale = self.scale.clamp(SCALE_RANGE.0, SCALE_RANGE.1);
        self
    }
}

/// A copy of `p` moved uniformly within `radius` (eq. 5 of the smartphone paper) and turned by
/// a normal heading error, on a surface of its level; `None` when that point is off the plan.
fn jitter(
    topology: &FloorTopology,
    p: &TrackParticle,
    radius: f64,
    heading_sigma: f32,
    rng: &mut Pcg64Mcg,
) -> Option<TrackParticle> {
    let level = topology.level(p.surface);
    let z = f64::from(topology.z(p.surface));
    for _ in 0..PLACEMENT_TRIES {
        let r = radius * rng.random::<f64>().sqrt();
        let phi = rng.random_range(0.0..std::f64::consts::TAU);
        let (x, y) = (
            f64::from(p.x) + r * phi.cos(),
            f64::from(p.y) + r * phi.sin(),
        );
        if let Some(surface) = topology.locate(x, y, Some(level), Some(z)) {
            let turn: f32 = rng.sample(StandardNormal);
            return Some(TrackParticle {
                x: x as f32,
                y: y as f32,
                heading: wrap(p.heading + heading_sigma * turn),
                scale: p.scale,
                drift: p.drift,
                surface,
            });
        }
    }
    None
}

/// Wraps an angle to [−π, π) (up to rounding at the ends).
#[inline]
fn wrap(a: f32) -> f32 {
    if (-PI..PI).contains(&a) {
        a
    } else {
        (a + PI).rem_euclid(2.0 * PI) - PI
    }
}

/// Sets `v`'s length to `n` (contents unspecified), keeping its allocation where it fits and
/// releasing most of it when the set shrinks a lot.
fn resize<T: Copy + Default>(v: &mut Vec<T>, n: usize) {
    if n < v.capacity() / 8 {
        v.truncate(n);
        v.shrink_to(2 * n);
    }
    if v.capacity() < n {
        v.reserve_exact(n - v.len());
    }
    v.resize(n, T::default());
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::filter::KldConfig;
    use crate::map::TopologyConfig;
    use crate::sim::{SimConfig, simulate};

    fn office() -> (crate::sim::Simulation, FloorTopology) {
        let mut config = SimConfig {
            seed: 7,
            ..Default::default()
        };
        config.walk.laps = 1;
        let sim = simulate(&config).expect("sim");
        let topology = FloorTopology::build(&sim.plan, &TopologyConfig::default()).expect("topo");
        (sim, topology)
    }

    fn small() -> TrackerConfig {
        TrackerConfig {
            kld: KldConfig {
                max_particles: 200_000,
                ..Default::default()
            },
            ..Default::default()
        }
    }

    /// [`small`] with a known start at the office's origin, on level 0.
    fn at_origin(heading: f64) -> TrackerConfig {
        TrackerConfig {
            start: Some(StartPose {
                x: 0.0,
                y: 0.0,
                heading: Some(heading),
                level: Some(0),
            }),
            ..small()
        }
    }

    #[test]
    fn particle_is_24_bytes_and_memory_is_at_most_64_bytes_per_particle() {
        assert_eq!(std::mem::size_of::<TrackParticle>(), 24);
        let (sim, topology) = office();
        let mut tracker = Tracker::new(&topology, &small()).expect("tracker");
        for s in &sim.steps.steps()[..3] {
            tracker.update(s).expect("update");
        }
        let b = tracker.bytes_per_particle();
        assert!(b <= 64.0, "{b} bytes per particle");
    }

    #[test]
    fn known_start_tracks_a_walk_closely() {
        let (sim, topology) = office();
        let config = at_origin(0.0);
        let mut tracker = Tracker::new(&topology, &config).expect("tracker");
        assert!(tracker.initial_particles() < 50_000);
        let mut errors = Vec::new();
        for (s, p) in sim.steps.steps().iter().zip(&sim.truth.poses) {
            let r = tracker.update(s).expect("update");
            assert!(r.recovery.is_none(), "death at t = {}", s.t);
            let c = r.estimate.expect("clustered");
            errors.push((c.x - p.x).hypot(c.y - p.y));
        }
        errors.sort_by(f64::total_cmp);
        let p95 = errors[errors.len() * 95 / 100];
        assert!(p95 < 0.8, "p95 {p95} m");
    }

    #[test]
    fn a_drift_rate_state_follows_a_drifting_gyro() {
        let mut config = SimConfig {
            seed: 9,
            ..Default::default()
        };
        config.walk.laps = 2;
        config.noise.drift_total = 120f64.to_radians();
        let sim = simulate(&config).expect("sim");
        let topology = FloorTopology::build(&sim.plan, &TopologyConfig::default()).expect("topo");
        let p95 = |drift_sigma: f64| {
            let config = TrackerConfig {
                drift_sigma,
                drift_walk_sigma: drift_sigma / 30.0,
                ..at_origin(0.0)
            };
            let mut tracker = Tracker::new(&topology, &config).expect("tracker");
            let mut errors: Vec<f64> = sim
                .steps
                .steps()
                .iter()
                .zip(&sim.truth.poses)
                .map(|(s, p)| {
                    let c = tracker
                        .update(s)
                        .expect("update")
                        .estimate
                        .expect("cluster");
                    (c.x - p.x).hypot(c.y - p.y)
                })
                .collect();
            errors.sort_by(f64::total_cmp);
            (
                errors[errors.len() * 95 / 100],
                tracker.particles()[0].drift,
            )
        };
        let (with, drift) = p95(0.05f64.to_radians());
        assert!(with < 1.0, "p95 {with} m with a drift state");
        // The walk drifts 120° over about 300 steps: about 0.4° a step, one sign.
        assert!(drift.abs() > 0.1f32.to_radians(), "drift {drift}");
    }

    #[test]
    fn unknown_start_prior_covers_the_plan_and_shrinks() {
        let (sim, topology) = office();
        let mut tracker = Tracker::new(&topology, &small()).expect("tracker");
        let n0 = tracker.initial_particles();
        let bins = topology.total_area() * 36.0;
        assert!(n0 as f64 > bins, "{n0} particles for {bins} bins");
        assert!(tracker.particles().iter().all(|p| {
            sim.plan
                .is_walkable(f64::from(p.x), f64::from(p.y), Some(0))
        }));
        for s in &sim.steps.steps()[..60] {
            tracker.update(s).expect("update");
        }
        assert!(tracker.particles().len() < n0 / 4);
    }

    #[test]
    fn results_do_not_depend_on_the_number_of_threads() {
        let (sim, topology) = office();
        let run = |threads| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("pool");
            pool.install(|| {
                let mut tracker = Tracker::new(&topology, &small()).expect("tracker");
                let reports: Vec<TrackStep> = sim.steps.steps()[..40]
                    .iter()
                    .map(|s| tracker.update(s).expect("update"))
                    .collect();
                (reports, tracker.particles().to_vec())
            })
        };
        assert_eq!(run(1), run(2));
    }

    #[test]
    fn a_walk_through_a_wall_is_recovered_not_a_crash() {
        let (_, topology) = office();
        let config = at_origin(-std::f64::consts::FRAC_PI_2);
        let mut tracker = Tracker::new(&topology, &config).expect("tracker");
        // Straight south from the corridor's centre line: through its south wall.
        let steps: Vec<Step> = (0..30)
            .map(|k| Step {
                t: f64::from(k) * 0.5 + 0.5,
                length: 0.7,
                dheading: 0.0,
                dz: 0.0,
                heading: None,
            })
            .collect();
        let mut deaths = 0;
        for s in &steps {
            let r = tracker.update(s).expect("update");
            deaths += usize::from(r.recovery.is_some());
            assert!(r.particles > 0);
            assert!(
                tracker
                    .particles()
                    .iter()
                    .all(|p| p.x.is_finite() && p.y.is_finite())
            );
        }
        assert!(deaths > 0);
    }

    #[test]
    fn an_unknown_start_heading_is_settled_by_step_headings() {
        let (sim, topology) = office();
        let unknown = |enabled: bool| TrackerConfig {
            start: Some(StartPose {
                heading: None,
                ..at_origin(0.0).start.expect("start")
            }),
            heading: crate::model::HeadingConfig {
                enabled,
                ..Default::default()
            },
            ..small()
        };
        // The mean resultant length of the particles' headings: 1 when all agree.
        let agreement = |t: &Tracker| {
            let (s, c) = t.particles().iter().fold((0.0, 0.0), |(s, c), p| {
                (
                    s + f64::from(p.heading.sin()),
                    c + f64::from(p.heading.cos()),
                )
            });
            s.hypot(c) / t.particles().len() as f64
        };
        let steps: Vec<Step> = sim
            .steps
            .steps()
            .iter()
            .zip(&sim.truth.poses)
            .map(|(s, p)| Step {
                heading: Some(p.heading),
                ..*s
            })
            .collect();
        let mut with = Tracker::new(&topology, &unknown(true)).expect("tracker");
        let mut without = Tracker::new(&topology, &unknown(false)).expect("tracker");
        assert!(agreement(&with) < 0.2, "a uniform prior heading");
        for s in &steps[..2] {
            with.update(s).expect("update");
            without.update(s).expect("update");
        }
        assert_eq!((with.headings_used(), without.headings_used()), (2, 0));
        // Two readings leave headings within about 20° (R = e^{−σ²/2} ≈ 0.94 for σ = 20°).
        assert!(agreement(&with) > 0.9, "{}", agreement(&with));
        assert!(agreement(&without) < agreement(&with));
        let mut errors: Vec<f64> = steps[2..]
            .iter()
            .zip(&sim.truth.poses[2..])
            .map(|(s, p)| {
                let c = with.update(s).expect("update").estimate.expect("cluster");
                (c.x - p.x).hypot(c.y - p.y)
            })
            .collect();
        errors.sort_by(f64::total_cmp);
        let p95 = errors[errors.len() * 95 / 100];
        assert!(p95 < 0.8, "p95 {p95} m");
    }

    #[test]
    fn a_measurement_judges_each_particle_where_it_was_at_the_measurements_time() {
        use crate::map::{CellConfig, CellMap, CellRaster, RadioMap};
        use std::sync::Arc;
        let (sim, topology) = office();
        let cells = CellMap::build(
            &sim.plan,
            &topology,
            &CellConfig {
                granularity: 1.0,
                ..Default::default()
            },
        )
        .expect("cells");
        let raster = Arc::new(
            CellRaster::on_plan(&RadioMap::empty(&cells), &topology, 0.25).expect("raster"),
        );
        // Inside: the 1 m cell the walker starts in, east along the corridor from (0, 0).
        let start = raster.cell_at(0, 0.0, 0.0).expect("a cell at the start");
        let values = (0..raster.cells())
            .map(|c| if c == start { 0.0 } else { f32::NEG_INFINITY })
            .collect();
        let region = CellField::new(raster, values, f32::NEG_INFINITY);
        let config = at_origin(0.0);
        // A 2 m step east leaves the start's cell: judged before the step (at = 0) every
        // particle is inside, after it (at = 1) none is, so that measurement is ignored.
        let step = Step {
            t: 1.0,
            length: 2.0,
            dheading: 0.0,
            dz: 0.0,
            heading: None,
        };
        let run = |at: f32| {
            let mut tracker = Tracker::new(&topology, &config).expect("tracker");
            let m = StepMeasurement { field: &region, at };
            let r = tracker.update_with(&step, Some(m)).expect("step");
            (
                tracker.measurements_ignored(),
                r.estimate.expect("estimate").x,
            )
        };
        let (ignored, x) = run(0.0);
        assert_eq!(ignored, 0);
        assert!((x - 2.0).abs() < 0.5, "{x}");
        assert_eq!(run(1.0).0, 1);
    }
}
