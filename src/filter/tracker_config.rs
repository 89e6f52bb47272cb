//! The configuration of [`super::Tracker`]: every parameter, its unit and default.

use super::cluster::ClusterConfig;
use super::kld::KldConfig;
use super::recovery::RecoveryConfig;
use super::rf_assist::RfConfig;
use crate::error::Result;
use crate::map::TopologyConfig;
use crate::model::{HeadingConfig, TransitionPriorConfig};
use crate::sensor::TruePose;
use serde::{Deserialize, Serialize};

/// A known start: where the walker stands before the first step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StartPose {
    /// East, metres (local frame).
    pub x: f64,
    /// North, metres.
    pub y: f64,
    /// Heading before the first step, radians counter-clockwise from east; `None` (or
    /// missing, or `null`) = unknown: uniform over the circle at the known position (step
    /// headings, where the trace has them, settle it within a few steps).
    #[serde(default)]
    pub heading: Option<f64>,
    /// Floor level; `None` = any surface containing the point (the lowest).
    pub level: Option<i32>,
}

impl From<TruePose> for StartPose {
    /// The known start of a walk whose true start pose is known (a simulation's), position,
    /// heading and floor.
    fn from(start: TruePose) -> Self {
        Self {
            x: start.x,
            y: start.y,
            heading: Some(start.heading),
            level: Some(start.level),
        }
    }
}

impl std::str::FromStr for StartPose {
    type Err = String;

    /// Parses `X,Y[,HEADING[,LEVEL]]` (as `--start` and the walk manifests take it); an
    /// empty HEADING (`X,Y,,LEVEL`) is unknown.
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let parts: Vec<&str> = s.split(',').map(str::trim).collect();
        if !(2..=4).contains(&parts.len()) {
            return Err(format!(
                "expected X,Y[,HEADING[,LEVEL]] (X,Y,,LEVEL for a level without a heading), got `{s}`"
            ));
        }
        let number = |i: usize, what: &str| {
            parts[i]
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("{what} `{}` is not a finite number", parts[i]))
        };
        let heading = match parts.get(2) {
            Some(h) if !h.is_empty() => Some(number(2, "HEADING")?),
            _ => None,
        };
        let level = match parts.get(3) {
            Some(l) => Some(
                l.parse::<i32>()
                    .map_err(|_| format!("level `{l}` is not an integer"))?,
            ),
            None => None,
        };
        Ok(StartPose {
            x: number(0, "X")?,
            y: number(1, "Y")?,
            heading,
            level,
        })
    }
}

/// The known-map tracker's parameters; every default in one place.
///
/// | field                 | default   | meaning                                                 |
/// |-----------------------|-----------|---------------------------------------------------------|
/// | `seed`                | 0         | seed of every random draw                               |
/// | `length_sigma`        | 0.15 m    | step length noise `σ_l` (eq. 7, the paper's value)      |
/// | `dheading_sigma`      | 0.6°      | heading change noise `σ_θ` (eq. 8, the paper's value)   |
/// | `dz_sigma`            | 0.1 m     | height change likelihood `σ_h` (eq. 17, the paper's)    |
/// | `scale_sigma`         | 0.05      | spread of the per-walk step length scale at the start   |
/// | `scale_walk_sigma`    | 0.0005    | random walk of the scale per step                       |
/// | `drift_sigma`         | 0 (off)   | spread of the heading-drift rate (per step) at the start |
/// | `drift_walk_sigma`    | 0 (off)   | random walk of the drift rate per step                  |
/// | `start`               | none      | known start pose (`None` = uniform prior)               |
/// | `start_position_sigma`| 0.3 m     | spread of a known start's position                      |
/// | `start_heading_sigma` | 5°        | spread of a known start's heading (when it has one)     |
/// | `heading`             | see [`HeadingConfig`] | step headings (compass): σ 20°, ε 0.2, on   |
/// | `ambiguous_min_particles` | 3000  | fewest particles while the belief is not one cluster |
/// | `smoothing`           | on        | keep the belief's ancestry for the whole-walk answer    |
/// | `smoothing_lag`       | 10 steps  | lag of the fixed-lag answer used where the walk is sure |
/// | `smoothing_max_nodes` | 67,108,864 | most path nodes the ancestry may hold (1 GiB); beyond, the whole-walk answer is given up for the filter's |
/// | `kld`                 | see [`KldConfig`]     | adaptive particle count                     |
/// | `cluster`             | see [`ClusterConfig`] | clusters and localisation                   |
/// | `recovery`            | see [`RecoveryConfig`]| when every particle dies                    |
/// | `topology`            | see [`TopologyConfig`]| connections and walls of the plan           |
/// | `rf`                  | see [`RfConfig`]      | WiFi with a radio map (`track --radiomap`)  |
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TrackerConfig {
    /// Seed of every random draw; equal seeds give equal results on any thread count.
    pub seed: u64,
    /// Step length noise `σ_l`, metres.
    pub length_sigma: f64,
    /// Heading change noise `σ_θ`, radians.
    pub dheading_sigma: f64,
    /// Height change likelihood's `σ_h`, metres.
    pub dz_sigma: f64,
    /// Spread (1σ) of the per-walk step length scale at the start (0 = no scale state).
    pub scale_sigma: f64,
    /// Random walk (1σ) of the step length scale per step.
    pub scale_walk_sigma: f64,
    /// Spread (1σ) of the heading-drift rate at the start, radians per step (0 = no drift
    /// state). Off by default: the per-step heading noise absorbs a foot-mounted sensor's
    /// drift (tens of degrees an hour); for gyros drifting several degrees a minute, set
    /// e.g. 0.0005 (0.03°/step) with `drift_walk_sigma` 0.00002 — the extra heading freedom
    /// also slows localisation a little.
    pub drift_sigma: f64,
    /// Random walk (1σ) of the heading-drift rate, radians per step per step.
    pub drift_walk_sigma: f64,
    /// Known start pose, or `None` for the uniform prior over all surfaces and headings.
    pub start: Option<StartPose>,
    /// Spread (1σ) of a known start's position, metres.
    pub start_position_sigma: f64,
    /// Spread (1σ) of a known start's heading, radians.
    pub start_heading_sigma: f64,
    /// Fewest particles while the belief is not a single cluster: several hypotheses (e.g.
    /// identical floors) each keep enough particles that resampling noise alone does not
    /// extinguish one (KLD's `min_particles` applies once localised).
    pub ambiguous_min_particles: usize,
    /// Keep the ancestry of the belief (a pruned path tree, 16 bytes per stored ancestor) so
    /// that [`super::Tracker::smoothed`] can answer for every step with the whole walk's
    /// evidence; off for causal (online) use.
    pub smoothing: bool,
    /// Steps of look-ahead of the fixed-lag answer that refines the whole-walk answer where
    /// the walk settles the place (see [`super::PathTree::new`]); 0 = the final belief's
    /// ancestral lines alone.
    pub smoothing_lag: usize,
    /// Most path nodes (16 bytes each) the ancestry may hold. A belief that never narrows
    /// (a large open plan) keeps every particle's path: past this bound the ancestry is
    /// dropped and the run answers with the filter's causal estimates, saying so.
    pub smoothing_max_nodes: usize,
    /// KLD-sampling.
    pub kld: KldConfig,
    /// Clustering.
    pub cluster: ClusterConfig,
    /// Recovery.
    pub recovery: RecoveryConfig,
    /// Floor-plan topology.
    pub topology: TopologyConfig,
    /// RF-assisted localisation (used only with a radio map and scans).
    pub rf: RfConfig,
    /// The absolute-heading measurement of steps that carry one (`enabled = false`
    /// ignores the column).
    pub heading: HeadingConfig,
    /// A learned map's transitions as a motion prior (used only with one,
    /// [`super::Tracker::set_transition_prior`]).
    pub transitions: TransitionPriorConfig,
}

impl Default for TrackerConfig {
    fn default() -> Self {
        Self {
            seed: 0,
            length_sigma: 0.15,
            dheading_sigma: 0.6f64.to_radians(),
            dz_sigma: 0.1,
            scale_sigma: 0.05,
            scale_walk_sigma: 0.0005,
            drift_sigma: 0.0,
            drift_walk_sigma: 0.0,
            start: None,
            start_position_sigma: 0.3,
            start_heading_sigma: 5f64.to_radians(),
            ambiguous_min_particles: 3000,
            smoothing: true,
            smoothing_lag: 10,
            smoothing_max_nodes: 1 << 26,
            kld: KldConfig::default(),
            cluster: ClusterConfig::default(),
            recovery: RecoveryConfig::default(),
            topology: TopologyConfig::default(),
            rf: RfConfig::default(),
            heading: HeadingConfig::default(),
            transitions: TransitionPriorConfig::default(),
        }
    }
}

impl TrackerConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) naming the first field out of its range (e.g.
    /// `length_sigma` outside [0, 2] m, `smoothing_max_nodes` below 1000, a `start` coordinate
    /// beyond ±10⁷ m), including the fields of `heading`, `rf`, `kld`, `cluster` and `topology`.
    pub fn validate(&self) -> Result<()> {
        crate::error::check_range("length_sigma", self.length_sigma, 0.0..=2.0, "metres")?;
        crate::error::check_range("dheading_sigma", self.dheading_sigma, 0.0..=1.0, "radians")?;
        crate::error::check_range("dz_sigma", self.dz_sigma, 0.001..=10.0, "metres")?;
        if self.smoothing_max_nodes < 1_000 {
            return Err(crate::error::Error::config(
                "smoothing_max_nodes",
                self.smoothing_max_nodes.to_string(),
                "must be at least 1000",
            ));
        }
        crate::error::check_range("scale_sigma", self.scale_sigma, 0.0..=0.3, "")?;
        crate::error::check_range("scale_walk_sigma", self.scale_walk_sigma, 0.0..=0.05, "")?;
        crate::error::check_range("drift_sigma", self.drift_sigma, 0.0..=0.1, "radians")?;
        crate::error::check_range(
            "drift_walk_sigma",
            self.drift_walk_sigma,
            0.0..=0.01,
            "radians",
        )?;
        crate::error::check_range(
            "start_position_sigma",
            self.start_position_sigma,
            0.0..=100.0,
            "metres",
        )?;
        crate::error::check_range(
            "start_heading_sigma",
            self.start_heading_sigma,
            0.0..=4.0,
            "radians",
        )?;
        if let Some(s) = self.start {
            for v in [s.x, s.y, s.heading.unwrap_or(0.0)] {
                crate::error::check_range("start", v, -1e7..=1e7, "")?;
            }
        }
        let r = &self.recovery;
        crate::error::check_range(
            "recovery.heading_increment",
            r.heading_increment,
            1e-4..=1.0,
            "radians",
        )?;
        crate::error::check_range(
            "recovery.heading_max",
            r.heading_max,
            0.0..=std::f64::consts::PI,
            "radians",
        )?;
        crate::error::check_range(
            "recovery.history_radius",
            r.history_radius,
            0.01..=100.0,
            "metres",
        )?;
        crate::error::check_range(
            "recovery.history_steps",
            r.history_steps as f64,
            0.0..=10_000.0,
            "",
        )?;
        crate::error::check_range(
            "recovery.history_attempts",
            r.history_attempts as f64,
            0.0..=20.0,
            "",
        )?;
        crate::error::check_range(
            "recovery.history_particles",
            r.history_particles as f64,
            1.0..=1e8,
            "",
        )?;
        crate::error::check_range(
            "ambiguous_min_particles",
            self.ambiguous_min_particles as f64,
            0.0..=1e8,
            "",
        )?;
        self.heading.validate()?;
        self.rf.validate()?;
        self.kld.validate()?;
        self.cluster.validate()?;
        self.topology.validate()
    }
}
