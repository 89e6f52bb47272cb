//! The magnetic field as evidence of revisits inside FootSLAM: each particle keeps its own
//! map of the field ([`FieldMap`], MagSLAM, Robertson et al., IPIN 2013) and is weighted by
//! how well each step's reading agrees with what that particle read before at the same
//! place.
//!
//! **The model.** A step's reading `y` (the field's magnitude and, where known, its
//! vertical part, [`crate::sensor::StepField`]) is taken at the particle's position, in
//! hexagon `h` of a grid of `cell_radius_m`. Where the particle read `n ≥ 1` times before,
//! with mean `ȳ_h`, the difference `δ = y − ȳ_h` is, if `h` is the same place,
//!
//! `δ ~ N(0, Σ_n)`,  `Σ_n = ½ S_near · (1 + 1/n)`                               (1)
//!
//! and, if the particle misplaced the walker (a different place with another field),
//!
//! `δ ~ N(0, Σ_f)`,  `Σ_f = S_far − S_near + ½ S_near · (1 + 1/n)`               (2)
//!
//! where `S_near` is the covariance of the difference of two readings one cell apart and
//! `S_far` that of two readings at unrelated places. A particle is weighted by the ratio,
//! robust to readings that agree with neither (a passing trolley, a phone held otherwise)
//! through an outlier share `η`, and tempered by `τ` because successive readings along a
//! walk are correlated:
//!
//! `ln w = τ · ln[(1 − η) · N(δ; 0, Σ_n) / N(δ; 0, Σ_f) + η]`                   (3)
//!
//! A hexagon without readings, or whose last reading is fewer than `min_gap_steps` old
//! (the particle's own reading of a moment ago, not a revisit), says nothing (`ln w = 0`);
//! then the reading joins the hexagon's mean either way.
//!
//! **Calibrated on the walk itself** ([`FieldEvidence::new`]). `S_near` comes from pairs of
//! the walk's own readings between half a cell and a cell diameter apart along the
//! dead-reckoned path, a few seconds apart (so that dead reckoning knows their distance),
//! widened by `revisit_factor` because a place revisited is read with the phone held and
//! facing otherwise; `S_far` is twice the covariance of the walk's readings about their median (two readings
//! of unrelated places). Both are robust (median absolute deviation, trimmed correlation).
//! Where the field does not vary more between places than within a cell (an outdoor walk,
//! a hall without steel), the evidence stays inactive and the filter ignores it.

use crate::geometry::{HexGrid, Pose2};
use crate::map::{FieldMap, level_key};
use crate::sensor::step::dead_reckon;
use crate::sensor::{Step, StepFields};
use serde::{Deserialize, Serialize};

/// Readings of a cell past which eq. (1)–(2) use their limit `n → ∞`.
const N_TABLE: usize = 32;
/// MAD to standard deviation for a normal distribution.
const MAD_TO_SD: f64 = 1.4826;
/// Differences beyond this many robust deviations are left out of a correlation.
const TRIM: f64 = 3.0;
/// Near pairs further apart in time than this do not calibrate (dead reckoning's distance
/// is then no longer sure to a fraction of a cell), seconds.
const NEAR_WINDOW_S: f64 = 10.0;

/// Settings of the magnetic-field term; every default in one place.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FieldConfig {
    /// Weight particles by the field over each step, when the steps carry it (`steps.csv`'s
    /// `field` column). Default true.
    pub enabled: bool,
    /// Use the field's vertical part beside its magnitude, where at least 90 % of the
    /// readings have one. Default true.
    pub use_vertical: bool,
    /// Circumradius of the field map's hexagons, metres. Default 1.
    pub cell_radius_m: f64,
    /// A hexagon read fewer than this many steps ago is not compared (eq. 3). Default 8.
    pub min_gap_steps: u16,
    /// `η` of eq. (3). Default 0.1.
    pub outlier_share: f64,
    /// `τ` of eq. (3). Default 0.25: on the museum routes of docs/footslam.md (3 seeds, with
    /// and without WiFi) 0.5 gained as much on average but collapsed the particles' ancestry
    /// more and once lost a route (p95 ratio 1.02); 0.25 did not.
    pub tempering: f64,
    /// The smallest standard deviation of a reading about its place's field, µT: a floor
    /// under the calibration (sensor noise, the phone held a little otherwise). Default 0.5.
    pub min_sd_ut: f64,
    /// How much more two readings of one place differ when it is revisited than when it is
    /// passed in one go (as a standard deviation, applied to `S_near`): the phone may be
    /// held another way and face another direction. Default 1: on the IPIN 2023 museum
    /// routes (docs/footslam.md) repetitions read a place up to 1.8 times further apart
    /// than successive steps do (an upper bound: the truth between surveyed points is
    /// interpolated), yet 1.8 gave a mean p95 ratio of 0.65 against 0.60 with 1; the
    /// tempering `τ` already widens eq. (3).
    pub revisit_factor: f64,
    /// Near pairs (and readings) needed to use the field at all. Default 30.
    pub min_calibration_pairs: usize,
    /// The field must vary between places by at least this multiple of its spread within a
    /// cell in one pass (in standard deviation, on either component) to be used.
    /// Default 1.5.
    pub min_contrast: f64,
}

impl Default for FieldConfig {
    fn default() -> Self {
        Self {
            enabled: true,
            use_vertical: true,
            cell_radius_m: 1.0,
            min_gap_steps: 8,
            outlier_share: 0.1,
            tempering: 0.25,
            min_sd_ut: 0.5,
            revisit_factor: 1.0,
            min_calibration_pairs: 30,
            min_contrast: 1.5,
        }
    }
}

impl FieldConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) for the first field that is not finite or is out of
    /// its range (e.g. `cell_radius_m` outside [0.1, 10] m, `tempering` outside [0, 1],
    /// `min_contrast` outside [1, 100]), with the range.
    pub fn validate(&self) -> crate::error::Result<()> {
        use crate::error::check_range;
        check_range("field.cell_radius_m", self.cell_radius_m, 0.1..=10.0, "m")?;
        check_range(
            "field.min_gap_steps",
            f64::from(self.min_gap_steps),
            0.0..=10_000.0,
            "",
        )?;
        check_range("field.outlier_share", self.outlier_share, 1e-6..=0.9, "")?;
        check_range("field.tempering", self.tempering, 0.0..=1.0, "")?;
        check_range("field.min_sd_ut", self.min_sd_ut, 0.01..=50.0, "µT")?;
        check_range("field.revisit_factor", self.revisit_factor, 1.0..=10.0, "")?;
        check_range(
            "field.min_calibration_pairs",
            self.min_calibration_pairs as f64,
            1.0..=1e6,
            "",
        )?;
        check_range("field.min_contrast", self.min_contrast, 1.0..=100.0, "")
    }
}

/// A symmetric 2×2 covariance as `[a, b, c]` for `[[a, b], [b, c]]`.
type Cov = [f64; 3];

/// The robust covariance of `values` (their first `dims` components, about zero).
fn robust_covariance(values: &[[f64; 2]], dims: usize, min_sd: f64) -> Cov {
    let sd = |d: usize| {
        let mut abs: Vec<f64> = values.iter().map(|v| v[d].abs()).collect();
        let mid = abs.len() / 2;
        (MAD_TO_SD * *abs.select_nth_unstable_by(mid, f64::total_cmp).1).max(min_sd)
    };
    let s0 = sd(0);
    if dims < 2 {
        return [s0 * s0, 0.0, 1.0];
    }
    let s1 = sd(1);
    let kept = values
        .iter()
        .filter(|v| v[0].abs() <= TRIM * s0 && v[1].abs() <= TRIM * s1);
    let (mut xx, mut xy, mut yy) = (0.0, 0.0, 0.0);
    for v in kept {
        xx += v[0] * v[0];
        xy += v[0] * v[1];
        yy += v[1] * v[1];
    }
    let rho = if xx > 0.0 && yy > 0.0 {
        (xy / (xx * yy).sqrt()).clamp(-0.95, 0.95)
    } else {
        0.0
    };
    [s0 * s0, rho * s0 * s1, s1 * s1]
}

/// `(inverse, ln det)` of a covariance.
fn invert(c: Cov) -> (Cov, f64) {
    let det = (c[0] * c[2] - c[1] * c[1]).max(1e-12);
    ([c[2] / det, -c[1] / det, c[0] / det], det.ln())
}

fn quadratic(inv: &Cov, d: [f64; 2]) -> f64 {
    inv[0] * d[0] * d[0] + 2.0 * inv[1] * d[0] * d[1] + inv[2] * d[1] * d[1]
}

/// What the walk's own readings say of its field (eq. 1–2's `S_near`, `S_far`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FieldCalibration {
    /// Components used: 1 (magnitude) or 2 (magnitude and vertical part).
    pub components: usize,
    /// Near pairs the calibration stands on.
    pub near_pairs: usize,
    /// Standard deviation of the difference of two readings one cell apart in one pass,
    /// per component, µT.
    pub passing_sd_ut: [f64; 2],
    /// The same on a revisit (`revisit_factor` times more): eq. (1)'s `S_near`, µT.
    pub near_sd_ut: [f64; 2],
    /// The same for two readings at unrelated places, µT.
    pub far_sd_ut: [f64; 2],
}

/// Why a walk's field readings weigh nothing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FieldUnused {
    /// `[field] enabled = false`.
    Disabled,
    /// Too few readings or near pairs to calibrate.
    TooFewReadings,
    /// The field varies between places hardly more than within a cell.
    NoContrast,
}

/// The precomputed eq. (1)–(3) for one walk.
#[derive(Debug, Clone)]
pub struct FieldLikelihood {
    grid: HexGrid,
    dims: usize,
    min_gap_steps: u16,
    outlier_share: f64,
    tempering: f64,
    /// Per `n − 1` (capped): the inverses and log determinants of `Σ_n`, `Σ_f`.
    table: Vec<(Cov, f64, Cov, f64)>,
}

impl FieldLikelihood {
    fn new(config: &FieldConfig, dims: usize, near: Cov, far: Cov) -> Self {
        let table = (1..=N_TABLE)
            .map(|n| {
                let grow = 0.5 * (1.0 + 1.0 / n as f64);
                let same = near.map(|v| v * grow);
                let mut other = [
                    far[0] - near[0] + same[0],
                    far[1] - near[1] + same[1],
                    far[2] - near[2] + same[2],
                ];
                if other[0] * other[2] - other[1] * other[1] <= 0.0 {
                    other[1] = 0.0;
                }
                let (a, la) = invert(same);
                let (b, lb) = invert(other);
                (a, la, b, lb)
            })
            .collect();
        Self {
            grid: HexGrid::new(config.cell_radius_m),
            dims,
            min_gap_steps: config.min_gap_steps,
            outlier_share: config.outlier_share,
            tempering: config.tempering,
            table,
        }
    }

    /// Components weighed: 1 (magnitude) or 2 (magnitude and vertical part).
    #[must_use]
    pub fn components(&self) -> usize {
        self.dims
    }

    /// Circumradius of the field map's hexagons, metres.
    #[must_use]
    pub fn cell_radius(&self) -> f64 {
        self.grid.radius()
    }

    /// Eq. (3) for reading `y` against a hexagon's `n ≥ 1` readings of mean `mean`.
    #[must_use]
    pub fn log_ratio(&self, y: [f32; 2], n: u16, mean: [f32; 2]) -> f64 {
        let (a, la, b, lb) = &self.table[usize::from(n.max(1)).min(N_TABLE) - 1];
        let mut d = [f64::from(y[0] - mean[0]), 0.0];
        if self.dims == 2 {
            d[1] = f64::from(y[1] - mean[1]);
        }
        let log_density_ratio = -0.5 * (quadratic(a, d) + la) + 0.5 * (quadratic(b, d) + lb);
        let eta = self.outlier_share;
        self.tempering * ((1.0 - eta) * log_density_ratio.exp() + eta).ln()
    }

    /// Weighs reading `y` of step `k`, taken at `pose` on `level`, against the particle's
    /// field map (eq. 3), then adds it to the map.
    pub fn weigh_and_learn(
        &self,
        map: &mut FieldMap,
        pose: &Pose2,
        level: i32,
        k: u32,
        y: [f32; 2],
    ) -> f64 {
        let key = level_key(level, self.grid.hex_at(pose.x, pose.y));
        let before = map.observe(key, k, y, self.dims);
        if before.n == 0 || before.steps_since(k) < self.min_gap_steps {
            return 0.0;
        }
        self.log_ratio(y, before.n, before.mean)
    }
}

/// A walk's field readings, ready for the filter: per step the reading, the calibration
/// and the likelihood, or why they weigh nothing.
#[derive(Debug, Clone)]
pub struct FieldEvidence {
    readings: Vec<Option<[f32; 2]>>,
    /// Steps with a reading.
    pub observed: usize,
    /// The calibration, when there were enough readings.
    pub calibration: Option<FieldCalibration>,
    /// The likelihood, when the field is used; else why not.
    pub model: Result<FieldLikelihood, FieldUnused>,
}

impl FieldEvidence {
    /// Calibrates the field term on the walk's own readings (see the module
    /// documentation); `fields` holds one entry per step of `steps`.
    pub fn new(config: &FieldConfig, steps: &[Step], fields: &StepFields) -> Self {
        let observed = fields.observed();
        let dims = if config.use_vertical && fields.with_vertical() * 10 >= observed * 9 {
            2
        } else {
            1
        };
        let readings: Vec<Option<[f32; 2]>> = (0..steps.len())
            .map(|i| {
                let f = fields.get(i)?;
                let v = if dims == 2 { f.vertical? } else { 0.0 };
                Some([f.magnitude as f32, v as f32])
            })
            .collect();
        let unused = |why, calibration| Self {
            readings: Vec::new(),
            observed,
            calibration,
            model: Err(why),
        };
        if !config.enabled {
            return unused(FieldUnused::Disabled, None);
        }
        let path = dead_reckon(steps, Pose2::default());
        let r = config.cell_radius_m;
        let mut near = Vec::new();
        for i in 0..readings.len() {
            let Some(a) = readings[i] else { continue };
            for j in i + 1..readings.len() {
                if steps[j].t - steps[i].t > NEAR_WINDOW_S {
                    break;
                }
                let Some(b) = readings[j] else { continue };
                let d = (path[j].x - path[i].x).hypot(path[j].y - path[i].y);
                if (0.5 * r..=2.0 * r).contains(&d) {
                    near.push([f64::from(a[0] - b[0]), f64::from(a[1] - b[1])]);
                }
            }
        }
        let values: Vec<[f64; 2]> = readings
            .iter()
            .flatten()
            .map(|v| v.map(f64::from))
            .collect();
        if near.len() < config.min_calibration_pairs || values.len() < config.min_calibration_pairs
        {
            return unused(FieldUnused::TooFewReadings, None);
        }
        let median = |d: usize| {
            let mut v: Vec<f64> = values.iter().map(|x| x[d]).collect();
            let mid = v.len() / 2;
            *v.select_nth_unstable_by(mid, f64::total_cmp).1
        };
        let centre = [median(0), median(1)];
        let deviations: Vec<[f64; 2]> = values
            .iter()
            .map(|v| [v[0] - centre[0], v[1] - centre[1]])
            .collect();
        // A pair difference's floor is √2 times a reading's.
        let passing = robust_covariance(&near, dims, config.min_sd_ut * std::f64::consts::SQRT_2);
        let near_cov = passing.map(|v| v * config.revisit_factor.powi(2));
        let spread = robust_covariance(&deviations, dims, config.min_sd_ut);
        let far_cov = spread.map(|v| 2.0 * v);
        let sd = |c: &Cov| [c[0].sqrt(), if dims == 2 { c[2].sqrt() } else { 0.0 }];
        let calibration = FieldCalibration {
            components: dims,
            near_pairs: near.len(),
            passing_sd_ut: sd(&passing),
            near_sd_ut: sd(&near_cov),
            far_sd_ut: sd(&far_cov),
        };
        let contrast = (0..dims)
            .map(|d| calibration.far_sd_ut[d] / calibration.passing_sd_ut[d])
            .fold(0.0, f64::max);
        if contrast < config.min_contrast {
            return unused(FieldUnused::NoContrast, Some(calibration));
        }
        // `S_far − S_near` must stay a covariance: the field varies more between places.
        let far_cov = [
            far_cov[0].max(near_cov[0] * 1.01),
            far_cov[1],
            far_cov[2].max(near_cov[2] * 1.01),
        ];
        Self {
            readings,
            observed,
            calibration: Some(calibration),
            model: Ok(FieldLikelihood::new(config, dims, near_cov, far_cov)),
        }
    }

    /// The likelihood, when the readings are used.
    #[must_use]
    pub fn reading_model(&self) -> Option<&FieldLikelihood> {
        self.model.as_ref().ok()
    }

    /// Whether the filter weighs the readings.
    #[must_use]
    pub fn active(&self) -> bool {
        self.model.is_ok()
    }

    /// The reading of step `i` and the likelihood to weigh it with, when used.
    #[must_use]
    pub fn reading(&self, i: usize) -> Option<(&FieldLikelihood, [f32; 2])> {
        let model = self.model.as_ref().ok()?;
        Some((model, self.readings.get(i).copied().flatten()?))
    }
}

#[cfg(test)]
mod tests;
