//! The configuration of [`super::FootSlam`]: every parameter, its unit and default.

use super::departure::DepartureConfig;
use super::resample::ResampleConfig;
use crate::error::Result;
use crate::geometry::Pose2;
use crate::model::{
    AxesConfig, FieldConfig, GpsConfig, HeadingConfig, LevelConfig, ScanPairConfig,
    StepMotionConfig,
};
use serde::{Deserialize, Serialize};

/// FootSLAM's disturbance correlation length for compass readings, metres
/// ([`HeadingConfig::correlation_length`], eq. 3 of the heading likelihood). FootSLAM adds
/// a whole walk's readings into the map's orientation, so a disturbance that persists over
/// a few metres would turn the map if each reading counted in full (a simulated walk with
/// 20° disturbances over 5 m: p95 16.8 m untempered, 6.5 m at 3 m). The tracker keeps
/// readings independent (its default 0): it reads them mostly to settle an unknown heading
/// within the first metres, where walls then take over, and on the real phone walks of the
/// ILC mall floor tempering placed fewer waypoints (185 against 195) no better.
pub const FOOTSLAM_HEADING_CORRELATION: f64 = 3.0;

/// FootSLAM's parameters; every default in one place.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FootSlamConfig {
    /// Number of particles `N_p`. Default 20,000.
    pub particles: usize,
    /// Seed of every random draw; equal seeds give equal results on any thread count.
    pub seed: u64,
    /// Hexagon circumradius `r`, metres. Default 0.5 m (the paper's value).
    pub hex_radius: f64,
    /// Dirichlet prior `α^e_h` per edge. Default 0.8 (the paper's value).
    pub alpha: f64,
    /// Apply the paper's direction correction to eq. (6) (sec. 3). Default true.
    pub direction_correction: bool,
    /// The walk's start pose (x, y metres, heading radians). Default (0, 0, 0).
    pub start: Pose2,
    /// The level of the walk's first floor: the walk's floors are numbered from it
    /// ([`crate::model::floor_levels`]). Default 0.
    pub start_level: i32,
    /// Spread (1σ per axis) of the start position about `start`, metres. Default 0 (the
    /// walk defines the frame); with GPS the first fix's accuracy.
    pub start_position_sigma: f64,
    /// Spread (1σ) of the start heading about `start.heading`, radians; π or more draws it
    /// uniformly. Default 0; with GPS uniform (the heading is not known).
    pub start_heading_sigma: f64,
    /// Dirichlet prior of edges that cross a building outline (`α_out`, see
    /// [`crate::map::edge_prior`]). Default 0.05.
    pub outline_alpha: f64,
    /// How well a building outline is known, metres: the outline fit counts a crossing only
    /// from this far inside to this far outside ([`crate::filter::outline_fit`]). Default 1.5 m.
    pub outline_margin: f64,
    /// Step error model.
    pub motion: StepMotionConfig,
    /// Resampling.
    pub resample: ResampleConfig,
    /// GPS likelihood (used when fixes are given).
    pub gps: GpsConfig,
    /// Absolute-heading likelihood (used for steps that carry a `heading`, unless
    /// `heading.enabled` is false). Default: see [`HeadingConfig`] (σ 20°, ε 0.2), with
    /// readings tempered over a 3 m disturbance correlation length
    /// ([`FOOTSLAM_HEADING_CORRELATION`]).
    pub heading: HeadingConfig,
    /// Floors from the steps' height changes: one hexagon map per floor
    /// ([`crate::model::floor_levels`]). Default: see [`LevelConfig`].
    pub levels: LevelConfig,
    /// WiFi scans as evidence of revisits (used for walks with scans, unless
    /// `wifi.enabled` is false). Default: see [`ScanPairConfig`].
    pub wifi: ScanPairConfig,
    /// The building's dominant directions as a soft prior on straight walking, learned
    /// per particle from the walk itself. Default: see [`AxesConfig`].
    pub axes: AxesConfig,
    /// The magnetic field over each step against each particle's own field map
    /// (MagSLAM), used when the steps carry the field. Default: see [`FieldConfig`].
    pub field: FieldConfig,
    /// The whole-walk answer: how many final paths are averaged, and which. Default: see
    /// [`SmoothingConfig`].
    pub smoothing: SmoothingConfig,
    /// The answer against dead reckoning, and when to trust dead reckoning instead
    /// ([`super::departure`]). Default: see [`DepartureConfig`].
    pub departure: DepartureConfig,
}

impl Default for FootSlamConfig {
    fn default() -> Self {
        Self {
            particles: 20_000,
            seed: 0,
            hex_radius: 0.5,
            alpha: 0.8,
            direction_correction: true,
            start: Pose2::default(),
            start_level: 0,
            start_position_sigma: 0.0,
            start_heading_sigma: 0.0,
            outline_alpha: 0.05,
            outline_margin: 1.5,
            motion: StepMotionConfig::default(),
            resample: ResampleConfig::default(),
            gps: GpsConfig::default(),
            heading: HeadingConfig {
                correlation_length: FOOTSLAM_HEADING_CORRELATION,
                ..HeadingConfig::default()
            },
            levels: LevelConfig::default(),
            wifi: ScanPairConfig::default(),
            axes: AxesConfig::default(),
            field: FieldConfig::default(),
            smoothing: SmoothingConfig::default(),
            departure: DepartureConfig::default(),
        }
    }
}

impl FootSlamConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) naming the first field out of its range: `particles`
    /// outside 1..=10⁸, `hex_radius` outside [0.05, 10] m, `alpha` outside (0, 1000],
    /// `outline_alpha` outside (0, `alpha`], a start or spread that is not finite,
    /// `resample.ess_threshold` outside [0, 1], or a field of a section that fails its own
    /// `validate` (`gps`, `motion`, `wifi`, …).
    pub fn validate(&self) -> Result<()> {
        if !(1..=100_000_000).contains(&self.particles) {
            return Err(crate::error::Error::config(
                "particles",
                self.particles.to_string(),
                "must be in 1..=100000000",
            ));
        }
        if !(self.hex_radius.is_finite() && (0.05..=10.0).contains(&self.hex_radius)) {
            return Err(crate::error::Error::config(
                "hex_radius",
                self.hex_radius.to_string(),
                "must be in [0.05, 10] metres",
            ));
        }
        if !(self.alpha.is_finite() && self.alpha > 0.0 && self.alpha <= 1000.0) {
            return Err(crate::error::Error::config(
                "alpha",
                self.alpha.to_string(),
                "must be in (0, 1000]",
            ));
        }
        let s = self.start;
        if !(s.x.is_finite() && s.y.is_finite() && s.heading.is_finite()) {
            return Err(crate::error::Error::config(
                "start",
                format!("{s:?}"),
                "must be finite",
            ));
        }
        for (field, v, hi) in [
            ("start_position_sigma", self.start_position_sigma, 10_000.0),
            ("start_heading_sigma", self.start_heading_sigma, 1000.0),
            ("outline_margin", self.outline_margin, 100.0),
        ] {
            if !(v.is_finite() && (0.0..=hi).contains(&v)) {
                return Err(crate::error::Error::config(
                    field,
                    v.to_string(),
                    "must be a finite number ≥ 0 (and not absurd)",
                ));
            }
        }
        if !(self.outline_alpha.is_finite()
            && self.outline_alpha > 0.0
            && self.outline_alpha <= self.alpha)
        {
            return Err(crate::error::Error::config(
                "outline_alpha",
                self.outline_alpha.to_string(),
                "must be in (0, alpha]",
            ));
        }
        self.gps.validate()?;
        self.heading.validate()?;
        self.levels.validate()?;
        self.wifi.validate()?;
        self.axes.validate()?;
        self.field.validate()?;
        self.smoothing.validate()?;
        self.departure.validate()?;
        let t = self.resample.ess_threshold;
        if !(t.is_finite() && (0.0..=1.0).contains(&t)) {
            return Err(crate::error::Error::config(
                "resample.ess_threshold",
                t.to_string(),
                "must be in [0, 1]",
            ));
        }
        self.motion.validate()
    }
}

/// How the whole-walk answer is made; every default in one place.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SmoothingConfig {
    /// Paths drawn from the final weights (at most the number of particles). 0: answer
    /// with the most probable particle's path alone. Default 256.
    pub draws: usize,
    /// Paths further than this from the most probable one (RMS over the walk, metres)
    /// belong to another mode and are left out of the mean. Default 2 m.
    pub mode_radius_m: f64,
}

impl Default for SmoothingConfig {
    fn default() -> Self {
        Self {
            draws: 256,
            mode_radius_m: 2.0,
        }
    }
}

impl SmoothingConfig {
    /// Checks every field; names the offending one.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) when `draws` is above 100 000 or `mode_radius_m` is
    /// outside (0, 10 000] m.
    pub fn validate(&self) -> crate::error::Result<()> {
        if self.draws > 100_000 {
            return Err(crate::error::Error::config(
                "smoothing.draws",
                self.draws,
                "must be at most 100000",
            ));
        }
        let r = self.mode_radius_m;
        if !(r.is_finite() && r > 0.0 && r <= 1e4) {
            return Err(crate::error::Error::config(
                "smoothing.mode_radius_m",
                r,
                "must be in (0, 10000] metres",
            ));
        }
        Ok(())
    }
}
