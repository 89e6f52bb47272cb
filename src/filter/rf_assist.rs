//! RF-assisted localisation with a radio map (Woodman & Harle 2009, sec. 5): a prior region
//! from the first scan, then a WiFi measurement at every step.
//!
//! * **prior** — `R_prior = ∪ Cell_i | ndist(z_0, c_i) < ε` (eq. 2): particles are drawn only
//!   there ([`super::Tracker::new_in_region`]), KLD-sized;
//! * **containment** (the paper's choice) — the region `R_t` of the latest scan (eq. 12)
//!   weights particles 1 inside and `outside_weight` outside (eq. 13 with 0), judged where
//!   each particle was when the scan was taken ([`super::RfTracker`]);
//! * **probabilistic** (the paper's alternative) — `p(z_t | c_i)` of the cell a particle
//!   stands in (eq. 14, [`crate::model::wifi_likelihood`]; tempered by the number of access
//!   points), relative to the likeliest cell and floored at `likelihood_floor`.
//!
//! `ndist` is the paper's distance divided by the number `k` of access points the cell hears,
//! or by `√k` ([`Normalisation`]; the default where the map holds a threshold calibrated for
//! it): one threshold then misses the walker's cell equally often whatever `k` is.
//!
//! Cells without scans (not surveyed) and places in no cell are always inside: what the map
//! does not know cannot rule a place out. A measurement no particle survives is ignored,
//! and a global re-initialisation draws its prior in the latest scan's `R_prior`.

use crate::error::{Error, Result};
use crate::map::{CellField, CellRaster, FloorTopology, RadioMap};
use crate::model::derived_epsilon::derive_epsilon;
use crate::model::radio_interpolation::InterpolationConfig;
use crate::model::radio_pathloss::PathLossConfig;
use crate::model::wifi_distance::{Fingerprints, Normalisation};
use crate::model::wifi_evidence::{
    EvidenceCalibration, EvidenceConfig, EvidenceSource, RadioEvidence,
};
use crate::model::wifi_evidence_interpolated::{InterpolatedCalibration, InterpolatedEvidence};
use crate::model::wifi_evidence_pathloss::{PathLossCalibration, PathLossEvidence};
use crate::model::wifi_likelihood::{HistogramLikelihood, LikelihoodConfig};
use crate::sensor::WifiScan;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The paper's region threshold for its distance, dBm (chosen on its building and hardware;
/// a radio map's own calibration, or a threshold derived from it, fits other buildings
/// better). Not a default: give it with `rf.epsilon` to reproduce the paper.
pub const PAPER_EPSILON: f64 = 9.5;

/// How WiFi weights the particles after the prior.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RfMode {
    /// Containment regions at every step (eqs. 12–13).
    Containment,
    /// The histogram likelihood of each scan (eq. 14).
    Probabilistic,
    /// The prior region only.
    PriorOnly,
    /// Radio evidence on a sparse map ([`crate::model::wifi_evidence`], eq. 1): each scan
    /// weighs every place by how much more likely it is there than elsewhere, calibrated on
    /// the map; places the map does not know are neither favoured nor excluded, and the walk
    /// starts anywhere on the plan. A map too sparse to calibrate it falls back to
    /// [`RfMode::Containment`] and says so.
    Evidence,
    /// The default: [`RfMode::Evidence`] on a map that covers less than
    /// `evidence.auto_below_coverage` of its cells (the ordinary walks' survey), else
    /// [`RfMode::Containment`] (the paper's complete survey, where regions rule out the
    /// most).
    #[default]
    Auto,
}

impl RfMode {
    /// Its name on the command line: `auto`, `evidence`, `containment`, `probabilistic` or
    /// `prior-only`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            RfMode::Containment => "containment",
            RfMode::Probabilistic => "probabilistic",
            RfMode::PriorOnly => "prior-only",
            RfMode::Evidence => "evidence",
            RfMode::Auto => "auto",
        }
    }

    /// The mode [`RfMode::name`] names (`prior_only` too); `None` for any other text.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        [
            RfMode::Auto,
            RfMode::Evidence,
            RfMode::Containment,
            RfMode::Probabilistic,
            RfMode::PriorOnly,
        ]
        .into_iter()
        .find(|m| m.name() == name || m.name().replace('-', "_") == name)
    }
}

/// RF-assisted localisation's parameters; every default in one place.
///
/// | field              | default  | meaning                                                 |
/// |--------------------|----------|---------------------------------------------------------|
/// | `mode`             | auto     | auto (evidence on a map covering less than `evidence.auto_below_coverage` of its cells, else containment), evidence (calibrated likelihood ratios on a sparse map; containment where the map cannot calibrate it), containment (eqs. 12–13), probabilistic (eq. 14) or prior only |
/// | `distance`         | none     | `ndist`'s divisor: `paper` (`k`, eqs. 8, 11) or `sqrt` (`√k`); none = `sqrt` where the map is calibrated for it, else `paper` |
/// | `epsilon`          | none     | region threshold on `ndist` (eqs. 2, 12): none = the map's calibrated `ε` for the distance, else derived from the map's histograms |
/// | `epsilon_miss`     | 0.001    | share of a walker's scans a derived `ε` may leave outside their own cell |
/// | `missing_rssi`     | −96 dBm  | fill for missing readings (the receiver's floor)         |
/// | `outside_weight`   | 0        | containment weight outside `R_t` (eq. 13: 0)             |
/// | `likelihood_floor` | 1e-6     | probabilistic: least weight relative to the likeliest cell |
/// | `min_scans`        | 1        | cells with fewer scans are unknown (always inside)       |
/// | `max_scan_age`     | 5 s      | a scan older than this at a step is not used             |
/// | `every_step`       | false    | apply the latest scan at every step where the particles are then, or (false) once, where they were at the scan's time |
/// | `raster`           | 0.25 m   | grid of the point-to-cell lookup                         |
/// | `likelihood`       | see [`LikelihoodConfig`] | eq. 14's histogram smoothing              |
/// | `evidence`         | see [`EvidenceConfig`] | the evidence mode's calibration              |
/// | `interpolation`    | see [`InterpolationConfig`] | the interpolated map the evidence reads (`evidence.source = "interpolated"`) |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RfConfig {
    /// Measurement after the prior.
    pub mode: RfMode,
    /// What the scan-to-cell distance is divided by ([`Normalisation`]); `None` = `√k`
    /// where the radio map holds a threshold calibrated for it (`footslam survey` measures
    /// one), else the paper's `k`.
    pub distance: Option<Normalisation>,
    /// Region threshold `ε` on the normalised distance, dBm; `None` = the radio map's own
    /// calibration for the distance, else one derived from the map's histograms
    /// ([`derive_epsilon`]).
    pub epsilon: Option<f64>,
    /// For an `ε` derived from the map: the share of a walker's scans whose own cell may
    /// fall outside the region (the survey's calibration uses the same miss rate).
    pub epsilon_miss: f64,
    /// Fill for missing readings, dBm.
    pub missing_rssi: f64,
    /// Containment: weight of a particle outside the region (0 = eq. 13).
    pub outside_weight: f64,
    /// Probabilistic: least weight of a cell relative to the likeliest.
    pub likelihood_floor: f64,
    /// Cells with fewer scans are unknown.
    pub min_scans: u32,
    /// Oldest usable scan at a step, seconds.
    pub max_scan_age: f64,
    /// Apply the latest scan's measurement at every step until the next scan, at the
    /// particles' places then (eq. 12 read literally: "the last WiFi scan to be completed
    /// prior to the completion of the step"); false: once, at the first step after it, at
    /// each particle's place at the scan's time ([`super::RfTracker`]) — a reused scan judges
    /// the walker up to a few metres from where it was taken.
    pub every_step: bool,
    /// Side of the point-to-cell grid, metres.
    pub raster: f64,
    /// The histogram likelihood (eq. 14).
    pub likelihood: LikelihoodConfig,
    /// The radio evidence ([`RfMode::Evidence`]).
    pub evidence: EvidenceConfig,
    /// The interpolated radio map the evidence reads ([`EvidenceSource::Interpolated`]).
    pub interpolation: InterpolationConfig,
    /// The path-loss model the evidence reads ([`EvidenceSource::PathLoss`]).
    pub pathloss: PathLossConfig,
}

impl Default for RfConfig {
    fn default() -> Self {
        Self {
            mode: RfMode::Auto,
            distance: None,
            epsilon: None,
            epsilon_miss: 0.001,
            missing_rssi: -96.0,
            outside_weight: 0.0,
            likelihood_floor: 1e-6,
            min_scans: 1,
            max_scan_age: 5.0,
            every_step: false,
            raster: 0.25,
            likelihood: LikelihoodConfig::default(),
            evidence: EvidenceConfig::default(),
            interpolation: InterpolationConfig::default(),
            pathloss: PathLossConfig::default(),
        }
    }
}

impl RfConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] naming the first field out of its range (e.g. `epsilon` outside
    /// [0.01, 200] dBm, `missing_rssi` outside [−150, −20] dBm, `raster` outside [0.05, 5] m),
    /// including the fields of `evidence` ([`EvidenceConfig::validate`]) and `likelihood`.
    pub fn validate(&self) -> Result<()> {
        if let Some(e) = self.epsilon {
            crate::error::check_range("rf.epsilon", e, 0.01..=200.0, "dBm")?;
        }
        crate::error::check_range("rf.epsilon_miss", self.epsilon_miss, 0.0..=0.5, "")?;
        crate::error::check_range("rf.missing_rssi", self.missing_rssi, -150.0..=-20.0, "dBm")?;
        crate::error::check_range("rf.outside_weight", self.outside_weight, 0.0..=1.0, "")?;
        crate::error::check_range("rf.likelihood_floor", self.likelihood_floor, 0.0..=1.0, "")?;
        crate::error::check_range(
            "rf.max_scan_age",
            self.max_scan_age,
            0.0..=3600.0,
            "seconds",
        )?;
        crate::error::check_range("rf.raster", self.raster, 0.05..=5.0, "metres")?;
        self.evidence.validate()?;
        self.interpolation.validate()?;
        self.pathloss.validate()?;
        crate::error::check_range(
            "rf.likelihood.kernel_sigma",
            self.likelihood.kernel_sigma,
            0.1..=50.0,
            "dB",
        )?;
        crate::error::check_range(
            "rf.likelihood.outlier",
            self.likelihood.outlier,
            0.0..=1.0,
            "",
        )?;
        match self.likelihood.exponent {
            Some(e) => crate::error::check_range("rf.likelihood.exponent", e, 0.0..=1.0, ""),
            None => Ok(()),
        }
    }
}

/// The radio evidence a localiser calibrated.
#[derive(Debug, Clone)]
enum Evidence {
    Ndist(RadioEvidence),
    Interpolated(Box<InterpolatedEvidence>),
    PathLoss(Box<PathLossEvidence>),
    /// Both on the cells in reach of the survey (marked), the path-loss model alone on the
    /// others.
    Combined(RadioEvidence, Box<PathLossEvidence>),
}

/// What the radio evidence's calibration found, by what it compares a scan with.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "source", rename_all = "snake_case")]
pub enum EvidenceReport {
    /// The nearest surveyed cell's fingerprint ([`EvidenceSource::Ndist`]).
    Ndist(EvidenceCalibration),
    /// The interpolated map ([`EvidenceSource::Interpolated`]).
    Interpolated(InterpolatedCalibration),
    /// The path-loss model ([`EvidenceSource::PathLoss`]).
    #[serde(rename = "pathloss")]
    PathLoss(PathLossCalibration),
    /// `ndist` and the path-loss model in reach of the survey, the path-loss model beyond
    /// ([`EvidenceSource::Combined`]).
    Combined {
        /// The `ndist` evidence's calibration.
        ndist: EvidenceCalibration,
        /// The path-loss evidence's calibration.
        pathloss: PathLossCalibration,
    },
}

/// The combined evidence's `ln Λ` per cell: `near + far` on the cells in reach of the
/// survey (`near` judged), `far` (the path-loss model's) on the others.
fn combine(near: &[Option<f32>], far: &[f32]) -> Vec<f32> {
    near.iter()
        .zip(far)
        .map(|(&n, &f)| n.map_or(f, |n| n + f))
        .collect()
}

/// Where a localiser's region threshold `ε` came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EpsilonSource {
    /// The configuration (`rf.epsilon`, `--rf-epsilon`).
    Given,
    /// The radio map's own calibration (`footslam survey` writes one).
    Calibrated,
    /// Derived from the radio map's histograms ([`derive_epsilon`]): a map without a
    /// calibration, e.g. another tool's.
    Derived,
}

impl EpsilonSource {
    /// The name used in summaries.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            EpsilonSource::Given => "given",
            EpsilonSource::Calibrated => "the map's calibration",
            EpsilonSource::Derived => "derived from the map's histograms",
        }
    }
}

/// A radio map made ready for localisation on a plan: its cells rasterised, their
/// fingerprints and histograms.
#[derive(Debug, Clone)]
pub struct RfLocaliser {
    config: RfConfig,
    distance: Normalisation,
    epsilon: f64,
    epsilon_source: EpsilonSource,
    raster: Arc<CellRaster>,
    prints: Fingerprints,
    /// The histograms' likelihood, built for [`RfMode::Probabilistic`] only.
    likelihood: Option<HistogramLikelihood>,
    /// The radio evidence, built for [`RfMode::Evidence`] only.
    evidence: Option<Evidence>,
    /// Why the evidence mode asked for fell back to containment regions.
    fallback: Option<String>,
}

impl RfLocaliser {
    /// Prepares `map` (cells in the plan's local frame) for tracking on `topology`.
    ///
    /// # Errors
    ///
    /// - [`Error::Config`] when `config` fails [`RfConfig::validate`], or (as `rf.epsilon`) when
    ///   none is given, the map carries no calibrated threshold for the distance and none can be
    ///   derived (no cell holds two scans).
    /// - As [`CellRaster::on_plan`]: [`Error::Mismatch`] when no cell of the map lies on
    ///   `topology`'s plan, [`Error::TooLarge`] for too fine a `raster`.
    /// - [`Error::NotEnough`] when the map holds no access point readings.
    ///
    /// In evidence mode a map too sparsely surveyed to calibrate the evidence is no error: the
    /// localiser falls back to containment and says why.
    pub fn new(map: &RadioMap, topology: &FloorTopology, config: &RfConfig) -> Result<Self> {
        config.validate()?;
        let (distance, epsilon, epsilon_source) = threshold(map, config)?;
        let raster = CellRaster::on_plan(map, topology, config.raster)?;
        let prints = Fingerprints::new(map, config.missing_rssi, config.min_scans, distance);
        if prints.access_points() == 0 {
            return Err(Error::not_enough(
                "the radio map has no access point readings",
                "survey the building first",
            ));
        }
        let (mut config, mut fallback, mut evidence) = (*config, None, None);
        if config.mode == RfMode::Auto {
            let known = (0..map.cells.len()).filter(|&c| prints.is_known(c)).count();
            let coverage = known as f64 / map.cells.len().max(1) as f64;
            config.mode = if coverage < config.evidence.auto_below_coverage {
                RfMode::Evidence
            } else {
                RfMode::Containment
            };
        }
        if config.mode == RfMode::Evidence {
            let calibrated = match config.evidence.source {
                EvidenceSource::Ndist => {
                    RadioEvidence::calibrate(map, &prints, &raster, &config.evidence)
                        .map(Evidence::Ndist)
                }
                EvidenceSource::Interpolated => InterpolatedEvidence::calibrate(
                    map,
                    (config.missing_rssi, config.min_scans),
                    &config.interpolation,
                    &config.evidence,
                )
                .map(|e| Evidence::Interpolated(Box::new(e))),
                EvidenceSource::PathLoss => {
                    PathLossEvidence::calibrate(map, &config.pathloss, &config.evidence)
                        .map(|e| Evidence::PathLoss(Box::new(e)))
                }
                EvidenceSource::Combined => {
                    RadioEvidence::calibrate(map, &prints, &raster, &config.evidence)
                        // The nearest fingerprints alone where the path-loss model cannot be
                        // calibrated (a map this small barely reaches beyond its survey); the
                        // report's `source` says which.
                        .and_then(|nd| {
                            match PathLossEvidence::calibrate(
                                map,
                                &config.pathloss,
                                &config.evidence,
                            ) {
                                Ok(pl) => Ok(Evidence::Combined(nd, Box::new(pl))),
                                Err(Error::NotEnough { .. }) => Ok(Evidence::Ndist(nd)),
                                Err(e) => Err(e),
                            }
                        })
                }
            };
            match calibrated {
                Ok(e) => evidence = Some(e),
                Err(Error::NotEnough { problem, .. }) => {
                    fallback = Some(problem);
                    config.mode = RfMode::Containment;
                }
                Err(e) => return Err(e),
            }
        }
        debug_assert_ne!(config.mode, RfMode::Auto);
        Ok(Self {
            config,
            distance,
            epsilon,
            epsilon_source,
            raster: Arc::new(raster),
            prints,
            likelihood: (config.mode == RfMode::Probabilistic)
                .then(|| HistogramLikelihood::new(map, &config.likelihood, config.min_scans)),
            evidence,
            fallback,
        })
    }

    /// Why the evidence mode fell back to containment regions (the mode in use is then
    /// [`RfMode::Containment`]), if it did.
    #[must_use]
    pub fn fallback(&self) -> Option<&str> {
        self.fallback.as_deref()
    }

    /// The radio evidence's calibration ([`RfMode::Evidence`] only).
    #[must_use]
    pub fn evidence(&self) -> Option<EvidenceReport> {
        self.evidence.as_ref().map(|e| match e {
            Evidence::Ndist(e) => EvidenceReport::Ndist(e.calibration().clone()),
            Evidence::Interpolated(e) => EvidenceReport::Interpolated(e.calibration().clone()),
            Evidence::PathLoss(e) => EvidenceReport::PathLoss(e.calibration().clone()),
            Evidence::Combined(nd, pl) => EvidenceReport::Combined {
                ndist: nd.calibration().clone(),
                pathloss: pl.calibration().clone(),
            },
        })
    }

    /// The configuration, with the mode in use (never [`RfMode::Auto`]).
    #[must_use]
    pub fn config(&self) -> &RfConfig {
        &self.config
    }

    /// The region threshold in use, dBm.
    #[must_use]
    pub fn epsilon(&self) -> f64 {
        self.epsilon
    }

    /// Where the threshold in use came from.
    #[must_use]
    pub fn epsilon_source(&self) -> EpsilonSource {
        self.epsilon_source
    }

    /// The distance's divisor in use.
    #[must_use]
    pub fn distance(&self) -> Normalisation {
        self.distance
    }

    /// `ndist(z, c_i)` of `scan` to every cell with the distance in use (eqs. 2–11); `None`
    /// for unknown cells.
    #[must_use]
    pub fn ndist(&self, scan: &WifiScan) -> Vec<Option<f64>> {
        self.prints.ndist(scan)
    }

    /// Whether each cell is in the scan's region (eqs. 2, 12); unknown cells are.
    #[must_use]
    pub fn in_region(&self, scan: &WifiScan) -> Vec<bool> {
        self.ndist(scan)
            .into_iter()
            .map(|d| d.is_none_or(|d| d < self.epsilon))
            .collect()
    }

    /// What `scan` says, from one set of distances: its region `R_prior` as a prior (eq. 2;
    /// 0 inside, −∞ outside), and its measurement for the configured mode — the containment
    /// region's log-weights (eq. 13) or the cells' relative log-likelihoods (eq. 14); `None`
    /// for [`RfMode::PriorOnly`].
    pub fn scan_fields(&self, scan: &WifiScan) -> (CellField, Option<CellField>) {
        if let Some(evidence) = &self.evidence {
            // Every place stays possible; the evidence weighs them. A re-initialisation
            // draws where the scan does not speak against the place (at least the
            // likeliest cells).
            let ratios = match evidence {
                Evidence::Ndist(e) => e.log_ratios(&self.ndist(scan)),
                Evidence::Interpolated(e) => e.log_ratios(scan),
                Evidence::PathLoss(e) => e.log_ratios(scan),
                Evidence::Combined(nd, pl) => combine(
                    &nd.judged_log_ratios(&self.ndist(scan)),
                    &pl.log_ratios(scan),
                ),
            };
            let best = ratios.iter().copied().fold(f32::NEG_INFINITY, f32::max);
            let bar = best.min(0.0);
            let region = ratios
                .iter()
                .map(|&r| if r >= bar { 0.0 } else { f32::NEG_INFINITY })
                .collect();
            return (
                CellField::new(self.raster.clone(), region, 0.0),
                Some(self.field(ratios)),
            );
        }
        let inside = self.in_region(scan);
        let region = |outside: f32| {
            self.field(
                inside
                    .iter()
                    .map(|&i| if i { 0.0 } else { outside })
                    .collect(),
            )
        };
        let measurement = match (self.config.mode, &self.likelihood) {
            (RfMode::Containment, _) => Some(region(self.config.outside_weight.ln() as f32)),
            (RfMode::Probabilistic, Some(likelihood)) => {
                let ll = likelihood.log_likelihood(scan);
                let best = ll
                    .iter()
                    .flatten()
                    .copied()
                    .fold(f64::NEG_INFINITY, f64::max);
                let floor = self.config.likelihood_floor.ln();
                Some(
                    self.field(
                        ll.into_iter()
                            .map(|l| l.map_or(0.0, |l| (l - best).max(floor) as f32))
                            .collect(),
                    ),
                )
            }
            _ => None,
        };
        (region(f32::NEG_INFINITY), measurement)
    }

    fn field(&self, values: Vec<f32>) -> CellField {
        debug_assert_eq!(values.len(), self.raster.cells());
        CellField::new(self.raster.clone(), values, 0.0)
    }
}

/// The distance and threshold `config` asks for on `map`, and where the threshold came from:
/// as given, else the map's calibration for the distance, else derived from the map's own
/// histograms ([`derive_epsilon`]). With no distance given: `√k` unless the map is calibrated
/// for the paper's distance only. A map whose threshold can be neither read nor derived (no
/// cell with two scans) is an error that names the way out.
fn threshold(map: &RadioMap, config: &RfConfig) -> Result<(Normalisation, f64, EpsilonSource)> {
    let distance =
        config
            .distance
            .unwrap_or(if map.epsilon.is_some() && map.epsilon_sqrt.is_none() {
                Normalisation::Paper
            } else {
                Normalisation::Sqrt
            });
    if let Some(e) = config.epsilon {
        return Ok((distance, e, EpsilonSource::Given));
    }
    if let Some(e) = distance.epsilon_of(map) {
        return Ok((distance, e, EpsilonSource::Calibrated));
    }
    let derived = derive_epsilon(
        map,
        distance,
        config.missing_rssi,
        config.epsilon_miss,
        config.min_scans,
    )
    .ok_or(crate::error::Error::config("rf.epsilon", "none", "the radio map carries no calibrated threshold and none can be derived from it (no cell holds two scans to show how readings spread): give one with --rf-epsilon (rf.epsilon), e.g. the paper's 9.5 dBm with --rf-distance paper, or survey the building with `footslam survey`, which calibrates it"))?;
    Ok((distance, derived, EpsilonSource::Derived))
}

#[cfg(test)]
mod tests {
    #[test]
    fn combined_evidence_adds_both_in_reach_and_keeps_the_path_loss_beyond() {
        let near = [Some(0.5), Some(-1.0), None, None];
        let far = [0.25, 0.25, -0.5, 1.0];
        assert_eq!(super::combine(&near, &far), vec![0.75, -0.75, -0.5, 1.0]);
    }
}
