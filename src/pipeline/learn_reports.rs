//! What one learned walk reports of its whole-walk answer, the building's axes and the
//! magnetic field: one
//! typed report each, which `summary.json` (the command line) and the Python package's
//! summary both serialise, so the two faces cannot drift apart.

use super::learn_walks::WalkRun;
use super::quality::{Quality, QualityConfig, learn_quality};
use crate::model::{FieldCalibration, FieldUnused};
use serde::Serialize;

/// The whole-walk answer ([`crate::filter::SmoothingConfig`]): how many final paths it
/// averages and how far they spread.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SmoothingReport {
    /// Distinct final paths drawn.
    pub distinct_paths: usize,
    /// Those near the most probable path, averaged into the answer.
    pub averaged_paths: usize,
    /// Median per-step spread of the averaged paths about their mean, metres (0 where the
    /// answer is dead reckoning).
    pub spread_median_m: f64,
    /// Largest per-step spread, metres.
    pub spread_max_m: f64,
}

/// What the walk's turns said of the building's axes ([`crate::model::building_axes`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AxesReport {
    /// Whether the prior weighed the straight steps (`[axes] enabled = true` and the turns
    /// show axes).
    pub used: bool,
    /// Whether the walk's turns show dominant directions (eq. 4 of the model), used or not.
    pub shows_axes: bool,
    /// Turns between successive straight stretches that were tested.
    pub turns: usize,
    /// Their mean `cos 4Δ`: 1 when every turn is a multiple of 90°, about 0 for turns at
    /// any angle.
    pub alignment: f64,
    /// Their mean `cos 8Δ`, for walls that also run at 45°.
    pub diagonal_alignment: f64,
    /// The dominant directions: 4, 8 (with the diagonals) or 0 (none).
    pub directions: u8,
    /// Metres walked in straight stretches.
    pub straight_m: f64,
    /// Straight steps the axes weighed.
    pub steps_weighed: usize,
}

/// What the steps' magnetic field readings did ([`crate::model::magnetic_field`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FieldReport {
    /// Steps with a reading.
    pub steps_with_field: usize,
    /// Steps whose reading weighed the particles (0 when unused).
    pub steps_weighed: usize,
    /// What the walk's own readings said of the field, when there were enough of them.
    pub calibration: Option<FieldCalibration>,
    /// Why the readings weighed nothing, when they did not.
    pub unused: Option<FieldUnused>,
}

impl WalkRun {
    /// Whether the start heading is tied to north (given, configured, from GPS fixes or
    /// from a compass), so that the learned map's y axis points north; `assumed` and
    /// `unknown` leave the map turned by the walker's first heading.
    #[must_use]
    pub fn heading_is_absolute(&self) -> bool {
        matches!(
            self.start_source,
            "gps fixes" | "compass" | "given" | "config"
        )
    }

    /// The report of the magnetic field, when the steps carried it.
    #[must_use]
    pub fn field_report(&self) -> Option<FieldReport> {
        let e = self.field.as_ref()?;
        Some(FieldReport {
            steps_with_field: e.observed,
            steps_weighed: self.filter.field_steps(),
            calibration: e.calibration.clone(),
            unused: e.model.as_ref().err().copied(),
        })
    }

    /// The walk's verdict ([`learn_quality`]): its answer against dead reckoning and how far
    /// its final paths disagree.
    #[must_use]
    pub fn quality(&self, config: &QualityConfig) -> Quality {
        learn_quality(
            &self.departure,
            self.smoothing_report().spread_median_m,
            config,
        )
    }

    /// The report of the whole-walk answer.
    pub fn smoothing_report(&self) -> SmoothingReport {
        let mut spread = self.estimate.spread_m.clone();
        spread.sort_by(f64::total_cmp);
        SmoothingReport {
            distinct_paths: self.estimate.smoothed_paths.0,
            averaged_paths: self.estimate.smoothed_paths.1,
            spread_median_m: spread.get(spread.len() / 2).copied().unwrap_or(0.0),
            spread_max_m: spread.last().copied().unwrap_or(0.0),
        }
    }

    /// The report of the building's axes.
    #[must_use]
    pub fn axes_report(&self) -> AxesReport {
        let e = &self.axes;
        AxesReport {
            used: self.filter.axis_steps() > 0,
            shows_axes: e.shows_axes(),
            turns: e.turns,
            alignment: e.alignment,
            diagonal_alignment: e.diagonal_alignment,
            directions: e.directions,
            straight_m: e.straight_m,
            steps_weighed: self.filter.axis_steps(),
        }
    }
}
